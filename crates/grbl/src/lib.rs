//! The grbl-family machine link.
//!
//! - [`messages`], [`realtime`], [`status`], [`response`]: the grbl 1.1 protocol vocabulary;
//! - [`gline`], [`interp`]: grbl's G-code dialect (shared by the emulator and resume);

pub mod emulator;
pub mod gline;
pub mod interp;
pub mod job;
pub mod journal;
pub mod link;
pub mod messages;
pub mod realtime;
pub mod response;
pub mod resume;
pub mod sender;
pub mod status;
pub mod transport;
