//! A block (one line of G-code) after its expressions were evaluated and its control-flow
//! words (O-words) were executed: what the modal interpreter consumes.

use crate::diag::Span;

/// One word: an upper-case letter and its evaluated value, with the span of the whole word
/// (letter and value expression) in the source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The letter, upper case.
    pub letter: char,
    /// The evaluated value.
    pub value: f64,
    /// Where the word (letter and value) is in the source.
    pub span: Span,
}

/// A comment of the block; `(MSG,…)` comments become operator messages.
#[derive(Clone, Debug, PartialEq)]
pub enum Note {
    /// An ordinary comment, without its parentheses.
    Comment(String),
    /// `(MSG, text)`
    Message(String),
    /// `(DEBUG, text)` / `(PRINT, text)` with parameters already substituted.
    Debug(String),
}

/// A block ready for the modal interpreter.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Block {
    /// 1-based source line number (of the file the block came from).
    pub line: u32,
    /// The `N` word, if any (not in `words`).
    pub n: Option<f64>,
    /// Words in source order, letters upper-cased (and the polar `@`, `^`); never `N` or `O`.
    pub words: Vec<Word>,
    /// The block's comments and messages, in source order.
    pub notes: Vec<Note>,
    /// Parameter assignments `#n=…` / `#<name>=…` on this line: evaluated with the values
    /// the parameters had before the line (as LinuxCNC does) and already applied to the
    /// [`crate::params::Params`] by the executor; kept here for tracing and tests.
    pub assignments: Vec<Assignment>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ParamRef {
    Numbered(u32),
    Named(String),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    pub target: ParamRef,
    pub value: f64,
    pub span: Span,
}

impl Block {
    /// The words with this letter.
    pub fn words_of(&self, letter: char) -> impl Iterator<Item = &Word> {
        self.words.iter().filter(move |w| w.letter == letter)
    }

    /// The single value of `letter`, if present (the interpreter reports duplicates).
    pub fn get(&self, letter: char) -> Option<f64> {
        self.words_of(letter).next().map(|w| w.value)
    }
}
