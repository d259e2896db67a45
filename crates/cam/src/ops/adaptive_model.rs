//! The 2-D material model adaptive clearing steers by: a square grid over the pocket, each
//! cell material (still to cut) or not, and the cells where the tool centre may stand.
//!
//! Engagement of a tool of radius r at q moving along u: the arc of its leading half-circle
//! (directions within ±90° of u) that meets material. For a straight cut of radial depth a
//! the material starts where the circle crosses the line r − a from the centre, at
//! sin φ = 1 − a/r from the direction of travel, so the arc is 90° − asin(1 − a/r) =
//! acos(1 − a/r); along a concave wall (inside corners, a pass growing out of a hole) the
//! same a wraps more of the circle, which is why each step is measured, not assumed.

/// Rings as (x, y) points, closed implicitly, filled even–odd.
pub(super) type Rings = Vec<Vec<[f64; 2]>>;

/// Samples on the leading half-circle: one per degree.
const SAMPLES: usize = 180;

/// A material state of a [`Model`] to go back to.
pub(super) struct Snapshot(Vec<bool>, Vec<[f64; 2]>, usize);

pub(super) struct Model {
    ox: f64,
    oy: f64,
    /// Cell size, mm.
    pub(super) px: f64,
    nx: usize,
    ny: usize,
    /// Tool radius, mm.
    pub(super) r: f64,
    /// Uncut material (what the tool meets).
    material: Vec<bool>,
    /// For each cut cell, the stamp nearest its centre (NaN: never material): a point of
    /// the cell outside that stamp's disc is still material. Cells alone would erase a
    /// strip thinner than a cell that the tool's circle meets along its tangent.
    cutter: Vec<[f64; 2]>,
    /// Cells some allowed tool position can cut (what passes seek).
    reach: Vec<bool>,
    /// Cells whose centre the tool centre may occupy.
    allowed: Vec<bool>,
    /// Where the tool centre may go up to exactly, and the cells within one of it, where a
    /// position is tested against it.
    exact: Option<(Rings, Vec<bool>)>,
    /// Material cells a pass could not start from (left over).
    banned: Vec<bool>,
    /// Material cells left.
    pub(super) left: usize,
}

/// Cells of an `nx` × `ny` grid at (ox + (i + ½)·px, oy + (j + ½)·px) inside `rings`
/// (even–odd), by scanlines through the cell centres.
fn raster(rings: &Rings, ox: f64, oy: f64, px: f64, nx: usize, ny: usize) -> Vec<bool> {
    let mut mask = vec![false; nx * ny];
    let mut xs = Vec::new();
    for j in 0..ny {
        let y = oy + (j as f64 + 0.5) * px;
        xs.clear();
        for ring in rings {
            for k in 0..ring.len() {
                let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                if (a[1] > y) != (b[1] > y) {
                    xs.push(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            let i0 = ((pair[0] - ox) / px - 0.5).ceil().max(0.0) as usize;
            let i1 = ((pair[1] - ox) / px - 0.5).floor();
            if i1 < 0.0 {
                continue;
            }
            for i in i0..=(i1 as usize).min(nx - 1) {
                mask[j * nx + i] = true;
            }
        }
    }
    mask
}

impl Model {
    /// Material inside `pocket` (the drawn region shrunk by the stock to leave and a cell,
    /// so the tool passing along the wall does not count the wall as material), the tool
    /// centre within `centres`. Material no allowed centre comes within `r` − a cell of is
    /// not sought (it is out of the tool's reach, left for a smaller one) but still met.
    pub(super) fn new(pocket: &Rings, centres: &Rings, r: f64, px: f64) -> Model {
        let pts = pocket.iter().flatten();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in pts {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let (ox, oy) = (lo[0] - r - 2.0 * px, lo[1] - r - 2.0 * px);
        let nx = ((hi[0] - lo[0] + 2.0 * r) / px).ceil() as usize + 5;
        let ny = ((hi[1] - lo[1] + 2.0 * r) / px).ceil() as usize + 5;
        let mut m = Model {
            ox,
            oy,
            px,
            nx,
            ny,
            r,
            material: raster(pocket, ox, oy, px, nx, ny),
            cutter: vec![[f64::NAN; 2]; nx * ny],
            reach: vec![],
            allowed: vec![],
            exact: None,
            banned: vec![],
            left: 0,
        };
        m.allow(centres, None);
        m
    }

    /// Lets the tool centre within `centres` from now on, and, given `exact`, wherever
    /// inside `exact` (tested point by point near its edge, so the tool can run along it
    /// while a cell's centre would stand outside): what passes seek is what a centre
    /// there can cut, and no cell is banned any more.
    pub(super) fn allow(&mut self, centres: &Rings, exact: Option<&Rings>) {
        let (nx, ny, r) = (self.nx, self.ny, self.r);
        let (ox, oy, px) = (self.ox, self.oy, self.px);
        self.allowed = raster(centres, ox, oy, px, nx, ny);
        let reach_from =
            exact.map_or_else(|| self.allowed.clone(), |e| raster(e, ox, oy, px, nx, ny));
        self.exact = exact.map(|e| {
            let mut near = reach_from.clone();
            for j in 1..ny - 1 {
                for i in 1..nx - 1 {
                    let c = j * nx + i;
                    near[c] |= reach_from[c - 1]
                        || reach_from[c + 1]
                        || reach_from[c - nx]
                        || reach_from[c + nx];
                }
            }
            (e.clone(), near)
        });
        // Reachable: the cells whose centre a centre may occupy, and discs of radius
        // r − px about those on the edge of that region.
        let mut reach = reach_from.clone();
        for j in 1..ny - 1 {
            for i in 1..nx - 1 {
                let c = j * nx + i;
                let a = &reach_from;
                let edge = a[c] && !(a[c - 1] && a[c + 1] && a[c - nx] && a[c + nx]);
                if edge {
                    let (x, y) = self.centre(c);
                    self.for_disc([x, y], r - self.px, |k| reach[k] = true);
                }
            }
        }
        self.left = self
            .material
            .iter()
            .zip(&reach)
            .filter(|(a, b)| **a && **b)
            .count();
        self.reach = reach;
        self.banned = vec![false; nx * ny];
    }

    fn centre(&self, c: usize) -> (f64, f64) {
        let (i, j) = (c % self.nx, c / self.nx);
        (
            self.ox + (i as f64 + 0.5) * self.px,
            self.oy + (j as f64 + 0.5) * self.px,
        )
    }

    fn cell(&self, p: [f64; 2]) -> Option<usize> {
        let i = ((p[0] - self.ox) / self.px).floor();
        let j = ((p[1] - self.oy) / self.px).floor();
        (i >= 0.0 && j >= 0.0 && (i as usize) < self.nx && (j as usize) < self.ny)
            .then(|| j as usize * self.nx + i as usize)
    }

    /// Calls `f` for every cell whose centre is within `radius` of `p`.
    fn for_disc(&self, p: [f64; 2], radius: f64, mut f: impl FnMut(usize)) {
        let px = self.px;
        let j0 = (((p[1] - radius - self.oy) / px - 0.5).ceil()).max(0.0) as usize;
        let j1 = (((p[1] + radius - self.oy) / px - 0.5).floor()).min(self.ny as f64 - 1.0);
        if j1 < 0.0 {
            return;
        }
        for j in j0..=j1 as usize {
            let dy = self.oy + (j as f64 + 0.5) * px - p[1];
            let w = (radius * radius - dy * dy).max(0.0).sqrt();
            let i0 = (((p[0] - w - self.ox) / px - 0.5).ceil()).max(0.0) as usize;
            let i1 = (((p[0] + w - self.ox) / px - 0.5).floor()).min(self.nx as f64 - 1.0);
            if i1 < 0.0 {
                continue;
            }
            for i in i0..=i1 as usize {
                f(j * self.nx + i);
            }
        }
    }

    /// Whether the tool centre may be at `p`.
    pub(super) fn allowed(&self, p: [f64; 2]) -> bool {
        self.cell(p).is_some_and(|c| {
            self.allowed[c]
                || self
                    .exact
                    .as_ref()
                    .is_some_and(|(rings, near)| near[c] && super::chain::inside(rings, p))
        })
    }

    fn is_material(&self, p: [f64; 2]) -> bool {
        self.cell(p).is_some_and(|c| {
            let s = self.cutter[c];
            // NaN compares false: never material.
            self.material[c] || (p[0] - s[0]).hypot(p[1] - s[1]) > self.r
        })
    }

    /// Engagement (degrees) of the tool at `q` heading `heading` (radians): the part of the
    /// leading half-circle, sampled half a cell outside the cutting circle, that is material.
    pub(super) fn engagement(&self, q: [f64; 2], heading: f64) -> f64 {
        let rr = self.r + 0.5 * self.px;
        let n = (0..SAMPLES)
            .filter(|&k| {
                let a = heading + ((k as f64 + 0.5) / SAMPLES as f64 - 0.5) * std::f64::consts::PI;
                self.is_material([q[0] + rr * a.cos(), q[1] + rr * a.sin()])
            })
            .count();
        n as f64 * 180.0 / SAMPLES as f64
    }

    /// Removes the material under the tool at `p`; returns how many cells it cut that
    /// passes seek, and how many in all.
    pub(super) fn stamp(&mut self, p: [f64; 2]) -> (usize, usize) {
        let mut cut = Vec::new();
        self.for_disc(p, self.r, |c| cut.push(c));
        let (mut n, mut all) = (0, 0);
        for c in cut {
            let (x, y) = self.centre(c);
            let s = self.cutter[c];
            if (x - p[0]).hypot(y - p[1]) < (x - s[0]).hypot(y - s[1]) {
                self.cutter[c] = p;
            }
            if self.material[c] {
                self.material[c] = false;
                self.cutter[c] = p;
                n += usize::from(self.reach[c]);
                all += 1;
            }
        }
        self.left -= n;
        (n, all)
    }

    /// Whether the tool at `p` touches no material (nor within a cell of it).
    pub(super) fn free(&self, p: [f64; 2]) -> bool {
        let mut hit = false;
        self.for_disc(p, self.r + self.px, |c| hit |= self.material[c]);
        !hit
    }

    /// Points from `a` to `b` a cell apart, `b` included.
    pub(super) fn along(&self, a: [f64; 2], b: [f64; 2]) -> impl Iterator<Item = [f64; 2]> {
        let n = ((b[0] - a[0]).hypot(b[1] - a[1]) / self.px).ceil().max(1.0) as usize;
        (1..=n).map(move |k| {
            let t = k as f64 / n as f64;
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        })
    }

    /// Whether the tool along `a`→`b` touches no material (nor within a cell of it).
    pub(super) fn free_along(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        self.free(a) && self.along(a, b).all(|q| self.free(q))
    }

    /// Whether the tool going along `a`→`b` meets no material ahead and keeps its centre
    /// allowed all along: a rapid there cuts nothing and stays off the walls.
    pub(super) fn cuts_nothing_along(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        let h = (b[1] - a[1]).atan2(b[0] - a[0]);
        std::iter::once(a)
            .chain(self.along(a, b))
            .all(|q| self.allowed(q) && self.engagement(q, h) == 0.0)
    }

    /// Up to `n` material cells not banned, nearest to `p` first.
    pub(super) fn nearest_material(&self, p: [f64; 2], n: usize) -> Vec<(usize, [f64; 2])> {
        let mut best: Vec<(f64, usize)> = Vec::with_capacity(n + 1);
        for c in 0..self.material.len() {
            if !self.material[c] || !self.reach[c] || self.banned[c] {
                continue;
            }
            let (x, y) = self.centre(c);
            let d = (x - p[0]).hypot(y - p[1]);
            if best.len() < n || d < best[best.len() - 1].0 {
                let at = best.partition_point(|b| b.0 <= d);
                best.insert(at, (d, c));
                best.truncate(n);
            }
        }
        best.into_iter()
            .map(|(_, c)| {
                let (x, y) = self.centre(c);
                (c, [x, y])
            })
            .collect()
    }

    /// The material state, to go back to.
    pub(super) fn snapshot(&self) -> Snapshot {
        Snapshot(self.material.clone(), self.cutter.clone(), self.left)
    }

    /// Back to a state [`Model::snapshot`] took.
    pub(super) fn restore(&mut self, Snapshot(material, cutter, left): Snapshot) {
        self.material = material;
        self.cutter = cutter;
        self.left = left;
    }

    /// Marks material cell `c` as one no pass could start from.
    pub(super) fn ban(&mut self, c: usize) {
        self.banned[c] = true;
    }

    /// Material cells left that no pass could start from, and not banned.
    pub(super) fn open_left(&self) -> usize {
        (0..self.material.len())
            .filter(|&c| self.material[c] && self.reach[c] && !self.banned[c])
            .count()
    }

    /// The allowed, still uncut cell farthest (approximately, 3-4 chamfer) from the edge
    /// of the allowed region, with that distance: where a helix can go down into fresh
    /// material.
    pub(super) fn deepest_uncut(&self) -> Option<([f64; 2], f64)> {
        let (nx, ny) = (self.nx, self.ny);
        let big = f64::INFINITY;
        let mut d: Vec<f64> = self
            .allowed
            .iter()
            .map(|&a| if a { big } else { 0.0 })
            .collect();
        let (a, b) = (self.px, self.px * std::f64::consts::SQRT_2);
        for j in 0..ny {
            for i in 0..nx {
                let c = j * nx + i;
                let mut v = d[c];
                if i > 0 {
                    v = v.min(d[c - 1] + a);
                }
                if j > 0 {
                    v = v.min(d[c - nx] + a);
                    if i > 0 {
                        v = v.min(d[c - nx - 1] + b);
                    }
                    if i + 1 < nx {
                        v = v.min(d[c - nx + 1] + b);
                    }
                }
                d[c] = v;
            }
        }
        for j in (0..ny).rev() {
            for i in (0..nx).rev() {
                let c = j * nx + i;
                let mut v = d[c];
                if i + 1 < nx {
                    v = v.min(d[c + 1] + a);
                }
                if j + 1 < ny {
                    v = v.min(d[c + nx] + a);
                    if i + 1 < nx {
                        v = v.min(d[c + nx + 1] + b);
                    }
                    if i > 0 {
                        v = v.min(d[c + nx - 1] + b);
                    }
                }
                d[c] = v;
            }
        }
        (0..d.len())
            .filter(|&c| self.allowed[c] && self.material[c] && !self.banned[c])
            .max_by(|&x, &y| d[x].total_cmp(&d[y]))
            .map(|c| {
                let (x, y) = self.centre(c);
                // The chamfer distance runs from cell centre to cell centre: half a cell
                // less reaches the region's edge.
                ([x, y], (d[c] - 0.5 * self.px).max(0.0))
            })
    }

    /// Whether the tool can feed along `a`→`b`, its centre allowed, engaged at most
    /// `target` degrees all along; if so the material it meets is cut.
    pub(super) fn link(&mut self, a: [f64; 2], b: [f64; 2], target: f64) -> bool {
        let h = (b[1] - a[1]).atan2(b[0] - a[0]);
        let pts: Vec<[f64; 2]> = self.along(a, b).collect();
        // Cut as it goes (engagement only grows as material is met, never shrinks
        // behind), back to the state before where it fails.
        let before = self.snapshot();
        for &p in &pts {
            if !self.allowed(p) || self.engagement(p, h) > target {
                self.restore(before);
                return false;
            }
            self.stamp(p);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, s: f64) -> Vec<[f64; 2]> {
        vec![[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]]
    }

    #[test]
    fn a_straight_cut_engages_acos_of_its_radial_depth() {
        // Material below y = 0 (a wide square), tool of radius 3 centred at y = 3 − a.
        let pocket = vec![square(-50.0, -50.0, 50.0)];
        let centres = vec![square(-60.0, -60.0, 120.0)];
        let m = Model::new(&pocket, &centres, 3.0, 0.02);
        for a in [0.5, 1.0, 1.5, 3.0] {
            let e = m.engagement([-25.0, 3.0 - a], 0.0);
            let want = (1.0f64 - a / 3.0).acos().to_degrees();
            assert!((e - want).abs() < 3.0, "a {a}: {e}° against {want}°");
        }
    }

    #[test]
    fn material_just_outside_a_stamp_is_met_within_its_cells() {
        // Cells of 0.2 mm against a 3 mm disc: some of the points 0.05 mm outside it lie
        // in cells whose centre it covers (a point inside it may lie in a cell left whole:
        // the model errs towards material).
        let pocket = vec![square(-20.0, -20.0, 40.0)];
        let mut m = Model::new(&pocket, &pocket, 3.0, 0.2);
        m.stamp([0.1, 0.05]);
        for k in 0..360 {
            let a = (k as f64).to_radians();
            let p = [0.1 + 3.05 * a.cos(), 0.05 + 3.05 * a.sin()];
            assert!(m.is_material(p), "{k}°: 0.05 mm outside");
        }
    }
}
