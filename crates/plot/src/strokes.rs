//! `Plot`: what a pen plotter draws: pens (one per colour or layer), each a list of strokes,
//! a stroke being a polyline drawn with the pen down.

use oficina_geom::{Color, Drawing, Point};

/// One pen-down polyline (at least two points once built by [`Plot::from_drawing`]).
pub type Stroke = Vec<Point>;

/// The strokes of one pen, drawn in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pen {
    /// The layer name or `#rrggbb` colour this pen draws.
    pub name: String,
    /// The strokes in drawing order.
    pub strokes: Vec<Stroke>,
}

/// How pens are assigned to the paths of a drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PenBy {
    /// One pen per stroke colour (the usual for SVG art).
    Color,
    /// One pen per layer (DXF layers, HPGL `SP` pens).
    Layer,
}

/// Pens in the order they are first met.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plot {
    /// The pens, in the order first met.
    pub pens: Vec<Pen>,
}

/// Pen-down and pen-up lengths of a plot, mm. Pen-up counts the travel between consecutive
/// strokes of each pen (not from or back to home), as vpype's `stat` does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lengths {
    /// Strokes counted.
    pub strokes: usize,
    /// Pen-down length, mm.
    pub pen_down: f64,
    /// Pen-up travel, mm.
    pub pen_up: f64,
}

/// The stroke that draws `path`, chords within `tol`; a closed path ends where it starts
/// (`flatten` leaves the return out; the pen draws it). `None` below two points.
pub(crate) fn path_stroke(path: &oficina_geom::Path, tol: f64) -> Option<Stroke> {
    let mut pts = path.flatten(tol);
    if path.closed && pts.len() > 1 {
        pts.push(pts[0]);
    }
    (pts.len() >= 2).then_some(pts)
}

/// Length of a polyline, mm.
pub fn polyline_length(s: &[Point]) -> f64 {
    s.windows(2).map(|w| w[0].distance(w[1])).sum()
}

pub(crate) fn color_name(c: Option<Color>) -> String {
    match c {
        Some(c) => format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b),
        None => "#000000".into(),
    }
}

impl Plot {
    /// Flattens every path (arcs and Béziers to chords within `tol` mm) into strokes, one pen
    /// per colour or layer. Paths with a fill and no stroke are still drawn as outlines.
    pub fn from_drawing(d: &Drawing, by: PenBy, tol: f64) -> Plot {
        let mut plot = Plot::default();
        for layer in &d.layers {
            for path in &layer.paths {
                let Some(pts) = path_stroke(path, tol) else {
                    continue;
                };
                let name = match by {
                    PenBy::Layer => layer.name.clone(),
                    PenBy::Color => color_name(path.style.stroke.or(path.style.fill)),
                };
                plot.pen_mut(&name).strokes.push(pts);
            }
        }
        plot
    }

    /// Index of the pen named `name`, added at the end if new.
    pub fn pen_index(&mut self, name: &str) -> usize {
        match self.pens.iter().position(|p| p.name == name) {
            Some(i) => i,
            None => {
                self.pens.push(Pen {
                    name: name.to_string(),
                    strokes: Vec::new(),
                });
                self.pens.len() - 1
            }
        }
    }

    /// The pen named `name`, added at the end if new.
    pub fn pen_mut(&mut self, name: &str) -> &mut Pen {
        match self.pens.iter().position(|p| p.name == name) {
            Some(i) => &mut self.pens[i],
            None => {
                self.pens.push(Pen {
                    name: name.to_string(),
                    strokes: Vec::new(),
                });
                self.pens.last_mut().unwrap()
            }
        }
    }

    /// Every stroke of every pen, in order.
    pub fn strokes(&self) -> impl Iterator<Item = &Stroke> {
        self.pens.iter().flat_map(|p| p.strokes.iter())
    }

    /// Pen-down and pen-up lengths of the plot.
    pub fn lengths(&self) -> Lengths {
        let mut l = Lengths::default();
        for pen in &self.pens {
            let mut last: Option<Point> = None;
            for s in &pen.strokes {
                l.strokes += 1;
                l.pen_down += polyline_length(s);
                if let (Some(a), Some(b)) = (last, s.first()) {
                    l.pen_up += a.distance(*b);
                }
                last = s.last().copied();
            }
        }
        l
    }

    /// Bounding box (min x, min y, max x, max y) of every point, `None` when empty.
    pub fn bounds(&self) -> Option<[f64; 4]> {
        let mut b: Option<[f64; 4]> = None;
        for p in self.strokes().flatten() {
            let r = b.get_or_insert([p.x, p.y, p.x, p.y]);
            r[0] = r[0].min(p.x);
            r[1] = r[1].min(p.y);
            r[2] = r[2].max(p.x);
            r[3] = r[3].max(p.y);
        }
        b
    }

    /// Every point moved by `f` (placing the drawing on the paper).
    pub fn map_points(&mut self, f: impl Fn(Point) -> Point) {
        for pen in &mut self.pens {
            for s in &mut pen.strokes {
                for p in s.iter_mut() {
                    *p = f(*p);
                }
            }
        }
    }
}
