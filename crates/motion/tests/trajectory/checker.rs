//! An independent check of planned motion against rs274's path (see `rs274_path`).
//!
//! It uses nothing of the planner but its output's positions: every move segment is sampled
//! about every millisecond of machine time, and velocities and accelerations are the finite
//! differences of those positions. It checks
//! - the path: each sample lies within the tolerance of the rs274 element(s) it belongs to
//!   (G64 P where the program set one, else `default_tol`), the elements taken in rs274's
//!   order (a segment that ends on an element's end moves on past it);
//! - speed: path speed ≤ the feed cap, every axis ≤ its max rate;
//! - acceleration: every axis ≤ its max acceleration (+0.1 % and 1 mm/s² numeric slack);
//! - junctions: speed continuous; a change of direction by φ at speed v changes axis i's
//!   velocity by v·|Δu_i|. A corner rounded within δ by a circle of radius R (tangent to both
//!   moves, its middle δ from the corner: R = δ·cos(φ/2)/(1 − cos(φ/2))) is run through in
//!   R·φ/v seconds, so the jump is allowed when its mean acceleration there,
//!   v²·|Δu_i|/(R·φ), is within axis i's limit. G61 stops at the end of its move; G61.1
//!   keeps δ = 0. The mode is the one in force when rs274 issued the move ending there, as
//!   LinuxCNC's planner applies a move's termination condition at its end.

use super::rs274_path::{dist, Element, Mode};
use oficina_motion::{Profile, Segment, SegmentKind};

/// Slack for rs274's four printed decimals (0.00005 in = 0.0013 mm per coordinate, and an
/// arc's radius from a rounded centre).
const ROUNDING: f64 = 0.004;

/// Elements ahead of the cursor a segment's end may be matched to.
const WINDOW: usize = 256;

/// Sampling period, s.
const PERIOD: f64 = 1e-3;

#[derive(Debug, Default)]
pub(crate) struct Verdict {
    pub(crate) samples: usize,
    pub(crate) worst_path: f64,
    pub(crate) worst_speed_ratio: f64,
    pub(crate) worst_accel_ratio: f64,
    pub(crate) violations: Vec<String>,
}

impl Verdict {
    fn bad(&mut self, s: String) {
        if self.violations.len() < 20 {
            self.violations.push(s);
        }
    }
}

struct Limits {
    /// XYZ then A B C: max rate (units/s, as the profile holds it) and acceleration (units/s²); ∞ where absent.
    rate: [f64; 6],
    accel: [f64; 6],
}

fn limits(p: &Profile) -> Limits {
    let j = p.all_joints();
    Limits {
        rate: std::array::from_fn(|i| j[i].map_or(f64::INFINITY, |j| j.max_rate)),
        accel: std::array::from_fn(|i| j[i].map_or(f64::INFINITY, |j| j.acceleration)),
    }
}

/// Position X Y Z A B C at time t of a segment.
fn at(s: &Segment, t: f64) -> [f64; 6] {
    let (p, _, _) = s.sample(t);
    let r = s.rotary_at(t);
    [p[0], p[1], p[2], r[0], r[1], r[2]]
}

fn norm3(v: &[f64]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn tol_of(e: &Element, default_tol: f64) -> f64 {
    match e.mode {
        Mode::Continuous(p) if p > 0.0 => p.max(default_tol),
        _ => default_tol,
    }
}

/// Velocity (6 axes) at the end (`end`) or start of a segment: the second-order one-sided
/// difference, exact while the acceleration is constant over the last/first 2h.
fn end_velocity(s: &Segment, end: bool) -> ([f64; 6], f64) {
    let t = s.duration();
    let h = (t / 2.0).min(2.5e-4);
    if h <= 0.0 {
        return ([0.0; 6], 0.0);
    }
    let (p0, p1, p2) = if end {
        (at(s, t), at(s, t - h), at(s, t - 2.0 * h))
    } else {
        (at(s, 0.0), at(s, h), at(s, 2.0 * h))
    };
    let sign = if end { 1.0 } else { -1.0 };
    (
        std::array::from_fn(|i| sign * (3.0 * p0[i] - 4.0 * p1[i] + p2[i]) / (2.0 * h)),
        h,
    )
}

/// Checks `segs` (planned from the program rs274 read as `elems`) on `p`.
pub(crate) fn check(elems: &[Element], segs: &[Segment], p: &Profile, default_tol: f64) -> Verdict {
    let lim = limits(p);
    let mut v = Verdict::default();
    let mut cursor = 0usize;
    // The last move and whether it ended on an element's end (then: that element's mode).
    let mut prev: Option<(&Segment, Option<Mode>)> = None;
    let mut planned_len = 0.0;
    // Planned length since the cursor's element was entered.
    let mut travelled = 0.0;
    for s in segs {
        if !matches!(s.kind, SegmentKind::Move(_)) {
            if let Some((a, _)) = prev.take() {
                let (va, _) = end_velocity(a, true);
                if norm3(&va) > 1e-2 {
                    v.bad(format!(
                        "line {}: moving at {:.3} mm/s into a dwell/stop",
                        a.line,
                        norm3(&va)
                    ));
                }
            }
            continue;
        }
        let len = dist(s.start, s.end);
        planned_len += len;
        if elems.is_empty() {
            v.bad(format!(
                "line {}: the plan moves where rs274's path has no move",
                s.line
            ));
            break;
        }
        // The elements this segment runs along.
        let c0 = cursor.min(elems.len().saturating_sub(1));
        travelled += len;
        // The first element ahead whose end this segment reaches, once the plan has run
        // about the length up to it (a circle passes its own end point on every turn).
        // The length of a spline is unknown: the search stops at the move after it, whose end
        // is the first known point.
        let mut ahead = 0.0;
        let mut end_match = None;
        for (j, e) in elems.iter().enumerate().take(c0 + WINDOW).skip(c0) {
            let tol = tol_of(e, default_tol) + ROUNDING;
            let known = e.length().is_finite();
            ahead += if known { e.length() } else { 0.0 };
            if travelled >= 0.99 * ahead - 2.0 * tol * (j - c0 + 1) as f64
                && e.end().is_some_and(|p| dist(p, s.end) <= tol)
            {
                end_match = Some(j);
                break;
            }
            if !known && e.end().is_some() {
                break;
            }
        }
        let last = end_match.unwrap_or((c0 + 1).min(elems.len().saturating_sub(1)));
        let cands = &elems[c0..=last.max(c0)];
        let tol = cands
            .iter()
            .map(|e| tol_of(e, default_tol))
            .fold(0.0, f64::max)
            + ROUNDING;
        let cap = cands.iter().map(|e| e.feed_cap).fold(0.0, f64::max);
        if let Some(j) = end_match {
            cursor = j + 1;
            travelled = 0.0;
        }
        // Junction with the previous move.
        let (vb, _) = end_velocity(s, false);
        match prev.take() {
            Some((a, mode)) => junction(&mut v, a, s, mode, &lim, default_tol),
            None => {
                if norm3(&vb) > 1e-2 {
                    v.bad(format!(
                        "line {}: starts moving at {:.3} mm/s",
                        s.line,
                        norm3(&vb)
                    ));
                }
            }
        }
        prev = Some((s, end_match.map(|j| elems[j].mode)));
        // Samples along the segment.
        let t = s.duration();
        let n = ((t / PERIOD).ceil() as usize).max(2);
        let h = t / n as f64;
        let pts: Vec<[f64; 6]> = (0..=n).map(|k| at(s, k as f64 * h)).collect();
        for q in &pts {
            let d = cands
                .iter()
                .map(|e| e.distance([q[0], q[1], q[2]]))
                .fold(f64::INFINITY, f64::min);
            v.worst_path = v.worst_path.max(d);
            if d > tol {
                v.bad(format!(
                    "line {}: ({:.4}, {:.4}, {:.4}) is {d:.4} mm off rs274's path (call {}), tolerance {tol:.4}",
                    s.line, q[0], q[1], q[2], cands[0].call
                ));
                break;
            }
        }
        v.samples += pts.len();
        if h <= 0.0 {
            continue;
        }
        let vel: Vec<[f64; 6]> = pts
            .windows(2)
            .map(|w| std::array::from_fn(|i| (w[1][i] - w[0][i]) / h))
            .collect();
        for w in &vel {
            let sp = norm3(w);
            let pure_rotary = len < 1e-9;
            if !pure_rotary && cap.is_finite() {
                v.worst_speed_ratio = v.worst_speed_ratio.max(sp / cap);
                if sp > cap * (1.0 + 1e-6) + 1e-6 {
                    v.bad(format!(
                        "line {}: {sp:.4} mm/s over the feed {cap:.4} mm/s",
                        s.line
                    ));
                    break;
                }
            }
            if let Some(i) = (0..6).find(|&i| w[i].abs() > lim.rate[i] * (1.0 + 1e-6) + 1e-6) {
                v.bad(format!(
                    "line {}: axis {i} at {:.4}/s over its {:.4}/s",
                    s.line,
                    w[i].abs(),
                    lim.rate[i]
                ));
                break;
            }
        }
        // Finite-difference noise grows as 1/h²: below 20 µs the junction check covers it.
        if h < 2e-5 {
            continue;
        }
        for w in vel.windows(2) {
            for i in 0..6 {
                let a = (w[1][i] - w[0][i]).abs() / h;
                if lim.accel[i].is_finite() {
                    v.worst_accel_ratio = v.worst_accel_ratio.max(a / lim.accel[i]);
                }
                if a > lim.accel[i] * 1.001 + 1.0 {
                    v.bad(format!(
                        "line {}: axis {i} accelerates at {a:.2}/s² over its {:.2}",
                        s.line, lim.accel[i]
                    ));
                }
            }
        }
    }
    if let Some((a, _)) = prev {
        let (va, _) = end_velocity(a, true);
        if norm3(&va) > 1e-2 {
            v.bad(format!(
                "line {}: the program ends moving at {:.3} mm/s",
                a.line,
                norm3(&va)
            ));
        }
    }
    // Every element of rs274's path was reached, in order.
    let needed = elems
        .iter()
        .rposition(|e| e.length() > tol_of(e, default_tol) + ROUNDING)
        .map_or(0, |i| i + 1);
    if cursor < needed {
        v.bad(format!(
            "the plan stops at rs274's call {} of {} (planned {planned_len:.3} mm)",
            elems.get(cursor).map_or(0, |e| e.call),
            elems.last().map_or(0, |e| e.call)
        ));
    }
    v
}

/// The junction from move `a` into move `b`.
fn junction(
    v: &mut Verdict,
    a: &Segment,
    b: &Segment,
    mode: Option<Mode>,
    lim: &Limits,
    default_tol: f64,
) {
    let (va, ha) = end_velocity(a, true);
    let (vb, hb) = end_velocity(b, false);
    let (sa, sb) = (norm3(&va), norm3(&vb));
    // Numeric slack of the one-sided differences (exact under constant acceleration; a
    // phase change inside the last 2h errs by at most a·2h).
    let amax = lim.accel[..3].iter().cloned().fold(0.0, f64::max).min(1e6);
    let slack = 2.0 * amax * (ha + hb) + 1e-3;
    if (sa - sb).abs() > slack && sa.max(sb) > 1e-3 {
        v.bad(format!(
            "line {}→{}: speed jumps {sa:.4} → {sb:.4} mm/s",
            a.line, b.line
        ));
        return;
    }
    let ua = unit(a);
    let ub = unit(b);
    let (Some(ua), Some(ub)) = (ua, ub) else {
        return; // a pure rotary move: its axes' limits were checked above
    };
    let cos_phi = (0..3).map(|i| ua[i] * ub[i]).sum::<f64>().clamp(-1.0, 1.0);
    let phi = cos_phi.acos();
    let speed = 0.5 * (sa + sb);
    let stop = 1e-2 + slack;
    let delta = match mode {
        Some(Mode::ExactStop) => {
            if speed > stop {
                v.bad(format!(
                    "line {}: G61 exact stop passed at {speed:.4} mm/s",
                    a.line
                ));
            }
            return;
        }
        Some(Mode::ExactPath) => 0.0,
        Some(Mode::Continuous(p)) if p > 0.0 => p.max(default_tol),
        _ => default_tol,
    };
    if phi < 1e-6 {
        return; // straight on
    }
    // Blend circle radius for deviation δ at a turn by φ.
    let c = (0.5 * phi).cos();
    let r = if c < 1.0 {
        delta * c / (1.0 - c)
    } else {
        f64::INFINITY
    };
    for i in 0..3 {
        let du = (ub[i] - ua[i]).abs();
        // v²·|Δu_i| ≤ a_i·R·φ
        let allowed = lim.accel[i] * r * phi * 1.001;
        if speed * speed * du > allowed + slack * speed.max(1.0) + 1e-6 {
            v.bad(format!(
                "line {}→{}: corner of {:.2}° at {speed:.4} mm/s: axis {i} changes by {:.4} mm/s, more than a blend within {delta:.4} mm allows",
                a.line, b.line, phi.to_degrees(), speed * du
            ));
            return;
        }
    }
}

fn unit(s: &Segment) -> Option<[f64; 3]> {
    let l = dist(s.start, s.end);
    (l > 1e-12).then(|| std::array::from_fn(|i| (s.end[i] - s.start[i]) / l))
}
