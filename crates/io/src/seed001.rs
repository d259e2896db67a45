//! The seed 001 graphic file (seed digest §5.3): a neutral ASCII format, numbers in mm.
//!
//! ```text
//! NI                         entities except points
//! xlm ylm xhm yhm            envelope of the drawing
//! c xlg ylg xhg yhg Np P1 … Pn   per entity: code, its box, Np pairs of numbers
//! NS                         points
//! x1 y1 x2 y2 …
//! ```
//! Numbers are separated by any white space (the layout of lines does not matter). Codes:
//! 1 arc (centre, start, end, (radius, sign)), 2 arc + line (centre, start, end, line end,
//! (sign, ·)), 3 two arcs (centre 1, centre 2, start, middle, end, (sign 1, sign 2)),
//! 4 polyline (vertices; closed when the last repeats the first), 6 regular polygon (centre,
//! vertex, (sides, ·)), 19 offset of a tangent-circle contour (per arc: start, centre,
//! (radius, sign); then the closing point), 20 tangent-circle contour, 25 Bézier,
//! 26 B-spline, 27 interpolation (control points, re-fitted on load), 24 closed polyline.
//! Arc sign: + counter-clockwise, − clockwise.

use crate::import::{ImportError, Imported, Unsupported};
use oficina_geom::fit::{bezier_seed, bspline_clamped, interpolate_local, tangent_circles};
use oficina_geom::{Arc, Drawing, Path, Point, Rect, Segment, SourceRef};
use std::fmt::Write;

/// Most entities or pairs one file may declare (each is checked against the numbers left).
const MAX_COUNT: usize = 50_000_000;

/// One entity of the file, with its parameters as stored.
#[derive(Clone, Debug, PartialEq)]
pub enum SeedEntity {
    /// 1: centre, start, end, radius, sign (+1 counter-clockwise).
    Arc {
        /// Centre.
        center: Point,
        /// Start point.
        start: Point,
        /// End point.
        end: Point,
        /// Radius, mm.
        radius: f64,
        /// +1 counter-clockwise, −1 clockwise.
        sign: f64,
    },
    /// 2: an arc, then a line to `line_end`.
    ArcLine {
        /// Centre.
        center: Point,
        /// Start point.
        start: Point,
        /// End point of the arc.
        end: Point,
        /// End point of the line.
        line_end: Point,
        /// +1 counter-clockwise, −1 clockwise.
        sign: f64,
    },
    /// 3: two arcs, start → middle about `c1`, middle → end about `c2`.
    TwoArcs {
        /// Centre of the first arc.
        c1: Point,
        /// Centre of the second arc.
        c2: Point,
        /// Start point.
        start: Point,
        /// Where the arcs meet.
        middle: Point,
        /// End point.
        end: Point,
        /// Direction of each arc (+1 counter-clockwise).
        signs: [f64; 2],
    },
    /// 4: polyline (open, or closed when its last vertex repeats the first).
    Polyline(Vec<Point>),
    /// 6: regular polygon.
    Polygon {
        /// Centre.
        center: Point,
        /// One vertex.
        vertex: Point,
        /// Number of sides.
        sides: u32,
    },
    /// 19: offset of a tangent-circle contour: (start, centre, radius, sign) per arc, then
    /// the closing point.
    ArcChain {
        /// (start, centre, radius, sign) of each arc.
        arcs: Vec<(Point, Point, f64, f64)>,
        /// The closing point.
        close: Point,
    },
    /// 24: closed polyline (offset of a polyline contour).
    ClosedPolyline(Vec<Point>),
    /// 20, 25, 26, 27: a contour stored as its control points, fitted on load.
    Contour {
        /// The entity code (20, 25, 26 or 27).
        code: u32,
        /// The control points.
        control: Vec<Point>,
    },
}

/// A whole graphic file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SeedFile {
    /// Entities with their source line.
    pub entities: Vec<(SeedEntity, usize)>,
    /// Entities with a code this reader does not know: (code, line).
    pub unknown: Vec<(u32, usize)>,
    /// The file's point list.
    pub points: Vec<Point>,
}

struct Tokens<'a> {
    toks: Vec<(&'a str, usize)>,
    at: usize,
    file: &'a str,
}

impl<'a> Tokens<'a> {
    fn line(&self) -> usize {
        self.toks
            .get(self.at)
            .or(self.toks.last())
            .map_or(1, |t| t.1)
    }

    fn err(&self, what: impl Into<String>) -> ImportError {
        ImportError::new(self.file, format!("line {}", self.line()), what)
    }

    fn num(&mut self, what: &str) -> Result<f64, ImportError> {
        let Some(&(t, _)) = self.toks.get(self.at) else {
            return Err(self.err(format!("file ends where {what} was expected")));
        };
        let v: f64 = t
            .parse()
            .map_err(|_| self.err(format!("'{t}' is not a number ({what})")))?;
        if !v.is_finite() || v.abs() > 1e12 {
            return Err(self.err(format!("{v} is not a usable number ({what})")));
        }
        self.at += 1;
        Ok(v)
    }

    fn count(&mut self, what: &str, per: usize) -> Result<usize, ImportError> {
        let line = self.line();
        let v = self.num(what)?;
        let left = self.toks.len() - self.at;
        if v < 0.0
            || v.fract() != 0.0
            || v as usize > MAX_COUNT
            || (v as usize).saturating_mul(per) > left
        {
            return Err(ImportError::new(
                self.file,
                format!("line {line}"),
                format!("{what} {v} is not a count the file holds ({left} numbers left)"),
            ));
        }
        Ok(v as usize)
    }

    fn point(&mut self, what: &str) -> Result<Point, ImportError> {
        Ok(Point::new(self.num(what)?, self.num(what)?))
    }
}

/// Reads a seed 001 graphic file.
pub fn parse_seed001(text: &str, file: &str) -> Result<SeedFile, ImportError> {
    let toks: Vec<(&str, usize)> = text
        .lines()
        .enumerate()
        .flat_map(|(i, l)| l.split_whitespace().map(move |t| (t, i + 1)))
        .collect();
    let mut t = Tokens { toks, at: 0, file };
    let ni = t.count("NI (entity count)", 6)?;
    for _ in 0..4 {
        t.num("drawing envelope")?;
    }
    let mut out = SeedFile::default();
    for k in 0..ni {
        let line = t.line();
        let code_f = t.num(&format!("code of entity {}", k + 1))?;
        let code = code_f as u32;
        for _ in 0..4 {
            t.num("entity box")?;
        }
        let np = t.count(&format!("Np of entity {} (code {code})", k + 1), 2)?;
        let mut pairs = Vec::with_capacity(np);
        for _ in 0..np {
            pairs.push(t.point("entity parameter")?);
        }
        let need = |n: usize| -> Result<(), ImportError> {
            if np < n {
                Err(ImportError::new(
                    file,
                    format!("line {line}"),
                    format!("entity {} (code {code}) needs {n} pairs, has {np}", k + 1),
                ))
            } else {
                Ok(())
            }
        };
        let e = match code {
            1 => {
                need(4)?;
                SeedEntity::Arc {
                    center: pairs[0],
                    start: pairs[1],
                    end: pairs[2],
                    radius: pairs[3].x,
                    sign: pairs[3].y,
                }
            }
            2 => {
                need(5)?;
                SeedEntity::ArcLine {
                    center: pairs[0],
                    start: pairs[1],
                    end: pairs[2],
                    line_end: pairs[3],
                    sign: pairs[4].x,
                }
            }
            3 => {
                need(6)?;
                SeedEntity::TwoArcs {
                    c1: pairs[0],
                    c2: pairs[1],
                    start: pairs[2],
                    middle: pairs[3],
                    end: pairs[4],
                    signs: [pairs[5].x, pairs[5].y],
                }
            }
            4 => {
                need(2)?;
                SeedEntity::Polyline(pairs)
            }
            6 => {
                need(3)?;
                let sides = pairs[2].x;
                if !(3.0..=10_000.0).contains(&sides) {
                    return Err(ImportError::new(
                        file,
                        format!("line {line}"),
                        format!("regular polygon of {sides} sides"),
                    ));
                }
                SeedEntity::Polygon {
                    center: pairs[0],
                    vertex: pairs[1],
                    sides: sides as u32,
                }
            }
            19 => {
                need(4)?;
                let arcs = pairs[..np - 1]
                    .chunks(3)
                    .filter(|c| c.len() == 3)
                    .map(|c| (c[0], c[1], c[2].x, c[2].y))
                    .collect();
                SeedEntity::ArcChain {
                    arcs,
                    close: pairs[np - 1],
                }
            }
            24 => {
                need(3)?;
                SeedEntity::ClosedPolyline(pairs)
            }
            20 | 25 | 26 | 27 => {
                need(4)?;
                SeedEntity::Contour {
                    code,
                    control: pairs,
                }
            }
            _ => {
                out.unknown.push((code, line));
                continue;
            }
        };
        out.entities.push((e, line));
    }
    if t.at < t.toks.len() {
        let ns = t.count("NS (point count)", 2)?;
        for _ in 0..ns {
            let p = t.point("point")?;
            out.points.push(p);
        }
    }
    if t.at < t.toks.len() {
        return Err(t.err(format!(
            "'{}' after the end of the file's data",
            t.toks[t.at].0
        )));
    }
    Ok(out)
}

fn arc_seg(center: Point, start: Point, end: Point, sign: f64) -> Segment {
    Segment::Arc(Arc::from_center(
        start,
        end,
        center,
        if sign < 0.0 { -1 } else { 1 },
    ))
}

impl SeedEntity {
    /// The entity as a path (contours are fitted by their method).
    pub fn to_path(&self) -> Result<Path, String> {
        Ok(match self {
            SeedEntity::Arc {
                center,
                start,
                end,
                sign,
                ..
            } => Path::new(
                vec![arc_seg(*center, *start, *end, *sign)],
                start.distance(*end) < 1e-9,
            ),
            SeedEntity::ArcLine {
                center,
                start,
                end,
                line_end,
                sign,
            } => Path::new(
                vec![
                    arc_seg(*center, *start, *end, *sign),
                    Segment::line(*end, *line_end),
                ],
                false,
            ),
            SeedEntity::TwoArcs {
                c1,
                c2,
                start,
                middle,
                end,
                signs,
            } => Path::new(
                vec![
                    arc_seg(*c1, *start, *middle, signs[0]),
                    arc_seg(*c2, *middle, *end, signs[1]),
                ],
                false,
            ),
            SeedEntity::Polyline(v) => {
                let closed = v.len() > 2 && v[0].distance(*v.last().unwrap()) < 1e-9;
                Path::polyline(v, closed)
            }
            SeedEntity::ClosedPolyline(v) => Path::polyline(v, true),
            SeedEntity::Polygon {
                center,
                vertex,
                sides,
            } => {
                let r = vertex.distance(*center);
                let a0 = (*vertex - *center).atan2();
                let pts: Vec<Point> = (0..*sides)
                    .map(|k| {
                        let a = a0 + std::f64::consts::TAU * k as f64 / *sides as f64;
                        *center + oficina_geom::Vec2::from_angle(a) * r
                    })
                    .collect();
                Path::polyline(&pts, true)
            }
            SeedEntity::ArcChain { arcs, close } => {
                let segs = (0..arcs.len())
                    .map(|k| {
                        let (s, c, _, sign) = arcs[k];
                        let e = arcs.get(k + 1).map_or(*close, |a| a.0);
                        arc_seg(c, s, e, sign)
                    })
                    .collect();
                Path::new(segs, true)
            }
            SeedEntity::Contour { code, control } => {
                let mut pts = control.clone();
                if pts.len() > 1 && pts[0].distance(*pts.last().unwrap()) < 1e-9 {
                    pts.pop();
                }
                match code {
                    20 => tangent_circles(&pts).map_err(|e| e.to_string())?,
                    25 => {
                        let b = bezier_seed(&pts);
                        Path::polyline(&b.flatten(0.01), true)
                    }
                    26 => Path::polyline(&bspline_clamped(&pts, 16), true),
                    _ => Path::polyline(&interpolate_local(&pts, 16), true),
                }
            }
        })
    }

    fn code(&self) -> u32 {
        match self {
            SeedEntity::Arc { .. } => 1,
            SeedEntity::ArcLine { .. } => 2,
            SeedEntity::TwoArcs { .. } => 3,
            SeedEntity::Polyline(_) => 4,
            SeedEntity::Polygon { .. } => 6,
            SeedEntity::ArcChain { .. } => 19,
            SeedEntity::ClosedPolyline(_) => 24,
            SeedEntity::Contour { code, .. } => *code,
        }
    }

    fn pairs(&self) -> Vec<(f64, f64)> {
        let p = |q: &Point| (q.x, q.y);
        match self {
            SeedEntity::Arc {
                center,
                start,
                end,
                radius,
                sign,
            } => {
                vec![p(center), p(start), p(end), (*radius, *sign)]
            }
            SeedEntity::ArcLine {
                center,
                start,
                end,
                line_end,
                sign,
            } => {
                vec![p(center), p(start), p(end), p(line_end), (*sign, 0.0)]
            }
            SeedEntity::TwoArcs {
                c1,
                c2,
                start,
                middle,
                end,
                signs,
            } => {
                vec![
                    p(c1),
                    p(c2),
                    p(start),
                    p(middle),
                    p(end),
                    (signs[0], signs[1]),
                ]
            }
            SeedEntity::Polyline(v) | SeedEntity::ClosedPolyline(v) => v.iter().map(p).collect(),
            SeedEntity::Contour { control, .. } => control.iter().map(p).collect(),
            SeedEntity::Polygon {
                center,
                vertex,
                sides,
            } => vec![p(center), p(vertex), (*sides as f64, 0.0)],
            SeedEntity::ArcChain { arcs, close } => {
                let mut v: Vec<(f64, f64)> = arcs
                    .iter()
                    .flat_map(|(s, c, r, sg)| [p(s), p(c), (*r, *sg)])
                    .collect();
                v.push(p(close));
                v
            }
        }
    }
}

impl SeedFile {
    /// The file as a drawing: each entity one path on layer `seed001`.
    pub fn to_imported(&self, file: &str) -> Result<Imported, ImportError> {
        let mut drawing = Drawing::new();
        let mut unsupported = Unsupported::default();
        for (k, (e, line)) in self.entities.iter().enumerate() {
            let mut src = SourceRef::new(file, format!("entity {} (code {})", k + 1, e.code()));
            src.line = Some(*line);
            let path = e.to_path().map_err(|m| {
                ImportError::new(
                    file,
                    format!("line {line}"),
                    format!("entity {}: {m}", k + 1),
                )
            })?;
            drawing.push("seed001", path.with_source(src));
        }
        for (code, line) in &self.unknown {
            unsupported.add(&format!("code {code}"), format!("line {line}"));
        }
        Ok(Imported {
            drawing,
            unsupported,
            points: self.points.clone(),
            ..Imported::default()
        })
    }

    /// A file of a drawing: each path as [`path_entities`] writes it.
    pub fn from_drawing(d: &Drawing) -> SeedFile {
        SeedFile {
            entities: d.paths().flat_map(path_entities).map(|e| (e, 0)).collect(),
            unknown: vec![],
            points: vec![],
        }
    }

    /// The file's text.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        let boxes: Vec<Rect> = self
            .entities
            .iter()
            .map(|(e, _)| {
                e.to_path()
                    .ok()
                    .and_then(|p| p.bounding_box())
                    .unwrap_or_else(|| {
                        let q = e.pairs();
                        Rect::from_points((q[0].0, q[0].1), (q[0].0, q[0].1))
                    })
            })
            .collect();
        let mut env = boxes
            .iter()
            .copied()
            .reduce(|a, b| a.union(b))
            .unwrap_or(Rect::ZERO);
        for p in &self.points {
            env = env.union_pt(*p);
        }
        let _ = writeln!(s, "{}", self.entities.len());
        let _ = writeln!(s, "{} {} {} {}", env.x0, env.y0, env.x1, env.y1);
        for ((e, _), b) in self.entities.iter().zip(&boxes) {
            let pairs = e.pairs();
            let _ = writeln!(s, "{} {} {} {} {}", e.code(), b.x0, b.y0, b.x1, b.y1);
            let _ = writeln!(s, "{}", pairs.len());
            for (x, y) in pairs {
                let _ = writeln!(s, "{x} {y}");
            }
        }
        let _ = writeln!(s, "{}", self.points.len());
        for p in &self.points {
            let _ = writeln!(s, "{} {}", p.x, p.y);
        }
        s
    }
}

/// One path as the file's entities: a closed all-arc path as code 19, a path without arcs
/// as one code 4 polyline (Béziers flattened to 0.01 mm), other paths piece by piece (arcs
/// code 1, other pieces code 4).
pub fn path_entities(path: &Path) -> Vec<SeedEntity> {
    let (lines, arcs, cubics) = path.counts();
    if path.is_empty() {
        return vec![];
    }
    if arcs > 0 && lines == 0 && cubics == 0 && path.closed {
        let chain = path
            .segments
            .iter()
            .filter_map(|s| match s {
                Segment::Arc(a) => Some((a.start(), a.center, a.radius, a.sweep.signum())),
                _ => None,
            })
            .collect();
        return vec![SeedEntity::ArcChain {
            arcs: chain,
            close: path.end().unwrap(),
        }];
    }
    if arcs == 0 {
        let mut pts = path.flatten(0.01);
        if path.closed {
            pts.push(pts[0]);
        }
        return vec![SeedEntity::Polyline(pts)];
    }
    path.segments
        .iter()
        .map(|s| match s {
            Segment::Arc(a) => SeedEntity::Arc {
                center: a.center,
                start: a.start(),
                end: a.end(),
                radius: a.radius,
                sign: a.sweep.signum(),
            },
            other => {
                let mut v = vec![other.start()];
                other.flatten_into(0.01, &mut v);
                SeedEntity::Polyline(v)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arc entity laid out as in the seed's App. C.5 example (radius 10, CCW).
    const EXAMPLE: &str = "1\n337.58 273.72 357.58 293.72\n1 337.58 283.72 357.58 293.72\n4\n347.58 283.72\n357.58 283.72\n337.58 283.72\n10.0 1.0\n0\n";

    #[test]
    fn reads_the_seeds_arc_example() {
        let f = parse_seed001(EXAMPLE, "ex.dat").unwrap();
        assert_eq!(f.entities.len(), 1);
        let imp = f.to_imported("ex.dat").unwrap();
        let p = imp.drawing.paths().next().unwrap();
        let Segment::Arc(a) = p.segments[0] else {
            panic!()
        };
        assert!((a.radius - 10.0).abs() < 1e-9 && a.is_ccw());
        assert!(
            (a.sweep - std::f64::consts::PI).abs() < 1e-9,
            "half circle over the top"
        );
        assert_eq!(p.source.line, Some(3));
    }

    #[test]
    fn writes_and_reads_back_every_kind() {
        let sq = vec![
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(4.0, 4.0),
            Point::new(0.0, 4.0),
        ];
        let mut ring: Vec<Point> = (0..20)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 20.0 + 0.1;
                Point::new(40.0 * t.cos(), 110.0 * t.sin())
            })
            .collect();
        ring.push(ring[0]);
        let f = SeedFile {
            entities: vec![
                (SeedEntity::Polyline(sq.clone()), 0),
                (
                    SeedEntity::Polygon {
                        center: Point::new(1.0, 1.0),
                        vertex: Point::new(3.0, 1.0),
                        sides: 6,
                    },
                    0,
                ),
                (
                    SeedEntity::Contour {
                        code: 20,
                        control: ring.clone(),
                    },
                    0,
                ),
                (
                    SeedEntity::Contour {
                        code: 26,
                        control: ring,
                    },
                    0,
                ),
                (
                    SeedEntity::ArcChain {
                        arcs: vec![
                            (Point::new(10.0, 0.0), Point::ORIGIN, 10.0, 1.0),
                            (Point::new(-10.0, 0.0), Point::ORIGIN, 10.0, 1.0),
                        ],
                        close: Point::new(10.0, 0.0),
                    },
                    0,
                ),
            ],
            unknown: vec![],
            points: vec![Point::new(5.0, 6.0)],
        };
        let text = f.to_text();
        let back = parse_seed001(&text, "w.dat").unwrap();
        assert_eq!(back.points, f.points);
        for ((a, _), (b, _)) in f.entities.iter().zip(&back.entities) {
            assert_eq!(a, b);
        }
        let imp = back.to_imported("w.dat").unwrap();
        assert_eq!(imp.drawing.path_count(), 5);
        let circle = imp.drawing.paths().nth(4).unwrap();
        assert!((circle.area() - std::f64::consts::PI * 100.0).abs() < 0.1);
        // A drawing → file → drawing keeps arcs as arcs.
        let again = SeedFile::from_drawing(&imp.drawing);
        let re = parse_seed001(&again.to_text(), "x")
            .unwrap()
            .to_imported("x")
            .unwrap();
        assert_eq!(re.drawing.paths().nth(4).unwrap().counts().1, 2);
    }

    #[test]
    fn errors_name_the_line_and_unknown_codes_are_listed() {
        let e = parse_seed001("1\n0 0 1 1\n4 0 0 1 1\n2\n0 0\n1 x\n", "b.dat").unwrap_err();
        assert_eq!(e.location, "line 6");
        assert!(e.message.contains("'x' is not a number"), "{e}");
        let e = parse_seed001("2\n0 0 1 1\n", "b.dat").unwrap_err();
        assert!(e.message.contains("NI"), "{e}");
        let e = parse_seed001("1\n0 0 1 1\n4 0 0 1 1\n999999999\n", "b.dat").unwrap_err();
        assert!(e.message.contains("not a count"), "{e}");
        let f = parse_seed001("1\n0 0 1 1\n5 0 0 1 1\n1\n0 0\n0\n", "u.dat").unwrap();
        let imp = f.to_imported("u.dat").unwrap();
        assert_eq!(imp.unsupported.total(), 1);
        assert!(imp.unsupported.to_string().contains("code 5"));
    }
}
