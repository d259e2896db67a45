//! `oficina check FILE`: every diagnostic with its place (the check goes on after errors),
//! then what the program does: extents, path length, tools and a time estimate.

use crate::gcode_input::{machine_for, print_diagnostics, ProgramArgs};
use crate::machine_profile;
use oficina_canon::{Extents, Summary};
use oficina_gcode::{Dialect, Severity};
use oficina_grbl::ToolChange;
use oficina_motion::format_hms;
use std::process::ExitCode;

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    #[command(flatten)]
    pub program: ProgramArgs,
    /// Machine profile (file or bundled name) whose planner gives the time estimate; default:
    /// the program's `(machine: NAME)` opening comment, else grbl-router.
    #[arg(long)]
    pub machine: Option<String>,
    /// Work zero in machine coordinates, X,Y,Z mm (default: the profile's stored G54).
    #[arg(long, value_parser = machine_profile::parse_xyz)]
    pub work_offset: Option<[f64; 3]>,
    /// With --dialect grbl: what the sender does at M6 (grbl has none), as `run` and
    /// `console` take it; the M6 lines then get a note instead of grbl's error:20
    /// (`firmware`: the error stays). The `%` tape marks the sender drops get a note too.
    #[arg(long, default_value = "pause", value_name = "POLICY")]
    pub tool_change: oficina_grbl::ToolPolicy,
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    let machine = machine_for(args.machine.as_deref(), &args.program.file);
    let profile = machine_profile::resolve_with_offset(&machine, args.work_offset)?;
    let opts = args.program.run_options_on(&profile, &machine, true)?;
    let checked = if args.program.dialect == Dialect::Grbl {
        // What grbl receives from the sender: M6 and the tape marks handled, with notes.
        let tc = ToolChange {
            policy: args.tool_change,
            ..ToolChange::default()
        };
        let (source, notes) = oficina_app::grbl_sender_source(&args.program.file, &tc)?;
        let mut checked = oficina_app::check_source(source, opts, &profile);
        checked.diagnostics.extend(notes);
        checked.diagnostics.sort_by_key(|d| d.span.line);
        checked
    } else {
        oficina_app::check_source(args.program.open()?, opts, &profile)
    };
    let (diags, summary, ops, planned) = (
        checked.diagnostics,
        checked.summary,
        checked.operations,
        checked.time,
    );
    print_diagnostics(&args.program.file, &diags, args.program.max_errors);
    let count = |s: Severity| diags.iter().filter(|d| d.severity == s).count();
    let (errors, warnings, notes) = (
        count(Severity::Error),
        count(Severity::Warning),
        count(Severity::Note),
    );
    println!(
        "{}: {} error{}, {} warning{}{}, {} canonical operations",
        args.program.file.display(),
        errors,
        plural(errors),
        warnings,
        plural(warnings),
        if notes > 0 {
            format!(", {notes} note{}", plural(notes))
        } else {
            String::new()
        },
        ops
    );
    print_summary(&summary);
    match planned {
        Ok(e) => println!(
            "  time estimate           {} on {} (look-ahead planner, {} segments)",
            format_hms(e.seconds, 1),
            machine,
            e.segments
        ),
        Err(e) => println!(
            "  time estimate           not available on {}: {e}",
            machine
        ),
    }
    Ok(if errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn print_summary(s: &Summary) {
    println!(
        "  extents (mm, machine)   {:>22} {:>22} {:>22}",
        "X", "Y", "Z"
    );
    print_extents("feed", &s.feed_extents);
    print_extents("rapid", &s.rapid_extents);
    println!(
        "  path length             feed {:.3} mm in {} moves ({} arcs), rapid {:.3} mm in {} moves",
        s.feed_length, s.feed_moves, s.arcs, s.rapid_length, s.rapid_moves
    );
    let tools: Vec<String> = s.tools.iter().map(|t| format!("T{t}")).collect();
    println!(
        "  tools                   {}",
        if tools.is_empty() {
            "none changed".into()
        } else {
            tools.join(" ")
        }
    );
    print!(
        "  feed-rate time          {} (a lower bound: programmed feeds and joint top speeds, no acceleration",
        format_hms(s.feed_rate_seconds, 1)
    );
    if s.untimed_moves > 0 {
        print!(
            "; {} feed moves without a feed rate not counted",
            s.untimed_moves
        );
    }
    println!(")");
}

fn print_extents(name: &str, e: &Extents) {
    if e.is_empty() {
        println!("  {name:<22}  none");
        return;
    }
    let cell = |i: usize| format!("{:.3} … {:.3}", e.min[i], e.max[i]);
    println!(
        "  {name:<22}  {:>22} {:>22} {:>22}",
        cell(0),
        cell(1),
        cell(2)
    );
}
