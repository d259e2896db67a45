//! grbl's homing cycle (`$H`, limits.c's `limits_go_home`) as the emulator times it: Z seeks
//! its switch first, then X and Y together, at the homing seek rate (`$25`). Meanwhile the
//! board reports `Home`, answers real-time bytes and takes no line; `ok` comes once the cycle
//! is over, at machine zero (as grbl built with `HOMING_FORCE_SET_ORIGIN` ends it).
//!
//! Without limit switches ([`Config::limit_switches`] false) Z searches 1.5 × its travel
//! (`$132`) and the cycle fails with `ALARM:9`; a soft reset during the cycle raises
//! `ALARM:6`. Either way grbl answers the `$H` line, then resets (banner, unlock prompt) and
//! stays in alarm.

use super::*;

/// A homing cycle under way: straight legs at the seek rate, the first one running.
pub(super) struct Homing {
    legs: VecDeque<Leg>,
}

struct Leg {
    from: [f64; 3],
    to: [f64; 3],
    seconds: f64,
    done: f64,
    /// The search ends here without finding a switch.
    fails: bool,
}

impl Leg {
    fn new(from: [f64; 3], to: [f64; 3], seek: f64, fails: bool) -> Leg {
        // Axes move together, each at the seek rate: the longest one sets the time.
        let longest = (0..3).map(|i| (to[i] - from[i]).abs()).fold(0.0, f64::max);
        Leg {
            from,
            to,
            seconds: longest / seek,
            done: 0.0,
            fails,
        }
    }

    fn at(&self) -> [f64; 3] {
        let f = if self.seconds > 0.0 {
            (self.done / self.seconds).min(1.0)
        } else {
            1.0
        };
        std::array::from_fn(|i| self.from[i] + (self.to[i] - self.from[i]) * f)
    }
}

impl Core {
    /// `$H` accepted (homing enabled, the machine idle or in alarm): the cycle begins.
    pub(super) fn start_homing(&mut self) {
        // $25 is mm/min.
        let seek = self.setting(25).max(1.0) / 60.0;
        let p = self.mpos;
        let legs = if self.config.limit_switches {
            let z_done = [p[0], p[1], 0.0];
            VecDeque::from([
                Leg::new(p, z_done, seek, false),
                Leg::new(z_done, [0.0; 3], seek, false),
            ])
        } else {
            let search = 1.5 * self.setting(132);
            VecDeque::from([Leg::new(p, [p[0], p[1], p[2] + search], seek, true)])
        };
        self.homing = Some(Homing { legs });
        self.state = GrblState::Home;
    }

    /// Moves the cycle on by `dt` seconds; answers `$H` when it ends.
    pub(super) fn advance_homing(&mut self, mut dt: f64) {
        let Some(h) = self.homing.as_mut() else {
            return;
        };
        while let Some(leg) = h.legs.front_mut() {
            let left = leg.seconds - leg.done;
            if dt < left {
                leg.done += dt;
                self.mpos = leg.at();
                self.stats.busy_seconds += dt;
                return;
            }
            dt -= left;
            self.stats.busy_seconds += left;
            self.mpos = leg.to;
            let fails = leg.fails;
            h.legs.pop_front();
            if fails {
                return self.homing_failed(9);
            }
        }
        self.homing = None;
        self.mpos = [0.0; 3];
        self.motion = new_motion(&self.settings, self.mpos);
        self.interp.pos = self.mpos;
        self.state = GrblState::Idle;
        self.stats.lines_executed += 1;
        self.say("ok");
    }

    /// The cycle ends in `ALARM:<code>`: grbl reports it, answers the `$H` line, then
    /// resets into the alarm state (the position is not known).
    pub(super) fn homing_failed(&mut self, code: u8) {
        self.homing = None;
        self.state = GrblState::Alarm;
        self.motion = new_motion(&self.settings, self.mpos);
        self.interp.pos = self.mpos;
        self.say(&format!("ALARM:{code}"));
        self.say("ok");
        self.soft_reset();
    }
}
