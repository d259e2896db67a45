//! Closed as drawn: CAD programs rarely set a closed flag or write `Z`. An outline is often a
//! polyline whose last point is its first, or a chain of separate lines, arcs and splines whose
//! ends meet within the program's own tolerance. [`close_and_chain`] is the one rule every
//! importer's drawing goes through: a path whose ends meet within the join tolerance is
//! closed; open pieces of one layer whose ends meet are chained (either direction, any kind of
//! segment) into loops; what stays open is reported per layer, never dropped.
//!
//! Chaining looks ends up in a grid of cells one tolerance wide, so it is linear in the
//! number of pieces, not quadratic.

use oficina_geom::{Drawing, Path, Point, Segment, SourceRef};
use std::collections::HashMap;
use std::fmt;

/// The default join tolerance, mm: what CAD programs write their ends to (AutoCAD's and
/// LibreCAD's default point tolerance is of this order).
pub const JOIN_TOL: f64 = 0.01;

/// The largest join tolerance accepted, mm: beyond it "meeting" would join separate parts.
pub const MAX_JOIN_TOL: f64 = 10.0;

/// Ends closer than this are the same point: no joining line is needed.
const SAME_POINT: f64 = 1e-9;

/// How many neighbours on each side the open-end report looks at (bounds its time on
/// pathological inputs: every end on one vertical line).
const GAP_SCAN: usize = 4096;

/// What stayed open on one layer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OpenLayer {
    /// The layer.
    pub layer: String,
    /// Open paths left on it (after chaining).
    pub paths: usize,
    /// The largest distance from an open end to the nearest other open end of the layer
    /// (its own other end included), mm.
    pub largest_gap: f64,
    /// That end.
    pub at: Point,
    /// The path that end belongs to.
    pub source: SourceRef,
    /// The smallest such distance, mm: a join tolerance above it would join those ends.
    pub smallest_gap: f64,
}

/// What [`close_and_chain`] found and did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Closure {
    /// The tolerance used, mm.
    pub tolerance: f64,
    /// Paths as the file had them (before closing and chaining).
    pub paths_read: usize,
    /// Paths closed in the file (closed flag, `Z`, CIRCLE).
    pub closed_in_file: usize,
    /// Open paths whose own ends met: closed as drawn.
    pub closed_by_ends: usize,
    /// Loops made by chaining two or more open pieces.
    pub chained: usize,
    /// Open pieces that went into those loops.
    pub pieces_chained: usize,
    /// Per layer, what stayed open (layers with nothing open are absent).
    pub open: Vec<OpenLayer>,
}

impl Closure {
    /// Closed loops in the drawing after closing and chaining.
    pub fn loops(&self) -> usize {
        self.closed_in_file + self.closed_by_ends + self.chained
    }

    /// Open paths left, all layers.
    pub fn open_paths(&self) -> usize {
        self.open.iter().map(|o| o.paths).sum()
    }

    /// For a job that found nothing closed to cut: what stayed open, per layer, and the
    /// tolerance that would join the nearest ends; `None` when nothing stayed open.
    pub fn open_hint(&self) -> Option<String> {
        let nearest = self
            .open
            .iter()
            .map(|o| o.smallest_gap)
            .filter(|g| *g > self.tolerance)
            .fold(f64::INFINITY, f64::min);
        let lines: Vec<String> = self
            .to_string()
            .lines()
            .skip(1)
            .map(str::to_string)
            .collect();
        if lines.is_empty() {
            return None;
        }
        let mut hint = lines.join("\n");
        if nearest.is_finite() {
            hint.push_str(&format!(
                "\nends closer than --join-tol ({} mm) are joined: --join-tol {:.3} would join the nearest",
                self.tolerance,
                // Rounded up, so the figure printed does join them.
                (nearest * 1000.0).ceil() / 1000.0
            ));
        }
        Some(hint)
    }
}

impl fmt::Display for Closure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} closed loop{}: {} closed in the file, {} closed where their ends meet, {} chained from {} pieces (join tolerance {} mm)",
            self.loops(),
            if self.loops() == 1 { "" } else { "s" },
            self.closed_in_file,
            self.closed_by_ends,
            self.chained,
            self.pieces_chained,
            self.tolerance
        )?;
        for o in &self.open {
            write!(
                f,
                "\nopen on layer {}: {} path{}, largest gap {:.3} mm at ({:.3}, {:.3}) ({}), smallest {:.3} mm",
                o.layer,
                o.paths,
                if o.paths == 1 { "" } else { "s" },
                o.largest_gap,
                o.at.x,
                o.at.y,
                o.source,
                o.smallest_gap
            )?;
        }
        Ok(())
    }
}

/// Closes and chains every layer of `drawing` with join tolerance `tol` mm (clamped to
/// 0..=[`MAX_JOIN_TOL`]; callers refuse other values with a message first). Closed paths keep
/// their place; a chained loop takes the place of its first piece; open paths stay, merged
/// where they met.
pub fn close_and_chain(drawing: &mut Drawing, tol: f64) -> Closure {
    let tol = if tol.is_finite() {
        tol.clamp(0.0, MAX_JOIN_TOL)
    } else {
        JOIN_TOL
    };
    let mut report = Closure {
        tolerance: tol,
        ..Closure::default()
    };
    for layer in &mut drawing.layers {
        let paths = std::mem::take(&mut layer.paths);
        report.paths_read += paths.len();
        layer.paths = close_layer(paths, tol, &mut report);
        if let Some(open) = open_report(&layer.name, &layer.paths) {
            report.open.push(open);
        }
    }
    report
}

/// One layer: closes what closes by itself, then chains the rest.
fn close_layer(paths: Vec<Path>, tol: f64, report: &mut Closure) -> Vec<Path> {
    // Slots in drawing order: a closed path, or the index of an open piece.
    let mut out: Vec<Option<Path>> = Vec::with_capacity(paths.len());
    let mut pieces: Vec<(usize, Path)> = Vec::new();
    for mut p in paths {
        if p.segments.is_empty() {
            continue;
        }
        if p.closed {
            report.closed_in_file += 1;
            out.push(Some(p));
        } else if ends_meet(&p, tol) && big_enough(&p, tol) {
            close_snapped(&mut p);
            report.closed_by_ends += 1;
            out.push(Some(p));
        } else {
            pieces.push((out.len(), p));
            out.push(None);
        }
    }
    for (slot, path) in chain(pieces, tol, report) {
        out[slot] = Some(path);
    }
    out.into_iter().flatten().collect()
}

fn ends_meet(p: &Path, tol: f64) -> bool {
    match (p.start(), p.end()) {
        (Some(s), Some(e)) => s.distance(e) <= tol,
        _ => false,
    }
}

/// A loop must be more than a point: a stray piece shorter than the tolerance is not a loop.
fn big_enough(p: &Path, tol: f64) -> bool {
    p.bounding_box()
        .is_some_and(|r| r.width().hypot(r.height()) > 2.0 * tol.max(SAME_POINT))
}

/// Marks `p` closed, its last end joined onto its first start as [`join`] does.
fn close_snapped(p: &mut Path) {
    let (Some(s), Some(e)) = (p.start(), p.end()) else {
        return;
    };
    if s.distance(e) > SAME_POINT {
        match (p.segments.last(), p.segments.first()) {
            (Some(Segment::Arc(_)), Some(Segment::Arc(_))) => p.segments.push(Segment::line(e, s)),
            (Some(Segment::Arc(_)), _) => move_start(&mut p.segments[0], e),
            _ => {
                let n = p.segments.len();
                move_end(&mut p.segments[n - 1], s);
            }
        }
    }
    p.closed = true;
}

/// `a` then `b`, where `b` starts within the tolerance of `a`'s end: the end of a line or
/// Bézier is moved onto the other side's point (a sub-tolerance nudge); between two arcs,
/// whose ends their angles fix, a joining line goes in.
fn join(mut a: Vec<Segment>, mut b: Vec<Segment>) -> Vec<Segment> {
    if let (Some(last), Some(first)) = (a.last_mut(), b.first_mut()) {
        let (e, s) = (last.end(), first.start());
        if e.distance(s) > SAME_POINT {
            match (&*last, &*first) {
                (Segment::Arc(_), Segment::Arc(_)) => a.push(Segment::line(e, s)),
                (Segment::Arc(_), _) => move_start(first, e),
                _ => move_end(last, s),
            }
        }
    }
    a.extend(b);
    a
}

/// Moves the end of a line or Bézier (with its last control point, keeping the tangent).
fn move_end(seg: &mut Segment, to: Point) {
    match seg {
        Segment::Line(l) => l.p1 = to,
        Segment::Cubic(c) => {
            let d = to - c.p3;
            c.p2 += d;
            c.p3 = to;
        }
        Segment::Arc(_) => {}
    }
}

/// Moves the start of a line or Bézier (with its first control point).
fn move_start(seg: &mut Segment, to: Point) {
    match seg {
        Segment::Line(l) => l.p0 = to,
        Segment::Cubic(c) => {
            let d = to - c.p0;
            c.p0 = to;
            c.p1 += d;
        }
        Segment::Arc(_) => {}
    }
}

/// Ends of open pieces by grid cell: end `2 i` is piece i's start, `2 i + 1` its end.
struct Ends {
    cell: f64,
    grid: HashMap<(i64, i64), Vec<usize>>,
    points: Vec<Point>,
}

impl Ends {
    fn new(pieces: &[(usize, Path)], tol: f64) -> Ends {
        // Cells one tolerance wide: every end within tol of a point is in its 3 × 3 cells.
        let cell = tol.max(1e-6);
        let mut e = Ends {
            cell,
            grid: HashMap::with_capacity(pieces.len() * 2),
            points: Vec::with_capacity(pieces.len() * 2),
        };
        for (_, p) in pieces {
            for q in [p.start(), p.end()] {
                let q = q.unwrap_or(Point::ORIGIN);
                let id = e.points.len();
                e.points.push(q);
                e.grid.entry(e.key(q)).or_default().push(id);
            }
        }
        e
    }

    fn key(&self, q: Point) -> (i64, i64) {
        // `as` saturates on huge or non-finite values: such points share an edge cell.
        (
            (q.x / self.cell).floor() as i64,
            (q.y / self.cell).floor() as i64,
        )
    }

    /// How many ends (of used pieces too) lie within `tol` of `q`.
    fn meeting(&self, q: Point, tol: f64) -> usize {
        let (kx, ky) = self.key(q);
        let mut n = 0;
        for dx in -1..=1 {
            for dy in -1..=1 {
                let k = (kx.saturating_add(dx), ky.saturating_add(dy));
                for &id in self.grid.get(&k).map(Vec::as_slice).unwrap_or(&[]) {
                    n += usize::from(self.points[id].distance(q) <= tol);
                }
            }
        }
        n
    }

    /// The nearest end within `tol` of `q` whose piece is not used yet.
    fn nearest(&self, q: Point, tol: f64, used: &[bool]) -> Option<usize> {
        let (kx, ky) = self.key(q);
        let mut best: Option<(f64, usize)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                let k = (kx.saturating_add(dx), ky.saturating_add(dy));
                for &id in self.grid.get(&k).map(Vec::as_slice).unwrap_or(&[]) {
                    if used[id / 2] {
                        continue;
                    }
                    let d = self.points[id].distance(q);
                    if d <= tol && best.is_none_or(|(bd, bi)| d < bd || (d == bd && id < bi)) {
                        best = Some((d, id));
                    }
                }
            }
        }
        best.map(|(_, id)| id)
    }
}

/// Chains open pieces whose ends meet into loops (and longer open paths); returns each result
/// with the slot of its first piece.
fn chain(pieces: Vec<(usize, Path)>, tol: f64, report: &mut Closure) -> Vec<(usize, Path)> {
    let ends = Ends::new(&pieces, tol);
    let mut used = vec![false; pieces.len()];
    let mut out = Vec::new();
    for i in 0..pieces.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        let first = &pieces[i].1;
        let mut segs = first.segments.clone();
        let mut members = vec![i];
        let mut closed = false;
        // Forward from the end, then backward from the start; close as soon as the chain's
        // ends meet (a loop is preferred to a longer chain).
        for forward in [true, false] {
            while !closed {
                let (Some(s), Some(e)) = (
                    segs.first().map(|x| x.start()),
                    segs.last().map(|x| x.end()),
                ) else {
                    break;
                };
                if members.len() > 1 && s.distance(e) <= tol {
                    closed = true;
                    break;
                }
                let at = if forward { e } else { s };
                // Only where exactly two ends meet: at a junction of three or more (a grid, a
                // T of strokes) which way an outline goes is a guess, and a guessed loop would
                // cut the network's other pieces off it (the plotter's merge, which walks whole
                // networks, then needs more strokes).
                if ends.meeting(at, tol) != 2 {
                    break;
                }
                let Some(id) = ends.nearest(at, tol, &used) else {
                    break;
                };
                let k = id / 2;
                used[k] = true;
                members.push(k);
                let piece = &pieces[k].1;
                // Forward, the piece must start at our end: matched by its end, it is reversed.
                // Backward, it must end at our start: matched by its start, it is reversed.
                let matched_start = id % 2 == 0;
                let add = if matched_start == forward {
                    piece.segments.clone()
                } else {
                    piece.reversed().segments
                };
                segs = if forward {
                    join(std::mem::take(&mut segs), add)
                } else {
                    join(add, std::mem::take(&mut segs))
                };
            }
        }
        let mut path = Path {
            segments: segs,
            closed: false,
            style: first.style,
            source: chained_source(&pieces, &members),
        };
        if closed && big_enough(&path, tol) {
            close_snapped(&mut path);
            report.chained += 1;
            report.pieces_chained += members.len();
        }
        out.push((pieces[i].0, path));
    }
    out
}

/// The source of a chain: its first piece's file, and the elements it was made of.
fn chained_source(pieces: &[(usize, Path)], members: &[usize]) -> SourceRef {
    let first = &pieces[members[0]].1.source;
    if members.len() == 1 {
        return first.clone();
    }
    let names: Vec<&str> = members
        .iter()
        .take(3)
        .map(|&k| pieces[k].1.source.element.as_str())
        .collect();
    let more = members.len().saturating_sub(3);
    let mut element = names.join(" + ");
    if more > 0 {
        element.push_str(&format!(" + {more} more"));
    }
    SourceRef {
        file: first.file.clone(),
        element,
        line: first.line,
    }
}

/// The open paths of a layer: how many, and the largest and smallest distance from an open
/// end to the nearest other open end.
fn open_report(layer: &str, paths: &[Path]) -> Option<OpenLayer> {
    let open: Vec<&Path> = paths.iter().filter(|p| !p.closed).collect();
    if open.is_empty() {
        return None;
    }
    // (point, path index) for every open end, sorted by x for a sweep.
    let mut ends: Vec<(Point, usize)> = open
        .iter()
        .enumerate()
        .flat_map(|(i, p)| {
            [p.start(), p.end()]
                .into_iter()
                .flatten()
                .map(move |q| (q, i))
        })
        .collect();
    ends.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    let mut largest: Option<(f64, usize)> = None;
    let mut smallest = f64::INFINITY;
    for i in 0..ends.len() {
        let q = ends[i].0;
        let mut best = f64::INFINITY;
        let right = ends.iter().skip(i + 1).take(GAP_SCAN);
        for (p, _) in right {
            if p.x - q.x >= best {
                break;
            }
            best = best.min(p.distance(q));
        }
        for (p, _) in ends[..i].iter().rev().take(GAP_SCAN) {
            if q.x - p.x >= best {
                break;
            }
            best = best.min(p.distance(q));
        }
        if !best.is_finite() {
            continue; // the layer's only end: nothing to measure a gap to
        }
        smallest = smallest.min(best);
        if largest.is_none_or(|(d, _)| best > d) {
            largest = Some((best, i));
        }
    }
    let (gap, at, source) = match largest {
        Some((d, i)) => (d, ends[i].0, open[ends[i].1].source.clone()),
        None => (
            0.0,
            ends.first().map_or(Point::ORIGIN, |e| e.0),
            open[0].source.clone(),
        ),
    };
    Some(OpenLayer {
        layer: layer.to_string(),
        paths: open.len(),
        largest_gap: gap,
        at,
        source,
        smallest_gap: if smallest.is_finite() { smallest } else { 0.0 },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use oficina_geom::kurbo::CubicBez;
    use oficina_geom::Arc;
    use std::f64::consts::FRAC_PI_2;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    fn piece(segs: Vec<Segment>, name: &str) -> Path {
        Path::new(segs, false).with_source(SourceRef::new("t.dxf", name))
    }

    fn drawing(layer: &str, paths: Vec<Path>) -> Drawing {
        let mut d = Drawing::new();
        for q in paths {
            d.push(layer, q);
        }
        d
    }

    /// Every closed path's segments run end to start without a break.
    fn continuous(path: &Path) {
        for w in path.segments.windows(2) {
            assert!(w[0].end().distance(w[1].start()) < 1e-9, "{path:?}");
        }
        if path.closed {
            let (s, e) = (path.start().unwrap(), path.end().unwrap());
            assert!(s.distance(e) < 1e-9, "{path:?}");
        }
    }

    /// A rounded slot: two lines, two half circles as arcs, one line run backwards, one
    /// arc as a Bézier; pieces shuffled and some reversed.
    fn slot_pieces(gap: f64) -> Vec<Path> {
        let right = Arc::new(p(20.0, 5.0), 5.0, -FRAC_PI_2, std::f64::consts::PI);
        let left = Arc::new(p(0.0, 5.0), 5.0, FRAC_PI_2, std::f64::consts::PI);
        vec![
            piece(vec![Segment::Arc(left)], "ARC #L"),
            // The top line, drawn right to left reversed: from (0,10) to (20,10).
            piece(vec![Segment::line(p(0.0, 10.0), p(20.0, 10.0))], "LINE #T"),
            piece(vec![Segment::line(p(gap, 0.0), p(20.0, 0.0))], "LINE #B"),
            piece(vec![Segment::Arc(right.reversed())], "ARC #R"),
        ]
    }

    #[test]
    fn pieces_chain_in_either_direction_across_kinds() {
        let mut d = drawing("0", slot_pieces(0.004));
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!((r.chained, r.pieces_chained, r.loops()), (1, 4, 1), "{r}");
        assert!(r.open.is_empty(), "{r}");
        let loop_ = &d.layers[0].paths[0];
        assert!(loop_.closed);
        continuous(loop_);
        // Area of the slot: 20 × 10 + π 5².
        let want = 200.0 + std::f64::consts::PI * 25.0;
        assert!((loop_.area().abs() - want).abs() < 0.05, "{}", loop_.area());
        assert!(loop_.source.element.contains("ARC #L"), "{}", loop_.source);
        assert!(
            loop_.source.element.contains("+ 1 more"),
            "{}",
            loop_.source
        );
    }

    #[test]
    fn no_chain_goes_through_a_junction_of_three_ends() {
        // Two squares sharing their middle edge (a "日"): its two ends are where three lines
        // meet. The outer ring's pieces chain only between junctions; nothing closes by guess.
        let l = |a: (f64, f64), b: (f64, f64), n: &str| {
            piece(vec![Segment::line(p(a.0, a.1), p(b.0, b.1))], n)
        };
        let pieces = vec![
            l((0.0, 0.0), (10.0, 0.0), "B"),
            l((10.0, 0.0), (10.0, 10.0), "R1"),
            l((10.0, 10.0), (10.0, 20.0), "R2"),
            l((10.0, 20.0), (0.0, 20.0), "T"),
            l((0.0, 20.0), (0.0, 10.0), "L1"),
            l((0.0, 10.0), (0.0, 0.0), "L2"),
            l((0.0, 10.0), (10.0, 10.0), "M"),
        ];
        let mut d = drawing("0", pieces);
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!(r.loops(), 0, "{r}");
        // The middle line and the two U-shaped runs between the junctions, all reported open.
        assert_eq!(r.open.iter().map(|o| o.paths).sum::<usize>(), 3, "{r}");
        let total: f64 = d.layers[0].paths.iter().map(|p| p.length()).sum();
        assert!((total - 70.0).abs() < 1e-9, "nothing dropped: {total}");
    }

    #[test]
    fn a_gap_just_inside_joins_and_just_outside_is_reported() {
        let mut d = drawing("0", slot_pieces(0.0099));
        assert_eq!(close_and_chain(&mut d, 0.01).chained, 1);
        let mut d = drawing("cut", slot_pieces(0.0101));
        let r = close_and_chain(&mut d, 0.01);
        assert_eq!(r.loops(), 0, "{r}");
        assert_eq!(r.open.len(), 1, "{r}");
        let o = &r.open[0];
        assert_eq!((o.layer.as_str(), o.paths), ("cut", 1), "{r}");
        assert!((o.largest_gap - 0.0101).abs() < 1e-9, "{r}");
        assert!(o.at.distance(p(0.0, 0.0)) < 0.011, "{r}");
        // Nothing is dropped: the pieces are one open path, all 4 in it.
        assert_eq!(d.path_count(), 1);
        assert!(!d.layers[0].paths[0].closed);
        assert_eq!(d.layers[0].paths[0].segments.len(), 4);
        let text = r.to_string();
        assert!(
            text.contains("open on layer cut: 1 path, largest gap 0.010 mm"),
            "{text}"
        );
        // A looser tolerance joins it.
        let mut d = drawing("cut", slot_pieces(0.0101));
        assert_eq!(close_and_chain(&mut d, 0.02).chained, 1);
    }

    #[test]
    fn a_polyline_ending_on_its_start_is_closed_as_drawn() {
        let sq = [
            p(0.0, 0.0),
            p(10.0, 0.0),
            p(10.0, 10.0),
            p(0.0, 10.0),
            p(0.0, 0.005),
        ];
        let mut d = drawing("0", vec![Path::polyline(&sq, false)]);
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!((r.closed_by_ends, r.loops()), (1, 1), "{r}");
        let sq = &d.layers[0].paths[0];
        assert!(sq.closed && sq.segments.len() == 4);
        continuous(sq);
        assert!((sq.area() - 100.0).abs() < 1e-9);
        // A piece shorter than the tolerance is no loop, and is not dropped.
        let mut d = drawing(
            "0",
            vec![piece(
                vec![Segment::line(p(0.0, 0.0), p(0.004, 0.0))],
                "LINE #tiny",
            )],
        );
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!((r.loops(), r.open_paths()), (0, 1), "{r}");
        assert!((r.open[0].largest_gap - 0.004).abs() < 1e-12, "{r}");
    }

    #[test]
    fn beziers_are_snapped_and_arcs_get_a_joining_line() {
        // A lens: a Bézier up and an arc back, meeting within 5 µm at both ends.
        let b = CubicBez::new(p(0.0, 0.0), p(3.0, 6.0), p(7.0, 6.0), p(10.0, 0.003));
        let a = Arc::new(p(5.0, 0.0), 5.0, 0.0, -std::f64::consts::PI); // (10,0) → (0,0) below
        let mut d = drawing(
            "0",
            vec![
                piece(vec![Segment::Cubic(b)], "SPLINE #1"),
                piece(vec![Segment::Arc(a)], "ARC #2"),
            ],
        );
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!(r.chained, 1, "{r}");
        let l = &d.layers[0].paths[0];
        continuous(l);
        assert_eq!(
            l.counts(),
            (0, 1, 1),
            "the Bézier's end moved onto the arc's start"
        );
        // Two half circles 5 µm apart at one junction: a joining line between the arcs.
        let top = Arc::new(p(0.0, 0.0), 5.0, 0.0, std::f64::consts::PI);
        let bottom = Arc::new(
            p(0.0, -0.005),
            5.0,
            std::f64::consts::PI,
            std::f64::consts::PI,
        );
        let mut d = drawing(
            "0",
            vec![
                piece(vec![Segment::Arc(top)], "ARC #1"),
                piece(vec![Segment::Arc(bottom)], "ARC #2"),
            ],
        );
        assert_eq!(close_and_chain(&mut d, JOIN_TOL).chained, 1);
        let l = &d.layers[0].paths[0];
        continuous(l);
        assert_eq!(
            l.counts(),
            (2, 2, 0),
            "a joining line at each junction 5 µm apart"
        );
    }

    #[test]
    fn layers_chain_only_their_own_pieces() {
        let mut d = Drawing::new();
        let pieces = slot_pieces(0.0);
        for (i, q) in pieces.into_iter().enumerate() {
            d.push(if i < 2 { "a" } else { "b" }, q);
        }
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!(r.loops(), 0, "{r}");
        assert_eq!(
            r.open.iter().map(|o| o.layer.as_str()).collect::<Vec<_>>(),
            ["a", "b"]
        );
        assert_eq!(
            r.open_paths(),
            2,
            "each layer's two pieces chained into one open path"
        );
    }

    #[test]
    fn closed_paths_stay_where_they_are_and_are_counted() {
        let c = Path::new(vec![Segment::Arc(Arc::circle(p(50.0, 50.0), 3.0))], true);
        let mut paths = vec![c.clone()];
        paths.extend(slot_pieces(0.0));
        paths.push(c);
        let mut d = drawing("0", paths);
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!((r.closed_in_file, r.chained, r.loops()), (2, 1, 3), "{r}");
        let kinds: Vec<usize> = d.layers[0].paths.iter().map(|q| q.segments.len()).collect();
        assert_eq!(kinds, [1, 4, 1], "the loop takes its first piece's place");
    }

    #[test]
    fn ten_thousand_shuffled_pieces_all_chain() {
        // 2500 squares of 4 separate lines each, every second line reversed, in shuffled
        // order: all chain into 2500 loops (through the grid; no timing is asserted).
        let mut lines = Vec::new();
        for k in 0..2500 {
            let (x, y) = ((k % 50) as f64 * 3.0, (k / 50) as f64 * 3.0);
            let c = [p(x, y), p(x + 2.0, y), p(x + 2.0, y + 2.0), p(x, y + 2.0)];
            for i in 0..4 {
                let (a, b) = (c[i], c[(i + 1) % 4]);
                let seg = if i % 2 == 0 {
                    Segment::line(a, b)
                } else {
                    Segment::line(b, a)
                };
                lines.push(piece(vec![seg], "LINE"));
            }
        }
        // A fixed shuffle: stride through the list by a number coprime with its length.
        let n = lines.len();
        let shuffled: Vec<Path> = (0..n).map(|i| lines[(i * 7919) % n].clone()).collect();
        let mut d = drawing("0", shuffled);
        let r = close_and_chain(&mut d, JOIN_TOL);
        assert_eq!(
            (r.chained, r.pieces_chained, r.open_paths()),
            (2500, 10_000, 0),
            "{r}"
        );
        assert!(d.layers[0]
            .paths
            .iter()
            .all(|q| (q.area().abs() - 4.0).abs() < 1e-9));
    }
}
