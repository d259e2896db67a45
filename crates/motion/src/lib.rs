//! Motion: from canonical operations to timed motion and motor steps.
//!
//! ```
//! use oficina_canon::{Canon, CanonOp, Pos};
//! use oficina_motion::{estimate, resolve};
//!
//! // A bundled machine profile, and a program already turned into canon operations.
//! let machine = resolve("grbl-router").unwrap();
//! let ops = [
//!     CanonOp::SetFeedRate(600.0),
//!     CanonOp::StraightFeed { to: Pos::xyz(30.0, 40.0, 0.0) },
//! ];
//! let ops = ops.into_iter().map(|op| Canon { line: 1, op });
//! let e = estimate(ops, &machine).unwrap();
//! // 50 mm at 10 mm/s is 5 s at full speed; accelerating and stopping take longer.
//! assert!(e.seconds > 5.0 && e.seconds < 6.0, "{}", e.seconds);
//! ```
//!
//! The stages, each in its own (private) module:
//! - `profile`: the machine profile (TOML) with every limit the planner honours;
//! - `kinematics`: Cartesian ↔ joint maps (Cartesian, CoreXY, offset-pen polar, polargraph);
//! - `moves`: canon ops → straight pieces (arcs split by chord tolerance, non-linear
//!   kinematics split by path tolerance), each tagged with its limits;
//! - `velocity`: trapezoidal and jerk-limited (S-curve) velocity profiles;
//! - `planner`: streaming look-ahead with junction deviation and a time horizon;
//! - `check`: an independent checker of every invariant the planner promises;
//! - `estimate`: total job time; `bound`: the least time of a move, in joint space;
//! - `steps`, `stepcompress`, `dda`: exact step times, Klipper-style compression and the
//!   seed 002 interpolators; `dda_steps`: a program stepped by those interpolators;
//! - `trace`: the planned motion sampled at a fixed period.
//!
//! What other crates use is the flat list below.

mod bound;
mod check;
mod dda;
mod dda_steps;
mod error;
mod estimate;
mod hms;
mod kinematics;
mod moves;
mod planner;
mod profile;
mod step_files;
mod stepcompress;
mod steps;
mod trace;
mod velocity;

pub use bound::JointBound;
pub use check::{check, CheckReport};
pub use dda_steps::{dda_steps, DdaSummary};
pub use error::MotionError;
pub use estimate::{estimate, estimate_with, Estimate};
pub use hms::format_hms;
pub use kinematics::{for_profile, AnyKinematics, Kinematics, KinematicsKind};
pub use moves::{lerp3, MoveKind, Overrides};
pub use planner::incremental::{Incremental, Push};
pub use planner::{plan, Cut, PlanOptions, Planner, Segment, SegmentKind};
pub use profile::{
    bundled, resolve, Joint, Profile, ProfileError, Rotary, VelocityProfile, BUNDLED, DEFAULT,
};
pub use step_files::StepFiles;
pub use stepcompress::{decompress, Compressor};
pub use steps::{motor_names, StepCount, StepGenerator, StepLog, StepSink, MOTORS};
pub use trace::TraceWriter;
pub use velocity::{Limits, Motion};
