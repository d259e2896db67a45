//! grbl-family firmware in software, for testing the host side (`oficina-grbl`) without a
//! machine: [`emulator`] runs grbl 1.1 (or grblHAL / FluidNC as they answer) over a
//! pseudo-terminal or TCP, its motion timed by Oficina's planner; [`proxy`] sits between a
//! sender and a firmware and injects link faults.
//!
//! The protocol vocabulary (status reports, messages, real-time bytes, the G-code dialect) is
//! `oficina-grbl`'s: this crate depends on it, never the reverse, so the host side does not
//! carry the motion planner.

pub mod emulator;
pub mod proxy;
