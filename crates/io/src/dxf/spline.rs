//! SPLINE → cubic Béziers.
//!
//! A NURBS curve of degree p with control points Pᵢ, weights wᵢ and knots uⱼ is, on each knot
//! span [uₛ, uₛ₊₁], one rational polynomial piece. De Boor's algorithm in homogeneous
//! coordinates (wᵢPᵢ, wᵢ) evaluates the piece of span s anywhere, also outside the span (the
//! piece's own polynomial continued), which is what the conversion needs:
//!
//! - non-rational (all weights equal) and p ≤ 3: each piece *is* a cubic polynomial, and a cubic
//!   is fixed by four of its points. With Q₀ = B(0), Q₁ = B(⅓), Q₂ = B(⅔), Q₃ = B(1) of the
//!   Bézier P₀..P₃: Q₁ = (8P₀ + 12P₁ + 6P₂ + P₃)/27 and Q₂ = (P₀ + 6P₁ + 12P₂ + 8P₃)/27, so with
//!   A = 27Q₁ − 8Q₀ − Q₃ and B = 27Q₂ − Q₀ − 8Q₃: P₁ = (2A − B)/18, P₂ = (2B − A)/18. Exact.
//! - rational, or p > 3: the same four-point cubic on a piece of the span, checked against the
//!   curve at seven more parameters and halved until the largest distance is within the
//!   tolerance (the error of a four-point cubic falls as h⁴, so few halvings are needed).
//!
//! A spline given by fit points only is the interpolating cubic that CAD programs (and ezdxf's
//! `fit_points_to_cad_cv`) build: chord-length parameters, knots at the parameters, end
//! derivatives from the file's end tangents scaled to the total chord length, or zero second
//! derivatives at the ends when the file has none. It is C², so its derivatives Dᵢ at the fit
//! points solve the tridiagonal system (hᵢ = tᵢ₊₁ − tᵢ)
//! hᵢ Dᵢ₋₁ + 2(hᵢ₋₁ + hᵢ) Dᵢ + hᵢ₋₁ Dᵢ₊₁ = 3 (hᵢ (Pᵢ − Pᵢ₋₁)/hᵢ₋₁ + hᵢ₋₁ (Pᵢ₊₁ − Pᵢ)/hᵢ),
//! with 2D₀ + D₁ = 3(P₁ − P₀)/h₀ (and its mirror) as natural ends; each interval is then the
//! Bézier Pᵢ, Pᵢ + hᵢDᵢ/3, Pᵢ₊₁ − hᵢDᵢ₊₁/3, Pᵢ₊₁.

use oficina_geom::kurbo::{CubicBez, ParamCurve, Point, Vec2};

/// Most Béziers one spline may become (a bound whatever the file asks for).
const MAX_PIECES: usize = 200_000;
/// Deepest halving of one knot span.
const MAX_DEPTH: u32 = 24;

/// A NURBS curve in the plane.
pub(super) struct Nurbs<'a> {
    pub(super) degree: usize,
    pub(super) ctrl: &'a [Point],
    /// Empty or one per control point.
    pub(super) weights: &'a [f64],
    pub(super) knots: &'a [f64],
}

impl Nurbs<'_> {
    fn check(&self) -> Result<(), String> {
        let (n, p) = (self.ctrl.len(), self.degree);
        if p == 0 || p > 11 {
            return Err(format!("degree {p} (1 to 11 are read)"));
        }
        if n <= p {
            return Err(format!(
                "{n} control points for degree {p}: at least {} are needed",
                p + 1
            ));
        }
        if self.knots.len() != n + p + 1 {
            return Err(format!(
                "{} knots for {n} control points of degree {p}: {} are needed",
                self.knots.len(),
                n + p + 1
            ));
        }
        if self.knots.windows(2).any(|k| k[1] < k[0]) {
            return Err("the knots decrease".into());
        }
        if !(self.knots[n] > self.knots[p]) {
            return Err("the knots span no parameter range".into());
        }
        if !self.weights.is_empty()
            && (self.weights.len() != n || self.weights.iter().any(|w| !(*w > 0.0)))
        {
            return Err(format!(
                "{} weights for {n} control points (one positive weight each)",
                self.weights.len()
            ));
        }
        Ok(())
    }

    fn weight(&self, i: usize) -> f64 {
        self.weights.get(i).copied().unwrap_or(1.0)
    }

    fn rational(&self) -> bool {
        self.weights
            .iter()
            .any(|w| (w - self.weights[0]).abs() > 1e-12 * self.weights[0].abs())
    }

    /// The piece of knot span `s` (uₛ ≤ u < uₛ₊₁, p ≤ s < n) at `u`: homogeneous de Boor.
    fn piece(&self, s: usize, u: f64) -> Point {
        let p = self.degree;
        let k = self.knots;
        let mut d = [(0.0, 0.0, 0.0); 12];
        for (j, dj) in d.iter_mut().enumerate().take(p + 1) {
            let c = self.ctrl[s - p + j];
            let w = self.weight(s - p + j);
            *dj = (c.x * w, c.y * w, w);
        }
        for r in 1..=p {
            for j in (r..=p).rev() {
                let i = s - p + j;
                let den = k[i + p + 1 - r] - k[i];
                let a = if den > 0.0 { (u - k[i]) / den } else { 0.0 };
                d[j] = (
                    (1.0 - a) * d[j - 1].0 + a * d[j].0,
                    (1.0 - a) * d[j - 1].1 + a * d[j].1,
                    (1.0 - a) * d[j - 1].2 + a * d[j].2,
                );
            }
        }
        let (x, y, w) = d[p];
        Point::new(x / w, y / w)
    }

    /// The curve as cubic Béziers, within `tol` of it (exact where that is possible).
    pub(super) fn to_cubics(&self, tol: f64) -> Result<Vec<CubicBez>, String> {
        self.check()?;
        let (n, p) = (self.ctrl.len(), self.degree);
        let exact = p <= 3 && !self.rational();
        let mut out = Vec::new();
        for s in p..n {
            let (a, b) = (self.knots[s], self.knots[s + 1]);
            if b <= a {
                continue;
            }
            let f = |u: f64| self.piece(s, u);
            if exact {
                out.push(four_point_cubic(&f, a, b));
            } else {
                // Checked at seven parameters only: half the tolerance there keeps the
                // points between them inside it.
                approximate(&f, a, b, 0.5 * tol, 0, &mut out)?;
            }
            if out.len() > MAX_PIECES {
                return Err(format!("more than {MAX_PIECES} pieces"));
            }
        }
        if out.iter().any(|c| {
            ![c.p0, c.p1, c.p2, c.p3]
                .iter()
                .all(|q| q.x.is_finite() && q.y.is_finite())
        }) {
            return Err("its points are not finite".into());
        }
        Ok(out)
    }
}

/// The cubic through f(a), f(a + h/3), f(a + 2h/3), f(b) at t = 0, ⅓, ⅔, 1.
fn four_point_cubic(f: &impl Fn(f64) -> Point, a: f64, b: f64) -> CubicBez {
    let h = b - a;
    let q0 = f(a).to_vec2();
    let q1 = f(a + h / 3.0).to_vec2();
    let q2 = f(a + 2.0 * h / 3.0).to_vec2();
    let q3 = f(b).to_vec2();
    let aa = q1 * 27.0 - q0 * 8.0 - q3;
    let bb = q2 * 27.0 - q0 - q3 * 8.0;
    let p1 = (aa * 2.0 - bb) / 18.0;
    let p2 = (bb * 2.0 - aa) / 18.0;
    CubicBez::new(q0.to_point(), p1.to_point(), p2.to_point(), q3.to_point())
}

fn approximate(
    f: &impl Fn(f64) -> Point,
    a: f64,
    b: f64,
    tol: f64,
    depth: u32,
    out: &mut Vec<CubicBez>,
) -> Result<(), String> {
    let c = four_point_cubic(f, a, b);
    let worst = [0.07, 0.17, 0.25, 0.5, 0.75, 0.83, 0.93]
        .iter()
        .map(|&t| c.eval(t).distance(f(a + (b - a) * t)))
        .fold(0.0f64, f64::max);
    if worst <= tol || depth >= MAX_DEPTH || !worst.is_finite() {
        out.push(c);
        return Ok(());
    }
    if out.len() > MAX_PIECES {
        return Err(format!("more than {MAX_PIECES} pieces"));
    }
    let m = 0.5 * (a + b);
    approximate(f, a, m, tol, depth + 1, out)?;
    approximate(f, m, b, tol, depth + 1, out)
}

/// The CAD interpolating cubic through `pts` (see the module notes); `tangents` are the
/// file's start and end tangent directions, if it has them.
pub(crate) fn through_fit_points(pts: &[Point], tangents: Option<(Vec2, Vec2)>) -> Vec<CubicBez> {
    // Repeated points give no parameter step: drop them.
    let mut p: Vec<Point> = Vec::with_capacity(pts.len());
    for &q in pts {
        if p.last().is_none_or(|l: &Point| l.distance(q) > 0.0) {
            p.push(q);
        }
    }
    let n = p.len();
    if n < 2 {
        return Vec::new();
    }
    let total: f64 = p.windows(2).map(|w| w[0].distance(w[1])).sum();
    let h: Vec<f64> = p.windows(2).map(|w| w[0].distance(w[1]) / total).collect();
    let chord = |i: usize| (p[i + 1] - p[i]) / h[i];
    // Tridiagonal system lo·Dᵢ₋₁ + di·Dᵢ + up·Dᵢ₊₁ = r (Thomas algorithm).
    let mut lo = vec![0.0; n];
    let mut di = vec![0.0; n];
    let mut up = vec![0.0; n];
    let mut r = vec![Vec2::ZERO; n];
    let tangents = tangents.filter(|(a, b)| a.hypot() > 0.0 && b.hypot() > 0.0);
    match tangents {
        Some((t0, _)) => {
            di[0] = 1.0;
            r[0] = t0.normalize() * total;
        }
        None => {
            di[0] = 2.0;
            up[0] = 1.0;
            r[0] = chord(0) * 3.0;
        }
    }
    for i in 1..n - 1 {
        lo[i] = h[i];
        di[i] = 2.0 * (h[i - 1] + h[i]);
        up[i] = h[i - 1];
        r[i] = (chord(i - 1) * h[i] + chord(i) * h[i - 1]) * 3.0;
    }
    match tangents {
        Some((_, t1)) => {
            di[n - 1] = 1.0;
            lo[n - 1] = 0.0;
            r[n - 1] = t1.normalize() * total;
        }
        None => {
            lo[n - 1] = 1.0;
            di[n - 1] = 2.0;
            r[n - 1] = chord(n - 2) * 3.0;
        }
    }
    for i in 1..n {
        let m = lo[i] / di[i - 1];
        di[i] -= m * up[i - 1];
        r[i] = r[i] - r[i - 1] * m;
    }
    let mut d = vec![Vec2::ZERO; n];
    d[n - 1] = r[n - 1] / di[n - 1];
    for i in (0..n - 1).rev() {
        d[i] = (r[i] - d[i + 1] * up[i]) / di[i];
    }
    (0..n - 1)
        .map(|i| {
            CubicBez::new(
                p[i],
                p[i] + d[i] * (h[i] / 3.0),
                p[i + 1] - d[i + 1] * (h[i] / 3.0),
                p[i + 1],
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[(f64, f64)]) -> Vec<Point> {
        v.iter().map(|&(x, y)| Point::new(x, y)).collect()
    }

    #[test]
    fn a_clamped_cubic_is_its_own_bezier() {
        let c = pts(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]);
        let k = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let b = Nurbs {
            degree: 3,
            ctrl: &c,
            weights: &[],
            knots: &k,
        }
        .to_cubics(1e-3)
        .unwrap();
        assert_eq!(b.len(), 1);
        for (got, want) in [b[0].p0, b[0].p1, b[0].p2, b[0].p3].iter().zip(&c) {
            assert!(got.distance(*want) < 1e-12, "{got:?} {want:?}");
        }
    }

    #[test]
    fn a_quadratic_rational_quarter_circle_within_tolerance() {
        // Weights 1, √½, 1 on (1,0), (1,1), (0,1): exactly the unit quarter circle.
        let c = pts(&[(100.0, 0.0), (100.0, 100.0), (0.0, 100.0)]);
        let w = [1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0];
        let k = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let b = Nurbs {
            degree: 2,
            ctrl: &c,
            weights: &w,
            knots: &k,
        }
        .to_cubics(1e-3)
        .unwrap();
        let worst = b
            .iter()
            .flat_map(|c| (0..=20).map(move |i| c.eval(i as f64 / 20.0)))
            .map(|p| (p.to_vec2().hypot() - 100.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "{worst}, {} pieces", b.len());
        // Unweighted, the same points are a parabola, converted exactly in one piece.
        let parabola = Nurbs {
            degree: 2,
            ctrl: &c,
            weights: &[],
            knots: &k,
        }
        .to_cubics(1e-3)
        .unwrap();
        assert_eq!(parabola.len(), 1);
        assert!(parabola[0].eval(0.5).distance(Point::new(75.0, 75.0)) < 1e-12);
    }

    #[test]
    fn bad_knots_and_weights_are_refused() {
        let c = pts(&[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)]);
        let n = |w: &[f64], k: &[f64]| {
            Nurbs {
                degree: 2,
                ctrl: &c,
                weights: w,
                knots: k,
            }
            .to_cubics(1e-3)
            .unwrap_err()
        };
        assert!(n(&[], &[0.0, 0.0, 1.0, 1.0]).contains("4 knots"));
        assert!(n(&[], &[0.0, 0.0, 0.0, 1.0, 0.5, 1.0]).contains("decrease"));
        assert!(n(&[1.0, 0.0, 1.0], &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).contains("weights"));
    }

    #[test]
    fn fit_points_are_passed_through_with_natural_ends() {
        let p = pts(&[(0.0, 0.0), (10.0, 5.0), (20.0, 0.0), (30.0, 5.0)]);
        let b = through_fit_points(&p, None);
        assert_eq!(b.len(), 3);
        for (i, c) in b.iter().enumerate() {
            assert_eq!((c.p0, c.p3), (p[i], p[i + 1]));
        }
        // C¹ at the inner points: the handles are collinear.
        let d0 = b[0].p3 - b[0].p2;
        let d1 = b[1].p1 - b[1].p0;
        assert!(d0.cross(d1).abs() < 1e-9 * d0.hypot() * d1.hypot());
        // Given end tangents are followed.
        let t = through_fit_points(&p, Some((Vec2::new(0.0, 1.0), Vec2::new(1.0, 0.0))));
        assert!((t[0].p1 - t[0].p0).x.abs() < 1e-12);
        assert!((t[2].p3 - t[2].p2).y.abs() < 1e-12);
    }
}
