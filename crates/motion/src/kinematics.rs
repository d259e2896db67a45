//! Cartesian ↔ joint maps behind one trait. Joint 2 is always Z and maps straight through;
//! the machines differ in how the first two joints move the XY point.

use crate::profile::{KinematicsKind, Profile};
use std::f64::consts::{PI, TAU};

pub trait Kinematics {
    /// Inverse kinematics; `Err` says why the point cannot be reached.
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String>;
    /// Forward kinematics.
    fn forward(&self, q: [f64; 3]) -> [f64; 3];
    /// True when joints are a linear function of Cartesian position (straight lines stay
    /// straight in joint space, so no extra segmentation is needed).
    fn is_linear(&self) -> bool;
    /// Inverse kinematics choosing, for periodic joints, the value nearest `near` (unwrap).
    fn joints_near(&self, p: [f64; 3], _near: [f64; 3]) -> Result<[f64; 3], String> {
        self.joints(p)
    }
    /// Checks that the whole straight move a → b stays reachable.
    fn check_line(&self, a: [f64; 3], b: [f64; 3]) -> Result<(), String> {
        self.joints(a)?;
        self.joints(b).map(|_| ())
    }
}

/// X, Y and Z each driven by its own motor.
pub struct Cartesian;

impl Kinematics for Cartesian {
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String> {
        Ok(p)
    }
    fn forward(&self, q: [f64; 3]) -> [f64; 3] {
        q
    }
    fn is_linear(&self) -> bool {
        true
    }
}

/// Two motors share one belt: A = X + Y, B = X − Y.
pub struct CoreXy;

impl Kinematics for CoreXy {
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String> {
        Ok([p[0] + p[1], p[0] - p[1], p[2]])
    }
    fn forward(&self, q: [f64; 3]) -> [f64; 3] {
        [(q[0] + q[1]) * 0.5, (q[0] - q[1]) * 0.5, q[2]]
    }
    fn is_linear(&self) -> bool {
        true
    }
}

/// Seed 003: arm angle θ about the origin, carriage at R along the arm, pen offset `h` to the
/// counter-clockwise side of the arm. Forward: x = R cosθ − h sinθ, y = R sinθ + h cosθ.
pub struct Polar {
    pub h: f64,
}

impl Polar {
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

/// Hanging polargraph: cords from motors at (0, 0) and (W, 0) to a pen hanging below.
pub struct Polargraph {
    pub w: f64,
    pub min_drop: f64,
}

impl Kinematics for Polargraph {
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String> {
        let (x, y) = (p[0], p[1]);
        // Gravity keeps both cords taut only below and between the motors.
        if !(x > 0.0 && x < self.w && y <= -self.min_drop) {
            return Err(format!(
                "the pen must hang between the motors (0 < x < {}) and at least {} mm below them",
                self.w, self.min_drop
            ));
        }
        Ok([x.hypot(y), (self.w - x).hypot(y), p[2]])
    }
    fn forward(&self, q: [f64; 3]) -> [f64; 3] {
        let x = (q[0] * q[0] - q[1] * q[1] + self.w * self.w) / (2.0 * self.w);
        [x, -(q[0] * q[0] - x * x).max(0.0).sqrt(), q[2]]
    }
    fn is_linear(&self) -> bool {
        false
    }
}

/// The kinematics of a profile, dispatched without a heap allocation.
pub enum AnyKinematics {
    Cartesian(Cartesian),
    CoreXy(CoreXy),
    Polar(Polar),
    Polargraph(Polargraph),
}

pub fn for_profile(profile: &Profile) -> AnyKinematics {
    from_kind(profile.kinematics)
}

pub fn from_kind(kind: KinematicsKind) -> AnyKinematics {
    match kind {
        KinematicsKind::Cartesian => AnyKinematics::Cartesian(Cartesian),
        KinematicsKind::CoreXy => AnyKinematics::CoreXy(CoreXy),
        KinematicsKind::Polar { pen_offset } => AnyKinematics::Polar(Polar { h: pen_offset }),
        KinematicsKind::Polargraph {
            motor_distance,
            min_drop,
        } => AnyKinematics::Polargraph(Polargraph {
            w: motor_distance,
            min_drop,
        }),
    }
}

macro_rules! dispatch {
    ($self:ident, $k:ident => $e:expr) => {
        match $self {
            AnyKinematics::Cartesian($k) => $e,
            AnyKinematics::CoreXy($k) => $e,
            AnyKinematics::Polar($k) => $e,
            AnyKinematics::Polargraph($k) => $e,
        }
    };
}

impl Kinematics for AnyKinematics {
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String> {
        dispatch!(self, k => k.joints(p))
    }
    fn forward(&self, q: [f64; 3]) -> [f64; 3] {
        dispatch!(self, k => k.forward(q))
    }
    fn is_linear(&self) -> bool {
        dispatch!(self, k => k.is_linear())
    }
    fn joints_near(&self, p: [f64; 3], near: [f64; 3]) -> Result<[f64; 3], String> {
        dispatch!(self, k => k.joints_near(p, near))
    }
    fn check_line(&self, a: [f64; 3], b: [f64; 3]) -> Result<(), String> {
        dispatch!(self, k => k.check_line(a, b))
    }
}

/// Wraps an angle difference into (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    a - ((a + PI) / TAU).floor() * TAU
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(k: &dyn Kinematics, p: [f64; 3]) {
        let q = k.joints(p).unwrap();
        let b = k.forward(q);
        for i in 0..3 {
            assert!((b[i] - p[i]).abs() < 1e-9, "{p:?} → {q:?} → {b:?}");
        }
    }

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

    #[test]
    fn corexy_and_polargraph_round_trip() {
        round_trip(&CoreXy, [12.0, -7.0, 1.0]);
        let pg = Polargraph {
            w: 1000.0,
            min_drop: 10.0,
        };
        round_trip(&pg, [300.0, -400.0, 0.0]);
        assert!(pg.joints([300.0, 5.0, 0.0]).is_err());
        assert!(pg.joints([1200.0, -50.0, 0.0]).is_err());
    }
}
