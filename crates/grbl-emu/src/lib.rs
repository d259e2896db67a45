//! grbl-family firmware in software, for testing the host side (`oficina-grbl`) without a
//! machine: [`Emulator`] runs grbl 1.1 (or grblHAL / FluidNC as they answer) over a
//! pseudo-terminal or TCP, its motion timed by Oficina's planner ([`Core`] is the firmware model without I/O); [`FaultProxy`] sits between a
//! sender and a firmware and injects link faults. [`grbl_settings`] gives the `$` settings of
//! a board for an Oficina machine profile.
//!
//! [`MarlinEmulator`] is a Marlin 2.x board (a Makelangelo's firmware) for the Marlin link.
//!
//! The protocol vocabulary (status reports, messages, real-time bytes, the G-code dialect) is
//! `oficina-grbl`'s: this crate depends on it, never the reverse, so the host side does not
//! carry the motion planner.

// What other crates do not use is `pub(crate)`: the API is the list below.

mod emulator;
mod marlin;
mod proxy;

pub use emulator::profile::{grbl_settings, motion_profile, GRBL_MAX_STEP_RATE};
pub use emulator::{Config, Core, Emulator, Flavor, Stats};
pub use emulator::{LengthSetter, ProbeModel, Stock, Tool, TouchPlate, SETTER_PAD};
pub use marlin::{Executed, MarlinConfig, MarlinCore, MarlinEmulator, MarlinStats, Move};
pub use proxy::{Fault, FaultProxy};
