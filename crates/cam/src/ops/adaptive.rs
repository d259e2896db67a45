//! Adaptive clearing: pockets (with islands) cleared at a bounded engagement angle.
//!
//! A material model ([`Model`]) follows the cut. The tool goes down by a helix where the
//! pocket is widest, then walks in short steps keeping the material on its right (climb
//! with an M3 spindle): at each step it takes the direction turned furthest towards the
//! material whose measured engagement stays within the target, so along a straight wall it
//! runs parallel at the radial depth the target allows, in inside corners it bends away, and
//! where it meets a wall or a neck it turns back through cleared material and loops in again
//! — the trochoidal loops come out of the same rule. A pass ends when nothing meets the
//! tool for a while or no direction is allowed; the next starts beside the nearest material
//! left, linked by a rapid where the tool meets nothing, a feed move through material
//! within the target, or else over the retraction plane. Each depth level repeats the same
//! plan; a contour pass along the tool-centre boundary, zigzagging into the sharp inside
//! corners ([`super::adaptive_corners`]), ends each level.

use super::adaptive_corners::with_corner_sweeps;
use super::adaptive_model::{Model, Rings};
use super::profile::OFFSET_TOL;
use super::{Builder, Cut, Entry, OpError, RAPID_GAP};
use crate::{Move, Operation};
use oficina_geom::{offset_areas, to_ring, Area, Path};
use std::f64::consts::{PI, TAU};

/// Adaptive clearing parameters besides the cut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveParams {
    /// Largest engagement angle of the tool in material, degrees (10–180).
    pub max_engagement: f64,
    /// Largest radial depth of a straight cut, mm (caps the target engagement at
    /// acos(1 − stepover / r)).
    pub stepover: f64,
    /// Stock left on the walls, mm (0: to size).
    pub stock_to_leave: f64,
}

/// Margin (degrees) the steering keeps below the target: the model's grid measures the
/// engagement to about a cell's angle, px / r rad ≈ 2.9° at r / 20, and a grid of other
/// cells walking the written moves differs by a degree more beside the walls.
const MARGIN: f64 = 4.0;
/// Model cell as a fraction of the tool radius.
const CELL: f64 = 1.0 / 20.0;
/// Step along a pass as a fraction of the tool radius.
const STEP: f64 = 1.0 / 8.0;
/// Steps without meeting material (below [`IDLE_DEG`]) that end a pass.
const IDLE_STEPS: usize = 24;
const IDLE_DEG: f64 = 2.0;
/// Steps over which a pass must make progress.
const WINDOW: usize = 48;
/// Sharpest turn per step while cutting, the direction search's increment, and the turn per
/// step while seeking material again (a loop of radius step / (2 sin(turn/2)) ≈ 0.7 r).
const TURN: f64 = 45.0;
const TURN_INC: f64 = 5.0;
const SEEK_TURN: f64 = 10.0;
/// Cells of the model at most (a 100 mm pocket with a 6 mm tool is 1.2 M).
const MAX_CELLS: usize = 16_000_000;

/// One piece of the plan, in the plane.
#[derive(Clone, Debug)]
enum Piece {
    /// Down into fresh material round a circle of `radius` about `centre` (0: plunge).
    Helix { centre: [f64; 2], radius: f64 },
    /// To the start of the next pass, or across cleared material within one.
    Link { to: [f64; 2], via: Via },
    /// Cutting moves through these points.
    Pass(Vec<[f64; 2]>),
}

/// How a [`Piece::Link`] gets there.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Via {
    /// A rapid at depth: the tool touches nothing on the way (as FreeCAD's Adaptive links
    /// through cleared area, `LinkClear` at a lift of 0).
    Clear,
    /// Fed at depth, cutting within the target.
    Cut,
    /// Over the retraction plane.
    Top,
}

/// Clears the inside of the closed `paths` (holes stay as islands) with `cut`.
pub fn adaptive(
    name: &str,
    paths: &[Path],
    cut: &Cut,
    p: &AdaptiveParams,
) -> Result<Operation, OpError> {
    cut.validate()?;
    let r = cut.radius();
    if !(p.max_engagement.is_finite() && (10.0..=180.0).contains(&p.max_engagement)) {
        return Err(OpError::Invalid(format!(
            "maximum engagement {}°: use 10 to 180 degrees",
            p.max_engagement
        )));
    }
    if !(p.stepover.is_finite()
        && p.stepover >= 0.02 * cut.tool.diameter
        && p.stepover <= cut.tool.diameter)
    {
        return Err(OpError::Invalid(format!(
            "step-over {} mm: use 2 % to 100 % of the tool diameter {} mm",
            p.stepover, cut.tool.diameter
        )));
    }
    if !(p.stock_to_leave.is_finite() && (0.0..=cut.tool.diameter).contains(&p.stock_to_leave)) {
        return Err(OpError::Invalid(
            "stock to leave: use 0 up to the tool diameter".into(),
        ));
    }
    let areas = Area::from_paths(paths);
    if areas.is_empty() {
        return Err(OpError::Empty("no closed contour to clear".into()));
    }
    let geo = |e: oficina_geom::PolygonError| OpError::Geometry(e.to_string());
    let rings = |a: &[Area]| -> Rings {
        a.iter()
            .flat_map(|a| {
                a.paths()
                    .map(|p| to_ring(&p.flatten(OFFSET_TOL)))
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let px = r * CELL;
    let wall = offset_areas(&areas, -(r + p.stock_to_leave), OFFSET_TOL).map_err(geo)?;
    if wall.is_empty() {
        return Err(OpError::Empty(format!(
            "every pocket is narrower than the {} mm tool",
            cut.tool.diameter
        )));
    }
    // The model holds no material within half a cell of the wall (a grid would count the
    // wall the tool runs along as contact). Clearing keeps the tool's edge 1.5 cells off
    // the wall, so the circle it samples half a cell out sees the material left between;
    // then a second plan, the centre let up to the tool-centre boundary itself (tested
    // exactly within 0.75 cell of it: a position whose cell centre is further in is
    // inside, √2/2 cell), takes that strip and nibbles the corners the first left, under
    // the same bound. The contour pass then runs on the boundary and meets next to
    // nothing (a strip thinner than a cell, left beside the wall, would be met along the
    // circle's tangent over tens of degrees).
    let centres = offset_areas(&wall, -1.5 * px, OFFSET_TOL).map_err(geo)?;
    let near_wall = offset_areas(&wall, -0.75 * px, OFFSET_TOL).map_err(geo)?;
    let pocket = offset_areas(&areas, -(p.stock_to_leave + 0.5 * px), OFFSET_TOL).map_err(geo)?;
    let boundary = rings(&wall);
    let (pocket, centres, near_wall) = (rings(&pocket), rings(&centres), rings(&near_wall));
    let extent = extent_cells(&pocket, r, px);
    if extent > MAX_CELLS as f64 {
        return Err(OpError::Invalid(format!(
            "the pocket is {:.0} model cells for a {} mm tool; at most {MAX_CELLS}",
            extent, cut.tool.diameter
        )));
    }
    // Target: the maximum less the model's margin, and no more than a straight cut at the
    // step-over engages, acos(1 − a/r) (a ≥ 2r: a slot, 180°).
    let by_stepover = (1.0 - (p.stepover / r).min(2.0)).acos().to_degrees();
    let target = (p.max_engagement - MARGIN)
        .min(by_stepover)
        .max(IDLE_DEG * 2.0);
    let helix_max = match cut.entry {
        Entry::Plunge => 0.0,
        Entry::Helix { radius, .. } => radius,
        Entry::Ramp { .. } => r / 2.0,
    };
    let mut model = Model::new(&pocket, &centres, r, px);
    let mut plan = self::plan(&mut model, target, helix_max, None)?;
    model.allow(&near_wall, Some(&boundary));
    let last = plan.iter().rev().find_map(Piece::end);
    plan.extend(self::plan(&mut model, target, helix_max, last)?);
    let contours: Vec<_> = boundary
        .iter()
        .filter(|ring| ring.len() >= 3)
        .map(|ring| with_corner_sweeps(&mut model, &boundary, &contour_order(ring)))
        .collect();
    Ok(cut.operation(name, emit(&plan, &contours, cut)?))
}

/// Cells the model of `rings` would have.
fn extent_cells(rings: &Rings, r: f64, px: f64) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in rings.iter().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    ((hi[0] - lo[0] + 2.0 * r) / px + 5.0) * ((hi[1] - lo[1] + 2.0 * r) / px + 5.0)
}

impl Piece {
    /// Where the tool is after this piece.
    fn end(&self) -> Option<[f64; 2]> {
        match self {
            Piece::Helix { centre, radius } => Some([centre[0] + radius, centre[1]]),
            Piece::Link { to, .. } => Some(*to),
            Piece::Pass(pts) => pts.last().copied(),
        }
    }
}

/// The plan in the plane from `at` (`None`: above the stock): helices, links and passes
/// until no material is left that a pass can start on.
fn plan(
    model: &mut Model,
    target: f64,
    helix_max: f64,
    mut at: Option<[f64; 2]>,
) -> Result<Vec<Piece>, OpError> {
    let r = model.r;
    let step = r * STEP;
    let mut plan = Vec::new();
    // Bounded work: every pass or helix must cut a cell, or bans one; steps in all passes
    // are bounded by the cells times a generous factor.
    let mut budget = 64 * (model.left + 1000);
    while model.open_left() > 0 {
        let here = match at {
            Some(p) => p,
            None => match helix(model, helix_max, &mut plan) {
                Some(p) => {
                    at = Some(p);
                    continue;
                }
                None => break,
            },
        };
        let near = model.nearest_material(here, 12);
        let mut started = false;
        for &(c, m) in &near {
            let Some(start) = start_beside(model, m) else {
                continue;
            };
            // A pass that cuts nothing is dropped with its link, and so is what the link cut.
            let before = model.snapshot();
            let via = if model.cuts_nothing_along(here, start) {
                Via::Clear
            } else if model.link(here, start, target) {
                Via::Cut
            } else {
                Via::Top
            };
            let heading = (m[1] - start[1]).atan2(m[0] - start[0]);
            let (pts, rapids, cut) = pass(model, start, heading, target, step, &mut budget);
            if cut == 0 {
                model.restore(before);
                model.ban(c);
                continue;
            }
            plan.push(Piece::Link { to: start, via });
            at = Some(*pts.last().unwrap_or(&start));
            plan.extend(pass_pieces(&pts, &rapids, 0.002 * model.r));
            started = true;
            break;
        }
        if budget == 0 {
            return Err(OpError::Geometry(
                "adaptive clearing did not converge within its step budget".into(),
            ));
        }
        if !started {
            // Nothing reachable from the cleared area: fresh material elsewhere gets its
            // own helix, or these cells are left over.
            match helix(model, helix_max, &mut plan) {
                Some(p) => at = Some(p),
                None => near.iter().for_each(|&(c, _)| model.ban(c)),
            }
        }
    }
    Ok(plan)
}

/// A helix down into the widest uncut spot; `None` when there is none.
fn helix(model: &mut Model, helix_max: f64, plan: &mut Vec<Piece>) -> Option<[f64; 2]> {
    let (centre, room) = model.deepest_uncut()?;
    let radius = helix_max.min(0.9 * room);
    let radius = if radius < 0.05 * model.r { 0.0 } else { radius };
    let n = ((TAU * radius / model.px).ceil() as usize).max(1);
    let mut cut = 0;
    for k in 0..=n {
        let a = TAU * k as f64 / n as f64;
        cut += model
            .stamp([centre[0] + radius * a.cos(), centre[1] + radius * a.sin()])
            .0;
    }
    if cut == 0 {
        // Cannot happen for an uncut centre cell, but never loop on it.
        model
            .nearest_material(centre, 1)
            .iter()
            .for_each(|&(c, _)| model.ban(c));
    }
    plan.push(Piece::Helix { centre, radius });
    plan.last().and_then(Piece::end)
}

/// A tool-centre position beside material cell `m`, touching nothing: on circles just
/// beyond the tool radius about it.
fn start_beside(model: &Model, m: [f64; 2]) -> Option<[f64; 2]> {
    for k in [1.5, 2.5, 4.0] {
        let rr = model.r + k * model.px;
        for i in 0..48 {
            let a = TAU * i as f64 / 48.0;
            let q = [m[0] + rr * a.cos(), m[1] + rr * a.sin()];
            if model.allowed(q) && model.free(q) {
                return Some(q);
            }
        }
    }
    None
}

/// Steps that touch nothing, in a run at least this long (as a fraction of the tool radius),
/// go as one rapid where the chord between its ends is clear too: shorter, a stop at each
/// end costs more than feeding through.
const AIR_RUN: f64 = 1.0;

/// One pass from `start`: steps of `step` keeping the engagement ≤ `target`; the points,
/// the runs of them (first, last index) that touched nothing and may go as a rapid, and
/// the cells cut.
fn pass(
    model: &mut Model,
    start: [f64; 2],
    heading: f64,
    target: f64,
    step: f64,
    budget: &mut usize,
) -> (Vec<[f64; 2]>, Vec<(usize, usize)>, usize) {
    let mut pts = vec![start];
    let (mut rapids, mut air_from) = (Vec::new(), None);
    let (mut at, mut heading) = (start, heading);
    let (mut cut, mut idle, mut last_cut_len) = (0, 0, 1);
    // A pass that loops without progress ends: over the last WINDOW steps it must cut a
    // tenth of what straight steps at the target would (step × radial depth / cell²).
    let radial = model.r * (1.0 - target.to_radians().cos());
    let least = (0.1 * step * radial / (model.px * model.px)).max(1.0) * WINDOW as f64;
    let mut recent: std::collections::VecDeque<usize> = Default::default();
    while *budget > 0 {
        *budget -= 1;
        // The most material within the target, turning least; where nothing within a
        // gentle turn meets material, curve right to find it again (the loop back of a
        // trochoid); where nothing is allowed ahead, turn back.
        let mut next = best_turn(model, at, heading, step, target, TURN, idle > 0);
        if next.is_none() {
            next = best_turn(model, at, heading, step, target, 180.0, false);
        }
        let Some((q, h, e)) = next else { break };
        // A run of steps meeting nothing ends here: judged on the material as it is when
        // the tool goes through (this step and those after cut more).
        let air = e == 0.0;
        if !air {
            if let Some(i) = air_from.take() {
                let j = pts.len() - 1;
                if (j - i) as f64 * step >= AIR_RUN * model.r
                    && model.cuts_nothing_along(pts[i], pts[j])
                {
                    rapids.push((i, j));
                }
            }
        }
        // Every step the model cuts is a move of the program, the one that ends a pass too.
        let (n, all) = model.stamp(q);
        if air {
            // A sliver the samples missed breaks the run.
            if all == 0 {
                air_from.get_or_insert(pts.len() - 1);
            } else {
                air_from = None;
            }
        }
        pts.push(q);
        cut += n;
        // Steps that cut anything are kept, the material out of reach included.
        if all > 0 {
            last_cut_len = pts.len();
        }
        recent.push_back(n);
        if recent.len() > WINDOW {
            recent.pop_front();
            if (recent.iter().sum::<usize>() as f64) < least {
                break;
            }
        }
        (at, heading) = (q, h.rem_euclid(TAU));
        if e < IDLE_DEG {
            idle += 1;
            if idle > IDLE_STEPS {
                break;
            }
        } else {
            idle = 0;
        }
    }
    // The tail after the last step that cut a cell cut nothing: leave it out.
    pts.truncate(last_cut_len.max(2).min(pts.len()));
    rapids.retain(|&(_, j)| j < pts.len());
    (pts, rapids, cut)
}

/// The pass `pts` as pieces: its `rapids` (index ranges) as links through clear space, the
/// rest fed, each fed stretch simplified within `tol`.
fn pass_pieces(pts: &[[f64; 2]], rapids: &[(usize, usize)], tol: f64) -> Vec<Piece> {
    let mut pieces = Vec::new();
    let mut from = 0;
    for &(i, j) in rapids.iter().chain([&(pts.len() - 1, pts.len() - 1)]) {
        if i > from {
            pieces.push(Piece::Pass(simplify(&pts[from..=i], tol)));
        }
        if j > i {
            pieces.push(Piece::Link {
                to: pts[j],
                via: Via::Clear,
            });
        }
        from = j;
    }
    pieces
}

/// The step from `at` within `turn` degrees of `heading` that engages most without passing
/// `target` (ties: the smallest turn); when `seek` and none engages, the gentle right turn.
fn best_turn(
    model: &Model,
    at: [f64; 2],
    heading: f64,
    step: f64,
    target: f64,
    turn: f64,
    seek: bool,
) -> Option<([f64; 2], f64, f64)> {
    let n = (turn / TURN_INC).round() as i32;
    let mut best: Option<([f64; 2], f64, f64, f64)> = None;
    for k in -n..=n {
        let dev = k as f64 * TURN_INC;
        let h = heading + dev.to_radians();
        let q = [at[0] + step * h.cos(), at[1] + step * h.sin()];
        if !model.allowed(q) {
            continue;
        }
        let e = step_engagement(model, at, h, step);
        if e > target {
            continue;
        }
        let better = match best {
            None => true,
            Some((_, _, be, bd)) => e > be + 0.5 || (e > be - 0.5 && dev.abs() < bd.abs()),
        };
        if better {
            best = Some((q, h, e, dev));
        }
    }
    let (q, h, e, _) = best?;
    if seek && e < IDLE_DEG {
        let h2 = heading - SEEK_TURN.to_radians();
        let q2 = [at[0] + step * h2.cos(), at[1] + step * h2.sin()];
        if model.allowed(q2) {
            let e2 = step_engagement(model, at, h2, step);
            if e2 <= target {
                return Some((q2, h2, e2));
            }
        }
    }
    Some((q, h, e))
}

/// Engagement along a step from `at` heading `h`: at its start (a turn swings the leading
/// half onto material the last step passed beside), quarters and end (going into a corner
/// it rises within half a step). The material cut along
/// the step lies within r of it, behind every leading half-circle sampled, so none of
/// it needs cutting first.
fn step_engagement(model: &Model, at: [f64; 2], h: f64, step: f64) -> f64 {
    [0.0, 0.25, 0.5, 0.75, 1.0]
        .iter()
        .map(|t| {
            let q = [at[0] + t * step * h.cos(), at[1] + t * step * h.sin()];
            model.engagement(q, h)
        })
        .fold(0.0, f64::max)
}

/// Drops points within `tol` of the chord through their neighbours (greedy, in order).
fn simplify(pts: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(pts.len());
    let mut i = 0;
    while i < pts.len() {
        out.push(pts[i]);
        let a = pts[i];
        let mut j = i + 1;
        // Extend the chord a→pts[j+1] while every point between stays within tol.
        while j + 1 < pts.len() {
            let b = pts[j + 1];
            let ok = (i + 1..=j).all(|k| dist_to_segment(pts[k], a, b) <= tol);
            if !ok || j - i > 64 {
                break;
            }
            j += 1;
        }
        i = j.max(i + 1);
        if i == pts.len() - 1 {
            out.push(pts[i]);
            break;
        }
    }
    out
}

fn dist_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// The moves: the plan at every depth level, then the contour passes (closed paths along the
/// tool-centre boundary, [`contour_order`]).
fn emit(plan: &[Piece], contours: &[Vec<[f64; 2]>], cut: &Cut) -> Result<Vec<Move>, OpError> {
    let mut b = Builder::new(cut.clear_z);
    let (feed, slow) = (cut.feed, cut.plunge_feed);
    let angle = cut.entry.angle().unwrap_or(3f64.to_radians());
    let mut z_prev = cut.top;
    for z in cut.levels() {
        let above = z_prev + RAPID_GAP;
        for piece in plan {
            match piece {
                Piece::Helix { centre, radius } => {
                    let s = [centre[0] + radius, centre[1]];
                    b.travel(cut.clear_z, s, above);
                    if *radius == 0.0 {
                        b.line([s[0], s[1], z], slow);
                        continue;
                    }
                    // Straight down through the air to the floor of the level before (the
                    // helix's turns above it cut nothing, at a twentieth of the pace), then
                    // turns of pitch 2πρ·tan(angle), each as two half circles, clockwise
                    // (climb with the material outside), then one flat turn at depth.
                    b.line([s[0], s[1], z_prev], slow);
                    let pitch = TAU * radius * angle.tan();
                    let halves = 2 * ((z_prev - z) / pitch).ceil().max(1.0) as usize;
                    for k in 1..=halves + 2 {
                        let zk = (z_prev - (z_prev - z) * k as f64 / halves as f64).max(z);
                        let a = -PI * k as f64;
                        b.push(Move::Arc {
                            to: [
                                centre[0] + radius * a.cos(),
                                centre[1] + radius * a.sin(),
                                zk,
                            ],
                            center: *centre,
                            ccw: false,
                            feed: slow,
                        });
                    }
                }
                Piece::Link { to, via } => match via {
                    Via::Clear if b.at[2] == z => b.push(Move::Rapid {
                        to: [to[0], to[1], z],
                    }),
                    Via::Cut if b.at[2] == z => b.line([to[0], to[1], z], feed),
                    _ => {
                        // Over the top and down into the spot: a pass starts where the tool
                        // touches nothing (`start_beside`), so this level is already cleared
                        // there; fast to the gap above that floor, fed the rest.
                        b.travel(cut.clear_z, *to, z + RAPID_GAP);
                        b.line([to[0], to[1], z], slow);
                    }
                },
                Piece::Pass(pts) => {
                    for p in &pts[1..] {
                        b.line([p[0], p[1], z], feed);
                    }
                }
            }
        }
        for path in contours {
            let s = path[0];
            // Down fast only to the gap above the level before: the strip beside the wall
            // still stands there.
            b.travel(cut.clear_z, s, above);
            b.line([s[0], s[1], z], cut.plunge_feed);
            for p in &path[1..] {
                b.line([p[0], p[1], z], cut.feed);
            }
        }
        z_prev = z;
    }
    Ok(b.finish(cut.clear_z))
}

/// A climb pass round `ring` (at least 3 points), closed: from the middle of its longest
/// edge (a corner would meet the material of both its walls at once).
fn contour_order(ring: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = ring.len();
    let edge = |i: usize| {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        (b[0] - a[0]).hypot(b[1] - a[1])
    };
    let longest = (0..n)
        .max_by(|&i, &j| edge(i).total_cmp(&edge(j)))
        .unwrap_or(0);
    let (a, c) = (ring[longest], ring[(longest + 1) % n]);
    let mid = [(a[0] + c[0]) / 2.0, (a[1] + c[1]) / 2.0];
    let mut ring: Vec<[f64; 2]> = ring.to_vec();
    ring.insert(longest + 1, mid);
    let k0 = longest + 1;
    // Outer rings run counter-clockwise, holes clockwise: reversed, the wall is on the
    // tool's right (climb).
    (0..=ring.len())
        .map(|i| ring[(k0 + ring.len() - i % ring.len()) % ring.len()])
        .collect()
}
