//! The fast path for the lines that make up nearly all of a real program: letters and plain
//! signed numbers only (`N10 G1 X12.5 Y-3 F600`). Read straight from the raw bytes into the
//! block, with no compaction, syntax tree or evaluation. Anything else (comments, brackets,
//! parameters, o-words, a blank inside a number, `/`, `%`, non-ASCII) returns `false` and
//! goes through the full lexer and parser, which handle it exactly as before.

use super::fanuc::is_call_or_return;
use crate::block::{Block, Word};
use crate::diag::Span;
use crate::lex::scan_number;

// The whole-line form: the tests' (the executor reads in place, `_upto`).
#[cfg(test)]
/// Fill `block` from `raw` if the line is plain; `false` leaves the line to the full path
/// (`block` may then hold partial content: the caller refills it).
pub(super) fn plain_line(raw: &[u8], line: u32, block: &mut Block) -> bool {
    plain_line_upto(raw, line, block).is_some()
}

/// [`plain_line`] over `raw` holding the line and perhaps what follows it (the reader's
/// buffer, read in place): reading stops at the first newline. The line's length when it
/// is taken: the newline's position, or the end of `raw` when it holds none.
pub(super) fn plain_line_upto(raw: &[u8], line: u32, block: &mut Block) -> Option<usize> {
    let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
    block.line = line;
    block.n = None;
    block.words.clear();
    block.notes.clear();
    block.assignments.clear();
    let mut i = 0;
    let len = raw.len();
    let mut end = len;
    while i < len {
        let b = raw[i];
        if b == b' ' || b == b'\t' {
            i += 1;
            continue;
        }
        if b == b'\n' {
            end = i;
            break;
        }
        let letter = b.to_ascii_lowercase();
        if !letter.is_ascii_lowercase() || letter == b'o' {
            return None;
        }
        let start = i;
        i += 1;
        while i < len && (raw[i] == b' ' || raw[i] == b'\t') {
            i += 1;
        }
        let (negative, signed) = match raw.get(i) {
            Some(b'-') => {
                i += 1;
                (true, true)
            }
            Some(b'+') => {
                i += 1;
                (false, true)
            }
            _ => (false, false),
        };
        while i < len && (raw[i] == b' ' || raw[i] == b'\t') {
            i += 1;
        }
        let (value, used) = match scan_number(&raw[i..]) {
            Some(Ok(v)) => v,
            _ => return None,
        };
        i += used;
        // A blank followed by more digits is a number with a blank inside: full path.
        let mut j = i;
        while j < len && (raw[j] == b' ' || raw[j] == b'\t') {
            j += 1;
        }
        if j < len && (raw[j].is_ascii_digit() || raw[j] == b'.') {
            return None;
        }
        let value = if negative { -value } else { value };
        if letter == b'n' {
            // Only first on the line, unsigned: anything else is the full path's error.
            if !block.words.is_empty() || block.n.is_some() || signed {
                return None;
            }
            block.n = Some(value);
        } else {
            // M98/M99 call and return: the full path's (see `fanuc.rs`).
            if letter == b'm' && is_call_or_return(value) {
                return None;
            }
            let span = Span::new(line, start as u32 + 1, (i - start) as u32);
            block.words.push(Word {
                letter: letter.to_ascii_uppercase() as char,
                value,
                span,
            });
        }
        i = j;
    }
    (!block.words.is_empty() || block.n.is_some()).then_some(end)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;

    /// The fast path gives what the full path gives, or declines.
    fn same_as_full_path(src: &str) -> bool {
        let mut fast = Block::default();
        if !plain_line(src.as_bytes(), 3, &mut fast) {
            return false;
        }
        let full =
            crate::exec::full_path_of(src, 3, &mut Params::new()).expect("a plain line evaluates");
        assert_eq!(fast.words, full.words, "{src}");
        assert_eq!(fast.n, full.n, "{src}");
        true
    }

    #[test]
    fn plain_lines_match_the_full_path() {
        for s in [
            "G1 X12.5 Y-3 F600",
            "n10 g0 x.5",
            "G1X1Y2",
            "  G 1 X - 2.25\r",
            "M2",
            "X+1 Y-0. Z7.",
        ] {
            assert!(same_as_full_path(s), "fast path declined {s}");
        }
    }

    #[test]
    fn anything_unusual_is_declined() {
        for s in [
            "G1 X1 0.5",
            "G1 X#1",
            "G1 X[1]",
            "(c)",
            "G1 ; c",
            "/G1",
            "%",
            "o1 sub",
            "G1 N1",
            "N-1",
            "G1 X",
            "G1 X1..2",
            "",
            "X1 µ",
            "G1 X--1",
            "M98 P1000 L2",
            "m99",
            "M 99.0",
        ] {
            let mut b = Block::default();
            assert!(
                !plain_line(s.as_bytes(), 1, &mut b),
                "{s} should take the full path"
            );
        }
    }
}

#[cfg(test)]
mod properties {
    use super::*;
    use crate::params::Params;
    use proptest::prelude::*;

    proptest! {
        /// Whenever the fast path takes a line, the full path accepts it with the same words.
        #[test]
        fn fast_path_never_disagrees_with_the_full_path(src in "[GXYNnoEe0-9.+\\- \t]{0,24}") {
            let mut fast = Block::default();
            if plain_line(src.as_bytes(), 1, &mut fast) {
                let full = crate::exec::full_path_of(&src, 1, &mut Params::new()).expect("a plain line evaluates");
                prop_assert_eq!(fast.words, full.words);
                prop_assert_eq!(fast.n, full.n);
            }
        }
    }
}
