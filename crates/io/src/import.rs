//! What every drawing importer returns: the `Drawing`, the entities it could not take
//! (counted and listed, never dropped in silence) and loose points; and one error type that
//! names the file, the place in it and what is wrong.

use crate::closure::{close_and_chain, Closure, JOIN_TOL};
use oficina_geom::{Drawing, Path as GeomPath, Point, SourceRef};
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

/// Files larger than this are refused before reading (no unbounded allocation).
pub const MAX_DRAWING_BYTES: u64 = 256 << 20;

/// Entities an importer met but could not turn into geometry, by kind.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Unsupported {
    /// Kind (e.g. `TEXT`, `<image>`) → how many.
    pub counts: BTreeMap<String, usize>,
    /// Kind → the first few elements (ids, handles or lines), for the message.
    pub examples: BTreeMap<String, Vec<String>>,
}

impl Unsupported {
    /// Counts one skipped `element` of `kind`.
    pub fn add(&mut self, kind: &str, element: impl Into<String>) {
        *self.counts.entry(kind.to_string()).or_default() += 1;
        let ex = self.examples.entry(kind.to_string()).or_default();
        if ex.len() < 5 {
            ex.push(element.into());
        }
    }

    /// Entities skipped, all kinds.
    pub fn total(&self) -> usize {
        self.counts.values().sum()
    }

    /// Nothing was skipped.
    pub fn is_empty(&self) -> bool {
        self.counts.is_empty()
    }
}

impl fmt::Display for Unsupported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} unsupported entit{} skipped:",
            self.total(),
            if self.total() == 1 { "y" } else { "ies" }
        )?;
        for (k, n) in &self.counts {
            let ex = self
                .examples
                .get(k)
                .map(|v| v.join(", "))
                .unwrap_or_default();
            write!(f, " {k} ×{n} ({ex});")?;
        }
        Ok(())
    }
}

/// An imported drawing.
#[derive(Clone, Debug, PartialEq)]
pub struct Imported {
    /// What could be read.
    pub drawing: Drawing,
    /// What was skipped.
    pub unsupported: Unsupported,
    /// Loose points (DXF POINT, the seed file's point list).
    pub points: Vec<Point>,
    /// The units the file's numbers were read in (e.g. `Inches ($INSUNITS)`); empty: mm.
    pub units: String,
    /// Millimetres per drawing unit (1 when the file is in mm or has no units).
    pub mm_per_unit: f64,
    /// What closing and chaining found: loops, and what stayed open per layer.
    pub closure: Closure,
    /// Elements (their `SourceRef::element`) filled by the even-odd rule; the others fill
    /// nonzero (SVG's default). Hatch fills and hidden-line removal read holes by it.
    pub even_odd: std::collections::HashSet<String>,
}

impl Default for Imported {
    fn default() -> Imported {
        Imported {
            drawing: Drawing::default(),
            unsupported: Unsupported::default(),
            points: Vec::new(),
            units: String::new(),
            mm_per_unit: 1.0,
            closure: Closure::default(),
            even_odd: Default::default(),
        }
    }
}

impl Imported {
    /// Records the units the file was read in: their name and millimetres per unit.
    pub fn set_units(&mut self, name: impl Into<String>, mm_per_unit: f64) {
        let name = name.into();
        self.units = format!("{name}, {mm_per_unit} mm per unit");
        self.mm_per_unit = mm_per_unit;
    }

    /// Closes and chains the drawing with join tolerance `tol` mm ([`close_and_chain`]) and
    /// keeps the report.
    pub fn close(&mut self, tol: f64) {
        self.closure = close_and_chain(&mut self.drawing, tol);
    }

    /// Layer names, in file order.
    pub fn layer_names(&self) -> Vec<&str> {
        self.drawing
            .layers
            .iter()
            .map(|l| l.name.as_str())
            .collect()
    }

    /// What was imported, in lines for a report: loops (closed in the file, where their ends
    /// meet, chained), what stayed open per layer with its largest gap, layers and units.
    pub fn summary(&self) -> Vec<String> {
        // Paths as read: what the file holds, before pieces were chained.
        let read = self.closure.paths_read.max(self.drawing.path_count());
        let mut lines = vec![format!(
            "{} path{} read on {} layer{} ({}), units: {}",
            read,
            if read == 1 { "" } else { "s" },
            self.drawing.layers.len(),
            if self.drawing.layers.len() == 1 {
                ""
            } else {
                "s"
            },
            self.layer_names().join(", "),
            if self.units.is_empty() {
                "mm"
            } else {
                &self.units
            }
        )];
        lines.extend(self.closure.to_string().lines().map(str::to_string));
        lines
    }
}

/// A file that cannot be read: which file, where in it, what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}: {location}: {message}")]
pub struct ImportError {
    /// The file.
    pub file: String,
    /// Line, element id or entity handle.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

impl ImportError {
    /// An error in `file` at `location`.
    pub fn new(file: &str, location: impl Into<String>, message: impl Into<String>) -> ImportError {
        ImportError {
            file: file.to_string(),
            location: location.into(),
            message: message.into(),
        }
    }
}

/// Reads a whole file with the size cap.
pub(crate) fn read_capped(path: &Path) -> Result<Vec<u8>, ImportError> {
    let name = path.display().to_string();
    let meta =
        std::fs::metadata(path).map_err(|e| ImportError::new(&name, "file", e.to_string()))?;
    if meta.len() > MAX_DRAWING_BYTES {
        return Err(ImportError::new(
            &name,
            "file",
            format!(
                "{} bytes is over the {} MiB limit for drawings",
                meta.len(),
                MAX_DRAWING_BYTES >> 20
            ),
        ));
    }
    std::fs::read(path).map_err(|e| ImportError::new(&name, "file", e.to_string()))
}

/// [`load_drawing_with`] at the default join tolerance, [`JOIN_TOL`].
pub fn load_drawing(path: &Path) -> Result<Imported, ImportError> {
    load_drawing_with(path, JOIN_TOL)
}

/// Loads a drawing by its extension (see [`read_drawing`]), then closes and chains it with
/// join tolerance `join_tol` mm: every importer's drawing goes through the one rule.
pub fn load_drawing_with(path: &Path, join_tol: f64) -> Result<Imported, ImportError> {
    let mut imported = read_drawing(path)?;
    imported.close(join_tol);
    Ok(imported)
}

/// Reads a drawing by its extension: HP-GL (`.plt`, `.hpgl`, `.hpg`, `.hp`, … or any file whose
/// content is HP-GL), `.svg`, `.dxf`, `.json` (a design file, `*.oficina.json`), `.csv`/`.txt`/`.xy`/`.pts` (a point list, taken as one
/// closed contour) or `.dat`/`.g01` (the seed 001 graphic file), as the file has it (nothing
/// closed or chained).
fn read_drawing(path: &Path) -> Result<Imported, ImportError> {
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let bytes = read_capped(path)?;
    // HP-GL by its extension or, whatever the extension, by its content.
    if crate::hpgl::HPGL_EXTENSIONS.contains(&ext.as_str()) || crate::hpgl::looks_like_hpgl(&bytes)
    {
        return crate::hpgl::hpgl_from_bytes(&bytes, &name).map(crate::hpgl::Hpgl::into_imported);
    }
    match ext.as_str() {
        "svg" => crate::svg::svg_from_bytes(&bytes, &name),
        "dxf" => crate::dxf::dxf_from_bytes(&bytes, &name),
        // The design editor's file, `*.oficina.json`.
        "json" => crate::design::design_from_bytes(&bytes, &name),
        "csv" | "txt" | "xy" | "pts" => {
            let text = utf8(&bytes, &name)?;
            let pts = crate::points::parse_points(text, &name)?;
            let mut drawing = Drawing::new();
            drawing.push(
                "points",
                GeomPath::polyline(&pts, true).with_source(SourceRef::new(name.as_str(), "points")),
            );
            Ok(Imported {
                drawing,
                ..Imported::default()
            })
        }
        "pub" => crate::pubfile::pub_from_str(utf8(&bytes, &name)?, &name),
        "dat" | "g01" => crate::seed001::parse_seed001(utf8(&bytes, &name)?, &name)?.to_imported(&name),
        other => Err(ImportError::new(
            &name,
            "file",
            format!("unknown drawing type '.{other}' (and not HP-GL by its content): use .svg, .dxf, .oficina.json (design), .csv/.txt (points), .dat (seed 001), .pub (CADTEC, seed 000) or HP-GL (.plt, .hpgl, .hpg, .hp)"),
        )),
    }
}

pub(crate) fn utf8<'a>(bytes: &'a [u8], name: &str) -> Result<&'a str, ImportError> {
    std::str::from_utf8(bytes)
        .map_err(|e| ImportError::new(name, format!("byte {}", e.valid_up_to()), "not UTF-8 text"))
}
