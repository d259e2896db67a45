//! Step compression in the form of Klipper's `queue_step`: runs of (interval, count, add)
//! where the first step comes `interval` ticks after the previous one and each following
//! interval grows by `add`. A run is accepted only while every step stays within
//! `max_error` of its exact time; the feasible (interval, add) pairs form a convex polygon
//! that each new step clips by a strip, so the greedy run is the longest exact one.

/// One compressed run of steps in one direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QueueStep {
    pub interval: u32,
    pub count: u16,
    pub add: i16,
    pub forward: bool,
}

/// Compresses the step times of one motor.
pub struct Compressor {
    clock_hz: f64,
    max_error: f64,
    /// Exact times (ticks) not yet compressed; bounded by `WINDOW`.
    pending: Vec<f64>,
    forward: bool,
    /// Tick of the last emitted step as a decoder reproduces it.
    last: i64,
    /// The compressed runs so far.
    pub out: Vec<QueueStep>,
}

const WINDOW: usize = 4096;
/// Longest run searched: keeps the polygon small and the search linear in the step count.
const MAX_RUN: usize = 1024;

impl Compressor {
    /// `start` is the reference time (s) of the queue; `max_error` in seconds.
    pub fn new(clock_hz: f64, max_error: f64) -> Compressor {
        Compressor {
            clock_hz,
            max_error: max_error * clock_hz,
            pending: Vec::new(),
            forward: true,
            last: 0,
            out: Vec::new(),
        }
    }

    /// Adds a step at `time` (s) in direction `forward`.
    pub fn push(&mut self, time: f64, forward: bool) {
        if forward != self.forward && !self.pending.is_empty() {
            self.flush();
        }
        self.forward = forward;
        self.pending.push(time * self.clock_hz);
        if self.pending.len() >= WINDOW {
            self.emit_run();
        }
    }

    /// Compresses every step still pending.
    pub fn flush(&mut self) {
        while !self.pending.is_empty() {
            self.emit_run();
        }
    }

    fn emit_run(&mut self) {
        let (n, interval, add) = self.longest_run();
        self.out.push(QueueStep {
            interval: interval as u32,
            count: n as u16,
            add: add as i16,
            forward: self.forward,
        });
        let n64 = n as i64;
        self.last += n64 * interval + add * n64 * (n64 - 1) / 2;
        self.pending.drain(..n);
    }

    /// The longest prefix of `pending` one run can reproduce, with its (interval, add).
    fn longest_run(&self) -> (usize, i64, i64) {
        let e = self.max_error;
        let base = self.last as f64;
        let p0 = self.pending[0] - base;
        // Fallback: a single step at the nearest tick (always within half a tick).
        let mut best = (1usize, p0.round().max(0.0) as i64, 0i64);
        let mut poly: Vec<(f64, f64)> = vec![
            ((p0 - e).max(0.0), -32768.0),
            (p0 + e, -32768.0),
            (p0 + e, 32767.0),
            ((p0 - e).max(0.0), 32767.0),
        ];
        let limit = self.pending.len().min(MAX_RUN);
        for i in 2..=limit {
            let fi = i as f64;
            let c = fi * (fi - 1.0) / 2.0;
            let target = self.pending[i - 1] - base;
            // |i·I + c·A − target| ≤ e, and intervals stay positive: I + (i−1)·A ≥ 1.
            poly = clip(&poly, fi, c, target - e, true);
            poly = clip(&poly, fi, c, target + e, false);
            poly = clip(&poly, 1.0, fi - 1.0, 1.0, true);
            if poly.len() < 3 {
                break;
            }
            match integer_point(&poly) {
                Some((iv, a)) if iv <= u32::MAX as i64 => best = (i, iv, a),
                _ => break,
            }
        }
        if best.0 == 1 {
            best.1 = best.1.max(1);
        }
        best
    }
}

/// Keeps the part of a convex polygon with a·I + b·A ≥ k (`ge`) or ≤ k.
fn clip(poly: &[(f64, f64)], a: f64, b: f64, k: f64, ge: bool) -> Vec<(f64, f64)> {
    let f = |p: (f64, f64)| {
        let v = a * p.0 + b * p.1 - k;
        if ge {
            v
        } else {
            -v
        }
    };
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(poly.len() + 2);
    let keep = |v: (f64, f64), out: &mut Vec<(f64, f64)>| {
        // Drop vertices that coincide with the previous one; they only slow later clips.
        if out
            .last()
            .is_none_or(|l| (l.0 - v.0).abs() + (l.1 - v.1).abs() > 1e-9)
        {
            out.push(v);
        }
    };
    for idx in 0..poly.len() {
        let (p, q) = (poly[idx], poly[(idx + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            keep(p, &mut out);
        }
        if (fp >= 0.0) != (fq >= 0.0) {
            let t = fp / (fp - fq);
            keep((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)), &mut out);
        }
    }
    out
}

/// An integer (interval, add) inside the polygon, trying adds near its middle.
fn integer_point(poly: &[(f64, f64)]) -> Option<(i64, i64)> {
    let amin = poly.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let amax = poly.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = (amin.ceil() as i64, amax.floor() as i64);
    if lo > hi {
        return None;
    }
    let mid = ((amin + amax) * 0.5).round() as i64;
    for d in [0i64, 1, -1, 2, -2] {
        let a = (mid + d).clamp(lo, hi);
        // The polygon's slice at this add.
        let (mut imin, mut imax) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            let af = a as f64;
            if (p.1 - af) * (q.1 - af) <= 0.0 {
                let x = if q.1 == p.1 {
                    p.0.min(q.0)
                } else {
                    p.0 + (af - p.1) / (q.1 - p.1) * (q.0 - p.0)
                };
                let x2 = if q.1 == p.1 { p.0.max(q.0) } else { x };
                imin = imin.min(x);
                imax = imax.max(x2);
            }
        }
        let (ilo, ihi) = (imin.ceil(), imax.floor());
        if ilo <= ihi {
            return Some((((ilo + ihi) * 0.5).round() as i64, a));
        }
    }
    None
}

/// Expands runs back into step ticks (what the firmware would do).
pub fn decompress(runs: &[QueueStep]) -> Vec<(i64, bool)> {
    let mut out = Vec::new();
    let mut t = 0i64;
    for r in runs {
        let mut iv = r.interval as i64;
        for _ in 0..r.count {
            t += iv;
            out.push((t, r.forward));
            iv += r.add as i64;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accelerating_steps_compress_within_error() {
        // Constant acceleration from rest: t_k = sqrt(2k/a) for a 200 step/mm axis.
        let times: Vec<f64> = (1..5000)
            .map(|k| (2.0 * k as f64 / (300.0 * 200.0)).sqrt())
            .collect();
        let mut c = Compressor::new(1e6, 25e-6);
        for &t in &times {
            c.push(t, true);
        }
        c.flush();
        let back = decompress(&c.out);
        assert_eq!(back.len(), times.len());
        let worst = back
            .iter()
            .zip(&times)
            .map(|(b, t)| (b.0 as f64 / 1e6 - t).abs())
            .fold(0.0, f64::max);
        assert!(worst <= 25e-6, "worst {worst}");
        assert!(
            c.out.len() * 20 < times.len(),
            "{} runs for {} steps",
            c.out.len(),
            times.len()
        );
    }
}
