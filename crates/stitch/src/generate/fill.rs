//! Tatami fill of an area with holes. The seed left area fill unimplemented ("the area-fill
//! algorithms ... proved quite complex", §7.5) and made AREA.BOR from parallel digitised
//! lines; this is that idea made automatic, as Ink/Stitch and Embird do it:
//! rows `spacing` apart at `angle`, each row's inside segments found by scanline, rows
//! grouped into sections (runs of rows where each segment meets exactly one segment of the
//! next row) sewn back and forth; needle points on a grid of `length` whose origin shifts by
//! length/`stagger` from row to row, so the points of neighbouring rows do not line up (the
//! brick pattern). Sections are joined by stitches where the straight line stays inside the
//! area, otherwise a new run starts (the caller jumps to it).

use super::running::straight;
use oficina_geom::{Point, Region};

pub(crate) struct FillParams {
    pub spacing: f64,
    pub length: f64,
    /// Radians, of the rows against the X axis.
    pub angle: f64,
    pub stagger: u32,
    /// Each row is lengthened by this in total (half at each end).
    pub pull_compensation: f64,
    /// A long way from one section to the next goes along the edge where it can, not
    /// straight across rows already sewn (Ink/Stitch's travel; Oficina's own fills go straight).
    pub along_edge: bool,
}

/// A run of stitches and whether the needle may sew straight to its first point from the
/// end of the previous run (the line stays inside the area, under the fill).
pub(super) struct Run {
    pub points: Vec<Point>,
    pub sew_into: bool,
}

/// Shortest stitch kept at the end of a row, as a fraction of the stitch length.
const MIN_END: f64 = 0.25;

pub(super) fn tatami(region: &Region, p: &FillParams) -> Vec<Run> {
    tatami_between(region, p, None, None)
}

/// Tatami whose first stitch is the row end nearest `start` and whose last is the row end
/// nearest `end` (Ink/Stitch's `fill_start` / `fill_end` commands), when given.
pub(super) fn tatami_between(
    region: &Region,
    p: &FillParams,
    start: Option<Point>,
    end: Option<Point>,
) -> Vec<Run> {
    let (c, s) = (p.angle.cos(), p.angle.sin());
    // Into the row frame (rows horizontal) and back.
    let to_row = |q: &[f64; 2]| Point::new(q[0] * c + q[1] * s, -q[0] * s + q[1] * c);
    let from_row = |q: Point| Point::new(q.x * c - q.y * s, q.x * s + q.y * c);
    let rings: Vec<Vec<Point>> = std::iter::once(&region.outer)
        .chain(region.holes.iter())
        .filter(|r| r.len() >= 3)
        .map(|r| r.iter().map(to_row).collect())
        .collect();
    let Some((y0, y1)) = rings
        .iter()
        .flatten()
        .fold(None, |acc: Option<(f64, f64)>, q| {
            Some(acc.map_or((q.y, q.y), |(a, b)| (a.min(q.y), b.max(q.y))))
        })
    else {
        return Vec::new();
    };
    let n_rows = ((y1 - y0) / p.spacing).floor() as usize + 1;
    // Row k at y0 + (k + ½)·spacing; its inside segments [x_in, x_out].
    let mut rows: Vec<Vec<(f64, f64)>> = Vec::with_capacity(n_rows);
    for k in 0..n_rows {
        let y = y0 + (k as f64 + 0.5) * p.spacing;
        let mut xs = Vec::new();
        for r in &rings {
            for i in 0..r.len() {
                let (a, b) = (r[i], r[(i + 1) % r.len()]);
                // Half-open in y so a vertex on the row counts once.
                if (a.y <= y) != (b.y <= y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        let half = p.pull_compensation / 2.0;
        rows.push(
            xs.chunks_exact(2)
                .map(|w| (w[0] - half, w[1] + half))
                .collect(),
        );
    }
    let overlaps = |a: (f64, f64), b: (f64, f64)| a.0 < b.1 && b.0 < a.1;
    let mut used: Vec<Vec<bool>> = rows.iter().map(|r| vec![false; r.len()]).collect();
    let mut sections: Vec<Vec<(usize, usize)>> = Vec::new();
    let first_free = |used: &Vec<Vec<bool>>| {
        (0..used.len()).find_map(|k| used[k].iter().position(|u| !u).map(|i| (k, i)))
    };
    while let Some((k0, i0)) = first_free(&used) {
        // A section: follow the unique overlapping segment row by row.
        let mut section = vec![(k0, i0)];
        used[k0][i0] = true;
        let (mut k, mut i) = (k0, i0);
        while k + 1 < rows.len() {
            let next: Vec<usize> = (0..rows[k + 1].len())
                .filter(|&j| !used[k + 1][j] && overlaps(rows[k][i], rows[k + 1][j]))
                .collect();
            if next.len() != 1 {
                break;
            }
            let j = next[0];
            let back = (0..rows[k].len())
                .filter(|&m| overlaps(rows[k][m], rows[k + 1][j]))
                .count();
            if back != 1 {
                break;
            }
            used[k + 1][j] = true;
            section.push((k + 1, j));
            (k, i) = (k + 1, j);
        }
        sections.push(section);
    }
    let sew = |rows_of: &[(usize, usize)], flip: bool| -> Vec<Point> {
        let mut pts: Vec<Point> = Vec::new();
        for (n, &(k, i)) in rows_of.iter().enumerate() {
            let y = y0 + (k as f64 + 0.5) * p.spacing;
            let row = row_points(rows[k][i], k, (n % 2 == 1) != flip, p);
            let first = Point::new(row[0], y);
            if let Some(&prev) = pts.last() {
                pts.extend(straight(prev, first, p.length));
            } else {
                pts.push(first);
            }
            pts.extend(row[1..].iter().map(|&x| Point::new(x, y)));
        }
        pts.into_iter().map(from_row).collect()
    };
    // A start (end) command: the section holding the row end nearest it is cut there, so
    // that row begins (ends) a piece, sewn first (last) from (to) that row end.
    let ends = |&(k, i): &(usize, usize)| {
        let y = y0 + (k as f64 + 0.5) * p.spacing;
        [rows[k][i].0, rows[k][i].1].map(|x| from_row(Point::new(x, y)))
    };
    let nearest = |sections: &[Vec<(usize, usize)>], q: Point| {
        let mut best = (f64::INFINITY, 0, 0);
        for (s, sec) in sections.iter().enumerate() {
            for (j, r) in sec.iter().enumerate() {
                let d = ends(r)
                    .iter()
                    .map(|e| e.distance(q))
                    .fold(f64::INFINITY, f64::min);
                if d < best.0 {
                    best = (d, s, j);
                }
            }
        }
        (best.1, best.2)
    };
    // Cuts section `s` at row `j` into the piece from `j` to the nearer end of the section
    // (row `j` first) and the rest (put back).
    let split = |sections: &mut Vec<Vec<(usize, usize)>>, s: usize, j: usize| {
        let mut sec = sections.remove(s);
        let (piece, rest) = if j < sec.len() - 1 - j {
            let rest = sec.split_off(j + 1);
            sec.reverse();
            (sec, rest)
        } else {
            let piece = sec.split_off(j);
            (piece, sec)
        };
        if !rest.is_empty() {
            sections.insert(s, rest);
        }
        piece
    };
    let flip_for = |piece: &[(usize, usize)], q: Point, first: bool| {
        let variant = |flip: bool| {
            let pts = sew(piece, flip);
            let at = if first { pts[0] } else { pts[pts.len() - 1] };
            (at.distance(q), pts)
        };
        let (a, b) = (variant(false), variant(true));
        if a.0 <= b.0 {
            a.1
        } else {
            b.1
        }
    };
    let mut start_piece = start.filter(|_| !sections.is_empty()).map(|q| {
        let (s, j) = nearest(&sections, q);
        split(&mut sections, s, j)
    });
    let mut end_piece = None;
    if let Some(q) = end {
        // The end's row may lie in the start piece: that piece is cut before it, and the
        // rest of it (from its far end to that row) is sewn last.
        let mut all = sections.clone();
        all.extend(start_piece.iter().cloned());
        if !all.is_empty() {
            let (s, j) = nearest(&all, q);
            if s == sections.len() && j > 0 {
                let piece = start_piece.as_mut().unwrap();
                let mut tail = piece.split_off(j);
                tail.reverse();
                end_piece = Some(tail);
            } else if s < sections.len() {
                let mut piece = split(&mut sections, s, j);
                piece.reverse(); // the row nearest the end last
                end_piece = Some(piece);
            }
        }
    }
    let first = start_piece
        .zip(start)
        .map(|(piece, q)| approach(q, flip_for(&piece, q, true), region, p));
    let last = end_piece
        .zip(end)
        .map(|(piece, q)| leave(flip_for(&piece, q, false), q, region, p));
    let middle: Vec<Vec<Point>> = sections.iter().map(|sec| sew(sec, false)).collect();
    join_sections(first, middle, last, region, p)
}

/// A fill's first stitches from a start command at `q` on the outline: along the edge to the
/// first row's end when that is more than a row away (Ink/Stitch travels so too).
pub(super) fn approach(q: Point, pts: Vec<Point>, region: &Region, p: &FillParams) -> Vec<Point> {
    match pts.first() {
        Some(&a) if a.distance(q) > p.spacing => match edge_travel(q, a, region, p.length) {
            Some(travel) => {
                let mut out = vec![q];
                out.extend(travel);
                out.extend(pts.into_iter().skip(1));
                out
            }
            None => pts,
        },
        _ => pts,
    }
}

/// A fill's last stitches to an end command at `q` on the outline (see [`approach`]).
pub(super) fn leave(mut pts: Vec<Point>, q: Point, region: &Region, p: &FillParams) -> Vec<Point> {
    if let Some(&z) = pts.last().filter(|z| z.distance(q) > p.spacing) {
        if let Some(travel) = edge_travel(z, q, region, p.length) {
            pts.extend(travel);
        }
    }
    pts
}

/// Sews `first` (when given), then the sections nearest-first from where the needle is (the
/// first one's start when nothing came before), each forwards or backwards (a serpentine
/// reads the same both ways), then `last`; the line to the next section is stitched where it
/// stays inside (the fill covers it) or travels along the edge, else the next section starts
/// a new run.
pub(super) fn join_sections(
    first: Option<Vec<Point>>,
    mut sections: Vec<Vec<Point>>,
    last: Option<Vec<Point>>,
    region: &Region,
    p: &FillParams,
) -> Vec<Run> {
    let length = p.length;
    sections.retain(|s| !s.is_empty());
    let mut runs: Vec<Run> = Vec::new();
    let mut at: Option<Point> = None;
    let mut sew = |pts: Vec<Point>, at: &mut Option<Point>| {
        let link = at.and_then(|e| {
            // A long way across would lie on rows already sewn: along the edge instead
            // when it can (as Ink/Stitch travels along the outline).
            let long = p.along_edge && e.distance(pts[0]) > 2.0 * length;
            let along = || edge_travel(e, pts[0], region, length);
            if inside_line(e, pts[0], region) {
                long.then(along)
                    .flatten()
                    .or_else(|| Some(straight(e, pts[0], length)))
            } else {
                along()
            }
        });
        match (link, runs.last_mut()) {
            (Some(travel), Some(prev)) => {
                prev.points.extend(travel);
                prev.points.extend(pts[1..].iter().copied());
            }
            _ => runs.push(Run {
                points: pts,
                sew_into: false,
            }),
        }
        *at = runs.last().and_then(|r| r.points.last().copied());
    };
    if let Some(f) = first.filter(|f| !f.is_empty()) {
        sew(f, &mut at);
    }
    while !sections.is_empty() {
        let (mut best, mut rev, mut best_d) = (0, false, f64::INFINITY);
        if let Some(a) = at {
            for (i, sec) in sections.iter().enumerate() {
                for (end, r) in [(sec[0], false), (sec[sec.len() - 1], true)] {
                    let d = a.distance(end);
                    if d < best_d {
                        (best, rev, best_d) = (i, r, d);
                    }
                }
            }
        }
        let mut pts = sections.swap_remove(best);
        if rev {
            pts.reverse();
        }
        sew(pts, &mut at);
    }
    if let Some(l) = last.filter(|l| !l.is_empty()) {
        sew(l, &mut at);
    }
    runs
}

/// Section ends lie on the boundary (within the pull compensation); farther than this from a
/// ring, a point is not on it.
const ON_RING: f64 = 0.6;

/// Travel from `a` to `b` along the boundary ring both lie on, the shorter way round, as
/// running stitches of at most `length` (the fill's rows cover them, as Ink/Stitch's travel
/// along the outline): no trim, no jump. None when they are not on one ring or the way round
/// is more than four times the straight line and 20 mm (a jump is better then).
fn edge_travel(a: Point, b: Point, region: &Region, length: f64) -> Option<Vec<Point>> {
    let rings = std::iter::once(&region.outer).chain(region.holes.iter());
    for ring in rings {
        let r: Vec<Point> = ring.iter().map(|q| Point::new(q[0], q[1])).collect();
        let n = r.len();
        if n < 3 {
            continue;
        }
        // Arc position along the ring of the nearest point to p, and its distance.
        let project = |p: Point| {
            let mut best = (f64::INFINITY, 0.0, Point::ZERO);
            let mut s0 = 0.0;
            for i in 0..n {
                let (u, v) = (r[i], r[(i + 1) % n]);
                let l = u.distance(v);
                let t = if l > 0.0 {
                    ((p - u).dot(v - u) / (l * l)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let q = u.lerp(v, t);
                if q.distance(p) < best.0 {
                    best = (q.distance(p), s0 + t * l, q);
                }
                s0 += l;
            }
            (best, s0)
        };
        let (((da, sa, qa), total), ((db, sb, qb), _)) = (project(a), project(b));
        if da > ON_RING || db > ON_RING {
            continue;
        }
        let fwd = (sb - sa).rem_euclid(total);
        let forward = fwd <= total - fwd;
        let way = fwd.min(total - fwd);
        if way > (4.0 * a.distance(b)).max(20.0) {
            return None;
        }
        // The ring's vertices strictly between the two arc positions, in travel order.
        let mut cum = Vec::with_capacity(n);
        let mut s0 = 0.0;
        for i in 0..n {
            cum.push(s0);
            s0 += r[i].distance(r[(i + 1) % n]);
        }
        let mut path = vec![a, qa];
        let mut between: Vec<(f64, Point)> = (0..n)
            .filter_map(|i| {
                let off = if forward {
                    (cum[i] - sa).rem_euclid(total)
                } else {
                    (sa - cum[i]).rem_euclid(total)
                };
                (off > 1e-9 && off < way - 1e-9).then_some((off, r[i]))
            })
            .collect();
        between.sort_by(|x, y| x.0.total_cmp(&y.0));
        path.extend(between.into_iter().map(|(_, q)| q));
        path.extend([qb, b]);
        let pts = super::running::running(&path, length);
        return Some(pts[1..].to_vec());
    }
    None
}

/// The x of the needle points of one row segment, from its start end to its other end.
pub(super) fn row_points(seg: (f64, f64), row: usize, reverse: bool, p: &FillParams) -> Vec<f64> {
    let (a, b) = seg;
    let offset = (row as u32 % p.stagger.max(1)) as f64 / p.stagger.max(1) as f64 * p.length;
    let mut xs = vec![a];
    let mut m = ((a - offset) / p.length).floor() as i64 + 1;
    loop {
        let x = offset + m as f64 * p.length;
        if x >= b {
            break;
        }
        xs.push(x);
        m += 1;
    }
    xs.push(b);
    // A grid point very near an end makes a tiny stitch: drop it where the stitch it
    // leaves is no longer than `length`.
    let tiny = MIN_END * p.length;
    if xs.len() > 2 && xs[1] - xs[0] < tiny && xs[2] - xs[0] <= p.length {
        xs.remove(1);
    }
    let n = xs.len();
    if n > 2 && xs[n - 1] - xs[n - 2] < tiny && xs[n - 1] - xs[n - 3] <= p.length {
        xs.remove(n - 2);
    }
    if reverse {
        xs.reverse();
    }
    xs
}

/// Whether the segment a–b crosses no boundary of the region (and so, starting on the
/// boundary of a filled section, stays inside).
pub(super) fn inside_line(a: Point, b: Point, region: &Region) -> bool {
    let mid = a.midpoint(b);
    let rings = std::iter::once(&region.outer).chain(region.holes.iter());
    let mut inside = false;
    for r in rings {
        for i in 0..r.len() {
            let (p, q) = (r[i], r[(i + 1) % r.len()]);
            let (p, q) = (Point::new(p[0], p[1]), Point::new(q[0], q[1]));
            if proper_cross(a, b, p, q) {
                return false;
            }
            if (p.y <= mid.y) != (q.y <= mid.y)
                && mid.x < p.x + (mid.y - p.y) / (q.y - p.y) * (q.x - p.x)
            {
                inside = !inside;
            }
        }
    }
    inside
}

fn proper_cross(a: Point, b: Point, p: Point, q: Point) -> bool {
    let d = |o: Point, u: Point, v: Point| (u - o).cross(v - o);
    let (d1, d2) = (d(a, b, p), d(a, b, q));
    let (d3, d4) = (d(p, q, a), d(p, q, b));
    let eps = 1e-9;
    ((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps))
        && ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> FillParams {
        FillParams {
            spacing: 0.4,
            length: 3.0,
            angle: 0.0,
            stagger: 4,
            pull_compensation: 0.0,
            along_edge: false,
        }
    }

    fn all(runs: &[Run]) -> Vec<Point> {
        runs.iter().flat_map(|r| r.points.iter().copied()).collect()
    }

    #[test]
    fn a_rectangle_is_one_section_of_rows() {
        let r = Region {
            outer: vec![[0.0, 0.0], [30.0, 0.0], [30.0, 20.0], [0.0, 20.0]],
            holes: vec![],
        };
        let runs = tatami(&r, &params());
        assert_eq!(runs.len(), 1);
        let pts = all(&runs);
        // 50 rows; every stitch ≤ 3 mm; all inside.
        let ys: std::collections::BTreeSet<i64> =
            pts.iter().map(|p| (p.y * 1000.0).round() as i64).collect();
        assert_eq!(ys.len(), 50);
        assert!(pts.windows(2).all(|w| w[0].distance(w[1]) <= 3.0 + 1e-9));
        assert!(pts.iter().all(|p| p.x >= -1e-9 && p.x <= 30.0 + 1e-9));
    }

    #[test]
    fn a_hole_is_left_empty_and_stitches_stay_out_of_it() {
        let r = Region {
            outer: vec![[0.0, 0.0], [30.0, 0.0], [30.0, 30.0], [0.0, 30.0]],
            holes: vec![vec![[10.0, 10.0], [10.0, 20.0], [20.0, 20.0], [20.0, 10.0]]],
        };
        let p = FillParams {
            angle: 0.5,
            ..params()
        };
        let runs = tatami(&r, &p);
        let pts = all(&runs);
        assert!(!pts
            .iter()
            .any(|q| q.x > 10.3 && q.x < 19.7 && q.y > 10.3 && q.y < 19.7));
        // Within each run, no stitch crosses the hole.
        for run in &runs {
            for w in run.points.windows(2) {
                let m = w[0].midpoint(w[1]);
                assert!(
                    !(m.x > 10.5 && m.x < 19.5 && m.y > 10.5 && m.y < 19.5),
                    "{w:?}"
                );
            }
        }
    }

    #[test]
    fn sections_around_a_hole_travel_along_its_edge_instead_of_jumping() {
        let r = Region {
            outer: vec![[0.0, 0.0], [30.0, 0.0], [30.0, 30.0], [0.0, 30.0]],
            holes: vec![vec![[10.0, 10.0], [10.0, 20.0], [20.0, 20.0], [20.0, 10.0]]],
        };
        let runs = tatami(&r, &params());
        assert_eq!(runs.len(), 1, "one continuous run, no jump");
        let pts = all(&runs);
        // No needle point inside the hole (its edge allowed), every stitch ≤ 3 mm.
        assert!(!pts
            .iter()
            .any(|q| q.x > 10.01 && q.x < 19.99 && q.y > 10.01 && q.y < 19.99));
        assert!(pts.windows(2).all(|w| w[0].distance(w[1]) <= 3.0 + 1e-9));
    }
}
