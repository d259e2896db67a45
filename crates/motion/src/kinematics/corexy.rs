//! CoreXY: two motors share one belt. No settings of its own.

use super::Kinematics;

/// Two motors share one belt: A = X + Y, B = X − Y.
pub struct CoreXy;

impl CoreXy {
    /// The profile's `[joints.*]` names, in joint order.
    pub(crate) const JOINTS: [&'static str; 3] = ["a", "b", "z"];
}

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

#[cfg(test)]
mod tests {
    use super::super::tests::round_trip;
    use super::*;

    #[test]
    fn corexy_round_trips() {
        round_trip(&CoreXy, [12.0, -7.0, 1.0]);
    }
}
