//! Marching squares on a picture's darkness: the outlines of where it is darker than a level,
//! as closed rings. A darkness band is the rings of its two levels read even-odd.

use std::collections::{HashMap, HashSet};

use oficina_geom::Ring;

use super::Gray;

/// At most this many grid points: a larger picture is averaged over blocks of pixels first
/// (bounded memory: the outlines hold at most two points a cell).
pub(crate) const MAX_CELLS: usize = 1_000_000;

/// The darkness (0 white … 1 black) on a grid of cell centres. Around it, on the picture's
/// edges, a copy of the border cells and then white points at the same place: every outline
/// closes, and along an edge it runs on the edge (the step to white has no width) instead of
/// leaving a strip of every lighter band there.
pub(crate) struct Field {
    nx: usize,
    ny: usize,
    dark: Vec<f32>,
    xs: Vec<f64>,
    ys: Vec<f64>,
}

impl Field {
    /// `img` averaged over blocks of `f × f` pixels, `pixel` mm wide, lower-left corner at the
    /// origin, Y up.
    pub(crate) fn new(img: &Gray, pixel: f64, f: usize) -> Field {
        let f = f.max(1);
        let (cw, ch) = (img.width.div_ceil(f), img.height.div_ceil(f));
        let mut cells = vec![0.0f32; cw * ch];
        for r in 0..ch {
            for c in 0..cw {
                let (mut sum, mut n) = (0u64, 0u64);
                for y in r * f..((r + 1) * f).min(img.height) {
                    let row = &img.pixels[y * img.width..(y + 1) * img.width];
                    for &g in &row[c * f..((c + 1) * f).min(img.width)] {
                        sum += 255 - g as u64;
                        n += 1;
                    }
                }
                cells[r * cw + c] = sum as f32 / (n as f32 * 255.0);
            }
        }
        let (nx, ny) = (cw + 4, ch + 4);
        let (wmm, hmm) = (img.width as f64 * pixel, img.height as f64 * pixel);
        // A block's centre: the middle of its pixels (the last block may be narrower).
        let mid = |c: usize, n: usize| (c * f + ((c + 1) * f).min(n)) as f64 * 0.5 * pixel;
        // Grid column i: 0 and 1 on the left edge, cells from 2, the last two on the right.
        let place = |i: usize, n: usize, cells: usize, size: f64| match i {
            0 | 1 => 0.0,
            _ if i >= cells + 2 => size,
            _ => mid(i - 2, n),
        };
        let xs: Vec<f64> = (0..nx).map(|i| place(i, img.width, cw, wmm)).collect();
        let ys: Vec<f64> = (0..ny)
            .map(|j| hmm - place(j, img.height, ch, hmm))
            .collect();
        let mut dark = vec![0.0f32; nx * ny];
        for j in 1..ny - 1 {
            for i in 1..nx - 1 {
                let (c, r) = ((i.max(2) - 2).min(cw - 1), (j.max(2) - 2).min(ch - 1));
                dark[j * nx + i] = cells[r * cw + c];
            }
        }
        Field {
            nx,
            ny,
            dark,
            xs,
            ys,
        }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.dark[j * self.nx + i] as f64
    }

    /// Where the darkness crosses `level` on edge `id` (even: towards +i, odd: towards +j),
    /// by linear interpolation between the edge's ends.
    fn crossing(&self, id: usize, level: f64) -> [f64; 2] {
        let (k, down) = (id / 2, id % 2 == 1);
        let (i, j) = (k % self.nx, k / self.nx);
        let (i1, j1) = if down { (i, j + 1) } else { (i + 1, j) };
        let (d0, d1) = (self.at(i, j), self.at(i1, j1));
        let t = ((level - d0) / (d1 - d0)).clamp(0.0, 1.0);
        [
            self.xs[i] + t * (self.xs[i1] - self.xs[i]),
            self.ys[j] + t * (self.ys[j1] - self.ys[j]),
        ]
    }

    /// Closed rings around the grid points darker than `level` (≥ 0, so the white frame is
    /// always outside): each cell joins the edges its corners' states cross; a saddle cell
    /// (two opposite corners dark) is split by its centre's mean.
    pub(crate) fn outlines(&self, level: f64) -> Vec<Ring> {
        let nx = self.nx;
        let h = |i: usize, j: usize| 2 * (j * nx + i);
        let v = |i: usize, j: usize| 2 * (j * nx + i) + 1;
        let mut segs: Vec<[usize; 2]> = Vec::new();
        for j in 0..self.ny - 1 {
            for i in 0..nx - 1 {
                // Corners a (i,j), b (i+1,j), c (i+1,j+1), e (i,j+1); the edge each cuts off.
                let d = [
                    self.at(i, j),
                    self.at(i + 1, j),
                    self.at(i + 1, j + 1),
                    self.at(i, j + 1),
                ];
                let inside = d.map(|x| x > level);
                let (top, right, bottom, left) = (h(i, j), v(i + 1, j), h(i, j + 1), v(i, j));
                let cut = [[top, left], [top, right], [right, bottom], [left, bottom]];
                let n = inside.iter().filter(|&&s| s).count();
                match n {
                    0 | 4 => {}
                    1 | 3 => {
                        // The odd corner out is cut off.
                        let odd = n == 1;
                        let k = inside.iter().position(|&s| s == odd).unwrap_or(0);
                        segs.push(cut[k]);
                    }
                    _ => {
                        if inside[0] == inside[2] {
                            // Saddle: the corners unlike the centre are cut off.
                            let centre = d.iter().sum::<f64>() / 4.0 > level;
                            for k in 0..4 {
                                if inside[k] != centre {
                                    segs.push(cut[k]);
                                }
                            }
                        } else if inside[0] == inside[1] {
                            segs.push([left, right]);
                        } else {
                            segs.push([top, bottom]);
                        }
                    }
                }
            }
        }
        // Every crossed edge is shared by two cells: two neighbours each, so the walk closes.
        let mut next: HashMap<usize, [usize; 2]> = HashMap::with_capacity(segs.len() * 2);
        for &[a, b] in &segs {
            for (p, q) in [(a, b), (b, a)] {
                next.entry(p).or_insert([usize::MAX; 2]);
                let e = next.get_mut(&p).expect("inserted above");
                if e[0] == usize::MAX {
                    e[0] = q;
                } else {
                    e[1] = q;
                }
            }
        }
        let mut seen: HashSet<usize> = HashSet::with_capacity(next.len());
        let mut rings = Vec::new();
        for &[start, first] in &segs {
            if seen.contains(&start) {
                continue;
            }
            let mut ring = vec![self.crossing(start, level)];
            seen.insert(start);
            let (mut prev, mut cur) = (start, first);
            while cur != start && seen.insert(cur) {
                ring.push(self.crossing(cur, level));
                let Some(n) = next.get(&cur) else { break };
                let to = if n[0] == prev { n[1] } else { n[0] };
                (prev, cur) = (cur, to);
            }
            if ring.len() >= 3 {
                rings.push(ring);
            }
        }
        rings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outlines_of_a_radial_ramp_are_its_circles() {
        // Darkness 1 − r/40 about the centre of 100 × 100 mm (1 mm pixels): the level t is
        // the circle of radius 40·(1 − t), within the 8-bit rounding (40/510 mm) and the
        // chords' sag between pixel centres.
        let (w, c) = (100usize, 50.0);
        let px: Vec<u8> = (0..w * w)
            .map(|i| {
                let (x, y) = ((i % w) as f64 + 0.5, (w - i / w) as f64 - 0.5);
                let d = (1.0 - (x - c).hypot(y - c) / 40.0).max(0.0);
                (255.0 * (1.0 - d)).round() as u8
            })
            .collect();
        let img = Gray {
            width: w,
            height: w,
            pixels: &px,
        };
        for f in [1, 2] {
            let field = Field::new(&img, 1.0, f);
            for t in [0.25, 0.5, 0.75] {
                let rings = field.outlines(t);
                assert_eq!(rings.len(), 1, "level {t}");
                let want = 40.0 * (1.0 - t);
                for p in &rings[0] {
                    let r = (p[0] - c).hypot(p[1] - c);
                    assert!(
                        (r - want).abs() < 0.15 * f as f64,
                        "f {f} level {t}: {r} vs {want}"
                    );
                }
            }
        }
    }
}
