//! Motor steps from the seed 002 interpolators instead of the planner: every straight move
//! runs the faithful linear DDA (one iteration per time slot), every XY arc the circular DDA
//! (one slot per emitted step). A slot lasts the seed's `resolution / speed`, never less than
//! one step at `max_step_rate`; there are no acceleration ramps (the seed had none). Backlash
//! is sent as a burst at `max_step_rate` before the first step of a reversed motor, the
//! seed's "amount added to the move".

use crate::dda::{CircularDda, LinearDda};
use crate::profile::{KinematicsKind, Profile, ProfileError};
use crate::steps::StepSink;
use crate::MotionError;
use oficina_canon::{Canon, CanonOp, FeedMode, Plane, Pos};
use oficina_geom::sweep_between;

/// What a DDA run produced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DdaSummary {
    /// Machine time at the end of the last slot, s.
    pub seconds: f64,
    /// Steps emitted, all motors.
    pub steps: u64,
    /// Moves interpolated (zero-length ones excluded).
    pub moves: u64,
    /// Path length programmed, mm.
    pub distance: f64,
}

#[derive(Clone, Copy, Debug)]
struct Motor {
    spu: f64,
    max_rate: f64,
    backlash_steps: i64,
    last_forward: Option<bool>,
}

/// The state of one DDA run over a program.
struct Dda<'p, S> {
    profile: &'p Profile,
    sink: &'p mut S,
    motors: [Option<Motor>; 3],
    /// Position in steps per axis (X, Y, Z are the joints of a Cartesian machine).
    pos: [i64; 3],
    time: f64,
    min_slot: f64,
    /// Programmed feed, mm/s (or 1/min in inverse time).
    feed: f64,
    inverse_time: bool,
    summary: DdaSummary,
}

/// Runs the seed's interpolators over `ops` on a Cartesian `profile`, sending every step to
/// `sink`. The machine starts at `profile.start`.
pub fn dda_steps<I, S>(ops: I, profile: &Profile, sink: &mut S) -> Result<DdaSummary, MotionError>
where
    I: Iterator<Item = Canon>,
    S: StepSink,
{
    if profile.kinematics != KinematicsKind::Cartesian {
        return Err(ProfileError {
            file: profile.name.clone(),
            key: "kinematics".into(),
            message: format!(
                "the DDA interpolator steps X, Y and Z directly, so it needs a cartesian \
                 machine, not {}; use the exact step generator",
                kinematics_name(profile.kinematics)
            ),
        }
        .into());
    }
    let motors = std::array::from_fn(|i| {
        profile.joints[i].map(|j| Motor {
            spu: j.steps_per_unit,
            max_rate: j.max_rate,
            backlash_steps: (j.backlash * j.steps_per_unit).round() as i64,
            last_forward: None,
        })
    });
    let pos = std::array::from_fn(|i| {
        motors[i].map_or(0, |m: Motor| (profile.start[i] * m.spu).round() as i64)
    });
    let mut dda = Dda {
        profile,
        sink,
        motors,
        pos,
        time: 0.0,
        min_slot: 1.0 / profile.max_step_rate,
        feed: profile.default_feed,
        inverse_time: false,
        summary: DdaSummary::default(),
    };
    for c in ops {
        dda.op(c)?;
    }
    dda.summary.seconds = dda.time;
    Ok(dda.summary)
}

impl<S: StepSink> Dda<'_, S> {
    fn op(&mut self, c: Canon) -> Result<(), MotionError> {
        let line = c.line;
        match c.op {
            CanonOp::SetFeedRate(f) => {
                if !(f.is_finite() && f >= 0.0) {
                    return Err(bad(line, format!("feed rate F{f} must be >= 0")));
                }
                self.feed = if self.inverse_time { f } else { f / 60.0 };
            }
            CanonOp::SetFeedMode(m) => {
                if m == FeedMode::UnitsPerRev {
                    return Err(bad(
                        line,
                        "G95 feed per revolution needs a spindle-synchronised machine",
                    ));
                }
                self.inverse_time = m == FeedMode::InverseTime;
            }
            CanonOp::StraightTraverse { to } => self.line(line, &to, true)?,
            CanonOp::StraightFeed { to } => self.line(line, &to, false)?,
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                // The DDA takes XY arcs only, and those are never turned.
                rotation: _,
            } => self.arc(line, plane, &end, center, turns)?,
            CanonOp::Dwell(s) => {
                if !(s.is_finite() && s >= 0.0) {
                    return Err(bad(line, format!("dwell of {s} s")));
                }
                self.time += s;
            }
            CanonOp::StartSpeedFeedSync { .. } | CanonOp::RigidTap { .. } => {
                return Err(bad(
                    line,
                    "the DDA interpolator has no spindle encoder: spindle-synchronised motion \
                     (G33, G33.1, G76) needs the exact step generator",
                ));
            }
            _ => {}
        }
        Ok(())
    }

    /// The target in steps; refuses rotary axes and axes the machine does not have.
    fn target(&self, line: u32, to: &Pos) -> Result<[i64; 3], MotionError> {
        let v = to.to_array();
        if !v.iter().all(|x| x.is_finite()) {
            return Err(bad(line, "non-finite coordinate"));
        }
        for (i, axis) in ["A", "B", "C"].iter().enumerate() {
            if v[3 + i].abs() > 1e-9 {
                return Err(MotionError::MissingJoint {
                    line,
                    axis: format!("rotary axis {axis}"),
                });
            }
        }
        let mut t = self.pos;
        for (i, axis) in ["X", "Y", "Z"].iter().enumerate() {
            match self.motors[i] {
                Some(m) => t[i] = (v[i] * m.spu).round() as i64,
                None if (v[i] - self.profile.start[i]).abs() > 1e-9 => {
                    return Err(MotionError::MissingJoint {
                        line,
                        axis: axis.to_string(),
                    })
                }
                None => {}
            }
        }
        Ok(t)
    }

    /// The resolution shared by the axes in `moving`, mm per step: the seed's slot timing
    /// makes iterations stand for path length only when every axis steps the same distance.
    fn resolution(&self, line: u32, moving: &[usize]) -> Result<f64, MotionError> {
        let spus: Vec<(usize, f64)> = moving
            .iter()
            .filter_map(|&i| self.motors[i].map(|m| (i, m.spu)))
            .collect();
        let Some(&(_, spu)) = spus.first() else {
            return Err(bad(line, "a move with no motor to step"));
        };
        if let Some(&(other, s)) = spus.iter().find(|(_, s)| (s - spu).abs() > 1e-9) {
            return Err(bad(
                line,
                format!(
                    "the DDA needs the same steps/mm on every moving axis, but {} has {spu} and \
                     {} has {s}; use the exact step generator",
                    axis_name(spus[0].0),
                    axis_name(other)
                ),
            ));
        }
        Ok(1.0 / spu)
    }

    /// Slot length for a move of `length` mm at the programmed feed (or the joints' maximum
    /// rate for a rapid), never shorter than one step at `max_step_rate`.
    fn slot(
        &self,
        line: u32,
        res: f64,
        length: f64,
        rapid_axes: Option<&[usize]>,
    ) -> Result<f64, MotionError> {
        let speed = match rapid_axes {
            Some(axes) => axes
                .iter()
                .filter_map(|&i| self.motors[i].map(|m| m.max_rate))
                .fold(f64::INFINITY, f64::min),
            None if self.feed <= 0.0 => {
                return Err(bad(line, "feed move with a zero feed rate; set F"))
            }
            // Inverse time: the move takes 1/F minutes.
            None if self.inverse_time => length * self.feed / 60.0,
            None => self.feed,
        };
        Ok((res / speed).max(self.min_slot))
    }

    fn line(&mut self, line: u32, to: &Pos, rapid: bool) -> Result<(), MotionError> {
        let target = self.target(line, to)?;
        let delta: [i64; 3] = std::array::from_fn(|i| target[i] - self.pos[i]);
        let moving: Vec<usize> = (0..3).filter(|&i| delta[i] != 0).collect();
        if moving.is_empty() {
            return Ok(());
        }
        let res = self.resolution(line, &moving)?;
        let length = res * (delta.iter().map(|d| (d * d) as f64).sum::<f64>()).sqrt();
        let slot = self.slot(line, res, length, rapid.then_some(&moving[..]))?;
        for tick in LinearDda::new(delta, true) {
            for (axis, &d) in tick.iter().enumerate() {
                if d != 0 {
                    self.step(line, axis, d > 0)?;
                }
            }
            self.time += slot;
        }
        self.summary.moves += 1;
        self.summary.distance += length;
        Ok(())
    }

    fn arc(
        &mut self,
        line: u32,
        plane: Plane,
        end: &Pos,
        center: [f64; 2],
        turns: i32,
    ) -> Result<(), MotionError> {
        if plane != Plane::XY {
            return Err(bad(
                line,
                format!("the circular DDA interpolates in the XY plane (G17), not {plane:?}"),
            ));
        }
        let target = self.target(line, end)?;
        if target[2] != self.pos[2] {
            return Err(bad(
                line,
                "a helix (the arc changes Z): the circular DDA interpolates X and Y only",
            ));
        }
        if turns == 0 || !center.iter().all(|v| v.is_finite()) {
            return Err(bad(line, "arc with zero turns or a non-finite centre"));
        }
        let res = self.resolution(line, &[0, 1])?;
        let c = [
            (center[0] / res).round() as i64,
            (center[1] / res).round() as i64,
        ];
        let from = (self.pos[0] - c[0], self.pos[1] - c[1]);
        let to = (target[0] - c[0], target[1] - c[1]);
        if from == (0, 0) || to == (0, 0) {
            return Err(bad(
                line,
                "arc centre within a step of its start or end point",
            ));
        }
        let angle = |p: (i64, i64)| (p.1 as f64).atan2(p.0 as f64);
        let sweep = sweep_between(angle(from), angle(to), turns);
        let radius = res * ((from.0 * from.0 + from.1 * from.1) as f64).sqrt();
        let slot = self.slot(line, res, radius * sweep.abs(), None)?;
        let circle = CircularDda::new(from, to, turns < 0, sweep);
        for (dx, dy) in circle {
            if dx != 0 {
                self.step(line, 0, dx > 0)?;
            }
            if dy != 0 {
                self.step(line, 1, dy > 0)?;
            }
            self.time += slot;
        }
        self.summary.moves += 1;
        self.summary.distance += radius * sweep.abs();
        Ok(())
    }

    /// One step of `axis` at the current slot's time, within the travel. A backlash burst
    /// before it delays the rest of the slot and the slots after it.
    fn step(&mut self, line: u32, axis: usize, forward: bool) -> Result<(), MotionError> {
        let Some(m) = self.motors[axis].as_mut() else {
            return Err(MotionError::MissingJoint {
                line,
                axis: axis_name(axis).into(),
            });
        };
        if m.last_forward.is_some_and(|f| f != forward) {
            for _ in 0..m.backlash_steps {
                self.sink.step(axis, self.time, forward);
                self.time += self.min_slot;
            }
            self.summary.steps += m.backlash_steps as u64;
        }
        m.last_forward = Some(forward);
        let spu = m.spu;
        self.pos[axis] += if forward { 1 } else { -1 };
        let mm = self.pos[axis] as f64 / spu;
        let [lo, hi] = self.profile.travel[axis];
        // Half a step of slack: a target on the limit rounds to the nearest step.
        if mm < lo - 0.5 / spu || mm > hi + 0.5 / spu {
            return Err(MotionError::SoftLimit {
                line,
                axis: ['X', 'Y', 'Z'][axis],
                value: mm,
                program: None,
                min: lo,
                max: hi,
            });
        }
        self.sink.step(axis, self.time, forward);
        self.summary.steps += 1;
        Ok(())
    }
}

fn kinematics_name(k: KinematicsKind) -> &'static str {
    match k {
        KinematicsKind::Cartesian => "cartesian",
        KinematicsKind::CoreXy => "corexy",
        KinematicsKind::Polar { .. } => "polar",
        KinematicsKind::Polargraph { .. } => "polargraph",
    }
}

fn axis_name(i: usize) -> &'static str {
    ["X", "Y", "Z"][i]
}

fn bad(line: u32, what: impl Into<String>) -> MotionError {
    MotionError::BadMove {
        line,
        what: what.into(),
    }
}
