//! A tool-centre contour as lines and arcs, walked by arc length with Z given as a
//! piecewise-linear function of it: ramps, tabs and flat passes are all such walks.

use crate::Move;
use oficina_geom::{Path, Segment};
use std::f64::consts::TAU;

pub(super) type P = [f64; 2];

/// One piece of a tool-centre chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    /// A straight piece from `a` to `b`.
    Line {
        /// Start.
        a: P,
        /// End.
        b: P,
    },
    /// Centre, radius, start angle, signed sweep (> 0 counter-clockwise).
    Arc {
        /// Centre.
        c: P,
        /// Radius, mm.
        r: f64,
        /// Start angle, radians.
        a0: f64,
        /// Signed sweep, radians (> 0 counter-clockwise).
        sweep: f64,
    },
}

impl Piece {
    /// Start point.
    pub fn start(&self) -> P {
        self.at(0.0)
    }
    /// End point.
    pub fn end(&self) -> P {
        self.at(1.0)
    }
    /// Length, mm.
    pub fn length(&self) -> f64 {
        match *self {
            Piece::Line { a, b } => (b[0] - a[0]).hypot(b[1] - a[1]),
            Piece::Arc { r, sweep, .. } => r * sweep.abs(),
        }
    }
    /// The point at fraction `t` of the piece.
    pub fn at(&self, t: f64) -> P {
        match *self {
            Piece::Line { a, b } => [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t],
            Piece::Arc { c, r, a0, sweep } => {
                let ang = a0 + sweep * t;
                [c[0] + r * ang.cos(), c[1] + r * ang.sin()]
            }
        }
    }
    /// Unit direction of travel at fraction `t` (a zero vector for a point).
    pub fn direction(&self, t: f64) -> P {
        let d = match *self {
            Piece::Line { a, b } => [b[0] - a[0], b[1] - a[1]],
            Piece::Arc { a0, sweep, .. } => {
                // d/dt (cos, sin)(a0 + sweep·t) = sweep·(−sin, cos).
                let ang = a0 + sweep * t;
                [-sweep * ang.sin(), sweep * ang.cos()]
            }
        };
        let n = d[0].hypot(d[1]);
        if n > 0.0 {
            [d[0] / n, d[1] / n]
        } else {
            [0.0, 0.0]
        }
    }
    /// The part between fractions `t0` < `t1`.
    pub fn sub(&self, t0: f64, t1: f64) -> Piece {
        match *self {
            Piece::Line { .. } => Piece::Line {
                a: self.at(t0),
                b: self.at(t1),
            },
            Piece::Arc { c, r, a0, sweep } => Piece::Arc {
                c,
                r,
                a0: a0 + sweep * t0,
                sweep: sweep * (t1 - t0),
            },
        }
    }
    /// The same piece run the other way.
    pub fn reversed(&self) -> Piece {
        match *self {
            Piece::Line { a, b } => Piece::Line { a: b, b: a },
            Piece::Arc { c, r, a0, sweep } => Piece::Arc {
                c,
                r,
                a0: a0 + sweep,
                sweep: -sweep,
            },
        }
    }
    /// The move that cuts this piece ending at height `z`.
    pub fn to_move(&self, z: f64, feed: f64) -> Move {
        let [x, y] = self.end();
        match *self {
            Piece::Line { .. } => Move::Line {
                to: [x, y, z],
                feed,
            },
            Piece::Arc { c, sweep, .. } => Move::Arc {
                to: [x, y, z],
                center: c,
                ccw: sweep > 0.0,
                feed,
            },
        }
    }
}

/// A chain of pieces, each starting where the last ended.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// The pieces, each starting where the previous ends.
    pub pieces: Vec<Piece>,
    /// The last end joins the first start.
    pub closed: bool,
}

/// Cubic Béziers become lines no further than this from the curve (mm).
pub(super) const FLATTEN_TOL: f64 = 0.005;

impl Chain {
    /// Lines and arcs as they are; Béziers flattened to [`FLATTEN_TOL`].
    pub fn from_path(p: &Path) -> Chain {
        let mut pieces = Vec::with_capacity(p.segments.len());
        for s in &p.segments {
            match s {
                Segment::Line(l) => pieces.push(Piece::Line {
                    a: [l.p0.x, l.p0.y],
                    b: [l.p1.x, l.p1.y],
                }),
                Segment::Arc(a) => pieces.push(Piece::Arc {
                    c: [a.center.x, a.center.y],
                    r: a.radius,
                    a0: a.start_angle,
                    sweep: a.sweep,
                }),
                Segment::Cubic(_) => {
                    let mut pts = vec![s.start()];
                    s.flatten_into(FLATTEN_TOL, &mut pts);
                    for w in pts.windows(2) {
                        pieces.push(Piece::Line {
                            a: [w[0].x, w[0].y],
                            b: [w[1].x, w[1].y],
                        });
                    }
                }
            }
        }
        pieces.retain(|p| p.length() > 1e-9);
        Chain {
            pieces,
            closed: p.closed,
        }
    }

    /// Length along the pieces, mm.
    pub fn length(&self) -> f64 {
        self.pieces.iter().map(Piece::length).sum()
    }

    /// Start point.
    pub fn start(&self) -> P {
        self.pieces.first().map_or([0.0; 2], Piece::start)
    }

    /// End point.
    pub fn end(&self) -> P {
        self.pieces.last().map_or([0.0; 2], Piece::end)
    }

    /// The same chain run the other way.
    pub fn reversed(&self) -> Chain {
        Chain {
            pieces: self.pieces.iter().rev().map(Piece::reversed).collect(),
            closed: self.closed,
        }
    }

    /// The point at arc length `s` (clamped to the chain).
    pub fn point_at(&self, s: f64) -> P {
        let mut at = 0.0;
        for p in &self.pieces {
            let l = p.length();
            if s <= at + l && l > 0.0 {
                return p.at(((s - at) / l).clamp(0.0, 1.0));
            }
            at += l;
        }
        self.end()
    }

    /// The same closed chain starting at arc length `s`.
    pub fn rotated(&self, s: f64) -> Chain {
        if !self.closed || self.pieces.is_empty() {
            return self.clone();
        }
        let len = self.length();
        let mut pieces = self.between(s, s + len);
        pieces.retain(|p| p.length() > 1e-9);
        Chain {
            pieces,
            closed: true,
        }
    }

    /// Arc length of the point of the chain nearest `p` (checked at every piece end and
    /// at the foot of the perpendicular on lines and arcs).
    pub fn nearest(&self, p: P) -> (f64, f64) {
        let mut best = (f64::INFINITY, 0.0);
        let mut s0 = 0.0;
        for piece in &self.pieces {
            let len = piece.length();
            let t = match *piece {
                Piece::Line { a, b } => {
                    let d = [b[0] - a[0], b[1] - a[1]];
                    let dd = d[0] * d[0] + d[1] * d[1];
                    (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / dd).clamp(0.0, 1.0)
                }
                Piece::Arc { c, a0, sweep, .. } => {
                    let ang = (p[1] - c[1]).atan2(p[0] - c[0]);
                    let rel = if sweep > 0.0 {
                        (ang - a0).rem_euclid(TAU)
                    } else {
                        (a0 - ang).rem_euclid(TAU)
                    };
                    (rel / sweep.abs()).min(1.0)
                }
            };
            for t in [0.0, t, 1.0] {
                let q = piece.at(t);
                let d = (q[0] - p[0]).hypot(q[1] - p[1]);
                if d < best.0 {
                    best = (d, s0 + t * len);
                }
            }
            s0 += len;
        }
        (best.1, best.0)
    }

    /// The pieces between arc lengths `s0` < `s1`; on a closed chain they may wrap round.
    pub fn between(&self, s0: f64, s1: f64) -> Vec<Piece> {
        let len = self.length();
        let mut out = Vec::new();
        if len <= 0.0 || s1 <= s0 {
            return out;
        }
        let mut base = if self.closed {
            (s0 / len).floor() * len
        } else {
            0.0
        };
        while base < s1 {
            let mut at = base;
            for piece in &self.pieces {
                let l = piece.length();
                let (a, b) = (at, at + l);
                at = b;
                if b <= s0 || a >= s1 || l <= 0.0 {
                    continue;
                }
                let t0 = ((s0 - a) / l).max(0.0);
                let t1 = ((s1 - a) / l).min(1.0);
                // A sliver from rounding at a piece end would post as an arc from a point
                // to itself, which controls read as a full circle.
                if (t1 - t0) * l > 1e-9 {
                    out.push(piece.sub(t0, t1));
                }
            }
            if !self.closed {
                break;
            }
            base += len;
        }
        out
    }

    /// Cuts from arc length `profile[0].0` to the last, with Z linear between the
    /// profile's points (arcs become helical where Z changes).
    pub fn walk(&self, profile: &[(f64, f64)], feed: f64, out: &mut Vec<Move>) {
        for w in profile.windows(2) {
            let ((sa, za), (sb, zb)) = (w[0], w[1]);
            let pieces = self.between(sa, sb);
            let total: f64 = pieces.iter().map(Piece::length).sum();
            let mut done = 0.0;
            for p in pieces {
                done += p.length();
                let z = if total > 0.0 {
                    za + (zb - za) * done / total
                } else {
                    zb
                };
                out.push(p.to_move(z, feed));
            }
        }
    }

    /// The chain as points, arcs cut into chords no further than `tol` from them.
    pub fn polygon(&self, tol: f64) -> Vec<P> {
        let mut pts = vec![self.start()];
        for p in &self.pieces {
            match *p {
                Piece::Line { b, .. } => pts.push(b),
                Piece::Arc { r, sweep, .. } => {
                    let n = oficina_geom::chord_count(r, sweep, tol).max(1);
                    for k in 1..=n {
                        pts.push(p.at(k as f64 / n as f64));
                    }
                }
            }
        }
        pts
    }
}

/// The larger of two piecewise-linear profiles over the same span, with a point added where
/// they cross.
pub(super) fn max_profile(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let eval = |f: &[(f64, f64)], s: f64| -> f64 {
        match f.iter().position(|&(x, _)| x >= s) {
            None => f.last().map_or(0.0, |p| p.1),
            Some(0) => f[0].1,
            Some(i) => {
                let ((x0, z0), (x1, z1)) = (f[i - 1], f[i]);
                if x1 - x0 <= 0.0 {
                    z1
                } else {
                    z0 + (z1 - z0) * (s - x0) / (x1 - x0)
                }
            }
        }
    };
    let mut xs: Vec<f64> = a.iter().chain(b).map(|p| p.0).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|x, y| (*x - *y).abs() < 1e-9);
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(xs.len() * 2);
    for (k, &x) in xs.iter().enumerate() {
        if k > 0 {
            let x0 = xs[k - 1];
            let d0 = eval(a, x0) - eval(b, x0);
            let d1 = eval(a, x) - eval(b, x);
            if d0 * d1 < 0.0 {
                let xc = x0 + (x - x0) * d0 / (d0 - d1);
                out.push((xc, eval(a, xc).max(eval(b, xc))));
            }
        }
        out.push((x, eval(a, x).max(eval(b, x))));
    }
    out
}

/// Even–odd point-in-polygon over several rings.
pub(crate) fn inside<R: AsRef<[P]>>(rings: &[R], p: P) -> bool {
    let mut inside = false;
    for r in rings {
        let r = r.as_ref();
        let n = r.len();
        for i in 0..n {
            let (a, b) = (r[i], r[(i + 1) % n]);
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    inside = !inside;
                }
            }
        }
    }
    inside
}

/// Rings with their bounding boxes, for many inside tests against a drawing of many shapes:
/// a ring whose box does not hold a point crosses the point's ray an even number of times
/// (it is closed and the point is outside it), so skipping it leaves the even–odd count as
/// it was; only the few rings near a segment are walked.
pub(super) struct Rings {
    rings: Vec<Vec<P>>,
    boxes: Vec<[f64; 4]>,
}

impl Rings {
    pub(super) fn new(rings: Vec<Vec<P>>) -> Rings {
        let boxes = rings
            .iter()
            .map(|r| {
                r.iter().fold(
                    [
                        f64::INFINITY,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        f64::NEG_INFINITY,
                    ],
                    |b, p| {
                        [
                            b[0].min(p[0]),
                            b[1].min(p[1]),
                            b[2].max(p[0]),
                            b[3].max(p[1]),
                        ]
                    },
                )
            })
            .collect();
        Rings { rings, boxes }
    }

    /// Whether the segment a→b stays inside the rings (sampled every 0.05 mm), so a feed
    /// link along it cuts only where the pass is allowed to cut.
    pub(super) fn segment_inside(&self, a: P, b: P) -> bool {
        let (x0, x1) = (a[0].min(b[0]), a[0].max(b[0]));
        let (y0, y1) = (a[1].min(b[1]), a[1].max(b[1]));
        let near: Vec<&Vec<P>> = self
            .rings
            .iter()
            .zip(&self.boxes)
            .filter(|(_, bx)| bx[0] <= x1 && bx[2] >= x0 && bx[1] <= y1 && bx[3] >= y0)
            .map(|(r, _)| r)
            .collect();
        segment_inside(&near, a, b)
    }
}

/// Whether the segment a→b stays inside `rings` (sampled every 0.05 mm), so a feed link
/// along it cuts only where the pass is allowed to cut.
pub(super) fn segment_inside<R: AsRef<[P]>>(rings: &[R], a: P, b: P) -> bool {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let n = (len / 0.05).ceil().max(1.0) as usize;
    (0..=n).all(|k| {
        let t = k as f64 / n as f64;
        inside(rings, [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t])
    })
}
