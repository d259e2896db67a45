//! The 4th axis A of a grblHAL board built with N_AXIS = 4 ($103 steps/°, $113 °/min,
//! $123 °/s², $133 travel). Its feed is combined as LinuxCNC (and Oficina's planner) does:
//! when X, Y or Z move, F is along the XYZ path and A keeps pace, slowed so A stays within
//! its rate; a move of A alone has F in degrees per minute and runs as a trapezoid of A's
//! own rate and acceleration, from rest to rest.
//!
//! What the incremental planner cannot see yet: A's acceleration limit inside a mixed move,
//! and A's share of the junction speeds (it plans X, Y, Z blocks only).

use super::*;
use oficina_motion::{Limits, Motion};

/// A's rate (°/s) and acceleration (°/s²) from `$113` and `$123`, if the board has A.
pub(super) fn limits(settings: &BTreeMap<u16, f64>) -> Option<(f64, f64)> {
    let steps = settings.get(&103)?;
    let rate = settings.get(&113).copied().unwrap_or(0.0).max(1.0) / 60.0;
    let accel = settings.get(&123).copied().unwrap_or(0.0).max(0.1);
    (*steps > 0.0).then_some((rate, accel))
}

/// A block in the planner: where it starts and how A turns along it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lane {
    pub start: [f64; 3],
    pub length: f64,
    pub a0: f64,
    pub a1: f64,
}

impl Lane {
    /// A where the tool is at `at` on this block.
    pub(super) fn a_at(&self, at: [f64; 3]) -> f64 {
        let f = (oficina_grbl::dist(&self.start, &at) / self.length).clamp(0.0, 1.0);
        self.a0 + (self.a1 - self.a0) * f
    }
}

/// A move of A alone, running.
#[derive(Clone, Copy, Debug)]
pub(super) struct Spin {
    motion: Motion,
    t: f64,
    a0: f64,
    a1: f64,
}

impl Spin {
    /// From `a0` to `a1` at `rate` (feed in °/min, or rapid), from rest to rest.
    pub(super) fn new(a0: f64, a1: f64, rate: Rate, (max_rate, accel): (f64, f64)) -> Spin {
        let v = match rate {
            Rate::Rapid => max_rate,
            Rate::Feed(f) => (f / 60.0).min(max_rate),
        };
        let lim = Limits {
            accel,
            jerk: f64::INFINITY,
        };
        Spin {
            motion: Motion::plan((a1 - a0).abs(), 0.0, v, 0.0, lim),
            t: 0.0,
            a0,
            a1,
        }
    }

    /// Runs `dt` seconds; returns A and the seconds left over once the turn is done.
    pub(super) fn advance(&mut self, dt: f64) -> (f64, Option<f64>) {
        self.t += dt;
        if self.t >= self.motion.duration {
            return (self.a1, Some(self.t - self.motion.duration));
        }
        let s = self.motion.at(self.t).0;
        (self.a0 + (self.a1 - self.a0).signum() * s, None)
    }

    pub(super) fn speed(&self) -> f64 {
        self.motion.at(self.t).1
    }
}

/// The path speed (mm/s) of a mixed move of `length` mm turning A by `turn`°, slowed so A
/// keeps within `max_rate` °/s.
pub(super) fn mixed_speed(speed: f64, length: f64, turn: f64, max_rate: f64) -> f64 {
    if turn.abs() > 1e-9 {
        speed.min(max_rate * length / turn.abs())
    } else {
        speed
    }
}
