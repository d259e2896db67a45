//! `Drawing`: named layers of paths; a path is a chain of lines, circular arcs and cubic
//! Béziers with a style and a reference to where it came from (for error messages).

use crate::arc::Arc;
use kurbo::{CubicBez, Line, ParamCurve, ParamCurveArclen, ParamCurveNearest, Point, Rect};
use std::fmt;

/// One piece of a path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A straight line.
    Line(Line),
    /// A circular arc.
    Arc(Arc),
    /// A cubic Bézier.
    Cubic(CubicBez),
}

impl Segment {
    /// A line from `a` to `b`.
    pub fn line(a: Point, b: Point) -> Segment {
        Segment::Line(Line::new(a, b))
    }

    /// Start point.
    pub fn start(&self) -> Point {
        match self {
            Segment::Line(l) => l.p0,
            Segment::Arc(a) => a.start(),
            Segment::Cubic(c) => c.p0,
        }
    }

    /// End point.
    pub fn end(&self) -> Point {
        match self {
            Segment::Line(l) => l.p1,
            Segment::Arc(a) => a.end(),
            Segment::Cubic(c) => c.p3,
        }
    }

    /// Length, mm.
    pub fn length(&self) -> f64 {
        match self {
            Segment::Line(l) => l.p0.distance(l.p1),
            Segment::Arc(a) => a.length(),
            Segment::Cubic(c) => c.arclen(1e-6),
        }
    }

    /// The same segment run the other way.
    pub fn reversed(&self) -> Segment {
        match self {
            Segment::Line(l) => Segment::line(l.p1, l.p0),
            Segment::Arc(a) => Segment::Arc(a.reversed()),
            Segment::Cubic(c) => Segment::Cubic(CubicBez::new(c.p3, c.p2, c.p1, c.p0)),
        }
    }

    /// Appends the points after the start, no chord further than `tol` from the segment.
    pub fn flatten_into(&self, tol: f64, out: &mut Vec<Point>) {
        match self {
            Segment::Line(l) => out.push(l.p1),
            Segment::Arc(a) => out.extend(a.flatten(tol).into_iter().skip(1)),
            Segment::Cubic(c) => {
                // kurbo's flattening of a one-segment Bézier path, to `tol`.
                let mut first = true;
                let els = [
                    kurbo::PathEl::MoveTo(c.p0),
                    kurbo::PathEl::CurveTo(c.p1, c.p2, c.p3),
                ];
                kurbo::flatten(els, tol.max(1e-9), |el| match el {
                    kurbo::PathEl::LineTo(p) => out.push(p),
                    kurbo::PathEl::MoveTo(_) if first => first = false,
                    _ => {}
                });
            }
        }
    }

    /// Distance from `p` to the segment.
    pub fn distance(&self, p: Point) -> f64 {
        match self {
            Segment::Line(l) => l.nearest(p, 1e-9).distance_sq.sqrt(),
            Segment::Arc(a) => a.distance(p),
            Segment::Cubic(c) => c.nearest(p, 1e-9).distance_sq.sqrt(),
        }
    }

    /// Bounding box.
    pub fn bounding_box(&self) -> Rect {
        match self {
            Segment::Line(l) => Rect::from_points(l.p0, l.p1),
            Segment::Arc(a) => a.bounding_box(),
            Segment::Cubic(c) => kurbo::ParamCurveExtrema::bounding_box(c),
        }
    }

    /// The point at fraction `t` ∈ [0, 1] (by parameter, not by length, for Béziers).
    pub fn eval(&self, t: f64) -> Point {
        match self {
            Segment::Line(l) => l.eval(t),
            Segment::Arc(a) => a.point_at(t),
            Segment::Cubic(c) => c.eval(t),
        }
    }
}

/// 8-bit RGBA colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Color {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
    /// Alpha (255 opaque).
    pub a: u8,
}

impl Color {
    /// Opaque black.
    pub const BLACK: Color = Color::rgb(0, 0, 0);

    /// An opaque colour.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Color {
        Color { r, g, b, a: 255 }
    }
}

/// How a path is drawn: stroke colour and width (mm), fill colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Stroke colour; `None`: not stroked.
    pub stroke: Option<Color>,
    /// Stroke width, mm (0: hairline).
    pub stroke_width: f64,
    /// Fill colour; `None`: not filled.
    pub fill: Option<Color>,
}

impl Default for Style {
    fn default() -> Self {
        Style {
            stroke: Some(Color::BLACK),
            stroke_width: 0.0,
            fill: None,
        }
    }
}

/// Where a path came from: file, element (SVG id, DXF handle, entity number) and line.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SourceRef {
    /// The file.
    pub file: String,
    /// SVG id, DXF handle or entity number.
    pub element: String,
    /// Line in the file, where known.
    pub line: Option<usize>,
}

impl SourceRef {
    /// A reference to `element` of `file`, line unknown.
    pub fn new(file: impl Into<String>, element: impl Into<String>) -> SourceRef {
        SourceRef {
            file: file.into(),
            element: element.into(),
            line: None,
        }
    }
}

impl fmt::Display for SourceRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = if self.file.is_empty() {
            "<drawing>"
        } else {
            &self.file
        };
        write!(f, "{file}")?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        if !self.element.is_empty() {
            write!(f, " ({})", self.element)?;
        }
        Ok(())
    }
}

/// A chain of segments, each starting where the previous ends; `closed` joins the last end
/// to the first start (with a line if they differ).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Path {
    /// The segments in order.
    pub segments: Vec<Segment>,
    /// The last end joins the first start.
    pub closed: bool,
    /// How it is drawn.
    pub style: Style,
    /// Where it came from.
    pub source: SourceRef,
}

impl Path {
    /// A path of `segments`, default style, no source.
    pub fn new(segments: Vec<Segment>, closed: bool) -> Path {
        Path {
            segments,
            closed,
            ..Path::default()
        }
    }

    /// A polyline through `points` (closed or not).
    pub fn polyline(points: &[Point], closed: bool) -> Path {
        let segments = points
            .windows(2)
            .filter(|w| w[0] != w[1])
            .map(|w| Segment::line(w[0], w[1]))
            .collect();
        let mut p = Path::new(segments, closed);
        p.close_gap();
        p
    }

    /// The same path with `source`.
    pub fn with_source(mut self, source: SourceRef) -> Path {
        self.source = source;
        self
    }

    /// The same path with `style`.
    pub fn with_style(mut self, style: Style) -> Path {
        self.style = style;
        self
    }

    /// No segments.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// Start of the first segment.
    pub fn start(&self) -> Option<Point> {
        self.segments.first().map(|s| s.start())
    }

    /// End of the last segment.
    pub fn end(&self) -> Option<Point> {
        self.segments.last().map(|s| s.end())
    }

    /// For a closed path whose last end misses its first start, adds the closing line.
    pub fn close_gap(&mut self) {
        if let (true, Some(s), Some(e)) = (self.closed, self.start(), self.end()) {
            if s.distance(e) > 1e-9 {
                self.segments.push(Segment::line(e, s));
            }
        }
    }

    /// Length along the segments, mm.
    pub fn length(&self) -> f64 {
        self.segments.iter().map(|s| s.length()).sum()
    }

    /// Vertices of the path flattened to `tol`: first point first; a closed path does not
    /// repeat its first point at the end.
    pub fn flatten(&self, tol: f64) -> Vec<Point> {
        let mut out = Vec::new();
        if let Some(s) = self.start() {
            out.push(s);
        }
        for seg in &self.segments {
            seg.flatten_into(tol, &mut out);
        }
        if self.closed && out.len() > 1 && out[0].distance(*out.last().unwrap()) < 1e-9 {
            out.pop();
        }
        out
    }

    /// Signed area of the closed path (> 0 counter-clockwise), from its flattening to 1 µm.
    pub fn area(&self) -> f64 {
        crate::polygon::ring_area(&to_ring(&self.flatten(1e-3)))
    }

    /// The path run backwards.
    pub fn reversed(&self) -> Path {
        Path {
            segments: self.segments.iter().rev().map(|s| s.reversed()).collect(),
            ..self.clone()
        }
    }

    /// Bounding box of every segment.
    pub fn bounding_box(&self) -> Option<Rect> {
        self.segments
            .iter()
            .map(|s| s.bounding_box())
            .reduce(|a, b| a.union(b))
    }

    /// Distance from `p` to the nearest segment.
    pub fn distance(&self, p: Point) -> f64 {
        self.segments
            .iter()
            .map(|s| s.distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    /// Count of each kind: (lines, arcs, cubics).
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for s in &self.segments {
            match s {
                Segment::Line(_) => c.0 += 1,
                Segment::Arc(_) => c.1 += 1,
                Segment::Cubic(_) => c.2 += 1,
            }
        }
        c
    }

    /// Applies `f` to every point of a path made only of lines and cubics, and maps arcs by
    /// `arc_map`: used by transforms that keep circles circles.
    pub fn map(&self, f: impl Fn(Point) -> Point, arc_map: impl Fn(&Arc) -> Segment) -> Path {
        let segments = self
            .segments
            .iter()
            .map(|s| match s {
                Segment::Line(l) => Segment::line(f(l.p0), f(l.p1)),
                Segment::Cubic(c) => {
                    Segment::Cubic(CubicBez::new(f(c.p0), f(c.p1), f(c.p2), f(c.p3)))
                }
                Segment::Arc(a) => arc_map(a),
            })
            .collect();
        Path {
            segments,
            ..self.clone()
        }
    }
}

impl Path {
    /// The path under an affine map. Arcs stay arcs under similarities (rotation, uniform
    /// scale, translation, reflection: a reflection reverses their direction); under any
    /// other map they become cubic Béziers (a circle becomes an ellipse).
    pub fn transform(&self, m: kurbo::Affine) -> Path {
        let c = m.as_coeffs();
        let det = c[0] * c[3] - c[1] * c[2];
        // Similar iff the columns are orthogonal and of equal length.
        let col0 = kurbo::Vec2::new(c[0], c[1]);
        let col1 = kurbo::Vec2::new(c[2], c[3]);
        let scale = det.abs().sqrt();
        let similar = (col0.dot(col1)).abs() <= 1e-12 * (1.0 + col0.hypot2())
            && (col0.hypot() - col1.hypot()).abs() <= 1e-12 * (1.0 + col0.hypot());
        let mut segments = Vec::with_capacity(self.segments.len());
        for s in &self.segments {
            match s {
                Segment::Line(l) => segments.push(Segment::line(m * l.p0, m * l.p1)),
                Segment::Cubic(b) => segments.push(Segment::Cubic(CubicBez::new(
                    m * b.p0,
                    m * b.p1,
                    m * b.p2,
                    m * b.p3,
                ))),
                Segment::Arc(a) if similar && det != 0.0 => {
                    let center = m * a.center;
                    let start = m * a.start();
                    segments.push(Segment::Arc(Arc::new(
                        center,
                        a.radius * scale,
                        (start - center).atan2(),
                        a.sweep * det.signum(),
                    )));
                }
                Segment::Arc(a) => {
                    // The cubic count grows as (radius / tolerance)^(1/6) and with the sweep:
                    // a tolerance relative to the radius and at most one turn keep it to a few
                    // dozen whatever the numbers (a fuzzed DXF asked for 2.4 GB of cubics).
                    let sweep = a.sweep.clamp(-std::f64::consts::TAU, std::f64::consts::TAU);
                    let tolerance = (a.radius.abs() * 1e-9).max(1e-6);
                    let k =
                        kurbo::Arc::new(a.center, (a.radius, a.radius), a.start_angle, sweep, 0.0);
                    let mut from = a.start();
                    k.to_cubic_beziers(tolerance, |p1, p2, p3| {
                        segments.push(Segment::Cubic(CubicBez::new(
                            m * from,
                            m * p1,
                            m * p2,
                            m * p3,
                        )));
                        from = p3;
                    });
                }
            }
        }
        Path {
            segments,
            ..self.clone()
        }
    }
}

/// Points as `[x, y]` pairs (the polygon library's type).
pub fn to_ring(points: &[Point]) -> Vec<[f64; 2]> {
    points.iter().map(|p| [p.x, p.y]).collect()
}

/// A named layer of paths.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    /// The layer's name.
    pub name: String,
    /// Its paths in drawing order.
    pub paths: Vec<Path>,
}

/// Layers of paths, in mm, y up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drawing {
    /// Layers in file order.
    pub layers: Vec<Layer>,
}

impl Drawing {
    /// An empty drawing.
    pub fn new() -> Drawing {
        Drawing::default()
    }

    /// The layer called `name`, made if missing.
    pub fn layer_mut(&mut self, name: &str) -> &mut Layer {
        if let Some(i) = self.layers.iter().position(|l| l.name == name) {
            return &mut self.layers[i];
        }
        self.layers.push(Layer {
            name: name.to_string(),
            paths: Vec::new(),
        });
        self.layers.last_mut().unwrap()
    }

    /// Adds `path` to the layer called `layer`, made if missing.
    pub fn push(&mut self, layer: &str, path: Path) {
        self.layer_mut(layer).paths.push(path);
    }

    /// Every path, layer by layer.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.layers.iter().flat_map(|l| l.paths.iter())
    }

    /// Paths over all layers.
    pub fn path_count(&self) -> usize {
        self.layers.iter().map(|l| l.paths.len()).sum()
    }

    /// Bounding box of every path.
    pub fn bounding_box(&self) -> Option<Rect> {
        self.paths()
            .filter_map(|p| p.bounding_box())
            .reduce(|a, b| a.union(b))
    }

    /// Every closed path (the candidates for pockets and profiles).
    pub fn closed_paths(&self) -> impl Iterator<Item = &Path> {
        self.paths().filter(|p| p.closed)
    }

    /// A copy with `f` applied to each path.
    pub fn map_paths(&self, f: impl Fn(&Path) -> Path) -> Drawing {
        Drawing {
            layers: self
                .layers
                .iter()
                .map(|l| Layer {
                    name: l.name.clone(),
                    paths: l.paths.iter().map(&f).collect(),
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_square_area_sign_and_reverse() {
        let sq = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let p = Path::polyline(&sq, true);
        assert_eq!(p.segments.len(), 4, "closing line added");
        assert!((p.area() - 100.0).abs() < 1e-9);
        assert!((p.reversed().area() + 100.0).abs() < 1e-9);
        assert!((p.length() - 40.0).abs() < 1e-12);
        assert!((p.distance(Point::new(5.0, 5.0)) - 5.0).abs() < 1e-9);
    }

    #[test]
    fn circle_path_flattens_within_tolerance_and_has_pi_r2_area() {
        let c = Path::new(
            vec![Segment::Arc(Arc::circle(Point::new(1.0, 2.0), 10.0))],
            true,
        );
        let pts = c.flatten(0.001);
        assert!(pts
            .iter()
            .all(|p| (p.distance(Point::new(1.0, 2.0)) - 10.0).abs() < 1e-9));
        // Inscribed polygon loses at most perimeter × tolerance.
        let a = c.area();
        assert!(a < 100.0 * std::f64::consts::PI && a > 100.0 * std::f64::consts::PI - 0.07);
    }

    #[test]
    fn cubic_flattening_ends_at_the_end_point() {
        let s = Segment::Cubic(CubicBez::new(
            (0.0, 0.0),
            (0.0, 10.0),
            (10.0, 10.0),
            (10.0, 0.0),
        ));
        let mut out = vec![s.start()];
        s.flatten_into(0.01, &mut out);
        assert!(out.len() > 5);
        assert_eq!(*out.last().unwrap(), Point::new(10.0, 0.0));
        for w in out.windows(2) {
            let m = w[0].midpoint(w[1]);
            assert!(s.distance(m) < 0.011);
        }
    }

    #[test]
    fn transforms_keep_arcs_under_similarities_only() {
        let c = Path::new(
            vec![Segment::Arc(Arc::circle(Point::new(1.0, 0.0), 2.0))],
            true,
        );
        let m = kurbo::Affine::translate((5.0, 0.0))
            * kurbo::Affine::rotate(0.3)
            * kurbo::Affine::scale(3.0);
        let t = c.transform(m);
        let Segment::Arc(a) = t.segments[0] else {
            panic!()
        };
        assert!((a.radius - 6.0).abs() < 1e-12 && a.is_ccw());
        let flip = c.transform(kurbo::Affine::FLIP_Y);
        let Segment::Arc(f) = flip.segments[0] else {
            panic!()
        };
        assert!(!f.is_ccw() && (f.center.y).abs() < 1e-12);
        let e = c.transform(kurbo::Affine::scale_non_uniform(2.0, 1.0));
        assert!(e.segments.iter().all(|s| matches!(s, Segment::Cubic(_))));
        assert!(
            (e.area() - 2.0 * std::f64::consts::PI * 4.0).abs() < 0.02,
            "{}",
            e.area()
        );
    }

    #[test]
    fn source_reference_reads_well() {
        let mut s = SourceRef::new("a.dxf", "LINE #3");
        s.line = Some(12);
        assert_eq!(s.to_string(), "a.dxf:12 (LINE #3)");
    }
}
