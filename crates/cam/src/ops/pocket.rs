//! Clearing the inside of closed contours (with islands): contour-parallel from the centre
//! out as in seed 001 §4.4, or zig-zag rows followed by a contour pass; both leave the
//! pre-finish allowance on the walls for one finishing pass at the tool radius at full
//! depth. Pockets that split into several regions are handled by the offsets themselves.

use super::chain::{Chain, Rings, P};
use super::entry::{enter_loop, enter_open, helix, Entry};
use super::profile::OFFSET_TOL;
use super::{Builder, Cut, OpError, RAPID_GAP};
use crate::Operation;
use oficina_geom::{offset_areas, Area, Path};

/// How a pocket is cleared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Offsets of the wall, innermost first, linked by feed moves without retracting.
    Offset,
    /// Parallel rows along X, alternating direction, then one contour pass.
    ZigZag,
}

/// Pocket parameters besides the cut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PocketParams {
    /// Offsets or zig-zag.
    pub strategy: Strategy,
    /// Distance between passes, mm: the seed's "porcentagem de corte", 0.5–0.75 × D.
    pub stepover: f64,
    /// Stock left on the walls for the finishing pass, mm (0: roughing cuts to size).
    pub allowance: f64,
}

impl PocketParams {
    /// Seed 001 defaults for a tool of diameter `d`: step-over 0.6·D, 0.2 mm allowance.
    pub fn for_tool(strategy: Strategy, d: f64) -> PocketParams {
        PocketParams {
            strategy,
            stepover: 0.6 * d,
            allowance: 0.2,
        }
    }
}

/// Most offset rings one pocket may need (a 10 m pocket at 0.1 mm steps): beyond it the
/// input is absurd, and an error says so rather than running out of memory.
const MAX_RINGS: usize = 100_000;

/// Clears the inside of the closed `paths` (holes stay) with `cut`.
pub fn pocket(
    name: &str,
    paths: &[Path],
    cut: &Cut,
    p: &PocketParams,
) -> Result<Operation, OpError> {
    cut.validate()?;
    let d = cut.tool.diameter;
    if !(p.stepover > 0.0 && p.stepover <= d) {
        return Err(OpError::Invalid(format!(
            "step-over {} mm: use more than 0 and at most the tool diameter {d} mm (0.5–0.75·D is usual)",
            p.stepover
        )));
    }
    if !(p.allowance.is_finite() && p.allowance >= 0.0) {
        return Err(OpError::Invalid("the allowance must be 0 or more".into()));
    }
    let areas = Area::from_paths(paths);
    if areas.is_empty() {
        return Err(OpError::Empty("no closed contour to pocket".into()));
    }
    let r = cut.radius();
    let geo = |e: oficina_geom::PolygonError| OpError::Geometry(e.to_string());
    let finish = offset_areas(&areas, -r, OFFSET_TOL).map_err(geo)?;
    if finish.is_empty() {
        return Err(OpError::Empty(format!(
            "every pocket is narrower than the {d} mm tool"
        )));
    }
    // Where a feed link may go: the tool-centre space, 10 µm generous so links that end
    // on the finishing contour count as inside.
    let link_rings = Rings::new(
        offset_areas(&areas, -(r - 0.01), OFFSET_TOL)
            .map_err(geo)?
            .iter()
            .flat_map(|a| {
                a.paths()
                    .map(|p| Chain::from_path(p).polygon(0.005))
                    .collect::<Vec<_>>()
            })
            .collect(),
    );
    let rough = if p.allowance > 0.0 {
        offset_areas(&finish, -p.allowance, OFFSET_TOL).map_err(geo)?
    } else {
        finish.clone()
    };
    let mut b = Builder::new(cut.clear_z);
    let mut z_prev = cut.top;
    match p.strategy {
        Strategy::Offset => {
            let mut rings = Vec::new();
            for a in &rough {
                centre_out(a, p.stepover, r, &mut rings)?;
            }
            for level in cut.levels() {
                cut_rings(&mut b, &rings, cut, &link_rings, z_prev, level, r)?;
                z_prev = level;
            }
        }
        Strategy::ZigZag => {
            let rows = zigzag_rows(&rough, p.stepover);
            let walls: Vec<Chain> = rough.iter().flat_map(loops_of).collect();
            for level in cut.levels() {
                cut_rows(&mut b, &rows, cut, &link_rings, z_prev, level)?;
                let wall_rings: Vec<Ring> = walls
                    .iter()
                    .map(|c| Ring {
                        chain: c.clone(),
                        leaf: None,
                    })
                    .collect();
                cut_rings(&mut b, &wall_rings, cut, &link_rings, z_prev, level, r)?;
                z_prev = level;
            }
        }
    }
    if p.allowance > 0.0 {
        let walls: Vec<Ring> = finish
            .iter()
            .flat_map(loops_of)
            .map(|chain| Ring { chain, leaf: None })
            .collect();
        // The allowance band still stands to the top: a loop entered by ramp comes down
        // from the top, one reached by a link at full depth only moves sideways into it.
        cut_rings(&mut b, &walls, cut, &link_rings, cut.top, cut.bottom(), r)?;
    }
    Ok(cut.operation(name, b.finish(cut.clear_z)))
}

/// A loop to cut, and for the innermost loops of a region the area it encloses (where a
/// helix may go down).
struct Ring {
    chain: Chain,
    leaf: Option<Area>,
}

/// The loops of an area: its outer boundary (counter-clockwise: climb on a pocket wall) and
/// its holes (clockwise round islands).
fn loops_of(a: &Area) -> Vec<Chain> {
    a.paths()
        .map(Chain::from_path)
        .filter(|c| !c.pieces.is_empty())
        .collect()
}

/// The offsets of `a` inward by `step` until nothing is left, pushed innermost first (each
/// region's own rings after its children's), so cutting goes from the centre out. A last
/// ring at 0.9·r inside a leaf leaves no island at its centre: without it a leaf up to a
/// step-over wide could keep material farther than r from its loop.
fn centre_out(a: &Area, step: f64, r: f64, out: &mut Vec<Ring>) -> Result<(), OpError> {
    if out.len() > MAX_RINGS {
        return Err(OpError::Invalid(format!(
            "more than {MAX_RINGS} offset rings: the step-over is too small for this pocket"
        )));
    }
    let geo = |e: oficina_geom::PolygonError| OpError::Geometry(e.to_string());
    let mut children = offset_areas(std::slice::from_ref(a), -step, OFFSET_TOL).map_err(geo)?;
    if children.is_empty() && step > 0.9 * r {
        children = offset_areas(std::slice::from_ref(a), -0.9 * r, OFFSET_TOL).map_err(geo)?;
    }
    for c in &children {
        centre_out(c, step, r, out)?;
    }
    let leaf = children.is_empty().then(|| a.clone());
    for (k, chain) in loops_of(a).into_iter().enumerate() {
        out.push(Ring {
            chain,
            leaf: if k == 0 { leaf.clone() } else { None },
        });
    }
    Ok(())
}

/// Feeds along `level` to the start of `chain` and cuts once around it.
fn around_from_start(b: &mut Builder, chain: &Chain, level: f64, feed: f64) {
    let to = chain.start();
    b.line([to[0], to[1], level], feed);
    let mut moves = Vec::new();
    chain.walk(&[(0.0, level), (chain.length(), level)], feed, &mut moves);
    b.extend(moves);
}

/// Cuts `rings` in order at `level`: each is reached by a feed link from where the tool is
/// when the straight link stays in the pocket, else by a retract and a new entry from
/// `z_prev` (the floor already cut there).
fn cut_rings(
    b: &mut Builder,
    rings: &[Ring],
    cut: &Cut,
    link: &Rings,
    z_prev: f64,
    level: f64,
    r: f64,
) -> Result<(), OpError> {
    let at_level = |b: &Builder| (b.at[2] - level).abs() < 1e-9;
    for ring in rings {
        let here = [b.at[0], b.at[1]];
        let (s, dist) = ring.chain.nearest(here);
        let chain = ring.chain.rotated(s);
        let linked = at_level(b) && dist < 2.0 * cut.tool.diameter + 1e-9 && {
            let to = chain.start();
            link.segment_inside(here, to)
        };
        if linked {
            around_from_start(b, &chain, level, cut.feed);
            continue;
        }
        let z_from = z_prev + RAPID_GAP;
        let helix_at = match (cut.entry, &ring.leaf) {
            (Entry::Helix { radius, .. }, Some(leaf)) => helix_centre(leaf, radius, r)?,
            _ => None,
        };
        match (helix_at, cut.entry) {
            (Some(c), Entry::Helix { radius, angle }) => {
                let start = [c[0] + radius, c[1]];
                b.travel(cut.clear_z, start, z_from);
                helix(
                    b,
                    c,
                    radius,
                    angle.to_radians(),
                    z_from,
                    level,
                    cut.plunge_feed,
                );
                let (s, _) = ring.chain.nearest(start);
                let chain = ring.chain.rotated(s);
                // The helix sits inside the innermost loop's area: the link stays there.
                around_from_start(b, &chain, level, cut.feed);
            }
            _ => {
                let start = ring.chain.start();
                b.travel(cut.clear_z, start, z_from);
                let run = enter_loop(b, &ring.chain, cut.entry, z_from, level, cut.plunge_feed);
                let len = ring.chain.length();
                let mut moves = Vec::new();
                ring.chain
                    .walk(&[(run, level), (run + len, level)], cut.feed, &mut moves);
                b.extend(moves);
            }
        }
    }
    Ok(())
}

/// A centre for a helix of `radius` inside `leaf` (tool-centre space), if one fits with a
/// radius-wide margin and leaves no core uncut (radius ≥ r/4).
fn helix_centre(leaf: &Area, radius: f64, r: f64) -> Result<Option<[f64; 2]>, OpError> {
    if radius < r / 4.0 {
        return Ok(None);
    }
    let room = offset_areas(std::slice::from_ref(leaf), -radius, OFFSET_TOL)
        .map_err(|e| OpError::Geometry(e.to_string()))?;
    Ok(room
        .first()
        .and_then(|a| a.outer.start())
        .map(|p| [p.x, p.y]))
}

/// Rows of a zig-zag, alternating direction: each a list of straight spans inside the areas.
fn zigzag_rows(areas: &[Area], step: f64) -> Vec<Vec<(P, P)>> {
    let rings: Vec<Vec<P>> = areas
        .iter()
        .flat_map(|a| {
            a.paths()
                .map(|p| Chain::from_path(p).polygon(0.005))
                .collect::<Vec<_>>()
        })
        .collect();
    let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
    for r in &rings {
        for p in r {
            y0 = y0.min(p[1]);
            y1 = y1.max(p[1]);
        }
    }
    if !(y1 > y0) {
        return vec![];
    }
    // Equal rows no farther apart than `step`, the outer ones 10 µm in from the extremes.
    let margin = 0.01f64.min((y1 - y0) / 4.0);
    let span = y1 - y0 - 2.0 * margin;
    let n = (span / step).ceil().max(1.0) as usize;
    let mut rows = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let y = y0 + margin + span * k as f64 / n as f64;
        let mut xs = Vec::new();
        for r in &rings {
            let m = r.len();
            for i in 0..m {
                let (a, b) = (r[i], r[(i + 1) % m]);
                if (a[1] > y) != (b[1] > y) {
                    xs.push(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        let mut spans: Vec<(P, P)> = xs
            .chunks_exact(2)
            .filter(|c| c[1] - c[0] > 1e-6)
            .map(|c| ([c[0], y], [c[1], y]))
            .collect();
        if k % 2 == 1 {
            spans.reverse();
            for s in &mut spans {
                *s = (s.1, s.0);
            }
        }
        rows.push(spans);
    }
    rows
}

fn cut_rows(
    b: &mut Builder,
    rows: &[Vec<(P, P)>],
    cut: &Cut,
    link: &Rings,
    z_prev: f64,
    level: f64,
) -> Result<(), OpError> {
    for &(a, e) in rows.iter().flatten() {
        let here = [b.at[0], b.at[1]];
        let chain = Chain {
            pieces: vec![super::chain::Piece::Line { a, b: e }],
            closed: false,
        };
        let linked = (b.at[2] - level).abs() < 1e-9 && link.segment_inside(here, a);
        if linked {
            b.line([a[0], a[1], level], cut.feed);
        } else {
            let z_from = z_prev + RAPID_GAP;
            b.travel(cut.clear_z, a, z_from);
            enter_open(b, &chain, cut.entry, z_from, level, cut.plunge_feed)?;
        }
        b.line([e[0], e[1], level], cut.feed);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::chain::inside;
    use super::*;

    #[test]
    fn rows_are_inside_the_area() {
        let sq = Path::polyline(
            &[
                (0.0, 0.0).into(),
                (10.0, 0.0).into(),
                (10.0, 10.0).into(),
                (0.0, 10.0).into(),
            ],
            true,
        );
        let areas = Area::from_paths(&[sq]);
        let rows = zigzag_rows(&areas, 3.0);
        assert_eq!(rows.len(), 5);
        let ring = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        for (a, b) in rows.iter().flatten() {
            assert!(inside(
                std::slice::from_ref(&ring),
                [(a[0] + b[0]) / 2.0, a[1]]
            ));
        }
    }
}
