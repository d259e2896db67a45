//! Buckets of triangles on an XY grid: each triangle is listed in every cell its box,
//! grown by the tool radius, overlaps, so a drop at a point reads one cell only.

use super::drop::{drop_on, Shape, Tri};

pub(crate) struct Buckets {
    pub(crate) tris: Vec<Tri>,
    origin: [f64; 2],
    cell: f64,
    nx: usize,
    ny: usize,
    /// CSR: the triangles of cell `k` are `index[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    index: Vec<u32>,
}

/// Cells per triangle at most, on average, before the cell grows (bounds the index).
const MAX_CELLS: usize = 1 << 22;

impl Buckets {
    /// Bytes the index needs for `n` triangles at most (for the memory estimate).
    pub(crate) fn bytes_estimate(n: usize) -> u64 {
        n as u64 * (std::mem::size_of::<Tri>() as u64 + 9 * 4) + (MAX_CELLS as u64 + 1) * 4
    }

    pub(crate) fn new(triangles: &[[[f64; 3]; 3]], reach: f64) -> Buckets {
        let tris: Vec<Tri> = triangles.iter().map(|&p| Tri::new(p)).collect();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut size = 0.0;
        for t in &tris {
            lo = [lo[0].min(t.bb[0]), lo[1].min(t.bb[1])];
            hi = [hi[0].max(t.bb[2]), hi[1].max(t.bb[3])];
            size += (t.bb[2] - t.bb[0]).max(t.bb[3] - t.bb[1]);
        }
        let origin = [lo[0] - reach, lo[1] - reach];
        let span = [hi[0] - lo[0] + 2.0 * reach, hi[1] - lo[1] + 2.0 * reach];
        // About one tool width or one mean triangle per cell, whichever is larger, and never
        // more than MAX_CELLS cells.
        let mean = size / tris.len().max(1) as f64;
        let mut cell = (2.0 * reach).max(mean).max(1e-6);
        while (span[0] / cell + 1.0) * (span[1] / cell + 1.0) > MAX_CELLS as f64 {
            cell *= 1.5;
        }
        let nx = (span[0] / cell) as usize + 1;
        let ny = (span[1] / cell) as usize + 1;
        let range = |t: &Tri| {
            let c =
                |v: f64, o: f64, n: usize| (((v - o) / cell).floor().max(0.0) as usize).min(n - 1);
            (
                c(t.bb[0] - reach, origin[0], nx),
                c(t.bb[2] + reach, origin[0], nx),
                c(t.bb[1] - reach, origin[1], ny),
                c(t.bb[3] + reach, origin[1], ny),
            )
        };
        let mut count = vec![0u32; nx * ny + 1];
        for t in &tris {
            let (x0, x1, y0, y1) = range(t);
            for iy in y0..=y1 {
                for ix in x0..=x1 {
                    count[iy * nx + ix + 1] += 1;
                }
            }
        }
        for k in 1..count.len() {
            count[k] += count[k - 1];
        }
        let mut fill = count.clone();
        let mut index = vec![0u32; *count.last().unwrap_or(&0) as usize];
        for (i, t) in tris.iter().enumerate() {
            let (x0, x1, y0, y1) = range(t);
            for iy in y0..=y1 {
                for ix in x0..=x1 {
                    let k = iy * nx + ix;
                    index[fill[k] as usize] = i as u32;
                    fill[k] += 1;
                }
            }
        }
        Buckets {
            tris,
            origin,
            cell,
            nx,
            ny,
            start: count,
            index,
        }
    }

    /// The highest tip of `shape` dropped at `c` onto any triangle, `None` out of reach.
    pub(crate) fn drop(&self, shape: &Shape, c: [f64; 2]) -> Option<f64> {
        let ix = ((c[0] - self.origin[0]) / self.cell).floor();
        let iy = ((c[1] - self.origin[1]) / self.cell).floor();
        if !(ix >= 0.0 && iy >= 0.0 && (ix as usize) < self.nx && (iy as usize) < self.ny) {
            return None;
        }
        let k = iy as usize * self.nx + ix as usize;
        let mut z = f64::NEG_INFINITY;
        for &i in &self.index[self.start[k] as usize..self.start[k + 1] as usize] {
            z = drop_on(shape, c, &self.tris[i as usize], z);
        }
        (z > f64::NEG_INFINITY).then_some(z)
    }
}
