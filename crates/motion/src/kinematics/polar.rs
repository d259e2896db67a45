//! Seed 003's polar plotter: an arm turning about the origin O, a carriage running along it,
//! and a pen set off the arm's line by `h` (the "eccentric pen").
//!
//! Forward. With the arm at angle θ, its unit vector is a = (cosθ, sinθ) and its
//! counter-clockwise normal n = (−sinθ, cosθ). The carriage sits at R·a and the pen h further
//! along n, so P = R·a + h·n:
//!
//! ```text
//! x = R cosθ − h sinθ
//! y = R sinθ + h cosθ
//! ```
//!
//! Inverse, R. a ⊥ n, so |P|² = R² + h² (seed eq. 1–2) and R = √(x² + y² − h²) (eq. 3),
//! taking the carriage on the pen's side of the pivot (R ≥ 0). No real R exists inside the
//! circle x² + y² < h²: those points are unreachable, and so is any straight move crossing it.
//!
//! Inverse, θ. Multiply the forward pair by R and by h and combine them so the cross terms
//! cancel:
//!
//! ```text
//! x·R + y·h = (R² + h²) cosθ
//! y·R − x·h = (R² + h²) sinθ
//! ```
//!
//! R² + h² = x² + y² > 0, so θ = atan2(yR − xh, xR + yh) with the right quadrant; the ratio is
//! the seed's eq. 9, tan θ = (yR − xh)/(xR + yh), reached there as θ = α − φ with tan α = y/x
//! and tan φ = h/R.
//!
//! Settings: `[kinematics] type = "polar"`, `pen_offset = h` (mm, required, ≥ 0). Joints are
//! θ (degrees in the file, radians inside), R and Z.

use super::{Check, Kinematics, KinematicsKind, RawKinematics};
use std::f64::consts::TAU;

/// Arm angle θ about the origin, carriage at R along the arm, pen offset `h` to the
/// counter-clockwise side of the arm. Forward: x = R cosθ − h sinθ, y = R sinθ + h cosθ.
pub struct Polar {
    pub h: f64,
}

impl Polar {
    /// The profile's `[joints.*]` names, in joint order.
    pub(crate) const JOINTS: [&'static str; 3] = ["theta", "r", "z"];

    /// Reads `[kinematics]` for `type = "polar"`.
    pub(crate) fn settings<C: Check>(
        raw: &RawKinematics,
        c: &C,
    ) -> Result<KinematicsKind, C::Error> {
        let h = raw.pen_offset.ok_or_else(|| {
            c.error(
                "kinematics.pen_offset",
                "required for type = \"polar\" (mm)".into(),
            )
        })?;
        Ok(KinematicsKind::Polar {
            pen_offset: c.non_negative("kinematics.pen_offset", h)?,
        })
    }

    fn unreachable(&self, p: [f64; 3]) -> String {
        format!(
            "it lies {:.4} mm from the arm pivot, inside the pen offset radius h = {} mm",
            p[0].hypot(p[1]),
            self.h
        )
    }
}

impl Kinematics for Polar {
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String> {
        let (x, y) = (p[0], p[1]);
        let r2 = x * x + y * y - self.h * self.h;
        // At the pivot itself θ is undefined even with h = 0.
        if r2 < 0.0 || x * x + y * y < 1e-18 {
            return Err(self.unreachable(p));
        }
        let r = r2.sqrt();
        // Eq. 9 of the seed, tan θ = (yR − xh)/(xR + yh), with atan2 for the quadrant.
        let theta = (y * r - x * self.h).atan2(x * r + y * self.h);
        Ok([theta, r, p[2]])
    }
    fn forward(&self, q: [f64; 3]) -> [f64; 3] {
        let (s, c) = q[0].sin_cos();
        [q[1] * c - self.h * s, q[1] * s + self.h * c, q[2]]
    }
    fn is_linear(&self) -> bool {
        false
    }
    fn joints_near(&self, p: [f64; 3], near: [f64; 3]) -> Result<[f64; 3], String> {
        let mut q = self.joints(p)?;
        // The arm turns freely: pick the turn nearest the previous angle.
        q[0] += ((near[0] - q[0]) / TAU).round() * TAU;
        Ok(q)
    }
    fn check_line(&self, a: [f64; 3], b: [f64; 3]) -> Result<(), String> {
        // The point of the line nearest the pivot is the one most likely inside the h circle.
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (-(a[0] * dx + a[1] * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c = [a[0] + t * dx, a[1] + t * dy, a[2]];
        self.joints(c).map_err(|_| {
            format!(
                "the straight move passes {:.4} mm from the arm pivot at ({:.4}, {:.4}), \
                 inside the pen offset radius h = {} mm",
                c[0].hypot(c[1]),
                c[0],
                c[1],
                self.h
            )
        })?;
        self.joints(a)?;
        self.joints(b).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::round_trip;
    use super::*;

    #[test]
    fn polar_round_trips_in_every_quadrant() {
        let k = Polar { h: 25.0 };
        for &(x, y) in &[
            (100.0, 50.0),
            (-100.0, 50.0),
            (-30.0, -200.0),
            (40.0, -10.0),
            (0.0, 25.0),
        ] {
            round_trip(&k, [x, y, 3.0]);
        }
    }

    #[test]
    fn polar_matches_eq3_and_eq9() {
        // Independent: R from eq. 3, tan θ from eq. 9 evaluated directly.
        let (h, x, y) = (20.0_f64, 120.0_f64, 70.0_f64);
        let q = Polar { h }.joints([x, y, 0.0]).unwrap();
        let r = (x * x + y * y - h * h).sqrt();
        assert!((q[1] - r).abs() < 1e-12);
        assert!((q[0].tan() - (y * r - x * h) / (x * r + y * h)).abs() < 1e-12);
    }

    #[test]
    fn polar_rejects_points_inside_offset_and_lines_through_it() {
        let k = Polar { h: 25.0 };
        assert!(k.joints([10.0, 10.0, 0.0]).is_err());
        let e = k
            .check_line([-100.0, 5.0, 0.0], [100.0, 5.0, 0.0])
            .unwrap_err();
        assert!(e.contains("pivot"), "{e}");
        assert!(k
            .check_line([-100.0, 30.0, 0.0], [100.0, 30.0, 0.0])
            .is_ok());
    }

    #[test]
    fn polar_unwraps_the_arm_angle() {
        let k = Polar { h: 0.0 };
        let a = k.joints_near([-100.0, 0.1, 0.0], [3.1, 0.0, 0.0]).unwrap();
        let b = k.joints_near([-100.0, -0.1, 0.0], a).unwrap();
        assert!((b[0] - a[0]).abs() < 0.01, "{a:?} {b:?}");
    }
}
