//! HP-GL and HP-GL/2 (the languages of HP's, Roland's and most pen and cutting plotters, and of
//! PCL printers' vector mode) → `Drawing`.
//!
//! Read: IN, DF, SP, PU, PD, PA, PR (with or without commas, trailing commas, one or many pairs,
//! lower case, no newlines), PE (polyline encoded, base 64 or 32, fractional bits), CI, AA, AR,
//! AT, RT (arcs through three points), BZ, BR (cubic Béziers), EA, ER, EW (outlined rectangles
//! and wedges; RA/RR rectangles for EP), PM/EP (polygons outlined), RO (rotation), LT (dashed and dotted line types,
//! drawn with the pen lifted in the gaps), CO (comments, quoted or not), IP and SC (scaling:
//! anisotropic, isotropic with its left/bottom placement, point factor; IR), LB, DT, SI, DI; PCL
//! around HP-GL/2 (`ESC E`, UEL and PJL lines, `ESC % n B` … `ESC % n A`, raster data skipped)
//! and device-control escapes (`ESC . ( …`). Coordinates are plotter units, 40 per mm (HP's
//! 0.025 mm); with SC they are user units mapped onto P1…P2 (IP; by default P1 = (0, 0),
//! P2 = (33600, 47520), hp2xx's A0 hard-clip limits). Each pen is a layer `pen N`; pen-down
//! runs become paths of lines, arcs and Béziers (arcs stay circular where the scaling is
//! isotropic; anisotropic scaling draws ellipses, as chords; an explicit chord angle draws the
//! polygon the plotter draws). Labels are returned as [`Label`]s (the caller draws them with a
//! single-stroke font). Everything else (speeds, fills, pages, vendor `!` commands, PCL text,
//! stray text between instructions) is counted as unsupported, never dropped in silence.
//! Errors name the line, column and instruction.

mod linetype;
mod pe;
mod scan;
mod sniff;

pub use sniff::{looks_like_hpgl, HPGL_EXTENSIONS};

use crate::import::{ImportError, Imported};
use oficina_geom::kurbo::CubicBez;
use oficina_geom::{chord_count, Arc, Path, Point, Segment, SourceRef, Vec2};
use scan::Scanner;

/// Plotter units per millimetre.
pub(crate) const UNITS_PER_MM: f64 = 40.0;
/// Default scaling points P1, P2 (plotter units): hp2xx's, the A0 hard-clip limits.
const P1_DEFAULT: Point = Point::new(0.0, 0.0);
const P2_DEFAULT: Point = Point::new(33600.0, 47520.0);

/// A label (`LB`): text at a place, in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub at: Point,
    pub text: String,
    /// Cap height and character width, mm (`SI`, default 3.75 × 2.85 as on A4 plotters).
    pub height: f64,
    pub width: f64,
    /// Direction of the text baseline, radians (`DI`).
    pub angle: f64,
    pub layer: String,
}

/// An imported HPGL file: the drawing and its labels.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hpgl {
    /// The drawing, pens as layers.
    pub imported: Imported,
    /// The `LB` labels, placed.
    pub labels: Vec<Label>,
}

impl Hpgl {
    /// The drawing alone, for callers without a font: each label is counted as unsupported.
    pub fn into_imported(self) -> Imported {
        let mut imported = self.imported;
        for l in &self.labels {
            imported.unsupported.add(
                "LB label (drawn by `oficina plot`)",
                format!("{:?}", l.text),
            );
        }
        imported
    }
}

/// User units → plotter units: pu = a·u + b per axis (SC).
#[derive(Clone, Copy, Debug)]
struct Scale {
    ax: f64,
    bx: f64,
    ay: f64,
    by: f64,
}

impl Scale {
    fn map(&self, u: Point) -> Point {
        Point::new(self.ax * u.x + self.bx, self.ay * u.y + self.by)
    }
    fn unmap(&self, p: Point) -> Point {
        Point::new((p.x - self.bx) / self.ax, (p.y - self.by) / self.ay)
    }
}

struct State {
    /// Current point, plotter units.
    at: Point,
    down: bool,
    relative: bool,
    pen: u32,
    terminator: u8,
    size: (f64, f64),
    angle: f64,
    /// The pen-down run being drawn (mm) and where it began.
    run: Vec<Segment>,
    run_place: (usize, String),
    p1: Point,
    p2: Point,
    /// The SC parameters in force, and the scale they make with P1, P2.
    sc: Option<Vec<f64>>,
    scale: Option<Scale>,
    /// Polygon mode (PM0 … PM2): outlines are kept for EP instead of drawn.
    polygon: Option<Vec<Path>>,
    last_polygon: Vec<Path>,
    /// RO: the plot's rotation on the paper, degrees counter-clockwise (0, 90, 180, 270).
    rotation: f64,
    /// LT: the line type in force (None: solid) and the pattern length set last, mm.
    line_type: Option<linetype::LineType>,
    pattern: f64,
}

impl State {
    fn new() -> State {
        State {
            at: Point::ORIGIN,
            down: false,
            relative: false,
            pen: 1,
            terminator: 3,
            size: (2.85, 3.75),
            angle: 0.0,
            run: Vec::new(),
            run_place: (1, String::new()),
            p1: P1_DEFAULT,
            p2: P2_DEFAULT,
            sc: None,
            scale: None,
            polygon: None,
            last_polygon: Vec::new(),
            rotation: 0.0,
            line_type: None,
            pattern: default_pattern(P1_DEFAULT, P2_DEFAULT),
        }
    }

    fn to_pu(&self, u: Point) -> Point {
        self.scale.map_or(u, |s| s.map(u))
    }

    fn to_user(&self, p: Point) -> Point {
        self.scale.map_or(p, |s| s.unmap(p))
    }

    /// A relative move `d` (user units) from the current point, in plotter units.
    fn offset(&self, d: Vec2) -> Point {
        match self.scale {
            Some(s) => Point::new(self.at.x + s.ax * d.x, self.at.y + s.ay * d.y),
            None => self.at + d,
        }
    }
}

/// Parses HPGL text; `file` names it in errors.
pub fn hpgl_from_bytes(bytes: &[u8], file: &str) -> Result<Hpgl, ImportError> {
    if bytes.iter().all(|b| b.is_ascii_whitespace() || *b == 0) {
        return Err(ImportError::new(
            file,
            "file",
            if bytes.is_empty() {
                "the file is empty (0 bytes): nothing to plot".to_string()
            } else {
                "the file holds only blanks: nothing to plot".to_string()
            },
        ));
    }
    let mut out = Hpgl::default();
    let mut st = State::new();
    let mut sc = Scanner::new(bytes, file);
    while let Some(mn) = sc.instruction()? {
        let name = std::str::from_utf8(&mn).unwrap_or("??").to_string();
        let line = sc.line;
        match &mn {
            b"LB" | b"BL" => {
                let text = sc.text_until(st.terminator);
                if mn == *b"LB" {
                    let (w, h) = st.size;
                    let start = st.at;
                    let turn = oficina_geom::kurbo::Affine::rotate(st.rotation.to_radians());
                    out.labels.push(Label {
                        at: turn * mm(st.at),
                        text: text.clone(),
                        height: h,
                        width: w,
                        angle: st.angle + st.rotation.to_radians(),
                        layer: layer(st.pen),
                    });
                    // The pen ends after the label: each character cell is 1.5 character
                    // widths; a carriage return goes back to the label's start, a line feed
                    // down two character heights (HP-GL's label spacing).
                    let along = Vec2::from_angle(st.angle) * UNITS_PER_MM;
                    let down = Vec2::new(along.y, -along.x);
                    let mut line_start = start;
                    let mut at = start;
                    for ch in text.chars() {
                        match ch {
                            '\r' => at = line_start,
                            '\n' => {
                                line_start += down * (2.0 * h);
                                at += down * (2.0 * h);
                            }
                            c if c.is_control() => {}
                            _ => at += along * (1.5 * w),
                        }
                    }
                    if check(at).is_ok() {
                        st.at = at;
                    }
                }
                continue;
            }
            b"DT" => {
                match sc.raw() {
                    None | Some(b';') => st.terminator = 3,
                    Some(t) => st.terminator = t,
                }
                sc.numbers(&name)?;
                continue;
            }
            b"SM" => {
                // Symbol mode: one character (or none) follows.
                if sc
                    .look()
                    .is_some_and(|c| c != b';' && !c.is_ascii_alphabetic())
                {
                    sc.raw();
                }
                out.imported.unsupported.add("SM", sc.place());
                continue;
            }
            b"PE" => {
                pe(&mut sc, &mut st, &mut out.imported, file, line)?;
                continue;
            }
            b"CO" => {
                // A comment: HP-GL/2 quotes it; older writers run it up to the ';'.
                while sc.look().is_some_and(|c| c == b' ') {
                    sc.raw();
                }
                if sc.look() == Some(b'"') {
                    sc.raw();
                    sc.text_until(b'"');
                } else {
                    sc.text_until(b';');
                }
                continue;
            }
            _ => {}
        }
        let params = sc.numbers(&name)?;
        let here = |msg: String| sc.err(&name, msg);
        match &mn {
            b"IN" | b"DF" => {
                flush(&mut st, &mut out.imported, file);
                st.down = false;
                st.relative = false;
                st.terminator = 3;
                st.size = (2.85, 3.75);
                st.angle = 0.0;
                st.polygon = None;
                st.line_type = None;
                st.pattern = default_pattern(st.p1, st.p2);
                if mn == *b"IN" {
                    st.rotation = 0.0;
                    st.at = Point::ORIGIN;
                    st.p1 = P1_DEFAULT;
                    st.p2 = P2_DEFAULT;
                }
                st.sc = None;
                st.scale = None;
            }
            b"SP" => {
                flush(&mut st, &mut out.imported, file);
                st.pen = match params.first() {
                    None => 0,
                    Some(&p) if (0.0..=255.0).contains(&p) => p as u32,
                    Some(p) => return Err(here(format!("pen {p} is not 0…255"))),
                };
            }
            b"IP" => {
                let (p1, p2) = match params.as_slice() {
                    [] => (P1_DEFAULT, P2_DEFAULT),
                    [x, y] => {
                        let p1 = Point::new(*x, *y);
                        (p1, p1 + (st.p2 - st.p1))
                    }
                    [a, b, c, d, ..] => (Point::new(*a, *b), Point::new(*c, *d)),
                    _ => {
                        return Err(here(format!(
                            "{} parameters: use IP, IP x1,y1 or IP x1,y1,x2,y2",
                            params.len()
                        )))
                    }
                };
                st.p1 = p1;
                st.p2 = p2;
                if let Some(p) = st.sc.clone() {
                    st.scale = Some(scale(&p, p1, p2).map_err(here)?);
                }
            }
            b"IR" => {
                // P1 (and P2) as percentages of the hard-clip limits (the default P1…P2).
                let at = |px: f64, py: f64| {
                    Point::new(
                        P1_DEFAULT.x + px / 100.0 * (P2_DEFAULT.x - P1_DEFAULT.x),
                        P1_DEFAULT.y + py / 100.0 * (P2_DEFAULT.y - P1_DEFAULT.y),
                    )
                };
                let (p1, p2) = match params.as_slice() {
                    [] => (P1_DEFAULT, P2_DEFAULT),
                    [x, y] => {
                        let p1 = at(*x, *y);
                        (p1, p1 + (st.p2 - st.p1))
                    }
                    [a, b, c, d, ..] => (at(*a, *b), at(*c, *d)),
                    _ => {
                        return Err(here(format!(
                            "{} parameters: use IR, IR x1%,y1% or IR x1%,y1%,x2%,y2%",
                            params.len()
                        )))
                    }
                };
                st.p1 = p1;
                st.p2 = p2;
                if let Some(p) = st.sc.clone() {
                    st.scale = Some(scale(&p, p1, p2).map_err(here)?);
                }
            }
            b"SC" => {
                if params.is_empty() {
                    st.sc = None;
                    st.scale = None;
                } else {
                    st.scale = Some(scale(&params, st.p1, st.p2).map_err(here)?);
                    st.sc = Some(params);
                }
            }
            b"PU" | b"PD" | b"PA" | b"PR" => {
                match &mn {
                    b"PU" => {
                        flush(&mut st, &mut out.imported, file);
                        st.down = false;
                    }
                    b"PD" => st.down = true,
                    b"PA" => st.relative = false,
                    _ => st.relative = true,
                }
                if params.len() % 2 == 1 {
                    return Err(here(format!(
                        "{} parameters: coordinates come in X,Y pairs",
                        params.len()
                    )));
                }
                for xy in params.chunks(2) {
                    let p = if st.relative {
                        st.offset(Vec2::new(xy[0], xy[1]))
                    } else {
                        st.to_pu(Point::new(xy[0], xy[1]))
                    };
                    check(p).map_err(&here)?;
                    move_to(&mut st, p, line, &sc.place(), &mut out.imported, file);
                }
            }
            b"CI" => {
                let r = *params
                    .first()
                    .ok_or_else(|| here("needs a radius (CI r[,chord angle])".into()))?;
                if r != 0.0 {
                    flush(&mut st, &mut out.imported, file);
                    let c = st.to_user(st.at);
                    let segs = arc(
                        &st,
                        c,
                        r.abs(),
                        0.0,
                        std::f64::consts::TAU,
                        params.get(1).copied(),
                    );
                    let path = Path::new(segs, true).with_source(source(file, line, "CI"));
                    emit(&mut st, &mut out.imported, path);
                }
            }
            b"AA" | b"AR" => {
                if params.len() < 3 {
                    return Err(here(format!(
                        "needs X,Y,sweep (centre and sweep angle in degrees), got {} parameters",
                        params.len()
                    )));
                }
                let cur = st.to_user(st.at);
                let c = if mn == *b"AR" {
                    cur + Vec2::new(params[0], params[1])
                } else {
                    Point::new(params[0], params[1])
                };
                check(st.to_pu(c)).map_err(&here)?;
                // A sweep beyond a turn retraces the circle: one turn draws the same.
                let sweep = params[2].clamp(-360.0, 360.0).to_radians();
                let r = c.distance(cur);
                let start = (cur - c).atan2();
                let end = c + Vec2::from_angle(start + sweep) * r;
                if st.down && r > 0.0 {
                    if st.run.is_empty() {
                        st.run_place = (line, sc.place());
                    }
                    let segs = arc(&st, c, r, start, sweep, params.get(3).copied());
                    st.run.extend(segs);
                }
                st.at = st.to_pu(end);
            }
            b"AT" | b"RT" => {
                // Arc through three points: the current one, an intermediate, the end.
                if params.len() < 4 {
                    return Err(here(format!(
                        "needs Xi,Yi,Xe,Ye (a point on the arc and its end), got {} parameters",
                        params.len()
                    )));
                }
                let cur = st.to_user(st.at);
                let off = if mn == *b"RT" {
                    cur.to_vec2()
                } else {
                    Vec2::ZERO
                };
                let mid = Point::new(params[0], params[1]) + off;
                let end = Point::new(params[2], params[3]) + off;
                check(st.to_pu(mid)).map_err(&here)?;
                check(st.to_pu(end)).map_err(&here)?;
                if st.down {
                    if st.run.is_empty() {
                        st.run_place = (line, sc.place());
                    }
                    match Arc::through(cur, mid, end) {
                        Some(a) => {
                            let segs = arc(
                                &st,
                                a.center,
                                a.radius,
                                a.start_angle,
                                a.sweep,
                                params.get(4).copied(),
                            );
                            st.run.extend(segs);
                        }
                        // Collinear (or coincident) points: the plotter draws straight lines.
                        None => {
                            for p in [mid, end] {
                                let (a, b) = (mm(st.at), mm(st.to_pu(p)));
                                if a != b {
                                    st.run.push(Segment::line(a, b));
                                }
                                st.at = st.to_pu(p);
                            }
                        }
                    }
                }
                st.at = st.to_pu(end);
            }
            b"BZ" | b"BR" => {
                if params.len() % 6 != 0 {
                    return Err(here(format!(
                        "{} parameters: a Bézier takes three X,Y pairs (two controls and the end)",
                        params.len()
                    )));
                }
                for b in params.chunks(6) {
                    let pts: Vec<Point> = (0..3)
                        .map(|k| {
                            let (x, y) = (b[2 * k], b[2 * k + 1]);
                            if mn == *b"BR" {
                                st.offset(Vec2::new(x, y))
                            } else {
                                st.to_pu(Point::new(x, y))
                            }
                        })
                        .collect();
                    for p in &pts {
                        check(*p).map_err(&here)?;
                    }
                    if st.down {
                        if st.run.is_empty() {
                            st.run_place = (line, sc.place());
                        }
                        st.run.push(Segment::Cubic(CubicBez::new(
                            mm(st.at),
                            mm(pts[0]),
                            mm(pts[1]),
                            mm(pts[2]),
                        )));
                    }
                    st.at = pts[2];
                }
            }
            b"EA" | b"ER" | b"RA" | b"RR" => {
                let [x, y] = params[..] else {
                    return Err(here(format!(
                        "needs X,Y (the opposite corner), got {} parameters",
                        params.len()
                    )));
                };
                let q = if mn == *b"ER" || mn == *b"RR" {
                    st.offset(Vec2::new(x, y))
                } else {
                    st.to_pu(Point::new(x, y))
                };
                check(q).map_err(&here)?;
                flush(&mut st, &mut out.imported, file);
                let p = st.at;
                let corners = [p, Point::new(q.x, p.y), q, Point::new(p.x, q.y)].map(mm);
                let path = Path::polyline(&corners, true).with_source(source(file, line, &name));
                if mn == *b"RA" || mn == *b"RR" {
                    // A filled rectangle: the fill is not drawn (noted); its outline goes to
                    // the polygon buffer, where a following EP edges it (HP-GL/2).
                    out.imported.unsupported.add(
                        &format!("{name} fill (its outline is drawn by EP)"),
                        sc.place(),
                    );
                    st.last_polygon = vec![path];
                } else {
                    emit(&mut st, &mut out.imported, path);
                }
            }
            b"EW" => {
                if params.len() < 3 {
                    return Err(here(format!(
                        "needs radius, start angle, sweep; got {} parameters",
                        params.len()
                    )));
                }
                flush(&mut st, &mut out.imported, file);
                let c = st.to_user(st.at);
                let (r, a0) = if params[0] < 0.0 {
                    (-params[0], params[1].to_radians() + std::f64::consts::PI)
                } else {
                    (params[0], params[1].to_radians())
                };
                let sweep = params[2].clamp(-360.0, 360.0).to_radians();
                let mut segs = arc(&st, c, r, a0, sweep, params.get(3).copied());
                if let (Some(s), Some(e)) = (
                    segs.first().map(Segment::start),
                    segs.last().map(Segment::end),
                ) {
                    let cm = mm(st.at);
                    segs.insert(0, Segment::line(cm, s));
                    segs.push(Segment::line(e, cm));
                    let path = Path::new(segs, true).with_source(source(file, line, "EW"));
                    emit(&mut st, &mut out.imported, path);
                }
            }
            b"PM" => {
                flush(&mut st, &mut out.imported, file);
                let mode = params.first().copied().unwrap_or(0.0) as i64;
                // PM1 and PM2 close the subpolygon with a move in the current pen state: a
                // line back to its start when the pen is down, nothing when it is up (as
                // hp2xx draws it).
                if mode != 0 && st.down {
                    if let Some(last) = st.polygon.as_mut().and_then(|p| p.last_mut()) {
                        last.closed = true;
                    }
                }
                match mode {
                    0 => st.polygon = Some(Vec::new()),
                    1 => {}
                    _ => st.last_polygon = st.polygon.take().unwrap_or_default(),
                }
            }
            b"EP" => {
                for p in st.last_polygon.clone() {
                    emit(&mut st, &mut out.imported, p);
                }
            }
            b"LT" => {
                flush(&mut st, &mut out.imported, file);
                let Some(&kind) = params.first() else {
                    st.line_type = None;
                    continue;
                };
                if let Some(&l) = params.get(1) {
                    if !(l.is_finite() && l > 0.0) {
                        return Err(here(format!("pattern length {l}: must be > 0")));
                    }
                    st.pattern = if params.get(2) == Some(&1.0) {
                        l
                    } else {
                        st.p1.distance(st.p2) * l / 100.0 / UNITS_PER_MM
                    };
                }
                let k = kind as i32;
                st.line_type = match k {
                    -8..=8 => Some(linetype::LineType {
                        kind: k,
                        length: st.pattern,
                    }),
                    _ => {
                        out.imported
                            .unsupported
                            .add(&format!("LT {kind} (drawn solid)"), sc.place());
                        None
                    }
                };
            }
            b"RO" => {
                // The coordinate system turns on the paper: what is drawn from here on is
                // turned with it (about the origin; a layout places the drawing afterwards).
                let r = params.first().copied().unwrap_or(0.0);
                if ![0.0, 90.0, 180.0, 270.0].contains(&r) {
                    return Err(here(format!("RO {r}: use 0, 90, 180 or 270")));
                }
                flush(&mut st, &mut out.imported, file);
                st.rotation = r;
            }
            b"SI" => {
                if params.len() >= 2 {
                    // SI is in centimetres.
                    st.size = (params[0] * 10.0, params[1] * 10.0);
                } else {
                    st.size = (2.85, 3.75);
                }
            }
            b"DI" => {
                st.angle = match params.as_slice() {
                    [run, rise, ..] if *run != 0.0 || *rise != 0.0 => rise.atan2(*run),
                    _ => 0.0,
                };
            }
            _ => {
                let what = if sniff::is_known(&mn) {
                    name.clone()
                } else {
                    format!("{name} (not an HP-GL instruction)")
                };
                out.imported.unsupported.add(&what, sc.place());
            }
        }
    }
    flush(&mut st, &mut out.imported, file);
    if sc.skipped_pcl && !sc.started {
        return Err(ImportError::new(
            file,
            "file",
            "PCL without HP-GL/2 in it (a raster or text print job, not a plot): nothing to draw",
        ));
    }
    if sc.skipped_pcl {
        out.imported
            .unsupported
            .add("PCL text or raster data (not HP-GL/2)", "file");
    }
    for (v, place) in sc.vendor.drain(..) {
        out.imported.unsupported.add(&v, place);
    }
    Ok(out)
}

/// `PE`: encoded moves, each pen-down unless flagged `<`, relative unless flagged `=`.
fn pe(
    sc: &mut Scanner,
    st: &mut State,
    out: &mut Imported,
    file: &str,
    line: usize,
) -> Result<(), ImportError> {
    let place = sc.place();
    for op in pe::read(sc)? {
        match op {
            pe::PeOp::Pen(p) => {
                flush(st, out, file);
                if !(0.0..=255.0).contains(&p) {
                    return Err(sc.err("PE", format!("pen {p} is not 0…255")));
                }
                st.pen = p as u32;
            }
            pe::PeOp::Move { up, absolute, x, y } => {
                let p = if absolute {
                    st.to_pu(Point::new(x, y))
                } else {
                    st.offset(Vec2::new(x, y))
                };
                check(p).map_err(|m| sc.err("PE", m))?;
                if up {
                    flush(st, out, file);
                }
                st.down = !up;
                move_to(st, p, line, &place, out, file);
            }
        }
    }
    Ok(())
}

/// The scale SC `p` makes on P1, P2: types 0 (anisotropic), 1 (isotropic, placed by left and
/// bottom percentages, 50 by default) and 2 (point factor).
fn scale(p: &[f64], p1: Point, p2: Point) -> Result<Scale, String> {
    let kind = p.get(4).copied().unwrap_or(0.0);
    if p.len() < 4 {
        return Err(format!(
            "{} parameters: use SC xmin,xmax,ymin,ymax[,type]",
            p.len()
        ));
    }
    let s = if kind == 2.0 {
        let (ax, ay) = (p[1], p[3]);
        if ax == 0.0 || ay == 0.0 {
            return Err("a point factor of 0".into());
        }
        Scale {
            ax,
            bx: p1.x - p[0] * ax,
            ay,
            by: p1.y - p[2] * ay,
        }
    } else {
        let (wx, wy) = (p[1] - p[0], p[3] - p[2]);
        if wx == 0.0 || wy == 0.0 {
            return Err(format!(
                "an empty range (x {}…{}, y {}…{}): min and max must differ",
                p[0], p[1], p[2], p[3]
            ));
        }
        let (mut ax, mut ay) = ((p2.x - p1.x) / wx, (p2.y - p1.y) / wy);
        let (mut bx, mut by) = (p1.x - p[0] * ax, p1.y - p[2] * ay);
        if kind == 1.0 {
            let s = ax.abs().min(ay.abs());
            ax = s * ax.signum();
            ay = s * ay.signum();
            let left = p.get(5).copied().unwrap_or(50.0) / 100.0;
            let bottom = p.get(6).copied().unwrap_or(50.0) / 100.0;
            bx = p1.x + left * ((p2.x - p1.x) - ax * wx) - p[0] * ax;
            by = p1.y + bottom * ((p2.y - p1.y) - ay * wy) - p[2] * ay;
        }
        Scale { ax, bx, ay, by }
    };
    if ![s.ax, s.ay, s.bx, s.by].iter().all(|v| v.is_finite()) || s.ax == 0.0 || s.ay == 0.0 {
        return Err("the scaling is degenerate (P1 and P2 coincide?)".into());
    }
    Ok(s)
}

/// An arc about user-space `c` of radius `r` (user units) from angle `a0` sweeping `sweep`,
/// in mm. With a chord angle (degrees, as the file gives it) it is the polygon the plotter
/// draws: chords of that angle from the start, the last one shorter. Without, it is circular
/// where the scaling keeps circles, else fine chords of the ellipse the scaling makes.
fn arc(st: &State, c: Point, r: f64, a0: f64, sweep: f64, chord: Option<f64>) -> Vec<Segment> {
    let s = st.scale.unwrap_or(Scale {
        ax: 1.0,
        bx: 0.0,
        ay: 1.0,
        by: 0.0,
    });
    let cm = mm(st.to_pu(c));
    let on = |a: f64| mm(st.to_pu(c + Vec2::from_angle(a) * r));
    if let Some(deg) = chord.filter(|d| d.is_finite() && *d != 0.0) {
        // HP clamps the chord angle to 0.5…180°.
        let step = deg.abs().clamp(0.5, 180.0).to_radians() * sweep.signum();
        let n = (sweep / step).ceil().max(1.0) as usize;
        let mut pts: Vec<Point> = (0..n).map(|k| on(a0 + step * k as f64)).collect();
        pts.push(on(a0 + sweep));
        return pts.windows(2).map(|w| Segment::line(w[0], w[1])).collect();
    }
    if (s.ax.abs() - s.ay.abs()).abs() <= 1e-12 * s.ax.abs() {
        let rm = r * s.ax.abs() / UNITS_PER_MM;
        // A mirrored axis mirrors the angles and the turning sense.
        let (a, sw) = match (s.ax > 0.0, s.ay > 0.0) {
            (true, true) => (a0, sweep),
            (false, false) => (a0 + std::f64::consts::PI, sweep),
            (false, true) => (std::f64::consts::PI - a0, -sweep),
            (true, false) => (-a0, -sweep),
        };
        return vec![Segment::Arc(Arc::new(cm, rm, a, sw))];
    }
    let big = r * s.ax.abs().max(s.ay.abs()) / UNITS_PER_MM;
    let n = chord_count(big, sweep, 0.005).min(4096);
    let pt = |k: usize| on(a0 + sweep * k as f64 / n as f64);
    (0..n).map(|k| Segment::line(pt(k), pt(k + 1))).collect()
}

/// The default pattern length: 4 % of the diagonal P1–P2, mm.
fn default_pattern(p1: Point, p2: Point) -> f64 {
    0.04 * p1.distance(p2) / UNITS_PER_MM
}

fn check(p: Point) -> Result<(), String> {
    if p.x.is_finite()
        && p.y.is_finite()
        && p.x.abs() <= scan::MAX_COORD
        && p.y.abs() <= scan::MAX_COORD
    {
        Ok(())
    } else {
        Err(format!(
            "the point ({:.3e}, {:.3e}) plotter units is beyond ±{:e} (≈ 25 km)",
            p.x,
            p.y,
            scan::MAX_COORD
        ))
    }
}

fn mm(p: Point) -> Point {
    Point::new(p.x / UNITS_PER_MM, p.y / UNITS_PER_MM)
}

fn layer(pen: u32) -> String {
    format!("pen {pen}")
}

fn source(file: &str, line: usize, element: &str) -> SourceRef {
    SourceRef {
        file: file.to_string(),
        element: element.to_string(),
        line: Some(line),
    }
}

fn move_to(st: &mut State, p: Point, line: usize, place: &str, out: &mut Imported, file: &str) {
    if st.down {
        if st.run.is_empty() {
            st.run_place = (line, place.to_string());
        }
        if p != st.at {
            st.run.push(Segment::line(mm(st.at), mm(p)));
        }
    } else {
        flush(st, out, file);
    }
    st.at = p;
}

/// A finished path goes to the drawing, or to the polygon buffer in polygon mode. Pen 0 is
/// no pen: what it would draw is counted, not drawn.
fn emit(st: &mut State, out: &mut Imported, path: Path) {
    if st.polygon.is_none() {
        let too_fine = st
            .line_type
            .is_some_and(|lt| path.length() / lt.length.max(1e-9) > 1e6);
        if too_fine {
            out.unsupported.add(
                "line type finer than a millionth of its path (drawn solid)",
                format!("line {}", path.source.line.unwrap_or(0)),
            );
        } else if let Some(lt) = st.line_type {
            // Dashed: the pen-down pieces of the pattern, each drawn as its own path.
            let mut pts = path.flatten(0.005);
            if path.closed && !pts.is_empty() {
                pts.push(pts[0]);
            }
            let (pieces, dots) = if lt.kind == 0 {
                (Vec::new(), pts.len())
            } else {
                linetype::dash(&pts, lt)
            };
            if dots > 0 {
                out.unsupported.add(
                    &format!(
                        "dots of line type {} (a touch of the pen: not drawn)",
                        lt.kind
                    ),
                    format!("line {}", path.source.line.unwrap_or(0)),
                );
            }
            let saved = st.line_type.take();
            for piece in pieces {
                let p = Path::polyline(&piece, false).with_source(path.source.clone());
                emit(st, out, p);
            }
            st.line_type = saved;
            return;
        }
    }
    if let Some(poly) = &mut st.polygon {
        poly.push(path);
    } else if st.pen == 0 {
        let at = format!("line {}", path.source.line.unwrap_or(0));
        out.unsupported
            .add("drawing with no pen selected (SP0)", at);
    } else if st.rotation != 0.0 {
        let turn = oficina_geom::kurbo::Affine::rotate(st.rotation.to_radians());
        out.drawing.push(&layer(st.pen), path.transform(turn));
    } else {
        out.drawing.push(&layer(st.pen), path);
    }
}

/// Ends the pen-down run as a path (a lone PD with no move draws nothing).
fn flush(st: &mut State, out: &mut Imported, file: &str) {
    if !st.run.is_empty() {
        let segs = std::mem::take(&mut st.run);
        let (line, _) = st.run_place;
        let path = Path::new(segs, false).with_source(source(file, line, "PD"));
        emit(st, out, path);
    }
}

/// Loads an HP-GL file (any extension) with the same size cap as the other importers.
pub fn load_hpgl(path: &std::path::Path) -> Result<Hpgl, ImportError> {
    let bytes = crate::import::read_capped(path)?;
    hpgl_from_bytes(&bytes, &path.display().to_string())
}

/// Whether the file at `path` is HP-GL: by its extension, else by its first kilobytes.
pub fn is_hpgl_file(path: &std::path::Path) -> bool {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if HPGL_EXTENSIONS.contains(&ext.as_str()) {
        return true;
    }
    use std::io::Read;
    let mut head = Vec::with_capacity(4096);
    std::fs::File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .is_ok()
        && looks_like_hpgl(&head)
}
