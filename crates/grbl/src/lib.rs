//! The grbl-family machine link.
//!
//! ```
//! use oficina_grbl::gline;
//! use oficina_grbl::status::{GrblState, StatusReport};
//!
//! // A status report with work coordinate offsets: the work position is MPos − WCO.
//! let st = StatusReport::parse("<Run|MPos:12.000,5.000,-1.000|FS:500,0|WCO:10.000,0.000,-2.000>");
//! let st = st.unwrap();
//! assert_eq!(st.state, GrblState::Run);
//! assert_eq!(st.feed, Some(500.0));
//! assert_eq!(st.work_position(None), Some(vec![2.0, 5.0, 1.0]));
//!
//! // An input line as grbl reads it: comments and spaces dropped, letters upper-cased.
//! let line = gline::clean("g1 x10 (to the edge) f300 ; finish").unwrap();
//! assert_eq!(line, "G1X10F300");
//! assert_eq!(gline::words(&line).unwrap(), [('G', 1.0), ('X', 10.0), ('F', 300.0)]);
//! // A line longer than grbl's 80-byte buffer is error 11.
//! assert_eq!(gline::clean(&"G1X1".repeat(21)), Err(gline::E_LINE_OVERFLOW));
//! ```
//!
//! - [`messages`], [`realtime`], [`status`], [`response`]: the grbl 1.1 protocol vocabulary;
//! - [`gline`], [`interp`]: grbl's G-code dialect (shared by the emulator and resume);
//! - [`transport`], [`link`]: serial, TCP and pty byte pipes and the line reader;
//! - [`job`], [`journal`], [`sender`], [`report`], [`track`], [`resume`]: streaming, its record,
//!   how it ended and resume; [`check`]: a job through grbl's check mode;
//! - [`settings`], [`jog`], [`device`] (the `Machine` trait): the rest of the machine panel;
//! - [`machine`]: `GrblMachine`, the one-call job runner; [`reconnect`]: the link life cycle.
//!
//! The emulator and the fault proxy live in `oficina-grbl-emu`, which depends on this crate.

pub mod check;
pub mod device;
pub mod eta;
pub mod gline;
pub mod interp;
pub mod job;
pub mod jog;
pub mod journal;
pub mod link;
pub mod machine;
pub mod messages;
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
