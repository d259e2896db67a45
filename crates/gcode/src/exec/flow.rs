//! The control-flow state of a running program: open `if`s and loops, subroutine calls in
//! progress, known subroutine definitions, and the search that is under way while lines
//! are being skipped.

use crate::ast::Keyword;

/// How many times loops may jump back and calls may nest before the executor gives up with
/// an error instead of running forever.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Deepest nesting of subroutine calls: 9, as in rs274, whose 10 call levels count the
    /// main program as the first (a 10th nested call is "Too many subroutine levels").
    pub max_call_depth: usize,
    /// Iterations of one loop (one entry into it).
    pub max_loop_iterations: u64,
    /// Loop iterations in a row without any block yielded: catches `o1 while [1]` around
    /// nothing long before `max_loop_iterations`.
    pub max_idle_iterations: u64,
    /// Backward jumps (loop iterations and subroutine calls) in the whole run: bounds the
    /// work of nested loops, whose iterations multiply.
    pub max_total_jumps: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_call_depth: 9,
            max_loop_iterations: 10_000_000,
            max_idle_iterations: 1_000_000,
            max_total_jumps: 1_000_000_000,
        }
    }
}

/// Where a loop body starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Mark {
    pub offset: u64,
    pub line: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub(super) enum LoopKind {
    /// `while` … `endwhile`: the mark is the `while` line itself (re-evaluated each time).
    While,
    /// `do` … `while`: the mark is the first body line.
    Do,
    /// `repeat` … `endrepeat`: the mark is the first body line.
    Repeat { remaining: u64 },
}

/// An open `if` or loop.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Ctl {
    If {
        label: String,
        taken: bool,
        line: u32,
    },
    Loop {
        label: String,
        kind: LoopKind,
        mark: Mark,
        line: u32,
        iterations: u64,
    },
}

impl Ctl {
    pub(super) fn label(&self) -> &str {
        match self {
            Ctl::If { label, .. } | Ctl::Loop { label, .. } => label,
        }
    }

    pub(super) fn line(&self) -> u32 {
        match self {
            Ctl::If { line, .. } | Ctl::Loop { line, .. } => *line,
        }
    }

    pub(super) fn opener(&self) -> &'static str {
        match self {
            Ctl::If { .. } => "if",
            Ctl::Loop {
                kind: LoopKind::While,
                ..
            } => "while",
            Ctl::Loop {
                kind: LoopKind::Do, ..
            } => "do",
            Ctl::Loop {
                kind: LoopKind::Repeat { .. },
                ..
            } => "repeat",
        }
    }

    /// The keyword that closes this construct.
    pub(super) fn closer(&self) -> Keyword {
        match self {
            Ctl::If { .. } => Keyword::EndIf,
            Ctl::Loop {
                kind: LoopKind::While,
                ..
            } => Keyword::EndWhile,
            Ctl::Loop {
                kind: LoopKind::Do, ..
            } => Keyword::While,
            Ctl::Loop {
                kind: LoopKind::Repeat { .. },
                ..
            } => Keyword::EndRepeat,
        }
    }
}

/// A subroutine call in progress.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct CallFrame {
    pub label: String,
    /// Where execution resumes after the return: the line after the call.
    pub resume: Mark,
    /// Open `if`s and loops below this index belong to the caller.
    pub ctl_base: usize,
    pub call_line: u32,
    /// A Fanuc-style `M98 P… L…` call: where its body starts and how many runs are left
    /// (`M99` goes back to the body until none are).
    pub fanuc: Option<FanucRuns>,
    /// Subroutine files open in the caller: the return closes the ones above.
    pub file_depth: usize,
}

/// The repetitions of an `M98 P… L…` call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct FanucRuns {
    pub body: Mark,
    pub remaining: u64,
}

/// A known subroutine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct SubDef {
    /// First line of the body.
    pub body: Mark,
    /// Line of `oN sub`.
    pub line: u32,
    /// Found by looking ahead for a call, not by running through its definition.
    pub found_by_search: bool,
    /// A Fanuc-style `O100` … `M99` subprogram (called with M98), not `o100 sub`.
    pub fanuc: bool,
}

/// What to do with the line that ends a skip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Arrival {
    /// Run it as usual (an `elseif`, `else` or `endif` after a false branch).
    Run,
    /// It only closes what was skipped (`endsub` of a definition, the end of a loop left).
    Consume,
}

/// Lines are being skipped until an o-word with this label and one of these keywords.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Skip {
    pub label: String,
    pub until: &'static [Keyword],
    pub arrival: Arrival,
    /// Skipping a subroutine definition: a `sub` inside it is an error.
    pub in_definition: bool,
    /// The line that started the skip (for "end of file while looking for…").
    pub from_line: u32,
}
