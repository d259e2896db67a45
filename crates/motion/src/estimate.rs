//! Job time estimate: the planner's own timeline summed, so it is the time the virtual
//! machine takes at 100 % overrides (pauses at M0 count as zero).

use crate::planner::{plan, PlanOptions};
use crate::profile::Profile;
use crate::MotionError;
use oficina_canon::Canon;

/// Machine time and figures of a planned program.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Estimate {
    /// Total machine time, seconds.
    pub seconds: f64,
    /// Seconds spent per source line, as (line, seconds) in program order, one entry per
    /// run of consecutive segments from the same line.
    pub per_line: Vec<(u32, f64)>,
    /// Path length travelled, mm (feeds and rapids).
    pub distance: f64,
    /// Number of planned segments.
    pub segments: u64,
    /// Motor steps the motion makes: each joint's travel in steps, summed (backlash and the
    /// rounding at segment ends aside). What a step file will hold, before it is written.
    pub steps: f64,
}

/// Estimates the time of a program without per-line detail (constant memory).
pub fn estimate(
    ops: impl Iterator<Item = Canon>,
    profile: &Profile,
) -> Result<Estimate, MotionError> {
    estimate_with(ops, profile, PlanOptions::default(), false)
}

/// As [`estimate`], with options and optionally the per-line breakdown.
pub fn estimate_with(
    ops: impl Iterator<Item = Canon>,
    profile: &Profile,
    opts: PlanOptions,
    per_line: bool,
) -> Result<Estimate, MotionError> {
    let mut e = Estimate::default();
    for seg in plan(ops, profile, opts)? {
        let seg = seg?;
        e.seconds += seg.duration();
        e.distance += seg.motion.length;
        e.segments += 1;
        for (i, joint) in profile.joints.iter().enumerate() {
            if let Some(j) = joint {
                e.steps += (seg.q1[i] - seg.q0[i]).abs() * j.steps_per_unit;
            }
        }
        if per_line {
            match e.per_line.last_mut() {
                Some((l, s)) if *l == seg.line => *s += seg.duration(),
                _ => e.per_line.push((seg.line, seg.duration())),
            }
        }
    }
    Ok(e)
}
