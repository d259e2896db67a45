//! O-word control flow of the executor: subroutine definitions, calls and returns, `if`
//! chains and loops, and the skipping of lines that goes with them (LinuxCNC seeks in the
//! file; so do we).

use super::flow::{Arrival, CallFrame, Ctl, LoopKind, Mark, Skip, SubDef};
use super::source::Read;
use super::{Executor, ProgramEnd, MAX_OPEN_BLOCKS, MAX_SUBS};
use crate::ast::{Keyword, OWord};
use crate::diag::{Diagnostic, Span};
use crate::expr::eval;
use crate::lex::Compact;
use crate::params::Params;
use crate::parse::{bare_oword, oword_head};
use std::io::{BufRead, Seek};

impl<R: BufRead + Seek> Executor<R> {
    /// One line while skipping: `Ok(true)` when this line ends the skip and must be run.
    pub(super) fn skip_step(&mut self) -> Result<bool, Diagnostic> {
        let Some(skip) = &self.skip else {
            return Ok(true);
        };
        let Some((label, keyword)) = oword_head(&self.compact) else {
            return Ok(false);
        };
        if skip.in_definition && keyword == Keyword::Sub {
            let from = skip.from_line;
            return Err(Diagnostic::error(
                self.compact.span(0, self.compact.bytes.len()),
                format!(
                    "subroutine {} defined inside the definition started at line {from}",
                    OWord::display_label(&label)
                ),
            )
            .with_help("subroutine definitions cannot be nested"));
        }
        if matches!(keyword, Keyword::Break | Keyword::Continue) {
            // LinuxCNC looks at a break/continue of the construct being skipped and rejects it
            // unless that construct is a while or do loop (it also re-reads a finished
            // repeat's body, see `next_repetition`, and keeps a repeat's count across calls):
            // a break/continue of a repeat loop is reported as soon as it is read.
            let base = self.ctl_base();
            let in_open_repeat = self.ctl[base.min(self.ctl.len())..].iter().any(|c| {
                matches!(c, Ctl::Loop { label: l, kind: LoopKind::Repeat { .. }, .. } if *l == label)
            });
            let construct = if in_open_repeat {
                Some("repeat")
            } else if label != skip.label {
                None
            } else {
                match skip.until.last() {
                    Some(Keyword::EndWhile | Keyword::While) => None,
                    Some(Keyword::EndRepeat) => Some("repeat"),
                    Some(Keyword::EndSub) => Some("sub"),
                    _ => Some("if"),
                }
            };
            if let Some(construct) = construct {
                let name = OWord::display_label(&label);
                return Err(Diagnostic::error(
                    self.compact.span(0, self.compact.bytes.len()),
                    format!("{name} {} inside {name} {construct}", keyword.name()),
                )
                .with_help("LinuxCNC allows break and continue only in while and do loops"));
            }
        }
        if label != skip.label || !skip.until.contains(&keyword) {
            return Ok(false);
        }
        let arrival = skip.arrival;
        self.skip = None;
        Ok(arrival == Arrival::Run)
    }

    pub(super) fn start_skip(
        &mut self,
        label: &str,
        until: &'static [Keyword],
        arrival: Arrival,
        in_definition: bool,
    ) {
        self.skip = Some(Skip {
            label: label.to_string(),
            until,
            arrival,
            in_definition,
            from_line: self.line.line,
        });
    }

    /// A false `if`/`elseif` condition: skip to the block's next `elseif`, `else` or `endif`.
    fn skip_to_next_branch(&mut self, label: &str) {
        self.start_skip(
            label,
            &[Keyword::ElseIf, Keyword::Else, Keyword::EndIf],
            Arrival::Run,
            false,
        );
    }

    pub(super) fn seek(&mut self, to: Mark) -> Result<(), Diagnostic> {
        self.src.seek(to.offset, to.line).map_err(|e| {
            self.end = Some(ProgramEnd::EndOfFile {
                opened_with_percent: self.opened_with_percent,
            });
            Diagnostic::error(
                Span::line(self.line.line),
                format!("cannot seek in the program: {e}"),
            )
            .with_help("loops and subroutine calls need a file or in-memory text, not a pipe")
        })
    }

    /// Where the line after the current one starts.
    pub(super) fn next_mark(&self) -> Mark {
        let (offset, line) = self.src.position();
        Mark { offset, line }
    }

    /// The start of the current line (for `while`, which is re-evaluated each iteration).
    pub(super) fn this_mark(&self) -> Mark {
        self.current
    }

    pub(super) fn eval_arg(&self, o: &OWord, params: &Params) -> Result<f64, Diagnostic> {
        match o.args.first() {
            Some(e) => eval(e, params),
            None => Ok(0.0),
        }
    }

    pub(super) fn err(&self, o: &OWord, message: String) -> Diagnostic {
        Diagnostic::error(o.span, message)
    }

    /// Index of the innermost open construct of this call level, if any.
    pub(super) fn ctl_base(&self) -> usize {
        self.calls.last().map_or(0, |c| c.ctl_base)
    }

    pub(super) fn top_matches(&self, label: &str) -> Option<&Ctl> {
        if self.ctl.len() > self.ctl_base() {
            self.ctl.last().filter(|c| c.label() == label)
        } else {
            None
        }
    }

    pub(super) fn run_oword(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
        let name = OWord::display_label(&o.label);
        let opens = matches!(
            o.keyword,
            Keyword::If | Keyword::Do | Keyword::While | Keyword::Repeat
        );
        if opens && self.ctl.len() >= MAX_OPEN_BLOCKS {
            return Err(self
                .err(
                    o,
                    format!("more than {MAX_OPEN_BLOCKS} if/loop blocks open at once"),
                )
                .with_help("close blocks with endif/endwhile/endrepeat"));
        }
        match o.keyword {
            Keyword::Sub => self.define_sub(o),
            Keyword::EndSub | Keyword::Return => self.return_from(o, params),
            Keyword::Call => self.call(o, params),
            Keyword::If => {
                let cond = self.eval_arg(o, params)? != 0.0;
                self.ctl.push(Ctl::If {
                    label: o.label.clone(),
                    taken: cond,
                    line: self.line.line,
                });
                if !cond {
                    self.skip_to_next_branch(&o.label);
                }
                Ok(())
            }
            Keyword::ElseIf | Keyword::Else => {
                let taken = match self.top_matches(&o.label) {
                    Some(Ctl::If { taken, .. }) => *taken,
                    _ => {
                        return Err(self
                            .err(o, format!("{name} {} without {name} if", o.keyword.name()))
                            .with_help(format!("open the block with {name} if [condition]")))
                    }
                };
                if taken {
                    self.start_skip(&o.label, &[Keyword::EndIf], Arrival::Run, false);
                    return Ok(());
                }
                let cond = o.keyword == Keyword::Else || self.eval_arg(o, params)? != 0.0;
                if cond {
                    if let Some(Ctl::If { taken, .. }) = self.ctl.last_mut() {
                        *taken = true;
                    }
                } else {
                    self.skip_to_next_branch(&o.label);
                }
                Ok(())
            }
            Keyword::EndIf => match self.top_matches(&o.label) {
                Some(Ctl::If { .. }) => {
                    self.ctl.pop();
                    Ok(())
                }
                _ => Err(self.err(o, format!("{name} endif without {name} if"))),
            },
            Keyword::Do => {
                let line = self.line.line;
                self.ctl.push(Ctl::Loop {
                    label: o.label.clone(),
                    kind: LoopKind::Do,
                    mark: self.next_mark(),
                    line,
                    iterations: 0,
                });
                Ok(())
            }
            Keyword::While => self.run_while(o, params),
            Keyword::EndWhile => match self.top_matches(&o.label) {
                Some(Ctl::Loop {
                    kind: LoopKind::While,
                    mark,
                    ..
                }) => {
                    let mark = *mark;
                    self.iterate(o)?;
                    self.seek(mark)
                }
                _ => Err(self.err(o, format!("{name} endwhile without {name} while"))),
            },
            Keyword::Repeat => {
                let count = self.eval_arg(o, params)?.round();
                if count < 1.0 {
                    self.start_skip(&o.label, &[Keyword::EndRepeat], Arrival::Consume, false);
                    return Ok(());
                }
                let line = self.line.line;
                self.ctl.push(Ctl::Loop {
                    label: o.label.clone(),
                    kind: LoopKind::Repeat {
                        remaining: count.min(u64::MAX as f64) as u64,
                    },
                    mark: self.next_mark(),
                    line,
                    iterations: 0,
                });
                Ok(())
            }
            Keyword::EndRepeat => match self.top_matches(&o.label) {
                Some(Ctl::Loop {
                    kind: LoopKind::Repeat { .. },
                    ..
                }) => self.next_repetition(o),
                _ => Err(self.err(o, format!("{name} endrepeat without {name} repeat"))),
            },
            Keyword::Break | Keyword::Continue => self.break_or_continue(o),
        }
    }

    fn define_sub(&mut self, o: &OWord) -> Result<(), Diagnostic> {
        let name = OWord::display_label(&o.label);
        let line = self.line.line;
        // rs274 2.9 takes a `sub` line met while a subroutine runs as part of the call
        // (convert_control_functions, O_sub at call_level != 0): it goes on into the body,
        // whose endsub returns from the running call. LinuxCNC 2.10 refuses it.
        if !self.calls.is_empty() {
            return Ok(());
        }
        // The body is skipped: never run a definition as main-line code.
        self.start_skip(&o.label, &[Keyword::EndSub], Arrival::Consume, true);
        match self.subs.get(&o.label) {
            Some(def) if def.line != line => Err(self
                .err(o, format!("subroutine {name} is defined twice (first at line {})", def.line))
                .with_help("rename one of them")),
            Some(def) if def.found_by_search => Err(self
                .err(o, format!("definition of {name} reached after a call made before it was defined"))
                .with_help("LinuxCNC rejects this: define subroutines before their first call, or after M2/M30")),
            Some(_) => Ok(()),
            None => {
                if self.subs.len() >= MAX_SUBS {
                    return Err(self.err(o, format!("more than {MAX_SUBS} subroutine definitions")));
                }
                let body = self.next_mark();
                self.subs.insert(o.label.clone(), SubDef { body, line, found_by_search: false, fanuc: false });
                Ok(())
            }
        }
    }

    pub(super) fn call(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
        let name = OWord::display_label(&o.label);
        let mut args = [0.0; crate::params::CALL_ARGS];
        for (slot, e) in args.iter_mut().zip(&o.args) {
            *slot = eval(e, params)?;
        }
        if self.calls.len() >= self.limits.max_call_depth {
            return Err(self
                .err(
                    o,
                    format!(
                        "too many nested subroutine calls: more than {}",
                        self.limits.max_call_depth
                    ),
                )
                .with_help(
                    "is the recursion missing its end condition? (LinuxCNC allows 9 nested calls)",
                ));
        }
        self.count_jump(o.span)?;
        let resume = self.next_mark();
        let file_depth = self.src.depth();
        // Definitions are remembered for the main program only (their marks are offsets in
        // it): a subroutine file calls them by going back to the main program.
        let def = match self.subs.get(&o.label).copied() {
            Some(def) => {
                if !self.src.in_main() {
                    self.src.enter_main();
                }
                def
            }
            None => match self.search_sub(&o.label, o.span, false) {
                Ok(def) => def,
                Err(e) => match self.open_sub_file(&o.label, o.span)? {
                    Some(def) => def,
                    None => return Err(e),
                },
            },
        };
        if def.fanuc {
            self.src.close_to(file_depth);
            return Err(self
                .err(
                    o,
                    format!("{name} is a Fanuc-style subprogram (O{} … M99)", o.label),
                )
                .with_help(format!("call it with M98 P{}", o.label)));
        }
        self.calls.push(CallFrame {
            label: o.label.clone(),
            resume,
            ctl_base: self.ctl.len(),
            call_line: self.line.line,
            fanuc: None,
            file_depth,
        });
        params.push_call(&args[..o.args.len()]);
        if let Err(e) = self.seek(def.body) {
            return Err(e.with_help(format!("while calling {name}")));
        }
        Ok(())
    }

    /// Look ahead for the definition of a subroutine called before it was defined: an
    /// `oN sub` line or a Fanuc-style bare `ON` line with this label (the caller checks that
    /// the kind found is the kind it calls).
    pub(super) fn search_sub(
        &mut self,
        wanted: &str,
        span: Span,
        fanuc_call: bool,
    ) -> Result<SubDef, Diagnostic> {
        let name = OWord::display_label(wanted);
        let back = self.next_mark();
        let mut scratch = Compact::new();
        let found = loop {
            match self.src.read() {
                Ok(Read::Line { number, .. }) => {
                    if scratch.load(self.src.text(), number).is_err() {
                        continue;
                    }
                    // A program opened with % ends at the next %: rs274 does not look past
                    // it ("Failed to find sub … before EOF").
                    if self.opened_with_percent
                        && self.src.in_main()
                        && scratch.bytes.as_slice() == b"%"
                    {
                        break None;
                    }
                    let fanuc = match oword_head(&scratch) {
                        Some((label, Keyword::Sub)) if label == wanted => false,
                        Some(_) => continue,
                        None if bare_oword(&scratch).as_deref() == Some(wanted) => true,
                        None => continue,
                    };
                    break Some(SubDef {
                        body: self.next_mark(),
                        line: number,
                        found_by_search: true,
                        fanuc,
                    });
                }
                Ok(Read::TooLong { .. }) => continue,
                Ok(Read::Eof) | Err(_) => break None,
            }
        };
        self.seek(back)?;
        match found {
            Some(def) if !self.src.in_main() => Ok(def),
            Some(def) => {
                if self.subs.len() >= MAX_SUBS {
                    return Err(Diagnostic::error(
                        span,
                        format!("more than {MAX_SUBS} subroutine definitions"),
                    ));
                }
                self.subs.insert(wanted.to_string(), def);
                Ok(def)
            }
            None if fanuc_call => Err(Diagnostic::error(
                span,
                format!("subprogram O{wanted} is not in this file after the call"),
            )
            .with_help(format!(
                "LinuxCNC looks for a line O{wanted} below the M98 (put subprograms after M2/M30)"
            ))),
            None => Err(
                Diagnostic::error(span, format!("subroutine {name} is not defined")).with_help(
                    format!("define it in this file: {name} sub … {name} endsub"),
                ),
            ),
        }
    }

    /// Count a call (or a repetition of one) against the limit on jumps in the run.
    pub(super) fn count_jump(&mut self, span: Span) -> Result<(), Diagnostic> {
        self.total_jumps += 1;
        if self.total_jumps > self.limits.max_total_jumps {
            return Err(Diagnostic::error(
                span,
                format!(
                    "more than {} loop iterations and calls in this run",
                    self.limits.max_total_jumps
                ),
            )
            .with_help("does every loop and recursion reach its end condition?"));
        }
        Ok(())
    }

    /// `name.ngc` from the subroutine path, opened and positioned at its `o<name> sub`, for
    /// a call of a subroutine this file does not define; `None` when no directory has it.
    fn open_sub_file(&mut self, label: &str, span: Span) -> Result<Option<SubDef>, Diagnostic> {
        // A number is not a file name; a name with a path in it must not reach outside the
        // search path.
        if label.bytes().all(|b| b.is_ascii_digit())
            || label.contains(['/', '\\'])
            || label.starts_with('.')
        {
            return Ok(None);
        }
        let name = OWord::display_label(label);
        let depth = self.src.depth();
        for dir in &self.subroutine_path {
            let path = dir.join(format!("{label}.ngc"));
            let Ok(file) = std::fs::File::open(&path) else {
                continue;
            };
            self.src.open(file);
            return match self.search_sub(label, span, false) {
                Ok(def) => Ok(Some(def)),
                Err(_) => {
                    self.src.close_to(depth);
                    Err(Diagnostic::error(
                        span,
                        format!("{} does not define {name} sub", path.display()),
                    )
                    .with_help(format!("the file must hold {name} sub … {name} endsub")))
                }
            };
        }
        Ok(None)
    }

    fn return_from(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
        let name = OWord::display_label(&o.label);
        // rs274 2.9 returns from the running subroutine whatever the label: `o1010 return`
        // inside `o1010 if` of `o1000 sub` returns from o1000 (execute_return on the frame).
        if self.calls.is_empty() {
            return Err(self
                .err(
                    o,
                    format!("{name} {} outside a subroutine", o.keyword.name()),
                )
                .with_help(format!(
                    "{name} {} belongs between {name} sub and {name} endsub",
                    o.keyword.name()
                )));
        }
        let value = match o.args.first() {
            Some(e) => Some(eval(e, params)?),
            None => None,
        };
        let Some(frame) = self.calls.pop() else {
            return Ok(());
        };
        self.ctl.truncate(frame.ctl_base);
        params.pop_call();
        params.set_system("_value", value.unwrap_or(0.0));
        params.set_system("_value_returned", if value.is_some() { 1.0 } else { 0.0 });
        self.src.close_to(frame.file_depth);
        self.seek(frame.resume)
    }

    fn run_while(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
        let this = self.this_mark();
        match self.top_matches(&o.label) {
            // The end of a do … while loop.
            Some(Ctl::Loop {
                kind: LoopKind::Do,
                mark,
                ..
            }) => {
                let mark = *mark;
                if self.eval_arg(o, params)? != 0.0 {
                    self.iterate(o)?;
                    self.seek(mark)
                } else {
                    self.ctl.pop();
                    Ok(())
                }
            }
            // Back at the top of a running while loop.
            Some(Ctl::Loop {
                kind: LoopKind::While,
                mark,
                ..
            }) if *mark == this => {
                if self.eval_arg(o, params)? == 0.0 {
                    self.ctl.pop();
                    self.start_skip(&o.label, &[Keyword::EndWhile], Arrival::Consume, false);
                }
                Ok(())
            }
            _ => {
                if self.eval_arg(o, params)? == 0.0 {
                    self.start_skip(&o.label, &[Keyword::EndWhile], Arrival::Consume, false);
                } else {
                    let line = self.line.line;
                    self.ctl.push(Ctl::Loop {
                        label: o.label.clone(),
                        kind: LoopKind::While,
                        mark: this,
                        line,
                        iterations: 0,
                    });
                }
                Ok(())
            }
        }
    }

    fn next_repetition(&mut self, o: &OWord) -> Result<(), Diagnostic> {
        let Some(Ctl::Loop {
            kind: LoopKind::Repeat { remaining },
            mark,
            ..
        }) = self.ctl.last_mut()
        else {
            return Ok(());
        };
        *remaining = remaining.saturating_sub(1);
        if *remaining == 0 {
            // Like LinuxCNC, go back once more and skip the body to the endrepeat: a
            // break/continue of this loop inside it is then reported (see `skip_step`).
            let mark = *mark;
            self.ctl.pop();
            self.seek(mark)?;
            self.start_skip(&o.label, &[Keyword::EndRepeat], Arrival::Consume, false);
            return Ok(());
        }
        let mark = *mark;
        self.iterate(o)?;
        self.seek(mark)
    }

    /// Count one more iteration of the innermost loop; past a limit, leave the loop with
    /// an error (the program goes on after it).
    fn iterate(&mut self, o: &OWord) -> Result<(), Diagnostic> {
        self.idle_iterations += 1;
        self.total_jumps += 1;
        let Some(Ctl::Loop { iterations, .. }) = self.ctl.last_mut() else {
            return Ok(());
        };
        *iterations += 1;
        let iterations = *iterations;
        let name = OWord::display_label(&o.label);
        let message = if iterations > self.limits.max_loop_iterations {
            format!(
                "loop {name} ran more than {} times",
                self.limits.max_loop_iterations
            )
        } else if self.total_jumps > self.limits.max_total_jumps {
            format!(
                "more than {} loop iterations and calls in this run",
                self.limits.max_total_jumps
            )
        } else if self.idle_iterations > self.limits.max_idle_iterations {
            format!(
                "loop {name} ran {} times without producing a block",
                self.idle_iterations
            )
        } else {
            return Ok(());
        };
        self.idle_iterations = 0;
        let Some(open) = self.ctl.pop() else {
            return Ok(());
        };
        let closer: &'static [Keyword] = match open.closer() {
            Keyword::EndWhile => &[Keyword::EndWhile],
            Keyword::EndRepeat => &[Keyword::EndRepeat],
            _ => &[Keyword::While],
        };
        // The closing line itself triggered this: the loop is left right after it, except a
        // while loop, whose closing line is below.
        if o.keyword == Keyword::EndWhile {
            // Already past the endwhile: nothing to skip.
        } else if !closer.contains(&o.keyword) {
            self.start_skip(&o.label, closer, Arrival::Consume, false);
        }
        Err(self
            .err(o, message)
            .with_help("is the loop condition ever false?"))
    }

    fn break_or_continue(&mut self, o: &OWord) -> Result<(), Diagnostic> {
        let name = OWord::display_label(&o.label);
        let base = self.ctl_base();
        let Some(index) = (base..self.ctl.len())
            .rev()
            .find(|&i| matches!(&self.ctl[i], Ctl::Loop { label, .. } if *label == o.label))
        else {
            return Err(self
                .err(
                    o,
                    format!("{name} {} outside a loop labelled {name}", o.keyword.name()),
                )
                .with_help(format!(
                    "{name} {} must be inside {name} while or {name} do",
                    o.keyword.name()
                )));
        };
        if matches!(
            &self.ctl[index],
            Ctl::Loop {
                kind: LoopKind::Repeat { .. },
                ..
            }
        ) {
            // LinuxCNC: "no matching while/do label".
            return Err(self
                .err(
                    o,
                    format!("{name} {} inside {name} repeat", o.keyword.name()),
                )
                .with_help("LinuxCNC allows break and continue only in while and do loops"));
        }
        self.ctl.truncate(index + 1);
        let Some(Ctl::Loop { kind, mark, .. }) = self.ctl.last() else {
            return Ok(());
        };
        let (kind, mark) = (kind.clone(), *mark);
        if o.keyword == Keyword::Break {
            self.ctl.pop();
            let until: &'static [Keyword] = match kind {
                LoopKind::While => &[Keyword::EndWhile],
                LoopKind::Do => &[Keyword::While],
                LoopKind::Repeat { .. } => &[Keyword::EndRepeat],
            };
            self.start_skip(&o.label, until, Arrival::Consume, false);
            return Ok(());
        }
        match kind {
            LoopKind::While => {
                self.iterate(o)?;
                self.seek(mark)
            }
            // Go on to the condition at the bottom.
            LoopKind::Do => {
                self.start_skip(&o.label, &[Keyword::While], Arrival::Run, false);
                Ok(())
            }
            LoopKind::Repeat { .. } => self.next_repetition(o),
        }
    }
}
