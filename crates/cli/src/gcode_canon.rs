//! `oficina gcode canon FILE`: the canonical operations in the text of LinuxCNC's standalone
//! interpreter, for line-by-line comparison with `rs274 -g`.

use crate::gcode_input::{print_diagnostics, ProgramArgs};
use oficina_gcode::Rs274Printer;
use oficina_gcode::Severity;
use std::io::{BufWriter, Write};
use std::process::ExitCode;

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    #[command(flatten)]
    pub program: ProgramArgs,
    /// Prefix each call with a counter and `N.....` in the layout of `rs274 -g`. The counter
    /// numbers the calls printed here; rs274 also numbers calls of its own driver that are not
    /// machine operations (ON_RESET, SET_FEED_REFERENCE, START_CHANGE, its `interpreter:`
    /// comments), so compare the calls, not the numbers.
    #[arg(long)]
    pub numbered: bool,
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut opts = args.program.run_options(false)?;
    // rs274 prints one NURBS_FEED per spline: no points on the curve are needed here.
    opts.whole_splines = true;
    let source = args.program.open()?;
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let mut printer = if args.numbered {
        Rs274Printer::new().numbered()
    } else {
        Rs274Printer::new()
    };
    let mut write_error = None;
    let diags = oficina_gcode::run(source, &opts, &mut |c| {
        if write_error.is_none() {
            if let Err(e) = printer.print(&c, &mut out) {
                write_error = Some(e);
            }
        }
    });
    out.flush()?;
    if let Some(e) = write_error {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            return Err(e.into());
        }
    }
    print_diagnostics(&args.program.file, &diags, args.program.max_errors);
    let failed = diags.iter().any(|d| d.severity == Severity::Error);
    Ok(if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
