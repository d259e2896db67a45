//! Offsets that keep arcs as arcs.
//!
//! The topology (which parts vanish, loops, a pocket that splits in two, islands that merge
//! with the wall) is left to the polygon library on the flattened contours; the geometry is
//! then rebuilt exactly: every offset contour lies on the analytic offsets of the input
//! pieces — a line shifted by d along its normal, an arc with the same centre and radius
//! r ± d (the seed's `r' = r + sn·Seq·e`), or a round corner of radius |d| about an input
//! vertex. Each polygon edge is matched to the piece it lies on, runs of edges on one piece
//! become one line or one arc, and consecutive pieces are joined at their exact intersection.

use crate::arc::{sweep_between, Arc};
use crate::drawing::{to_ring, Path, Segment};
use crate::polygon::{offset_regions, ring_area, Join, PolygonError, Region};
use kurbo::{Point, Rect, Vec2};

/// One connected area bounded by curves: an outer path (counter-clockwise) and holes
/// (clockwise), e.g. a pocket wall with islands.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Area {
    /// The outer boundary (counter-clockwise).
    pub outer: Path,
    /// The holes (clockwise).
    pub holes: Vec<Path>,
}

impl Area {
    /// Groups closed paths into areas by nesting (even–odd: a path inside one outer is a
    /// hole, inside a hole is a new outer) and orients them.
    pub fn from_paths(paths: &[Path]) -> Vec<Area> {
        let closed: Vec<&Path> = paths.iter().filter(|p| p.closed && !p.is_empty()).collect();
        let rings: Vec<Vec<[f64; 2]>> = closed.iter().map(|p| to_ring(&p.flatten(1e-3))).collect();
        let probe: Vec<Point> = closed.iter().map(|p| p.segments[0].eval(0.5)).collect();
        let inside = |i: usize, j: usize| i != j && point_in_ring(probe[i], &rings[j]);
        let depth: Vec<usize> = (0..closed.len())
            .map(|i| (0..closed.len()).filter(|&j| inside(i, j)).count())
            .collect();
        let mut areas: Vec<(usize, Area)> = Vec::new();
        for i in (0..closed.len()).filter(|&i| depth[i].is_multiple_of(2)) {
            areas.push((
                i,
                Area {
                    outer: oriented(closed[i], true),
                    holes: vec![],
                },
            ));
        }
        for i in (0..closed.len()).filter(|&i| depth[i] % 2 == 1) {
            // The hole belongs to the containing outer of depth one less.
            if let Some(k) = areas
                .iter()
                .position(|(o, _)| depth[*o] + 1 == depth[i] && inside(i, *o))
            {
                areas[k].1.holes.push(oriented(closed[i], false));
            }
        }
        areas.into_iter().map(|(_, a)| a).collect()
    }

    /// Enclosed area (outer less holes), mm².
    pub fn area(&self) -> f64 {
        self.outer.area().abs() - self.holes.iter().map(|h| h.area().abs()).sum::<f64>()
    }

    /// The polygon of this area, flattened to `tol`.
    pub fn to_region(&self, tol: f64) -> Region {
        Region {
            outer: to_ring(&self.outer.flatten(tol)),
            holes: self
                .holes
                .iter()
                .map(|h| to_ring(&h.flatten(tol)))
                .collect(),
        }
    }

    /// Every boundary: the outer then the holes.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        std::iter::once(&self.outer).chain(self.holes.iter())
    }
}

/// A copy of a closed path running counter-clockwise (`ccw`) or clockwise.
pub fn oriented(p: &Path, ccw: bool) -> Path {
    if (p.area() > 0.0) == ccw {
        p.clone()
    } else {
        p.reversed()
    }
}

fn point_in_ring(p: Point, r: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = r.len();
    for i in 0..n {
        let a = r[i];
        let b = r[(i + 1) % n];
        if (a[1] > p.y) != (b[1] > p.y) {
            let x = a[0] + (p.y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// What an offset contour can lie on.
#[derive(Clone, Copy, Debug)]
enum Carrier {
    /// An input line shifted along its right normal; polygon edges may run `reach` past
    /// its ends (where the neighbour's chords were offset).
    Line { a: Point, b: Point, reach: f64 },
    /// An input arc with its radius changed (`span` is the arc), or a round corner about an
    /// input vertex (no span: the whole circle).
    Circle { c: Point, r: f64, span: Option<Arc> },
}

impl Carrier {
    fn radius(&self) -> f64 {
        match *self {
            Carrier::Line { .. } => 0.0,
            Carrier::Circle { r, .. } => r,
        }
    }

    fn bbox(&self) -> Rect {
        match *self {
            Carrier::Line { a, b, reach } => Rect::from_points(a, b).inflate(reach, reach),
            Carrier::Circle {
                c,
                r,
                span: Some(s),
            } => Arc {
                radius: r,
                center: c,
                ..s
            }
            .bounding_box(),
            Carrier::Circle { c, r, span: None } => Rect::new(c.x - r, c.y - r, c.x + r, c.y + r),
        }
    }

    /// Whether the edge p→q lies on this carrier within `tol`, running its way.
    fn holds(&self, p: Point, q: Point, tol: f64) -> bool {
        match *self {
            Carrier::Line { a, b, reach } => {
                let d = b - a;
                let len = d.hypot();
                if len < 1e-12 {
                    return false;
                }
                let u = d / len;
                let off = |x: Point| (x - a).cross(u).abs();
                let along = |x: Point| (x - a).dot(u);
                let e = q - p;
                off(p) <= tol
                    && off(q) <= tol
                    && (-reach..=len + reach).contains(&along(p))
                    && (-reach..=len + reach).contains(&along(q))
                    && (e.hypot() < tol || e.dot(u) > 0.0)
            }
            Carrier::Circle { c, r, span } => {
                let on = |x: Point| (x.distance(c) - r).abs() <= tol;
                if !(on(p) && on(q)) {
                    return false;
                }
                match span {
                    None => true,
                    Some(s) => {
                        // The polygon's vertices near an end come from offset chords of the
                        // flattened input arc, a chord angle (√(8·tol/r)) or so beyond it.
                        let slack = 2.0 * (8.0 * tol / s.radius.max(1e-9)).sqrt().min(0.5);
                        let e = q - p;
                        let turning = (p - c).cross(e);
                        s.contains_angle((p - c).atan2(), slack)
                            && s.contains_angle((q - c).atan2(), slack)
                            && (e.hypot() < tol || (turning > 0.0) == (s.sweep > 0.0))
                    }
                }
            }
        }
    }
}

/// Intersections of two carriers' full lines / circles.
fn intersections(x: &Carrier, y: &Carrier) -> Vec<Point> {
    match (*x, *y) {
        (Carrier::Line { a, b, .. }, Carrier::Line { a: c, b: d, .. }) => {
            let r = b - a;
            let s = d - c;
            let den = r.cross(s);
            if den.abs() < 1e-12 * r.hypot() * s.hypot() {
                return vec![];
            }
            let t = (c - a).cross(s) / den;
            vec![a + r * t]
        }
        (Carrier::Line { a, b, .. }, Carrier::Circle { c, r, .. })
        | (Carrier::Circle { c, r, .. }, Carrier::Line { a, b, .. }) => {
            let d = b - a;
            let len = d.hypot();
            if len < 1e-12 {
                return vec![];
            }
            let u = d / len;
            let t0 = (c - a).dot(u);
            let foot = a + u * t0;
            let h2 = r * r - foot.distance_squared(c);
            if h2 < 0.0 {
                return vec![foot];
            }
            let h = h2.sqrt();
            vec![foot - u * h, foot + u * h]
        }
        (Carrier::Circle { c: c1, r: r1, .. }, Carrier::Circle { c: c2, r: r2, .. }) => {
            circle_circle(c1, r1, c2, r2)
        }
    }
}

/// The two points where circles meet (for circles that just miss, the nearest point on the
/// line of centres, so tangent joints still get one).
pub(crate) fn circle_circle(c1: Point, r1: f64, c2: Point, r2: f64) -> Vec<Point> {
    let v = c2 - c1;
    let d = v.hypot();
    if d < 1e-12 {
        return vec![];
    }
    let u = v / d;
    // Distance along the line of centres to the chord: (r1² − r2² + d²) / 2d.
    let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h2 = r1 * r1 - a * a;
    let m = c1 + u * a;
    if h2 <= 0.0 {
        return vec![m];
    }
    let h = h2.sqrt();
    let n = Vec2::new(-u.y, u.x);
    vec![m + n * h, m - n * h]
}

/// Uniform grid of carriers for looking up which lie near a point.
struct Grid {
    origin: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    fn new(carriers: &[Carrier], pad: f64) -> Grid {
        let boxes: Vec<Rect> = carriers
            .iter()
            .map(|c| c.bbox().inflate(pad, pad))
            .collect();
        let all = boxes
            .iter()
            .copied()
            .reduce(|a, b| a.union(b))
            .unwrap_or(Rect::ZERO);
        let side = (carriers.len() as f64).sqrt().ceil().clamp(1.0, 512.0);
        let cell = (all.width().max(all.height()) / side).max(1e-6);
        let nx = ((all.width() / cell).ceil() as usize + 1).min(1024);
        let ny = ((all.height() / cell).ceil() as usize + 1).min(1024);
        let mut g = Grid {
            origin: Point::new(all.x0, all.y0),
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        };
        for (i, b) in boxes.iter().enumerate() {
            let (x0, y0) = g.index(Point::new(b.x0, b.y0));
            let (x1, y1) = g.index(Point::new(b.x1, b.y1));
            for y in y0..=y1 {
                for x in x0..=x1 {
                    g.cells[y * nx + x].push(i as u32);
                }
            }
        }
        g
    }

    fn index(&self, p: Point) -> (usize, usize) {
        let f = |v: f64, n: usize| ((v / self.cell).floor().max(0.0) as usize).min(n - 1);
        (
            f(p.x - self.origin.x, self.nx),
            f(p.y - self.origin.y, self.ny),
        )
    }

    fn near(&self, p: Point) -> &[u32] {
        let (x, y) = self.index(p);
        &self.cells[y * self.nx + x]
    }
}

/// The carriers of the offsets by `d` of an oriented closed path (material on the left:
/// growing the area moves the boundary to the right of travel).
fn carriers_of(path: &Path, d: f64, tol: f64, out: &mut Vec<Carrier>) {
    let right = |u: Vec2| Vec2::new(u.y, -u.x);
    let reach = 3.0 * tol + 0.1 * d.abs();
    let corner = |p: Point, out: &mut Vec<Carrier>| {
        out.push(Carrier::Circle {
            c: p,
            r: d.abs(),
            span: None,
        })
    };
    let n = path.segments.len();
    for (i, seg) in path.segments.iter().enumerate() {
        // No round corner where the pieces meet tangentially (G1 joints).
        let before = end_tangent(&path.segments[(i + n - 1) % n]);
        if before.dot(start_tangent(seg)) < 1.0 - 1e-9 {
            corner(seg.start(), out);
        }
        match seg {
            Segment::Line(l) => {
                let v = l.p1 - l.p0;
                if v.hypot() > 1e-12 {
                    let n = right(v / v.hypot()) * d;
                    out.push(Carrier::Line {
                        a: l.p0 + n,
                        b: l.p1 + n,
                        reach,
                    });
                }
            }
            Segment::Arc(a) => {
                let r = a.radius + d * a.sweep.signum();
                if r > 1e-9 {
                    out.push(Carrier::Circle {
                        c: a.center,
                        r,
                        span: Some(*a),
                    });
                }
            }
            Segment::Cubic(_) => {
                let mut pts = vec![seg.start()];
                seg.flatten_into(tol, &mut pts);
                for w in pts.windows(2) {
                    let v = w[1] - w[0];
                    if v.hypot() > 1e-12 {
                        let n = right(v / v.hypot()) * d;
                        out.push(Carrier::Line {
                            a: w[0] + n,
                            b: w[1] + n,
                            reach,
                        });
                    }
                    corner(w[1], out);
                }
            }
        }
    }
}

fn start_tangent(s: &Segment) -> Vec2 {
    let v = match s {
        Segment::Line(l) => l.p1 - l.p0,
        Segment::Arc(a) => a.tangent_at(0.0),
        Segment::Cubic(c) => [c.p1 - c.p0, c.p2 - c.p0, c.p3 - c.p0]
            .into_iter()
            .find(|v| v.hypot() > 1e-12)
            .unwrap_or_default(),
    };
    v.normalize()
}

fn end_tangent(s: &Segment) -> Vec2 {
    start_tangent(&s.reversed()) * -1.0
}

/// Offsets areas by `distance` (> 0 grows, < 0 shrinks; holes move the other way), keeping
/// lines as lines and arcs as arcs (convex and concave), with every offset contour within
/// `tol` of the exact offset. Loops are removed, a split area comes back as several areas.
pub fn offset_areas(areas: &[Area], distance: f64, tol: f64) -> Result<Vec<Area>, PolygonError> {
    let tol = tol.max(1e-6);
    let flat_tol = tol / 4.0;
    let oriented_areas: Vec<Area> = areas
        .iter()
        .map(|a| Area {
            outer: oriented(&a.outer, true),
            holes: a.holes.iter().map(|h| oriented(h, false)).collect(),
        })
        .collect();
    let regions: Vec<Region> = oriented_areas
        .iter()
        .map(|a| a.to_region(flat_tol))
        .collect();
    let out = offset_regions(
        &regions,
        distance,
        Join::Round {
            tolerance: flat_tol,
        },
    )?;
    let mut carriers = Vec::new();
    for a in &oriented_areas {
        for p in a.paths() {
            carriers_of(p, distance, flat_tol, &mut carriers);
        }
    }
    if carriers.is_empty() {
        return Ok(vec![]);
    }
    let match_tol = 3.0 * flat_tol + 1e-6;
    let grid = Grid::new(&carriers, match_tol);
    let template = areas.first().map(|a| a.outer.clone()).unwrap_or_default();
    let rebuild = |ring: &[[f64; 2]]| {
        let segments = rebuild_ring(ring, &carriers, &grid, match_tol);
        Path {
            segments,
            closed: true,
            style: template.style,
            source: template.source.clone(),
        }
    };
    Ok(out
        .iter()
        .map(|r| Area {
            outer: rebuild(&r.outer),
            holes: r.holes.iter().map(|h| rebuild(h)).collect(),
        })
        .collect())
}

/// One polygon ring back to lines and arcs on the carriers.
fn rebuild_ring(ring: &[[f64; 2]], carriers: &[Carrier], grid: &Grid, tol: f64) -> Vec<Segment> {
    let pts: Vec<Point> = ring.iter().map(|p| Point::new(p[0], p[1])).collect();
    let n = pts.len();
    if n < 2 {
        return vec![];
    }
    // Carrier of each edge i (pts[i] → pts[i+1]); keep the previous edge's when it fits.
    let mut owner: Vec<Option<u32>> = Vec::with_capacity(n);
    for i in 0..n {
        let (p, q) = (pts[i], pts[(i + 1) % n]);
        let prev = owner.last().copied().flatten();
        let fits = |k: u32| carriers[k as usize].holds(p, q, tol);
        // Input pieces before round corners: at a tangent joint both fit a short edge.
        let is_corner = |k: u32| matches!(carriers[k as usize], Carrier::Circle { span: None, .. });
        let near = grid.near(p);
        let pick = match prev {
            Some(k) if fits(k) => Some(k),
            _ => near
                .iter()
                .copied()
                .find(|&k| !is_corner(k) && fits(k))
                .or_else(|| near.iter().copied().find(|&k| fits(k))),
        };
        owner.push(pick);
    }
    // Start at a change of carrier so no run wraps around the end.
    let start = (0..n).find(|&i| owner[i] != owner[(i + n - 1) % n] || owner[i].is_none());
    let Some(start) = start else {
        // One carrier all the way round: a full circle (a line cannot close on itself).
        if let Some(Carrier::Circle { c, r, .. }) = owner[0].map(|k| carriers[k as usize]) {
            let a0 = (pts[0] - c).atan2();
            let sign = ring_area(ring).signum();
            return vec![Segment::Arc(Arc::new(
                c,
                r,
                a0,
                sign * std::f64::consts::TAU,
            ))];
        }
        return polyline(&pts);
    };
    // Runs: (carrier, first vertex index, last vertex index) in ring order from `start`.
    let mut runs: Vec<(Option<u32>, usize, usize)> = Vec::new();
    for j in 0..n {
        let i = (start + j) % n;
        match runs.last_mut() {
            Some((k, _, end)) if *k == owner[i] && k.is_some() => *end = (i + 1) % n,
            _ => runs.push((owner[i], i, (i + 1) % n)),
        }
    }
    // Junctions: where consecutive runs meet, snapped to their carriers' intersection.
    let m = runs.len();
    let junction: Vec<Point> = (0..m)
        .map(|j| {
            let (prev, cur) = (runs[(j + m - 1) % m].0, runs[j].0);
            let v = pts[runs[j].1];
            match (prev, cur) {
                (Some(a), Some(b)) if a != b => {
                    let (ca, cb) = (&carriers[a as usize], &carriers[b as usize]);
                    let best = intersections(ca, cb)
                        .into_iter()
                        .min_by(|x, y| x.distance(v).total_cmp(&y.distance(v)));
                    // Where pieces meet tangentially the polygon's vertex may slide along the
                    // tangent by up to a chord: √(8·tol·r).
                    let r = ca.radius().max(cb.radius());
                    match best {
                        Some(x) if x.distance(v) <= 4.0 * tol + (8.0 * tol * r).sqrt() => x,
                        _ => v,
                    }
                }
                _ => v,
            }
        })
        .collect();
    let mut segs = Vec::new();
    for j in 0..m {
        let (k, first, last) = runs[j];
        let (s, e) = (junction[j], junction[(j + 1) % m]);
        match k.map(|k| carriers[k as usize]) {
            Some(Carrier::Line { .. }) => segs.push(Segment::line(s, e)),
            Some(Carrier::Circle { c, r, .. }) => {
                // Direction from the polygon's own turning about the centre.
                let mut turn = 0.0;
                let mut i = first;
                while i != last {
                    let (p, q) = (pts[i] - c, pts[(i + 1) % n] - c);
                    turn += p.cross(q).atan2(p.dot(q));
                    i = (i + 1) % n;
                }
                let a0 = (s - c).atan2();
                let sweep = sweep_between(a0, (e - c).atan2(), if turn >= 0.0 { 1 } else { -1 });
                // A run that turned only a little but whose ends coincide is not a full turn.
                let sweep = if sweep.abs() > turn.abs() + std::f64::consts::PI {
                    turn
                } else {
                    sweep
                };
                if s.distance(e) > 1e-12 || sweep.abs() > 1.0 {
                    segs.push(Segment::Arc(Arc::new(c, r, a0, sweep)));
                }
            }
            None => {
                // Unmatched edges stay as they are.
                let mut i = first;
                let mut from = s;
                while i != last {
                    let nxt = (i + 1) % n;
                    let to = if nxt == last { e } else { pts[nxt] };
                    if from.distance(to) > 1e-12 {
                        segs.push(Segment::line(from, to));
                    }
                    from = to;
                    i = nxt;
                }
            }
        }
    }
    segs
}

fn polyline(pts: &[Point]) -> Vec<Segment> {
    let mut segs: Vec<Segment> = pts.windows(2).map(|w| Segment::line(w[0], w[1])).collect();
    segs.push(Segment::line(*pts.last().unwrap(), pts[0]));
    segs
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A stadium: two half circles of radius 10 joined by 30 mm lines, counter-clockwise.
    fn stadium() -> Path {
        let a1 = Arc::new(Point::new(30.0, 10.0), 10.0, -PI / 2.0, PI);
        let a2 = Arc::new(Point::new(0.0, 10.0), 10.0, PI / 2.0, PI);
        Path::new(
            vec![
                Segment::line(Point::new(0.0, 0.0), Point::new(30.0, 0.0)),
                Segment::Arc(a1),
                Segment::line(Point::new(30.0, 20.0), Point::new(0.0, 20.0)),
                Segment::Arc(a2),
            ],
            true,
        )
    }

    fn arcs(p: &Path) -> Vec<Arc> {
        p.segments
            .iter()
            .filter_map(|s| {
                if let Segment::Arc(a) = s {
                    Some(*a)
                } else {
                    None
                }
            })
            .collect()
    }

    #[test]
    fn convex_arc_line_offsets_keep_two_arcs_with_the_same_centres() {
        let areas = Area::from_paths(&[stadium()]);
        for d in [2.0, -3.0, -9.5] {
            let out = offset_areas(&areas, d, 0.001).unwrap();
            assert_eq!(out.len(), 1);
            let p = &out[0].outer;
            let a = arcs(p);
            assert_eq!(a.len(), 2, "d={d}: {:?}", p.segments);
            assert_eq!(p.segments.len(), 4, "d={d}: {:?}", p.segments);
            for arc in &a {
                assert!((arc.radius - (10.0 + d)).abs() < 1e-9);
                assert!((arc.sweep - PI).abs() < 1e-6, "sweep {}", arc.sweep);
            }
            // Exact area of the offset stadium: 30·2r' + π r'².
            let r = 10.0 + d;
            let want = 60.0 * r + PI * r * r;
            assert!(
                (out[0].area() - want).abs() < 0.01 * want.max(1.0),
                "{}",
                out[0].area()
            );
            // Closed chain: every segment starts where the previous ends.
            for w in 0..p.segments.len() {
                let e = p.segments[w].end();
                let s = p.segments[(w + 1) % p.segments.len()].start();
                assert!(e.distance(s) < 1e-6);
            }
        }
    }

    #[test]
    fn square_grown_gets_round_corners_as_arcs() {
        let sq = Path::polyline(
            &[
                Point::new(0.0, 0.0),
                Point::new(10.0, 0.0),
                Point::new(10.0, 10.0),
                Point::new(0.0, 10.0),
            ],
            true,
        );
        let out = offset_areas(&Area::from_paths(&[sq]), 1.0, 0.001).unwrap();
        let p = &out[0].outer;
        let (lines, arcs_n, _) = p.counts();
        assert_eq!((lines, arcs_n), (4, 4), "{:?}", p.segments);
        for a in arcs(p) {
            assert!((a.radius - 1.0).abs() < 1e-9 && (a.sweep - PI / 2.0).abs() < 1e-6);
        }
    }

    #[test]
    fn dumbbell_pocket_splits_into_two_areas_and_an_island_survives() {
        let ring = [
            (0.0, 0.0),
            (20.0, 0.0),
            (20.0, 8.0),
            (30.0, 8.0),
            (30.0, 0.0),
            (50.0, 0.0),
            (50.0, 20.0),
            (30.0, 20.0),
            (30.0, 12.0),
            (20.0, 12.0),
            (20.0, 20.0),
            (0.0, 20.0),
        ];
        let pts: Vec<Point> = ring.iter().map(|&(x, y)| Point::new(x, y)).collect();
        let island = Path::new(
            vec![Segment::Arc(Arc::circle(Point::new(10.0, 10.0), 2.0))],
            true,
        );
        let areas = Area::from_paths(&[Path::polyline(&pts, true), island]);
        assert_eq!(areas.len(), 1);
        assert_eq!(areas[0].holes.len(), 1);
        let out = offset_areas(&areas, -3.0, 0.001).unwrap();
        assert_eq!(out.len(), 2, "split at the neck");
        let with_hole: Vec<&Area> = out.iter().filter(|a| !a.holes.is_empty()).collect();
        assert_eq!(with_hole.len(), 1);
        // The island grew to a circle of radius 5 about its centre: still one arc.
        let h = &with_hole[0].holes[0];
        assert_eq!(h.segments.len(), 1);
        let a = arcs(h)[0];
        assert!((a.radius - 5.0).abs() < 1e-9 && a.sweep < 0.0, "{a:?}");
    }

    #[test]
    fn concave_arc_vanishes_when_its_radius_would_go_below_zero() {
        // A 20×20 square with a concave bite of radius 2 in the top edge.
        // The bite runs clockwise from (12,20) through (10,18) to (8,20).
        let p = Path::new(
            vec![
                Segment::line(Point::new(0.0, 0.0), Point::new(20.0, 0.0)),
                Segment::line(Point::new(20.0, 0.0), Point::new(20.0, 20.0)),
                Segment::line(Point::new(20.0, 20.0), Point::new(12.0, 20.0)),
                Segment::Arc(Arc::new(Point::new(10.0, 20.0), 2.0, 0.0, -PI)),
                Segment::line(Point::new(8.0, 20.0), Point::new(0.0, 20.0)),
                Segment::line(Point::new(0.0, 20.0), Point::new(0.0, 0.0)),
            ],
            true,
        );
        // Growing: the concave arc's radius 2 − 3 < 0, it is gone.
        let out = offset_areas(&Area::from_paths(std::slice::from_ref(&p)), 3.0, 0.001).unwrap();
        assert!(arcs(&out[0].outer)
            .iter()
            .all(|a| (a.radius - 3.0).abs() < 1e-9));
        // Shrinking: the bite grows to radius 3 about the same centre.
        let out = offset_areas(&Area::from_paths(&[p]), -1.0, 0.001).unwrap();
        let big = arcs(&out[0].outer);
        assert!(big
            .iter()
            .any(|a| (a.radius - 3.0).abs() < 1e-9 && a.center == Point::new(10.0, 20.0)));
    }
}
