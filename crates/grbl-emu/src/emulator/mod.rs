//! A grbl 1.1 emulator reachable over a pseudo-terminal or TCP, so a job can be dry-run
//! against the exact protocol. [`core`] is the firmware model; this module runs it in real
//! time and paces the wire at the emulated baud rate.

pub(crate) mod core;
mod flavor;
mod fluidnc;
mod probe;
pub(crate) mod profile;
mod serve;

pub use self::core::{Config, Core, Stats};
pub use flavor::Flavor;
pub use probe::{LengthSetter, ProbeModel, Stock, Tool, TouchPlate, SETTER_PAD};
pub use serve::Emulator;
