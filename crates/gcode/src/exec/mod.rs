//! The streaming executor: reads lines one at a time, runs O-word control flow (sub/call/
//! return, if/elseif/else, while, do/while, repeat, break/continue) by seeking in the
//! source as LinuxCNC does, evaluates every expression and yields [`Block`]s with plain
//! values, in execution order.
//!
//! Memory stays bounded by the longest line (itself bounded), the nesting depth and the
//! number of subroutine definitions: a program is never loaded whole.
//!
//! After an error the next call goes on with the next line, so a checker can report many
//! errors in one run.
//!
//! Where LinuxCNC 2.9's `rs274` is inconsistent we follow its documentation instead (each
//! case is a test in `tests/frontend_exec.rs`): a `break` leaves no stale state behind for a
//! later do-while; a `continue` does not obey a `break` it skips over; loops inside a
//! skipped branch do not restart an enclosing repeat. A break/continue of a repeat loop,
//! which LinuxCNC rejects whenever its skipping reads it, is reported as soon as it is read.
//! A call to an undefined subroutine is reported at the call, not at the end of the file.

mod direct;
mod flow;
mod plain;
mod source;

pub use flow::Limits;
pub use source::DEFAULT_MAX_LINE_LEN;

use crate::ast::{CommentKind, Item, Keyword, Line, OWord, Target};
use crate::block::{Assignment, Block, Note, ParamRef, Word};
use crate::diag::{Diagnostic, Span};
use crate::expr::{eval, param_error, param_number};
use crate::lex::Compact;
use crate::params::Params;
use crate::parse::{oword_head, parse_line};
use crate::Dialect;
use flow::{Arrival, CallFrame, Ctl, LoopKind, Mark, Skip, SubDef};
use source::{LineSource, Read};
use std::collections::HashMap;
use std::io::{BufRead, Cursor, Seek};

/// How the program ended, once [`Executor::next_block`] has returned `None`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgramEnd {
    /// The closing `%` of a program that opened with `%`.
    Percent,
    /// The end of the file. LinuxCNC reports an error here unless M2/M30 came first (the
    /// interpreter knows; the executor does not look at M words).
    EndOfFile { opened_with_percent: bool },
}

/// Most subroutine definitions remembered: a bound on memory for hostile input.
const MAX_SUBS: usize = 100_000;
/// Most `if`s and loops open at once (a million `o1 if [1]` lines must not grow memory).
const MAX_OPEN_BLOCKS: usize = 1_000;

pub struct Executor<R> {
    src: LineSource<R>,
    dialect: Dialect,
    block_delete: bool,
    limits: Limits,
    compact: Compact,
    line: Line,
    subs: HashMap<String, SubDef>,
    ctl: Vec<Ctl>,
    calls: Vec<CallFrame>,
    skip: Option<Skip>,
    /// Loop jumps since the last yielded block.
    idle_iterations: u64,
    /// Loop jumps and calls since the start.
    total_jumps: u64,
    started: bool,
    seen_content: bool,
    opened_with_percent: bool,
    end: Option<ProgramEnd>,
    /// Assignments of the current line, before they are applied (reused buffer).
    pending: Vec<(ParamRef, f64, Span)>,
    /// Buffers of the one-pass fast path.
    scratch: direct::Scratch,
    /// The last line taken by a fast path was plain: try the plain path first.
    plain_lines: bool,
    /// Plain lines the direct path has taken in a row since the plain path last failed.
    plain_run: u8,
    /// Start of the line being run.
    current: Mark,
}

impl Executor<Cursor<Vec<u8>>> {
    /// An executor over program text held in memory.
    pub fn from_text(text: &str, dialect: Dialect) -> Self {
        Executor::new(Cursor::new(text.as_bytes().to_vec()), dialect)
    }
}

impl<R: BufRead + Seek> Executor<R> {
    pub fn new(reader: R, dialect: Dialect) -> Self {
        Executor {
            src: LineSource::new(reader),
            dialect,
            block_delete: false,
            limits: Limits::default(),
            compact: Compact::new(),
            line: Line::default(),
            subs: HashMap::new(),
            ctl: Vec::new(),
            calls: Vec::new(),
            skip: None,
            idle_iterations: 0,
            total_jumps: 0,
            started: false,
            seen_content: false,
            opened_with_percent: false,
            end: None,
            pending: Vec::new(),
            scratch: direct::Scratch::default(),
            plain_lines: true,
            plain_run: 0,
            current: Mark { offset: 0, line: 0 },
        }
    }

    /// Skip lines that start with `/` (the block delete switch is on).
    pub fn honour_block_delete(&mut self, on: bool) {
        self.block_delete = on;
    }

    /// Same as [`Executor::honour_block_delete`].
    pub fn set_block_delete(&mut self, on: bool) {
        self.honour_block_delete(on);
    }

    /// Longest line accepted, in bytes (default [`DEFAULT_MAX_LINE_LEN`]); longer lines
    /// are errors and are never held in memory.
    pub fn set_max_line_len(&mut self, bytes: usize) {
        self.src.set_max_len(bytes);
    }

    pub fn set_limits(&mut self, limits: Limits) {
        self.limits = limits;
    }

    pub fn limits(&self) -> Limits {
        self.limits
    }

    pub fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// How the program ended (after `next_block` returned `None`).
    pub fn end(&self) -> Option<ProgramEnd> {
        self.end
    }

    /// Depth of subroutine calls in progress.
    pub fn call_depth(&self) -> usize {
        self.calls.len()
    }

    /// The next block in execution order, `None` at the end of the program.
    pub fn next_block(&mut self, params: &mut Params) -> Option<Result<Block, Diagnostic>> {
        let mut block = Block::default();
        match self.read_block(params, &mut block) {
            Ok(true) => Some(Ok(block)),
            Ok(false) => None,
            Err(e) => Some(Err(e)),
        }
    }

    /// Like [`Executor::next_block`] but fills `block` (reusing its vectors): `Ok(false)`
    /// at the end of the program.
    pub fn read_block(
        &mut self,
        params: &mut Params,
        block: &mut Block,
    ) -> Result<bool, Diagnostic> {
        if !self.started {
            self.started = true;
            params.set_system("_value", 0.0);
            params.set_system("_value_returned", 0.0);
        }
        loop {
            if self.end.is_some() {
                return Ok(false);
            }
            let number = match self.src.read() {
                Ok(Read::Line { number, offset }) => {
                    self.current = Mark {
                        offset,
                        line: number,
                    };
                    number
                }
                // Skipped lines are not looked at, however long.
                Ok(Read::TooLong { .. }) if self.skip.is_some() => continue,
                Ok(Read::TooLong { number, len }) => {
                    return Err(Diagnostic::error(
                        Span::line(number),
                        format!("line {number} is {len} bytes long, more than the limit of {} bytes", self.src.max_len()),
                    )
                    .with_help("a G-code line is short; is this really a G-code file? (--max-line-kb raises the limit)"));
                }
                Ok(Read::Eof) => return self.at_end_of_file(),
                Err(e) => {
                    let (_, line) = self.src.position();
                    self.end = Some(ProgramEnd::EndOfFile {
                        opened_with_percent: self.opened_with_percent,
                    });
                    return Err(Diagnostic::error(
                        Span::line(line),
                        format!("cannot read the program: {e}"),
                    ));
                }
            };
            // grbl has its own letters and line limit: always the full path.
            if self.skip.is_none()
                && self.dialect != Dialect::Grbl
                && self.seen_content
                && self.fast_path(number, params, block)
            {
                self.idle_iterations = 0;
                return Ok(true);
            }
            let loaded = if self.dialect == Dialect::Grbl {
                self.compact.load_grbl(self.src.text(), number);
                Ok(())
            } else {
                self.compact.load(self.src.text(), number)
            };
            if let Err(e) = loaded {
                if self.skip.is_none() {
                    self.seen_content = true;
                    return Err(e);
                }
                continue;
            }
            if self.skip.is_some() {
                match self.skip_step()? {
                    true => {}
                    false => continue,
                }
            }
            if self.compact.is_empty() {
                continue;
            }
            if let Err(e) = parse_line(&self.compact, self.dialect, &mut self.line) {
                self.seen_content = true;
                return Err(e);
            }
            if self.line.percent {
                if !self.seen_content {
                    self.seen_content = true;
                    self.opened_with_percent = true;
                    continue;
                }
                if self.opened_with_percent {
                    self.end = Some(ProgramEnd::Percent);
                    return Ok(false);
                }
                return Err(Diagnostic::error(
                    self.compact.span(0, 1),
                    "'%' in the middle of a program",
                )
                .with_help(
                    "a '%' ends the program only when the first non-blank line was a '%' too",
                ));
            }
            self.seen_content = true;
            if self.line.block_delete && self.block_delete {
                continue;
            }
            if let Some(o) = self.line.oword.take() {
                let result = self.run_oword(&o, params);
                self.line.oword = Some(o);
                result?;
                continue;
            }
            if self.line.items.is_empty() && self.line.n.is_none() {
                continue;
            }
            self.fill_block(params, block)?;
            self.idle_iterations = 0;
            return Ok(true);
        }
    }

    /// The current line through one of the fast paths, if one takes it. Both give what the
    /// full path gives; the plain one is quicker but wasted on lines with expressions, so
    /// it goes first only while lines are plain.
    fn fast_path(&mut self, number: u32, params: &mut Params, block: &mut Block) -> bool {
        let text = self.src.text();
        let direct = |params: &mut Params, block: &mut Block, scratch: &mut direct::Scratch| {
            direct::direct_line(text, number, params, block, scratch)
        };
        if self.plain_lines {
            if plain::plain_line(text, number, block) {
                return true;
            }
            self.plain_lines = false;
            self.plain_run = 0;
            direct(params, block, &mut self.scratch)
        } else if direct(params, block, &mut self.scratch) {
            // Back to the plain path only after two plain lines in a row: a lone plain line
            // between lines with expressions would make the next line fail the plain path
            // first, wasting its reading.
            self.plain_run = if self.scratch.was_plain {
                self.plain_run.saturating_add(1)
            } else {
                0
            };
            self.plain_lines = self.plain_run >= 2;
            true
        } else {
            false
        }
    }

    fn at_end_of_file(&mut self) -> Result<bool, Diagnostic> {
        self.end = Some(ProgramEnd::EndOfFile {
            opened_with_percent: self.opened_with_percent,
        });
        let (_, line) = self.src.position();
        let here = Span::line(line.saturating_sub(1).max(1));
        if let Some(skip) = self.skip.take() {
            let label = OWord::display_label(&skip.label);
            let wanted: Vec<&str> = skip.until.iter().map(|k| k.name()).collect();
            return Err(Diagnostic::error(
                here,
                format!(
                    "end of file while looking for {label} {} (from line {})",
                    wanted.join("/"),
                    skip.from_line
                ),
            )
            .with_help(format!(
                "close the block with {label} {}",
                wanted.last().copied().unwrap_or("end")
            )));
        }
        if let Some(frame) = self.calls.last() {
            return Err(Diagnostic::error(
                here,
                format!(
                    "end of file inside subroutine {} called at line {}",
                    OWord::display_label(&frame.label),
                    frame.call_line
                ),
            )
            .with_help("end the subroutine with endsub"));
        }
        if let Some(open) = self.ctl.last() {
            let label = OWord::display_label(open.label());
            return Err(Diagnostic::error(
                here,
                format!(
                    "end of file inside {label} {} opened at line {}",
                    open.opener(),
                    open.line()
                ),
            )
            .with_help(format!("close it with {label} {}", open.closer().name())));
        }
        Ok(false)
    }

    /// One line while skipping: `Ok(true)` when this line ends the skip and must be run.
    fn skip_step(&mut self) -> Result<bool, Diagnostic> {
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

    fn start_skip(
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

    fn seek(&mut self, to: Mark) -> Result<(), Diagnostic> {
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
    fn next_mark(&self) -> Mark {
        let (offset, line) = self.src.position();
        Mark { offset, line }
    }

    /// The start of the current line (for `while`, which is re-evaluated each iteration).
    fn this_mark(&self) -> Mark {
        self.current
    }

    fn eval_arg(&self, o: &OWord, params: &Params) -> Result<f64, Diagnostic> {
        match o.args.first() {
            Some(e) => eval(e, params),
            None => Ok(0.0),
        }
    }

    fn err(&self, o: &OWord, message: String) -> Diagnostic {
        Diagnostic::error(o.span, message)
    }

    /// Index of the innermost open construct of this call level, if any.
    fn ctl_base(&self) -> usize {
        self.calls.last().map_or(0, |c| c.ctl_base)
    }

    fn top_matches(&self, label: &str) -> Option<&Ctl> {
        if self.ctl.len() > self.ctl_base() {
            self.ctl.last().filter(|c| c.label() == label)
        } else {
            None
        }
    }

    fn run_oword(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
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
                    self.start_skip(
                        &o.label,
                        &[Keyword::ElseIf, Keyword::Else, Keyword::EndIf],
                        Arrival::Run,
                        false,
                    );
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
                    self.start_skip(
                        &o.label,
                        &[Keyword::ElseIf, Keyword::Else, Keyword::EndIf],
                        Arrival::Run,
                        false,
                    );
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
        // The body is skipped in any case: never run a definition as main-line code.
        self.start_skip(&o.label, &[Keyword::EndSub], Arrival::Consume, true);
        if let Some(frame) = self.calls.last() {
            return Err(self
                .err(
                    o,
                    format!(
                        "subroutine {name} defined inside subroutine {} while it runs",
                        OWord::display_label(&frame.label)
                    ),
                )
                .with_help("subroutine definitions cannot be nested"));
        }
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
                self.subs.insert(o.label.clone(), SubDef { body, line, found_by_search: false });
                Ok(())
            }
        }
    }

    fn call(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
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
                    "is the recursion missing its end condition? (LinuxCNC allows 10 levels)",
                ));
        }
        self.total_jumps += 1;
        if self.total_jumps > self.limits.max_total_jumps {
            return Err(self
                .err(
                    o,
                    format!(
                        "more than {} loop iterations and calls in this run",
                        self.limits.max_total_jumps
                    ),
                )
                .with_help("does every loop and recursion reach its end condition?"));
        }
        let resume = self.next_mark();
        let def = match self.subs.get(&o.label) {
            Some(def) => *def,
            None => self.search_sub(o)?,
        };
        self.calls.push(CallFrame {
            label: o.label.clone(),
            resume,
            ctl_base: self.ctl.len(),
            call_line: self.line.line,
        });
        params.push_call(&args[..o.args.len()]);
        if let Err(e) = self.seek(def.body) {
            return Err(e.with_help(format!("while calling {name}")));
        }
        Ok(())
    }

    /// Look ahead for the definition of a subroutine called before it was defined.
    fn search_sub(&mut self, o: &OWord) -> Result<SubDef, Diagnostic> {
        let name = OWord::display_label(&o.label);
        let back = self.next_mark();
        let mut scratch = Compact::new();
        let found = loop {
            match self.src.read() {
                Ok(Read::Line { number, .. }) => {
                    if scratch.load(self.src.text(), number).is_err() {
                        continue;
                    }
                    if let Some((label, Keyword::Sub)) = oword_head(&scratch) {
                        if label == o.label {
                            break Some(SubDef {
                                body: self.next_mark(),
                                line: number,
                                found_by_search: true,
                            });
                        }
                    }
                }
                Ok(Read::TooLong { .. }) => continue,
                Ok(Read::Eof) | Err(_) => break None,
            }
        };
        self.seek(back)?;
        match found {
            Some(def) => {
                if self.subs.len() >= MAX_SUBS {
                    return Err(self.err(o, format!("more than {MAX_SUBS} subroutine definitions")));
                }
                self.subs.insert(o.label.clone(), def);
                Ok(def)
            }
            None => Err(self
                .err(o, format!("subroutine {name} is not defined"))
                .with_help(format!(
                    "define it in this file: {name} sub … {name} endsub"
                ))),
        }
    }

    fn return_from(&mut self, o: &OWord, params: &mut Params) -> Result<(), Diagnostic> {
        let name = OWord::display_label(&o.label);
        let Some(frame) = self.calls.last() else {
            return Err(self
                .err(
                    o,
                    format!("{name} {} outside a subroutine", o.keyword.name()),
                )
                .with_help(format!(
                    "{name} {} belongs between {name} sub and {name} endsub",
                    o.keyword.name()
                )));
        };
        if frame.label != o.label {
            return Err(self.err(
                o,
                format!(
                    "{name} {} inside subroutine {}",
                    o.keyword.name(),
                    OWord::display_label(&frame.label)
                ),
            ));
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

    /// The block the full path makes of `line` (tests of the fast path).
    #[cfg(test)]
    pub(crate) fn full_path_block(&mut self, line: &Line, params: &mut Params) -> Block {
        self.line = line.clone();
        let mut block = Block::default();
        self.fill_block(params, &mut block)
            .expect("a plain line evaluates");
        block
    }

    /// The block the full path makes of `line`, or its error (tests of the fast paths).
    #[cfg(test)]
    pub(crate) fn full_path_result(
        &mut self,
        line: &Line,
        params: &mut Params,
    ) -> Result<Block, Diagnostic> {
        self.line = line.clone();
        let mut block = Block::default();
        self.fill_block(params, &mut block).map(|_| block)
    }

    /// Evaluate the words and assignments of the current line into `block`.
    fn fill_block(&mut self, params: &mut Params, block: &mut Block) -> Result<(), Diagnostic> {
        block.line = self.line.line;
        block.n = self.line.n;
        block.words.clear();
        block.notes.clear();
        block.assignments.clear();
        self.pending.clear();
        let mut debug_at = Vec::new();
        for item in &self.line.items {
            match item {
                Item::Word {
                    letter,
                    value,
                    span,
                } => {
                    block.words.push(Word {
                        letter: *letter,
                        value: eval(value, params)?,
                        span: *span,
                    });
                }
                Item::Assign {
                    target,
                    value,
                    span,
                } => {
                    let target = match target {
                        Target::Numbered(index) => {
                            ParamRef::Numbered(param_number(index, *span, params)? as u32)
                        }
                        Target::Named(name) => {
                            // LinuxCNC defines the name while reading the line: later reads on
                            // the same line see it (with 0 if it is new).
                            if !params.exists_named(name) {
                                params
                                    .set_named(name, 0.0)
                                    .map_err(|e| param_error(e, *span))?;
                            }
                            ParamRef::Named(name.clone())
                        }
                    };
                    let v = eval(value, params)?;
                    self.pending.push((target, v, *span));
                }
                Item::Comment { kind, text } => match kind {
                    CommentKind::Plain => block.notes.push(Note::Comment(text.clone())),
                    CommentKind::Message => block.notes.push(Note::Message(text.clone())),
                    CommentKind::Debug => {
                        debug_at.push(block.notes.len());
                        block.notes.push(Note::Debug(text.clone()));
                    }
                },
            }
        }
        // All values were taken from before the line; now the assignments take effect.
        for (target, value, span) in self.pending.drain(..) {
            match &target {
                ParamRef::Numbered(n) => params.set(i64::from(*n), value),
                ParamRef::Named(name) => params.set_named(name, value),
            }
            .map_err(|e| param_error(e, span))?;
            block.assignments.push(Assignment {
                target,
                value,
                span,
            });
        }
        // DEBUG/PRINT show the values after the line's assignments, as LinuxCNC does.
        for i in debug_at {
            if let Some(Note::Debug(text)) = block.notes.get_mut(i) {
                *text = substitute_params(text, params);
            }
        }
        Ok(())
    }
}

/// `#n` and `#<name>` in a DEBUG/PRINT text replaced by their values (`%lf` style, six
/// decimals), `######` for a parameter that cannot be read.
pub fn substitute_params(text: &str, params: &Params) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find('#') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        if let Some(stripped) = after.strip_prefix('<') {
            if let Some(end) = stripped.find('>') {
                let name: String = stripped[..end]
                    .chars()
                    .filter(|c| !c.is_whitespace())
                    .collect();
                match params.get_named(&name) {
                    Ok(v) => out.push_str(&format!("{v:.6}")),
                    Err(_) => out.push_str("######"),
                }
                rest = &stripped[end + 1..];
                continue;
            }
        }
        let digits = after.bytes().take_while(u8::is_ascii_digit).count();
        if digits > 0 {
            let value = after[..digits]
                .parse::<i64>()
                .ok()
                .filter(|n| (1..=crate::expr::LAST_NUMBERED).contains(n))
                .and_then(|n| params.get(n).ok());
            match value {
                Some(v) => out.push_str(&format!("{v:.6}")),
                None => out.push_str("######"),
            }
            rest = &after[digits..];
        } else {
            out.push('#');
            rest = after;
        }
    }
    out.push_str(rest);
    out
}
