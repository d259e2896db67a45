//! rs274's canonical text (`rs274 -g`) read back as the path a program commands, in machine
//! millimetres: each motion call becomes an element with the feed cap, the path mode and the
//! tolerance in force when rs274 issued it. Written from LinuxCNC's `saicanon.cc` output and
//! `emccanon.cc`'s `rotate_and_offset_pos` ([`Frame`]), not from Oficina's interpreter or planner.

use std::f64::consts::TAU;

/// The shape of one motion call.
#[derive(Clone, Debug)]
pub(crate) enum Shape {
    /// A straight move from `a` to `b` (machine frame, mm).
    Line { a: [f64; 3], b: [f64; 3] },
    /// A circle, helix or spiral in the program frame (un-rotated, un-offset), with
    /// `frame` taking it to the machine: in-plane axes `ax` (first, second), normal `ax.2`.
    Arc {
        ax: (usize, usize, usize),
        c: [f64; 2],
        r0: f64,
        r1: f64,
        th0: f64,
        sweep: f64,
        k0: f64,
        k1: f64,
        frame: Frame,
        /// Machine-frame end point.
        end: [f64; 3],
    },
    /// A spline (NURBS_FEED), whose points rs274 does not print, and the move after it,
    /// whose start is the spline's unprinted end: any point is accepted; `end` when known.
    Unknown { end: Option<[f64; 3]> },
}

/// Program → machine frame, as `emccanon.cc`'s `rotate_and_offset_pos`: add the G92 offset,
/// rotate about Z (radians), then add the G5x and tool offsets (mm).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Frame {
    pub(crate) g92: [f64; 3],
    pub(crate) rot: f64,
    pub(crate) off: [f64; 3],
}

impl Frame {
    pub(crate) fn to_machine(self, p: [f64; 3]) -> [f64; 3] {
        let (x, y) = (p[0] + self.g92[0], p[1] + self.g92[1]);
        let (s, c) = self.rot.sin_cos();
        [
            c * x - s * y + self.off[0],
            s * x + c * y + self.off[1],
            p[2] + self.g92[2] + self.off[2],
        ]
    }
    pub(crate) fn to_program(self, m: [f64; 3]) -> [f64; 3] {
        let (x, y) = (m[0] - self.off[0], m[1] - self.off[1]);
        let (s, c) = self.rot.sin_cos();
        [
            c * x + s * y - self.g92[0],
            -s * x + c * y - self.g92[1],
            m[2] - self.off[2] - self.g92[2],
        ]
    }
}

/// How rs274 asked the machine to pass the end of a move (SET_MOTION_CONTROL_MODE).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Mode {
    /// G61: stop at the end.
    ExactStop,
    /// G61.1: stay on the path (no rounding of corners).
    ExactPath,
    /// G64 P: corners may be rounded within the tolerance (mm; 0: no limit given).
    Continuous(f64),
}

/// One motion call of rs274's output.
#[derive(Clone, Debug)]
pub(crate) struct Element {
    pub(crate) shape: Shape,
    /// Highest path speed the program allows, mm/s (∞ for traverses).
    pub(crate) feed_cap: f64,
    pub(crate) mode: Mode,
    /// Index of the rs274 call, 1-based as printed.
    pub(crate) call: usize,
}

impl Element {
    /// Length (mm) of the XYZ path, for coverage; unknown shapes count as long.
    pub(crate) fn length(&self) -> f64 {
        match &self.shape {
            Shape::Line { a, b } => dist(*a, *b),
            Shape::Arc {
                r0,
                r1,
                sweep,
                k0,
                k1,
                ..
            } => (0.5 * (r0 + r1) * sweep.abs()).hypot(k1 - k0),
            Shape::Unknown { .. } => f64::INFINITY,
        }
    }

    /// Machine-frame end point (None for a spline).
    pub(crate) fn end(&self) -> Option<[f64; 3]> {
        match &self.shape {
            Shape::Line { b, .. } => Some(*b),
            Shape::Arc { end, .. } => Some(*end),
            Shape::Unknown { end } => *end,
        }
    }

    /// Distance (mm) from machine point `p` to the element.
    pub(crate) fn distance(&self, p: [f64; 3]) -> f64 {
        match &self.shape {
            Shape::Line { a, b } => dist_to_segment(p, *a, *b),
            Shape::Arc { .. } => self.arc_distance(p),
            Shape::Unknown { .. } => 0.0,
        }
    }

    /// The point of the arc at parameter t ∈ [0, 1] (program frame): angle, radius and
    /// axial height all move linearly with t (LinuxCNC's helix and spiral).
    fn arc_point(&self, t: f64) -> [f64; 3] {
        let Shape::Arc {
            ax,
            c,
            r0,
            r1,
            th0,
            sweep,
            k0,
            k1,
            ..
        } = &self.shape
        else {
            unreachable!()
        };
        let th = th0 + t * sweep;
        let r = r0 + t * (r1 - r0);
        let mut q = [0.0; 3];
        q[ax.0] = c[0] + r * th.cos();
        q[ax.1] = c[1] + r * th.sin();
        q[ax.2] = k0 + t * (k1 - k0);
        q
    }

    /// Nearest distance to the arc: a candidate parameter per turn at the point's own angle,
    /// each refined by a golden-section search (a steep helix's nearest point is not at the
    /// point's angle), and the two ends.
    fn arc_distance(&self, m: [f64; 3]) -> f64 {
        let Shape::Arc {
            ax,
            c,
            th0,
            sweep,
            frame,
            ..
        } = &self.shape
        else {
            unreachable!()
        };
        let p = frame.to_program(m);
        let d = |t: f64| dist(p, self.arc_point(t));
        let mut best = d(0.0).min(d(1.0));
        let phi = (p[ax.1] - c[1]).atan2(p[ax.0] - c[0]);
        // Angle from the start along the sweep's direction, in [0, 2π).
        let rel = ((phi - th0) * sweep.signum()).rem_euclid(TAU);
        let span = sweep.abs();
        let win = 0.5 / span.max(1e-9); // half a radian either side
        let mut a = rel;
        while a <= span + TAU * 1e-9 {
            let t = (a / span).clamp(0.0, 1.0);
            best = best.min(golden(&d, (t - win).max(0.0), (t + win).min(1.0)));
            a += TAU;
        }
        best
    }
}

/// Minimum of a unimodal `f` over [lo, hi] (40 golden-section steps).
fn golden(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..40 {
        if f1 < f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
    }
    f1.min(f2)
}

pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn dist_to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab: [f64; 3] = std::array::from_fn(|i| b[i] - a[i]);
    let l2: f64 = ab.iter().map(|v| v * v).sum();
    let t = if l2 > 0.0 {
        ((0..3).map(|i| (p[i] - a[i]) * ab[i]).sum::<f64>() / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, std::array::from_fn(|i| a[i] + t * ab[i]))
}

/// The numbers between the parentheses of `call(...)`.
fn args(line: &str) -> Vec<f64> {
    let (Some(o), Some(c)) = (line.find('('), line.rfind(')')) else {
        return Vec::new();
    };
    line[o + 1..c]
        .split([',', ' '])
        .filter_map(|w| w.trim().parse().ok())
        .collect()
}

/// rs274's interpreter state while reading its calls.
struct Reader {
    scale: f64,
    g5x: [f64; 3],
    g92: [f64; 3],
    tool: [f64; 3],
    rot: f64,
    /// Machine-frame position (NaN after a spline, whose end rs274 does not print).
    pos: [f64; 3],
    feed: f64,
    per_rev: bool,
    sync_pitch: Option<f64>,
    rpm: f64,
    mode: Mode,
    plane: (usize, usize, usize),
    out: Vec<Element>,
    calls: usize,
}

impl Reader {
    fn frame(&self) -> Frame {
        Frame {
            g92: self.g92,
            rot: self.rot.to_radians(),
            off: std::array::from_fn(|i| self.g5x[i] + self.tool[i]),
        }
    }

    /// Path speed cap in mm/s of a feed move: F units/min, F units/rev × rpm, or the
    /// synchronised pitch × rpm.
    fn feed_cap(&self) -> f64 {
        match self.sync_pitch {
            Some(p) => p * self.rpm / 60.0,
            None if self.per_rev => self.feed * self.rpm / 60.0,
            None => self.feed / 60.0,
        }
    }

    fn push(&mut self, shape: Shape, feed_cap: f64) {
        self.out.push(Element {
            shape,
            feed_cap,
            mode: self.mode,
            call: self.calls,
        });
    }

    /// A straight move to machine point `b`.
    fn line_to(&mut self, b: [f64; 3], cap: f64) {
        let a = self.pos;
        self.pos = b;
        let shape = if a[0].is_nan() {
            Shape::Unknown { end: Some(b) }
        } else if dist(a, b) < 1e-9 {
            return; // a move to where the tool is (or A B C alone): no path
        } else {
            Shape::Line { a, b }
        };
        self.push(shape, cap);
    }

    fn read(&mut self, line: &str) {
        // `   12 N..... NAME(args)` or `   12 N120   NAME(args)`: the sequence number and
        // the block's N word (dots when it has none) go first.
        let call = line
            .trim_start()
            .trim_start_matches(|c: char| c.is_ascii_digit());
        let call = call.trim_start();
        let call = match call.strip_prefix('N') {
            Some(rest) => rest.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.'),
            None => call,
        }
        .trim();
        if call.is_empty() {
            return;
        }
        let name = call.split('(').next().unwrap_or("");
        let v = args(call);
        let s = self.scale;
        let xyz = |v: &[f64]| [v[0] * s, v[1] * s, v[2] * s];
        self.calls += 1;
        match name {
            "USE_LENGTH_UNITS" => self.scale = if call.contains("INCHES") { 25.4 } else { 1.0 },
            "SET_G5X_OFFSET" if v.len() >= 4 => self.g5x = xyz(&v[1..4]),
            "SET_G92_OFFSET" if v.len() >= 3 => self.g92 = xyz(&v[..3]),
            "USE_TOOL_LENGTH_OFFSET" if v.len() >= 3 => self.tool = xyz(&v[..3]),
            "SET_XY_ROTATION" if !v.is_empty() => self.rot = v[0],
            "SET_FEED_RATE" if !v.is_empty() => self.feed = v[0] * s,
            "SET_FEED_MODE" if v.len() >= 2 => self.per_rev = v[1] == 1.0,
            "SET_SPINDLE_SPEED" if v.len() >= 2 => self.rpm = v[1],
            "START_SPEED_FEED_SYNC" if !v.is_empty() => self.sync_pitch = Some(v[0] * s),
            "STOP_SPEED_FEED_SYNCH" => self.sync_pitch = None,
            "SELECT_PLANE" => {
                self.plane = if call.contains("PLANE_YZ") {
                    (1, 2, 0)
                } else if call.contains("PLANE_XZ") {
                    (2, 0, 1) // first Z, second X: rs274's order
                } else {
                    (0, 1, 2)
                }
            }
            "SET_MOTION_CONTROL_MODE" => {
                self.mode = if call.contains("EXACT_STOP") {
                    Mode::ExactStop
                } else if call.contains("EXACT_PATH") {
                    Mode::ExactPath
                } else {
                    Mode::Continuous(v.first().copied().unwrap_or(0.0) * s)
                }
            }
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" | "STRAIGHT_PROBE" if v.len() >= 6 => {
                let cap = if name == "STRAIGHT_TRAVERSE" {
                    f64::INFINITY
                } else {
                    self.feed_cap()
                };
                let b = self.frame().to_machine(xyz(&v[..3]));
                self.line_to(b, cap);
            }
            "RIGID_TAP" if v.len() >= 3 => {
                // In to the point and back out along the same line.
                let (back, cap) = (self.pos, self.feed_cap());
                let b = self.frame().to_machine(xyz(&v[..3]));
                self.line_to(b, cap);
                self.line_to(back, cap);
            }
            "ARC_FEED" if v.len() >= 9 => self.arc(&v),
            "NURBS_FEED" => {
                let cap = self.feed_cap();
                self.push(Shape::Unknown { end: None }, cap);
                self.pos = [f64::NAN; 3]; // known again at the next call's start
            }
            _ => {}
        }
    }

    /// ARC_FEED(first_end, second_end, first_centre, second_centre, turns, axis_end, a, b,
    /// c, …): positive turns run counter-clockwise from the first axis towards the second.
    fn arc(&mut self, v: &[f64]) {
        let s = self.scale;
        let ax = self.plane;
        let frame = self.frame();
        let start = frame.to_program(self.pos);
        let mut end = start;
        end[ax.0] = v[0] * s;
        end[ax.1] = v[1] * s;
        end[ax.2] = v[5] * s;
        let c = [v[2] * s, v[3] * s];
        let turns = v[4] as i64;
        self.pos = frame.to_machine(end);
        let cap = self.feed_cap();
        if start[0].is_nan() {
            let end = Some(frame.to_machine(end));
            return self.push(Shape::Unknown { end }, cap);
        }
        let (th0, th1) = (
            (start[ax.1] - c[1]).atan2(start[ax.0] - c[0]),
            (end[ax.1] - c[1]).atan2(end[ax.0] - c[0]),
        );
        // Sweep in the direction of the turns: the short way round to the end angle, a whole
        // turn when it coincides with the start, plus |turns| − 1 more full turns.
        let dir = if turns >= 0 { 1.0 } else { -1.0 };
        let mut d = ((th1 - th0) * dir).rem_euclid(TAU);
        if d < 1e-9 {
            d = TAU;
        }
        let sweep = dir * (d + (turns.unsigned_abs().max(1) - 1) as f64 * TAU);
        let r0 = (start[ax.0] - c[0]).hypot(start[ax.1] - c[1]);
        let r1 = (end[ax.0] - c[0]).hypot(end[ax.1] - c[1]);
        let shape = Shape::Arc {
            ax,
            c,
            r0,
            r1,
            th0,
            sweep,
            k0: start[ax.2],
            k1: end[ax.2],
            frame,
            end: frame.to_machine(end),
        };
        self.push(shape, cap);
    }
}

/// The elements of rs274's output `text`, from the machine start point `start` (mm).
pub(crate) fn read(text: &str, start: [f64; 3]) -> Vec<Element> {
    let mut r = Reader {
        scale: 1.0,
        g5x: [0.0; 3],
        g92: [0.0; 3],
        tool: [0.0; 3],
        rot: 0.0,
        pos: start,
        feed: 0.0,
        per_rev: false,
        sync_pitch: None,
        rpm: 0.0,
        mode: Mode::Continuous(0.0),
        plane: (0, 1, 2),
        out: Vec::new(),
        calls: 0,
    };
    for line in text.lines() {
        r.read(line);
    }
    r.out
}
