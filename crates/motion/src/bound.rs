//! The least time a move can take on a machine: each joint must cover at least the difference
//! of its end values at no more than its top speed, whatever path the planner takes between
//! them. On a Cartesian machine that is the familiar "slowest axis" rapid time; on a polar or
//! polargraph machine it is computed in joint space, where the limits are.

use crate::kinematics::{for_profile, AnyKinematics, Kinematics};
use crate::Profile;
use oficina_canon::MoveBound;
use std::f64::consts::TAU;

/// The least time of a move from the joints' top speeds (see the module comment).
pub struct JointBound {
    kinematics: AnyKinematics,
    /// Top speed of each joint, its units per second (`None`: the joint does not exist).
    rates: [Option<f64>; 3],
    /// Joints that turn freely (angles): the shorter way round is the bound.
    periodic: [bool; 3],
}

impl JointBound {
    /// The bound for `profile`'s kinematics and joint rates.
    pub fn new(profile: &Profile) -> JointBound {
        JointBound {
            kinematics: for_profile(profile),
            rates: profile
                .joints
                .map(|j| j.map(|j| j.max_rate).filter(|r| *r > 0.0)),
            periodic: [0, 1, 2].map(|i| profile.kinematics.is_angular(i)),
        }
    }
}

impl MoveBound for JointBound {
    /// 0 when an end cannot be reached: the planner refuses that move anyway.
    fn min_seconds(&self, from: [f64; 3], to: [f64; 3]) -> f64 {
        let (Ok(a), Ok(b)) = (self.kinematics.joints(from), self.kinematics.joints(to)) else {
            return 0.0;
        };
        (0..3)
            .filter_map(|i| {
                let rate = self.rates[i]?;
                let mut d = (b[i] - a[i]).abs();
                if self.periodic[i] {
                    d %= TAU;
                    d = d.min(TAU - d);
                }
                Some(d / rate)
            })
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_arm_goes_the_short_way_round() {
        let text = include_str!("../../../profiles/polar-plotter.toml");
        let p = Profile::parse(text, "polar").unwrap();
        let b = JointBound::new(&p);
        // 900 °/min = 15 °/s: a half turn of the arm takes 12 s at the least.
        let t = b.min_seconds([600.0, 0.0, 0.0], [-600.0, 0.0, 0.0]);
        assert!((t - 12.0).abs() < 0.5, "{t}");
        // Across the ±180° seam: a few degrees, not a whole turn.
        let t = b.min_seconds([-600.0, 1.0, 0.0], [-600.0, -1.0, 0.0]);
        assert!(t < 1.0, "{t}");
        assert_eq!(b.min_seconds([0.0, 0.0, 0.0], [600.0, 0.0, 0.0]), 0.0);
    }
}
