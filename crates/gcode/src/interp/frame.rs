//! The chain from program coordinates to machine coordinates, in LinuxCNC's order:
//! add the G92/G52 offset, rotate the XY plane (G10 L2 R), add the work offset (G54…),
//! add the tool length offset. The printer runs the same chain backwards.

/// All offsets in mm (A B C in degrees); `rotation` in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Frame {
    pub g5x: [f64; 6],
    pub g92: [f64; 6],
    pub rotation: f64,
    pub tool: [f64; 6],
}

impl Frame {
    pub fn to_machine(self, p: [f64; 6]) -> [f64; 6] {
        let mut q = [0.0; 6];
        for i in 0..6 {
            q[i] = p[i] + self.g92[i];
        }
        if self.rotation != 0.0 {
            let (s, c) = self.rotation.to_radians().sin_cos();
            let (x, y) = (q[0], q[1]);
            q[0] = x * c - y * s;
            q[1] = x * s + y * c;
        }
        for i in 0..6 {
            q[i] += self.g5x[i] + self.tool[i];
        }
        q
    }

    pub fn to_program(self, m: [f64; 6]) -> [f64; 6] {
        let mut q = [0.0; 6];
        for i in 0..6 {
            q[i] = m[i] - self.g5x[i] - self.tool[i];
        }
        if self.rotation != 0.0 {
            let (s, c) = self.rotation.to_radians().sin_cos();
            let (x, y) = (q[0], q[1]);
            q[0] = x * c + y * s;
            q[1] = -x * s + y * c;
        }
        for i in 0..6 {
            q[i] -= self.g92[i];
        }
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chain_inverts_and_matches_a_hand_computation() {
        let f = Frame {
            g5x: [25.4, 10.0, 0.0, 0.0, 0.0, 0.0],
            g92: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            rotation: 90.0,
            tool: [0.0, 0.0, 5.0, 0.0, 0.0, 0.0],
        };
        // (2,3,4) + g92 → (3,3,4); rotated 90° → (-3,3,4); + g5x + tool → (22.4, 13, 9).
        let m = f.to_machine([2.0, 3.0, 4.0, 0.0, 0.0, 0.0]);
        assert!((m[0] - 22.4).abs() < 1e-12 && (m[1] - 13.0).abs() < 1e-12 && m[2] == 9.0);
        let p = f.to_program(m);
        assert!((p[0] - 2.0).abs() < 1e-12 && (p[1] - 3.0).abs() < 1e-12 && p[2] == 4.0);
    }
}
