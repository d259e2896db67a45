//! Z-level roughing on the mesh itself: at each step-down level the tool clears every place
//! it fits without coming nearer the model than the allowance, by contour-parallel passes.
//!
//! The tool grown by the allowance `a` (its Minkowski sum with a ball of radius `a`: a flat
//! of radius R becomes a bull of radius R + a and corner a, a ball of radius r a ball of
//! r + a, a bull (R, c) a bull (R + a, c + a)) has its tip `a` below the real tool's. The
//! real tool at tip height `z` over `p` stays `a` from the model exactly where the grown
//! tool's drop-cutter height `d(p)` is at most `z − a`; the boundary of that set is the
//! grown tool's waterline at `z − a` ([`loops_at`]). The region the tool centre may sweep
//! at the level is the stock's box (its boundary pass clears the rim) less the inside of
//! those loops; its insets every step-over are the passes, cut outside in.
//!
//! Every level clears its whole region: the regions shrink going down (`d` does not depend
//! on `z`), so what a level cuts under is stock the levels above left.

use super::waterline::{loops_at, ContactGrid};
use super::DropCutter;
use crate::ops::{Chain, Entry, Piece};
use crate::{CutterShape, Move, Tool};
use oficina_geom::{boolean, offset_steps, BoolOp, Fill, Region, Ring};

/// A z-level roughing pass (mm, mm/s).
#[derive(Clone, Debug)]
pub struct ZLevel {
    /// Distance between contours (at most the tool's diameter).
    pub stepover: f64,
    /// Distance between levels.
    pub stepdown: f64,
    /// Material kept on the model, measured from the tool's surface.
    pub allowance: f64,
    /// Largest dip of a straight move into the grown tool's no-go zone, and of offsets.
    pub tolerance: f64,
    /// Stock top: the first level is one step-down below.
    pub top: f64,
    /// Stock bottom: the last level.
    pub floor: f64,
    /// The stock's XY box: min x, min y, max x, max y.
    pub stock: [f64; 4],
    /// Absolute height for rapids.
    pub safe: f64,
    /// Above cut stock, how high the tool comes down fast before plunging.
    pub clearance: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Plunge feed.
    pub plunge: f64,
    /// The roughing tool's radius (its entries: ramps round rings at least this long,
    /// lead-ins from this far outside the stock).
    pub radius: f64,
}

/// `tool` grown by `a` mm all round (see the module's comment); V and tapered tools have
/// no such bull or ball and are refused.
pub fn grown(tool: &Tool, a: f64) -> Result<Tool, String> {
    let d = tool.diameter + 2.0 * a;
    let shape = match tool.shape {
        CutterShape::Flat if a == 0.0 => CutterShape::Flat,
        CutterShape::Flat => CutterShape::Bull { corner_radius: a },
        CutterShape::Ball => CutterShape::Ball,
        CutterShape::Bull { corner_radius } => CutterShape::Bull {
            corner_radius: corner_radius + a,
        },
        _ => {
            return Err(format!(
                "z-level roughing takes a flat, ball or bull tool, not {}",
                tool.spec()
            ))
        }
    };
    Tool::new(shape, d).map_err(|e| e.to_string())
}

/// The contact grid's step for a grown tool of `radius`: a quarter of it (no feature of the
/// drop height narrower than the tool is missed), at most 0.5 mm.
pub(super) fn grid_step(radius: f64) -> f64 {
    (radius / 4.0).clamp(0.02, 0.5)
}

/// The contact grid's extent: the stock box grown by the grown tool's reach and two steps,
/// so every no-go loop closes inside the grid.
pub(super) fn grid_region(z: &ZLevel, reach: f64, step: f64) -> [f64; 4] {
    let g = reach + 2.0 * step;
    [
        z.stock[0] - g,
        z.stock[1] - g,
        z.stock[2] + g,
        z.stock[3] + g,
    ]
}

/// Bytes the contact grid of [`rough`] takes for a grown tool of `radius`.
pub fn bytes_estimate(z: &ZLevel, radius: f64) -> u64 {
    let step = grid_step(radius);
    ContactGrid::bytes_estimate(grid_region(z, radius, step), step)
}

/// The tip heights of the levels, top down: every step-down below the top, the floor last.
pub(super) fn levels(top: f64, floor: f64, stepdown: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut k = 1;
    loop {
        let z = top - k as f64 * stepdown;
        if z <= floor + 1e-6 {
            out.push(floor);
            return out;
        }
        out.push(z);
        k += 1;
    }
}

/// Where the tool centre may go at tip height `z`: the stock box (its boundary pass sweeps
/// the band a radius wide inside it, and the machine's travel is the stock's) less the
/// grown tool's no-go loops at `z − allowance`.
pub(super) fn region_at(
    grown: &DropCutter,
    g: &ContactGrid,
    z: &ZLevel,
    level: f64,
) -> Result<Vec<Region>, String> {
    let s = z.stock;
    let rect: Ring = vec![[s[0], s[1]], [s[2], s[1]], [s[2], s[3]], [s[0], s[3]]];
    let loops: Vec<Ring> = loops_at(grown, g, level - z.allowance, z.tolerance)
        .into_iter()
        .map(|lp| lp[..lp.len() - 1].iter().map(|p| [p[0], p[1]]).collect())
        .collect();
    boolean(&[rect], &loops, BoolOp::Difference, Fill::EvenOdd).map_err(|e| e.0)
}

/// The contours cut at one level, outside in within each part of the region: its
/// boundary, insets every step-over, and one more half a step-over in where the last full
/// one leaves a core (a point there would be up to a whole step-over from any pass).
pub(super) fn contours(region: &[Region], z: &ZLevel) -> Result<Vec<(usize, Vec<Ring>)>, String> {
    let tol = z.tolerance.max(1e-3);
    let steps = offset_steps(region, 0.0, -z.stepover, 100_000, tol).map_err(|e| e.0)?;
    let mut out: Vec<(usize, Vec<Ring>)> = Vec::new();
    for rs in &steps {
        for r in rs {
            let part = region
                .iter()
                .position(|p| inside(p, r.outer[0]))
                .unwrap_or(0);
            out.push((part, rings_of(r)));
        }
    }
    if let Some(last) = steps.last() {
        let core = oficina_geom::offset_regions(
            last,
            -z.stepover / 2.0,
            oficina_geom::Join::Round { tolerance: tol },
        )
        .map_err(|e| e.0)?;
        for r in &core {
            let part = region
                .iter()
                .position(|p| inside(p, r.outer[0]))
                .unwrap_or(0);
            out.push((part, rings_of(r)));
        }
    }
    // Stable: each part's contours keep their outside-in order.
    out.sort_by_key(|c| c.0);
    Ok(out)
}

/// The outer ring then the holes.
fn rings_of(r: &Region) -> Vec<Ring> {
    std::iter::once(&r.outer).chain(&r.holes).cloned().collect()
}

/// Whether `p` is in the region (on its boundary counts either way: insets lie well in).
fn inside(r: &Region, p: [f64; 2]) -> bool {
    // The crossing rule of ops::chain, ring by ring (no copies per point).
    let one = |ring: &Ring| crate::ops::inside(std::slice::from_ref(ring), p);
    one(&r.outer) && !r.holes.iter().any(one)
}

/// Whether the segment `a`–`b` crosses any edge of `rings` (touching does not count).
fn crosses(a: [f64; 2], b: [f64; 2], rings: &[&Ring]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    rings.iter().any(|ring| {
        let n = ring.len();
        (0..n).any(|i| {
            let (c, d) = (ring[i], ring[(i + 1) % n]);
            let (o1, o2) = (orient(a, b, c), orient(a, b, d));
            let (o3, o4) = (orient(c, d, a), orient(c, d, b));
            o1 * o2 < 0.0 && o3 * o4 < 0.0
        })
    })
}

/// The roughing moves of `z` with `tool` on the mesh `grown` was made from (for `tool`
/// grown by the allowance), top level first; `stop` is read between levels (and makes
/// `grown`'s drops return at once when it is the cutter's cancel flag).
pub fn rough(
    grown: &DropCutter,
    tool: &Tool,
    z: &ZLevel,
    stop: &dyn Fn() -> bool,
) -> Result<Vec<Move>, String> {
    if !(z.stepover > 0.0 && z.stepover <= tool.diameter + 1e-9) {
        return Err(format!(
            "roughing step-over {} mm: above 0 and at most the tool's diameter {} mm",
            z.stepover, tool.diameter
        ));
    }
    if !(z.stepdown > 0.0 && z.allowance >= 0.0 && z.floor < z.top) {
        return Err(
            "z-level roughing: step-down above 0, allowance 0 or more, stock bottom below its top"
                .into(),
        );
    }
    let step = grid_step(grown.radius());
    let g = ContactGrid::new(grown, grid_region(z, grown.radius(), step), step);
    let mut moves = Vec::new();
    let mut at: Option<[f64; 3]> = None;
    let mut above = z.top;
    for level in levels(z.top, z.floor, z.stepdown) {
        if stop() {
            return Err("cancelled".into());
        }
        let region = region_at(grown, &g, z, level)?;
        let all: Vec<&Ring> = region
            .iter()
            .flat_map(|r| std::iter::once(&r.outer).chain(&r.holes))
            .collect();
        let mut part_at: Option<usize> = None;
        for (part, rings) in contours(&region, z)? {
            for ring in rings {
                // Start at the vertex nearest where the tool is.
                let from = at.unwrap_or([ring[0][0], ring[0][1], z.safe]);
                let k = (0..ring.len())
                    .min_by(|&i, &j| {
                        let d = |p: [f64; 2]| (p[0] - from[0]).hypot(p[1] - from[1]);
                        d(ring[i]).total_cmp(&d(ring[j]))
                    })
                    .unwrap_or(0);
                let s = ring[k];
                let near = (s[0] - from[0]).hypot(s[1] - from[1]) <= 2.0 * z.stepover;
                let stay = at.is_some_and(|p| p[2] == level)
                    && part_at == Some(part)
                    && near
                    && !crosses([from[0], from[1]], s, &all);
                let (k, skip) = if stay {
                    moves.push(Move::Line {
                        to: [s[0], s[1], level],
                        feed: z.feed,
                    });
                    (k, 0.0)
                } else {
                    if let Some(p) = at {
                        moves.push(Move::Rapid {
                            to: [p[0], p[1], z.safe],
                        });
                    }
                    // Over the way in, and fast down to just above the stock the level above
                    // left (the start is in this level's region, so in the one above).
                    let way_in = lead_in(grown, z, &ring, from, level);
                    let over = way_in.map_or(s, |(_, o)| o);
                    moves.push(Move::Rapid {
                        to: [over[0], over[1], z.safe],
                    });
                    let fast = (above + z.clearance).min(z.safe);
                    if fast < z.safe {
                        moves.push(Move::Rapid {
                            to: [over[0], over[1], fast],
                        });
                    }
                    match way_in {
                        // From outside the stock: down in air, then in along the level.
                        Some((k, o)) => {
                            moves.push(Move::Line {
                                to: [o[0], o[1], level],
                                feed: z.plunge,
                            });
                            moves.push(Move::Line {
                                to: [ring[k][0], ring[k][1], level],
                                feed: z.feed,
                            });
                            (k, 0.0)
                        }
                        None => (k, enter_ring(&mut moves, &ring, k, above, level, z)),
                    }
                };
                let end = cut_ring(&mut moves, &ring, k, skip, level, z.feed);
                at = Some([end[0], end[1], level]);
                part_at = Some(part);
            }
        }
        above = level;
    }
    if let Some(p) = at {
        moves.push(Move::Rapid {
            to: [p[0], p[1], z.safe],
        });
    }
    Ok(moves)
}

/// The ramp's angle from horizontal into material, radians: the ops' default entry.
fn ramp_angle() -> f64 {
    Entry::default().angle().unwrap_or(3f64.to_radians())
}

/// `ring` as a closed chain starting at its vertex `k`.
fn ring_chain(ring: &Ring, k: usize) -> Chain {
    let n = ring.len();
    let mut pieces: Vec<Piece> = (0..n)
        .map(|i| Piece::Line {
            a: ring[(k + i) % n],
            b: ring[(k + i + 1) % n],
        })
        .collect();
    pieces.retain(|p| p.length() > 1e-9);
    Chain {
        pieces,
        closed: true,
    }
}

/// Once round `ring` from vertex `k` at `level`, beginning `skip` mm along it; where it
/// ends.
fn cut_ring(
    moves: &mut Vec<Move>,
    ring: &Ring,
    k: usize,
    skip: f64,
    level: f64,
    feed: f64,
) -> [f64; 2] {
    let chain = ring_chain(ring, k);
    let len = chain.length();
    if len <= 0.0 {
        return ring[k];
    }
    chain.walk(&[(skip, level), (skip + len, level)], feed, moves);
    chain.point_at(skip % len)
}

/// Into material at vertex `k` of `ring`, from the level `above` down to `level`: along
/// the ring at the ramp angle (round it more than once where it is short: a helix on the
/// ring); returns how far along the ring the descent ended, where the pass round the ring
/// at the level starts (so the ramp's stretch is cut again at full depth). Every point of
/// the ring is in this level's region, so in every region above (they only shrink going
/// down): the descent keeps the allowance as the level does. A ring shorter than the
/// tool's radius leaves no room to ramp: there the tool goes straight down, as the height
/// field's roughing does.
fn enter_ring(
    moves: &mut Vec<Move>,
    ring: &Ring,
    k: usize,
    above: f64,
    level: f64,
    z: &ZLevel,
) -> f64 {
    let s = ring[k];
    // Down through what the level above cleared (in air).
    moves.push(Move::Line {
        to: [s[0], s[1], above],
        feed: z.plunge,
    });
    let chain = ring_chain(ring, k);
    if chain.length() < z.radius.max(1e-3) {
        moves.push(Move::Line {
            to: [s[0], s[1], level],
            feed: z.plunge,
        });
        return 0.0;
    }
    let run = (above - level).max(0.0) / ramp_angle().tan();
    chain.walk(&[(0.0, above), (run, level)], z.feed, moves);
    run
}

/// Where `ring` can be entered from outside the stock: of its vertices on the stock's box,
/// the nearest `from` with a clear way in, and the point the tool's radius plus the
/// clearance (at least 1 mm) out from that side. Fed in along the side's normal from
/// there, the tool only covers ground inside the box that it covers at the vertex (a disc
/// t out along the normal meets the box within sqrt(R² − t²) of the vertex), so it comes
/// no nearer the model there than at the vertex; the drop-cutter checks the way outside
/// the box, where a model could overhang its stock.
fn lead_in(
    grown: &DropCutter,
    z: &ZLevel,
    ring: &Ring,
    from: [f64; 3],
    level: f64,
) -> Option<(usize, [f64; 2])> {
    const ON: f64 = 1e-6;
    let b = z.stock;
    let out = z.radius + z.clearance.max(1.0);
    let normal = |p: [f64; 2]| -> Option<[f64; 2]> {
        if (p[0] - b[0]).abs() < ON {
            Some([-1.0, 0.0])
        } else if (p[0] - b[2]).abs() < ON {
            Some([1.0, 0.0])
        } else if (p[1] - b[1]).abs() < ON {
            Some([0.0, -1.0])
        } else if (p[1] - b[3]).abs() < ON {
            Some([0.0, 1.0])
        } else {
            None
        }
    };
    let d = |p: [f64; 2]| (p[0] - from[0]).hypot(p[1] - from[1]);
    let mut on_box: Vec<(usize, [f64; 2])> = ring
        .iter()
        .enumerate()
        .filter_map(|(k, &p)| normal(p).map(|n| (k, [p[0] + n[0] * out, p[1] + n[1] * out])))
        .collect();
    on_box.sort_by(|a, b| d(ring[a.0]).total_cmp(&d(ring[b.0])));
    let clear = level - z.allowance;
    let steps = (out / (z.radius / 4.0).max(0.05)).ceil() as usize;
    on_box.into_iter().take(8).find(|&(k, o)| {
        let s = ring[k];
        (0..=steps).all(|i| {
            let t = i as f64 / steps as f64;
            let p = [s[0] + t * (o[0] - s[0]), s[1] + t * (o[1] - s[1])];
            grown.drop(p[0], p[1]).is_none_or(|h| h <= clear + 1e-9)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_end_on_the_floor() {
        assert_eq!(levels(10.0, 0.0, 4.0), vec![6.0, 2.0, 0.0]);
        assert_eq!(levels(10.0, 0.0, 5.0), vec![5.0, 0.0]);
    }

    #[test]
    fn a_grown_flat_is_a_bull_and_a_v_is_refused() {
        let t = grown(&Tool::new(CutterShape::Flat, 6.0).unwrap(), 0.5).unwrap();
        assert_eq!(t.diameter, 7.0);
        assert_eq!(t.shape, CutterShape::Bull { corner_radius: 0.5 });
        let v = Tool::new(CutterShape::V { angle: 90.0 }, 6.0).unwrap();
        assert!(grown(&v, 0.5).unwrap_err().contains("flat, ball or bull"));
    }
}
