//! An element of an Ink/Stitch design sewn with its own parameters (`crate::inkstitch`), as
//! Ink/Stitch sews it:
//! - a fill → rows at its `angle`, `row_spacing_mm`, `max_stitch_length_mm`, `staggers`
//!   (or a contour fill: rings parallel to the outline), over a fill underlay of one layer per
//!   `fill_underlay_angle`, inset by `fill_underlay_inset_mm`;
//! - a `satin_column` → a satin between its two rails (told from the rungs as Ink/Stitch
//!   does: a rung crosses exactly two subpaths; else the two longest), the other
//!   subpaths rungs that pair the rails' points; each side pushed out by the pull
//!   compensation; underlays in Ink/Stitch's order: centre walk (there and back), contour
//!   (along one rail and back along the other), zig-zag (forward and back, crossing); then
//!   the satin (or an E-stitch) forward from the start;
//! - any other stroke → running stitch of `running_stitch_length_mm`, `repeats` passes back
//!   and forth, each stitch sewn `bean_stitch_repeats` more times back and forth; a manual
//!   stitch puts the needle on every node; a zig-zag stroke is a satin of the stroke's width.

use super::fill::{self, FillParams, Run};
use super::running::{running, straight};
use super::{guided, ripple, satin, Shape, ShapeKind};
use crate::inkstitch::{
    ElementParams, FillMethod, Placement, ReverseRails, StrokeMethod, FILL_STITCH_LENGTH,
};
use crate::{GenerateError, Params};
use oficina_geom::{offset_regions, Area, Color, Join, Path, Point, Region};

fn run(points: Vec<Point>, sew_into: bool) -> Run {
    Run { points, sew_into }
}

fn shape(
    max: f64,
    color: Color,
    kind: ShapeKind,
    e: &ElementParams,
    mut underlay: Vec<Run>,
    mut top: Vec<Run>,
) -> Shape {
    if let Some(min) = e.min_stitch_length.filter(|&m| m > 0.0) {
        for r in underlay.iter_mut().chain(top.iter_mut()) {
            r.points = drop_short(&r.points, min, max);
        }
    }
    Shape {
        color,
        kind,
        underlay,
        top,
        rev_link: false,
        ties: e.ties,
        force_lock: e.force_lock,
        trim_after: e.trim_after,
        stop_after: e.stop_after,
        min_jump: e.min_jump_length.unwrap_or(0.0),
    }
}

/// The shapes of one element (its subpaths `paths`) with parameters `e`.
pub(super) fn element_shapes(
    paths: &[&Path],
    e: &ElementParams,
    at: &Placement,
    needle: Option<Point>,
    p: &Params,
) -> Result<Vec<Shape>, GenerateError> {
    let style = paths[0].style;
    let mut out = Vec::new();
    let whose = || paths[0].source.to_string();
    if let Some(color) = style.fill {
        let closed: Vec<Path> = paths
            .iter()
            .filter(|q| q.closed)
            .map(|q| (*q).clone())
            .collect();
        let mut regions: Vec<Region> = Area::from_paths(&closed)
            .iter()
            .map(|a| a.to_region(p.tolerance))
            .collect();
        if e.expand.abs() > 1e-9 {
            regions = offset_regions(&regions, e.expand, Join::Miter { min_angle: 0.5 })
                .map_err(|m| GenerateError(format!("{}: expand: {m}", whose())))?;
        }
        // Each part of the fill starts where the one before ended (Ink/Stitch's order).
        let mut needle = needle;
        for region in regions {
            let length = e
                .max_stitch_length
                .unwrap_or(FILL_STITCH_LENGTH)
                .min(p.max_stitch);
            let fp = FillParams {
                spacing: e.row_spacing,
                length,
                angle: e.angle.to_radians(),
                stagger: e.staggers,
                pull_compensation: 0.0,
                along_edge: true,
            };
            let mut underlay = Vec::new();
            // The underlay starts at the start command, else where the needle is (the last
            // element's end), each layer and then the top where the one before ended
            // (Ink/Stitch's order); the top ends at the end command.
            let mut from = at.fill_start.or(needle);
            if e.fill_underlay {
                let inset = if e.fill_underlay_inset.abs() > 1e-9 {
                    offset_regions(
                        std::slice::from_ref(&region),
                        -e.fill_underlay_inset,
                        Join::Miter { min_angle: 0.5 },
                    )
                    .map_err(|m| GenerateError(format!("{}: underlay inset: {m}", whose())))?
                } else {
                    vec![region.clone()]
                };
                for angle in &e.fill_underlay_angles {
                    for r in &inset {
                        let layer = fill::tatami_between(
                            r,
                            &FillParams {
                                spacing: e.fill_underlay_row_spacing,
                                length: e.fill_underlay_max_stitch_length.min(p.max_stitch),
                                angle: angle.to_radians(),
                                stagger: 1,
                                pull_compensation: 0.0,
                                along_edge: true,
                            },
                            from,
                            None,
                        );
                        if from.is_some() {
                            from = layer.iter().rev().find_map(|r| r.points.last().copied());
                        }
                        underlay.extend(layer);
                    }
                }
            }
            let guide = at.guide.as_ref().map(|g| g.flatten(p.tolerance));
            let top = match (e.fill_method, guide) {
                (FillMethod::Guided { parallel }, Some(g)) => {
                    guided::guided(&region, &g, &fp, parallel, from, at.fill_end)
                        .unwrap_or_else(|| fill::tatami_between(&region, &fp, from, at.fill_end))
                }
                (FillMethod::Contour, _) => contour_fill(&region, e.row_spacing, length, from)
                    .map_err(|m| GenerateError(format!("{}: contour fill: {m}", whose())))?,
                // A guided fill without its guide: rows at the fill angle (Ink/Stitch warns).
                _ => fill::tatami_between(&region, &fp, from, at.fill_end),
            };
            let mut top = top;
            // Layers follow one another inside the shape: sewn into where the line stays in.
            let mut prev: Option<Point> = None;
            for r in underlay.iter_mut().chain(top.iter_mut()) {
                if let (Some(a), Some(&b)) = (prev, r.points.first()) {
                    r.sew_into = r.sew_into || fill::inside_line(a, b, &region);
                }
                prev = r.points.last().copied().or(prev);
            }
            needle = prev.or(needle);
            out.push(shape(
                p.max_stitch,
                color,
                ShapeKind::Fill,
                e,
                underlay,
                top,
            ));
        }
    }
    let Some(color) = style.stroke else {
        return Ok(out);
    };
    let lines: Vec<Vec<Point>> = paths
        .iter()
        .map(|q| {
            let mut pts = q.flatten(p.tolerance);
            if q.closed && !pts.is_empty() {
                pts.push(pts[0]);
            }
            pts
        })
        .filter(|pts| pts.len() >= 2 && length(pts) > 1e-9)
        .collect();
    if lines.is_empty() {
        return Ok(out);
    }
    if e.satin_column {
        let mut s = if lines.len() >= 2 {
            rail_satin(color, &lines, e, p)
        } else {
            // One subpath: Ink/Stitch asks for two rails; sewn as a satin of the stroke width.
            let (l, r) = satin::rails(&lines[0], style.stroke_width / 2.0);
            column(color, l, r, e, p)
        };
        // `satin_start` / `satin_end`: sewn from the end nearer the start (or to the end
        // nearer the end) command; the same column backwards otherwise.
        if let (Some(a), Some(b)) = (s.start(), s.reversed_start()) {
            let flip = match (at.start, at.end) {
                (Some(q), _) => b.distance(q) < a.distance(q),
                (None, Some(q)) => {
                    let last = s.runs().filter_map(|r| r.points.last().copied()).last();
                    last.is_some_and(|z| a.distance(q) < z.distance(q))
                }
                (None, None) => false,
            };
            if flip {
                s = s.reversed();
            }
        }
        out.push(s);
        return Ok(out);
    }
    // `run_start` / `run_end`: each line starts (ends) at its point nearest the command.
    let lines: Vec<Vec<Point>> = lines
        .into_iter()
        .map(|l| oriented(l, at.start, at.end))
        .collect();
    match e.stroke_method {
        StrokeMethod::Zigzag => {
            for line in &lines {
                let (l, r) = satin::rails(line, style.stroke_width / 2.0);
                out.push(column(color, l, r, e, p));
            }
        }
        StrokeMethod::Manual => {
            for q in paths {
                let mut pts: Vec<Point> =
                    q.segments.first().map(|s| s.start()).into_iter().collect();
                pts.extend(q.segments.iter().map(|s| s.end()));
                if pts.len() >= 2 {
                    // No stitch longer than the machine's.
                    let mut sewn = vec![pts[0]];
                    for w in pts.windows(2) {
                        sewn.extend(straight(w[0], w[1], p.max_stitch));
                    }
                    out.push(shape(
                        p.max_stitch,
                        color,
                        ShapeKind::Running,
                        e,
                        vec![],
                        vec![run(sewn, false)],
                    ));
                }
            }
        }
        StrokeMethod::Ripple => {
            let guide = at.guide.as_ref().map(|g| g.flatten(p.tolerance));
            let len = e.running_stitch_length.min(p.max_stitch);
            let line = ripple::ripple(&lines, &e.ripple, len, at.ripple_target, guide.as_deref());
            let pts = running_passes(&line, len, e.repeats, e.bean_stitch_repeats);
            out.push(shape(
                p.max_stitch,
                color,
                ShapeKind::Running,
                e,
                vec![],
                vec![run(pts, false)],
            ));
        }
        StrokeMethod::Running => {
            for line in &lines {
                let pts = running_passes(
                    line,
                    e.running_stitch_length.min(p.max_stitch),
                    e.repeats,
                    e.bean_stitch_repeats,
                );
                out.push(shape(
                    p.max_stitch,
                    color,
                    ShapeKind::Running,
                    e,
                    vec![],
                    vec![run(pts, false)],
                ));
            }
        }
    }
    Ok(out)
}

/// A line from its end (or, closed, its point) nearest `start`, or to the one nearest `end`.
fn oriented(mut l: Vec<Point>, start: Option<Point>, end: Option<Point>) -> Vec<Point> {
    let n = l.len();
    let closed = n > 3 && l[0].distance(l[n - 1]) < 1e-6;
    match (start, end) {
        (Some(q), _) if closed => {
            let i = (0..n - 1)
                .min_by(|&i, &j| l[i].distance(q).total_cmp(&l[j].distance(q)))
                .unwrap_or(0);
            let mut r: Vec<Point> = l[i..n - 1].to_vec();
            r.extend_from_slice(&l[..=i]);
            r
        }
        (Some(q), _) if l[n - 1].distance(q) < l[0].distance(q) => {
            l.reverse();
            l
        }
        (None, Some(q)) if closed => oriented(l, Some(q), None),
        (None, Some(q)) if l[0].distance(q) < l[n - 1].distance(q) => {
            l.reverse();
            l
        }
        _ => l,
    }
}

/// Stitches shorter than `min` merged into the next (`min_stitch_length_mm`): a needle point
/// nearer than `min` to the last one kept is left out; the run's last point stays (the
/// column or line ends where it was drawn to), so a short last stitch may remain.
fn drop_short(pts: &[Point], min: f64, max: f64) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::with_capacity(pts.len());
    for (i, &q) in pts.iter().enumerate() {
        let next = pts.get(i + 1);
        match out.last() {
            // Left out only where the stitch to the next point stays within the machine's.
            Some(&k) if k.distance(q) < min && next.is_some_and(|&n| k.distance(n) <= max) => {}
            Some(&k) if next.is_none() && k.distance(q) <= 1e-9 => {}
            _ => out.push(q),
        }
    }
    out
}

fn length(l: &[Point]) -> f64 {
    l.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// A running line sewn `repeats` times back and forth, each stitch then sewn `bean` more
/// times back and forth (bean 1: the triple stitch).
pub(super) fn running_passes(line: &[Point], len: f64, repeats: u32, bean: u32) -> Vec<Point> {
    let one = running(line, len);
    let mut pts: Vec<Point> = one.clone();
    for k in 1..repeats.max(1) {
        let pass: Vec<Point> = if k % 2 == 1 {
            one.iter().rev().copied().collect()
        } else {
            one.clone()
        };
        pts.extend(pass.into_iter().skip(1));
    }
    if bean == 0 || pts.len() < 2 {
        return pts;
    }
    let mut out = vec![pts[0]];
    for w in pts.windows(2) {
        out.push(w[1]);
        for _ in 0..bean {
            out.push(w[0]);
            out.push(w[1]);
        }
    }
    out
}

/// Arc-length position (0..total) of the point of `line` nearest to `q`, and its distance.
fn project(line: &[Point], q: Point) -> (f64, f64) {
    let (mut best, mut s0) = ((f64::INFINITY, 0.0), 0.0);
    for w in line.windows(2) {
        let l = w[0].distance(w[1]);
        let t = if l > 0.0 {
            ((q - w[0]).dot(w[1] - w[0]) / (l * l)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = w[0].lerp(w[1], t).distance(q);
        if d < best.0 {
            best = (d, s0 + t * l);
        }
        s0 += l;
    }
    (best.1, best.0)
}

/// The part of `line` between arc positions `s0` and `s1`, resampled to `m` points.
fn piece(line: &[Point], s0: f64, s1: f64, m: usize) -> Vec<Point> {
    let at = |s: f64| {
        let mut acc = 0.0;
        for w in line.windows(2) {
            let l = w[0].distance(w[1]);
            if acc + l >= s && l > 0.0 {
                return w[0].lerp(w[1], ((s - acc) / l).clamp(0.0, 1.0));
            }
            acc += l;
        }
        *line.last().unwrap()
    };
    let mut pts = vec![at(s0)];
    let mut acc = 0.0;
    for w in line.windows(2) {
        acc += w[0].distance(w[1]);
        if acc > s0 + 1e-9 && acc < s1 - 1e-9 {
            pts.push(w[1]);
        }
    }
    pts.push(at(s1));
    satin::resample(&pts, m)
}

/// Subpath indices, the two rails first, as Ink/Stitch tells them: a rung crosses exactly
/// two other subpaths; when exactly two subpaths are not rungs they are the rails, otherwise
/// (a `#`, or no ladder at all) the two longest. A short wide column (a letter's foot) has
/// rungs longer than its rails, so length alone would take a rung for a rail.
pub(crate) fn rails_first(lines: &[Vec<Point>]) -> Vec<usize> {
    let n = lines.len();
    let mut by_length: Vec<usize> = (0..n).collect();
    by_length.sort_by(|&i, &j| length(&lines[j]).total_cmp(&length(&lines[i])));
    if n <= 2 {
        return by_length;
    }
    let crosses = |i: usize| {
        (0..n)
            .filter(|&j| j != i && polylines_cross(&lines[i], &lines[j]))
            .count()
    };
    let rails: Vec<usize> = (0..n).filter(|&i| crosses(i) != 2).collect();
    if rails.len() != 2 {
        return by_length;
    }
    let mut out = rails.clone();
    out.extend(by_length.into_iter().filter(|i| !rails.contains(i)));
    out
}

/// Whether two polylines meet (touching counts, as Shapely's `intersects`).
fn polylines_cross(a: &[Point], b: &[Point]) -> bool {
    let side = |p: Point, q: Point, r: Point| (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
    let on = |p: Point, q: Point, r: Point| {
        r.x >= p.x.min(q.x) - 1e-9
            && r.x <= p.x.max(q.x) + 1e-9
            && r.y >= p.y.min(q.y) - 1e-9
            && r.y <= p.y.max(q.y) + 1e-9
    };
    a.windows(2).any(|u| {
        b.windows(2).any(|v| {
            let (d1, d2) = (side(v[0], v[1], u[0]), side(v[0], v[1], u[1]));
            let (d3, d4) = (side(u[0], u[1], v[0]), side(u[0], u[1], v[1]));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                return true;
            }
            (d1 == 0.0 && on(v[0], v[1], u[0]))
                || (d2 == 0.0 && on(v[0], v[1], u[1]))
                || (d3 == 0.0 && on(u[0], u[1], v[0]))
                || (d4 == 0.0 && on(u[0], u[1], v[1]))
        })
    })
}

/// Whether rail `b` runs against `a`, as Ink/Stitch's automatic `reverse_rails` decides:
/// ten points spread evenly along each, paired in order, lie farther apart in all than when
/// `b`'s are taken backwards. (Comparing only the first ends misjudges a short, wide column,
/// whose ends are all about as far apart, and depends on which rail comes first.)
fn drawn_opposite(a: &[Point], b: &[Point]) -> bool {
    let (sa, sb) = (satin::resample(a, 10), satin::resample(b, 10));
    let along: f64 = sa.iter().zip(&sb).map(|(p, q)| p.distance(*q)).sum();
    let against: f64 = sa
        .iter()
        .zip(sb.iter().rev())
        .map(|(p, q)| p.distance(*q))
        .sum();
    against < along
}

/// A satin between its two rails with the others as rungs: rail points
/// are paired section by section between the rungs, so the zigs follow them.
fn rail_satin(color: Color, lines: &[Vec<Point>], e: &ElementParams, p: &Params) -> Shape {
    let order = rails_first(lines);
    let (i, j) = (order[0].min(order[1]), order[0].max(order[1]));
    let mut a = lines[i].clone();
    let mut b = lines[j].clone();
    if e.swap_rails {
        // Ink/Stitch's "swap rails": the first zig starts on the other rail; `reverse_rails`
        // then names the rails in the swapped order, as Ink/Stitch's `rails` property does.
        std::mem::swap(&mut a, &mut b);
    }
    // A ring drawn without closing it (the ends a hair apart) is a ring too.
    match e.reverse_rails {
        ReverseRails::First => a.reverse(),
        ReverseRails::Second => b.reverse(),
        ReverseRails::Both => {
            a.reverse();
            b.reverse();
        }
        ReverseRails::Automatic | ReverseRails::None => {}
    }
    let auto = e.reverse_rails == ReverseRails::Automatic;
    let closed =
        |l: &[Point]| l.len() > 3 && l[0].distance(l[l.len() - 1]) < (0.01 * length(l)).max(0.05);
    if closed(&a) && closed(&b) {
        // Two rings (a circle of satin): the same turning sense, b starting nearest a's start.
        if signed_area(&a) * signed_area(&b) < 0.0 {
            b.reverse();
        }
        for r in [&mut a, &mut b] {
            if r[0].distance(r[r.len() - 1]) > 1e-9 {
                r.push(r[0]);
            }
        }
        let n = b.len() - 1;
        let k = (0..n)
            .min_by(|&i, &j| b[i].distance(a[0]).total_cmp(&b[j].distance(a[0])))
            .unwrap_or(0);
        let mut r: Vec<Point> = b[k..n].to_vec();
        r.extend_from_slice(&b[..=k]);
        b = r;
    } else if auto && drawn_opposite(&a, &b) {
        // Rails drawn in opposite directions are paired end to start.
        b.reverse();
    }
    let (la, lb) = (length(&a), length(&b));
    // Matched positions: the ends, and where each rung meets the rails.
    let mut pairs: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    let mut rungs: Vec<(f64, f64)> = order[2..]
        .iter()
        .filter_map(|&k| {
            let r = &lines[k];
            let (s0, e0) = (r[0], r[r.len() - 1]);
            // The rung's end nearer rail a meets a, the other b.
            let (pa, pb) =
                if project(&a, s0).1 + project(&b, e0).1 <= project(&a, e0).1 + project(&b, s0).1 {
                    (s0, e0)
                } else {
                    (e0, s0)
                };
            let (sa, sb) = (project(&a, pa).0, project(&b, pb).0);
            // A rung far from proportional (a ring's rung at the seam, projected past the
            // start on one rail and before the end on the other) would fold the column.
            let apart = (sa / la - sb / lb).abs() > 0.25;
            (sa > 1e-6 && sa < la - 1e-6 && sb > 1e-6 && sb < lb - 1e-6 && !apart)
                .then_some((sa, sb))
        })
        .collect();
    rungs.sort_by(|x, y| x.0.total_cmp(&y.0));
    for r in rungs {
        // Rungs that cross one another are left out.
        if r.1 > pairs.last().unwrap().1 + 1e-6 && r.0 > pairs.last().unwrap().0 + 1e-6 {
            pairs.push(r);
        }
    }
    pairs.push((la, lb));
    let (mut ra, mut rb) = (Vec::new(), Vec::new());
    for w in pairs.windows(2) {
        let sec = (w[1].0 - w[0].0).max(w[1].1 - w[0].1);
        let m = ((sec / 0.2).ceil() as usize).clamp(2, 100_000);
        let (pa, pb) = (piece(&a, w[0].0, w[1].0, m), piece(&b, w[0].1, w[1].1, m));
        let skip = usize::from(!ra.is_empty());
        ra.extend(pa.into_iter().skip(skip));
        rb.extend(pb.into_iter().skip(skip));
    }
    column(color, ra, rb, e, p)
}

/// Twice the signed area of a closed polyline (positive counter-clockwise).
fn signed_area(l: &[Point]) -> f64 {
    l.windows(2)
        .map(|w| w[0].x * w[1].y - w[1].x * w[0].y)
        .sum()
}

/// Rails moved towards each other by `inset` each (not past the centre).
fn inset_rails(a: &[Point], b: &[Point], inset: f64) -> (Vec<Point>, Vec<Point>) {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| {
            let w = x.distance(y);
            let t = if w > 0.0 { (inset / w).min(0.5) } else { 0.0 };
            (x.lerp(y, t), y.lerp(x, t))
        })
        .unzip()
}

/// A satin column between paired rails `a` and `b`, with its underlays.
/// An odd number of centre-walk passes ends at the column's end: the rest (contour, zig-zag,
/// the satin) then runs from there back to the start, as in Ink/Stitch.
fn column(
    color: Color,
    mut a: Vec<Point>,
    mut b: Vec<Point>,
    e: &ElementParams,
    p: &Params,
) -> Shape {
    let mut under: Vec<Point> = Vec::new();
    let mut add = |pts: Vec<Point>| {
        if let (Some(&last), Some(&first)) = (under.last(), pts.first()) {
            under.extend(straight(last, first, p.max_stitch));
            under.extend(pts.into_iter().skip(1));
        } else {
            under.extend(pts);
        }
    };
    if e.center_walk_underlay {
        let centre: Vec<Point> = a.iter().zip(&b).map(|(x, y)| x.midpoint(*y)).collect();
        add(running_passes(
            &centre,
            e.center_walk_length,
            e.center_walk_repeats,
            0,
        ));
        if e.center_walk_repeats % 2 == 1 {
            a.reverse();
            b.reverse();
        }
    }
    if e.contour_underlay {
        let (ca, mut cb) = inset_rails(&a, &b, e.contour_inset);
        cb.reverse();
        add(running(&ca, e.contour_length));
        add(running(&cb, e.contour_length));
    }
    if e.zigzag_underlay {
        let (za, zb) = inset_rails(&a, &b, e.zigzag_underlay_inset);
        add(satin::satin(
            &za,
            &zb,
            e.zigzag_underlay_spacing,
            p.max_stitch,
        ));
        let mut back = satin::satin(&zb, &za, e.zigzag_underlay_spacing, p.max_stitch);
        back.reverse();
        add(back);
    }
    // Pull compensation: each side of the top outwards (the underlays keep the drawn rails).
    for k in 0..a.len().min(b.len()) {
        let d = (a[k] - b[k]).normalize();
        if d.is_finite() {
            a[k] += d * e.pull_compensation;
            b[k] -= d * e.pull_compensation;
        }
    }
    // `max_stitch_length_mm` on a satin splits its wider zigs (Ink/Stitch's split stitch).
    let split = e
        .max_stitch_length
        .unwrap_or(p.max_stitch)
        .min(p.max_stitch);
    let top = if e.e_stitch {
        e_stitch(&a, &b, e.zigzag_spacing, split)
    } else {
        satin::satin(&a, &b, e.zigzag_spacing, split)
    };
    let has_under = !under.is_empty();
    let underlay = if has_under {
        vec![run(under, false)]
    } else {
        vec![]
    };
    shape(
        p.max_stitch,
        color,
        ShapeKind::Satin,
        e,
        underlay,
        vec![run(top, has_under)],
    )
}

/// The E-stitch: along rail `a` at `spacing`, at each step out to rail `b` and back.
fn e_stitch(a: &[Point], b: &[Point], spacing: f64, max: f64) -> Vec<Point> {
    // The satin's needle points pair a with b; keep a, b, a per pair, and walk along a.
    let zig = satin::satin(a, b, spacing, f64::INFINITY);
    let mut out: Vec<Point> = Vec::new();
    for pair in zig.chunks(2) {
        let (x, y) = (pair[0], *pair.get(1).unwrap_or(&pair[0]));
        for q in [x, y, x] {
            match out.last() {
                Some(&last) => out.extend(straight(last, q, max)),
                None => out.push(q),
            }
        }
    }
    out
}

/// Contour fill: rings parallel to the outline `spacing` apart, inwards, each sewn along and
/// the next one reached straight across (inside the shape).
fn contour_fill(
    region: &Region,
    spacing: f64,
    length: f64,
    from: Option<Point>,
) -> Result<Vec<Run>, String> {
    let mut rings: Vec<Vec<Point>> = Vec::new();
    let mut current = vec![region.clone()];
    let mut k = 0;
    while !current.is_empty() && k < 10_000 {
        for r in &current {
            for ring in std::iter::once(&r.outer).chain(r.holes.iter()) {
                let mut pts: Vec<Point> = ring.iter().map(|q| Point::new(q[0], q[1])).collect();
                if pts.len() >= 3 {
                    pts.push(pts[0]);
                    rings.push(running(&pts, length));
                }
            }
        }
        current = offset_regions(&current, -spacing, Join::Round { tolerance: 0.05 })
            .map_err(|e| e.to_string())?;
        k += 1;
    }
    let mut runs: Vec<Run> = Vec::new();
    for ring in rings {
        // Start each ring where the needle is nearest (the first at the start command).
        let start = runs
            .last()
            .and_then(|r: &Run| r.points.last().copied())
            .or(from);
        let ring = match start {
            Some(at) if ring.len() > 2 => {
                let n = ring.len() - 1;
                let i = (0..n)
                    .min_by(|&i, &j| ring[i].distance(at).total_cmp(&ring[j].distance(at)))
                    .unwrap_or(0);
                let mut r: Vec<Point> = ring[i..n].to_vec();
                r.extend_from_slice(&ring[..=i]);
                r
            }
            _ => ring,
        };
        let sew =
            !runs.is_empty() && start.is_some_and(|at| fill::inside_line(at, ring[0], region));
        runs.push(run(ring, sew));
    }
    Ok(runs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expand_grows_the_filled_shape() {
        let sq = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let mut path = Path::polyline(&sq, true);
        path.style.fill = Some(Color::BLACK);
        path.style.stroke = None;
        let extent = |expand: f64| {
            let e = ElementParams {
                expand,
                fill_underlay: false,
                ..ElementParams::default()
            };
            let shapes = element_shapes(
                &[&path],
                &e,
                &Placement::default(),
                None,
                &Params::default(),
            )
            .unwrap();
            let pts: Vec<Point> = shapes[0]
                .top
                .iter()
                .flat_map(|r| r.points.clone())
                .collect();
            let (lo, hi) = pts
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), q| (l.min(q.x), h.max(q.x)));
            hi - lo
        };
        assert!((extent(0.0) - 10.0).abs() < 0.05, "{}", extent(0.0));
        assert!((extent(1.0) - 12.0).abs() < 0.05, "{}", extent(1.0));
        assert!((extent(-1.0) - 8.0).abs() < 0.05, "{}", extent(-1.0));
    }

    #[test]
    fn short_stitches_are_merged_and_the_end_kept() {
        let pts: Vec<Point> = [0.0, 0.1, 0.2, 1.0, 1.1, 2.0, 2.05]
            .iter()
            .map(|&x| Point::new(x, 0.0))
            .collect();
        let out = drop_short(&pts, 0.3, 12.1);
        let xs: Vec<f64> = out.iter().map(|q| q.x).collect();
        assert_eq!(xs, [0.0, 1.0, 2.0, 2.05]);
    }

    #[test]
    fn bean_and_repeats_multiply_the_stitches() {
        let line = [Point::new(0.0, 0.0), Point::new(10.0, 0.0)];
        let one = running_passes(&line, 2.5, 1, 0);
        assert_eq!(one.len(), 5);
        // Triple (bean 1): each of the 4 stitches sewn three times.
        let bean = running_passes(&line, 2.5, 1, 1);
        assert_eq!(bean.len(), 1 + 4 * 3);
        assert!(bean.windows(2).all(|w| w[0].distance(w[1]) <= 2.5 + 1e-9));
        // Repeats 2: there and back, ending where it began.
        let two = running_passes(&line, 2.5, 2, 0);
        assert_eq!(two.len(), 9);
        assert!(two[8].distance(line[0]) < 1e-12);
    }

    #[test]
    fn rungs_pair_the_rails() {
        // Rail b has its points bunched at its start; a rung at x = 5 pairs a's middle with
        // b's point at x = 5, so the zig crossing the rung is square to it.
        let a = vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0)];
        let b = vec![
            Point::new(-5.0, 3.0),
            Point::new(5.0, 3.0),
            Point::new(10.0, 3.0),
        ];
        let rung = vec![Point::new(5.0, -1.0), Point::new(5.0, 4.0)];
        let e = ElementParams {
            zigzag_spacing: 0.5,
            ..ElementParams::default()
        };
        let s = rail_satin(
            Color::BLACK,
            &[a.clone(), b.clone(), rung],
            &e,
            &Params::default(),
        );
        let top = &s.top[0].points;
        let near = top
            .chunks(2)
            .filter(|z| z.len() == 2)
            .min_by(|x, y| (x[0].x - 5.0).abs().total_cmp(&(y[0].x - 5.0).abs()))
            .unwrap();
        assert!((near[1].x - 5.0).abs() < 0.3, "{near:?}");
        // Without the rung the same zig leans to b's proportional point (x = 2.5).
        let s = rail_satin(Color::BLACK, &[a, b], &e, &Params::default());
        let near = s.top[0]
            .points
            .chunks(2)
            .filter(|z| z.len() == 2)
            .min_by(|x, y| (x[0].x - 5.0).abs().total_cmp(&(y[0].x - 5.0).abs()))
            .unwrap();
        assert!((near[1].x - 2.5).abs() < 0.3, "{near:?}");
    }

    #[test]
    fn satin_underlays_start_and_end_at_the_column_start() {
        let a = vec![Point::new(0.0, 0.0), Point::new(20.0, 0.0)];
        let b = vec![Point::new(0.0, 4.0), Point::new(20.0, 4.0)];
        let e = ElementParams {
            center_walk_underlay: true,
            contour_underlay: true,
            zigzag_underlay: true,
            pull_compensation: 0.3,
            ..ElementParams::default()
        };
        let s = rail_satin(Color::BLACK, &[a, b], &e, &Params::default());
        let u = &s.underlay[0].points;
        assert!(
            u[0].distance(Point::new(0.0, 2.0)) < 1e-9,
            "centre walk starts mid-column"
        );
        assert!(
            u.last().unwrap().x < 1.0,
            "underlays come back to the start"
        );
        // Contour inset 0.4, zig-zag inset 0.2: all inside the drawn column.
        assert!(u.iter().all(|q| q.y >= 0.2 - 1e-9 && q.y <= 3.8 + 1e-9));
        // Pull compensation pushes each side out by 0.3.
        let top = &s.top[0].points;
        let (lo, hi) = top
            .iter()
            .fold((9.0f64, -9.0f64), |(l, h), q| (l.min(q.y), h.max(q.y)));
        assert!(
            (lo + 0.3).abs() < 1e-9 && (hi - 4.3).abs() < 1e-9,
            "{lo} {hi}"
        );
        assert!(s.top[0].sew_into);
    }

    #[test]
    fn an_odd_centre_walk_turns_the_satin_round() {
        let a = vec![Point::new(0.0, 0.0), Point::new(20.0, 0.0)];
        let b = vec![Point::new(0.0, 4.0), Point::new(20.0, 4.0)];
        for (repeats, start_x) in [(1, 20.0), (2, 0.0), (3, 20.0)] {
            let e = ElementParams {
                center_walk_underlay: true,
                center_walk_repeats: repeats,
                ..ElementParams::default()
            };
            let s = rail_satin(
                Color::BLACK,
                &[a.clone(), b.clone()],
                &e,
                &Params::default(),
            );
            let u = &s.underlay[0].points;
            assert!((u.last().unwrap().x - start_x).abs() < 1e-9, "{repeats}");
            assert!((s.top[0].points[0].x - start_x).abs() < 1e-9, "{repeats}");
        }
        // A 4 mm column split at 1.5 mm: every zig in three stitches.
        let e = ElementParams {
            max_stitch_length: Some(1.5),
            ..ElementParams::default()
        };
        let s = rail_satin(Color::BLACK, &[a, b], &e, &Params::default());
        let top = &s.top[0].points;
        assert!(top.windows(2).all(|w| w[0].distance(w[1]) <= 1.5 + 1e-9));
        assert!(top.len() > 3 * 2 * 50, "{}", top.len());
    }

    #[test]
    fn contour_fill_rings_stay_inside_and_cover() {
        let r = Region {
            outer: vec![[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 10.0]],
            holes: vec![],
        };
        let runs = contour_fill(&r, 0.5, 3.0, None).unwrap();
        let pts: Vec<Point> = runs.iter().flat_map(|r| r.points.iter().copied()).collect();
        assert!(pts
            .iter()
            .all(|q| q.x > -1e-6 && q.x < 20.0 + 1e-6 && q.y > -1e-6 && q.y < 10.0 + 1e-6));
        // Rings down to the middle: some point within a spacing of the centre line y = 5.
        assert!(pts
            .iter()
            .any(|q| (q.y - 5.0).abs() <= 0.5 + 1e-9 && q.x > 5.0 && q.x < 15.0));
        assert!(runs.len() >= 9, "{} rings", runs.len());
    }
}
