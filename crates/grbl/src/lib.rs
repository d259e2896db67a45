//! The grbl-family machine link.
//!
//! - [`messages`], [`realtime`], [`status`], [`response`]: the grbl 1.1 protocol vocabulary;
//! - [`gline`], [`interp`]: grbl's G-code dialect (shared by the emulator and resume);
//! - [`transport`], [`link`]: serial, TCP and pty byte pipes and the line reader;
//! - [`job`], [`journal`], [`sender`], [`report`], [`track`], [`resume`]: streaming, its record,
//!   how it ended and resume; [`check`]: a job through grbl's check mode;
//! - [`settings`], [`jog`], [`device`] (the `Machine` trait): the rest of the machine panel;
//! - [`machine`]: `GrblMachine`, the one-call job runner; [`reconnect`]: the link life cycle;
//! - [`emulator`]: grbl 1.1 in software over a pty or TCP; [`proxy`]: fault injection.

pub mod check;
pub mod device;
pub mod emulator;
pub mod eta;
pub mod gline;
pub mod interp;
pub mod job;
pub mod jog;
pub mod journal;
pub mod link;
pub mod machine;
pub mod messages;
pub mod proxy;
pub mod realtime;
pub mod reconnect;
pub mod report;
pub mod response;
pub mod resume;
pub mod sender;
pub mod settings;
pub mod status;
pub mod track;
pub mod transport;
