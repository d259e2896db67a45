//! Connected regions of a mask (8-connectivity), for machining only where a previous tool
//! left material, block by block as seed 004 did with OpenCV's connected components.

/// A labelled region: its pixels' bounding box and size.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Region {
    pub label: u32,
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
    pub area: usize,
}

/// Grows the mask by `radius` pixels (a disk), so a region includes the ground the tool
/// needs to enter and leave it.
pub(crate) fn grow(mask: &[bool], width: usize, radius: f64) -> Vec<bool> {
    let height = mask.len() / width.max(1);
    let r = radius.max(0.0).floor() as i64;
    let spans: Vec<i64> = (-r..=r)
        .map(|dy| {
            ((radius * radius - (dy * dy) as f64).max(0.0))
                .sqrt()
                .floor() as i64
        })
        .collect();
    let mut out = vec![false; mask.len()];
    for iy in 0..height {
        // Per row: distance to the nearest set pixel along the row, left and right passes.
        for (k, dy) in (-r..=r).enumerate() {
            let ty = iy as i64 + dy;
            if ty < 0 || ty >= height as i64 {
                continue;
            }
            let src = &mask[iy * width..(iy + 1) * width];
            let dst = &mut out[ty as usize * width..(ty as usize + 1) * width];
            let w = spans[k];
            let mut last: i64 = i64::MIN / 2;
            for (ix, &m) in src.iter().enumerate() {
                if m {
                    last = ix as i64;
                }
                if ix as i64 - last <= w {
                    dst[ix] = true;
                }
            }
            last = i64::MAX / 2;
            for ix in (0..width).rev() {
                if src[ix] {
                    last = ix as i64;
                }
                if last - ix as i64 <= w {
                    dst[ix] = true;
                }
            }
        }
    }
    out
}

/// Labels 8-connected regions; returns the label grid (0 = outside) and the regions.
pub(crate) fn label(mask: &[bool], width: usize) -> (Vec<u32>, Vec<Region>) {
    let height = mask.len() / width.max(1);
    let mut labels = vec![0u32; mask.len()];
    let mut regions = Vec::new();
    let mut stack = Vec::new();
    for start in 0..mask.len() {
        if !mask[start] || labels[start] != 0 {
            continue;
        }
        let id = regions.len() as u32 + 1;
        let (sx, sy) = (start % width, start / width);
        let mut reg = Region {
            label: id,
            x0: sx,
            y0: sy,
            x1: sx,
            y1: sy,
            area: 0,
        };
        labels[start] = id;
        stack.push(start);
        while let Some(i) = stack.pop() {
            let (x, y) = (i % width, i / width);
            reg.area += 1;
            reg.x0 = reg.x0.min(x);
            reg.x1 = reg.x1.max(x);
            reg.y0 = reg.y0.min(y);
            reg.y1 = reg.y1.max(y);
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                        continue;
                    }
                    let j = ny as usize * width + nx as usize;
                    if mask[j] && labels[j] == 0 {
                        labels[j] = id;
                        stack.push(j);
                    }
                }
            }
        }
        regions.push(reg);
    }
    (labels, regions)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_diagonal_neighbours_together() {
        #[rustfmt::skip]
        let m = [
            1, 0, 0, 0, 1,
            0, 1, 0, 0, 1,
            0, 0, 0, 0, 0,
            1, 1, 0, 0, 0,
        ].map(|v| v == 1);
        let (labels, regions) = label(&m, 5);
        assert_eq!(regions.len(), 3);
        assert_eq!(labels[0], labels[6]);
        assert_eq!(regions[0].area, 2);
        assert_eq!((regions[1].x0, regions[1].y1), (4, 1));
    }

    #[test]
    fn grow_is_a_disk_dilation() {
        let (w, h) = (15, 13);
        let mut m = vec![false; w * h];
        m[6 * w + 7] = true;
        let g = grow(&m, w, 3.0);
        for y in 0..h {
            for x in 0..w {
                let d2 = (x as i64 - 7).pow(2) + (y as i64 - 6).pow(2);
                assert_eq!(g[y * w + x], d2 <= 9, "at {x},{y}");
            }
        }
    }
}
