//! Exact drop-cutter of a tool of revolution onto one triangle (OpenCAMLib's
//! `vertexDrop` / `facetDrop` / `edgeDrop`, derived anew).
//!
//! The tool's lower surface is `z = tip + p(ρ)` for `ρ ≤ R`, with `p` convex and increasing
//! for every shape we have (flat, ball, bull, V, tapered ball). Dropped at XY `c`, the tip
//! rests at `max over triangle points q with |q − c| ≤ R of q.z − p(|q − c|)`. On the
//! triangle `q.z` is linear and `p(|q − c|)` convex, so the function is concave: its maximum
//! is either the unconstrained one on the facet's plane (facet contact), or on the
//! triangle's boundary, where each edge again gives a concave function of one parameter
//! (edge contact, with the vertices as the segment's ends).

use crate::{CutterShape, Tool};

/// The cutting end as drop-cutter needs it: radius and profile, mm.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shape {
    Flat {
        r: f64,
    },
    Ball {
        r: f64,
    },
    /// `rc`: corner radius.
    Bull {
        r: f64,
        rc: f64,
    },
    /// `cot`: 1 / tan(half angle), the flank's slope.
    Cone {
        r: f64,
        cot: f64,
    },
    /// Tip ball of radius `rb` up to `ρ_t = rb·cos a`, then the flank of slope `cot a` to `r`.
    Taper {
        r: f64,
        rb: f64,
        a: f64,
    },
}

impl Shape {
    pub(crate) fn of(tool: &Tool) -> Shape {
        let r = tool.radius();
        match tool.shape {
            CutterShape::Flat => Shape::Flat { r },
            CutterShape::Ball => Shape::Ball { r },
            CutterShape::Bull { corner_radius } => Shape::Bull {
                r,
                rc: corner_radius,
            },
            CutterShape::V { angle } => Shape::Cone {
                r,
                cot: 1.0 / (angle.to_radians() / 2.0).tan(),
            },
            CutterShape::Taper { angle } => Shape::Taper {
                r: tool.cutting_radius(),
                rb: r,
                a: angle.to_radians(),
            },
        }
    }

    /// The cutting radius R, mm.
    pub(crate) fn radius(&self) -> f64 {
        match *self {
            Shape::Flat { r }
            | Shape::Ball { r }
            | Shape::Bull { r, .. }
            | Shape::Cone { r, .. }
            | Shape::Taper { r, .. } => r,
        }
    }

    /// Height of the lower surface above the tip at radius `rho ≤ R`.
    pub(crate) fn profile(&self, rho: f64) -> f64 {
        let circle = |r: f64, u: f64| r - (r * r - u * u).max(0.0).sqrt();
        match *self {
            Shape::Flat { .. } => 0.0,
            Shape::Ball { r } => circle(r, rho),
            Shape::Bull { r, rc } => circle(rc, (rho - (r - rc)).max(0.0)),
            Shape::Cone { cot, .. } => rho * cot,
            Shape::Taper { rb, a, .. } => {
                let rho_t = rb * a.cos();
                if rho <= rho_t {
                    circle(rb, rho)
                } else {
                    rb - rb * a.sin() + (rho - rho_t) / a.tan()
                }
            }
        }
    }

    /// Facet contact radius on a plane whose unit normal has horizontal part `h` and
    /// vertical part `nz`: where the profile's slope equals the plane's, `s = h/nz`
    /// (maximising `s·ρ − p(ρ)` over `[0, R]`).
    fn facet_rho(&self, h: f64, nz: f64) -> f64 {
        if h <= 0.0 {
            return 0.0;
        }
        match *self {
            // Slope 0 everywhere: the rim, downhill-most.
            Shape::Flat { r } => r,
            // Sphere: the contact is r·n from the centre, so ρ = r·h.
            Shape::Ball { r } => r * h,
            // Torus: the corner circle's centre is at R − rc; its contact rc·h further out.
            Shape::Bull { r, rc } => r - rc + rc * h,
            // Constant slope: the tip when the plane is less steep, else the rim.
            Shape::Cone { r, cot } => {
                if h / nz > cot {
                    r
                } else {
                    0.0
                }
            }
            // The ball's contact while on the ball part, else the flank's slope cot a is
            // below the plane's and the rim touches.
            Shape::Taper { r, rb, a } => {
                if rb * h <= rb * a.cos() {
                    rb * h
                } else {
                    r
                }
            }
        }
    }
}

/// A triangle with what drop-cutter reuses: the unit normal pointing up and the XY box.
#[derive(Clone, Debug)]
pub(crate) struct Tri {
    pub(crate) p: [[f64; 3]; 3],
    /// Unit normal with `n.z ≥ 0` (zero vector for a degenerate triangle).
    n: [f64; 3],
    /// min x, min y, max x, max y.
    pub(crate) bb: [f64; 4],
    pub(crate) zmax: f64,
}

impl Tri {
    pub(crate) fn new(p: [[f64; 3]; 3]) -> Tri {
        let u = sub(p[1], p[0]);
        let v = sub(p[2], p[0]);
        let mut n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len > 0.0 {
            let s = if n[2] < 0.0 { -1.0 / len } else { 1.0 / len };
            n = [n[0] * s, n[1] * s, n[2] * s];
        } else {
            n = [0.0; 3];
        }
        let bb = [
            p[0][0].min(p[1][0]).min(p[2][0]),
            p[0][1].min(p[1][1]).min(p[2][1]),
            p[0][0].max(p[1][0]).max(p[2][0]),
            p[0][1].max(p[1][1]).max(p[2][1]),
        ];
        Tri {
            p,
            n,
            bb,
            zmax: p[0][2].max(p[1][2]).max(p[2][2]),
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Tip height at which the tool dropped at `c` touches `t`, if it is above `best` (else
/// `best`). `f64::NEG_INFINITY` when the triangle is out of reach.
pub(crate) fn drop_on(shape: &Shape, c: [f64; 2], t: &Tri, best: f64) -> f64 {
    let r = shape.radius();
    // The tip never rises above the triangle's highest corner (p ≥ 0).
    if t.zmax <= best
        || c[0] < t.bb[0] - r
        || c[0] > t.bb[2] + r
        || c[1] < t.bb[1] - r
        || c[1] > t.bb[3] + r
    {
        return best;
    }
    let mut z = best;
    // Vertex contact: the corner at ρ from the axis touches at p(ρ) above the tip.
    for q in &t.p {
        let rho = (q[0] - c[0]).hypot(q[1] - c[1]);
        if rho <= r {
            z = z.max(q[2] - shape.profile(rho));
        }
    }
    z = z.max(facet(shape, c, t));
    for k in 0..3 {
        z = z.max(edge(shape, c, t.p[k], t.p[(k + 1) % 3]));
    }
    z
}

/// Facet contact: on the plane `z = q.z − (nx(x − qx) + ny(y − qy))/nz`, which rises
/// fastest along `−(nx, ny)`, the tool touches at `ρ*` that way from the axis.
fn facet(shape: &Shape, c: [f64; 2], t: &Tri) -> f64 {
    let [nx, ny, nz] = t.n;
    if nz < 1e-12 {
        return f64::NEG_INFINITY; // vertical or degenerate: the edges decide
    }
    let h = nx.hypot(ny);
    let rho = shape.facet_rho(h, nz);
    let q = if h > 0.0 {
        [c[0] - nx / h * rho, c[1] - ny / h * rho]
    } else {
        c
    };
    if !inside(&t.p, q) {
        return f64::NEG_INFINITY;
    }
    let a = t.p[0];
    let plane = a[2] - (nx * (q[0] - a[0]) + ny * (q[1] - a[1])) / nz;
    plane - shape.profile(rho)
}

/// `q` inside the triangle's XY projection (edges included, to 1e-12 relative).
fn inside(p: &[[f64; 3]; 3], q: [f64; 2]) -> bool {
    let cross =
        |a: [f64; 3], b: [f64; 3]| (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
    let d = [cross(p[0], p[1]), cross(p[1], p[2]), cross(p[2], p[0])];
    let scale = 1e-12 * (1.0 + d.iter().map(|v| v.abs()).fold(0.0, f64::max));
    (d.iter().all(|&v| v >= -scale)) || (d.iter().all(|&v| v <= scale))
}

/// Edge contact on segment `a → b`: the best `q(t).z − p(|q(t) − c|)` over the `t` whose
/// point lies within R of the axis in XY.
fn edge(shape: &Shape, c: [f64; 2], a: [f64; 3], b: [f64; 3]) -> f64 {
    let r = shape.radius();
    let d = sub(b, a);
    let (ex, ey) = (a[0] - c[0], a[1] - c[1]);
    // |e + t·d_xy|² = R²: A t² + 2 B t + C = 0.
    let qa = d[0] * d[0] + d[1] * d[1];
    if qa < 1e-24 {
        return f64::NEG_INFINITY; // vertical edge: its top vertex decides
    }
    let qb = ex * d[0] + ey * d[1];
    let qc = ex * ex + ey * ey - r * r;
    let disc = qb * qb - qa * qc;
    if disc < 0.0 {
        return f64::NEG_INFINITY;
    }
    let s = disc.sqrt();
    let t0 = ((-qb - s) / qa).max(0.0);
    let t1 = ((-qb + s) / qa).min(1.0);
    if t0 > t1 {
        return f64::NEG_INFINITY;
    }
    let at = |t: f64| {
        let rho = (ex + t * d[0]).hypot(ey + t * d[1]).min(r);
        a[2] + t * d[2] - shape.profile(rho)
    };
    match *shape {
        // Linear along the edge: one of the ends, where the rim crosses it.
        Shape::Flat { .. } => at(t0).max(at(t1)),
        Shape::Ball { r } => ball_edge(r, c, a, d, t0, t1).max(at(t0)).max(at(t1)),
        _ => golden_max(&at, t0, t1),
    }
}

/// Ball on an infinite line `a + t·d`: the centre `(c, zc)` at distance r from it.
/// With `w = (c − a_xy, zc − a_z)` and unit `u = d/|d|`: `|w|² − (w·u)² = r²`, a quadratic
/// in `zc` (upper root); valid when the foot `t = w·u/|d|` lies on `[t0, t1]`.
fn ball_edge(r: f64, c: [f64; 2], a: [f64; 3], d: [f64; 3], t0: f64, t1: f64) -> f64 {
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let u = [d[0] / len, d[1] / len, d[2] / len];
    let w0 = [c[0] - a[0], c[1] - a[1], -a[2]];
    let wu = w0[0] * u[0] + w0[1] * u[1] + w0[2] * u[2];
    let w2 = w0[0] * w0[0] + w0[1] * w0[1] + w0[2] * w0[2];
    // zc²(1 − uz²) + 2 zc (w0z − (w0·u) uz) + |w0|² − (w0·u)² − r² = 0.
    let qa = 1.0 - u[2] * u[2];
    let qb = w0[2] - wu * u[2];
    let qc = w2 - wu * wu - r * r;
    let disc = qb * qb - qa * qc;
    if qa < 1e-12 || disc < 0.0 {
        return f64::NEG_INFINITY;
    }
    let zc = (-qb + disc.sqrt()) / qa;
    let t = (wu + zc * u[2]) / len;
    if t < t0 || t > t1 {
        return f64::NEG_INFINITY;
    }
    zc - r
}

/// Maximum of a concave function on `[lo, hi]` by golden-section search (to ~1e-13 of the
/// interval), ends included.
fn golden_max(f: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let ends = f(lo).max(f(hi));
    let g = 0.618_033_988_749_894_9;
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..64 {
        if hi - lo < 1e-12 {
            break;
        }
        if f1 < f2 {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        }
    }
    ends.max(f1).max(f2)
}

#[cfg(test)]
mod tests {
    use super::*;

    // A horizontal triangle at z = 1: every tool's tip rests on it when the axis is over it.
    #[test]
    fn flat_facet_holds_every_tool_at_its_height() {
        let t = Tri::new([[0.0, 0.0, 1.0], [10.0, 0.0, 1.0], [0.0, 10.0, 1.0]]);
        for shape in [
            Shape::Flat { r: 1.0 },
            Shape::Ball { r: 1.0 },
            Shape::Bull { r: 1.0, rc: 0.3 },
            Shape::Cone { r: 1.0, cot: 1.0 },
        ] {
            assert!((drop_on(&shape, [2.0, 2.0], &t, f64::NEG_INFINITY) - 1.0).abs() < 1e-12);
        }
    }

    // A ball beside a horizontal edge at distance d touches it at z = 1 − (r − √(r² − d²)).
    #[test]
    fn ball_on_an_edge() {
        let t = Tri::new([[0.0, 0.0, 1.0], [10.0, 0.0, 1.0], [0.0, -10.0, 1.0]]);
        let z = drop_on(&Shape::Ball { r: 2.0 }, [5.0, 1.0], &t, f64::NEG_INFINITY);
        assert!((z - (1.0 - (2.0 - 3f64.sqrt()))).abs() < 1e-12, "{z}");
        let z = drop_on(
            &Shape::Bull { r: 2.0, rc: 2.0 },
            [5.0, 1.0],
            &t,
            f64::NEG_INFINITY,
        );
        assert!((z - (1.0 - (2.0 - 3f64.sqrt()))).abs() < 1e-9, "{z}");
    }
}
