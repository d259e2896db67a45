//! Cutting along a contour: outside it (the part stays), inside it (a hole), or on it (a
//! groove, the seed's slots and letters). Tool-centre paths are exact offsets at the tool
//! radius (arcs stay arcs); climb milling with a clockwise spindle: outside contours run
//! clockwise, inside ones counter-clockwise.

use super::chain::{inside, max_profile, Chain, Piece, P};
use super::entry::enter_open;
use super::{Builder, Cut, OpError, RAPID_GAP};
use crate::{CompSide, Move, Operation};
use oficina_geom::{offset_areas, oriented, Area, Path};

/// Which side of the line the tool cuts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Inside closed shapes (a hole).
    Inside,
    /// Outside closed shapes (a part).
    Outside,
    /// On the line.
    On,
}

/// Bridges left standing so a cut-out part stays in the stock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tabs {
    /// Tabs per contour, evenly spaced.
    pub count: usize,
    /// Length of material left, mm (the tool centre rises over this plus a diameter).
    pub width: f64,
    /// Height of the bridge above the bottom of the cut, mm.
    pub height: f64,
}

/// Profile parameters besides the cut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileParams {
    /// Inside, outside or on the line.
    pub side: Side,
    /// Stock left on the wall by the depth passes, taken by one finishing pass at full
    /// depth (0: the passes cut to size).
    pub allowance: f64,
    /// Bridges to leave, if any.
    pub tabs: Option<Tabs>,
    /// Radius of a tangent arc off the wall after the last pass (0: none).
    pub lead_out: f64,
    /// Radius of a tangent quarter arc from the waste side onto each closed loop (0: none);
    /// [`DEFAULT_LEAD_IN`] × the tool radius is a good start. Where it does not fit it is
    /// halved, and left out if even an eighth does not.
    pub lead_in: f64,
    /// Who offsets by the tool radius: Oficina (the moves are the tool centre) or the
    /// control (G41 + D: the moves are the part outline, so wear is corrected at the
    /// machine).
    pub comp: Comp,
}

/// Who offsets the path by the tool radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Comp {
    /// Oficina: the moves are the tool centre.
    #[default]
    Computer,
    /// G41 on a straight entry move of [`COMP_ENTRY`] × the radius, G40 after a straight
    /// exit move as long.
    Control,
}

/// LinuxCNC refuses an entry move not longer than the tool radius; twice it leaves room.
pub(super) const COMP_ENTRY: f64 = 2.0;

/// A lead-in radius of about the tool radius keeps the arc short and its tangent join
/// gentle.
pub const DEFAULT_LEAD_IN: f64 = 1.0;

/// Offsets are exact to this (mm).
pub(super) const OFFSET_TOL: f64 = 0.001;

/// The tool-centre loops for `side` at wall distance `d` (≥ 0) from the contours.
/// Inside and outside follow the nesting (Estlcam's part mode): cutting a part out
/// (`Outside`) runs outside its outline and inside the holes it contains, outside the
/// islands in those holes again; `Inside` is the mirror. Loops come innermost first, so a
/// hole is cut while its part is still held by the stock.
pub(super) fn contour_loops(paths: &[Path], side: Side, d: f64) -> Result<Vec<Chain>, OpError> {
    Ok(nested_loops(paths, side, d, true)?
        .into_iter()
        .map(|(_, c)| c)
        .collect())
}

/// [`contour_loops`] with each loop's nesting depth (how many loops contain it); only the
/// outermost loop of each area unless `nested` (under cutter compensation the control's
/// entry and exit moves need more room than a hole of a part usually has).
fn nested_loops(
    paths: &[Path],
    side: Side,
    d: f64,
    nested: bool,
) -> Result<Vec<(usize, Chain)>, OpError> {
    match side {
        Side::On => Ok(paths
            .iter()
            .map(|p| (0, Chain::from_path(p)))
            .filter(|(_, c)| !c.pieces.is_empty())
            .collect()),
        Side::Inside | Side::Outside => {
            let areas = Area::from_paths(paths);
            if areas.is_empty() {
                return Err(OpError::Empty(
                    "no closed contour to cut inside or outside of".into(),
                ));
            }
            let dist = if side == Side::Outside { d } else { -d };
            let out = offset_areas(&areas, dist, OFFSET_TOL)
                .map_err(|e| OpError::Geometry(e.to_string()))?;
            // Climb milling: the tool runs clockwise round material inside the loop and
            // counter-clockwise round waste inside it.
            let mut loops: Vec<(usize, Chain)> = Vec::new();
            for a in &out {
                loops.push((
                    0,
                    Chain::from_path(&oriented(&a.outer, side == Side::Inside)),
                ));
                for h in a.holes.iter().filter(|_| nested) {
                    loops.push((0, Chain::from_path(&oriented(h, side == Side::Outside))));
                }
            }
            loops.retain(|(_, c)| !c.pieces.is_empty());
            let rings: Vec<Vec<P>> = loops.iter().map(|(_, c)| c.polygon(OFFSET_TOL)).collect();
            for (k, (depth, c)) in loops.iter_mut().enumerate() {
                let probe = c.start();
                *depth = rings
                    .iter()
                    .enumerate()
                    .filter(|&(j, r)| j != k && inside(std::slice::from_ref(r), probe))
                    .count();
            }
            // Deepest first; the stable sort keeps the drawing's order within a depth.
            loops.sort_by_key(|(depth, _)| std::cmp::Reverse(*depth));
            Ok(loops)
        }
    }
}

/// Deepest loops first, nearest-neighbour order from `from` within each depth.
fn order_nested(mut loops: Vec<(usize, Chain)>, mut from: [f64; 2]) -> Vec<Chain> {
    let mut out = Vec::with_capacity(loops.len());
    loops.sort_by_key(|(depth, _)| std::cmp::Reverse(*depth));
    while let Some(&(depth, _)) = loops.first() {
        let n = loops.iter().take_while(|(d, _)| *d == depth).count();
        let group: Vec<Chain> = loops.drain(..n).map(|(_, c)| c).collect();
        let ordered = order_nearest(group, from);
        if let Some(last) = ordered.last() {
            from = last.end();
        }
        out.extend(ordered);
    }
    out
}

/// Nearest-neighbour order from `from`.
pub(crate) fn order_nearest(mut chains: Vec<Chain>, mut from: [f64; 2]) -> Vec<Chain> {
    let mut out = Vec::with_capacity(chains.len());
    while !chains.is_empty() {
        let (k, _) = chains
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let s = c.start();
                (k, (s[0] - from[0]).hypot(s[1] - from[1]))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("not empty");
        let c = chains.swap_remove(k);
        from = c.end();
        out.push(c);
    }
    out
}

/// Cuts along the closed and open `paths` on `p.side` with `cut`.
pub fn profile(
    name: &str,
    paths: &[Path],
    cut: &Cut,
    p: &ProfileParams,
) -> Result<Operation, OpError> {
    cut.validate()?;
    if !(p.allowance.is_finite()
        && p.allowance >= 0.0
        && p.lead_out >= 0.0
        && p.lead_in.is_finite()
        && p.lead_in >= 0.0
        && p.lead_in <= 1000.0)
    {
        return Err(OpError::Invalid(
            "allowance, lead-in and lead-out must be 0 or more (lead-in up to 1000 mm)".into(),
        ));
    }
    if let Some(t) = p.tabs {
        if t.count == 0 || !(t.width > 0.0 && t.height > 0.0) || t.height >= cut.depth {
            return Err(OpError::Invalid(format!(
                "tabs need a count, a width above 0 and a height between 0 and the depth {} mm",
                cut.depth
            )));
        }
    }
    let r = cut.radius();
    let control = p.comp == Comp::Control;
    if control && p.side == Side::On {
        return Err(OpError::Invalid(
            "cutter compensation needs a side: profile inside or outside".into(),
        ));
    }
    let finishing = p.allowance > 0.0 && p.side != Side::On;
    // With compensation the moves are the outline (plus allowance) and the control adds r.
    let shift = if control { 0.0 } else { r };
    if contour_loops(paths, p.side, r + p.allowance)?.is_empty() {
        return Err(OpError::Empty(format!(
            "every contour is too small for a {} mm tool",
            cut.tool.diameter
        )));
    }
    let rough = order_nested(
        nested_loops(paths, p.side, shift + p.allowance, !control)?,
        [0.0, 0.0],
    );
    let mut b = Builder::new(cut.clear_z);
    let rings = loop_rings(&rough);
    let hints = comp_hints(paths, p, r + p.allowance)?;
    for chain in rough {
        let centre = hint_for(&chain, &hints);
        let (chain, lead) = lead_in(chain, p, &rings, r - shift, centre.map(Chain::start));
        passes(
            &mut b,
            &chain,
            centre,
            (lead, &rings),
            cut,
            p,
            &cut.levels(),
        )?;
    }
    if finishing {
        let finish = order_nested(
            nested_loops(paths, p.side, shift, !control)?,
            [b.at[0], b.at[1]],
        );
        let rings = loop_rings(&finish);
        let hints = comp_hints(paths, p, r)?;
        for chain in finish {
            // One pass at full depth, ramping down along the wall: only the allowance
            // is left there.
            let centre = hint_for(&chain, &hints);
            let (chain, lead) = lead_in(chain, p, &rings, r - shift, centre.map(Chain::start));
            passes(
                &mut b,
                &chain,
                centre,
                (lead, &rings),
                cut,
                p,
                &[cut.bottom()],
            )?;
        }
    }
    Ok(cut.operation(name, b.finish(cut.clear_z)))
}

/// The tool-centre loops as polygons, for the waste-side test.
fn loop_rings(loops: &[Chain]) -> Vec<Vec<P>> {
    loops.iter().map(|c| c.polygon(OFFSET_TOL / 10.0)).collect()
}

/// The loop started where a lead-in fits (the middle of its longest piece first: a corner
/// start would have the arc cross the wall before it), and that arc.
/// `extra`: added to the arc radius (the tool radius under compensation, where the
/// programmed arc is the outline's and the tool runs inside it).
pub(super) fn lead_in(
    chain: Chain,
    p: &ProfileParams,
    rings: &[Vec<P>],
    extra: f64,
    hint: Option<P>,
) -> (Chain, Option<Piece>) {
    if p.lead_in <= 0.0 && p.comp == Comp::Computer || !chain.closed || p.side == Side::On {
        return (chain, None);
    }
    let s = match hint {
        Some(h) => chain.nearest(h).0,
        None => preferred_start(&chain),
    };
    let middle = chain.rotated(s);
    if let Some(arc) = lead_in_arc(&middle, p, rings, extra) {
        return (middle, Some(arc));
    }
    let arc = lead_in_arc(&chain, p, rings, extra);
    (chain, arc)
}

/// Arc length of the middle of the longest piece.
fn preferred_start(chain: &Chain) -> f64 {
    let mut s = 0.0;
    let mut best = (0.0, 0.0);
    for piece in &chain.pieces {
        let l = piece.length();
        if l > best.1 {
            best = (s + l / 2.0, l);
        }
        s += l;
    }
    best.0
}

/// Under compensation the outline loops start across from where the tool-centre loops
/// would (the nearest of their preferred starts), so the control cuts the path Oficina
/// would have: the tool-centre loops at wall distance `d`.
fn comp_hints(paths: &[Path], p: &ProfileParams, d: f64) -> Result<Vec<Chain>, OpError> {
    if p.comp == Comp::Computer {
        return Ok(vec![]);
    }
    Ok(nested_loops(paths, p.side, d, false)?
        .iter()
        .map(|(_, c)| c)
        .map(|c| c.rotated(preferred_start(c)))
        .collect())
}

/// The tool-centre loop (of `hints`) that runs along outline `chain`.
fn hint_for<'a>(chain: &Chain, hints: &'a [Chain]) -> Option<&'a Chain> {
    hints.iter().min_by(|a, b| {
        chain
            .nearest(a.start())
            .1
            .total_cmp(&chain.nearest(b.start()).1)
    })
}

/// The quarter arc that ends tangent to the start of closed `chain`, turning left (the
/// waste side when climb milling: outside loops run clockwise, holes counter-clockwise).
/// With the start P, unit direction t and left normal n = (−t_y, t_x), the centre is
/// C = P + R·n and the arc runs counter-clockwise from C − R·t to P, whose tangent there
/// is +t. Every sampled point must lie on the waste side of all `rings` (outside them for
/// outside profiles, inside for holes): then the tool centre stays at least the offset
/// distance from the part. Too big an arc is halved, up to three times.
pub(super) fn lead_in_arc(
    chain: &Chain,
    p: &ProfileParams,
    rings: &[Vec<P>],
    extra: f64,
) -> Option<Piece> {
    if p.lead_in <= 0.0 || !chain.closed || p.side == Side::On {
        return None;
    }
    let first = chain.pieces.first()?;
    let s = first.start();
    let t = first.direction(0.0);
    if t == [0.0, 0.0] {
        return None;
    }
    let waste_inside = p.side == Side::Inside;
    // Under compensation only the tool centre's part of the radius is halved: the control
    // refuses an arc no wider than the tool on the side the tool runs.
    let mut lead = p.lead_in;
    for _ in 0..4 {
        let radius = lead + extra;
        let c = [s[0] - t[1] * radius, s[1] + t[0] * radius];
        // Angle of C − R·t seen from C is atan2(−t); a quarter turn counter-clockwise.
        let arc = Piece::Arc {
            c,
            r: radius,
            a0: (-t[1]).atan2(-t[0]),
            sweep: std::f64::consts::FRAC_PI_2,
        };
        let n = 32;
        let fits = (0..n).all(|k| inside(rings, arc.at(k as f64 / n as f64)) == waste_inside);
        if fits {
            return Some(arc);
        }
        lead /= 2.0;
    }
    None
}

/// Cuts `chain` at each of `levels` without leaving it, entering along `lead` (an arc
/// ending at the chain's start) if given, then the lead-out. Under compensation `centre`
/// is the tool-centre loop the control will make of outline `chain` (starting across from
/// it): ramps and tabs are laid out by its lengths, then carried to the outline point
/// across, so the control cuts the same path Oficina would.
fn passes(
    b: &mut Builder,
    chain: &Chain,
    centre: Option<&Chain>,
    (lead, rings): (Option<Piece>, &[Vec<P>]),
    cut: &Cut,
    p: &ProfileParams,
    levels: &[f64],
) -> Result<(), OpError> {
    let start = lead.map_or(chain.start(), |a| a.start());
    let mut z = cut.top + RAPID_GAP;
    let comp = p.comp == Comp::Control && chain.closed;
    if comp {
        // A straight entry from the waste side onto the arc start (or the loop start),
        // along the direction the arc starts in: towards the wall, i.e. −(left normal).
        let t = chain
            .pieces
            .first()
            .map_or([1.0, 0.0], |q| q.direction(0.0));
        let len = COMP_ENTRY * cut.radius();
        let from = [start[0] - t[1] * len, start[1] + t[0] * len];
        b.travel(cut.clear_z, from, z);
        b.push(Move::Comp(Some((CompSide::Left, cut.tool_number))));
        b.line([start[0], start[1], z], cut.feed);
    } else {
        b.travel(cut.clear_z, start, z);
    }
    if let (Some(arc), Some(&first)) = (lead, levels.first()) {
        // Down along the arc as far as the ramp angle allows (or plunged in the waste
        // where the tool may), so the wall is met moving along it.
        let z_end = match cut.entry.angle() {
            Some(angle) => {
                // Under compensation the tool runs inside the programmed arc, r nearer C.
                let tool_len = match (arc, comp) {
                    (Piece::Arc { r, sweep, .. }, true) => (r - cut.radius()) * sweep.abs(),
                    _ => arc.length(),
                };
                (z - tool_len * angle.tan()).max(first)
            }
            None => {
                b.line([start[0], start[1], first], cut.plunge_feed);
                first
            }
        };
        b.push(arc.to_move(z_end, cut.feed));
        z = z_end;
    }
    if !chain.closed {
        // Open grooves: back and forth, each level entered where the last ended.
        let mut c = chain.clone();
        for &level in levels {
            enter_open(b, &c, cut.entry, z, level, cut.plunge_feed)?;
            let mut moves = Vec::new();
            c.walk(&[(0.0, level), (c.length(), level)], cut.feed, &mut moves);
            b.extend(moves);
            z = level;
            c = c.reversed();
        }
        return Ok(());
    }
    let len = centre.unwrap_or(chain).length();
    // Tool-centre arc length → outline arc length, through the outline point nearest the
    // tool-centre point, in the same turn round the loop.
    let to_outline = |s: f64| -> f64 {
        let Some(c) = centre else {
            return s;
        };
        let lp = chain.length();
        let turns = (s / len).floor();
        let along = s - turns * len;
        let want = along / len * lp;
        let mut f = chain.nearest(c.point_at(along)).0;
        if f - want > lp / 2.0 {
            f -= lp;
        } else if want - f > lp / 2.0 {
            f += lp;
        }
        turns * lp + f
    };
    let mut s = 0.0;
    for &level in levels {
        let mut profile = match cut.entry.angle() {
            Some(angle) => {
                let run = (z - level).max(0.0) / angle.tan();
                vec![(s, z), (s + run, level), (s + run + len, level)]
            }
            None => {
                let here = b.at;
                if here[2] > level {
                    b.line([here[0], here[1], level], cut.plunge_feed);
                }
                vec![(s, level), (s + len, level)]
            }
        };
        if let Some(t) = p.tabs {
            let angle = cut.entry.angle().unwrap_or(45f64.to_radians());
            profile = max_profile(&profile, &tab_profile(t, cut, len, &profile, angle));
        }
        let mut moves = Vec::new();
        let walked: Vec<(f64, f64)> = profile.iter().map(|&(s, z)| (to_outline(s), z)).collect();
        chain.walk(&walked, cut.feed, &mut moves);
        b.extend(moves);
        s = profile.last().map_or(s, |q| q.0);
        z = level;
    }
    let ended = chain.rotated(to_outline(s));
    if p.lead_out > 0.0 {
        let extra = if comp { cut.radius() } else { 0.0 };
        lead_out(b, &ended, p.lead_out + extra, cut.feed, (rings, p.side));
    }
    if comp {
        // Straight off along the left normal at the loop's end (where a lead-out arc ends
        // heading), then G40 before the retract.
        let [tx, ty] = ended.pieces.last().map_or([1.0, 0.0], |q| q.direction(1.0));
        let len = COMP_ENTRY * cut.radius();
        let at = b.at;
        b.line([at[0] - ty * len, at[1] + tx * len, at[2]], cut.feed);
        b.push(Move::Comp(None));
    }
    Ok(())
}

/// Z of the tool centre over the tabs (raised to the bridge top), and below any cut
/// elsewhere, over the span of `base`.
fn tab_profile(t: Tabs, cut: &Cut, len: f64, base: &[(f64, f64)], angle: f64) -> Vec<(f64, f64)> {
    let (s0, s1) = (base[0].0, base[base.len() - 1].0);
    let low = cut.bottom() - 1.0;
    let top = cut.bottom() + t.height;
    let half = (t.width + cut.tool.diameter) / 2.0;
    let ramp = (top - low) / angle.tan();
    let mut out = vec![(s0, low)];
    let spacing = len / t.count as f64;
    let first = ((s0 - half - ramp) / len).floor() * len;
    let mut k = 0usize;
    loop {
        let c = first + (k as f64 + 0.5) * spacing;
        k += 1;
        if c - half - ramp > s1 {
            break;
        }
        for (s, z) in [
            (c - half - ramp, low),
            (c - half, top),
            (c + half, top),
            (c + half + ramp, low),
        ] {
            if s > out.last().map_or(f64::MIN, |q: &(f64, f64)| q.0) {
                out.push((s, z));
            }
        }
    }
    out.push((s1.max(out.last().map_or(s1, |q| q.0)), low));
    // Clip to the span [s0, s1] by evaluating at the ends through max_profile's sampler.
    let clipped: Vec<(f64, f64)> = out
        .iter()
        .copied()
        .filter(|q| q.0 >= s0 && q.0 <= s1)
        .collect();
    let eval = |s: f64| -> f64 {
        match out.iter().position(|q| q.0 >= s) {
            None | Some(0) => low,
            Some(i) => {
                let ((a, za), (b2, zb)) = (out[i - 1], out[i]);
                if b2 - a <= 0.0 {
                    zb
                } else {
                    za + (zb - za) * (s - a) / (b2 - a)
                }
            }
        }
    };
    let mut res = vec![(s0, eval(s0))];
    res.extend(clipped.into_iter().filter(|q| q.0 > s0 && q.0 < s1));
    res.push((s1, eval(s1)));
    res
}

/// A quarter arc off the wall to the left of travel (the waste side when climb milling),
/// halved up to three times until every point of it lies on the waste side of `rings`
/// (outside them for `Side::Outside`, inside for `Side::Inside`): in a small hole a full
/// arc would swing the tool into the far wall. Left out if even an eighth does not fit.
fn lead_out(
    b: &mut Builder,
    chain: &Chain,
    radius: f64,
    feed: f64,
    (rings, side): (&[Vec<P>], Side),
) {
    let Some(last) = chain.pieces.last() else {
        return;
    };
    let end = last.end();
    let [tx, ty] = last.direction(1.0);
    if tx == 0.0 && ty == 0.0 {
        return;
    }
    let mut radius = radius;
    for _ in 0..4 {
        // Left normal (−ty, tx); the arc turns left: counter-clockwise about the centre.
        let centre = [end[0] - ty * radius, end[1] + tx * radius];
        let arc = Piece::Arc {
            c: centre,
            r: radius,
            a0: ty.atan2(tx) - std::f64::consts::FRAC_PI_2,
            sweep: std::f64::consts::FRAC_PI_2,
        };
        let n = 32;
        let fits = side == Side::On
            || (1..=n)
                .all(|k| inside(rings, arc.at(k as f64 / n as f64)) == (side == Side::Inside));
        if fits {
            let to = [centre[0] + tx * radius, centre[1] + ty * radius, b.at[2]];
            b.push(Move::Arc {
                to,
                center: centre,
                ccw: true,
                feed,
            });
            return;
        }
        radius /= 2.0;
    }
}
