//! The design editor's operations that have geometry in Rust: offsets (the arc-keeping
//! offset of `oficina_geom::offset`) and the exports. The page and `oficina design` both
//! call these; the design file itself is `oficina_io`'s.

use crate::Error;
pub use oficina_io::entity_paths;
use oficina_io::geom::{offset_areas, Area, Path};
use oficina_io::{design_from_paths, path_to_polyline};
pub use oficina_io::{
    design_from_seed001, design_to_dxf, design_to_seed001, design_to_string, design_to_svg,
    parse_design, Design, DesignLayer, Entity, Shape,
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

/// The design as `format` (`svg`, `dxf` or `seed001`, seed 001's graphic file).
pub fn export(design: &Design, format: &str) -> Result<String, Error> {
    match format {
        "svg" => Ok(design_to_svg(design)),
        "dxf" => Ok(design_to_dxf(design)),
        "seed001" => Ok(design_to_seed001(design)),
        other => Err(Error(format!(
            "export: '{other}' is not svg, dxf or seed001"
        ))),
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
        Shape::Point { .. } => "point",
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

/// How to grade a digitised sole contour, as `oficina sole` does.
pub struct GradeParams {
    /// The size the points were digitised at.
    pub from_size: f64,
    /// The sizes to make.
    pub sizes: Vec<f64>,
    /// `br` or `us`.
    pub system: String,
    /// Material shrinkage, percent.
    pub shrink: f64,
    /// Fitting tolerance, mm.
    pub tol: f64,
}

/// Most sizes one grading makes (a size run, with room).
const MAX_SIZES: usize = 40;

/// One graded size: the fitted contour of each foot.
pub struct GradedSize {
    /// The size.
    pub size: f64,
    /// Left then right foot, closed polylines in the points' frame.
    pub feet: [Shape; 2],
    /// `tangent circles` or `biarc`.
    pub method: String,
    /// Lines and arcs of one foot.
    pub blocks: usize,
    /// Largest distance of the fit from the graded points, mm.
    pub max_deviation: f64,
}

/// The digitised points graded to each size, fitted and mirrored by the mold job's own
/// `graded_feet` (`oficina sole`): about the heel, α on the width and β on the length.
pub fn grade(points: &[[f64; 2]], p: &GradeParams) -> Result<Vec<GradedSize>, Error> {
    use oficina_cam::ops::{graded_feet, SoleJob};
    use oficina_geom::SizeSystem;
    let system = SizeSystem::parse(&p.system).ok_or_else(|| {
        Error(format!(
            "grade: system '{}': br (Brazilian/French) or us (English/American)",
            p.system
        ))
    })?;
    if p.sizes.is_empty() || p.sizes.len() > MAX_SIZES {
        return Err(Error(format!(
            "grade: {} sizes: give 1 to {MAX_SIZES}",
            p.sizes.len()
        )));
    }
    if let Some(s) = [p.from_size]
        .iter()
        .chain(&p.sizes)
        .find(|s| !(s.is_finite() && (0.0..=100.0).contains(*s)))
    {
        return Err(Error(format!("grade: size {s}: a number from 0 to 100")));
    }
    if !(0.0..=20.0).contains(&p.shrink) {
        return Err(Error(format!("grade: shrink {} %: use 0 to 20", p.shrink)));
    }
    if !(p.tol > 0.0 && p.tol.is_finite()) {
        return Err(Error(format!("grade: tolerance {}: above 0 mm", p.tol)));
    }
    if points.len() < 3 || points.len() > 100_000 || points.iter().flatten().any(|v| !v.is_finite())
    {
        return Err(Error(format!(
            "grade: {} points: 3 to 100000 finite points",
            points.len()
        )));
    }
    let pts: Vec<_> = points.iter().map(|q| (q[0], q[1]).into()).collect();
    p.sizes
        .iter()
        .map(|&size| {
            let job = SoleJob {
                system,
                shrink: p.shrink / 100.0,
                fit_tolerance: p.tol,
                ..SoleJob::seed(p.from_size, size)
            };
            let g = graded_feet(&pts, &job).map_err(|e| Error(format!("grade to {size}: {e}")))?;
            Ok(GradedSize {
                size,
                feet: feet_shapes(&[g.left, g.right])
                    .map_err(|e| Error(format!("grade to {size}: {}", e.0)))?,
                method: g.fit.method.name().to_string(),
                blocks: g.fit.blocks,
                max_deviation: g.fit.max_deviation,
            })
        })
        .collect()
}

/// The two feet's contours (lines and arcs) as closed polylines.
pub fn feet_shapes(feet: &[Path; 2]) -> Result<[Shape; 2], Error> {
    let shape = |p: &Path| {
        path_to_polyline(p).ok_or_else(|| Error("a foot's contour has Bézier pieces".into()))
    };
    Ok([shape(&feet[0])?, shape(&feet[1])?])
}

/// Adds each foot of a graded size to `design` on its own layer (`size 40 left`, `size 40
/// right`, made when missing), ids after the design's largest.
pub fn add_graded(design: &mut Design, size: f64, feet: [Shape; 2]) {
    for (foot, shape) in ["left", "right"].into_iter().zip(feet) {
        let layer = format!("size {size} {foot}");
        if !design.layers.iter().any(|l| l.name == layer) {
            let color = if foot == "left" { "#2f7fd8" } else { "#d8782f" };
            design.layers.push(DesignLayer {
                name: layer.clone(),
                color: color.into(),
            });
        }
        let id = design.entities.iter().map(|e| e.id).max().unwrap_or(0) + 1;
        design.entities.push(Entity { id, layer, shape });
    }
}
