//! The application layer that the `oficina` CLI and the workbench server share: programs
//! loaded (text, tool table, the machine they name, rendered diagnostics), machines opened
//! from a URI, a session that drives one with its job, check summaries of a program, the
//! plan of a program (time, trace, steps), preview segments, and the job pipelines (relief
//! carving, 2.5D milling, sole molds, pen plots, embroidery) and benchmark workloads. It
//! returns data and progress events and prints nothing.
//!
//! ```
//! use oficina_app::{check_program, CheckOptions};
//! use std::sync::Arc;
//!
//! // Line 4 names two motion codes at once; check mode reports it and reads on.
//! let text = Arc::new("G21 G90 G17\nG0 X0 Y0 Z5\nG1 X30 Y40 F600\nG0 G1 X5\nM2\n".to_string());
//! let opts = CheckOptions {
//!     profile: oficina_motion::resolve("grbl-router").unwrap(),
//!     dialect: oficina_gcode::Dialect::LinuxCnc,
//! };
//! let report = check_program(&text, &opts);
//! assert_eq!(report.errors, 1);
//! assert_eq!(report.diagnostics[0].line, 4);
//! assert!((report.feed_length - 50.0).abs() < 1e-9);
//! // 5 s at the programmed feed plus the rapid: a lower bound the planner's time respects.
//! assert!(report.feed_rate_seconds > 5.0, "{}", report.feed_rate_seconds);
//! let time = report.time.unwrap();
//! assert!(time.seconds >= report.feed_rate_seconds, "{}", time.seconds);
//! ```

// `profile` stays a public module: its `resolve`, `tool_table` and `DEFAULT` read well only
// behind it (motion has its own `resolve`).
pub mod bench;
pub mod carve;
pub mod carve_mesh;
mod check;
mod controls;
pub mod design;
pub mod embroider;
mod error;
mod feeds;
mod job;
mod jog;
mod judge;
mod level;
mod machine_uri;
mod macros;
mod mill;
mod mill_job;
mod offsets;
mod output;
mod plan;
mod plot;
mod post_params;
mod preview;
pub mod profile;
mod program;
mod relief;
mod run_options;
mod session;
pub mod simulate;
mod sole;
mod text;
mod tools;
mod travel_fit;

pub use check::{
    check_for_sender, check_program, check_program_with_tools, check_source, CheckOptions,
    CheckReport, CheckedSource, Diag, ExtentsBox, TimeEstimate,
};
pub use controls::MdiReply;
pub use error::{Error, CANCELLED};
pub use feeds::{library_tool, tool_feeds, FeedsAnswer, FeedsQuery, LibraryChoice};
pub use job::{Feedback, ProgressFn};
pub use judge::{Judged, GOUGE_REPORTED};
pub use level::{
    level_file, level_options, load_map, probe_grid, probe_map, run_levelled, save_map,
    LevelTuning, LevelledRun, MapSource, ProbeRequest,
};
pub use machine_uri::{
    is_firmware, is_marlin, open_firmware, open_machine, open_machine_with, open_machine_with_tools,
};
pub use macros::{check_macros, expand as expand_macro, Macro, MacroValues, MACROS_FILE};
pub use mill::{mill, EntryKind, MillOpKind, MillParams, MillResult, PocketStrategy};
pub use mill_job::{
    job_shapes, mill_job, mill_job_upto, JobOpReport, JobOptions, JobProgram, JobResult,
    JobShapeView, JobStock,
};
pub use offsets::{system_index, Probe, WorkOffsets, SYSTEMS};
pub use output::{
    check_output, check_output_dir, plot_extensions, refuse_overwriting_drawing, same_file,
    HPGL_EXTENSIONS, PROGRAM_EXTENSIONS,
};
pub use plan::{plan_program, Interpolator, PlanOutcome, PlanOutputs, PlanRequest, PlanSummary};
pub use plot::{pen_machine, plot, FilledBy, Lift, PensBy, PlotFormat, PlotParams, PlotResult};
pub use post_params::PostParams;
pub use preview::{for_each_segment, PathKind, PreviewSegment};
pub use program::{
    grbl_sender_source, load_tool_table, machine_for, open_program, read_program,
    render_diagnostics, tool_table_for, LoadError, MachineChoice, ProgramOptions,
    DEFAULT_MAX_PROGRAM_MB,
};
pub use relief::{carve_relief, ReliefParams, ReliefResult};
pub use run_options::run_options_for;
pub use session::{
    alarm_meaning, JobRequest, Probing, ProbingResult, Session, SessionEvent, Snapshot,
    ToolChangeView,
};
pub use sole::{sole, SoleOutput, SoleParams, SoleResult};
pub use text::source_lines;
pub use tools::{
    check_tool_table, parse_tool_table, tool_rows, ToolRow, ToolTableError, TOOL_TABLE_FILE,
};
