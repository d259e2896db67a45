//! Alteration and linking of programs (the seed's ALTER and LINKA, §4.4 and §4.7).
//!
//! ALTER could only shift the Zero-Peça; rotation, mirroring and scaling were in its menu but
//! left to CADTEC. Here all four apply to a plan, in the order scale, rotate, mirror, shift,
//! about the plan's origin (its Zero-Peça). Scaling a stitch plan scales its stitches too
//! (density changes); when the design is at hand the caller scales the design instead and
//! regenerates ([`Alteration::affine`] gives the same transform for a drawing).
//!
//! LINKA joins programs: the first is copied whole, then the move from its last point to the
//! start (Zero-Peça) of the next is one stitch point — a long point (jump) when longer than
//! the sewable 12.4 mm — and the next program follows, and so on.

use crate::plan::{ColorBlock, Kind, Stitch, StitchPlan};
use crate::speed::MAX_SEWN;

/// A mirror axis: `X` flips Y (mirror about the X axis), `Y` flips X.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MirrorAxis {
    /// About the X axis (y → −y).
    X,
    /// About the Y axis (x → −x).
    Y,
}

/// What to do to a plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Alteration {
    /// Zero-Peça shift, mm.
    pub shift: [f64; 2],
    /// Counter-clockwise rotation, degrees.
    pub rotate_deg: f64,
    /// Mirror axis, if any.
    pub mirror: Option<MirrorAxis>,
    /// Scale factor (> 0).
    pub scale: f64,
}

impl Default for Alteration {
    fn default() -> Alteration {
        Alteration {
            shift: [0.0, 0.0],
            rotate_deg: 0.0,
            mirror: None,
            scale: 1.0,
        }
    }
}

impl Alteration {
    /// Nothing changes.
    pub fn is_identity(&self) -> bool {
        *self == Alteration::default()
    }

    /// The scale, rotation and mirror as a 2×2 matrix `[a, b, c, d]`: x' = a x + c y,
    /// y' = b x + d y (kurbo's column order, so `Affine::new([a, b, c, d, sx, sy])`).
    pub fn linear(&self) -> [f64; 4] {
        let (s, c) = self.rotate_deg.to_radians().sin_cos();
        let k = self.scale;
        // Rotation then mirror: the mirror flips the rows of R·k.
        let (mut a, mut b, mut cc, mut d) = (k * c, k * s, -k * s, k * c);
        match self.mirror {
            Some(MirrorAxis::X) => {
                b = -b;
                d = -d;
            }
            Some(MirrorAxis::Y) => {
                a = -a;
                cc = -cc;
            }
            None => {}
        }
        [a, b, cc, d]
    }

    /// The whole alteration as kurbo's affine coefficients `[a, b, c, d, e, f]`.
    pub fn affine(&self) -> [f64; 6] {
        let [a, b, c, d] = self.linear();
        [a, b, c, d, self.shift[0], self.shift[1]]
    }

    /// Checks the figures: finite, scale positive.
    pub fn check(&self) -> Result<(), String> {
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(format!("--scale {}: a factor above 0", self.scale));
        }
        if !self.rotate_deg.is_finite() || !self.shift.iter().all(|v| v.is_finite()) {
            return Err("--rotate and --shift take finite numbers".into());
        }
        Ok(())
    }
}

/// The plan altered: every point through [`Alteration::affine`].
pub fn alter(plan: &StitchPlan, a: &Alteration) -> StitchPlan {
    let [m0, m1, m2, m3, e, f] = a.affine();
    let mut p = plan.clone();
    for b in &mut p.blocks {
        for s in &mut b.stitches {
            let (x, y) = (s.x, s.y);
            s.x = m0 * x + m2 * y + e;
            s.y = m1 * x + m3 * y + f;
        }
    }
    p
}

/// LINKA: `programs` (each a plan with points from its own Zero-Peça, and that Zero-Peça
/// from Zero-Máquina, mm) joined in order. The result's points are from the first program's
/// Zero-Peça. Blocks of the same thread across a joint stay one block.
pub fn link(programs: &[(StitchPlan, [f64; 2])]) -> StitchPlan {
    let mut out = StitchPlan {
        name: programs
            .iter()
            .map(|(p, _)| p.name.as_str())
            .collect::<Vec<_>>()
            .join("+"),
        blocks: Vec::new(),
    };
    let Some((_, origin)) = programs.first() else {
        return out;
    };
    let mut last: Option<(f64, f64)> = None;
    for (plan, start) in programs {
        let (dx, dy) = (start[0] - origin[0], start[1] - origin[1]);
        let moved = plan.translated(dx, dy);
        let mut first_block = true;
        for block in moved.blocks {
            let mut stitches = Vec::with_capacity(block.stitches.len() + 1);
            if first_block {
                if let Some((lx, ly)) = last {
                    // The difference from the last point to this program's start: one point.
                    let d = (dx - lx).hypot(dy - ly);
                    if d > 1e-9 {
                        let kind = if d > MAX_SEWN {
                            Kind::Jump
                        } else {
                            Kind::Stitch
                        };
                        stitches.push(Stitch::new(dx, dy, kind));
                    }
                }
                first_block = false;
            }
            stitches.extend(block.stitches);
            match out.blocks.last_mut() {
                Some(b) if b.thread == block.thread => b.stitches.extend(stitches),
                _ => out.blocks.push(ColorBlock {
                    thread: block.thread,
                    stitches,
                }),
            }
        }
        if let Some(s) = out.blocks.last().and_then(|b| b.stitches.last()) {
            last = Some((s.x, s.y));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::Thread;

    fn square() -> StitchPlan {
        let s = |x, y| Stitch::new(x, y, Kind::Stitch);
        StitchPlan {
            name: "sq".into(),
            blocks: vec![ColorBlock {
                thread: Thread::rgb(0, 0, 0),
                stitches: vec![s(10.0, 0.0), s(10.0, 5.0), s(0.0, 5.0), s(0.0, 0.0)],
            }],
        }
    }

    fn pts(p: &StitchPlan) -> Vec<(f64, f64)> {
        p.entries()
            .map(|(_, s)| ((s.x * 1e6).round() / 1e6, (s.y * 1e6).round() / 1e6))
            .collect()
    }

    #[test]
    fn each_alteration_moves_points_as_computed_by_hand() {
        let sq = square();
        // The seed's EMC1: +30 X, −30 Y.
        let a = Alteration {
            shift: [30.0, -30.0],
            ..Alteration::default()
        };
        assert_eq!(pts(&alter(&sq, &a))[1], (40.0, -25.0));
        let r = Alteration {
            rotate_deg: 90.0,
            ..Alteration::default()
        };
        assert_eq!(pts(&alter(&sq, &r))[..2], [(0.0, 10.0), (-5.0, 10.0)]);
        let mx = Alteration {
            mirror: Some(MirrorAxis::X),
            ..Alteration::default()
        };
        assert_eq!(pts(&alter(&sq, &mx))[1], (10.0, -5.0));
        let my = Alteration {
            mirror: Some(MirrorAxis::Y),
            ..Alteration::default()
        };
        assert_eq!(pts(&alter(&sq, &my))[1], (-10.0, 5.0));
        // Rotate 90 then mirror about X: (10, 5) → (−5, 10) → (−5, −10).
        let both = Alteration {
            rotate_deg: 90.0,
            mirror: Some(MirrorAxis::X),
            scale: 2.0,
            shift: [1.0, 1.0],
        };
        assert_eq!(pts(&alter(&sq, &both))[1], (-9.0, -19.0));
        // Lengths scale with the factor: the perimeter 30 → 60.
        let len = |p: &StitchPlan| p.counts().per_block[0].1;
        let s2 = Alteration {
            scale: 2.0,
            ..Alteration::default()
        };
        assert!((len(&alter(&sq, &s2)) - 60.0).abs() < 1e-9);
        assert!(Alteration {
            scale: 0.0,
            ..Alteration::default()
        }
        .check()
        .is_err());
    }

    #[test]
    fn linking_joins_with_one_point_from_the_last_to_the_next_start() {
        let a = square();
        let mut b = square();
        b.blocks[0].thread = Thread::rgb(200, 0, 0);
        // b starts 50 mm right of a's Zero-Peça: a long point from (0, 0) to (50, 0).
        let l = link(&[
            (a.clone(), [0.0, 0.0]),
            (b.clone(), [50.0, 0.0]),
            (a.clone(), [55.0, 0.0]),
        ]);
        assert_eq!(l.blocks.len(), 3);
        let s = &l.blocks[1].stitches;
        assert_eq!(s.len(), 5);
        assert_eq!((s[0].x, s[0].y, s[0].kind), (50.0, 0.0, Kind::Jump));
        assert_eq!((s[1].x, s[1].y), (60.0, 0.0));
        // The third starts 5 mm from b's end (50, 0): a sewn stitch.
        let s = &l.blocks[2].stitches;
        assert_eq!((s[0].x, s[0].y, s[0].kind), (55.0, 0.0, Kind::Stitch));
        let c = l.counts();
        assert_eq!(c.stitches, 4 * 3 + 1);
        assert_eq!(c.jumps, 1);
        // Same thread across the joint: one block.
        let same = link(&[(a.clone(), [0.0, 0.0]), (a, [0.0, 0.0])]);
        assert_eq!(same.blocks.len(), 1);
        assert_eq!(same.blocks[0].stitches.len(), 8);
    }
}
