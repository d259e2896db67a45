//! The one error type of the motion stage. Every variant names where (file and key, or
//! source line) and what, so the user can fix the input.

use crate::profile::ProfileError;

/// Why motion could not be planned: names the file and key or the source line, and what.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MotionError {
    /// The machine profile is invalid.
    #[error(transparent)]
    Profile(#[from] ProfileError),
    /// The kinematics cannot reach a point.
    #[error("line {line}: point ({x:.4}, {y:.4}) is unreachable: {why}")]
    Unreachable {
        /// Source line.
        line: u32,
        /// X of the point, mm.
        x: f64,
        /// Y of the point, mm.
        y: f64,
        /// Why it is out of reach.
        why: String,
    },
    /// A move changes an axis the machine has no joint for.
    #[error("line {line}: the move changes {axis}, but the machine profile has no such joint")]
    MissingJoint {
        /// Source line.
        line: u32,
        /// The axis the move changes.
        axis: String,
    },
    /// A position outside the profile's travel limits.
    #[error("line {line}: {}", soft_limit_text(*axis, *value, *program, *min, *max))]
    SoftLimit {
        /// Source line.
        line: u32,
        /// The axis letter.
        axis: char,
        /// The position asked for, machine coordinates, mm.
        value: f64,
        /// The same position as the program wrote it (its work coordinates: the G5x, G92
        /// and tool length offsets taken off), when known.
        program: Option<f64>,
        /// Lower travel limit, mm.
        min: f64,
        /// Upper travel limit, mm.
        max: f64,
    },
    /// A move the machine cannot make as programmed.
    #[error("line {line}: {what}")]
    BadMove {
        /// Source line.
        line: u32,
        /// What is wrong with it.
        what: String,
    },
    /// A joint would step faster than the profile's `max_step_rate`.
    #[error(
        "line {line}: joint {joint} needs {rate_hz:.0} steps/s but the profile allows \
         max_step_rate = {limit_hz:.0}"
    )]
    StepRate {
        /// Source line.
        line: u32,
        /// The joint's name.
        joint: String,
        /// Step rate needed, steps/s.
        rate_hz: f64,
        /// Step rate allowed, steps/s.
        limit_hz: f64,
    },
}

/// The operator reads the program, so the limit message quotes its own coordinate first
/// and the machine's beside it.
fn soft_limit_text(axis: char, value: f64, program: Option<f64>, min: f64, max: f64) -> String {
    match program {
        Some(w) if (w - value).abs() > 1e-9 => format!(
            "{axis}{w:.4} of the program is {axis} = {value:.4} mm on the machine, outside its travel limits [{min}, {max}] mm (check the work zero)"
        ),
        _ => format!("{axis} = {value:.4} mm is outside the travel limits [{min}, {max}] mm"),
    }
}
