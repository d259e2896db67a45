//! Programs run through rs274 (the path's oracle) and through Oficina's interpreter and
//! planner, the plan checked by `checker` against rs274's path.

pub(crate) mod checker;
pub(crate) mod rs274_path;

use oficina_canon::{Canon, Units};
use oficina_gcode::{RunOptions, Severity, ToolTable};
use oficina_motion::{plan, PlanOptions, Profile, Segment};
use std::path::Path;
use std::process::{Command, Stdio};

/// Tools 1…20, zero length: the tool changes of the stress programs find their tools.
pub(crate) fn tool_table_text() -> String {
    (1..=20)
        .map(|t| format!("T{t} P{t} D0.125 Z0 ;\n"))
        .collect()
}

/// What happened to one program.
pub(crate) enum Outcome {
    /// Both read it; the plan checked against the path.
    Checked(checker::Verdict),
    /// rs274 and Oficina both refused it: their messages.
    BothRefused(String, String),
    /// rs274 refused it, Oficina did not.
    OnlyRs274Refused(String),
    /// rs274 accepted it; Oficina refused it (interpreter or planner): why.
    Refused(String),
}

/// rs274's canonical text for `program`, or its refusal. None: rs274 is not installed.
/// Runs one rs274 at a time (the caller's loop), with a private HOME for its tool file.
pub(crate) fn rs274(program: &Path, work: &Path) -> Option<Result<String, String>> {
    let tools = work.join("tool.tbl");
    std::fs::write(&tools, tool_table_text()).ok()?;
    let out = work.join("rs274.out");
    let _ = std::fs::remove_file(&out);
    let run = Command::new("rs274")
        .env("HOME", work)
        .arg("-g")
        .arg("-t")
        .arg(&tools)
        .arg(program)
        .arg(&out)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .ok()?;
    if run.status.success() {
        std::fs::read_to_string(&out).ok().map(Ok)
    } else {
        let msg = String::from_utf8_lossy(&run.stderr).replace("executing", "");
        Some(Err(msg.trim().lines().next().unwrap_or("").to_string()))
    }
}

/// Oficina's canon for `text`, or the first error.
pub(crate) fn interpret(text: &str) -> Result<Vec<Canon>, String> {
    let opts = RunOptions {
        tool_table: ToolTable::parse(&tool_table_text(), Units::Mm).map_err(|d| d.to_string())?,
        ..RunOptions::default()
    };
    let mut ops = Vec::new();
    let diags = oficina_gcode::run_text(text, &opts, &mut |c| ops.push(c));
    match diags.iter().find(|d| d.severity == Severity::Error) {
        Some(d) => Err(d.to_string()),
        None => Ok(ops),
    }
}

/// Oficina's canon printed as rs274 prints: the path's stand-in where rs274 is missing.
pub(crate) fn own_text(ops: &[Canon]) -> String {
    let mut p = oficina_gcode::Rs274Printer::new().numbered();
    let mut out = Vec::new();
    for c in ops {
        p.print(c, &mut out).expect("printing to memory");
    }
    String::from_utf8(out).expect("utf-8")
}

pub(crate) fn planned(ops: &[Canon], profile: &Profile) -> Result<Vec<Segment>, String> {
    plan(ops.iter().cloned(), profile, PlanOptions::default())
        .map_err(|e| e.to_string())?
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())
}

/// Runs `program` both ways and checks the plan; `oracle` false takes Oficina's own canon as
/// the path (rs274 not installed).
pub(crate) fn run(program: &Path, profile: &Profile, work: &Path, oracle: bool) -> Outcome {
    let text = match std::fs::read(program) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => return Outcome::Refused(format!("cannot read: {e}")),
    };
    let ours = interpret(&text);
    let peer = if oracle { rs274(program, work) } else { None };
    let reference = match (peer, &ours) {
        (Some(Err(theirs)), Err(e)) => return Outcome::BothRefused(theirs, e.clone()),
        (Some(Err(theirs)), Ok(_)) => return Outcome::OnlyRs274Refused(theirs),
        (_, Err(e)) => return Outcome::Refused(e.clone()),
        (Some(Ok(t)), Ok(_)) => t,
        (None, Ok(ops)) => own_text(ops),
    };
    let ops = ours.expect("accepted above");
    let segs = match planned(&ops, profile) {
        Ok(s) => s,
        Err(e) => return Outcome::Refused(e),
    };
    let elems = rs274_path::read(&reference, profile.start);
    Outcome::Checked(checker::check(
        &elems,
        &segs,
        profile,
        profile.path_tolerance,
    ))
}
