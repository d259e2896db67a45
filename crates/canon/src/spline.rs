//! A spline kept whole: LinuxCNC's `NURBS_FEED` with its control points, and the one place
//! where it becomes straight feeds ([`Nurbs::trace`], through [`flatten`]).
//!
//! The curve is LinuxCNC's: a rational B-spline of order k (4 for G5, 3 for G5.1, the L word
//! or 3 for G5.2) over its control points and weights, with the clamped uniform knot vector
//! of `nurbs_additional_functions.cc` (k zeros, 1 … n−k+1, k times n−k+2, n + 1 points).
//! G5 and G5.1 are then the cubic and quadratic Béziers through their four and three points.
//!
//! The control points are in machine coordinates: a rational B-spline is invariant under
//! affine maps of its control points (the weights unchanged), so the offsets and the XY
//! rotation that take program to machine coordinates take the curve along exactly, and a
//! rigid map keeps the tolerance.

use crate::{CanonOp, Pos};

/// A spline in the XY plane, whole (see [`CanonOp::Spline`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Nurbs {
    /// Control points X, Y (machine coordinates, mm) and weight; the start point first.
    pub points: Vec<[f64; 3]>,
    /// The order k (degree + 1).
    pub order: u32,
    /// Largest distance between the traced feeds and the curve, mm (the program's G64 P).
    pub tolerance: f64,
    /// Where the curve ends, machine coordinates: X Y its last control point, the other
    /// axes where they were (a spline moves X and Y only).
    pub end: Pos,
    /// Under G93, the inverse-time rate (1/min) that times the whole curve.
    pub inverse_time: Option<f64>,
}

impl Nurbs {
    /// The spline as the operations that move along it: [`CanonOp::NurbsFeed`], then
    /// straight feeds through points of the curve within the tolerance. Under G93 each feed
    /// is preceded by the inverse-time rate that gives it its share of 1/F minutes, by
    /// length: a feed of length l of a curve of length L takes (l/L)/F minutes, rate F·L/l.
    pub fn trace(&self, mut emit: impl FnMut(CanonOp)) {
        let on_curve = flatten(&self.points, self.order, self.tolerance);
        emit(CanonOp::NurbsFeed {
            control_points: self.points.len() as u32,
            segments: on_curve.len() as u32,
        });
        let start = self.points.first().map_or([0.0; 2], |p| [p[0], p[1]]);
        let length = |p: [f64; 2], q: [f64; 2]| (q[0] - p[0]).hypot(q[1] - p[1]);
        let timed = self.inverse_time.filter(|&f| f > 0.0);
        let total: f64 = match timed {
            Some(_) => on_curve
                .iter()
                .scan(start, |a, b| {
                    let l = length(*a, *b);
                    *a = *b;
                    Some(l)
                })
                .sum(),
            None => 0.0,
        };
        let mut from = start;
        for p in on_curve {
            if let Some(f) = timed {
                let len = length(from, p);
                if len > 0.0 && total > 0.0 {
                    emit(CanonOp::SetFeedRate(f * total / len));
                }
            }
            from = p;
            emit(CanonOp::StraightFeed {
                to: Pos {
                    x: p[0],
                    y: p[1],
                    ..self.end
                },
            });
        }
    }
}

/// Deepest halving of a parameter interval while flattening: at most 2^12 feeds per knot
/// span, whatever the weights.
const MAX_DEPTH: u32 = 12;

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
pub fn flatten(points: &[[f64; 3]], order: u32, tolerance: f64) -> Vec<[f64; 2]> {
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
