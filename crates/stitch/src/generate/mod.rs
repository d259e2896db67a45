//! A `Drawing` becomes a `StitchPlan`. Per SVG element (its subpaths together):
//! - a fill colour on closed subpaths → tatami fill (holes from nesting), fill colour;
//! - a stroke at least `satin_min_width` wide → a satin column along each subpath, or between
//!   the two rails when the element is exactly two open subpaths (Ink/Stitch's convention);
//! - any other stroke (or a DXF line) → running stitch.
//!
//! Shapes are grouped by thread colour in order of first appearance (the seed: "group all
//! primitives of one colour" to save thread changes), within a colour fills first, then
//! satins, then running lines (details on top), each group ordered nearest-neighbour from
//! where the needle is, each shape sewn forwards or backwards, whichever starts nearer (plot's
//! `nearest_neighbour` assumes a stroke reversed starts at its end; a shape with underlay
//! does not, so the order is chosen here on each shape's two real starts).
//! Travel: a jump; longer than `trim_length` a trim first. The design is centred on the
//! hoop centre.
//!
//! An Ink/Stitch design ([`generate_inkstitch`] with `crate::inkstitch`'s attributes) is sewn
//! as Ink/Stitch sews it instead: each element with its own parameters (`ink.rs`), in document
//! order, a colour change wherever the colour changes, trims, stops and ties per element.

mod fill;
mod guided;
mod ink;
mod ripple;
mod running;
mod satin;

use crate::inkstitch::{Inkstitch, Ties};
use crate::plan::{ColorBlock, Kind, Stitch, StitchPlan, Thread};
use oficina_geom::{offset_regions, Area, Color, Drawing, Join, Path, Point};

pub(crate) use fill::FillParams;
pub use running::running;

/// What the generator needs; lengths in mm, the angle in degrees.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// Running stitch length (the seed's PASSO).
    pub stitch_length: f64,
    /// Satin zig spacing on the outer rail.
    pub satin_spacing: f64,
    /// Strokes at least this wide sew as satin (the seed's LARGURA starts at 1 mm).
    pub satin_min_width: f64,
    /// Distance between tatami rows, mm.
    pub fill_spacing: f64,
    /// Tatami stitch length, mm.
    pub fill_stitch_length: f64,
    /// Direction of the tatami rows, degrees from X.
    pub fill_angle_deg: f64,
    /// Rows per stagger cycle of the tatami grid.
    pub stagger: u32,
    /// Underlay: a centre walk under satins, a sparse cross fill under fills.
    pub underlay: bool,
    /// Added to satin widths and fill rows (mm in total), against the fabric's pull-in.
    pub pull_compensation: f64,
    /// Jumps longer than this are trimmed first.
    pub trim_length: f64,
    /// The longest sewn stitch (the seed's machine: 12.4 mm; DST holds 12.1).
    pub max_stitch: f64,
    /// Flattening tolerance of curves before stitching.
    pub tolerance: f64,
    /// Move the design's centre to the hoop centre (the files' origin).
    pub center: bool,
    /// Closed paths without a fill colour (DXF outlines) are filled too, in their stroke
    /// colour, instead of outlined.
    pub fill_closed: bool,
    /// Lock stitches where the thread is cut: a tie-in after each trim or colour change, a
    /// tie-off before it, each two stitches of `TIE` mm back and forth.
    pub ties: bool,
}

/// Length of a lock stitch, mm.
pub const TIE: f64 = 0.5;

impl Default for Params {
    fn default() -> Params {
        Params {
            stitch_length: 2.5,
            satin_spacing: 0.4,
            satin_min_width: 1.0,
            fill_spacing: 0.4,
            fill_stitch_length: 3.0,
            fill_angle_deg: 0.0,
            stagger: 4,
            underlay: true,
            pull_compensation: 0.2,
            trim_length: 3.0,
            max_stitch: 12.1,
            tolerance: 0.02,
            center: true,
            ties: true,
            fill_closed: false,
        }
    }
}

/// Bad parameters or a design with nothing to sew.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct GenerateError(pub String);

impl Params {
    /// The seed's ranges (PASSO 0.1–12.7 mm) and what keeps the stitch count bounded.
    pub fn check(&self) -> Result<(), GenerateError> {
        let range = |name: &str, v: f64, lo: f64, hi: f64| {
            if v >= lo && v <= hi {
                Ok(())
            } else {
                Err(GenerateError(format!("{name} {v} is outside {lo}..{hi}")))
            }
        };
        range("stitch length (mm)", self.stitch_length, 0.1, 12.7)?;
        range(
            "fill stitch length (mm)",
            self.fill_stitch_length,
            0.5,
            12.1,
        )?;
        range("satin spacing (mm)", self.satin_spacing, 0.1, 5.0)?;
        range("fill row spacing (mm)", self.fill_spacing, 0.1, 5.0)?;
        range("satin minimum width (mm)", self.satin_min_width, 0.0, 100.0)?;
        range("fill angle (degrees)", self.fill_angle_deg, -360.0, 360.0)?;
        range("pull compensation (mm)", self.pull_compensation, 0.0, 5.0)?;
        range("trim length (mm)", self.trim_length, 0.0, 1000.0)?;
        range("maximum stitch (mm)", self.max_stitch, 1.0, 12.7)?;
        range("tolerance (mm)", self.tolerance, 0.001, 1.0)?;
        if self.stagger == 0 || self.stagger > 100 {
            return Err(GenerateError(format!(
                "stagger {} is outside 1..100",
                self.stagger
            )));
        }
        Ok(())
    }
}

/// The most stitches a design may have (commercial designs rarely pass 200,000).
pub const MAX_STITCHES: usize = 2_000_000;

/// An upper estimate of the stitches, before any is made: fills by their bounding boxes'
/// area over (row spacing × stitch length), satins by length over spacing, doubled, running
/// stitch by length over stitch length; an Ink/Stitch element with its own spacings, times
/// its repeats, bean stitches and underlay layers.
fn estimate_stitches(drawing: &Drawing, p: &Params, ink: &Inkstitch) -> f64 {
    drawing
        .paths()
        .map(|path| {
            let len = path.length();
            let st = path.style;
            let area = path.bounding_box().map_or(0.0, |b| b.area());
            let (line, rows, times) = if ink.is_inkstitch {
                let e = ink.element(&path.source.element);
                let line = e
                    .running_stitch_length
                    .min(e.zigzag_spacing)
                    .min(e.center_walk_length)
                    .min(e.contour_length)
                    .min(p.stitch_length.min(p.satin_spacing));
                let rows = e.row_spacing.min(e.fill_underlay_row_spacing);
                let layers = 1 + e.fill_underlay_angles.len();
                // A ripple sews its line once per copy (the copies are no longer than it).
                let copies = match (e.stroke_method, e.ripple.min_line_dist) {
                    (crate::StrokeMethod::Ripple, Some(d)) => {
                        path.bounding_box()
                            .map_or(0.0, |b| b.width().hypot(b.height()))
                            / d
                            + 2.0
                    }
                    (crate::StrokeMethod::Ripple, None) => e.ripple.line_count as f64 + 2.0,
                    _ => 1.0,
                };
                // Its grid: a line across the copies (no longer than the box) per grid step.
                let diag = path
                    .bounding_box()
                    .map_or(0.0, |b| b.width().hypot(b.height()));
                let copies =
                    if e.stroke_method == crate::StrokeMethod::Ripple && e.ripple.grid_size > 0.0 {
                        copies + diag / e.ripple.grid_size.max(0.1)
                    } else {
                        copies
                    };
                let times = (e.repeats as usize * (1 + 2 * e.bean_stitch_repeats as usize))
                    .max(layers)
                    .max(4) as f64
                    * copies;
                (line, rows, times)
            } else {
                (p.stitch_length.min(p.satin_spacing), p.fill_spacing, 1.0)
            };
            let mut n = len / line * 2.0 * times;
            if st.fill.is_some() || p.fill_closed {
                n += area / (rows * p.fill_stitch_length.min(1.0)) * 2.0 * times;
            }
            if n.is_finite() {
                n
            } else {
                f64::INFINITY
            }
        })
        .sum()
}

/// Stitch type of a shape, in the order they are sewn within a colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ShapeKind {
    /// Tatami fill.
    Fill,
    /// Satin column.
    Satin,
    /// Running stitch.
    Running,
}

/// One stitched object: underlay runs first, then top runs; a run is reached by a jump
/// (or sewn into when `sew_into`).
struct Shape {
    color: Color,
    kind: ShapeKind,
    underlay: Vec<fill::Run>,
    top: Vec<fill::Run>,
    /// Whether the backwards shape may sew from its underlay into its top (the forwards
    /// one says it in its first top run).
    rev_link: bool,
    /// Lock stitches where a cut thread starts it (`start`) and where it is cut after it.
    ties: Ties,
    /// Tied off at its end even when the thread goes on to the next shape uncut.
    force_lock: bool,
    /// The thread is cut after the shape.
    trim_after: bool,
    /// The machine stops after the shape.
    stop_after: bool,
    /// A move to the shape no longer than this is sewn, not jumped (Ink/Stitch's minimum jump).
    min_jump: f64,
}

const BOTH_TIES: Ties = Ties {
    start: true,
    end: true,
};

impl Shape {
    fn runs(&self) -> impl Iterator<Item = &fill::Run> {
        self.underlay.iter().chain(self.top.iter())
    }

    fn start(&self) -> Option<Point> {
        self.runs().find_map(|r| r.points.first().copied())
    }

    /// Where [`Shape::reversed`] starts, without building it: the underlay's last point, or
    /// the top's if there is no underlay.
    fn reversed_start(&self) -> Option<Point> {
        let part = if self.underlay.iter().any(|r| !r.points.is_empty()) {
            &self.underlay
        } else {
            &self.top
        };
        part.iter().rev().find_map(|r| r.points.last().copied())
    }

    /// The same stitches sewn backwards, underlay still first.
    fn reversed(&self) -> Shape {
        let rev = |runs: &[fill::Run]| {
            let n = runs.len();
            (0..n)
                .rev()
                .map(|i| fill::Run {
                    points: runs[i].points.iter().rev().copied().collect(),
                    // Reaching run i backwards comes from run i + 1: the same link.
                    sew_into: i + 1 < n && runs[i + 1].sew_into,
                })
                .collect()
        };
        let mut top: Vec<fill::Run> = rev(&self.top);
        let fwd_link = self.top.first().is_some_and(|r| r.sew_into);
        if let Some(t) = top.first_mut() {
            t.sew_into = self.rev_link && !self.underlay.is_empty();
        }
        Shape {
            color: self.color,
            kind: self.kind,
            underlay: rev(&self.underlay),
            top,
            rev_link: fwd_link,
            ties: self.ties,
            force_lock: self.force_lock,
            trim_after: self.trim_after,
            stop_after: self.stop_after,
            min_jump: self.min_jump,
        }
    }
}

/// How many shapes of each kind, for the report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Generated {
    /// The stitches.
    pub plan: StitchPlan,
    /// Shapes sewn as fill.
    pub fills: usize,
    /// Shapes sewn as satin.
    pub satins: usize,
    /// Shapes sewn as running stitch.
    pub runnings: usize,
}

/// Stitches for every path of `drawing`. `progress(done, total)` is called per shape.
pub fn generate(
    drawing: &Drawing,
    name: &str,
    p: &Params,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Generated, GenerateError> {
    generate_inkstitch(drawing, name, p, &Inkstitch::default(), progress)
}

/// Stitches for every path of `drawing`, an Ink/Stitch design when `ink` says so: each
/// element with its own parameters, sewn in document order (Ink/Stitch's), a colour change
/// wherever the colour changes from one element to the next. Otherwise as [`generate`].
pub fn generate_inkstitch(
    drawing: &Drawing,
    name: &str,
    p: &Params,
    ink: &Inkstitch,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Generated, GenerateError> {
    p.check()?;
    let estimate = estimate_stitches(drawing, p, ink);
    if estimate > MAX_STITCHES as f64 {
        return Err(GenerateError(format!(
            "{name}: about {estimate:.0} stitches at these settings, more than the {MAX_STITCHES} \
             a design may have: scale the design down or use longer stitches / wider spacing"
        )));
    }
    let groups = elements(drawing);
    let total = groups.len();
    // Where Ink/Stitch's commands and guide lines place things, per element.
    let placed = if ink.is_inkstitch {
        ink.placed(drawing)
    } else {
        Default::default()
    };
    let nowhere = crate::inkstitch::Placement::default();
    let mut shapes: Vec<Shape> = Vec::new();
    for (n, paths) in groups.iter().enumerate() {
        if ink.is_inkstitch {
            if ink.ignored(&paths[0].source.element) {
                progress(n + 1, total);
                continue;
            }
            let id = &paths[0].source.element;
            let e = ink.element(id);
            let at = placed.get(id).unwrap_or(&nowhere);
            // Ink/Stitch starts a fill where the needle is (without a start command).
            let needle = shapes
                .last()
                .and_then(|s| s.runs().filter_map(|r| r.points.last().copied()).last());
            shapes.extend(ink::element_shapes(paths, &e, at, needle, p)?);
        } else {
            shapes.extend(element_shapes(paths, p)?);
        }
        progress(n + 1, total);
    }
    shapes.retain(|s| s.start().is_some());
    if shapes.is_empty() {
        return Err(GenerateError(format!(
            "{name}: nothing to sew (no stroked or filled path with length)"
        )));
    }
    let mut g = Generated::default();
    for s in &shapes {
        match s.kind {
            ShapeKind::Fill => g.fills += 1,
            ShapeKind::Satin => g.satins += 1,
            ShapeKind::Running => g.runnings += 1,
        }
    }
    let plan = assemble(shapes, name, p, ink.is_inkstitch);
    // Centre the design on the hoop centre.
    let plan = match plan.bounds().filter(|_| p.center) {
        Some(b) => plan.translated(-(b[0] + b[2]) / 2.0, -(b[1] + b[3]) / 2.0),
        None => plan,
    };
    g.plan = plan;
    Ok(g)
}

/// Paths grouped by their source element, in drawing order (an SVG path's subpaths
/// together, so holes stay with their outline).
fn elements(drawing: &Drawing) -> Vec<Vec<&Path>> {
    let mut out: Vec<Vec<&Path>> = Vec::new();
    let mut prev: Option<(&str, &str)> = None;
    for layer in &drawing.layers {
        for path in &layer.paths {
            let key = (layer.name.as_str(), path.source.element.as_str());
            let same = prev == Some(key) && !key.1.is_empty();
            if same {
                out.last_mut().unwrap().push(path);
            } else {
                out.push(vec![path]);
            }
            prev = Some(key);
        }
    }
    out
}

fn run(points: Vec<Point>) -> fill::Run {
    fill::Run {
        points,
        sew_into: false,
    }
}

fn element_shapes(paths: &[&Path], p: &Params) -> Result<Vec<Shape>, GenerateError> {
    let mut style = paths[0].style;
    if p.fill_closed && style.fill.is_none() && paths.iter().any(|q| q.closed) {
        style.fill = Some(style.stroke.unwrap_or(Color::BLACK));
        style.stroke = None;
    }
    let mut out = Vec::new();
    if let Some(color) = style.fill {
        let closed: Vec<Path> = paths
            .iter()
            .filter(|q| q.closed)
            .map(|q| (*q).clone())
            .collect();
        for area in Area::from_paths(&closed) {
            let region = area.to_region(p.tolerance);
            let angle = p.fill_angle_deg.to_radians();
            let top = fill::tatami(
                &region,
                &FillParams {
                    spacing: p.fill_spacing,
                    length: p.fill_stitch_length,
                    angle,
                    stagger: p.stagger,
                    pull_compensation: p.pull_compensation,
                    along_edge: false,
                },
            );
            let mut underlay = Vec::new();
            if p.underlay {
                // Inset so the underlay never peeks out; rows across the top's.
                let inset = offset_regions(
                    std::slice::from_ref(&region),
                    -0.6,
                    Join::Miter { min_angle: 0.5 },
                )
                .map_err(|e| GenerateError(format!("{}: underlay inset: {e}", paths[0].source)))?;
                for r in &inset {
                    underlay.extend(fill::tatami(
                        r,
                        &FillParams {
                            spacing: (4.0 * p.fill_spacing).max(1.5),
                            length: p.fill_stitch_length,
                            angle: angle + std::f64::consts::FRAC_PI_2,
                            stagger: 1,
                            pull_compensation: 0.0,
                            along_edge: false,
                        },
                    ));
                }
            }
            // The top is sewn into from the underlay's end where that line stays inside
            // (the top covers it); the same backwards, from the underlay's start.
            let mut top = top;
            let ends = |runs: &[fill::Run]| {
                Some((*runs.first()?.points.first()?, *runs.last()?.points.last()?))
            };
            let mut rev_link = false;
            if let (Some((u0, u1)), Some((t0, t1))) = (ends(&underlay), ends(&top)) {
                top[0].sew_into = fill::inside_line(u1, t0, &region);
                rev_link = fill::inside_line(u0, t1, &region);
            }
            out.push(Shape {
                color,
                kind: ShapeKind::Fill,
                underlay,
                top,
                rev_link,
                ties: BOTH_TIES,
                force_lock: false,
                trim_after: false,
                stop_after: false,
                min_jump: 0.0,
            });
        }
    }
    if let Some(color) = style.stroke.or(if style.fill.is_none() {
        Some(Color::BLACK)
    } else {
        None
    }) {
        let lines: Vec<Vec<Point>> = paths
            .iter()
            .map(|q| {
                let mut pts = q.flatten(p.tolerance);
                if q.closed && !pts.is_empty() {
                    pts.push(pts[0]);
                }
                pts
            })
            .filter(|pts| pts.len() >= 2)
            .collect();
        let width = style.stroke_width + p.pull_compensation;
        let two_rails = lines.len() == 2 && paths.iter().all(|q| !q.closed) && style.fill.is_none();
        if style.stroke.is_some() && style.stroke_width >= p.satin_min_width && two_rails {
            // Satin between two rails: both resampled to a common parameter.
            let len = |l: &Vec<Point>| l.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
            let m = ((len(&lines[0]).max(len(&lines[1])) / 0.2).ceil() as usize).clamp(2, 100_000);
            let (mut a, mut b) = (satin::resample(&lines[0], m), satin::resample(&lines[1], m));
            // Rails drawn in opposite directions are paired end to start.
            if a[0].distance(b[0]) > a[0].distance(b[m - 1]) {
                b.reverse();
            }
            let centre: Vec<Point> = a.iter().zip(&b).map(|(x, y)| x.midpoint(*y)).collect();
            let half = p.pull_compensation / 2.0;
            for i in 0..m {
                let d = (a[i] - b[i]).normalize();
                if d.is_finite() {
                    a[i] += d * half;
                    b[i] -= d * half;
                }
            }
            out.push(satin_shape(color, &centre, &a, &b, p));
        } else {
            for line in &lines {
                if style.stroke.is_some() && style.stroke_width >= p.satin_min_width {
                    let (l, r) = satin::rails(line, width / 2.0);
                    out.push(satin_shape(color, line, &l, &r, p));
                } else {
                    out.push(Shape {
                        color,
                        kind: ShapeKind::Running,
                        underlay: vec![],
                        top: vec![run(running(line, p.stitch_length))],
                        rev_link: false,
                        ties: BOTH_TIES,
                        force_lock: false,
                        trim_after: false,
                        stop_after: false,
                        min_jump: 0.0,
                    });
                }
            }
        }
    }
    Ok(out)
}

/// A satin: a centre walk underlay out, the column sewn back over it.
fn satin_shape(color: Color, centre: &[Point], l: &[Point], r: &[Point], p: &Params) -> Shape {
    let mut top = satin::satin(l, r, p.satin_spacing, p.max_stitch);
    let underlay = if p.underlay {
        top.reverse();
        vec![run(running(centre, p.stitch_length))]
    } else {
        vec![]
    };
    let mut top = vec![run(top)];
    top[0].sew_into = p.underlay;
    Shape {
        color,
        kind: ShapeKind::Satin,
        underlay,
        top,
        rev_link: p.underlay,
        ties: BOTH_TIES,
        force_lock: false,
        trim_after: false,
        stop_after: false,
        min_jump: 0.0,
    }
}

fn thread(c: Color) -> Thread {
    Thread {
        rgb: [c.r, c.g, c.b],
        name: String::new(),
    }
}

/// A tie-off at `at`: back along the last stitch by `TIE` and forward again.
fn tie(stitches: &mut Vec<Stitch>, at: Point) {
    let prev = stitches
        .iter()
        .rev()
        .filter(|s| s.kind == Kind::Stitch)
        .map(|s| Point::new(s.x, s.y))
        .find(|q| q.distance(at) > 1e-6);
    if let Some(prev) = prev {
        let v = (at - prev).normalize();
        let q = at - v * TIE.min(prev.distance(at));
        stitches.push(Stitch::new(q.x, q.y, Kind::Stitch));
        stitches.push(Stitch::new(at.x, at.y, Kind::Stitch));
    }
}

/// Sews shapes one after another into colour blocks: jumps, trims and lock stitches.
struct Sewer<'a> {
    p: &'a Params,
    stitches: Vec<Stitch>,
    at: Point,
    first_in_plan: bool,
    /// The thread was cut after the last shape (its `trim_after`).
    cut: bool,
    /// The last shape wants a tie-off where the thread is cut after it.
    tie_end: bool,
}

impl Sewer<'_> {
    fn shape(&mut self, shape: &Shape) {
        let p = self.p;
        for r in shape.runs() {
            let Some(&start) = r.points.first() else {
                continue;
            };
            let at = self.at;
            // A move shorter than the shape's minimum jump is sewn (Ink/Stitch's collapse).
            let d = start.distance(at);
            let short = d > 1e-9 && d <= shape.min_jump;
            if (r.sew_into || short) && !self.first_in_plan && !self.cut {
                for q in running::straight(at, start, p.stitch_length) {
                    self.stitches.push(Stitch::new(q.x, q.y, Kind::Stitch));
                }
            } else if self.first_in_plan || self.cut || start.distance(at) > 1e-9 {
                let cut = if self.stitches.is_empty() || self.cut {
                    true // a new thread: a colour change or a trim cut the last one
                } else if start.distance(at) > p.trim_length {
                    if p.ties && self.tie_end {
                        tie(&mut self.stitches, at);
                    }
                    self.stitches.push(Stitch::new(at.x, at.y, Kind::Trim));
                    true
                } else {
                    false
                };
                self.stitches
                    .push(Stitch::new(start.x, start.y, Kind::Jump));
                // The needle goes down where the jump ends: the run's anchor.
                self.stitches
                    .push(Stitch::new(start.x, start.y, Kind::Stitch));
                if cut && p.ties && shape.ties.start {
                    if let Some(&next) = r.points.get(1) {
                        let u = (next - start).normalize();
                        if u.is_finite() {
                            let q = start + u * TIE;
                            self.stitches.push(Stitch::new(q.x, q.y, Kind::Stitch));
                            self.stitches
                                .push(Stitch::new(start.x, start.y, Kind::Stitch));
                        }
                    }
                }
            }
            self.first_in_plan = false;
            self.cut = false;
            for q in &r.points[1..] {
                self.stitches.push(Stitch::new(q.x, q.y, Kind::Stitch));
            }
            self.at = *r.points.last().unwrap();
        }
        self.tie_end = shape.ties.end;
        if shape.force_lock && p.ties && self.tie_end {
            // Tied off here already: a trim after it, or later, needs no second knot.
            tie(&mut self.stitches, self.at);
            self.tie_end = false;
        }
        if shape.trim_after {
            if p.ties && self.tie_end {
                tie(&mut self.stitches, self.at);
            }
            let at = self.at;
            self.stitches.push(Stitch::new(at.x, at.y, Kind::Trim));
            self.cut = true;
        }
        if shape.stop_after {
            let at = self.at;
            self.stitches.push(Stitch::new(at.x, at.y, Kind::Stop));
        }
    }

    /// The block's stitches, tied off (the colour change cuts the thread).
    fn end_block(&mut self) -> Vec<Stitch> {
        if self.p.ties && self.tie_end && !self.cut {
            tie(&mut self.stitches, self.at);
        }
        self.cut = false;
        std::mem::take(&mut self.stitches)
    }
}

/// Orders the shapes and joins them with jumps and trims into colour blocks: grouped by
/// colour and kind, nearest first (a drawing), or in the order given (`ordered`: an
/// Ink/Stitch design, whose author set the order).
fn assemble(shapes: Vec<Shape>, name: &str, p: &Params, ordered: bool) -> StitchPlan {
    let mut sewer = Sewer {
        p,
        stitches: Vec::new(),
        // The design starts where its first shape does (the seed sews in digitising order;
        // the first object drawn is where the operator expects the needle to begin).
        at: shapes.first().and_then(Shape::start).unwrap_or(Point::ZERO),
        first_in_plan: true,
        cut: false,
        tie_end: true,
    };
    let mut blocks = Vec::new();
    if ordered {
        let mut color: Option<Color> = None;
        for s in &shapes {
            if color.is_some_and(|c| c != s.color) {
                blocks.push(ColorBlock {
                    thread: thread(color.unwrap()),
                    stitches: sewer.end_block(),
                });
            }
            color = Some(s.color);
            sewer.shape(s);
        }
        if let Some(c) = color {
            blocks.push(ColorBlock {
                thread: thread(c),
                stitches: sewer.end_block(),
            });
        }
        return StitchPlan {
            name: name.to_string(),
            blocks,
        };
    }
    let mut colors: Vec<Color> = Vec::new();
    for s in &shapes {
        if !colors.contains(&s.color) {
            colors.push(s.color);
        }
    }
    let mut pool: Vec<Option<Shape>> = shapes.into_iter().map(Some).collect();
    for color in colors {
        for kind in [ShapeKind::Fill, ShapeKind::Satin, ShapeKind::Running] {
            loop {
                // Nearest start, forwards or backwards.
                let at = sewer.at;
                let mut best: Option<(f64, usize, bool)> = None;
                for (i, s) in pool.iter().enumerate() {
                    let Some(s) = s.as_ref().filter(|s| s.color == color && s.kind == kind) else {
                        continue;
                    };
                    let fwd = s.start().map_or(f64::INFINITY, |q| q.distance(at));
                    let bwd = s.reversed_start().map_or(f64::INFINITY, |q| q.distance(at));
                    for (d, rev) in [(fwd, false), (bwd, true)] {
                        if best.is_none_or(|b| d < b.0) {
                            best = Some((d, i, rev));
                        }
                    }
                }
                let Some((_, i, rev)) = best else { break };
                let shape = pool[i].take().unwrap();
                let shape = if rev { shape.reversed() } else { shape };
                sewer.shape(&shape);
            }
        }
        blocks.push(ColorBlock {
            thread: thread(color),
            stitches: sewer.end_block(),
        });
    }
    StitchPlan {
        name: name.to_string(),
        blocks,
    }
}
