//! What `check` and `gcode canon` share: opening a program and the interpreter options.

use anyhow::Context;
use oficina_canon::Units;
use oficina_gcode::interp::tool_table::ToolTable;
use oficina_gcode::program::RunOptions;
use oficina_gcode::{Diagnostic, Dialect};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

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
    /// Machine units: the unit of the tool table and of the offset parameters (#5161…,
    /// #5211…, #5221…). `gcode canon` defaults to inch like LinuxCNC's standalone `rs274`;
    /// `check` to mm.
    #[arg(long, value_enum)]
    pub machine_units: Option<MachineUnits>,
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
    pub fn open(&self) -> anyhow::Result<BufReader<File>> {
        let f = File::open(&self.file)
            .with_context(|| format!("cannot open {}", self.file.display()))?;
        Ok(BufReader::with_capacity(1 << 16, f))
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
        // `gcode canon` exists to be compared with `rs274`, whose machine is in inches.
        let default_units = if check_mode {
            MachineUnits::Mm
        } else {
            MachineUnits::Inch
        };
        let machine_units: Units = self.machine_units.unwrap_or(default_units).into();
        opts.start.machine_units = machine_units;
        if let Some(path) = &self.tool_table {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read tool table {}", path.display()))?;
            opts.tool_table = ToolTable::parse(&text, machine_units).map_err(|d| {
                anyhow::anyhow!(
                    "{}",
                    d.render(
                        &path.display().to_string(),
                        text.lines().nth(d.span.line as usize - 1)
                    )
                )
            })?;
        }
        Ok(opts)
    }
}

/// Longest source line shown under a diagnostic; longer ones are cut (a 10 GB line is not
/// echoed to the terminal).
const SHOWN_LINE_MAX: usize = 240;

/// Fetch the text of the given 1-based lines by streaming the file once more.
pub fn source_lines(path: &Path, wanted: impl IntoIterator<Item = u32>) -> BTreeMap<u32, String> {
    let mut out: BTreeMap<u32, String> = wanted.into_iter().map(|l| (l, String::new())).collect();
    let Some(&last) = out.keys().next_back() else {
        return out;
    };
    let Ok(f) = File::open(path) else { return out };
    let mut reader = BufReader::new(f);
    let mut buf = Vec::new();
    for line_no in 1..=last {
        buf.clear();
        // Read at most a screenful of each line, then skip to its end without keeping it.
        let n = (&mut reader)
            .take(SHOWN_LINE_MAX as u64)
            .read_until(b'\n', &mut buf)
            .unwrap_or(0);
        if n == 0 {
            break;
        }
        if !buf.ends_with(b"\n") {
            let mut sink = Vec::new();
            loop {
                sink.clear();
                let m = (&mut reader)
                    .take(1 << 16)
                    .read_until(b'\n', &mut sink)
                    .unwrap_or(0);
                if m == 0 || sink.ends_with(b"\n") {
                    break;
                }
            }
        }
        if let Some(slot) = out.get_mut(&line_no) {
            *slot = String::from_utf8_lossy(&buf)
                .trim_end_matches(['\n', '\r'])
                .to_string();
        }
    }
    out
}

/// Print diagnostics like a compiler, with the source line and a caret under the place.
pub fn print_diagnostics(path: &Path, diags: &[Diagnostic]) {
    let lines = source_lines(path, diags.iter().map(|d| d.span.line));
    let name = path.display().to_string();
    for d in diags {
        eprint!(
            "{}",
            d.render(&name, lines.get(&d.span.line).map(|s| s.as_str()))
        );
    }
}
