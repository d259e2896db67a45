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
mod fanuc;
mod fast;
mod flow;
mod oword;
mod plain;
mod profile;
mod source;

pub use flow::Limits;
pub use source::DEFAULT_MAX_LINE_LEN;

use crate::ast::{CommentKind, Item, Line, OWord, Target};
use crate::block::{Assignment, Block, Note, ParamRef, Word};
use crate::diag::{Diagnostic, Span};
use crate::expr::{eval, param_error, param_number};
use crate::lex::Compact;
use crate::params::Params;
use crate::parse::{bare_oword, parse_line};
use crate::Dialect;
use flow::{CallFrame, Ctl, Mark, Skip, SubDef};
use source::{Read, Sources};
use std::collections::HashMap;
use std::io::{BufRead, Cursor, Seek};

/// How the program ended, once [`Executor::next_block`] has returned `None`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgramEnd {
    /// The closing `%` of a program that opened with `%`.
    Percent,
    /// The end of the file. LinuxCNC reports an error here unless M2/M30 came first (the
    /// interpreter knows; the executor does not look at M words).
    EndOfFile {
        /// The first line was a `%` (then a closing `%` was missing).
        opened_with_percent: bool,
    },
}

/// Most subroutine definitions remembered: a bound on memory for hostile input.
const MAX_SUBS: usize = 100_000;
/// Most `if`s and loops open at once (a million `o1 if [1]` lines must not grow memory).
const MAX_OPEN_BLOCKS: usize = 1_000;

/// The front end's executor: reads lines from a seekable reader, runs O-word control flow
/// and evaluates expressions, yielding [`Block`]s.
pub struct Executor<R> {
    src: Sources<R>,
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
    /// The plain and direct paths for ordinary lines.
    fast: fast::FastPaths,
    /// Start of the last line read whole by `read` (every o-word line is: `while` jumps
    /// back to it).
    current: Mark,
    /// Fanuc-style subprograms (`O100` … `M99`, `M98`) are read (LinuxCNC's default).
    fanuc_subs: bool,
    /// Texts of `(print, …)` comments of the last block read (see `take_printed`).
    printed: Vec<String>,
    /// Directories where `o<name> call` looks for `name.ngc` (LinuxCNC's SUBROUTINE_PATH).
    subroutine_path: Vec<std::path::PathBuf>,
    /// Marlin: the state of the line rewriting, the rewritten line, and the notes of the
    /// last line read.
    marlin: crate::marlin::MarlinState,
    marlin_line: Vec<u8>,
    notes: Vec<Diagnostic>,
    /// A G7x profile being read (see profile.rs).
    profile: profile::ProfileCall,
}

impl Executor<Cursor<Vec<u8>>> {
    /// An executor over program text held in memory.
    pub fn from_text(text: &str, dialect: Dialect) -> Self {
        Executor::new(Cursor::new(text.as_bytes().to_vec()), dialect)
    }
}

impl<R: BufRead + Seek> Executor<R> {
    /// An executor reading `reader` in `dialect`.
    pub fn new(reader: R, dialect: Dialect) -> Self {
        Executor {
            src: Sources::new(reader),
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
            fast: fast::FastPaths::default(),
            current: Mark { offset: 0, line: 0 },
            fanuc_subs: true,
            printed: Vec::new(),
            subroutine_path: Vec::new(),
            marlin: Default::default(),
            marlin_line: Vec::new(),
            notes: Vec::new(),
            profile: Default::default(),
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

    /// Read Fanuc-style subprograms (on by default); off, a bare `O100` line and `M98` are
    /// errors, as with LinuxCNC's `DISABLE_FANUC_STYLE_SUB` (see `exec/fanuc.rs`).
    pub fn set_fanuc_subs(&mut self, on: bool) {
        self.fanuc_subs = on;
    }

    /// Directories where `o<name> call` of a subroutine that this file does not define looks
    /// for `name.ngc`, in order, as LinuxCNC's `SUBROUTINE_PATH`.
    pub fn set_subroutine_path(&mut self, dirs: Vec<std::path::PathBuf>) {
        self.subroutine_path = dirs;
    }

    /// Replace the limits on loops, calls and subroutines.
    pub fn set_limits(&mut self, limits: Limits) {
        self.limits = limits;
    }

    /// The limits on loops, calls and subroutines.
    pub fn limits(&self) -> Limits {
        self.limits
    }

    /// The dialect lines are read in.
    pub fn dialect(&self) -> Dialect {
        self.dialect
    }

    /// How the program ended (after `next_block` returned `None`).
    pub fn end(&self) -> Option<ProgramEnd> {
        self.end
    }

    /// The `(print, …)` texts of the block just read, parameters substituted (rs274 writes
    /// them to its output). Emptied by the next read.
    pub fn take_printed(&mut self) -> std::vec::Drain<'_, String> {
        self.printed.drain(..)
    }

    /// Whether the block just read has `(print, …)` texts to take: a test cheaper than an
    /// empty [`Executor::take_printed`].
    pub fn has_printed(&self) -> bool {
        !self.printed.is_empty()
    }

    /// Notes (and warnings) the dialect gives the lines read since the last take: Marlin's
    /// pauses, motors, fans, ignored words.
    pub fn take_notes(&mut self) -> std::vec::Drain<'_, Diagnostic> {
        self.notes.drain(..)
    }

    /// Whether [`Executor::take_notes`] has anything.
    pub fn has_notes(&self) -> bool {
        !self.notes.is_empty()
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
        self.read_block_with(params, block, &mut |_| {})
    }

    /// [`Executor::read_block`], calling `refresh` before running a line that names a
    /// system parameter (`#<_x>`, `#< _metric >`…) while [`Params::system_stale`]: the
    /// caller marks them stale after each block and brings them up to date only for the
    /// lines that read them. The fast paths decline such lines (see `direct.rs`), so only
    /// the full path looks for the names.
    // Inlined into the caller's loop: the usual line costs no call and no `Result` built
    // in memory; anything else goes to `read_block_slow`.
    #[inline]
    pub fn read_block_with(
        &mut self,
        params: &mut Params,
        block: &mut Block,
        refresh: &mut dyn FnMut(&mut Params),
    ) -> Result<bool, Diagnostic> {
        if self.fast_path_open() && self.fast_path_in_place(params, block) {
            // No M98/M99 to run: the fast paths decline their lines.
            self.printed.clear();
            self.idle_iterations = 0;
            return Ok(true);
        }
        self.read_block_slow(params, block, refresh)
    }

    /// Reads the usual lines one after another straight from the reader's buffer, handing
    /// each block to `each` until it answers false, a fast path declines a line or the
    /// buffer runs out; [`Executor::read_block_slow`] reads what comes next. Returns the
    /// number of the last line taken (0 when none was). The reader's position is brought
    /// up to date once per stretch, not once per line: this is the loop most programs
    /// spend their time in (`Driver::run`).
    #[inline]
    pub(crate) fn read_fast_lines(
        &mut self,
        params: &mut Params,
        block: &mut Block,
        mut each: impl FnMut(&mut Block, &mut Params) -> bool,
    ) -> u32 {
        if !self.fast_path_open() {
            return 0;
        }
        // Nothing in a stretch can close it: fast lines run no o-word, no `%`, no M98/M99.
        let max_len = self.src.max_len();
        let (_, first) = self.src.position();
        let chunk = self.src.buffered();
        let mut used = 0;
        let mut lines: u32 = 0;
        let mut number = first;
        while let Some(len) = self
            .fast
            .line(&chunk[used..], Some(max_len), number, params, block)
        {
            // `line` took `len` bytes and saw the newline after them.
            used += len + 1;
            lines = lines.saturating_add(1);
            if !each(block, params) {
                break;
            }
            number = number.saturating_add(1);
        }
        if lines == 0 {
            return 0;
        }
        self.src.take_lines(used, lines);
        self.printed.clear();
        self.idle_iterations = 0;
        // The last line taken (`block` may hold part of a line declined after it).
        first.saturating_add(lines - 1)
    }

    /// Whether the next line may go through a fast path: lines are not being skipped, the
    /// program has begun (its first line, perhaps a `%`, is the full path's) and not ended.
    /// grbl has its own letters and line limit: always the full path.
    #[inline]
    fn fast_path_open(&self) -> bool {
        // `seen_content` implies `started`: set on a line read after the start.
        self.seen_content
            && self.skip.is_none()
            && self.end.is_none()
            && matches!(self.dialect, Dialect::LinuxCnc | Dialect::Legacy2006)
    }

    /// [`Executor::read_block_with`] for every line but the usual one.
    #[inline(never)]
    pub(crate) fn read_block_slow(
        &mut self,
        params: &mut Params,
        block: &mut Block,
        refresh: &mut dyn FnMut(&mut Params),
    ) -> Result<bool, Diagnostic> {
        self.printed.clear();
        if !self.started {
            self.started = true;
            params.set_system("_value", 0.0);
            params.set_system("_value_returned", 0.0);
        }
        loop {
            if self.end.is_some() {
                return Ok(false);
            }
            if self.fast_path_open() && self.fast_path_in_place(params, block) {
                self.idle_iterations = 0;
                return Ok(true);
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
            if self.fast_path_open() && self.fast_path(number, params, block) {
                self.idle_iterations = 0;
                return Ok(true);
            }
            if self.dialect == Dialect::Marlin {
                let text = self.src.text();
                if let Err(e) = crate::marlin::rewrite(
                    text,
                    number,
                    &mut self.marlin,
                    &mut self.marlin_line,
                    &mut self.notes,
                ) {
                    self.seen_content = true;
                    return Err(e);
                }
            }
            let text: &[u8] = if self.dialect == Dialect::Marlin {
                &self.marlin_line
            } else {
                self.src.text()
            };
            if names_system_param(text) {
                if params.system_stale() {
                    params.take_system_stale();
                    refresh(params);
                }
                // rs274's #<_line> is the line being read (its sequence_number), in the
                // file being read; the interpreter only knows the last block it ran.
                params.set_system("_line", number as f64);
            }
            let loaded = if self.dialect == Dialect::Grbl {
                self.compact.load_grbl(text, number);
                Ok(())
            } else {
                self.compact.load(text, number)
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
            if self.dialect != Dialect::Grbl && bare_oword(&self.compact).is_some() {
                // A program number (or a subprogram's first line, reached by running).
                self.seen_content = true;
                if !self.fanuc_subs {
                    return Err(Diagnostic::error(
                        self.compact.span(0, self.compact.bytes.len()),
                        "DISABLE_FANUC_STYLE_SUB disabled in INI file, but found bare O-word",
                    )
                    .with_help("Fanuc-style program numbers are disabled; an o-word needs a keyword (sub, call, if, …)"));
                }
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
            if let Some(mut o) = self.line.oword.take() {
                let result = resolve_label(&mut o, params).and_then(|_| self.run_oword(&o, params));
                self.line.oword = Some(o);
                result?;
                if self.profile_returned() {
                    return Ok(false);
                }
                continue;
            }
            if self.line.items.is_empty() && self.line.n.is_none() {
                continue;
            }
            self.fill_block(params, block)?;
            if self.fanuc_block(block)? {
                continue;
            }
            self.idle_iterations = 0;
            return Ok(true);
        }
    }

    /// The current line through one of the fast paths, if one takes it.
    fn fast_path(&mut self, number: u32, params: &mut Params, block: &mut Block) -> bool {
        // A line read by `read` holds no newline: taken, it is taken whole.
        let text = self.src.text();
        self.fast.line(text, None, number, params, block).is_some()
    }

    /// The next line through one of the fast paths, read where it lies in the reader's
    /// buffer, before `read` has looked for its end or set it apart: taken only when the
    /// fast path stops at its newline (a line that goes on past the bytes at hand, an
    /// over-long one, or any line a fast path declines, is left to `read`).
    #[inline]
    fn fast_path_in_place(&mut self, params: &mut Params, block: &mut Block) -> bool {
        let (_, number) = self.src.position();
        let max_len = self.src.max_len();
        let chunk = self.src.buffered();
        match self.fast.line(chunk, Some(max_len), number, params, block) {
            // `current` is left as it is: only o-word lines read it, and they are the full
            // path's.
            Some(len) => {
                self.src.take_line(len);
                true
            }
            // `block` may be half-filled: the full path refills it.
            None => false,
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

    /// Evaluate the words and assignments of the current line into `block`.
    fn fill_block(&mut self, params: &mut Params, block: &mut Block) -> Result<(), Diagnostic> {
        block.line = self.line.line;
        block.n = self.line.n;
        block.words.clear();
        block.notes.clear();
        block.assignments.clear();
        self.pending.clear();
        let mut debug_at = Vec::new();
        // rs274 keeps one comment per block, the last (read_comment overwrites it): only
        // that one is a COMMENT, a message, a DEBUG, a PRINT or an ABORT.
        let last_comment = self
            .line
            .items
            .iter()
            .rposition(|i| matches!(i, Item::Comment { .. }));
        for (at, item) in self.line.items.iter().enumerate() {
            match item {
                Item::Comment { .. } if Some(at) != last_comment => {}
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
                    // rs274 writes (LOG,…) and its file commands to a log file, not as a
                    // comment; Oficina keeps no log file.
                    CommentKind::Plain if is_log_command(text) => {}
                    CommentKind::Plain => block.notes.push(Note::Comment(text.clone())),
                    CommentKind::Message => block.notes.push(Note::Message(text.clone())),
                    CommentKind::Debug => {
                        debug_at.push(block.notes.len());
                        block.notes.push(Note::Debug(text.clone()));
                    }
                    // rs274 writes it out (not a canonical call): the caller takes it from
                    // `take_printed` after this block.
                    CommentKind::Print => self.printed.push(substitute_params(text, params)),
                    CommentKind::Abort => {
                        return Err(Diagnostic::error(
                            Span::line(self.line.line),
                            substitute_params(text, params),
                        )
                        .with_help("the program stopped itself with (abort, …)"));
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

/// rs274's log file commands (`convert_comment`): `(LOG,…)`, `(LOGOPEN,…)`,
/// `(LOGAPPEND,…)`, `(LOGCLOSE)`, any case (the leading blanks are already gone).
fn is_log_command(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    ["log,", "logopen,", "logappend,"]
        .iter()
        .any(|k| lower.starts_with(k))
        || lower == "logclose"
}

/// The block the full path makes of the source line `src` (number `line`), reading and
/// writing `params` (tests of the fast paths, which must give the same). Panics when
/// the line does not compact and parse as an ordinary line: the fast paths take none
/// other.
#[cfg(test)]
pub(crate) fn full_path_of(src: &str, line: u32, params: &mut Params) -> Result<Block, Diagnostic> {
    let mut c = Compact::new();
    c.load(src.as_bytes(), line)
        .unwrap_or_else(|e| panic!("{src}: {e}"));
    let mut exec = Executor::from_text("", Dialect::LinuxCnc);
    parse_line(&c, Dialect::LinuxCnc, &mut exec.line).unwrap_or_else(|e| panic!("{src}: {e}"));
    let parsed = &exec.line;
    assert!(
        parsed.oword.is_none() && !parsed.percent && !parsed.block_delete,
        "{src}"
    );
    let mut block = Block::default();
    exec.fill_block(params, &mut block).map(|_| block)
}

/// Whether `line` may read a system parameter: a `<` followed, blanks aside, by `_`. A
/// search for each `<`, as they are rare in G-code; false positives only cost a refresh.
fn names_system_param(mut line: &[u8]) -> bool {
    while let Some(i) = crate::bytes::find_byte(b'<', line) {
        line = &line[i + 1..];
        let blanks = line
            .iter()
            .take_while(|&&b| b == b' ' || b == b'\t')
            .count();
        if line.get(blanks) == Some(&b'_') {
            return true;
        }
    }
    false
}

/// The label of an `o[expression]` line: the expression's value, an integer.
fn resolve_label(o: &mut OWord, params: &Params) -> Result<(), Diagnostic> {
    let Some(e) = &o.label_expr else {
        return Ok(());
    };
    let v = eval(e, params)?;
    let n = v.round();
    if (v - n).abs() > 1e-4 || !(0.0..=99_999_999.0).contains(&n) {
        return Err(Diagnostic::error(
            o.span,
            format!("o[…] evaluates to {v}, not an o-word number"),
        )
        .with_help("the expression must give a whole number such as 100"));
    }
    o.label = format!("{}", n as i64);
    Ok(())
}

/// `#n` and `#<name>` in a DEBUG/PRINT text replaced by their values (`%lf` style, six
/// decimals), `######` for a parameter that cannot be read.
pub(crate) fn substitute_params(text: &str, params: &Params) -> String {
    let mut out = String::with_capacity(text.len());
    // rs274's convert_param_comment: `%d`, `%f` and `%.Nf` set how the parameters after
    // them print (`%.0f`, `%.4f`, `%.Nf`; `%lf` until then) and are not printed.
    let mut decimals = 6;
    let mut rest = text;
    while let Some(i) = rest.find(['#', '%']) {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        if rest.as_bytes()[i] == b'%' {
            let b = after.as_bytes();
            rest = match b.first() {
                Some(b'd') => {
                    decimals = 0;
                    &after[1..]
                }
                Some(b'f') => {
                    decimals = 4;
                    &after[1..]
                }
                Some(b'.')
                    if b.get(1).is_some_and(u8::is_ascii_digit) && b.get(2) == Some(&b'f') =>
                {
                    decimals = usize::from(b[1] - b'0');
                    &after[3..]
                }
                // rs274 drops the '%' of `%.` that is no format, keeping the '.'.
                Some(b'.') => {
                    out.push('.');
                    &after[1..]
                }
                _ => {
                    out.push('%');
                    after
                }
            };
            continue;
        }
        if let Some(stripped) = after.strip_prefix('<') {
            if let Some(end) = stripped.find('>') {
                let name: String = stripped[..end]
                    .chars()
                    .filter(|c| !c.is_whitespace())
                    .collect();
                match params.get_named(&name) {
                    Ok(v) => out.push_str(&format!("{v:.decimals$}")),
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
                Some(v) => out.push_str(&format!("{v:.decimals$}")),
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

#[cfg(test)]
mod tests {
    use crate::{run, RunOptions};
    use oficina_canon::{Canon, CanonOp};
    use std::io::{BufReader, Cursor};

    /// Runs `text` through a reader whose buffer holds `capacity` bytes.
    fn run_with_buffer(text: &str, capacity: usize, opts: &RunOptions) -> Vec<Canon> {
        let mut ops = Vec::new();
        let reader = BufReader::with_capacity(capacity, Cursor::new(text.as_bytes().to_vec()));
        let diagnostics = run(reader, opts, &mut |c| ops.push(c));
        assert!(diagnostics.is_empty(), "{capacity}: {diagnostics:?}");
        ops
    }

    #[test]
    fn lines_read_in_place_match_lines_read_whole_at_any_buffer_size() {
        // Lines cut anywhere by the reader's buffer are read apart and whole; an
        // assignment must still run exactly once (the X of each move counts them).
        for newline in ["\n", "\r\n"] {
            let mut text = format!("G21 G90 G1 F100{newline}#1 = 0{newline}");
            for _ in 0..40 {
                text += &format!("#1 = [#1 + 1]{newline}G1 X#1 Y[#1 * 2]{newline}G1 Z-1{newline}");
            }
            text += "M2";
            let whole = run_with_buffer(&text, 1 << 16, &RunOptions::default());
            let last_x = whole.iter().rev().find_map(|c| match c.op {
                CanonOp::StraightFeed { to } => Some(to.x),
                _ => None,
            });
            assert_eq!(last_x, Some(40.0));
            for capacity in 1..48 {
                assert_eq!(
                    run_with_buffer(&text, capacity, &RunOptions::default()),
                    whole,
                    "buffer of {capacity} bytes, {newline:?}"
                );
            }
        }
    }

    #[test]
    fn a_line_read_in_place_empties_the_printed_texts() {
        // The second and third lines take the inlined fast path: they must not hand back
        // the first line's text.
        let mut exec = crate::Executor::from_text(
            "G21 G1 F100\nG1 X1 (print, one)\nG1 X2\nG1 X[2 * 2]\nM2\n",
            crate::Dialect::LinuxCnc,
        );
        let mut params = crate::params::Params::new();
        let mut block = crate::block::Block::default();
        let mut printed = Vec::new();
        while exec.read_block(&mut params, &mut block).expect("reads") {
            printed.push((block.line, exec.has_printed()));
        }
        assert_eq!(
            printed,
            vec![(1, false), (2, true), (3, false), (4, false), (5, false)]
        );
    }

    #[test]
    fn the_line_limit_holds_for_lines_read_in_place() {
        let long = format!("G1 X1 Y[2 + {}]\n", "0".repeat(200));
        let text = format!("G21 G1 F100\n{long}M2\n");
        let opts = RunOptions {
            max_line_len: 100,
            ..RunOptions::default()
        };
        let reader = BufReader::with_capacity(1 << 16, Cursor::new(text.into_bytes()));
        let diagnostics = run(reader, &opts, &mut |_| {});
        assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
        assert_eq!(diagnostics[0].span.line, 2);
        assert!(diagnostics[0].message.contains("more than the limit"));
    }
}
