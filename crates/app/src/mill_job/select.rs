//! The drawing's shapes numbered as the import report lists them, their nesting, and the
//! selections of a job's operations.

use super::model::Select;
use oficina_geom::{to_ring, Color, Path};

/// A circle is a closed path within this of a fitted circle, mm (a DXF's 24-gon hole too).
const CIRCLE_TOL: f64 = 0.05;

/// One shape of the job: numbered from 1 in drawing order (layer by layer, then the job's
/// own shapes).
#[derive(Clone, Debug)]
pub(crate) struct Shape {
    /// Its number.
    pub id: usize,
    /// Its layer.
    pub layer: String,
    /// The path.
    pub path: Path,
    /// A circle's diameter, mm.
    pub circle: Option<f64>,
    /// How many closed shapes contain it (even: material inside when cut out; odd: a hole).
    pub depth: usize,
}

impl Shape {
    /// A circle's diameter, else the larger side of the box, mm.
    pub(crate) fn size(&self) -> f64 {
        self.circle.unwrap_or_else(|| {
            self.path
                .bounding_box()
                .map_or(0.0, |b| b.width().max(b.height()))
        })
    }

    /// One line of the import report: `#3 HOLES closed circle Ø3.60 at (5.50, 5.50)`.
    pub(crate) fn describe(&self) -> String {
        let what = match (self.path.closed, self.circle) {
            (true, Some(d)) => {
                let c = self
                    .path
                    .fit_circle()
                    .map_or([0.0, 0.0], |c| [c.center.x, c.center.y]);
                format!("closed circle Ø{d:.2} at ({:.2}, {:.2})", c[0], c[1])
            }
            (closed, _) => {
                let b = self.path.bounding_box().unwrap_or_default();
                format!(
                    "{} {:.2} × {:.2} at ({:.2}, {:.2})",
                    if closed { "closed" } else { "open" },
                    b.width(),
                    b.height(),
                    b.x0,
                    b.y0
                )
            }
        };
        let colour = self.path.style.stroke.map_or(String::new(), |c| {
            format!(" #{:02x}{:02x}{:02x}", c.r, c.g, c.b)
        });
        let nest = if self.path.closed && self.depth % 2 == 1 {
            " (a hole)"
        } else {
            ""
        };
        format!("#{} {}{colour} {what}{nest}", self.id, self.layer)
    }
}

/// The shapes of `layers` (name, paths) numbered from 1, with their nesting (for the first
/// `nest_limit` of them: a report that lists only so many need not test the rest).
pub(crate) fn number_shapes(layers: Vec<(String, Path)>, nest_limit: usize) -> Vec<Shape> {
    let mut shapes: Vec<Shape> = layers
        .into_iter()
        .enumerate()
        .map(|(k, (layer, path))| Shape {
            id: k + 1,
            circle: path.as_circle(CIRCLE_TOL).map(|c| 2.0 * c.radius),
            layer,
            path,
            depth: 0,
        })
        .collect();
    // Each closed ring with its box: a point outside the box is outside the ring.
    let rings: Vec<Option<(Vec<[f64; 2]>, oficina_geom::Rect)>> = shapes
        .iter()
        .map(|s| {
            let b = s.path.bounding_box()?;
            (s.path.closed && !s.path.is_empty()).then(|| (to_ring(&s.path.flatten(1e-3)), b))
        })
        .collect();
    for k in 0..shapes.len().min(nest_limit) {
        let Some(probe) = shapes[k].path.segments.first().map(|s| s.eval(0.5)) else {
            continue;
        };
        shapes[k].depth = rings
            .iter()
            .enumerate()
            .filter(|(j, r)| {
                *j != k
                    && r.as_ref()
                        .is_some_and(|(r, b)| b.contains(probe) && in_ring([probe.x, probe.y], r))
            })
            .count();
    }
    shapes
}

/// Even–odd point in ring.
fn in_ring(p: [f64; 2], r: &[[f64; 2]]) -> bool {
    let mut inside = false;
    for i in 0..r.len() {
        let (a, b) = (r[i], r[(i + 1) % r.len()]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            inside = !inside;
        }
    }
    inside
}

/// A colour by `#rrggbb` or name.
fn parse_colour(text: &str) -> Option<Color> {
    let t = text.trim().to_ascii_lowercase();
    if let Some(hex) = t.strip_prefix('#') {
        if hex.len() == 6 {
            let v = u32::from_str_radix(hex, 16).ok()?;
            return Some(Color::rgb((v >> 16) as u8, (v >> 8) as u8, v as u8));
        }
        return None;
    }
    Some(match t.as_str() {
        "black" => Color::rgb(0, 0, 0),
        "white" => Color::rgb(255, 255, 255),
        "red" => Color::rgb(255, 0, 0),
        "green" => Color::rgb(0, 255, 0),
        "blue" => Color::rgb(0, 0, 255),
        "yellow" => Color::rgb(255, 255, 0),
        "cyan" => Color::rgb(0, 255, 255),
        "magenta" => Color::rgb(255, 0, 255),
        _ => return None,
    })
}

/// The shapes `sel` picks, or why it is wrong (a bad colour, an unknown id or layer).
pub(crate) fn select<'a>(shapes: &'a [Shape], sel: &Select) -> Result<Vec<&'a Shape>, String> {
    let colour = match &sel.color {
        Some(c) => Some(parse_colour(c).ok_or_else(|| {
            format!("select.color = {c:?}: write #rrggbb or black, white, red, green, blue, yellow, cyan, magenta")
        })?),
        None => None,
    };
    if let Some(ids) = &sel.ids {
        if let Some(bad) = ids.iter().find(|&&i| i == 0 || i > shapes.len()) {
            return Err(format!(
                "select.ids: no shape #{bad} (the shapes are #1 to #{})",
                shapes.len()
            ));
        }
    }
    if let Some(layers) = &sel.layer {
        for name in layers.names() {
            if !shapes.iter().any(|s| s.layer.eq_ignore_ascii_case(name)) {
                let mut known: Vec<&str> = shapes.iter().map(|s| s.layer.as_str()).collect();
                known.dedup();
                return Err(format!(
                    "select.layer: no layer {name:?} (the layers are {})",
                    known.join(", ")
                ));
            }
        }
    }
    Ok(shapes
        .iter()
        .filter(|s| {
            sel.layer
                .as_ref()
                .is_none_or(|l| l.names().iter().any(|n| s.layer.eq_ignore_ascii_case(n)))
                && colour.is_none_or(|c| {
                    s.path
                        .style
                        .stroke
                        .is_some_and(|k| (k.r, k.g, k.b) == (c.r, c.g, c.b))
                })
                && sel.ids.as_ref().is_none_or(|ids| ids.contains(&s.id))
                && sel.diameter_under.is_none_or(|d| s.size() < d)
                && sel.diameter_over.is_none_or(|d| s.size() > d)
                && sel.closed.is_none_or(|c| s.path.closed == c)
                && sel.circle.is_none_or(|c| s.circle.is_some() == c)
        })
        .collect())
}
