//! The design file (`*.oficina.json`): what the workbench's design editor draws, written
//! once and read by every drawing command like an SVG or a DXF.
//!
//! Lossless: the file holds the editor's own entities (line, arc, circle, polyline with
//! bulges, spline through points, single-stroke text) with their ids and layers, the layers
//! with their colours, and the process parameters the page keeps beside them (any JSON
//! object, kept as written). Format `"oficina-design"`, version 1; see
//! `docs/design-editor.md`.

mod dxf_out;
mod model;
mod seed_io;
mod svg_out;
mod to_drawing;

pub use dxf_out::design_to_dxf;
pub use model::{Design, DesignLayer, Entity, Shape, DESIGN_FORMAT, DESIGN_VERSION};
pub use seed_io::{design_from_seed001, design_to_seed001};
pub use svg_out::design_to_svg;
pub use to_drawing::{design_from_paths, entity_paths, path_to_polyline};

use crate::import::{ImportError, Imported};

/// Reads a design file's text: JSON in the schema of [`Design`], checked entity by entity.
/// Errors name the file and the line and column (JSON) or the entity (its index and id).
pub fn parse_design(text: &str, file: &str) -> Result<Design, ImportError> {
    let design: Design = serde_json::from_str(text).map_err(|e| {
        ImportError::new(
            file,
            format!("line {} column {}", e.line(), e.column()),
            e.to_string(),
        )
    })?;
    design.check(file)?;
    Ok(design)
}

/// The design as the text of its file (pretty JSON, ends in a newline).
pub fn design_to_string(design: &Design) -> String {
    // Serialising plain data with string keys cannot fail.
    let mut s = serde_json::to_string_pretty(design).unwrap_or_default();
    s.push('\n');
    s
}

/// A design file as every importer returns a drawing.
pub fn design_from_bytes(bytes: &[u8], file: &str) -> Result<Imported, ImportError> {
    let text = crate::import::utf8(bytes, file)?;
    let design = parse_design(text, file)?;
    Ok(Imported {
        drawing: design.to_drawing(file),
        ..Imported::default()
    })
}
