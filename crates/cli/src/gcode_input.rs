//! The flags of the commands that read a program, and printing what `oficina_app::program`
//! loads: its diagnostics, the machine it names.

use oficina_app::{LoadError, ProgramOptions};
use oficina_canon::Units;
use oficina_gcode::RunOptions;
use oficina_gcode::ToolTable;
use oficina_gcode::{Diagnostic, Dialect};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

pub(crate) use oficina_app::DEFAULT_MAX_PROGRAM_MB;

#[derive(clap::Args, Debug, Clone)]
pub(crate) struct ProgramArgs {
    /// The G-code program.
    pub file: PathBuf,
    /// linuxcnc (default), grbl, marlin (Marlin 2.x plotters) or legacy-2006.
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
    /// A LinuxCNC INI file: `[RS274NGC]ORIENT_OFFSET` for M19 and, unless `INI_VARS = 0`,
    /// every numeric entry as the read-only `#<_ini[section]name>`.
    #[arg(long, value_name = "FILE")]
    pub ini: Option<PathBuf>,
    /// A LinuxCNC parameter file (.var, lines `NUMBER VALUE`): the parameters the program
    /// starts with (a saved G92 offset is put in force, as rs274 `-v` does). Only read.
    #[arg(long, value_name = "FILE")]
    pub var_file: Option<PathBuf>,
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

/// The program `plan` and `run` hold in memory, and where its work zero is.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct HeldProgram {
    /// G-code program.
    pub(crate) file: PathBuf,
    /// Work zero in machine coordinates, X,Y,Z mm (default: the profile's stored G54).
    #[arg(long, value_parser = crate::machine_profile::parse_xyz)]
    pub(crate) work_offset: Option<[f64; 3]>,
    #[command(flatten)]
    pub(crate) line_limit: LineLimit,
    /// Largest program held in memory, MB.
    #[arg(long, default_value_t = DEFAULT_MAX_PROGRAM_MB)]
    pub(crate) max_program_mb: u64,
}

impl HeldProgram {
    /// The whole program's text.
    pub(crate) fn read(&self) -> anyhow::Result<String> {
        read_program(&self.file, self.max_program_mb)
    }
}

/// Longest program line accepted, for every command that reads a program.
#[derive(clap::Args, Debug, Clone, Copy)]
pub(crate) struct LineLimit {
    /// Longest line accepted, KiB (longer ones are errors, never held in memory).
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub max_line_kb: u32,
}

impl LineLimit {
    pub(crate) fn bytes(self) -> usize {
        self.max_line_kb as usize * 1024
    }
}

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
    pub(crate) fn open(&self) -> anyhow::Result<BufReader<File>> {
        Ok(oficina_app::open_program(&self.file)?)
    }

    /// What the flags ask of the interpreter.
    pub(crate) fn options(&self) -> ProgramOptions {
        ProgramOptions {
            dialect: self.dialect,
            tool_table: self.tool_table.clone(),
            block_delete: self.block_delete,
            disable_fanuc_subs: self.disable_fanuc_subs,
            subroutine_path: self.subroutine_path.clone(),
            ini: self.ini.clone(),
            var_file: self.var_file.clone(),
            machine_units: self.machine_units.map(Units::from),
            max_line_len: self.limits.bytes(),
            max_errors: self.max_errors,
        }
    }

    pub(crate) fn run_options(&self, check_mode: bool) -> anyhow::Result<RunOptions> {
        loaded(self.options().run_options(check_mode))
    }

    /// The interpreter's options on `profile`: its offsets, its tool table unless one is given.
    pub(crate) fn run_options_on(
        &self,
        profile: &oficina_motion::Profile,
        spec: &str,
        check_mode: bool,
    ) -> anyhow::Result<RunOptions> {
        loaded(self.options().run_options_on(profile, spec, check_mode))
    }
}

/// A load's result for `?`: a rendered diagnostic is printed here as it is (it says "error"
/// itself) and the command fails without printing it again.
pub(crate) fn loaded<T>(result: Result<T, LoadError>) -> anyhow::Result<T> {
    match result {
        Ok(v) => Ok(v),
        Err(LoadError::Diagnostic(text)) => {
            eprint!("{text}");
            Err(crate::Reported.into())
        }
        Err(LoadError::Other(e)) => Err(e.into()),
    }
}

/// The tool table: `given`, else the one `profile` names (lengths in `units`).
pub(crate) fn tool_table_for(
    given: Option<&Path>,
    profile: &oficina_motion::Profile,
    spec: &str,
    units: Units,
) -> anyhow::Result<Option<ToolTable>> {
    loaded(oficina_app::tool_table_for(given, profile, spec, units))
}

/// Read a LinuxCNC tool table (`--tool-table`) whose lengths are in `machine_units`.
pub(crate) fn load_tool_table(path: &Path, machine_units: Units) -> anyhow::Result<ToolTable> {
    loaded(oficina_app::load_tool_table(path, machine_units))
}

/// Read a whole program as text for `run` and `plan`.
pub(crate) fn read_program(path: &Path, max_mb: u64) -> anyhow::Result<String> {
    loaded(oficina_app::read_program(path, max_mb))
}

/// The machine profile to use (`--machine`, the program's `(machine: NAME)` comment, the
/// default); where it came from is said on stderr.
pub(crate) fn machine_for(given: Option<&str>, program: &Path) -> String {
    let choice = oficina_app::machine_for(given, program);
    if let Some(line) = choice.named_on_line {
        eprintln!(
            "machine: {} (named on line {line} of {}; --machine overrides it)",
            oficina_gcode::text::escape(&choice.spec),
            program.display()
        );
    }
    choice.spec
}

/// Print diagnostics like a compiler, with the source line and a caret under the place.
pub(crate) fn print_diagnostics(path: &Path, diags: &[Diagnostic], max_shown: usize) {
    eprint!(
        "{}",
        oficina_app::render_diagnostics(path, diags, max_shown)
    );
}
