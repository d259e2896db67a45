//! The design editor's operations that have geometry in Rust: offsets (the arc-keeping
//! offset of `oficina_geom::offset`) and the exports. The page and `oficina design` both
//! call these; the design file itself is `oficina_io`'s.

use crate::Error;
use oficina_io::design_from_paths;
pub use oficina_io::entity_paths;
use oficina_io::geom::{offset_areas, Area, Path};
pub use oficina_io::{
    design_to_dxf, design_to_string, design_to_svg, parse_design, Design, DesignLayer, Entity,
    Shape,
};

/// Offset contours are within this of the exact offset, mm (lines and arcs are rebuilt
/// exactly on the offset carriers; this bounds only where pieces are matched).
const OFFSET_TOL: f64 = 1e-4;

/// The closed entities `ids` offset by `distance` mm (> 0 outwards, < 0 inwards; a contour
/// inside another is a hole and moves the other way), as new polylines on the first
/// entity's layer with ids after the design's largest. A rounded corner is an arc.
pub fn offset(design: &Design, ids: &[u64], distance: f64) -> Result<Vec<Entity>, Error> {
    if !distance.is_finite() || distance == 0.0 || distance.abs() > 1e5 {
        return Err(Error(format!(
            "offset distance {distance}: a non-zero number of mm within ±100000"
        )));
    }
    if ids.is_empty() {
        return Err(Error("offset: select the closed contours to offset".into()));
    }
    let mut paths: Vec<Path> = Vec::new();
    let mut layer = None;
    for id in ids {
        let e = design
            .entities
            .iter()
            .find(|e| e.id == *id)
            .ok_or_else(|| Error(format!("offset: no entity {id} in the design")))?;
        layer.get_or_insert(e.layer.clone());
        for p in entity_paths(&e.shape) {
            if !p.closed {
                return Err(Error(format!(
                    "offset: entity {id} ({}) is open; only closed contours are offset",
                    kind(&e.shape)
                )));
            }
            paths.push(p);
        }
    }
    let areas = offset_areas(&Area::from_paths(&paths), distance, OFFSET_TOL)
        .map_err(|e| Error(format!("offset: {}", e.0)))?;
    let out: Vec<Path> = areas.iter().flat_map(|a| a.paths().cloned()).collect();
    let first = design.entities.iter().map(|e| e.id).max().unwrap_or(0) + 1;
    design_from_paths(&out, layer.as_deref().unwrap_or("0"), first)
        .map_err(|e| Error(format!("offset: {e}")))
}

/// The design as `format` (`svg` or `dxf`).
pub fn export(design: &Design, format: &str) -> Result<String, Error> {
    match format {
        "svg" => Ok(design_to_svg(design)),
        "dxf" => Ok(design_to_dxf(design)),
        other => Err(Error(format!("export: '{other}' is not svg or dxf"))),
    }
}

/// Reads a design file (no larger than the drawings' limit).
pub fn read(path: &std::path::Path) -> Result<Design, Error> {
    let name = path.display().to_string();
    let size = std::fs::metadata(path)
        .map_err(|e| Error(format!("{name}: {e}")))?
        .len();
    if size > oficina_io::MAX_DRAWING_BYTES {
        return Err(Error(format!(
            "{name}: {size} bytes is over the drawings' limit"
        )));
    }
    let text = std::fs::read_to_string(path).map_err(|e| Error(format!("{name}: {e}")))?;
    parse_design(&text, &name).map_err(Error::from_display)
}

fn kind(s: &Shape) -> &'static str {
    match s {
        Shape::Line { .. } => "line",
        Shape::Arc { .. } => "arc",
        Shape::Circle { .. } => "circle",
        Shape::Polyline { .. } => "polyline",
        Shape::Spline { .. } => "spline",
        Shape::Text { .. } => "text",
    }
}

/// A digitised contour fitted by one of `oficina fit`'s methods.
pub struct Fitted {
    /// The fitted contour as a closed polyline (every method gives lines and arcs).
    pub shape: Shape,
    /// Largest distance from a picked point to the contour, mm.
    pub max_deviation: f64,
    /// Lines and arcs: NC blocks.
    pub blocks: usize,
}

/// Fits the closed contour through `points` (mm) by `method` (a name `oficina fit`
/// prints: `biarc`, `tangent circles`, …) within `tol` mm.
pub fn fit(points: &[[f64; 2]], method: &str, tol: f64) -> Result<Fitted, Error> {
    use oficina_io::geom::fit::{fit_method, Method};
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(Error(format!(
            "fit tolerance {tol}: a number of mm above 0"
        )));
    }
    if points.len() > 100_000 || points.iter().flatten().any(|v| !v.is_finite()) {
        return Err(Error("fit: up to 100000 finite points".into()));
    }
    let m = Method::ALL
        .into_iter()
        .find(|m| m.name() == method || m.name().starts_with(method))
        .ok_or_else(|| {
            let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
            Error(format!(
                "fit method '{method}': one of {}",
                names.join(", ")
            ))
        })?;
    let pts: Vec<_> = points.iter().map(|p| (p[0], p[1]).into()).collect();
    let f = fit_method(m, &pts, tol).map_err(|e| Error(format!("fit ({}): {e}", m.name())))?;
    let shape = oficina_io::path_to_polyline(&f.path)
        .ok_or_else(|| Error(format!("fit ({}): Bézier pieces", m.name())))?;
    Ok(Fitted {
        shape,
        max_deviation: f.max_deviation,
        blocks: f.blocks,
    })
}
