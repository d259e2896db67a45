//! G5 (cubic spline), G5.1 (quadratic B-spline), G5.2 … G5.3 (NURBS) in the XY plane, read as
//! LinuxCNC's interpreter reads them (`interp_convert.cc`, `convert_spline` and
//! `convert_nurbs`): the same checks, the same control points (the start point first, all
//! in program coordinates), one `NURBS_FEED` call per curve.
//!
//! Each curve is emitted as [`CanonOp::NurbsFeed`] (what `rs274` prints) followed by the
//! curve itself: straight feeds through points on it, no farther from it than the program's
//! G64 P tolerance (or [`DEFAULT_TOLERANCE`]), so the planner, the preview, the simulator
//! and the time estimate follow the curve, not its control polygon.
//!
//! The curve is LinuxCNC's: a rational B-spline of order k (4 for G5, 3 for G5.1, the L word
//! or 3 for G5.2) over its control points and weights, with the clamped uniform knot vector
//! of `nurbs_additional_functions.cc` (k zeros, 1 … n−k+1, k times n−k+2, n + 1 points).
//! G5 and G5.1 are then the cubic and quadratic Béziers through their four and three points.

use super::state::Motion;
use super::words::{g_group as G, Decoded};
use super::{Interpreter, Sink};
use crate::diag::Diagnostic;
use oficina_canon::{CanonOp, FeedMode, Plane};

/// Largest distance between the emitted straight feeds and the curve when the program sets
/// no G64 P tolerance, mm.
pub(crate) const DEFAULT_TOLERANCE: f64 = 0.01;

/// Deepest halving of a parameter interval while flattening: at most 2^12 feeds per knot
/// span, whatever the weights.
const MAX_DEPTH: u32 = 12;

/// What the interpreter remembers between spline blocks.
#[derive(Clone, Debug, Default)]
pub(crate) struct SplineMemory {
    /// G5.2 control points so far: X, Y (program coordinates, mm) and weight.
    nurbs: Vec<[f64; 3]>,
    /// The order of the NURBS being built (3 unless an L word over 3 says otherwise).
    order: u32,
    /// G5 without I and J starts with the reflection of the previous G5's P Q (mm).
    last_pq: [f64; 2],
    /// The motion mode is G5.2 (a NURBS is being built): LinuxCNC's
    /// `motion_mode == G_5_2`, cleared by any other motion code but G5.3.
    pub(crate) continuing: bool,
}

impl Interpreter {
    /// G5 / G5.1 (`tenths` 50 / 51) to the block's X Y.
    pub(super) fn spline(
        &mut self,
        d: &Decoded,
        tenths: u16,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        if self.modal.comp.is_some() {
            return Err(self.fail(
                span,
                "Cannot convert spline with cutter radius compensation",
                0,
            ));
        }
        match self.modal.feed_mode {
            FeedMode::InverseTime if !d.has('F') => {
                return Err(self.fail(span, "F word missing with inverse time arc move", 0))
            }
            FeedMode::UnitsPerMinute if self.modal.feed <= 0.0 => {
                return Err(self
                    .fail(span, "Cannot make arc with zero feed rate", 0)
                    .with_help("program a feed with an F word before the first feed move"))
            }
            _ => {}
        }
        if self.modal.plane != Plane::XY {
            return Err(self
                .fail(span, "Splines must be in the XY plane", 0)
                .with_help("select the XY plane with G17 before G5 or G5.1"));
        }
        if let Some(l) = ['Z', 'A', 'B', 'C'].into_iter().find(|&l| d.has(l)) {
            return Err(self.fail(
                d.span_of(l),
                "Splines may not have motion in Z, A, B, or C",
                0,
            ));
        }
        let k = self.k();
        let start = [self.pos[0], self.pos[1]];
        let stop = [end[0], end[1]];
        let points = if tenths == 51 {
            let (Some(i), Some(j)) = (d.get('I'), d.get('J')) else {
                return Err(self.fail(span, "Must specify both I and J with G5.1", 0));
            };
            vec![start, [start[0] + i * k, start[1] + j * k], stop]
        } else {
            let first = match (d.get('I'), d.get('J')) {
                (Some(i), Some(j)) => [i * k, j * k],
                (None, None) => self.spline.last_pq,
                _ => {
                    return Err(self.fail(span, "Must specify both I and J, or neither", 0));
                }
            };
            let (Some(p), Some(q)) = (d.get('P'), d.get('Q')) else {
                return Err(self.fail(span, "Must specify both P and Q with G5", 0));
            };
            let (p, q) = (p * k, q * k);
            self.spline.last_pq = [-p, -q];
            vec![
                start,
                [start[0] + first[0], start[1] + first[1]],
                [stop[0] + p, stop[1] + q],
                stop,
            ]
        };
        self.inverse_time_rate(d, sink);
        let weighted: Vec<[f64; 3]> = points.iter().map(|p| [p[0], p[1], 1.0]).collect();
        let order = weighted.len() as u32;
        self.emit_nurbs(sink, &weighted, order, d.get('F'));
        Ok(())
    }

    /// G5.2 (`tenths` 52): one more control point; G5.3 (53): the curve.
    pub(super) fn nurbs(
        &mut self,
        d: &Decoded,
        tenths: u16,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        if tenths == 53 {
            if !self.spline.continuing {
                return Err(self.fail(span, "Cannot use G5.3 without G5.2 first", 0));
            }
            let (points, order) = (std::mem::take(&mut self.spline.nurbs), self.spline.order);
            self.spline.continuing = false;
            self.modal.motion = Motion::Off;
            if (points.len() as u32) < order {
                return Err(self.fail(
                    span,
                    format!(
                        "You must specify a number of control points at least equal to the order L = {order}"
                    ),
                    0,
                ));
            }
            self.emit_nurbs(sink, &points, order, d.get('F'));
            return Ok(());
        }
        let (x, y) = (d.has('X'), d.has('Y'));
        if x != y {
            return Err(self.fail(
                d.axis_span(),
                "You must specify both X and Y coordinates for Control Points",
                0,
            ));
        }
        let p = d.get('P').unwrap_or(-1.0);
        let started = self.spline.continuing && !self.spline.nurbs.is_empty();
        if !x && p > 0.0 && started {
            return Err(self.fail(
                d.span_of('P'),
                "Can specify P without X and Y only for the first control point",
                0,
            ));
        }
        if p <= 0.0 && started {
            return Err(self
                .fail(
                    span,
                    "Must specify positive weight P for every Control Point",
                    0,
                )
                .with_help(
                    "each control point after the first needs its weight: P1 for an ordinary one",
                ));
        }
        if self.modal.feed_mode == FeedMode::UnitsPerMinute && self.modal.feed <= 0.0 {
            return Err(self.fail(span, "Cannot make a NURBS with 0 feedrate", 0));
        }
        if !self.spline.continuing {
            self.spline.nurbs.clear();
            self.spline.continuing = true;
        }
        if self.spline.nurbs.is_empty() {
            let w = if !x && p > 0.0 { p } else { 1.0 };
            self.spline.nurbs.push([self.pos[0], self.pos[1], w]);
            self.spline.order = 3;
        }
        if let Some(l) = d.get('L') {
            if l > 3.0 {
                self.spline.order = l as u32;
            }
        }
        if x {
            self.spline.nurbs.push([end[0], end[1], p]);
        }
        Ok(())
    }

    /// NURBS_FEED, then the curve as straight feeds from the current point; the current point
    /// becomes the last control point (X and Y only, as in LinuxCNC). Under G93 the block's F
    /// (else the last one) times the whole curve: each feed gets the inverse-time rate that
    /// gives it its share of 1/F minutes, by length.
    fn emit_nurbs(&mut self, sink: Sink, points: &[[f64; 3]], order: u32, f: Option<f64>) {
        let tolerance = if self.modal.blend_tolerance > 0.0 {
            self.modal.blend_tolerance
        } else {
            DEFAULT_TOLERANCE
        };
        let on_curve = flatten(points, order, tolerance);
        self.emit(
            sink,
            CanonOp::NurbsFeed {
                control_points: points.len() as u32,
                segments: on_curve.len() as u32,
            },
        );
        let inverse_f = f.unwrap_or(self.modal.feed);
        let timed = self.modal.feed_mode == FeedMode::InverseTime && inverse_f > 0.0;
        let mut from = [self.pos[0], self.pos[1]];
        let total: f64 = if timed {
            on_curve
                .iter()
                .scan(from, |a, b| {
                    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
                    *a = *b;
                    Some(l)
                })
                .sum()
        } else {
            0.0
        };
        for p in on_curve {
            if timed {
                let len = (p[0] - from[0]).hypot(p[1] - from[1]);
                if len > 0.0 && total > 0.0 {
                    self.emit(sink, CanonOp::SetFeedRate(inverse_f * total / len));
                }
            }
            from = p;
            let mut to = self.pos;
            to[0] = p[0];
            to[1] = p[1];
            self.emit_straight(sink, true, to);
        }
        if let Some(last) = points.last() {
            self.pos[0] = last[0];
            self.pos[1] = last[1];
        }
    }
}

/// The clamped uniform knot vector of LinuxCNC for `n_points` control points of order `k`.
fn knots(n_points: usize, k: usize) -> Vec<f64> {
    let n = n_points - 1;
    (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i - k + 1) as f64
            } else {
                (n + 2 - k) as f64
            }
        })
        .collect()
}

/// Orders up to this are evaluated in a buffer on the stack (G5 is 4, G5.1 and G5.2 3).
const STACK_ORDER: usize = 8;

/// The point of the rational B-spline at parameter `u` (de Boor in homogeneous coordinates);
/// `None` where the weights cancel.
fn point_at(points: &[[f64; 3]], k: usize, knots: &[f64], u: f64) -> Option<[f64; 2]> {
    let n = points.len() - 1;
    // The knot span holding u: knots[s] <= u < knots[s + 1], the last span for the end.
    let mut s = k - 1;
    while s < n && u >= knots[s + 1] {
        s += 1;
    }
    let mut stack = [[0.0; 3]; STACK_ORDER];
    let mut heap = Vec::new();
    let d: &mut [[f64; 3]] = if k <= STACK_ORDER {
        &mut stack[..k]
    } else {
        heap.resize(k, [0.0; 3]);
        &mut heap
    };
    for (j, dj) in d.iter_mut().enumerate() {
        let [x, y, w] = points[j + s + 1 - k];
        *dj = [x * w, y * w, w];
    }
    for r in 1..k {
        for j in (r..k).rev() {
            let i = j + s + 1 - k;
            let den = knots[i + k - r] - knots[i];
            let a = if den == 0.0 {
                0.0
            } else {
                (u - knots[i]) / den
            };
            for c in 0..3 {
                d[j][c] = (1.0 - a) * d[j - 1][c] + a * d[j][c];
            }
        }
    }
    let [x, y, w] = d[k - 1];
    let p = [x / w, y / w];
    (w != 0.0 && p[0].is_finite() && p[1].is_finite()).then_some(p)
}

/// Points on the curve after its start, ending at its last control point, such that the
/// straight lines through them stay within `tolerance` of the curve (checked at a quarter,
/// half and three quarters of each piece). Order below 2 or above the number of points
/// (refused before this by the interpreter) gives the straight line to the end.
pub(crate) fn flatten(points: &[[f64; 3]], order: u32, tolerance: f64) -> Vec<[f64; 2]> {
    let Some(last) = points.last() else {
        return Vec::new();
    };
    let end = [last[0], last[1]];
    let k = order as usize;
    if k < 2 || k > points.len() {
        return vec![end];
    }
    let knots = knots(points.len(), k);
    let curve = Curve {
        points,
        k,
        knots: &knots,
        tolerance2: tolerance * tolerance,
        bezier: (points.len() == k && k <= STACK_ORDER).then(|| power_basis(points)),
    };
    let mut out = Vec::new();
    let spans = (points.len() - k + 1) as u32;
    let mut prev = [points[0][0], points[0][1]];
    for span in 0..spans {
        let (u0, u1) = (f64::from(span), f64::from(span + 1));
        if let Some(p1) = curve.at(u1) {
            let mid = curve.at(0.5 * (u0 + u1));
            curve.refine(u0, prev, u1, p1, mid, 0, &mut out);
        }
        if let Some(p) = out.last() {
            prev = *p;
        }
    }
    // The curve ends on its last control point (clamped knots): say so exactly.
    match out.last_mut() {
        Some(p) => *p = end,
        None => out.push(end),
    }
    out
}

/// A curve being flattened: its control points, order, knots and squared tolerance.
struct Curve<'a> {
    points: &'a [[f64; 3]],
    k: usize,
    knots: &'a [f64],
    tolerance2: f64,
    /// A curve of one knot span (G5, G5.1, a G5.2 of as many points as its order) is a
    /// rational Bézier over u ∈ [0, 1]: its homogeneous coordinates in the power basis.
    bezier: Option<PowerBasis>,
}

/// Coefficients c_0 … c_d of x·w, y·w and w as polynomials in u (Horner's rule: d
/// multiply-adds per coordinate, where de Boor takes d(d+1)/2 interpolations and divisions).
struct PowerBasis {
    c: [[f64; 3]; STACK_ORDER],
    n: usize,
}

/// The power basis of the Bézier of `points` (x, y, weight): with homogeneous points
/// P_i = (x·w, y·w, w) and degree d, c_j = C(d, j) · Σ_{i ≤ j} (−1)^{j−i} C(j, i) P_i
/// (the binomial expansion of Σ C(d, i) (1−u)^{d−i} u^i P_i).
fn power_basis(points: &[[f64; 3]]) -> PowerBasis {
    let d = points.len() - 1;
    let binom =
        |n: usize, r: usize| (0..r).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64);
    let mut c = [[0.0; 3]; STACK_ORDER];
    for (j, cj) in c.iter_mut().enumerate().take(d + 1) {
        for (i, p) in points.iter().enumerate().take(j + 1) {
            let sign = if (j - i) % 2 == 0 { 1.0 } else { -1.0 };
            let f = sign * binom(j, i);
            let h = [p[0] * p[2], p[1] * p[2], p[2]];
            for a in 0..3 {
                cj[a] += f * h[a];
            }
        }
        let b = binom(d, j);
        for v in cj.iter_mut() {
            *v *= b;
        }
    }
    PowerBasis { c, n: d + 1 }
}

impl Curve<'_> {
    fn at(&self, u: f64) -> Option<[f64; 2]> {
        let Some(b) = &self.bezier else {
            return point_at(self.points, self.k, self.knots, u);
        };
        let mut h = b.c[b.n - 1];
        for cj in b.c[..b.n - 1].iter().rev() {
            for a in 0..3 {
                h[a] = h[a] * u + cj[a];
            }
        }
        let p = [h[0] / h[2], h[1] / h[2]];
        (h[2] != 0.0 && p[0].is_finite() && p[1].is_finite()).then_some(p)
    }

    /// Pushes the end of the piece u0…u1 (p0 to p1, `mid` its point at the middle) once the
    /// chord p0–p1 lies within the tolerance of the curve at a quarter, half and three
    /// quarters; else the two halves, each reusing the points found here (its end and its
    /// middle), so every level costs two evaluations, not four.
    #[allow(clippy::too_many_arguments)]
    fn refine(
        &self,
        u0: f64,
        p0: [f64; 2],
        u1: f64,
        p1: [f64; 2],
        mid: Option<[f64; 2]>,
        depth: u32,
        out: &mut Vec<[f64; 2]>,
    ) {
        let q1 = self.at(u0 + (u1 - u0) * 0.25);
        let q3 = self.at(u0 + (u1 - u0) * 0.75);
        let far = depth < MAX_DEPTH
            && [q1, mid, q3]
                .iter()
                .any(|q| q.is_none_or(|q| distance2_to_segment(q, p0, p1) > self.tolerance2));
        if !far {
            out.push(p1);
            return;
        }
        let um = 0.5 * (u0 + u1);
        // Where the weights cancel at the middle, the first half has no end to go to.
        let pm = match mid {
            Some(pm) => {
                self.refine(u0, p0, um, pm, q1, depth + 1, out);
                out.last().copied().unwrap_or(p0)
            }
            None => p0,
        };
        self.refine(um, pm, u1, p1, q3, depth + 1, out);
    }
}

/// Squared distance from q to the segment a–b.
fn distance2_to_segment(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (q[0] - a[0] - t * dx, q[1] - a[1] - t * dy);
    ex * ex + ey * ey
}

#[cfg(test)]
fn distance_to_segment(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    distance2_to_segment(q, a, b).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cubic(p: [[f64; 2]; 4], t: f64) -> [f64; 2] {
        let s = 1.0 - t;
        let b = [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t];
        [
            (0..4).map(|i| b[i] * p[i][0]).sum(),
            (0..4).map(|i| b[i] * p[i][1]).sum(),
        ]
    }

    #[test]
    fn the_power_basis_is_de_boors_curve_on_one_span() {
        // Rational, orders 2 to 6: Horner on the power basis against de Boor's recursion.
        for k in 2..=6usize {
            let pts: Vec<[f64; 3]> = (0..k)
                .map(|i| {
                    let f = i as f64;
                    [
                        f * 3.0 - (f * 1.7).sin() * 5.0,
                        (f * 0.9).cos() * 7.0,
                        0.5 + f * 0.4,
                    ]
                })
                .collect();
            let knots = knots(k, k);
            let curve = Curve {
                points: &pts,
                k,
                knots: &knots,
                tolerance2: 1e-4,
                bezier: Some(power_basis(&pts)),
            };
            for i in 0..=20 {
                let u = i as f64 / 20.0;
                let a = curve.at(u).unwrap();
                let b = point_at(&pts, k, &knots, u).unwrap();
                assert!(
                    (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9,
                    "{k} {u}"
                );
            }
        }
    }

    #[test]
    fn g5_is_the_cubic_bezier_of_its_points() {
        let p = [[0.0, 0.0], [0.0, 30.0], [10.0, -20.0], [10.0, 10.0]];
        let w: Vec<[f64; 3]> = p.iter().map(|q| [q[0], q[1], 1.0]).collect();
        let knots = knots(4, 4);
        assert_eq!(knots, [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
        for t in [0.0, 0.1, 0.37, 0.5, 0.99] {
            let a = point_at(&w, 4, &knots, t).unwrap();
            let b = cubic(p, t);
            assert!(
                (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12,
                "{t}"
            );
        }
        // Every point of the true curve lies within the tolerance of the flattened path.
        let tol = 0.01;
        let flat = flatten(&w, 4, tol);
        assert_eq!(*flat.last().unwrap(), [10.0, 10.0]);
        assert!(
            flat.len() > 10,
            "a polyline of the curve, not of its 4 points"
        );
        let mut path = vec![[0.0, 0.0]];
        path.extend(&flat);
        for i in 0..=1000 {
            let q = cubic(p, i as f64 / 1000.0);
            let d = path
                .windows(2)
                .map(|s| distance_to_segment(q, s[0], s[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= tol * 1.01, "{i}: {d}");
        }
    }

    #[test]
    fn a_nurbs_with_equal_weights_passes_its_clamped_ends_and_a_circle_quarter_is_round() {
        // Quarter circle of radius 10 as a rational quadratic: weights 1, √½, 1.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let w = [[10.0, 0.0, 1.0], [10.0, 10.0, h], [0.0, 10.0, 1.0]];
        let flat = flatten(&w, 3, 0.001);
        for p in &flat {
            assert!((p[0].hypot(p[1]) - 10.0).abs() < 1e-9, "{p:?}");
        }
        assert_eq!(*flat.last().unwrap(), [0.0, 10.0]);
        // Five points of order 3: knots 0 0 0 1 2 3 3 3.
        assert_eq!(knots(5, 3), [0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]);
        // Order above the point count: the straight line to the end.
        assert_eq!(flatten(&w[..2], 3, 0.01), vec![[10.0, 10.0]]);
    }
}
