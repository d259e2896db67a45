//! The application layer that the `oficina` CLI and the workbench server share: machines
//! opened from a URI, a session that drives one with its job, check summaries of a program,
//! preview segments, relief carving. It returns data and progress events and prints nothing.

mod check;
mod error;
mod machine_uri;
mod preview;
pub mod profile;
mod relief;
mod session;
mod text;

pub use check::{check_program, CheckOptions, CheckReport, Diag, ExtentsBox, TimeEstimate};
pub use error::Error;
pub use machine_uri::{is_firmware, open_machine, open_machine_with, open_machine_with_tools};
pub use preview::{for_each_segment, PathKind, PreviewSegment};
pub use relief::{carve_relief, ReliefParams, ReliefResult};
pub use session::{alarm_meaning, JobRequest, Session, SessionEvent, Snapshot};
