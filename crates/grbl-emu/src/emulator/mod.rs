//! A grbl 1.1 emulator reachable over a pseudo-terminal or TCP, so a job can be dry-run
//! against the exact protocol. [`core`] is the firmware model; this module runs it in real
//! time and paces the wire at the emulated baud rate.

pub mod core;
pub mod flavor;
pub mod fluidnc;
pub mod profile;
mod serve;

pub use self::core::{Config, Core, Stats};
pub use flavor::Flavor;
pub use serve::Emulator;
