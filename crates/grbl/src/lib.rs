//! The grbl-family machine link.
//!
//! ```
//! use oficina_grbl::{clean_line, line_words, GrblState, StatusReport, E_LINE_OVERFLOW};
//!
//! // A status report with work coordinate offsets: the work position is MPos − WCO.
//! let st = StatusReport::parse("<Run|MPos:12.000,5.000,-1.000|FS:500,0|WCO:10.000,0.000,-2.000>");
//! let st = st.unwrap();
//! assert_eq!(st.state, GrblState::Run);
//! assert_eq!(st.feed, Some(500.0));
//! assert_eq!(st.work_position(None), Some(vec![2.0, 5.0, 1.0]));
//!
//! // An input line as grbl reads it: comments and spaces dropped, letters upper-cased.
//! let line = clean_line("g1 x10 (to the edge) f300 ; finish").unwrap();
//! assert_eq!(line, "G1X10F300");
//! assert_eq!(line_words(&line).unwrap(), [('G', 1.0), ('X', 10.0), ('F', 300.0)]);
//! // A line longer than grbl's 80-byte buffer is error 11.
//! assert_eq!(clean_line(&"G1X1".repeat(21)), Err(E_LINE_OVERFLOW));
//! ```
//!
//! The API is the flat list below (modules are private):
//! - the grbl 1.1 protocol vocabulary: [`Realtime`], [`StatusReport`] / [`GrblState`],
//!   [`Response`], the error/alarm/setting texts ([`describe_error`], [`setting_info`]);
//! - grbl's G-code dialect (shared by the emulator and resume): [`clean_line`],
//!   [`line_words`], the modal [`Interp`] and the [`Segment`]s a line moves;
//! - byte pipes and the line reader: [`Endpoint`], [`Pty`], [`Link`] / [`LinkEvent`];
//! - streaming, its record, how it ended and resume: [`StreamProgram`], [`Sender`], [`StreamReport`],
//!   [`ResumeOptions`], [`replay`], [`resume_preamble`];
//! - the machine panel: [`read_settings`], [`write_setting`], [`ContinuousJog`],
//!   [`GrblDevice`] (Oficina's `Machine` trait), [`GrblMachine`] (the one-call job runner),
//!   [`connect_with_retry`] (the link life cycle);
//! - probing (touch plate, corner, tool length setter) over a [`ProbeLink`] (a [`Sender`]
//!   or any `Machine`): [`run_z_plate`], [`run_corner`], [`run_tool_setter`];
//! - auto-levelling: [`ProbeGrid`] probes a [`HeightMap`] through a [`SurfaceProbe`]
//!   ([`MachineProbe`] over a [`ProbeLink`]), [`level_program`] / [`level_stream`] /
//!   [`level_text`] make a program follow it;
//! - tool changes at `M6` for firmware without a changer: [`ToolChange`] ([`ToolPolicy`],
//!   [`setter_at`]) in [`RunSettings`], the [`ToolStop`]s of a [`StreamProgram`].
//!
//! - Marlin 2.x (Makelangelo): [`MarlinLink`] streams numbered, checksummed lines, one in
//!   flight, over the same transports and journal; [`MarlinDevice`] is its `Machine`.
//!
//! The emulator and the fault proxy live in `oficina-grbl-emu`, which depends on this crate.

// What other crates do not use is `pub(crate)`: the API is the list below.

mod autolevel;
mod check;
mod device;
mod eta;
mod gline;
mod interp;
mod job;
mod jog;
mod journal;
mod link;
mod machine;
mod marlin;
mod messages;
mod probe;
mod realtime;
mod reconnect;
mod report;
mod response;
mod resume;
mod sender;
mod settings;
mod status;
mod toolchange;
mod track;
mod transport;
mod worker;

pub use autolevel::{
    feed_area, level_program, level_stream, level_text, Area, GridSpec, HeightMap, LevelOptions,
    LevelReport, MachineProbe, ProbeGrid, ProbeMotion, SurfaceProbe, MAX_GRID,
};
pub use device::{GrblDevice, Routine};
pub use gline::{clean as clean_line, words as line_words, E_LINE_OVERFLOW, MAX_LINE};
pub use interp::{dist, Effect, Flow, Interp, Modal, ProbeKind, Rate, Segment, Spindle};
pub use job::{StreamLine, StreamProgram};
pub use jog::{parse_request as parse_jog, step_line as jog_step_line, ContinuousJog, JogRequest};
pub use link::{Link, LinkEvent};
pub use machine::{GrblMachine, RunOutcome, RunSettings, Start};
pub use marlin::{
    checksum as marlin_checksum, code_of as marlin_code, frame as marlin_frame, marlin_endpoint,
    marlin_program, plan_resume as plan_marlin_resume, strip_comment as marlin_command,
    MarlinControl, MarlinDevice, MarlinEnd, MarlinLink, MarlinNotice, MarlinOptions, MarlinReport,
    MarlinResume, Reply as MarlinReply, MAX_CMD_SIZE as MARLIN_MAX_CMD_SIZE,
};
pub use messages::{describe_alarm, describe_error, setting_info, SettingInfo, SETTINGS};
pub use probe::{run_corner, run_tool_setter, run_z_plate, Approach, Corner, ProbeError};
pub use probe::{ProbeLink, ProbeResult, SetterResult, ToolSetter, ZPlate};
pub use realtime::{override_by_name, Realtime};
pub use reconnect::{connect_with_retry, LinkState, RetryPolicy};
pub use report::{StreamEnd, StreamReport};
pub use response::{probe_report, report_xyz, Response};
pub use resume::{preamble as resume_preamble, replay, ResumeOptions};
pub use sender::{Control, Mode, Notice, Reply, Sender, SenderOptions};
pub use settings::{read as read_settings, write as write_setting, Setting};
pub use status::{GrblState, StatusReport};
pub use toolchange::{sender_view, setter_at, SenderNote, ToolChange, ToolPolicy, ToolStop};
pub use transport::{is_timeout, list_ports, Endpoint, PortInfo, Pty};
