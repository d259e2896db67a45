//! Hatch fills of areas: parallel lines at an angle (and at right angles to it for a cross
//! hatch), or concentric insets. Lines lie at whole multiples of the spacing from the origin,
//! so neighbouring shapes' hatches line up as one.

use oficina_geom::{offset_regions, Join, Point, Region, Ring, Vec2};

use crate::strokes::Stroke;

/// Hatch spacings below this are refused: no pen draws lines that close apart, mm.
pub const MIN_FILL_SPACING: f64 = 0.01;
/// More hatch lines than this for one plot are refused (bounded memory and time).
pub const MAX_FILL_LINES: f64 = 1.0e6;

/// How filled areas are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FillStyle {
    /// Direction of the hatch lines, degrees counter-clockwise from +X.
    pub angle: f64,
    /// Distance between hatch lines (or between concentric rings), mm on paper.
    pub spacing: f64,
    /// A second set of lines at right angles.
    pub cross: bool,
    /// Concentric insets instead of parallel lines.
    pub concentric: bool,
}

impl Default for FillStyle {
    fn default() -> Self {
        FillStyle {
            angle: 45.0,
            spacing: 1.0,
            cross: false,
            concentric: false,
        }
    }
}

impl FillStyle {
    /// Refuses settings that cannot be drawn: says which.
    pub fn check(&self) -> Result<(), String> {
        if !(self.spacing.is_finite() && self.spacing >= MIN_FILL_SPACING) {
            return Err(format!(
                "fill spacing {} mm: must be at least {MIN_FILL_SPACING} mm (no pen draws lines closer)",
                self.spacing
            ));
        }
        if !self.angle.is_finite() {
            return Err(format!(
                "fill angle {}: must be a number of degrees",
                self.angle
            ));
        }
        Ok(())
    }
}

/// Counts hatch lines over `regions` before drawing any (the memory bound).
fn line_count(regions: &[Region], spacing: f64) -> f64 {
    regions
        .iter()
        .map(|r| {
            let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
            for p in &r.outer {
                lo = [lo[0].min(p[0]), lo[1].min(p[1])];
                hi = [hi[0].max(p[0]), hi[1].max(p[1])];
            }
            (hi[0] - lo[0]).hypot(hi[1] - lo[1]) / spacing + 1.0
        })
        .sum()
}

/// Hatch strokes of `regions` (non-overlapping outers with their holes, as
/// `oficina_geom::simplify` returns them). `budget` is how many lines may still be drawn;
/// it is reduced, and an error says so when exceeded. `tol` is the chord tolerance of
/// concentric rings' round corners.
pub fn fill_regions(
    regions: &[Region],
    style: &FillStyle,
    tol: f64,
    budget: &mut f64,
) -> Result<Vec<Stroke>, String> {
    if !(style.spacing.is_finite() && style.spacing > 0.0) {
        return Err(format!("fill spacing {} must be > 0", style.spacing));
    }
    let n = line_count(regions, style.spacing) * if style.cross { 2.0 } else { 1.0 };
    if n > *budget {
        return Err(format!(
            "a fill spacing of {} mm needs more than {MAX_FILL_LINES} hatch lines: use a larger spacing",
            style.spacing
        ));
    }
    *budget -= n;
    if style.concentric {
        return concentric(regions, style.spacing, tol);
    }
    let rings: Vec<&Ring> = regions
        .iter()
        .flat_map(|r| std::iter::once(&r.outer).chain(r.holes.iter()))
        .collect();
    let mut out = parallel(&rings, style.angle, style.spacing);
    if style.cross {
        out.extend(parallel(&rings, style.angle + 90.0, style.spacing));
    }
    Ok(out)
}

/// Scan lines: the rings turned so the hatch runs along +X, each line's crossings with the
/// edges sorted and paired (even-odd), turned back.
fn parallel(rings: &[&Ring], angle: f64, spacing: f64) -> Vec<Stroke> {
    let u = Vec2::from_angle(angle.to_radians());
    // Turned frame: x along u, y along its normal.
    let to = |p: &[f64; 2]| (p[0] * u.x + p[1] * u.y, -p[0] * u.y + p[1] * u.x);
    let back = |x: f64, y: f64| Point::new(x * u.x - y * u.y, x * u.y + y * u.x);
    let (mut y0, mut y1) = (f64::MAX, f64::MIN);
    for p in rings.iter().flat_map(|r| r.iter()) {
        let (_, y) = to(p);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if y0 > y1 {
        return Vec::new();
    }
    let k0 = (y0 / spacing).ceil() as i64;
    let k1 = (y1 / spacing).floor() as i64;
    if k1 < k0 {
        return Vec::new();
    }
    let mut rows: Vec<Vec<f64>> = vec![Vec::new(); (k1 - k0 + 1) as usize];
    for r in rings {
        for i in 0..r.len() {
            let (ax, ay) = to(&r[i]);
            let (bx, by) = to(&r[(i + 1) % r.len()]);
            if ay == by {
                continue;
            }
            // Half-open in y so a vertex on a scan line counts once.
            let (lo, hi) = (ay.min(by), ay.max(by));
            let mut k = (lo / spacing).ceil() as i64;
            while (k as f64) * spacing < hi {
                let y = k as f64 * spacing;
                if y >= lo && k >= k0 && k <= k1 {
                    rows[(k - k0) as usize].push(ax + (y - ay) / (by - ay) * (bx - ax));
                }
                k += 1;
            }
        }
    }
    let mut out = Vec::new();
    for (i, xs) in rows.iter_mut().enumerate() {
        xs.sort_by(f64::total_cmp);
        let y = (k0 + i as i64) as f64 * spacing;
        for pair in xs.chunks_exact(2) {
            if pair[1] > pair[0] {
                out.push(vec![back(pair[0], y), back(pair[1], y)]);
            }
        }
    }
    out
}

/// Rings inset by `spacing`, 2·`spacing`, … until nothing is left.
fn concentric(regions: &[Region], spacing: f64, tol: f64) -> Result<Vec<Stroke>, String> {
    let close = |r: &Ring| -> Stroke {
        let mut s: Stroke = r.iter().map(|p| Point::new(p[0], p[1])).collect();
        if let Some(&f) = s.first() {
            s.push(f);
        }
        s
    };
    let mut out = Vec::new();
    let mut cur = regions.to_vec();
    let join = Join::Round {
        tolerance: tol.max(1e-3),
    };
    while !cur.is_empty() {
        cur = offset_regions(&cur, -spacing, join).map_err(|e| e.to_string())?;
        for r in &cur {
            out.push(close(&r.outer));
            out.extend(r.holes.iter().map(close));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use oficina_geom::{simplify, Fill};

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Ring {
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }

    fn len(v: &[Stroke]) -> f64 {
        v.iter().map(|s| crate::polyline_length(s)).sum()
    }

    #[test]
    fn hatch_length_is_area_over_spacing_and_holes_stay_empty() {
        // 20 × 10 with a 4 × 4 hole: area 184, hatch length ≈ area / spacing.
        let rings = vec![square(0.0, 0.0, 20.0, 10.0), square(8.0, 3.0, 12.0, 7.0)];
        let regions = simplify(&rings, Fill::EvenOdd).unwrap();
        let mut budget = MAX_FILL_LINES;
        for angle in [0.0, 30.0, 45.0, 90.0] {
            let s = FillStyle {
                angle,
                spacing: 0.5,
                ..FillStyle::default()
            };
            let h = fill_regions(&regions, &s, 0.01, &mut budget).unwrap();
            let l = len(&h);
            assert!((l * 0.5 - 184.0).abs() < 184.0 * 0.03, "{angle}: {l}");
            for p in h.iter().flat_map(|s| [s[0].midpoint(s[1])]) {
                assert!(
                    !(p.x > 8.0 && p.x < 12.0 && p.y > 3.0 && p.y < 7.0),
                    "{p:?}"
                );
            }
        }
        let cross = FillStyle {
            spacing: 0.5,
            cross: true,
            ..FillStyle::default()
        };
        let l = len(&fill_regions(&regions, &cross, 0.01, &mut budget).unwrap());
        assert!((l * 0.5 - 368.0).abs() < 368.0 * 0.03, "{l}");
        // Concentric: rings of a 10 × 10 square at 1 mm: 8×4·… perimeters 32, 24, 16, 8.
        let sq = simplify(&[square(0.0, 0.0, 10.0, 10.0)], Fill::NonZero).unwrap();
        let c = FillStyle {
            spacing: 1.0,
            concentric: true,
            ..FillStyle::default()
        };
        let l = len(&fill_regions(&sq, &c, 0.01, &mut budget).unwrap());
        assert!((l - (32.0 + 24.0 + 16.0 + 8.0)).abs() < 1.0, "{l}");
    }

    #[test]
    fn tiny_spacing_is_refused() {
        let sq = simplify(&[square(0.0, 0.0, 10.0, 10.0)], Fill::NonZero).unwrap();
        let mut budget = MAX_FILL_LINES;
        let s = FillStyle {
            spacing: 1e-9,
            ..FillStyle::default()
        };
        let e = fill_regions(&sq, &s, 0.01, &mut budget).unwrap_err();
        assert!(e.contains("larger spacing"), "{e}");
        for bad in [0.0, -1.0, f64::NAN] {
            let s = FillStyle {
                spacing: bad,
                ..FillStyle::default()
            };
            assert!(fill_regions(&sq, &s, 0.01, &mut budget).is_err());
        }
    }
}
