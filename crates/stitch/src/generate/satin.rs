//! Satin columns (seed §7, POLICH): stitches zig-zag across a column between two rails.
//! Along a stroke the rails are the centreline offset by ±(width + pull compensation)/2 with
//! mitred corners; between two given rails they are used as drawn. The zigs are spaced by
//! `spacing` measured on the LONGER rail of each piece: at a corner the outer rail keeps the
//! density and the inner rail gets the extra points, the seed's corner accommodation (Fig
//! 3.9: "additional points on the inner side of the corner, so that the outer side keeps its
//! point density constant"). It also covers the seed's fill arc rule (ARCOCH): when
//! R_out > 2·R_in the inner rail is simply shorter and its points crowd.

use oficina_geom::{Point, Vec2};

/// Mitres longer than this many half-widths are clipped (a hairpin would shoot away).
const MITRE_LIMIT: f64 = 3.0;

/// Left and right rails of a centreline at half-width `h`.
pub(super) fn rails(center: &[Point], h: f64) -> (Vec<Point>, Vec<Point>) {
    // Repeated points have no direction.
    let mut pts: Vec<Point> = Vec::with_capacity(center.len());
    for &p in center {
        if pts.last().is_none_or(|q: &Point| q.distance(p) > 1e-6) {
            pts.push(p);
        }
    }
    let center = &pts[..];
    let n = center.len();
    let normal = |a: Point, b: Point| {
        let d = (b - a).normalize();
        Vec2::new(-d.y, d.x)
    };
    let mut left = Vec::with_capacity(n);
    let mut right = Vec::with_capacity(n);
    for i in 0..n {
        let n_in = (i > 0).then(|| normal(center[i - 1], center[i]));
        let n_out = (i + 1 < n).then(|| normal(center[i], center[i + 1]));
        let off = match (n_in, n_out) {
            (Some(a), Some(b)) => {
                // The mitre: the bisector scaled by 1 / cos(half the turn).
                let m = a + b;
                if m.hypot() < 1e-9 {
                    // A hairpin: the column turns back on itself.
                    a * h
                } else {
                    let cos_half = (m.hypot() / 2.0).max(1.0 / MITRE_LIMIT);
                    m.normalize() * (h / cos_half)
                }
            }
            (Some(a), None) | (None, Some(a)) => a * h,
            (None, None) => Vec2::ZERO,
        };
        left.push(center[i] + off);
        right.push(center[i] - off);
    }
    (left, right)
}

/// The needle points of a satin between `left` and `right` (same vertex count), zigs
/// `spacing` apart on the longer rail, each zig cut into stitches of at most `max_stitch`.
pub(super) fn satin(left: &[Point], right: &[Point], spacing: f64, max_stitch: f64) -> Vec<Point> {
    let n = left.len().min(right.len());
    if n < 2 {
        return Vec::new();
    }
    let lmax: Vec<f64> = (0..n - 1)
        .map(|k| {
            left[k]
                .distance(left[k + 1])
                .max(right[k].distance(right[k + 1]))
        })
        .collect();
    let total: f64 = lmax.iter().sum();
    let zigs = (total / spacing).ceil().max(1.0) as usize;
    let step = total / zigs as f64;
    let mut out = Vec::with_capacity(2 * zigs + 2);
    let (mut k, mut k_start) = (0usize, 0.0);
    let mut prev: Option<Point> = None;
    for j in 0..=zigs {
        let s = j as f64 * step;
        while k + 1 < n - 1 && k_start + lmax[k] < s {
            k_start += lmax[k];
            k += 1;
        }
        let t = if lmax[k] > 0.0 {
            ((s - k_start) / lmax[k]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (left[k].lerp(left[k + 1], t), right[k].lerp(right[k + 1], t));
        for p in [a, b] {
            if let Some(q) = prev {
                // A zig wider than the machine's longest stitch is split (auto split satin).
                let d = q.distance(p);
                let parts = (d / max_stitch - 1e-9).ceil().max(1.0) as usize;
                for m in 1..parts {
                    out.push(q.lerp(p, m as f64 / parts as f64));
                }
            }
            out.push(p);
            prev = Some(p);
        }
    }
    out
}

/// Resamples a polyline to `m` points equally spaced along it (m ≥ 2).
pub(super) fn resample(points: &[Point], m: usize) -> Vec<Point> {
    let total: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    let mut out = Vec::with_capacity(m);
    let (mut k, mut k_start) = (0usize, 0.0);
    for j in 0..m {
        let s = total * j as f64 / (m - 1) as f64;
        while k + 2 < points.len() && k_start + points[k].distance(points[k + 1]) < s {
            k_start += points[k].distance(points[k + 1]);
            k += 1;
        }
        let l = points[k].distance(points[k + 1]);
        let t = if l > 0.0 {
            ((s - k_start) / l).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(points[k].lerp(points[k + 1], t));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_column_has_width_and_density() {
        let c = [Point::new(0.0, 0.0), Point::new(20.0, 0.0)];
        let (l, r) = rails(&c, 1.5);
        let p = satin(&l, &r, 0.4, 12.0);
        assert_eq!(p.len(), 2 * 51);
        assert!((p[0].y - 1.5).abs() < 1e-12 && (p[1].y + 1.5).abs() < 1e-12);
        assert!((p[2].x - 0.4).abs() < 1e-12);
    }

    #[test]
    fn at_a_corner_the_outer_rail_keeps_the_spacing() {
        // An L turning left: the right rail is outside.
        let c = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
        ];
        let (l, r) = rails(&c, 2.0);
        let p = satin(&l, &r, 0.5, 12.0);
        let outer: Vec<Point> = p.iter().skip(1).step_by(2).copied().collect();
        let gaps: Vec<f64> = outer.windows(2).map(|w| w[0].distance(w[1])).collect();
        let max = gaps.iter().cloned().fold(0.0, f64::max);
        assert!(max <= 0.5 + 1e-9, "outer gap {max}");
        let inner: Vec<Point> = p.iter().step_by(2).copied().collect();
        let min_inner = inner
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .fold(9.0, f64::min);
        assert!(
            min_inner < 0.4,
            "inner points crowd at the corner: {min_inner}"
        );
    }

    #[test]
    fn wide_zigs_are_split() {
        let c = [Point::new(0.0, 0.0), Point::new(2.0, 0.0)];
        let (l, r) = rails(&c, 10.0); // 20 mm wide
        let p = satin(&l, &r, 1.0, 12.0);
        assert!(p.windows(2).all(|w| w[0].distance(w[1]) <= 12.0 + 1e-9));
    }
}
