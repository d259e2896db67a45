//! Velocity profiles along one straight block: trapezoidal (bang-bang acceleration) and
//! jerk-limited S-curve (acceleration ramps linearly). A profile is up to seven polynomial
//! pieces s(t) = s0 + v0·t + a0·t²/2 + j·t³/6; every ramp starts and ends at zero
//! acceleration in S-curve mode, so acceleration is continuous across blocks.

/// One polynomial piece of a profile.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Piece {
    pub t0: f64,
    pub dur: f64,
    pub s0: f64,
    pub v0: f64,
    pub a0: f64,
    pub jerk: f64,
}

impl Piece {
    #[inline]
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let (a, j) = (self.a0, self.jerk);
        let s = self.s0 + t * (self.v0 + t * (a * 0.5 + t * j / 6.0));
        (s, self.v0 + t * (a + t * j * 0.5), a + t * j)
    }
}

/// Limits of one block: peak acceleration and (for S-curve) jerk along the path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Peak acceleration along the path, mm/s².
    pub accel: f64,
    /// `f64::INFINITY` for a trapezoid.
    pub jerk: f64,
}

/// The timed motion of one block.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    pieces: [Piece; 7],
    n: u8,
    /// Time the block takes, seconds.
    pub duration: f64,
    /// Path length, mm.
    pub length: f64,
}

/// Time to change speed by `dv` ≥ 0 under `lim`.
#[inline]
pub(crate) fn ramp_time(dv: f64, lim: Limits) -> f64 {
    if !lim.jerk.is_finite() {
        return dv / lim.accel;
    }
    let knee = lim.accel * lim.accel / lim.jerk;
    if dv >= knee {
        dv / lim.accel + lim.accel / lim.jerk
    } else {
        2.0 * (dv / lim.jerk).sqrt()
    }
}

/// The highest speed in `lo..=hi` from which both ramps (from `v0`, down to `v1`) fit in
/// `length`, by bisection: with a jerk limit the ramp distance has no closed inverse.
fn fastest_fitting(length: f64, v0: f64, v1: f64, lim: Limits, lo: f64, hi: f64) -> f64 {
    let (mut a, mut b) = (lo, hi);
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if ramp_distance(v0, m, lim) + ramp_distance(m, v1, lim) > length {
            b = m;
        } else {
            a = m;
        }
    }
    a
}

/// Distance covered while changing speed from `v0` to `v1`: both shapes are symmetric in
/// time, so the mean speed is (v0 + v1)/2.
#[inline]
pub(crate) fn ramp_distance(v0: f64, v1: f64, lim: Limits) -> f64 {
    0.5 * (v0 + v1) * ramp_time((v1 - v0).abs(), lim)
}

/// The highest speed reachable from `v0` within `dist` (by symmetry also the highest speed
/// from which `v0` is reachable).
#[inline]
pub(crate) fn reachable(v0: f64, dist: f64, lim: Limits) -> f64 {
    if !lim.jerk.is_finite() {
        return (v0 * v0 + 2.0 * lim.accel * dist).sqrt();
    }
    let (a, j) = (lim.accel, lim.jerk);
    let knee = a * a / j;
    if ramp_distance(v0, v0 + knee, lim) <= dist {
        // dv²/(2a) + dv·(v0/a + a/(2j)) + v0·a/j − dist = 0
        let (qa, qb, qc) = (0.5 / a, v0 / a + 0.5 * a / j, v0 * a / j - dist);
        let dv = (-qb + (qb * qb - 4.0 * qa * qc).max(0.0).sqrt()) / (2.0 * qa);
        return v0 + dv.max(knee);
    }
    // Short ramp: with u = √(dv/j), j·u³ + 2·v0·u − dist = 0 (one real root; Cardano).
    let (p, q) = (2.0 * v0 / j, -dist / j);
    let disc = (q * 0.5).powi(2) + (p / 3.0).powi(3);
    let sd = disc.sqrt();
    let mut u = (-q * 0.5 + sd).cbrt() + (-q * 0.5 - sd).cbrt();
    for _ in 0..2 {
        // Newton polish against cancellation when v0 dominates.
        let f = j * u * u * u + 2.0 * v0 * u - dist;
        let df = 3.0 * j * u * u + 2.0 * v0;
        if df > 0.0 {
            u -= f / df;
        }
    }
    v0 + j * u.max(0.0) * u.max(0.0)
}

/// The lowest speed reachable by braking from `v0` within `dist` (0 when it can stop).
pub(crate) fn brake_floor(v0: f64, dist: f64, lim: Limits) -> f64 {
    if ramp_distance(0.0, v0, lim) <= dist {
        return 0.0;
    }
    if !lim.jerk.is_finite() {
        return (v0 * v0 - 2.0 * lim.accel * dist).max(0.0).sqrt();
    }
    // ramp_distance(v, v0) falls as v rises towards v0: bisect for the one that equals dist.
    let (mut lo, mut hi) = (0.0, v0);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if ramp_distance(m, v0, lim) > dist {
            lo = m;
        } else {
            hi = m;
        }
    }
    hi
}

impl Motion {
    /// A pause of `duration` seconds at rest.
    pub fn dwell(duration: f64) -> Motion {
        let mut m = Motion {
            duration,
            ..Motion::default()
        };
        m.pieces[0] = Piece {
            dur: duration,
            ..Piece::default()
        };
        m.n = 1;
        m
    }

    /// Plans `length` from `v0` to `v1` cruising at most at `vmax`. The caller guarantees
    /// that v1 is reachable from v0 within length (the planner's passes do); small
    /// violations from rounding are absorbed by capping the peak.
    pub fn plan(length: f64, v0: f64, vmax: f64, v1: f64, lim: Limits) -> Motion {
        if v0 > vmax {
            return Motion::slow_down(length, v0, vmax, v1, lim);
        }
        let lo = v0.max(v1);
        let mut peak = vmax.max(lo);
        if ramp_distance(v0, peak, lim) + ramp_distance(peak, v1, lim) > length {
            peak = if !lim.jerk.is_finite() {
                ((2.0 * lim.accel * length + v0 * v0 + v1 * v1) * 0.5)
                    .sqrt()
                    .clamp(lo, peak)
            } else {
                fastest_fitting(length, v0, v1, lim, lo, peak)
            };
        }
        Motion::ramp_cruise_ramp(length, v0, peak, v1, lim)
    }

    /// Entering above the cruise speed (a feed override lowered it while moving): brake to
    /// the new cruise speed first, cruise, then reach `v1`. When the block is too short for
    /// both ramps, the cruise speed is the highest one, between `v1` and `vmax`, that fits.
    fn slow_down(length: f64, v0: f64, vmax: f64, v1: f64, lim: Limits) -> Motion {
        let mut cruise = vmax.max(v1);
        if ramp_distance(v0, cruise, lim) + ramp_distance(cruise, v1, lim) > length {
            cruise = fastest_fitting(length, v0, v1, lim, v1.min(cruise), cruise);
        }
        Motion::ramp_cruise_ramp(length, v0, cruise, v1, lim)
    }

    /// `length` as a ramp from `v0` to `cruise`, a cruise, and a ramp to `v1`; the caller
    /// chose `cruise` so that both ramps fit.
    fn ramp_cruise_ramp(length: f64, v0: f64, cruise: f64, v1: f64, lim: Limits) -> Motion {
        let mut m = Motion {
            length,
            ..Motion::default()
        };
        let (mut t, mut s) = (0.0, 0.0);
        m.ramp(&mut t, &mut s, v0, cruise, lim);
        let rest = length - s - ramp_distance(cruise, v1, lim);
        if cruise > 0.0 && rest > 0.0 {
            m.push(
                &mut t,
                &mut s,
                Piece {
                    dur: rest / cruise,
                    v0: cruise,
                    ..Piece::default()
                },
            );
        }
        m.ramp(&mut t, &mut s, cruise, v1, lim);
        m.duration = t;
        m
    }

    fn push(&mut self, t: &mut f64, s: &mut f64, mut p: Piece) {
        if p.dur <= 0.0 {
            return;
        }
        p.t0 = *t;
        p.s0 = *s;
        *s = p.at(p.dur).0;
        *t += p.dur;
        self.pieces[self.n as usize] = p;
        self.n += 1;
    }

    fn ramp(&mut self, t: &mut f64, s: &mut f64, v0: f64, v1: f64, lim: Limits) {
        let dv = v1 - v0;
        if dv == 0.0 {
            return;
        }
        let sign = dv.signum();
        let a = lim.accel * sign;
        if !lim.jerk.is_finite() {
            self.push(
                t,
                s,
                Piece {
                    dur: dv / a,
                    v0,
                    a0: a,
                    ..Piece::default()
                },
            );
            return;
        }
        let j = lim.jerk * sign;
        let knee = lim.accel * lim.accel / lim.jerk;
        // Jerk up to the peak acceleration `ap`, hold it for `tc`, jerk back down. A change
        // below the knee never reaches the limit: no hold, and ap = jerk · tj.
        let (tj, tc, ap) = if dv.abs() >= knee {
            let tj = lim.accel / lim.jerk;
            (tj, dv.abs() / lim.accel - tj, a)
        } else {
            let tj = (dv.abs() / lim.jerk).sqrt();
            (tj, 0.0, lim.jerk * tj * sign)
        };
        let v_mid = v0 + ap * tj * 0.5;
        self.push(
            t,
            s,
            Piece {
                dur: tj,
                v0,
                jerk: j,
                ..Piece::default()
            },
        );
        // `push` drops a piece of no duration: the hold below the knee.
        self.push(
            t,
            s,
            Piece {
                dur: tc,
                v0: v_mid,
                a0: ap,
                ..Piece::default()
            },
        );
        self.push(
            t,
            s,
            Piece {
                dur: tj,
                v0: v_mid + ap * tc,
                a0: ap,
                jerk: -j,
                ..Piece::default()
            },
        );
    }

    /// The first `t` seconds of this motion (what was executed before a live re-plan).
    pub fn truncated(&self, t: f64) -> Motion {
        let mut m = Motion::default();
        for p in self.pieces() {
            if p.t0 >= t {
                break;
            }
            let mut q = *p;
            q.dur = q.dur.min(t - p.t0);
            m.pieces[m.n as usize] = q;
            m.n += 1;
        }
        m.duration = t.clamp(0.0, self.duration);
        m.length = self.at(m.duration).0;
        m
    }

    /// The pieces (constant jerk each) of the motion, in time order.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces[..self.n as usize]
    }

    /// Entry speed.
    pub fn v_start(&self) -> f64 {
        self.pieces().first().map_or(0.0, |p| p.v0)
    }

    /// Exit speed.
    pub fn v_end(&self) -> f64 {
        self.pieces().last().map_or(0.0, |p| p.at(p.dur).1)
    }

    /// Distance, speed and acceleration at time `t` (clamped to the block).
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let ps = self.pieces();
        let Some(last) = ps.last() else {
            return (0.0, 0.0, 0.0);
        };
        let p = ps.iter().find(|p| t < p.t0 + p.dur).unwrap_or(last);
        let (s, v, a) = p.at((t - p.t0).clamp(0.0, p.dur));
        (s.min(self.length), v, a)
    }

    /// The time at which distance `s` is reached (inverse of [`Motion::at`]).
    pub fn time_at(&self, s: f64) -> f64 {
        let ps = self.pieces();
        let n = ps.len();
        for (i, p) in ps.iter().enumerate() {
            let s_end = if i + 1 < n {
                ps[i + 1].s0
            } else {
                f64::INFINITY
            };
            if s < s_end {
                return p.t0 + piece_time(p, s - p.s0);
            }
        }
        self.duration
    }
}

/// Time into `p` at which it has covered `ds` (s is monotone since v ≥ 0).
#[inline]
fn piece_time(p: &Piece, ds: f64) -> f64 {
    if ds <= 0.0 {
        return 0.0;
    }
    if p.jerk == 0.0 {
        if p.a0 == 0.0 {
            return if p.v0 > 0.0 {
                (ds / p.v0).min(p.dur)
            } else {
                p.dur
            };
        }
        // Stable root of a/2·t² + v0·t − ds = 0.
        let disc = p.v0 * p.v0 + 2.0 * p.a0 * ds;
        if disc <= 0.0 {
            return p.dur; // beyond a decelerating piece's reach: rounding at its end
        }
        let t = 2.0 * ds / (p.v0 + disc.sqrt());
        return if t.is_finite() { t.min(p.dur) } else { p.dur };
    }
    // Cubic: Newton inside a shrinking bracket.
    let (mut lo, mut hi) = (0.0, p.dur);
    let mut t = p.dur * 0.5;
    for _ in 0..60 {
        let (s, v, _) = p.at(t);
        let f = s - p.s0 - ds;
        if f > 0.0 {
            hi = t;
        } else {
            lo = t;
        }
        if hi - lo < 1e-13 {
            break;
        }
        let next = if v > 0.0 { t - f / v } else { f64::NAN };
        t = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRAP: Limits = Limits {
        accel: 100.0,
        jerk: f64::INFINITY,
    };
    const SC: Limits = Limits {
        accel: 100.0,
        jerk: 2000.0,
    };

    #[test]
    fn long_trapezoid_time_is_closed_form() {
        // 100 mm at 50 mm/s with 100 mm/s²: ramps 0.5 s and 12.5 mm each, cruise 75 mm.
        let m = Motion::plan(100.0, 0.0, 50.0, 0.0, TRAP);
        assert!(
            (m.duration - (0.5 + 1.5 + 0.5)).abs() < 1e-12,
            "{}",
            m.duration
        );
        assert!((m.at(m.duration).0 - 100.0).abs() < 1e-9);
    }

    #[test]
    fn scurve_ends_exactly_and_inverts() {
        for &(l, v0, vm, v1) in &[
            (100.0_f64, 0.0_f64, 50.0, 0.0_f64),
            (1.0, 3.0, 50.0, 1.0),
            (0.001, 0.0, 9.0, 0.0),
        ] {
            let v1 = v1.min(reachable(v0, l, SC));
            let m = Motion::plan(l, v0, vm, v1, SC);
            let (s, v, a) = m.at(m.duration);
            assert!((s - l).abs() < 1e-9 * l.max(1.0), "{s} vs {l}");
            assert!((v - v1).abs() < 1e-6, "{v} vs {v1}");
            assert!(a.abs() < 1e-6);
            for k in 1..10 {
                let t = m.duration * k as f64 / 10.0;
                let back = m.time_at(m.at(t).0);
                assert!((back - t).abs() < 1e-7, "{t} {back}");
            }
        }
    }

    #[test]
    fn slowing_down_from_above_the_cruise_speed() {
        for lim in [TRAP, SC] {
            // 40 → 20 mm/s over 100 mm, ending at rest.
            let m = Motion::plan(100.0, 40.0, 20.0, 0.0, lim);
            let (s, v, _) = m.at(m.duration);
            assert!((s - 100.0).abs() < 1e-9 && v.abs() < 1e-9, "{s} {v}");
            // Closed form: brake 40→20 and 20→0 (each symmetric, so mean speed), cruise the rest.
            let (t1, t2) = (ramp_time(20.0, lim), ramp_time(20.0, lim));
            let (d1, d2) = (30.0 * t1, 10.0 * t2);
            let expect = t1 + t2 + (100.0 - d1 - d2) / 20.0;
            assert!(
                (m.duration - expect).abs() < 1e-9,
                "{} {expect}",
                m.duration
            );
            // Never faster than the entry, and at the new cruise speed halfway.
            assert!((m.at(m.time_at(50.0)).1 - 20.0).abs() < 1e-9);
            // Too short to cruise: the brake ends where the block does.
            let d = ramp_distance(30.0, 40.0, lim);
            let short = Motion::plan(d, 40.0, 10.0, 30.0, lim);
            assert!((short.v_end() - 30.0).abs() < 1e-6, "{}", short.v_end());
        }
    }

    #[test]
    fn brake_floor_inverts_ramp_distance() {
        for lim in [TRAP, SC] {
            for &(v0, d) in &[(50.0, 0.5), (20.0, 1.0), (5.0, 100.0)] {
                let v = brake_floor(v0, d, lim);
                if v > 0.0 {
                    assert!((ramp_distance(v, v0, lim) - d).abs() < 1e-9, "{v0} {d} {v}");
                } else {
                    assert!(ramp_distance(0.0, v0, lim) <= d);
                }
            }
        }
    }

    #[test]
    fn reachable_inverts_ramp_distance() {
        for lim in [TRAP, SC] {
            for &(v0, d) in &[(0.0, 0.001), (0.0, 10.0), (20.0, 0.5), (5.0, 100.0)] {
                let v1 = reachable(v0, d, lim);
                assert!(
                    (ramp_distance(v0, v1, lim) - d).abs() < 1e-9 * d.max(1.0),
                    "{v0} {d}"
                );
            }
        }
    }
}
