//! A program read as Oficina's interpreter reads it, in the dialect its post wrote.

use crate::{Dialect, PostOptions};
use oficina_canon::Canon;
use oficina_gcode::program::{run_text, RunOptions};

/// The canonical operations of a program this crate wrote. Any diagnostic means the post
/// wrote something the control would reject or misread: the error quotes it with its line.
pub fn read_back(program: &str, opts: &PostOptions) -> Result<Vec<Canon>, String> {
    let translated;
    let (text, dialect) = match opts.dialect {
        // M6-capable grbl forks read tool changes as LinuxCNC does.
        Dialect::Grbl if !opts.allow_m6 => (program, oficina_gcode::Dialect::Grbl),
        Dialect::Grbl | Dialect::LinuxCnc => (program, oficina_gcode::Dialect::LinuxCnc),
        Dialect::Legacy2006 => (program, oficina_gcode::Dialect::Legacy2006),
        Dialect::Sinumerik => {
            translated = crate::sinumerik::to_ngc(program)?;
            (translated.as_str(), oficina_gcode::Dialect::LinuxCnc)
        }
    };
    let run = RunOptions {
        dialect,
        ..RunOptions::default()
    };
    let mut canon = Vec::new();
    let diagnostics = run_text(text, &run, &mut |c| canon.push(c));
    if let Some(d) = diagnostics.first() {
        let line = text.lines().nth(d.span.line.saturating_sub(1) as usize);
        return Err(format!(
            "the interpreter rejects the generated program ({} diagnostics):\n{}",
            diagnostics.len(),
            d.render("<generated program>", line)
        ));
    }
    Ok(canon)
}
