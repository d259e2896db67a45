//! A program read as Oficina's interpreter reads it, in the dialect its post wrote.

use crate::{PostDialect, PostOptions};
use oficina_canon::Canon;
use oficina_canon::Units;
use oficina_gcode::ToolTable;
use oficina_gcode::{run_text, RunOptions};

/// The canonical operations of a program this crate wrote. Any diagnostic means the post
/// wrote something the control would reject or misread: the error quotes it with its line.
pub fn read_back(program: &str, opts: &PostOptions) -> Result<Vec<Canon>, String> {
    read_back_with_tools(program, opts, &[])
}

/// [`read_back`] with the control's tool table as (tool number, diameter mm): what
/// G41/G42 need to know the radius.
pub fn read_back_with_tools(
    program: &str,
    opts: &PostOptions,
    tools: &[(u32, f64)],
) -> Result<Vec<Canon>, String> {
    let mut tbl = String::new();
    let mut tools = tools.to_vec();
    if opts.dialect == PostDialect::Sinumerik
        && !tools.is_empty()
        && !tools.iter().any(|t| t.0 == crate::sinumerik::EMPTY_TOOL)
    {
        // Its programs end by loading the empty spindle.
        tools.push((crate::sinumerik::EMPTY_TOOL, 0.0));
    }
    for (t, d) in &tools {
        tbl.push_str(&format!("T{t} P{t} D{d} Z0\n"));
    }
    let tool_table = ToolTable::parse(&tbl, Units::Mm)
        .map_err(|d| format!("tool table: {}", d.render("<tool table>", None)))?;
    let translated;
    let (text, dialect) = match opts.dialect {
        // M6-capable grbl forks read tool changes as LinuxCNC does.
        PostDialect::Grbl if !opts.allow_m6 => (program, oficina_gcode::Dialect::Grbl),
        PostDialect::Grbl | PostDialect::LinuxCnc => (program, oficina_gcode::Dialect::LinuxCnc),
        PostDialect::Legacy2006 => (program, oficina_gcode::Dialect::Legacy2006),
        PostDialect::Sinumerik => {
            translated = crate::sinumerik_to_ngc(program)?;
            (translated.as_str(), oficina_gcode::Dialect::LinuxCnc)
        }
    };
    let run = RunOptions {
        dialect,
        tool_table,
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
