//! Hanging polargraph: two motors at (0, 0) and (W, 0) wind cords to a pen hanging below.
//!
//! Inverse: each cord is the distance from its motor, L = |P|, R = |P − (W, 0)|. Forward:
//! subtracting the two circles' equations, L² − R² = 2Wx − W², gives x; y is the root of
//! L² − x² below the motors.
//!
//! Settings: `[kinematics] type = "polargraph"`, `motor_distance = W` (mm, required, > 0),
//! `min_drop` (mm below the motors the pen must hang for gravity to keep both cords taut,
//! default 10). Joints are `left`, `right` and Z.

use super::{Check, Kinematics, KinematicsKind, RawKinematics};

/// Hanging polargraph: cords from motors at (0, 0) and (W, 0) to a pen hanging below.
pub struct Polargraph {
    pub w: f64,
    pub min_drop: f64,
}

impl Polargraph {
    /// The profile's `[joints.*]` names, in joint order.
    pub(crate) const JOINTS: [&'static str; 3] = ["left", "right", "z"];

    /// Reads `[kinematics]` for `type = "polargraph"`.
    pub(crate) fn settings<C: Check>(
        raw: &RawKinematics,
        c: &C,
    ) -> Result<KinematicsKind, C::Error> {
        let w = raw.motor_distance.ok_or_else(|| {
            c.error(
                "kinematics.motor_distance",
                "required for type = \"polargraph\"".into(),
            )
        })?;
        Ok(KinematicsKind::Polargraph {
            motor_distance: c.positive("kinematics.motor_distance", w)?,
            min_drop: c.positive("kinematics.min_drop", raw.min_drop.unwrap_or(10.0))?,
        })
    }
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

#[cfg(test)]
mod tests {
    use super::super::tests::round_trip;
    use super::*;

    #[test]
    fn polargraph_round_trips_and_refuses_slack_cords() {
        let pg = Polargraph {
            w: 1000.0,
            min_drop: 10.0,
        };
        round_trip(&pg, [300.0, -400.0, 0.0]);
        assert!(pg.joints([300.0, 5.0, 0.0]).is_err());
        assert!(pg.joints([1200.0, -50.0, 0.0]).is_err());
    }
}
