//! Exact step times (Klipper's idea): for every motor, solve for the moment its commanded
//! position crosses each step boundary, instead of ticking a timer and asking "step now?".
//!
//! Within a segment the joints move linearly with path distance, so joint j is at
//! q0 + (q1 − q0)·s/L. A motor at step count n takes its next step when that position crosses
//! n ± ½ (round-to-nearest), i.e. at path distance s_k, and the time is the profile's inverse
//! t(s_k). Backlash: on a reversal the motor first takes `backlash` worth of extra steps at
//! the profile's maximum step rate, placed just before the first step of the new direction.

use crate::planner::{Segment, SegmentKind};
use crate::profile::Profile;
use crate::velocity::Piece;
use crate::MotionError;

/// Receives every step. `forward` is the joint's positive direction; the electrical DIR level
/// is `forward != invert_direction` of the joint.
pub trait StepSink {
    /// One step of `motor` at `time` (s) in direction `forward`.
    fn step(&mut self, motor: usize, time: f64, forward: bool);
}

/// Motors in step order: the kinematics' three joints, then the rotary A, B, C.
pub const MOTORS: usize = 6;

/// Collects steps per motor (for tests and exports of small programs).
#[derive(Default, Debug, Clone)]
pub struct StepLog {
    /// Each motor's steps: (time in s, forward).
    pub motors: [Vec<(f64, bool)>; MOTORS],
}

impl StepSink for StepLog {
    fn step(&mut self, motor: usize, time: f64, forward: bool) {
        self.motors[motor].push((time, forward));
    }
}

/// Counts steps only (benchmarks).
#[derive(Default, Debug, Clone, Copy)]
pub struct StepCount {
    /// Steps counted, all motors.
    pub steps: u64,
    /// Time of the last step, s.
    pub last_time: f64,
}

impl StepSink for StepCount {
    fn step(&mut self, _motor: usize, time: f64, _forward: bool) {
        self.steps += 1;
        self.last_time = time;
    }
}

#[derive(Clone, Copy, Debug)]
struct MotorState {
    spu: f64,
    backlash_steps: i64,
    /// Step count of the commanded joint position (backlash steps excluded).
    count: i64,
    last_dir: Option<bool>,
    last_time: f64,
    catching_up: bool,
}

/// Turns planned segments into steps for every motor, keeping time across segments.
pub struct StepGenerator {
    motors: [Option<MotorState>; MOTORS],
    names: [&'static str; MOTORS],
    min_interval: f64,
    max_step_rate: f64,
    time: f64,
    /// Largest delay a backlash burst forced onto a regular step, seconds.
    pub backlash_delay: f64,
}

impl StepGenerator {
    /// Starts with the motors at joint position `q` (usually the profile's start) and the
    /// rotary joints at 0°.
    pub fn new(profile: &Profile, q: [f64; 3]) -> StepGenerator {
        let joints = profile.all_joints();
        let motors = std::array::from_fn(|i| {
            let at = if i < 3 { q[i] } else { 0.0 };
            joints[i].map(|j| MotorState {
                spu: j.steps_per_unit,
                backlash_steps: (j.backlash * j.steps_per_unit).round() as i64,
                count: (at * j.steps_per_unit).round() as i64,
                last_dir: None,
                last_time: f64::NEG_INFINITY,
                catching_up: false,
            })
        });
        StepGenerator {
            motors,
            names: motor_names(profile),
            min_interval: 1.0 / profile.max_step_rate,
            max_step_rate: profile.max_step_rate,
            time: 0.0,
            backlash_delay: 0.0,
        }
    }

    /// Machine time at the end of the segments seen so far.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Step count of each rotary motor A, B, C (commanded position, backlash excluded).
    pub fn rotary_counts(&self) -> [i64; 3] {
        std::array::from_fn(|i| self.motors[3 + i].map_or(0, |m| m.count))
    }

    /// Step count of each motor (commanded position, backlash excluded).
    pub fn counts(&self) -> [i64; 3] {
        std::array::from_fn(|i| self.motors[i].map_or(0, |m| m.count))
    }

    /// Emits the steps of `seg` to `sink`, in time order.
    pub fn segment<S: StepSink>(&mut self, seg: &Segment, sink: &mut S) -> Result<(), MotionError> {
        let t_start = self.time;
        self.time += seg.motion.duration;
        if !matches!(seg.kind, SegmentKind::Move(_)) || seg.motion.length <= 0.0 {
            return Ok(());
        }
        let len = seg.motion.length;
        let pieces = seg.motion.pieces();
        for i in 0..MOTORS {
            let Some(mut m) = self.motors[i] else {
                continue;
            };
            let (j0, j1) = if i < 3 {
                (seg.q0[i], seg.q1[i])
            } else {
                (seg.rot0[i - 3], seg.rot1[i - 3])
            };
            let (x0, x1) = (j0 * m.spu, j1 * m.spu);
            let dx = x1 - x0;
            if dx == 0.0 {
                continue;
            }
            let up = dx > 0.0;
            // Step boundaries between counts sit at half steps.
            let mut k = if up {
                m.count as f64 + 0.5
            } else {
                m.count as f64 - 0.5
            };
            let mut cursor = 0usize;
            while (up && k <= x1) || (!up && k >= x1) {
                let s = ((k - x0) / dx * len).clamp(0.0, len);
                let mut t = t_start + time_at(pieces, &mut cursor, s, seg.motion.duration);
                if m.catching_up {
                    // A burst that did not fit delays the following steps until they
                    // fall behind their planned times no more.
                    let earliest = m.last_time + self.min_interval;
                    if t < earliest {
                        self.backlash_delay = self.backlash_delay.max(earliest - t);
                        t = earliest;
                    } else {
                        m.catching_up = false;
                    }
                }
                let reversing = m.last_dir.is_some_and(|d| d != up);
                if m.last_dir != Some(up) {
                    if m.last_dir.is_some() && m.backlash_steps > 0 {
                        // Take up the play before the first step of the new direction.
                        let burst = m.backlash_steps as f64 * self.min_interval;
                        let mut tb = (t - burst).max(m.last_time + self.min_interval);
                        for _ in 0..m.backlash_steps {
                            sink.step(i, tb, up);
                            m.last_time = tb;
                            tb += self.min_interval;
                        }
                        if tb > t {
                            self.backlash_delay = self.backlash_delay.max(tb - t);
                            t = tb;
                            m.catching_up = true;
                        }
                    }
                    m.last_dir = Some(up);
                }
                let dt = t - m.last_time;
                // A step back across the boundary just crossed is a reversal at rest on this
                // joint (a corner), not speed: only same-direction intervals measure rate.
                if !reversing && dt < self.min_interval * (1.0 - 1e-6) {
                    return Err(MotionError::StepRate {
                        line: seg.line,
                        joint: self.names[i].to_string(),
                        rate_hz: 1.0 / dt,
                        limit_hz: self.max_step_rate,
                    });
                }
                sink.step(i, t, up);
                m.last_time = t;
                m.count += if up { 1 } else { -1 };
                k += if up { 1.0 } else { -1.0 };
            }
            self.motors[i] = Some(m);
        }
        Ok(())
    }
}

/// Names of the motors in step order: the kinematics' joints, then "a", "b", "c".
pub fn motor_names(profile: &Profile) -> [&'static str; MOTORS] {
    let k = profile.kinematics.joint_names();
    let r = crate::profile::ROTARY_NAMES;
    [k[0], k[1], k[2], r[0], r[1], r[2]]
}

/// Inverse of the profile for increasing `s`, walking the pieces with a cursor.
#[inline]
fn time_at(pieces: &[Piece], cursor: &mut usize, s: f64, duration: f64) -> f64 {
    while *cursor + 1 < pieces.len() && s >= pieces[*cursor + 1].s0 {
        *cursor += 1;
    }
    let Some(p) = pieces.get(*cursor) else {
        return duration;
    };
    let ds = s - p.s0;
    if ds <= 0.0 {
        return p.t0;
    }
    if p.jerk == 0.0 && p.a0 == 0.0 && p.v0 > 0.0 {
        return p.t0 + (ds / p.v0).min(p.dur);
    }
    if p.jerk == 0.0 {
        let disc = p.v0 * p.v0 + 2.0 * p.a0 * ds;
        if disc <= 0.0 {
            return p.t0 + p.dur; // beyond a decelerating piece's reach: rounding at its end
        }
        let t = 2.0 * ds / (p.v0 + disc.sqrt());
        return p.t0 + if t.is_finite() { t.min(p.dur) } else { p.dur };
    }
    // Jerk pieces: Newton inside a bracket on the cubic.
    let (mut lo, mut hi) = (0.0, p.dur);
    let mut t = 0.5 * p.dur;
    for _ in 0..50 {
        let (sv, v, _) = p.at(t);
        let f = sv - s;
        if f > 0.0 {
            hi = t
        } else {
            lo = t
        }
        if hi - lo < 1e-12 {
            break;
        }
        let n = if v > 0.0 { t - f / v } else { f64::NAN };
        t = if n > lo && n < hi { n } else { 0.5 * (lo + hi) };
    }
    p.t0 + t
}
