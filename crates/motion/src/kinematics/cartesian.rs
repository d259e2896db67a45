//! Cartesian: X, Y and Z each driven by its own motor. No settings of its own.

use super::Kinematics;

/// X, Y and Z each driven by its own motor.
pub struct Cartesian;

impl Cartesian {
    /// The profile's `[joints.*]` names, in joint order.
    pub(crate) const JOINTS: [&'static str; 3] = ["x", "y", "z"];
}

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
