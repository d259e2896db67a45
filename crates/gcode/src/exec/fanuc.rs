//! Fanuc-style subprograms as LinuxCNC 2.9 reads them: `O100` opens a subprogram (a bare
//! o-word, no keyword), `M98 P100 L3` calls it three times, `M99` returns. Measured on
//! `rs274` (each case is a corpus program `tests/corpus/fanuc_*.ngc`):
//!
//! - a bare `O…` line met while running is a program number and does nothing, so a
//!   subprogram written before the main program runs as main-line code;
//! - `M98` looks for its `O…` line below the call only (like an `oN call` of an undefined
//!   subroutine) and shares the caller's parameters (no `#1`…`#30` frame);
//! - `M98` and `M99` stand alone on their line (besides N, P and L);
//! - `M99` in the main program ends it exactly as `M2` does. On a machine LinuxCNC's task
//!   then starts the program again, forever; `rs274` (and Oficina) run it once, which is the
//!   bound on an "endless" M99 program;
//! - with Fanuc-style subprograms disabled (LinuxCNC's `DISABLE_FANUC_STYLE_SUB`), a bare
//!   o-word and `M98` are errors with rs274's messages; `M99` in the main program still ends it.

use super::flow::{CallFrame, FanucRuns};
use super::Executor;
use crate::block::Block;
use crate::diag::{Diagnostic, Span};
use std::io::{BufRead, Seek};

/// Whether an M word's value is M98 or M99. The fast paths decline such lines, so that only
/// the full path's blocks need [`Executor::fanuc_block`]'s look at every word.
#[inline(always)]
pub(super) fn is_call_or_return(m: f64) -> bool {
    m == 98.0 || m == 99.0
}

impl<R: BufRead + Seek> Executor<R> {
    /// Run the M98 or M99 of `block`, if it has one: `Ok(true)` when the block was a call
    /// or a return and is used up. `M99` in the main program becomes `M2`.
    #[inline(always)]
    pub(super) fn fanuc_block(&mut self, block: &mut Block) -> Result<bool, Diagnostic> {
        // Every block of the full path passes here: the test is one pass over its few
        // words, the work is out of line.
        match block
            .words
            .iter()
            .position(|w| w.letter == 'M' && is_call_or_return(w.value))
        {
            None => Ok(false),
            Some(m) => self.m98_or_m99(block, m),
        }
    }

    #[inline(never)]
    fn m98_or_m99(&mut self, block: &mut Block, m: usize) -> Result<bool, Diagnostic> {
        if block.words[m].value == 98.0 {
            self.m98(block, block.words[m].span)?;
            Ok(true)
        } else {
            self.m99(block, m)
        }
    }

    fn m98(&mut self, block: &Block, span: Span) -> Result<(), Diagnostic> {
        if !self.fanuc_subs {
            return Err(Diagnostic::error(
                span,
                "DISABLE_FANUC_STYLE_SUB set in INI file, but found m98",
            )
            .with_help("Fanuc-style subprograms are disabled; use o<name> call"));
        }
        let mut p = None;
        let mut l = 1.0;
        for w in &block.words {
            match w.letter {
                'P' => p = Some(w),
                'L' => l = w.value,
                'M' if w.value == 98.0 => {}
                _ => {
                    return Err(Diagnostic::error(span, "Unknown m code used: M98")
                        .with_help("LinuxCNC reads M98 only on a line of its own: M98 P… L…"))
                }
            }
        }
        let Some(p) = p else {
            return Err(Diagnostic::error(span, "Found 'm98' code with no P-word")
                .with_help("M98 P100 calls the subprogram that starts with the line O100"));
        };
        for w in [Some(p.value), Some(l)].into_iter().flatten() {
            if w.fract() != 0.0 || !w.is_finite() {
                return Err(Diagnostic::error(span, "Non integer value for integer")
                    .with_help("P (the subprogram number) and L (the count) are integers"));
            }
        }
        if l < 1.0 {
            return Ok(());
        }
        let label = format!("{}", p.value as i64);
        if self.calls.len() >= self.limits.max_call_depth {
            return Err(
                Diagnostic::error(span, "Too many subroutine levels").with_help(format!(
                    "more than {} nested calls: is the recursion missing its end?",
                    self.limits.max_call_depth
                )),
            );
        }
        self.count_jump(span)?;
        let resume = self.next_mark();
        let file_depth = self.src.depth();
        let def = match self.subs.get(&label) {
            Some(def) => {
                if !self.src.in_main() {
                    self.src.enter_main();
                }
                *def
            }
            None => self.search_sub(&label, span, true)?,
        };
        if !def.fanuc {
            self.src.close_to(file_depth);
            return Err(Diagnostic::error(
                span,
                "'O.... sub' subroutine must be called with 'O.... call'",
            )
            .with_help(format!("call it with o{label} call")));
        }
        self.calls.push(CallFrame {
            label,
            resume,
            ctl_base: self.ctl.len(),
            call_line: block.line,
            file_depth,
            fanuc: Some(FanucRuns {
                body: def.body,
                remaining: l.min(u64::MAX as f64) as u64,
            }),
        });
        self.seek(def.body)
    }

    fn m99(&mut self, block: &mut Block, m: usize) -> Result<bool, Diagnostic> {
        let span = block.words[m].span;
        let Some(frame) = self.calls.last_mut() else {
            block.words[m].value = 2.0;
            return Ok(false);
        };
        let Some(runs) = &mut frame.fanuc else {
            return Err(Diagnostic::error(span, "M99 inside an o-word subroutine")
                .with_help("end an o<name> sub with o<name> endsub or o<name> return"));
        };
        if block.words.len() > 1 || !block.assignments.is_empty() {
            return Err(Diagnostic::error(
                span,
                "Bug:  Reached convert_stop() from M99 as subprogram return",
            )
            .with_help(
                "rs274's words: LinuxCNC reads M99 in a subprogram only on a line of its own",
            ));
        }
        runs.remaining = runs.remaining.saturating_sub(1);
        if runs.remaining > 0 {
            let body = runs.body;
            self.count_jump(span)?;
            self.seek(body)?;
            return Ok(true);
        }
        if let Some(frame) = self.calls.pop() {
            self.ctl.truncate(frame.ctl_base);
            self.src.close_to(frame.file_depth);
            self.seek(frame.resume)?;
        }
        Ok(true)
    }
}
