//! A Marlin 2.x board in software (a Makelangelo's firmware as its host sees it): the
//! serial reader's line-number and checksum checks, keep-alives, `M0` waits, and a pen
//! plotter's position and servo, with faults injected on the wire.

mod core;
mod serve;

pub use self::core::{Executed, MarlinConfig, MarlinCore, MarlinStats, Move};
pub use serve::MarlinEmulator;
