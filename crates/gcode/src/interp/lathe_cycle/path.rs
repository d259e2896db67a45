//! The profile of a G7x cycle and its cuts, after LinuxCNC's `interp_g7x.cc` (class g7x):
//! the profile is turned so that Z and X decrease along it, then cut in passes and mapped
//! back. The first piece is the move from the cycle's start point to the profile.

use super::segment::{c, intersect, Geo, Move, Segment, C, I, TOLERANCE};

/// More moves than any real part needs: a runaway cut stops here with an error.
const MAX_MOVES: usize = 1_000_000;

#[derive(Clone, Debug, Default)]
pub(super) struct Path {
    pub(super) segs: Vec<Segment>,
    delta: f64,
    escape: C,
    /// Bit 0: Z mirrored, bit 1: X mirrored, bit 2: turned by 90° (G72).
    flip_state: u8,
    pocket_starts: Vec<C>,
}

/// Map a point of the turned profile back to the program's (Z, X), and whether the map
/// mirrors (reverses arcs).
fn unturn(state: u8, p: C) -> (C, bool) {
    match state {
        0 => (p, false),
        1 => (-p.conj(), true),
        2 => (p.conj(), true),
        3 => (-p, false),
        4 => (I * p, false),
        5 => ((I * p).conj(), true),
        6 => (-(I * p).conj(), true),
        _ => (-(I * p), false),
    }
}

impl Path {
    pub(super) fn new(segs: Vec<Segment>) -> Path {
        Path {
            segs,
            delta: 0.5,
            escape: c(0.3, 0.3),
            ..Path::default()
        }
    }

    /// The moves mapped back to the program's frame.
    fn unturned(&self, moves: Vec<Move>) -> Vec<Move> {
        let s = self.flip_state;
        moves
            .into_iter()
            .map(|m| match m {
                Move::Feed(p) => Move::Feed(unturn(s, p).0),
                Move::Rapid(p) => Move::Rapid(unturn(s, p).0),
                Move::Arc { ccw, center, end } => {
                    let (end, mirror) = unturn(s, end);
                    Move::Arc {
                        ccw: ccw != mirror,
                        center: unturn(s, center).0,
                        end,
                    }
                }
            })
            .collect()
    }

    /// Turn the profile by 90° (G72 faces along X as G71 turns along Z).
    fn rotate(&mut self) {
        for s in &mut self.segs {
            s.map(|p| -(p * I), false);
        }
        self.flip_state ^= 4;
    }

    /// Mirror the profile so that Z and X decrease from its first point to its last.
    fn swap(&mut self) {
        let (first, last) = (self.segs[0].end, self.segs[self.segs.len() - 1].end);
        if (first - last).im > 0.0 {
            for s in &mut self.segs {
                s.map(C::conj, true);
            }
            self.flip_state ^= 2;
        }
        if (first - last).re < 0.0 {
            for s in &mut self.segs {
                s.map(|p| -p.conj(), true);
            }
            self.flip_state ^= 1;
        }
    }

    fn monotonic(&mut self) -> Geo<()> {
        let f = &mut self.segs[0];
        if (f.end - f.start).re > 0.0 {
            f.start.re = f.end.re;
        }
        if self.segs.iter().all(Segment::monotonic) {
            Ok(())
        } else {
            Err("Not monotonic".into())
        }
    }

    fn do_finish(&mut self) -> Geo<()> {
        for h in 1..self.segs.len().saturating_sub(1) {
            let (before, rest) = self.segs.split_at_mut(h);
            let (this, after) = rest.split_at_mut(1);
            this[0].finish_corner(&mut before[h - 1], &mut after[0])?;
        }
        self.segs.retain(|s| s.radius() >= 1e-3);
        Ok(())
    }

    /// G70 faces (turns the profile) when the profile without its lead-in is not
    /// monotonic as it is; turned, it must be.
    fn should_rotate(&self) -> Geo<bool> {
        let mut paths = self.clone();
        paths.segs.remove(0);
        paths.swap();
        let rotate = paths.segs.iter().any(|s| !s.monotonic());
        if rotate {
            paths.rotate();
            paths.swap();
        }
        paths.monotonic()?;
        Ok(rotate)
    }

    /// G70: `p` passes along the profile offset from `d` down to `e`, each starting with
    /// a rapid to (x, z) and one to the profile.
    pub(super) fn finish(
        &mut self,
        x: f64,
        z: f64,
        d: f64,
        e: f64,
        p: i32,
    ) -> (Vec<Move>, Geo<()>) {
        let mut out = Vec::new();
        let r = self.finish_into(x, z, d, e, p, &mut out);
        (self.unturned(out), r)
    }

    fn finish_into(
        &mut self,
        x: f64,
        z: f64,
        d: f64,
        e: f64,
        p: i32,
        out: &mut Vec<Move>,
    ) -> Geo<()> {
        self.segs[0].start = c(z, x);
        if self.should_rotate()? {
            self.rotate();
        }
        self.swap();
        self.do_finish()?;
        self.monotonic()?;
        for pass in (1..=p).rev() {
            let distance = f64::from(pass - 1) * (d - e) / f64::from(p) + e;
            let mut paths = self.clone();
            paths.add_distance(distance)?;
            out.push(Move::Rapid(paths.segs[0].start));
            out.push(Move::Rapid(paths.segs[0].end));
            out.extend(paths.segs[1..].iter().map(Segment::draw));
        }
        Ok(())
    }

    /// G71/G72 roughing. `cycle`: 0 everything, 1 no pockets, 2 only the pockets; (x, z)
    /// where the cutting starts; `d` the stock left on the profile; `i` the depth of cut;
    /// `r` the retract.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rough(
        &mut self,
        rotate: bool,
        cycle: u8,
        (x, z): (f64, f64),
        (u, w): (f64, f64),
        d: f64,
        i: f64,
        r: f64,
    ) -> (Vec<Move>, Geo<()>) {
        let mut out = Vec::new();
        let res = self.rough_into(rotate, cycle, (x, z), (u, w), d, i, r, &mut out);
        (self.unturned(out), res)
    }

    #[allow(clippy::too_many_arguments)]
    fn rough_into(
        &mut self,
        rotate: bool,
        cycle: u8,
        (x, z): (f64, f64),
        (u, w): (f64, f64),
        d: f64,
        i: f64,
        r: f64,
        out: &mut Vec<Move>,
    ) -> Geo<()> {
        self.segs[0].start = c(z, x);
        if rotate {
            self.rotate();
        }
        self.swap();
        self.do_finish()?;
        self.monotonic()?;
        self.add_distance(d)?;
        for s in &mut self.segs {
            s.translate(c(w, u));
        }
        self.delta = i.max(2.0 * TOLERANCE);
        self.escape = c(r, r);
        let first = self.segs[0].start;
        out.push(Move::Rapid(first));
        let last = self.segs[self.segs.len() - 1].end;
        if last.im < first.im {
            self.segs
                .push(Segment::straight(last, c(last.re, first.im)));
        }
        self.pocket_starts.push(first);
        self.pocket(cycle, first, 0, out)
    }

    /// Cut from `location` on piece `p` on: dive, cut across, climb into the next pocket
    /// (rs274 recurses into each pocket; here the loop starts again).
    fn pocket(
        &mut self,
        mut cycle: u8,
        mut location: C,
        mut p: usize,
        out: &mut Vec<Move>,
    ) -> Geo<()> {
        let n = self.segs.len();
        // rs274 2.9 loops for ever on some profiles (its interp/g71-endless-loop): bounded.
        let mut steps = 0usize;
        'pocket: loop {
            let mut x = self.pocket_starts.last().map_or(0.0, |s| s.im);
            if cycle == 2 {
                // Skip the first roughing pass.
                while p < n {
                    if self.segs[p].dive(&mut location, -1e9, out, p == 0)? {
                        break;
                    }
                    p += 1;
                }
                cycle = 3;
            }
            while p < n {
                steps += 1;
                if out.len() > MAX_MOVES || steps > 10 * MAX_MOVES {
                    return Err(format!("more than {MAX_MOVES} moves"));
                }
                while x - TOLERANCE > location.im {
                    x -= self.delta;
                }
                if self.segs[p].dive(&mut location, x, out, p == 0)? {
                    if cycle == 1 {
                        // After the roughing pass, along the final contour and done.
                        for s in &self.segs[p..] {
                            s.climb_only(&mut location, out);
                        }
                    } else {
                        // Along the final contour until a pocket, then cut that pocket.
                        while p < n {
                            if self.segs[p].climb(&mut location, out)? {
                                if cycle == 3 {
                                    let top = self.pocket_starts.last().map_or(0.0, |s| s.im);
                                    if location.im > top && self.pocket_starts.len() > 1 {
                                        self.pocket_starts.pop();
                                    }
                                    if self.pocket_starts.len() == 1 {
                                        self.pocket_starts.push(location);
                                    }
                                }
                                continue 'pocket;
                            }
                            p += 1;
                        }
                    }
                    return Ok(());
                }
                if (location.im - x).abs() > TOLERANCE {
                    // x is beyond the current piece: on to the next.
                    p += 1;
                    continue;
                }
                for ip in p..n {
                    let mut is = Vec::new();
                    self.segs[ip].intersection_z(location.im, &mut is);
                    if is.is_empty() {
                        continue;
                    }
                    // The diving piece itself can be hit again if it is an arc.
                    let destination_z = if ip != p { is[0] } else { is[is.len() - 1] };
                    let distance = (destination_z - location.re).abs();
                    if destination_z - TOLERANCE > location.re {
                        continue; // the diving piece at the starting point only
                    }
                    if distance < TOLERANCE {
                        if p == ip {
                            continue;
                        } else if (location - self.segs[ip].start).abs() < TOLERANCE {
                            // Another piece, at its entry point: go on along it.
                            p = ip;
                            break;
                        } else {
                            // A piece of zero length: done.
                            x -= self.delta;
                            break;
                        }
                    }
                    let mut dest = c(destination_z, location.im);
                    out.push(Move::Feed(dest));
                    // Less escape when the cut is too short for the whole of it.
                    let escape = self
                        .escape
                        .scale((distance / 2.0 / self.escape.re).min(1.0));
                    dest += escape;
                    out.push(Move::Rapid(dest));
                    out.push(Move::Rapid(location - escape.conj()));
                    out.push(if p == 0 {
                        Move::Rapid(location)
                    } else {
                        Move::Feed(location)
                    });
                    x -= self.delta;
                    break;
                }
            }
            return Ok(());
        }
    }

    /// Offset the profile (all but its first piece) by `distance`, in steps no larger than
    /// half the smallest piece, joining pieces that part with arcs.
    fn add_distance(&mut self, distance: f64) -> Geo<()> {
        let v1 = self.segs[0].end - self.segs[0].start;
        let v2 = self.segs[self.segs.len() - 1].start - self.segs[0].start;
        let distance = if (v1 / v2).im < 0.0 {
            -distance
        } else {
            distance
        };
        let of = self.segs.remove(0);
        let mut current = 0.0;
        let mut steps = 0usize;
        while current != distance {
            steps += 1;
            if steps > MAX_MOVES || self.segs.is_empty() {
                return Err("Cannot offset the profile".into());
            }
            let mut step = self
                .segs
                .iter()
                .map(|s| s.radius() / 2.0)
                .fold(1e9, f64::min);
            step = step.min((distance - current).abs());
            if distance < 0.0 {
                step = -step;
            }
            for s in &mut self.segs {
                s.offset(step);
            }
            self.segs.retain(|s| s.radius() >= 1e-3);
            let mut k = 0;
            while k + 1 < self.segs.len() {
                let (p, n) = (self.segs[k], self.segs[k + 1]);
                if (p.end - n.start).re > 1e-2 {
                    // Join with an arc about the pieces' old meeting point.
                    let (mut s, mut e) = (p, n);
                    s.offset(-step);
                    e.offset(-step);
                    let center = (s.end + e.start).scale(0.5);
                    self.segs.insert(
                        k + 1,
                        Segment::round(distance > 0.0, p.end, center, n.start),
                    );
                    k += 1;
                }
                k += 1;
            }
            let mut k = 0;
            while k + 1 < self.segs.len() {
                if !self.segs[k].monotonic() {
                    if k == 0 {
                        return Err("Not monotonic".into());
                    }
                    if self.segs[k].radius() < self.segs[k - 1].radius() {
                        self.segs.remove(k);
                    } else {
                        self.segs.remove(k - 1);
                    }
                    k = 0;
                }
                if k + 1 >= self.segs.len() {
                    break;
                }
                if self.segs[k].radius() < 1e-3 {
                    self.segs.remove(k);
                    k = 0;
                } else {
                    let (a, b) = self.segs.split_at_mut(k + 1);
                    intersect(&mut a[k], &mut b[0])?;
                }
                k += 1;
            }
            current += step;
        }
        for k in 0..self.segs.len().saturating_sub(1) {
            let mid = (self.segs[k].end + self.segs[k + 1].start).scale(0.5);
            self.segs[k].end = mid;
            self.segs[k + 1].start = mid;
        }
        let mut of = of;
        of.end = self.segs[0].start;
        self.segs.insert(0, of);
        Ok(())
    }
}
