//! Single-stroke text: the Hershey font lives in `oficina_geom::text` (one font for the
//! plotter, the mill and the importers); a pen stroke is one of its strokes.

pub use oficina_geom::text_strokes;
