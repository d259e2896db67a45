//! The driver: front end (text → evaluated blocks) and interpreter (blocks → canonical
//! operations) joined, streaming. Nothing is kept per block, so a program of any size runs
//! in constant memory (the diagnostics of check mode are bounded too).

use crate::block::Block;
use crate::diag::{Diagnostic, Span};
use crate::exec::{Executor, ProgramEnd};
use crate::interp::tool_table::ToolTable;
use crate::interp::{Flow, Interpreter, StartState};
use crate::params::Params;
use crate::Dialect;
use oficina_canon::Canon;
use std::io::{BufRead, Cursor, Seek};

/// How to run a program.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// The dialect the program is read in.
    pub dialect: Dialect,
    /// Skip blocks that start with `/` (the front end honours it).
    pub block_delete: bool,
    /// The tools the machine knows.
    pub tool_table: ToolTable,
    /// Check mode: report an erroneous block, skip it, go on. Run mode stops at the first.
    pub continue_after_error: bool,
    /// The modal state the program starts in.
    pub start: StartState,
    /// Most diagnostics kept in check mode (0 = 1000); past it checking stops.
    pub max_diagnostics: usize,
    /// Longest line accepted, in bytes (0 = [`crate::exec::DEFAULT_MAX_LINE_LEN`]).
    pub max_line_len: usize,
    /// Parameter values the machine holds before the program starts, like LinuxCNC's `.var`
    /// file or grbl's EEPROM: e.g. the stored G54 offset in #5221…#5223 (machine units).
    pub initial_params: Vec<(i64, f64)>,
    /// Refuse Fanuc-style subprograms (`O100` … `M99`, `M98`), as LinuxCNC's
    /// `DISABLE_FANUC_STYLE_SUB` does.
    pub disable_fanuc_subs: bool,
    /// Directories searched for `name.ngc` by `o<name> call` (LinuxCNC's SUBROUTINE_PATH).
    pub subroutine_path: Vec<std::path::PathBuf>,
    /// What a LinuxCNC INI file sets: M19's ORIENT_OFFSET, `#<_ini[section]name>` values.
    pub ini: crate::IniSettings,
    /// Each spline as one [`oficina_canon::CanonOp::Spline`], as rs274 reads it, for
    /// readers that need no points on it (printing rs274's text, counting); otherwise
    /// (the default) traced into the straight feeds that move along it.
    pub whole_splines: bool,
}

impl RunOptions {
    /// Options for check mode in `dialect`: go on after an error.
    pub fn check(dialect: Dialect) -> RunOptions {
        RunOptions {
            dialect,
            continue_after_error: true,
            ..RunOptions::default()
        }
    }
}

/// Feeds blocks to the interpreter and collects what went wrong.
pub struct Driver {
    /// The modal interpreter.
    pub interp: Interpreter,
    /// The parameters of the run.
    pub params: Params,
    diagnostics: Vec<Diagnostic>,
    continue_after_error: bool,
    limit: usize,
    ended: bool,
    /// Line of the last block read: where an unterminated program is reported.
    last_line: u32,
    /// The subroutine call depth when the last block ran (a drop is a return: M73).
    call_depth: usize,
}

/// Before a block: if a subroutine returned since the last one, the state its M73 saved
/// comes back (rs274 restores it in `leave_context`, at the return).
fn returned(
    interp: &mut Interpreter,
    params: &mut Params,
    depth: &mut usize,
    sink: &mut dyn FnMut(Canon),
) -> Result<(), Diagnostic> {
    let now = params.call_depth();
    let dropped = now < *depth;
    *depth = now;
    if dropped && interp.has_saved_contexts() {
        interp.left_call(params, sink)?;
    }
    Ok(())
}

impl Driver {
    /// A driver for `opts`, its interpreter started (operations it makes go to `sink`).
    pub fn new(opts: &RunOptions, sink: &mut dyn FnMut(Canon)) -> Driver {
        let mut interp = Interpreter::new(opts.dialect, &opts.start, opts.tool_table.clone());
        let mut params = Params::new();
        for &(n, v) in &opts.initial_params {
            // Numbers come from our own callers (profiles, CLI), checked there; a bad one is
            // ignored rather than aborting a run before it starts.
            let _ = params.set(n, v);
        }
        if opts.ini.disable_g92_persistence {
            // rs274 clears the saved G92 parameters before reading them.
            for n in 5210..5220 {
                let _ = params.set(n, 0.0);
            }
        }
        // INI values are read-only globals, as rs274 caches them (PA_READONLY).
        for (name, v) in &opts.ini.values {
            params.set_system(name, *v);
        }
        interp.orient_offset = opts.ini.orient_offset;
        interp.whole_splines = opts.whole_splines;
        interp.begin(&mut params, sink);
        interp.update_named_params(&mut params);
        Driver {
            interp,
            params,
            diagnostics: Vec::new(),
            continue_after_error: opts.continue_after_error,
            limit: if opts.max_diagnostics == 0 {
                1000
            } else {
                opts.max_diagnostics
            },
            ended: false,
            last_line: 1,
            call_depth: 0,
        }
    }

    fn report(&mut self, d: Diagnostic) {
        if self.diagnostics.len() < self.limit {
            self.diagnostics.push(d);
        } else if self.diagnostics.len() == self.limit {
            let line = d.span.line;
            self.diagnostics.push(
                Diagnostic::error(
                    Span::line(line),
                    format!(
                        "more than {} diagnostics: checking stopped here",
                        self.limit
                    ),
                )
                .with_help("fix the ones above and check again"),
            );
        }
    }

    /// A G70–G72 cycle: its profile subroutine read block by block, then cut.
    fn lathe_cycle<R: BufRead + Seek>(
        &mut self,
        exec: &mut Executor<R>,
        sink: &mut dyn FnMut(Canon),
    ) -> Result<(), Diagnostic> {
        let read = self.read_profile(exec);
        self.call_depth = self.params.call_depth();
        match read {
            Ok(()) => self.interp.finish_lathe_cycle(sink),
            Err(e) => {
                self.interp.abort_lathe_cycle();
                Err(e)
            }
        }
    }

    fn read_profile<R: BufRead + Seek>(
        &mut self,
        exec: &mut Executor<R>,
    ) -> Result<(), Diagnostic> {
        let Some((label, line)) = self.interp.lathe_profile_call() else {
            return Ok(());
        };
        exec.call_for_profile(&label, line, &mut self.params)?;
        let mut block = Block::default();
        loop {
            let interp = &self.interp;
            let mut refresh = |params: &mut Params| interp.update_named_params(params);
            let read = exec.read_block_slow(&mut self.params, &mut block, &mut refresh);
            let notes: Vec<Diagnostic> = exec.take_notes().collect();
            for d in notes {
                self.report(d);
            }
            if !read? {
                if exec.take_profile_returned() {
                    return Ok(());
                }
                return Err(Diagnostic::error(
                    Span::line(line),
                    format!("the program ended inside the profile o{label} of this cycle"),
                ));
            }
            self.interp.profile_block(&block)?;
            self.params.mark_system_stale();
        }
    }

    /// Run the whole program from `exec`.
    pub fn run<R: BufRead + Seek>(
        mut self,
        exec: &mut Executor<R>,
        sink: &mut dyn FnMut(Canon),
    ) -> Vec<Diagnostic> {
        // One block reused throughout: no allocation per block on the straight path.
        let mut block = Block::default();
        loop {
            // The usual lines first, in one stretch, until one is declined or its block
            // does not simply continue the program.
            let interp = &mut self.interp;
            let mut stopped = None;
            let depth = &mut self.call_depth;
            let last = exec.read_fast_lines(&mut self.params, &mut block, |block, params| {
                params.mark_system_stale();
                if let Err(e) = returned(interp, params, depth, sink) {
                    stopped = Some(Err(e));
                    return false;
                }
                match interp.execute(block, params, sink) {
                    Ok(Flow::Continue) => true,
                    other => {
                        stopped = Some(other);
                        false
                    }
                }
            });
            if last > 0 {
                self.last_line = last;
            }
            let result = match stopped {
                Some(result) => result,
                None => {
                    // `#<_x>` and friends cost a map update each: brought up to date only
                    // before a line that reads them, which only programs that read them pay.
                    let interp = &self.interp;
                    let mut refresh = |params: &mut Params| interp.update_named_params(params);
                    let read = exec.read_block_slow(&mut self.params, &mut block, &mut refresh);
                    if exec.has_notes() {
                        let notes: Vec<Diagnostic> = exec.take_notes().collect();
                        for d in notes {
                            self.report(d);
                        }
                    }
                    let result = match read {
                        Ok(false) => break,
                        Ok(true) => {
                            self.params.mark_system_stale();
                            returned(
                                &mut self.interp,
                                &mut self.params,
                                &mut self.call_depth,
                                sink,
                            )
                            .and_then(|()| self.interp.execute(&block, &mut self.params, sink))
                        }
                        Err(e) => Err(e),
                    };
                    if block.line > 0 {
                        self.last_line = block.line;
                    }
                    if exec.has_printed() {
                        for text in exec.take_printed() {
                            self.report(Diagnostic::warning(
                                Span::line(block.line),
                                format!("(print) {text}"),
                            ));
                        }
                    }
                    result
                }
            };
            let result = match result {
                Ok(Flow::ReadProfile) => self.lathe_cycle(exec, sink).map(|()| Flow::Continue),
                other => other,
            };
            match result {
                Ok(Flow::ReadProfile) => unreachable!("the profile was read above"),
                Ok(Flow::End) => {
                    self.ended = true;
                    break;
                }
                Ok(Flow::Continue) => {}
                Err(d) => {
                    let is_error = d.severity == crate::diag::Severity::Error;
                    self.report(d);
                    if is_error && !self.continue_after_error {
                        return self.diagnostics;
                    }
                    if self.diagnostics.len() > self.limit {
                        return self.diagnostics;
                    }
                }
            }
        }
        if !self.ended {
            let unterminated = match exec.end() {
                Some(ProgramEnd::EndOfFile {
                    opened_with_percent,
                }) => Some(opened_with_percent),
                _ => None,
            };
            match unterminated {
                // LinuxCNC refuses a file that stops without M2/M30 or a closing `%`.
                Some(opened_with_percent) if self.interp.dialect == Dialect::LinuxCnc => {
                    let (message, help) = if opened_with_percent {
                        (
                            "File ended with no percent sign",
                            "a program that opens with % must close with a % line",
                        )
                    } else {
                        (
                            "File ended with no percent sign or program end",
                            "end the program with M2 or M30 (or wrap it in % lines)",
                        )
                    };
                    self.report(
                        Diagnostic::error(Span::line(self.last_line), message).with_help(help),
                    );
                }
                // grbl and the legacy dialect run a file to its end.
                _ => self.interp.finish(sink),
            }
        }
        self.diagnostics
    }
}

/// Run a program read from `source`; operations go to `sink` as they are made.
pub fn run(
    source: impl BufRead + Seek,
    opts: &RunOptions,
    sink: &mut dyn FnMut(Canon),
) -> Vec<Diagnostic> {
    let mut exec = Executor::new(source, opts.dialect);
    exec.set_block_delete(opts.block_delete);
    exec.set_fanuc_subs(!opts.disable_fanuc_subs);
    exec.set_subroutine_path(opts.subroutine_path.clone());
    if opts.max_line_len > 0 {
        exec.set_max_line_len(opts.max_line_len);
    }
    Driver::new(opts, sink).run(&mut exec, sink)
}

/// [`run`] over a string.
pub fn run_text(text: &str, opts: &RunOptions, sink: &mut dyn FnMut(Canon)) -> Vec<Diagnostic> {
    run(Cursor::new(text.as_bytes()), opts, sink)
}

/// Run `text` and collect the operations (tests and small programs only).
pub fn canon_of(text: &str, opts: &RunOptions) -> (Vec<Canon>, Vec<Diagnostic>) {
    let mut ops = Vec::new();
    let diags = run_text(text, opts, &mut |c| ops.push(c));
    (ops, diags)
}

#[cfg(test)]
mod tests {
    use super::*;
    use oficina_canon::CanonOp;

    /// X of every straight move, in order.
    fn xs(text: &str) -> Vec<f64> {
        let (ops, diags) = canon_of(text, &RunOptions::default());
        assert!(diags.is_empty(), "{diags:?}");
        ops.iter()
            .filter_map(|c| match &c.op {
                CanonOp::StraightFeed { to } | CanonOp::StraightTraverse { to } => Some(to.x),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn errors_inside_a_stretch_of_usual_lines_name_their_line() {
        // Every line here is a fast path's: the lines read in one stretch still say which
        // line erred, check mode goes on after it, and the missing end names the last line.
        let text = "G21 G90 G1 F100\nG1 X1\nG2 X2 Y0 I0 J0\nG1 X3\nG1 X[2 + 2]\n";
        let (ops, diags) = canon_of(text, &RunOptions::check(Dialect::LinuxCnc));
        let lines: Vec<u32> = diags.iter().map(|d| d.span.line).collect();
        assert_eq!(lines, vec![3, 5], "{diags:?}");
        assert!(diags[1].message.contains("no percent sign"), "{diags:?}");
        let feeds = ops
            .iter()
            .filter(|c| matches!(c.op, CanonOp::StraightFeed { .. }))
            .count();
        // The first line's G1 without axis words is a feed of length zero, as in rs274.
        assert_eq!(feeds, 4);
    }

    #[test]
    fn system_parameters_are_current_wherever_they_are_read() {
        // Refreshed lazily, before each line that names one: after the block before it,
        // inside o-word conditions, with blanks in the name, and in a line of its own.
        let text = "G21 G90 G1 X5 F100\n\
                    #1 = #<_x>\n\
                    G1 X7\n\
                    o100 if [#< _x > GT 6]\n\
                    #2 = 3\n\
                    o100 endif\n\
                    G0 X#1\n\
                    G1 X[#2 + #<_X>]\n\
                    G91 G1 X1\n\
                    G90 G1 X[#<_incremental> * 100 + #<_absolute>]\n\
                    M2\n";
        // The last line reads the values from before it: still G91.
        assert_eq!(xs(text), vec![5.0, 7.0, 5.0, 8.0, 9.0, 100.0]);
    }
}
