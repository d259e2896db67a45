//! Engagement of a flat end mill along a program, measured on its own stock model.
//!
//! The program's canonical moves (as the interpreter read the written G-code) are walked in
//! steps of half a cell over a height grid of the stock. At each step, before the tool's
//! disc is cut out, the leading half of its circle (directions within ±90° of the travel in
//! XY) is sampled half a cell outside the cutting radius, one sample per degree: a sample
//! meets material where the stock there stands more than `min_axial` above the tool tip.
//! The engagement is the sampled arc that meets material (a straight cut of radial depth a
//! on radius r gives acos(1 − a/r)). Moves that go down (ramps, helices, plunges) are the
//! entry: they cut but are not measured.
//!
//! This shares no code with the CAM's own material model: other grid, other sampling,
//! the moves as written and read back.

use crate::replay::arc_chords;
use oficina_canon::{from_arc_frame, to_arc_frame, Canon, CanonOp};

/// The stock: heights on a square grid; cells outside the region to clear hold no material.
#[derive(Clone, Debug)]
pub struct EngagementStock {
    ox: f64,
    oy: f64,
    px: f64,
    nx: usize,
    ny: usize,
    z: Vec<f32>,
}

impl EngagementStock {
    /// Material at height `top` inside `rings` (even–odd), none elsewhere, on cells of
    /// `px` mm covering the rings and `margin` mm around them. `None` when the grid would
    /// exceed `max_cells` or the input is degenerate.
    pub fn from_rings(
        rings: &[Vec<[f64; 2]>],
        top: f64,
        px: f64,
        margin: f64,
        max_cells: usize,
    ) -> Option<EngagementStock> {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in rings.iter().flatten() {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if !(px > 0.0 && lo[0].is_finite() && hi[0].is_finite() && margin >= 0.0) {
            return None;
        }
        let nxf = ((hi[0] - lo[0] + 2.0 * margin) / px).ceil() + 1.0;
        let nyf = ((hi[1] - lo[1] + 2.0 * margin) / px).ceil() + 1.0;
        if nxf * nyf > max_cells as f64 {
            return None;
        }
        let (nx, ny) = (nxf as usize, nyf as usize);
        let (ox, oy) = (lo[0] - margin, lo[1] - margin);
        let mut z = vec![f32::NEG_INFINITY; nx * ny];
        // Cell (i, j) is the square [ox + i·px, +px) × [oy + j·px, +px); its state is its
        // centre's.
        for j in 0..ny {
            let y = oy + (j as f64 + 0.5) * px;
            for i in 0..nx {
                let x = ox + (i as f64 + 0.5) * px;
                if inside(rings, x, y) {
                    z[j * nx + i] = top as f32;
                }
            }
        }
        Some(EngagementStock {
            ox,
            oy,
            px,
            nx,
            ny,
            z,
        })
    }

    fn cell(&self, x: f64, y: f64) -> Option<usize> {
        let i = ((x - self.ox) / self.px).floor();
        let j = ((y - self.oy) / self.px).floor();
        (i >= 0.0 && j >= 0.0 && (i as usize) < self.nx && (j as usize) < self.ny)
            .then(|| j as usize * self.nx + i as usize)
    }

    /// Area (mm²) of cells still standing above `z`.
    pub fn area_above(&self, z: f64) -> f64 {
        self.z.iter().filter(|&&h| f64::from(h) > z).count() as f64 * self.px * self.px
    }

    /// Side (mm) of the largest square of cells standing above `z` with their centres
    /// inside `within` (even–odd): the biggest leftover where the tool could reach.
    pub fn largest_leftover_within(&self, z: f64, within: &[Vec<[f64; 2]>]) -> f64 {
        let mut best = 0usize;
        let mut prev = vec![0usize; self.nx + 1];
        let mut row = vec![0usize; self.nx + 1];
        for j in 0..self.ny {
            let y = self.oy + (j as f64 + 0.5) * self.px;
            for i in 0..self.nx {
                let x = self.ox + (i as f64 + 0.5) * self.px;
                let left = f64::from(self.z[j * self.nx + i]) > z && inside(within, x, y);
                row[i + 1] = if left {
                    1 + prev[i].min(prev[i + 1]).min(row[i])
                } else {
                    0
                };
                best = best.max(row[i + 1]);
            }
            std::mem::swap(&mut prev, &mut row);
        }
        best as f64 * self.px
    }

    /// Cuts the disc down to `z`; whether any cell stood more than `tol` above it.
    fn cut_disc(&mut self, x: f64, y: f64, r: f64, z: f32, tol: f32) -> bool {
        let mut cut = false;
        let px = self.px;
        let j0 = ((y - r - self.oy) / px - 0.5).ceil().max(0.0) as usize;
        let j1 = ((y + r - self.oy) / px - 0.5).floor();
        if j1 < 0.0 {
            return false;
        }
        for j in j0..=(j1 as usize).min(self.ny.saturating_sub(1)) {
            let dy = self.oy + (j as f64 + 0.5) * px - y;
            let w = (r * r - dy * dy).max(0.0).sqrt();
            let i0 = ((x - w - self.ox) / px - 0.5).ceil().max(0.0) as usize;
            let i1 = ((x + w - self.ox) / px - 0.5).floor();
            if i1 < 0.0 {
                continue;
            }
            for i in i0..=(i1 as usize).min(self.nx.saturating_sub(1)) {
                let h = &mut self.z[j * self.nx + i];
                cut |= *h > z + tol;
                if *h > z {
                    *h = z;
                }
            }
        }
        cut
    }
}

/// Whether (x, y) is inside `rings`, even–odd.
fn inside(rings: &[Vec<[f64; 2]>], x: f64, y: f64) -> bool {
    let mut inside = false;
    for ring in rings {
        let n = ring.len();
        for k in 0..n {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            if (a[1] > y) != (b[1] > y) && x < a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                inside = !inside;
            }
        }
    }
    inside
}

/// What the walk found.
#[derive(Clone, Debug, PartialEq)]
pub struct Engagement {
    /// Largest engagement, degrees.
    pub peak: f64,
    /// Where it was: tool tip, and the program line.
    pub peak_at: ([f64; 3], u32),
    /// Length (mm) of the measured moves at each whole degree of engagement, 0..=180.
    pub histogram: Vec<f64>,
    /// Length of the entry moves (going down), not measured, mm.
    pub entry_length: f64,
    /// Length of rapid moves that cut material (more than 0.01 mm of it), mm.
    pub rapid_cutting: f64,
}

/// Material (mm) a rapid may graze: a grid's cell beside the cleared path.
const RAPID_TOL: f32 = 0.01;

impl Engagement {
    /// Length of measured moves that met material (≥ 1°), mm.
    pub fn cutting_length(&self) -> f64 {
        self.histogram[1..].iter().sum()
    }

    /// Mean engagement over the moves that met material, degrees.
    pub fn mean(&self) -> f64 {
        let l = self.cutting_length();
        if l == 0.0 {
            return 0.0;
        }
        self.histogram
            .iter()
            .enumerate()
            .skip(1)
            .map(|(d, len)| d as f64 * len)
            .sum::<f64>()
            / l
    }

    /// Length of moves engaged more than `deg`, mm.
    pub fn length_above(&self, deg: f64) -> f64 {
        self.histogram
            .iter()
            .enumerate()
            .filter(|(d, _)| *d as f64 > deg)
            .map(|(_, l)| l)
            .sum()
    }
}

/// Walks `ops` from `start` with a flat end mill of `radius` over `stock`, cutting it.
/// Material counts where it stands more than `min_axial` mm above the tip. Work is bounded
/// by `max_steps` (an error past it).
pub fn engagement(
    ops: &[Canon],
    radius: f64,
    stock: &mut EngagementStock,
    start: [f64; 3],
    min_axial: f64,
    max_steps: usize,
) -> Result<Engagement, String> {
    let mut w = Walk {
        stock,
        r: radius,
        min_axial,
        steps: max_steps,
        out: Engagement {
            peak: 0.0,
            peak_at: (start, 0),
            histogram: vec![0.0; 181],
            entry_length: 0.0,
            rapid_cutting: 0.0,
        },
    };
    let mut pos = start;
    for c in ops {
        match &c.op {
            CanonOp::StraightTraverse { to } => {
                let to = [to.x, to.y, to.z];
                w.line(pos, to, c.line, true)?;
                pos = to;
            }
            CanonOp::StraightFeed { to } => {
                let to = [to.x, to.y, to.z];
                w.line(pos, to, c.line, false)?;
                pos = to;
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let to = [end.x, end.y, end.z];
                let (a, b) = (to_arc_frame(pos, *rotation), to_arc_frame(to, *rotation));
                let tol = w.stock.px / 20.0;
                let mut from = pos;
                for p in arc_chords(*plane, a, b, *center, *turns, tol) {
                    let p = from_arc_frame(p, *rotation);
                    w.line(from, p, c.line, false)?;
                    from = p;
                }
                pos = to;
            }
            _ => {}
        }
    }
    Ok(w.out)
}

struct Walk<'a> {
    stock: &'a mut EngagementStock,
    r: f64,
    min_axial: f64,
    steps: usize,
    out: Engagement,
}

impl Walk<'_> {
    /// Walks `a`→`b`; a `rapid` that cuts counts in [`Engagement::rapid_cutting`].
    fn line(&mut self, a: [f64; 3], b: [f64; 3], line: u32, rapid: bool) -> Result<(), String> {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(len > 0.0) {
            return Ok(());
        }
        let n = (len / (0.5 * self.stock.px)).ceil() as usize;
        if n > self.steps {
            return Err(format!("line {line}: more steps than the walk allows"));
        }
        self.steps -= n;
        let entry = d[2] < -1e-9;
        let heading = d[1].atan2(d[0]);
        let flat = d[0].hypot(d[1]) > 1e-9;
        for k in 1..=n {
            let t = k as f64 / n as f64;
            let q = [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]];
            if entry {
                self.out.entry_length += len / n as f64;
            } else if flat {
                let e = self.measure(q, heading);
                self.out.histogram[e.round() as usize] += len / n as f64;
                if e > self.out.peak {
                    self.out.peak = e;
                    self.out.peak_at = (q, line);
                }
            }
            let tol = if rapid { RAPID_TOL } else { f32::INFINITY };
            if self.stock.cut_disc(q[0], q[1], self.r, q[2] as f32, tol) {
                self.out.rapid_cutting += len / n as f64;
            }
        }
        Ok(())
    }

    /// Degrees of the leading half-circle at `q` meeting material.
    fn measure(&self, q: [f64; 3], heading: f64) -> f64 {
        let rr = self.r + 0.5 * self.stock.px;
        let floor = q[2] + self.min_axial;
        (0..180)
            .filter(|&k| {
                let a = heading + (k as f64 + 0.5 - 90.0).to_radians();
                self.stock
                    .cell(q[0] + rr * a.cos(), q[1] + rr * a.sin())
                    .is_some_and(|c| f64::from(self.stock.z[c]) > floor)
            })
            .count() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use oficina_canon::Pos;

    fn walk(path: &[[f64; 3]], stock: &mut EngagementStock) -> Engagement {
        let ops: Vec<Canon> = path[1..]
            .iter()
            .map(|p| Canon {
                line: 1,
                op: CanonOp::StraightFeed {
                    to: Pos::xyz(p[0], p[1], p[2]),
                },
            })
            .collect();
        engagement(&ops, 3.0, stock, path[0], 0.1, 10_000_000).unwrap()
    }

    #[test]
    fn a_slot_is_180_and_a_side_cut_is_acos() {
        let block = vec![vec![[0.0, 0.0], [60.0, 0.0], [60.0, 40.0], [0.0, 40.0]]];
        // A slot across the block: half a circle in material all along.
        let mut s = EngagementStock::from_rings(&block, 0.0, 0.05, 5.0, 10_000_000).unwrap();
        let e = walk(&[[-5.0, 20.0, -2.0], [65.0, 20.0, -2.0]], &mut s);
        assert!(e.peak >= 178.0 && e.peak <= 180.0, "{}", e.peak);
        // Beside it, radial depth a: acos(1 − a/3) for the run in full material.
        for a in [0.75f64, 1.5, 3.0] {
            let mut s = EngagementStock::from_rings(&block, 0.0, 0.05, 5.0, 10_000_000).unwrap();
            let e = walk(
                &[[-5.0, 40.0 + 3.0 - a, -2.0], [65.0, 43.0 - a, -2.0]],
                &mut s,
            );
            let want = (1.0 - a / 3.0).acos().to_degrees();
            assert!((e.peak - want).abs() < 3.0, "a {a}: {} vs {want}", e.peak);
        }
        // Going down is the entry: not measured.
        let mut s = EngagementStock::from_rings(&block, 0.0, 0.05, 5.0, 10_000_000).unwrap();
        let e = walk(&[[10.0, 10.0, 1.0], [20.0, 10.0, -3.0]], &mut s);
        assert_eq!(e.peak, 0.0);
        assert!(e.entry_length > 10.0);
    }

    #[test]
    fn rapids_through_material_are_counted() {
        let block = vec![vec![[0.0, 0.0], [60.0, 0.0], [60.0, 40.0], [0.0, 40.0]]];
        let rapid = |to: [f64; 3]| Canon {
            line: 1,
            op: CanonOp::StraightTraverse {
                to: Pos::xyz(to[0], to[1], to[2]),
            },
        };
        let mut s = EngagementStock::from_rings(&block, 0.0, 0.05, 5.0, 10_000_000).unwrap();
        // Down beside the block: nothing; into it 2 mm deep from x = -3 (the disc's edge at
        // 0) to 20: 23 mm; back along the same slot: nothing left to cut.
        let ops = [
            rapid([-5.0, 20.0, -2.0]),
            rapid([20.0, 20.0, -2.0]),
            rapid([-5.0, 20.0, -2.0]),
        ];
        let e = engagement(&ops, 3.0, &mut s, [-5.0, 20.0, 1.0], 0.1, 10_000_000).unwrap();
        assert!((e.rapid_cutting - 23.0).abs() < 0.2, "{}", e.rapid_cutting);
    }
}
