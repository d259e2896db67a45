//! The region a cut on the line may take, for the stock check: every point within the tool
//! radius of the path, built from a capsule per flattened piece (a rectangle and the circles
//! at its ends), so a job with an engraving is still checked against its drawing.

use super::mill::GOUGE_TOL;
use super::profile::OFFSET_TOL;
use super::OpError;
use oficina_geom::{ring_area, simplify, Fill, Path, Ring};

/// Sides of each end circle.
const SIDES: usize = 32;

/// Rings (even–odd) of the points within `radius` (+ [`GOUGE_TOL`]) of `paths`.
pub fn groove_region(paths: &[Path], radius: f64) -> Result<Vec<Ring>, OpError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(OpError::Invalid(format!("groove radius {radius}")));
    }
    // Circumscribed polygons: their sides stay outside the true circle.
    let r = (radius + GOUGE_TOL) / (std::f64::consts::PI / SIDES as f64).cos();
    let mut rings: Vec<Ring> = Vec::new();
    for p in paths {
        let mut pts: Vec<[f64; 2]> = p
            .flatten(OFFSET_TOL / 10.0)
            .iter()
            .map(|q| [q.x, q.y])
            .collect();
        if p.closed {
            if let Some(&first) = pts.first() {
                pts.push(first);
            }
        }
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l = dx.hypot(dy);
            if l > 1e-9 {
                let (nx, ny) = (-dy / l * r, dx / l * r);
                rings.push(ccw(vec![
                    [a[0] + nx, a[1] + ny],
                    [a[0] - nx, a[1] - ny],
                    [b[0] - nx, b[1] - ny],
                    [b[0] + nx, b[1] + ny],
                ]));
            }
        }
        for c in &pts {
            rings.push(
                (0..SIDES)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / SIDES as f64;
                        [c[0] + r * t.cos(), c[1] + r * t.sin()]
                    })
                    .collect(),
            );
        }
    }
    // All counter-clockwise: non-zero winding is their union.
    Ok(simplify(&rings, Fill::NonZero)
        .map_err(|e| OpError::Geometry(e.to_string()))?
        .into_iter()
        .flat_map(|g| std::iter::once(g.outer).chain(g.holes))
        .collect())
}

fn ccw(mut ring: Ring) -> Ring {
    if ring_area(&ring) < 0.0 {
        ring.reverse();
    }
    ring
}
