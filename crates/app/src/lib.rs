//! The application layer that the `oficina` CLI and the workbench server share: machines
//! opened from a URI, a session that drives one with its job, check summaries of a program,
//! preview segments, and the job pipelines (relief carving, 2.5D milling, sole molds, pen
//! plots). It returns data and progress events and prints nothing.

mod check;
mod error;
mod job;
pub mod jog;
mod judge;
mod machine_uri;
pub mod mill;
pub mod plot;
mod post_params;
mod preview;
pub mod profile;
mod relief;
mod session;
pub mod sole;
mod text;
pub mod tools;

pub use check::{check_program, CheckOptions, CheckReport, Diag, ExtentsBox, TimeEstimate};
pub use error::{Error, CANCELLED};
pub use job::{Feedback, ProgressFn};
pub use judge::{Judged, GOUGE_REPORTED};
pub use machine_uri::{is_firmware, open_machine, open_machine_with};
pub use post_params::PostParams;
pub use preview::{for_each_segment, PathKind, PreviewSegment};
pub use relief::{carve_relief, ReliefParams, ReliefResult};
pub use session::{alarm_meaning, JobRequest, Session, SessionEvent, Snapshot};
