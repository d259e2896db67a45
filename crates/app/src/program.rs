//! Loading what a command that reads a program needs: the program (streamed or held), its
//! interpreter options, a tool table, the machine it names, and its diagnostics rendered to
//! fit a terminal. `check`, `gcode canon`, `plan` and `run` share it.

use crate::text::source_lines;
use crate::Error;
use oficina_canon::Units;
use oficina_gcode::text::ReadError;
use oficina_gcode::{Diagnostic, Dialect, RunOptions, Severity, ToolTable};
use oficina_motion::Profile;
use std::fmt;
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

/// Most of a program `run` and `plan` hold in memory, by default, MB.
pub const DEFAULT_MAX_PROGRAM_MB: u64 = 1024;

/// Diagnostics kept by `check` beyond those printed, so the rest can be counted; past this
/// many the interpreter stops checking (memory stays bounded on a binary file).
const KEPT_DIAGNOSTICS: usize = 10_000;

/// Why a program or a tool table could not be loaded.
#[derive(Debug)]
pub enum LoadError {
    /// A bad line, already rendered with its place and source line (as `check` shows it).
    Diagnostic(String),
    /// The file could not be read, or is too large.
    Other(Error),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Diagnostic(text) => f.write_str(text.trim_end()),
            LoadError::Other(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for LoadError {}

impl From<Error> for LoadError {
    fn from(e: Error) -> LoadError {
        LoadError::Other(e)
    }
}

/// The interpreter options a user sets for reading a program (`check`, `gcode canon`).
#[derive(Clone, Debug)]
pub struct ProgramOptions {
    /// The G-code dialect.
    pub dialect: Dialect,
    /// A LinuxCNC tool table (.tbl) for G43 and M6; without one (and without a profile's),
    /// the LinuxCNC dialect uses rs274's standalone default ([`ToolTable::rs274_default`]).
    pub tool_table: Option<PathBuf>,
    /// Skip blocks that start with `/`.
    pub block_delete: bool,
    /// Refuse Fanuc-style subprograms.
    pub disable_fanuc_subs: bool,
    /// Where `o<name> call` finds `name.ngc`, searched in order.
    pub subroutine_path: Vec<PathBuf>,
    /// A LinuxCNC INI file: its ORIENT_OFFSET and `#<_ini[section]name>` values.
    pub ini: Option<PathBuf>,
    /// A LinuxCNC parameter file (.var) read before the program starts (never written).
    pub var_file: Option<PathBuf>,
    /// Machine units; `None` is mm in check mode and inch otherwise (LinuxCNC's `rs274`).
    pub machine_units: Option<Units>,
    /// Longest line accepted, bytes.
    pub max_line_len: usize,
    /// Diagnostics the caller shows at most (0 = all).
    pub max_errors: usize,
}

impl ProgramOptions {
    /// The machine units these options mean in `check_mode` or not.
    pub fn units(&self, check_mode: bool) -> Units {
        // `gcode canon` exists to be compared with `rs274`, whose machine is in inches.
        self.machine_units
            .unwrap_or(if check_mode { Units::Mm } else { Units::Inch })
    }

    /// [`Self::run_options`] on a machine profile (named `spec` by the user): its stored
    /// offsets, and its tool table unless one was given.
    pub fn run_options_on(
        &self,
        profile: &Profile,
        spec: &str,
        check_mode: bool,
    ) -> Result<RunOptions, LoadError> {
        let mut opts = self.run_options(check_mode)?;
        opts.initial_params = crate::run_options::initial_params_for(profile, opts.dialect);
        if self.tool_table.is_none() {
            if let Some(t) = tool_table_for(None, profile, spec, opts.start.machine_units)? {
                opts.tool_table = t;
            }
        }
        Ok(opts)
    }

    /// The interpreter's options, the tool table read.
    pub fn run_options(&self, check_mode: bool) -> Result<RunOptions, LoadError> {
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
        if let Some(path) = &self.ini {
            let bytes = std::fs::read(path)
                .map_err(|e| Error(format!("cannot read INI file {}: {e}", path.display())))?;
            opts.ini = oficina_gcode::IniSettings::parse(&oficina_gcode::text::decode(&bytes));
        }
        if let Some(path) = &self.var_file {
            let bytes = std::fs::read(path).map_err(|e| {
                Error(format!(
                    "cannot read parameter file {}: {e}",
                    path.display()
                ))
            })?;
            opts.initial_params =
                oficina_gcode::parse_var_file(&oficina_gcode::text::decode(&bytes));
        }
        opts.max_line_len = self.max_line_len;
        opts.max_diagnostics = KEPT_DIAGNOSTICS.max(self.max_errors);
        let machine_units = self.units(check_mode);
        opts.start.machine_units = machine_units;
        match &self.tool_table {
            Some(path) => opts.tool_table = load_tool_table(path, machine_units)?,
            // LinuxCNC's standalone rs274 runs with its default table when given none; the
            // other dialects have no tool table (every tool number is taken as it is).
            None if self.dialect == Dialect::LinuxCnc => {
                opts.tool_table = ToolTable::rs274_default();
            }
            None => {}
        }
        Ok(opts)
    }
}

/// The tool table a program runs with on `profile` (named `spec` by the user): the one
/// `given` (`--tool-table`), else the one the profile names, else none.
pub fn tool_table_for(
    given: Option<&Path>,
    profile: &Profile,
    spec: &str,
    units: Units,
) -> Result<Option<ToolTable>, LoadError> {
    match given {
        Some(path) => load_tool_table(path, units).map(Some),
        None => Ok(crate::profile::tool_table(profile, spec, units)?),
    }
}

/// Read a LinuxCNC tool table (`--tool-table`) whose lengths are in `machine_units`; a bad
/// line comes back rendered like a program diagnostic.
pub fn load_tool_table(path: &Path, machine_units: Units) -> Result<ToolTable, LoadError> {
    let bytes = std::fs::read(path)
        .map_err(|e| Error(format!("cannot read tool table {}: {e}", path.display())))?;
    let text = oficina_gcode::text::decode(&bytes);
    ToolTable::parse(&text, machine_units).map_err(|d| {
        LoadError::Diagnostic(d.render(
            &path.display().to_string(),
            text.lines().nth(d.span.line.saturating_sub(1) as usize),
        ))
    })
}

/// Open a program to stream it through the interpreter (`check`, `gcode canon`).
pub fn open_program(path: &Path) -> Result<BufReader<File>, Error> {
    oficina_gcode::text::open_program(path).map_err(|e| read_error(path, e))
}

/// The program at `path` as grbl receives it from the sender under `tc`
/// ([`oficina_grbl::sender_view`]: `M6` and the `%` tape marks blanked in place, so lines and
/// columns hold), to check in the grbl dialect, and a note for each line the sender changes.
/// The whole program is held in memory.
pub fn grbl_sender_source(
    path: &Path,
    tc: &oficina_grbl::ToolChange,
) -> Result<(std::io::Cursor<Vec<u8>>, Vec<Diagnostic>), Error> {
    use std::io::Read;
    let mut bytes = Vec::new();
    open_program(path)?
        .read_to_end(&mut bytes)
        .map_err(|e| Error(format!("cannot read {}: {e}", path.display())))?;
    let (view, notes) = oficina_grbl::sender_view(&bytes, tc);
    Ok((std::io::Cursor::new(view), sender_notes(notes)))
}

/// The sender's notes as diagnostics of severity note.
pub(crate) fn sender_notes(notes: Vec<oficina_grbl::SenderNote>) -> Vec<Diagnostic> {
    notes
        .into_iter()
        .map(|n| Diagnostic::note(oficina_gcode::Span::new(n.line, n.col, n.len), n.message))
        .collect()
}

/// A program that could not be opened or read: the OS error once, after the file name.
fn read_error(path: &Path, e: ReadError) -> Error {
    match e {
        ReadError::Io(e) => Error(format!("cannot open {}: {e}", path.display())),
        ReadError::TooLarge { .. } => Error(format!(
            "{}: {e} (--max-program-mb raises the limit)",
            path.display()
        )),
        ReadError::Bad(d) => Error(format!("{}:{d}", path.display())),
    }
}

/// Read a whole program as text for `run` and `plan`, by the same rule as the streaming
/// commands (oficina_gcode::text); at most `max_mb` MB.
pub fn read_program(path: &Path, max_mb: u64) -> Result<String, LoadError> {
    match oficina_gcode::text::read_program(path, max_mb.saturating_mul(1_000_000)) {
        Ok(text) => Ok(text),
        Err(ReadError::Bad(d)) => Err(LoadError::Diagnostic(render_diagnostics(
            path,
            std::slice::from_ref(&d),
            0,
        ))),
        Err(e) => Err(read_error(path, e).into()),
    }
}

/// The machine profile a command uses, and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineChoice {
    /// The profile: a file or a bundled name.
    pub spec: String,
    /// The line of the program's `(machine: NAME)` comment, when the choice came from it.
    pub named_on_line: Option<u32>,
}

/// `given` (`--machine`) when there is one, else the profile the program names in a
/// `(machine: NAME)` opening comment, else the default.
pub fn machine_for(given: Option<&str>, program: &Path) -> MachineChoice {
    if let Some(m) = given {
        return MachineChoice {
            spec: m.to_string(),
            named_on_line: None,
        };
    }
    let hint = File::open(program)
        .ok()
        .and_then(|f| oficina_gcode::machine_hint(BufReader::new(f)));
    match hint {
        Some(h) => MachineChoice {
            spec: h.name,
            named_on_line: Some(h.line),
        },
        None => MachineChoice {
            spec: crate::profile::DEFAULT.to_string(),
            named_on_line: None,
        },
    }
}

/// Diagnostics rendered like a compiler's, with the source line and a caret under the place:
/// the first `max_shown` (0 = all), then how many more there are of each kind.
pub fn render_diagnostics(path: &Path, diags: &[Diagnostic], max_shown: usize) -> String {
    let shown = if max_shown == 0 {
        diags
    } else {
        &diags[..diags.len().min(max_shown)]
    };
    let lines = source_lines(path, shown.iter().map(|d| (d.span.line, d.span.col)));
    let name = path.display().to_string();
    let mut out = String::new();
    for d in shown {
        out.push_str(&d.render(&name, lines.get(&d.span.line).map(|s| s.as_str())));
    }
    let rest = &diags[shown.len()..];
    if !rest.is_empty() {
        let count = |s: Severity| rest.iter().filter(|d| d.severity == s).count();
        let (errors, warnings) = (count(Severity::Error), count(Severity::Warning));
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        out.push_str(&format!(
            "{name}: {} more not shown ({errors} error{}, {warnings} warning{}); --max-errors 0 shows all\n",
            rest.len(),
            plural(errors),
            plural(warnings),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_machine_comes_from_the_flag_then_the_program_then_the_default() {
        let dir = std::env::temp_dir().join(format!("oficina-app-program-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let named = dir.join("named.ngc");
        std::fs::write(&named, "(job)\n(machine: hotwire-xy)\nG0 X1\n").unwrap();
        let plain = dir.join("plain.ngc");
        std::fs::write(&plain, "G0 X1\n").unwrap();
        assert_eq!(
            machine_for(Some("polar-plotter"), &named).spec,
            "polar-plotter"
        );
        assert_eq!(
            machine_for(None, &named),
            MachineChoice {
                spec: "hotwire-xy".into(),
                named_on_line: Some(2)
            }
        );
        assert_eq!(machine_for(None, &plain).spec, crate::profile::DEFAULT);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
