//! The one error type of the motion stage. Every variant names where (file and key, or
//! source line) and what, so the user can fix the input.

use crate::profile::ProfileError;

#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MotionError {
    #[error(transparent)]
    Profile(#[from] ProfileError),
    #[error("line {line}: point ({x:.4}, {y:.4}) is unreachable: {why}")]
    Unreachable {
        line: u32,
        x: f64,
        y: f64,
        why: String,
    },
    #[error("line {line}: the move changes {axis}, but the machine profile has no such joint")]
    MissingJoint { line: u32, axis: String },
    #[error("line {line}: {axis} = {value:.4} mm is outside the travel limits [{min}, {max}] mm")]
    SoftLimit {
        line: u32,
        axis: char,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("line {line}: {what}")]
    BadMove { line: u32, what: String },
    #[error(
        "line {line}: joint {joint} needs {rate_hz:.0} steps/s but the profile allows \
         max_step_rate = {limit_hz:.0}"
    )]
    StepRate {
        line: u32,
        joint: String,
        rate_hz: f64,
        limit_hz: f64,
    },
}
