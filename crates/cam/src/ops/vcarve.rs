//! V-carving (2.5D) with a V bit of included angle θ.
//!
//! **Closed shapes.** The ideal carving lowers each point p of the shape to
//! z(p) = top − min(dist(p, outline) / tan(θ/2), depth): walls at the bit's own slope, a
//! flat floor where the cap `depth` is reached. A tool tip at a centre c at depth
//! h(c) = min(dist(c) / tan(θ/2), depth) never cuts below that surface: its cone at p is at
//! −h(c) + |p − c| / tan(θ/2), and dist(p) ≥ dist(c) − |p − c| (distance is 1-Lipschitz), so
//! the cone stays above −dist(p) / tan(θ/2); where the cap holds it stays above −depth.
//!
//! The method (a standard approximation of the medial axis by dense offsets): the tool
//! follows the insets of the outline at distances d_k = k·δ, each at depth h(d_k). Along an
//! inset the cone cuts the exact wall from the outline to itself; between the last inset
//! that still exists and the medial axis (less than δ further in) the next cone is missing,
//! so the ridge left there is at most 2·δ / tan(θ/2) high. Where the cap holds the insets
//! are 2·δ apart: a V bit at equal depth leaves cusps (2δ/2) / tan(θ/2) between them and a
//! ridge under 2δ / tan(θ/2) at the medial axis past the last one.
//! So δ = leftover · tan(θ/2) / 2 bounds the material left by `leftover`, and gouge is zero
//! up to the offsets' tolerance, which the depth gives away ([`OFFSET_TOL`] less distance).
//!
//! **Open strokes** (single-line fonts): the tool runs along the stroke at the depth that
//! cuts the stroke's width, (w/2) / tan(θ/2), or at `depth` when the stroke has no width or
//! that is deeper.
//!
//! Order: each shape from its outline inwards (outer insets first, so every pass takes a
//! thin layer), a region that splits carved one part at a time. Links between insets stay
//! at the depth of the inset one step outside the shallower of the two, over ground at least
//! that far from the outline (tested exactly against that inset's polygon); otherwise up to
//! the retraction plane. The V bit goes straight down at the plunge feed: it cuts under its
//! point.

use super::chain::{inside, Chain, P};
use super::profile::OFFSET_TOL;
use super::{Builder, Cut, OpError, RAPID_GAP};
use crate::{CutterShape, Operation};
use oficina_geom::{offset_areas, Area, Path};

/// V-carving parameters besides the cut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VCarveParams {
    /// Largest height of material left below the ideal surface (ridges at the medial axis,
    /// cusps on a capped floor), mm.
    pub leftover: f64,
}

impl Default for VCarveParams {
    fn default() -> Self {
        VCarveParams { leftover: 0.05 }
    }
}

/// Most insets one shape may need (each is an offset of the whole shape): 20,000 at the
/// default 0.05 mm leftover with a 90° bit reach 500 mm in; beyond it the step is absurd
/// for the drawing and the work would run for hours.
const MAX_INSETS: usize = 20_000;

/// tan(θ/2) of a V tool, or an error for other shapes.
pub fn half_tan(cut: &Cut) -> Result<f64, OpError> {
    match cut.tool.shape {
        CutterShape::V { angle } => Ok((angle.to_radians() / 2.0).tan()),
        _ => Err(OpError::Invalid(format!(
            "V-carving needs a V bit (v:DIAMETER:ANGLE), not {}",
            cut.tool.spec()
        ))),
    }
}

/// One inset to cut: its loop and the index of its level.
struct Inset {
    chain: Chain,
    level: usize,
}

/// The insets of one shape in cutting order, the distance of each level from the outline,
/// and each level's polygons (for the link test).
struct Levels {
    insets: Vec<Inset>,
    dists: Vec<f64>,
    polys: Vec<Vec<Vec<Vec<P>>>>,
}

/// V-carves the closed `paths` (depth from the distance to the outline) and the open ones
/// as strokes, with `cut`'s V tool.
pub fn vcarve(
    name: &str,
    paths: &[Path],
    cut: &Cut,
    p: &VCarveParams,
) -> Result<Operation, OpError> {
    cut.validate()?;
    let t = half_tan(cut)?;
    if !(p.leftover.is_finite() && p.leftover >= 0.001 && p.leftover <= 10.0) {
        return Err(OpError::Invalid(format!(
            "V-carving leftover {} mm: use 0.001 to 10",
            p.leftover
        )));
    }
    // The bit must be wide enough for the deepest cut: its cone is depth·tan(θ/2) wide.
    let widest = cut.depth * t;
    if widest > cut.tool.radius() + 1e-9 {
        return Err(OpError::Invalid(format!(
            "{} is {:.3} mm wide at the depth {} mm: the carving needs {:.3} mm (less --depth or a wider bit)",
            cut.tool.spec(),
            cut.tool.diameter,
            cut.depth,
            2.0 * widest
        )));
    }
    let delta = p.leftover * t / 2.0;
    let d_cap = cut.depth * t;
    // Distances of the insets: δ apart on the walls, 2δ apart on the capped floor.
    let mut dists = Vec::new();
    let mut d = delta;
    while d < d_cap {
        dists.push(d);
        d += delta;
        if dists.len() > MAX_INSETS {
            return Err(too_many());
        }
    }
    dists.push(d_cap);
    let depth_at = |d: f64| ((d - OFFSET_TOL).max(0.0) / t).min(cut.depth);
    let mut b = Builder::new(cut.clear_z);
    let areas = Area::from_paths(paths);
    for area in &areas {
        let levels = insets_of(area, &dists, 2.0 * delta)?;
        carve_insets(&mut b, cut, &levels, &depth_at);
    }
    // Open strokes: along the line at the stroke's depth.
    for path in paths.iter().filter(|p| !p.closed && !p.is_empty()) {
        let chain = Chain::from_path(path);
        if chain.pieces.is_empty() {
            continue;
        }
        let w = path.style.stroke_width;
        let h = if w > 0.0 {
            (w / 2.0 / t).min(cut.depth)
        } else {
            cut.depth
        };
        let start = chain.start();
        b.travel(cut.clear_z, start, cut.top + RAPID_GAP);
        b.line([start[0], start[1], cut.top - h], cut.plunge_feed);
        let mut moves = Vec::new();
        chain.walk(
            &[(0.0, cut.top - h), (chain.length(), cut.top - h)],
            cut.feed,
            &mut moves,
        );
        b.extend(moves);
    }
    if b.moves.is_empty() {
        return Err(OpError::Empty("nothing to carve".into()));
    }
    Ok(cut.operation(name, b.finish(cut.clear_z)))
}

fn too_many() -> OpError {
    OpError::Invalid(format!(
        "more than {MAX_INSETS} insets: raise the leftover or carve a smaller drawing"
    ))
}

/// The insets of `area` in cutting order (outline inwards, one split part at a time).
/// Levels past the last of `dists` go on `floor_step` apart until nothing is left.
fn insets_of(area: &Area, dists: &[f64], floor_step: f64) -> Result<Levels, OpError> {
    let geo = |e: oficina_geom::PolygonError| OpError::Geometry(e.to_string());
    // Every level: the inset areas at that distance, offset from the outline itself so the
    // error stays that of one offset.
    let mut levels: Vec<(f64, Vec<Area>)> = Vec::new();
    let mut k = 0;
    loop {
        let d = match dists.get(k) {
            Some(&d) => d,
            None => {
                dists.last().copied().unwrap_or(0.0) + floor_step * (k + 1 - dists.len()) as f64
            }
        };
        let inset = offset_areas(std::slice::from_ref(area), -d, OFFSET_TOL).map_err(geo)?;
        if inset.is_empty() {
            break;
        }
        levels.push((d, inset));
        k += 1;
        if k > MAX_INSETS {
            return Err(too_many());
        }
    }
    // Parent of each area: the area one level out that holds a point of it.
    let polys: Vec<Vec<Vec<Vec<P>>>> = levels
        .iter()
        .map(|(_, areas)| {
            areas
                .iter()
                .map(|a| {
                    a.paths()
                        .map(|p| Chain::from_path(p).polygon(OFFSET_TOL))
                        .collect()
                })
                .collect()
        })
        .collect();
    let mut children: Vec<Vec<Vec<usize>>> =
        levels.iter().map(|(_, a)| vec![vec![]; a.len()]).collect();
    let mut roots = Vec::new();
    for (l, (_, areas)) in levels.iter().enumerate() {
        for (i, a) in areas.iter().enumerate() {
            if l == 0 {
                roots.push(i);
                continue;
            }
            let probe = a.outer.start().map(|q| [q.x, q.y]).unwrap_or([0.0; 2]);
            let parent = polys[l - 1]
                .iter()
                .position(|rings| inside(rings, probe))
                .unwrap_or(0);
            children[l - 1][parent].push(i);
        }
    }
    let mut out = Vec::new();
    let mut stack: Vec<(usize, usize)> = roots.into_iter().rev().map(|i| (0, i)).collect();
    while let Some((l, i)) = stack.pop() {
        for path in levels[l].1[i].paths() {
            let chain = Chain::from_path(path);
            if !chain.pieces.is_empty() {
                out.push(Inset { chain, level: l });
            }
        }
        if l + 1 < levels.len() {
            for &c in children[l][i].iter().rev() {
                stack.push((l + 1, c));
            }
        }
    }
    Ok(Levels {
        insets: out,
        dists: levels.iter().map(|(d, _)| *d).collect(),
        polys,
    })
}

fn carve_insets(b: &mut Builder, cut: &Cut, levels: &Levels, depth_at: &dyn Fn(f64) -> f64) {
    let (dists, polys) = (&levels.dists, &levels.polys);
    let mut prev: Option<usize> = None;
    for inset in &levels.insets {
        let z = cut.top - depth_at(dists[inset.level]);
        let here = [b.at[0], b.at[1]];
        let (s, _) = inset.chain.nearest(here);
        let chain = inset.chain.rotated(s);
        let to = chain.start();
        // A link over ground at least the distance of the level one step outside the
        // shallower of the two insets, at that level's depth.
        let linked = prev.is_some_and(|pl| {
            let m = pl.min(inset.level);
            if m == 0 {
                return false;
            }
            let rings: Vec<&Vec<P>> = polys[m - 1].iter().flatten().collect();
            if !segment_clear(&rings, here, to) {
                return false;
            }
            let z_link = cut.top - depth_at(dists[m - 1]);
            if b.at[2] < z_link {
                b.line([here[0], here[1], z_link], cut.feed);
            }
            b.line([to[0], to[1], z_link], cut.feed);
            true
        });
        if !linked {
            b.travel(cut.clear_z, to, cut.top + RAPID_GAP);
        }
        if b.at[2] > z {
            b.line([to[0], to[1], z], cut.plunge_feed);
        }
        let mut moves = Vec::new();
        chain.walk(&[(0.0, z), (chain.length(), z)], cut.feed, &mut moves);
        b.extend(moves);
        prev = Some(inset.level);
    }
}

/// Whether segment a→b lies inside `rings` (even–odd): both ends inside and no ring edge
/// crossing it (an exact test, not sampled).
fn segment_clear(rings: &[&Vec<P>], a: P, b: P) -> bool {
    if !inside(rings, a) || !inside(rings, b) {
        return false;
    }
    let cross = |o: P, p: P, q: P| (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    for r in rings {
        let n = r.len();
        for i in 0..n {
            let (c, d) = (r[i], r[(i + 1) % n]);
            let (d1, d2) = (cross(c, d, a), cross(c, d, b));
            let (d3, d4) = (cross(a, b, c), cross(a, b, d));
            if (d1 > 0.0) != (d2 > 0.0) && (d3 > 0.0) != (d4 > 0.0) {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_segments_are_not_clear() {
        let sq = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let notch = vec![
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 10.0],
            [5.0, 1.0],
            [0.0, 10.0],
        ];
        assert!(segment_clear(&[&sq], [1.0, 5.0], [9.0, 5.0]));
        assert!(!segment_clear(&[&notch], [1.0, 5.0], [9.0, 5.0]));
    }
}
