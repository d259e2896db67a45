//! The design file's schema and its checks.

use crate::import::ImportError;
use oficina_geom::Color;
use serde::{Deserialize, Serialize};

/// The `format` every design file carries.
pub const DESIGN_FORMAT: &str = "oficina-design";
/// The version this reader writes and reads.
pub const DESIGN_VERSION: u32 = 1;
/// Largest coordinate or length, mm: a workshop part, with room (a bound on what a file asks).
const MAX_COORD: f64 = 1e6;
/// Most characters in one text entity.
const MAX_TEXT: usize = 10_000;

/// A whole design.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Design {
    /// Always [`DESIGN_FORMAT`].
    pub format: String,
    /// [`DESIGN_VERSION`].
    pub version: u32,
    /// Layers in drawing order.
    pub layers: Vec<DesignLayer>,
    /// Entities in drawing order.
    pub entities: Vec<Entity>,
    /// The process parameters the page keeps with the design (tool, depths, …), as written.
    #[serde(default, skip_serializing_if = "serde_json::Map::is_empty")]
    pub process: serde_json::Map<String, serde_json::Value>,
}

/// A layer: its name and colour.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignLayer {
    /// Unique within the design.
    pub name: String,
    /// `#rrggbb`.
    pub color: String,
}

/// One entity: an id unique in the design, its layer, its shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Entity {
    /// Unique within the design (the page selects by it).
    pub id: u64,
    /// A layer of the design.
    pub layer: String,
    /// The geometry.
    #[serde(flatten)]
    pub shape: Shape,
}

/// Geometry, mm, y up; angles in degrees, counter-clockwise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Shape {
    /// A segment.
    Line {
        /// Start.
        a: [f64; 2],
        /// End.
        b: [f64; 2],
    },
    /// An arc about `center` from angle `start` sweeping `sweep`.
    Arc {
        /// Centre.
        center: [f64; 2],
        /// Radius (> 0).
        radius: f64,
        /// Angle of the start point, degrees.
        start: f64,
        /// Signed sweep, degrees, > 0 counter-clockwise.
        sweep: f64,
    },
    /// A full circle.
    Circle {
        /// Centre.
        center: [f64; 2],
        /// Radius (> 0).
        radius: f64,
    },
    /// A chain of lines and arcs.
    Polyline {
        /// `[x, y]` or `[x, y, bulge]`: the bulge (DXF's, tan(sweep/4), > 0
        /// counter-clockwise) bends the piece from this vertex to the next into an arc.
        vertices: Vec<Vec<f64>>,
        /// The last vertex joins the first.
        closed: bool,
    },
    /// The interpolating cubic that CAD programs build through points (chord-length
    /// parameters, natural ends): the DXF reader's curve for a SPLINE given by fit points.
    Spline {
        /// The points it passes through, in order.
        points: Vec<[f64; 2]>,
    },
    /// A point: a mark (a hole's centre, a reference), no stroke; DXF POINT, seed 001's
    /// point list.
    Point {
        /// Where.
        at: [f64; 2],
    },
    /// Single-stroke text (the Hershey Roman Simplex of `oficina_geom::text`).
    Text {
        /// Where the first baseline starts.
        at: [f64; 2],
        /// Capital height (> 0).
        height: f64,
        /// Baseline direction, degrees counter-clockwise.
        #[serde(default)]
        angle: f64,
        /// The text; `\n` starts a line below.
        text: String,
    },
}

impl Design {
    /// An empty design with one layer "0" in black.
    pub fn new() -> Design {
        Design {
            format: DESIGN_FORMAT.into(),
            version: DESIGN_VERSION,
            layers: vec![DesignLayer {
                name: "0".into(),
                color: "#000000".into(),
            }],
            entities: Vec::new(),
            process: Default::default(),
        }
    }

    /// The colour of `layer` (black when it has none that parses).
    pub fn layer_color(&self, layer: &str) -> Color {
        self.layers
            .iter()
            .find(|l| l.name == layer)
            .and_then(|l| parse_color(&l.color))
            .unwrap_or(Color::BLACK)
    }

    /// Everything a reader relies on: the format and version, layers unique with `#rrggbb`
    /// colours, ids unique, every entity on a layer, numbers finite and within ±10⁶ mm,
    /// radii and heights above 0, enough points.
    pub(crate) fn check(&self, file: &str) -> Result<(), ImportError> {
        let err = |loc: String, msg: String| Err(ImportError::new(file, loc, msg));
        if self.format != DESIGN_FORMAT {
            return err(
                "format".into(),
                format!("'{}' is not '{DESIGN_FORMAT}'", self.format),
            );
        }
        if self.version != DESIGN_VERSION {
            return err(
                "version".into(),
                format!(
                    "version {} (this Oficina reads version {DESIGN_VERSION})",
                    self.version
                ),
            );
        }
        // Sets, not pairwise scans: a file of many layers or entities stays linear.
        let mut names = std::collections::HashSet::new();
        for (i, l) in self.layers.iter().enumerate() {
            if !names.insert(l.name.as_str()) {
                return err(format!("layers[{i}]"), format!("layer '{}' twice", l.name));
            }
            if parse_color(&l.color).is_none() {
                return err(
                    format!("layers[{i}] ({})", l.name),
                    format!("colour '{}' is not #rrggbb", l.color),
                );
            }
        }
        let mut ids = std::collections::HashSet::new();
        for (i, e) in self.entities.iter().enumerate() {
            let loc = || format!("entities[{i}] (id {})", e.id);
            if !ids.insert(e.id) {
                return err(loc(), format!("id {} is used twice", e.id));
            }
            if !names.contains(e.layer.as_str()) {
                return err(loc(), format!("layer '{}' is not in the layers", e.layer));
            }
            e.shape.check().or_else(|m| err(loc(), m))?;
        }
        Ok(())
    }
}

impl Default for Design {
    fn default() -> Design {
        Design::new()
    }
}

impl Shape {
    /// What is wrong with this shape's numbers, if anything.
    fn check(&self) -> Result<(), String> {
        let coord = |v: f64, what: &str| {
            if v.is_finite() && v.abs() <= MAX_COORD {
                Ok(())
            } else {
                Err(format!("{what} {v} is not a number within ±{MAX_COORD} mm"))
            }
        };
        let point = |p: &[f64; 2], what: &str| coord(p[0], what).and(coord(p[1], what));
        let positive = |v: f64, what: &str| {
            coord(v, what)?;
            if v > 0.0 {
                Ok(())
            } else {
                Err(format!("{what} {v} must be above 0"))
            }
        };
        match self {
            Shape::Line { a, b } => point(a, "start").and(point(b, "end")),
            Shape::Point { at } => point(at, "position"),
            Shape::Arc {
                center,
                radius,
                start,
                sweep,
            } => {
                point(center, "centre")?;
                positive(*radius, "radius")?;
                coord(*start, "start angle")?;
                if sweep.abs() > 1e-9 && sweep.abs() <= 360.0 {
                    Ok(())
                } else {
                    Err(format!("sweep {sweep}° must be non-zero and within ±360°"))
                }
            }
            Shape::Circle { center, radius } => {
                point(center, "centre").and(positive(*radius, "radius"))
            }
            Shape::Polyline { vertices, .. } => {
                if vertices.len() < 2 {
                    return Err(format!("{} vertices: a polyline needs 2", vertices.len()));
                }
                for (k, v) in vertices.iter().enumerate() {
                    if v.len() != 2 && v.len() != 3 {
                        return Err(format!(
                            "vertex {k}: [x, y] or [x, y, bulge], not {} numbers",
                            v.len()
                        ));
                    }
                    for &x in v {
                        coord(x, &format!("vertex {k}"))?;
                    }
                    // A bulge of 1 is a half circle; beyond, more than half (a bulge on the
                    // last vertex of an open polyline bends nothing and is allowed).
                    if v.len() == 3 && !(v[2].abs() < 1e3) {
                        return Err(format!("vertex {k}: bulge {} is beyond ±1000", v[2]));
                    }
                }
                Ok(())
            }
            Shape::Spline { points } => {
                if points.len() < 2 {
                    return Err(format!("{} points: a spline needs 2", points.len()));
                }
                points
                    .iter()
                    .enumerate()
                    .try_for_each(|(k, p)| point(p, &format!("point {k}")))
            }
            Shape::Text {
                at,
                height,
                angle,
                text,
            } => {
                point(at, "position")?;
                positive(*height, "height")?;
                coord(*angle, "angle")?;
                if text.chars().count() > MAX_TEXT {
                    return Err(format!("text over {MAX_TEXT} characters"));
                }
                Ok(())
            }
        }
    }
}

/// `#rrggbb` → colour.
pub(crate) fn parse_color(s: &str) -> Option<Color> {
    let h = s.strip_prefix('#')?;
    if h.len() != 6 || !h.is_ascii() {
        return None;
    }
    let byte = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
    Some(Color::rgb(byte(0)?, byte(2)?, byte(4)?))
}
