//! What every drawing importer returns: the `Drawing`, the entities it could not take
//! (counted and listed, never dropped in silence) and loose points; and one error type that
//! names the file, the place in it and what is wrong.

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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Imported {
    /// What could be read.
    pub drawing: Drawing,
    /// What was skipped.
    pub unsupported: Unsupported,
    /// Loose points (DXF POINT, the seed file's point list).
    pub points: Vec<Point>,
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

/// Loads a drawing by its extension: HP-GL (`.plt`, `.hpgl`, `.hpg`, `.hp`, … or any file whose
/// content is HP-GL), `.svg`, `.dxf`, `.csv`/`.txt`/`.xy`/`.pts` (a point
/// list, taken as one closed contour) or `.dat`/`.g01` (the seed 001 graphic file).
pub fn load_drawing(path: &Path) -> Result<Imported, ImportError> {
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
        "dat" | "g01" => crate::seed001::parse_seed001(utf8(&bytes, &name)?, &name)?.to_imported(&name),
        other => Err(ImportError::new(
            &name,
            "file",
            format!("unknown drawing type '.{other}' (and not HP-GL by its content): use .svg, .dxf, .csv/.txt (points), .dat (seed 001) or HP-GL (.plt, .hpgl, .hpg, .hp)"),
        )),
    }
}

pub(crate) fn utf8<'a>(bytes: &'a [u8], name: &str) -> Result<&'a str, ImportError> {
    std::str::from_utf8(bytes)
        .map_err(|e| ImportError::new(name, format!("byte {}", e.valid_up_to()), "not UTF-8 text"))
}
