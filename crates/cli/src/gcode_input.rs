//! What the commands that read a program share: opening it, the interpreter options, the
//! machine it names, and printing diagnostics so that they fit a terminal.

use anyhow::Context;
use oficina_canon::Units;
use oficina_gcode::RunOptions;
use oficina_gcode::ToolTable;
use oficina_gcode::{Diagnostic, Dialect};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args, Debug, Clone)]
pub struct ProgramArgs {
    /// The G-code program.
    pub file: PathBuf,
    /// linuxcnc (default), grbl or legacy-2006.
    #[arg(long, default_value = "linuxcnc")]
    pub dialect: Dialect,
    /// A LinuxCNC tool table (.tbl) for G43 and M6.
    #[arg(long)]
    pub tool_table: Option<PathBuf>,
    /// Skip blocks that start with `/`.
    #[arg(long)]
    pub block_delete: bool,
    /// Refuse Fanuc-style subprograms (`O100` … `M99`, `M98 P100`), as LinuxCNC's
    /// `DISABLE_FANUC_STYLE_SUB` does.
    #[arg(long)]
    pub disable_fanuc_subs: bool,
    /// A directory where `o<name> call` finds `name.ngc` (LinuxCNC's SUBROUTINE_PATH);
    /// repeat for several, searched in order.
    #[arg(long, value_name = "DIR")]
    pub subroutine_path: Vec<PathBuf>,
    /// Machine units: the unit of the tool table and of the offset parameters (#5161…,
    /// #5211…, #5221…). `gcode canon` defaults to inch like LinuxCNC's standalone `rs274`;
    /// `check` to mm.
    #[arg(long, value_enum)]
    pub machine_units: Option<MachineUnits>,
    #[command(flatten)]
    pub limits: LineLimit,
    /// Print at most this many diagnostics (then a count of the rest); 0 prints them all.
    #[arg(long, default_value_t = 50)]
    pub max_errors: usize,
}

/// Longest program line accepted, for every command that reads a program.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct LineLimit {
    /// Longest line accepted, KiB (longer ones are errors, never held in memory).
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub max_line_kb: u32,
}

impl LineLimit {
    pub fn bytes(self) -> usize {
        self.max_line_kb as usize * 1024
    }
}

/// Diagnostics kept by `check` beyond those printed, so the rest can be counted; past this
/// many the interpreter stops checking (memory stays bounded on a binary file).
const KEPT_DIAGNOSTICS: usize = 10_000;

#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum MachineUnits {
    Mm,
    Inch,
}

impl From<MachineUnits> for Units {
    fn from(u: MachineUnits) -> Units {
        match u {
            MachineUnits::Mm => Units::Mm,
            MachineUnits::Inch => Units::Inch,
        }
    }
}

impl ProgramArgs {
    pub fn open(&self) -> anyhow::Result<BufReader<File>> {
        open(&self.file)
    }

    pub fn run_options(&self, check_mode: bool) -> anyhow::Result<RunOptions> {
        let mut opts = if check_mode {
            RunOptions::check(self.dialect)
        } else {
            RunOptions {
                dialect: self.dialect,
                ..RunOptions::default()
            }
        };
        opts.block_delete = self.block_delete;
        opts.disable_fanuc_subs = self.disable_fanuc_subs;
        opts.subroutine_path = self.subroutine_path.clone();
        opts.max_line_len = self.limits.bytes();
        opts.max_diagnostics = KEPT_DIAGNOSTICS.max(self.max_errors);
        // `gcode canon` exists to be compared with `rs274`, whose machine is in inches.
        let default_units = if check_mode {
            MachineUnits::Mm
        } else {
            MachineUnits::Inch
        };
        let machine_units: Units = self.machine_units.unwrap_or(default_units).into();
        opts.start.machine_units = machine_units;
        if let Some(path) = &self.tool_table {
            opts.tool_table = load_tool_table(path, machine_units)?;
        }
        Ok(opts)
    }
}

/// Read a LinuxCNC tool table (`--tool-table`) whose lengths are in `machine_units`; a bad
/// line is printed like a program diagnostic.
pub fn load_tool_table(path: &Path, machine_units: Units) -> anyhow::Result<ToolTable> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read tool table {}", path.display()))?;
    let text = oficina_gcode::text::decode(&bytes);
    let table = ToolTable::parse(&text, machine_units).map_err(|d| {
        eprint!(
            "{}",
            d.render(
                &path.display().to_string(),
                text.lines().nth(d.span.line.saturating_sub(1) as usize)
            )
        );
        crate::Reported
    })?;
    Ok(table)
}

/// Open a program to stream it through the interpreter (`check`, `gcode canon`).
pub fn open(path: &Path) -> anyhow::Result<BufReader<File>> {
    oficina_gcode::text::open_program(path).map_err(|e| read_error(path, e))
}

/// A program that could not be opened or read: the OS error once, after the file name.
fn read_error(path: &Path, e: oficina_gcode::text::ReadError) -> anyhow::Error {
    use oficina_gcode::text::ReadError;
    match e {
        ReadError::Io(e) => {
            anyhow::Error::new(e).context(format!("cannot open {}", path.display()))
        }
        ReadError::TooLarge { .. } => {
            anyhow::anyhow!(
                "{}: {e} (--max-program-mb raises the limit)",
                path.display()
            )
        }
        ReadError::Bad(d) => anyhow::anyhow!("{}:{d}", path.display()),
    }
}

/// Most of a program `run` and `plan` hold in memory, by default.
pub const DEFAULT_MAX_PROGRAM_MB: u64 = 1024;

/// Read a whole program as text for `run` and `plan`, by the same rule as the streaming
/// commands (oficina_gcode::text). A diagnostic is printed here, as `check` prints it.
pub fn read_program(path: &Path, max_mb: u64) -> anyhow::Result<Result<String, ExitCode>> {
    use oficina_gcode::text::ReadError;
    match oficina_gcode::text::read_program(path, max_mb.saturating_mul(1_000_000)) {
        Ok(text) => Ok(Ok(text)),
        Err(ReadError::Bad(d)) => {
            print_diagnostics(path, std::slice::from_ref(&d), 0);
            Ok(Err(ExitCode::FAILURE))
        }
        Err(e) => Err(read_error(path, e)),
    }
}

/// The machine profile to use: `--machine` when given, else the one the program names in a
/// `(machine: NAME)` opening comment (said on stderr), else the default.
pub fn machine_for(given: Option<&str>, program: &Path) -> String {
    if let Some(m) = given {
        return m.to_string();
    }
    let hint = File::open(program)
        .ok()
        .and_then(|f| oficina_gcode::machine_hint(BufReader::new(f)));
    match hint {
        Some(h) => {
            eprintln!(
                "machine: {} (named on line {} of {}; --machine overrides it)",
                oficina_gcode::text::escape(&h.name),
                h.line,
                program.display()
            );
            h.name
        }
        None => crate::machine_profile::DEFAULT.to_string(),
    }
}

/// Print diagnostics like a compiler, with the source line and a caret under the place: the
/// first `max_shown` (0 = all), then how many more there are of each kind.
pub fn print_diagnostics(path: &Path, diags: &[Diagnostic], max_shown: usize) {
    let shown = if max_shown == 0 {
        diags
    } else {
        &diags[..diags.len().min(max_shown)]
    };
    let lines = oficina_app::source_lines(path, shown.iter().map(|d| (d.span.line, d.span.col)));
    let name = path.display().to_string();
    for d in shown {
        eprint!(
            "{}",
            d.render(&name, lines.get(&d.span.line).map(|s| s.as_str()))
        );
    }
    let rest = &diags[shown.len()..];
    if !rest.is_empty() {
        let errors = rest
            .iter()
            .filter(|d| d.severity == oficina_gcode::Severity::Error)
            .count();
        eprintln!(
            "{name}: {} more not shown ({errors} error{}, {} warning{}); --max-errors 0 shows all",
            rest.len(),
            if errors == 1 { "" } else { "s" },
            rest.len() - errors,
            if rest.len() - errors == 1 { "" } else { "s" },
        );
    }
}
