//! The fast path for ordinary lines with expressions (`G1 X[#1 + 2.5] Y#<y>`, `#3 = [#2 *
//! 2]`): parsed and evaluated in one pass over the raw bytes, straight into the block, with
//! no compaction, syntax tree or allocation per node.
//!
//! It only takes lines it can run exactly as the full path would, and declines (returns
//! `false`, having changed no parameter) on anything else: comments, o-words, `/`, `%`,
//! non-ASCII, a blank inside a number or a keyword, `EXISTS`, an assignment that defines a
//! new name, and every error. The full path then reads the line from scratch, so errors and
//! unusual syntax keep their one implementation.

use super::fanuc::is_call_or_return;
use crate::ast::{BinOp, Func};
use crate::block::{Assignment, Block, ParamRef, Word};
use crate::diag::Span;
use crate::expr::{binary, call, degrees, LAST_NUMBERED};
use crate::params::Params;
use crate::parse::{MAX_NESTING, WORD_OPS};

/// Spare name strings kept: more than a line's named assignments is never needed.
const MAX_SPARE_NAMES: usize = 16;

/// How far from an integer a parameter number may be (as `expr::param_number`).
const INTEGER_TOLERANCE: f64 = 0.0001;

/// Scratch space kept between lines (the name being read), and what the last line held.
#[derive(Default)]
pub(super) struct Scratch {
    name: String,
    /// Strings of the named assignments of earlier lines, reused for later ones: a line
    /// like `#<scale> = …` then allocates nothing.
    spare_names: Vec<String>,
    /// The last line taken had only letters and plain numbers (no brackets, parameters,
    /// functions or assignments): one the plain path would have taken.
    pub was_plain: bool,
}

// The whole-line form: the tests' (the executor reads in place, `_upto`).
#[cfg(test)]
/// Fill `block` from `raw` and apply its assignments to `params` if the line is ordinary;
/// `false` leaves the line (and `params`) to the full path, `block` possibly half-filled.
pub(super) fn direct_line(
    raw: &[u8],
    line: u32,
    params: &mut Params,
    block: &mut Block,
    scratch: &mut Scratch,
) -> bool {
    direct_line_upto(raw, None, line, params, block, scratch).is_some()
}

/// [`direct_line`] over `raw` holding the line and perhaps what follows it (the reader's
/// buffer, read in place): reading stops at the first newline. The line's length when it
/// is taken: the newline's position, or the end of `raw` when it holds none. With
/// `in_place = Some(max_len)` the line is taken only if a newline ends it within `max_len`
/// bytes (checked before any assignment is applied: a line declined changed nothing).
pub(super) fn direct_line_upto(
    raw: &[u8],
    in_place: Option<usize>,
    line: u32,
    params: &mut Params,
    block: &mut Block,
    scratch: &mut Scratch,
) -> Option<usize> {
    let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
    block.line = line;
    block.n = None;
    block.words.clear();
    block.notes.clear();
    for a in block.assignments.drain(..) {
        if let ParamRef::Named(name) = a.target {
            if scratch.spare_names.len() < MAX_SPARE_NAMES {
                scratch.spare_names.push(name);
            }
        }
    }
    let mut r = Reader {
        raw,
        pos: 0,
        depth: 0,
        params,
        name: &mut scratch.name,
        spare_names: &mut scratch.spare_names,
        plain: true,
        end: raw.len(),
    };
    r.line(line, block)?;
    let end = r.end;
    scratch.was_plain = r.plain;
    if block.words.is_empty() && block.n.is_none() && block.assignments.is_empty() {
        return None;
    }
    if in_place.is_some_and(|max_len| raw.get(end) != Some(&b'\n') || end > max_len) {
        return None;
    }
    // All values were read from before the line; now the assignments take effect, in
    // order. Their targets were checked while reading, so none can fail.
    for a in &block.assignments {
        let applied = match &a.target {
            ParamRef::Numbered(n) => params.set(i64::from(*n), a.value),
            ParamRef::Named(name) => params.set_named(name, a.value),
        };
        debug_assert!(applied.is_ok());
    }
    Some(end)
}

/// Blanks as the compactor drops them.
fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | 0x0B | 0x0C)
}

struct Reader<'a> {
    raw: &'a [u8],
    pos: usize,
    depth: usize,
    params: &'a Params,
    name: &'a mut String,
    spare_names: &'a mut Vec<String>,
    /// Nothing but letters and plain numbers so far.
    plain: bool,
    /// Where the line ends: at the first newline, or the end of `raw`.
    end: usize,
}

/// Functions taken here (`EXISTS` is left to the full path; ATAN has its own syntax).
const FUNCS: [(&[u8], Option<Func>); 13] = [
    (b"abs", Some(Func::Abs)),
    (b"acos", Some(Func::Acos)),
    (b"asin", Some(Func::Asin)),
    (b"atan", None),
    (b"cos", Some(Func::Cos)),
    (b"exp", Some(Func::Exp)),
    (b"fix", Some(Func::Fix)),
    (b"fup", Some(Func::Fup)),
    (b"ln", Some(Func::Ln)),
    (b"round", Some(Func::Round)),
    (b"sin", Some(Func::Sin)),
    (b"sqrt", Some(Func::Sqrt)),
    (b"tan", Some(Func::Tan)),
];

/// Whether `rest` starts with `name` (lower-case letters only, as in the tables), in any
/// case: setting bit 5 lower-cases a letter, and only the two cases of a letter end up
/// equal to a lower-case letter that way.
fn starts_with_ci(rest: &[u8], name: &[u8]) -> bool {
    rest.len() >= name.len() && rest.iter().zip(name).all(|(&r, &n)| r | 0x20 == n)
}

/// The first entry of `table` whose lower-case name starts `rest`, in any case. The first
/// byte is compared alone before the whole name: most entries fail on it, cheaply.
fn lookup<T: Copy>(table: &[(&'static [u8], T)], rest: &[u8]) -> Option<(&'static [u8], T)> {
    let first = rest.first()? | 0x20;
    table
        .iter()
        .find(|(n, _)| n[0] == first && starts_with_ci(rest, n))
        .copied()
}

impl<'a> Reader<'a> {
    /// The next non-blank byte and its position, without consuming anything.
    fn peek(&self) -> Option<(u8, usize)> {
        // Usually the next byte is the token itself (blanks are all at most b' ').
        if let Some(&b) = self.raw.get(self.pos) {
            if b > b' ' {
                return Some((b, self.pos));
            }
            // Or after the one space that usually separates tokens.
            if b == b' ' {
                if let Some(&c) = self.raw.get(self.pos + 1) {
                    if c > b' ' {
                        return Some((c, self.pos + 1));
                    }
                }
            }
        }
        let mut i = self.pos;
        while let Some(&b) = self.raw.get(i) {
            if !is_blank(b) {
                return Some((b, i));
            }
            i += 1;
        }
        None
    }

    /// Consume blanks and the byte after them if it is `want`.
    fn eat(&mut self, want: u8) -> Option<()> {
        match self.peek() {
            Some((b, i)) if b == want => {
                self.pos = i + 1;
                Some(())
            }
            _ => None,
        }
    }

    fn line(&mut self, line: u32, block: &mut Block) -> Option<()> {
        while let Some((b, start)) = self.peek() {
            self.pos = start + 1;
            match b.to_ascii_lowercase() {
                b'\n' => {
                    self.end = start;
                    return Some(());
                }
                b'#' => {
                    self.plain = false;
                    self.assignment(line, start, block)?
                }
                b'n' => {
                    // Only first on the line and unsigned, as the full path reads it.
                    if !block.words.is_empty() || !block.assignments.is_empty() || block.n.is_some()
                    {
                        return None;
                    }
                    let (b, i) = self.peek()?;
                    if !(b.is_ascii_digit() || b == b'.') {
                        return None;
                    }
                    self.pos = i;
                    block.n = Some(self.number()?);
                }
                letter @ b'a'..=b'z' if letter != b'o' => {
                    let value = self.simple_value()?;
                    // M98/M99 call and return: the full path's (see `fanuc.rs`).
                    if letter == b'm' && is_call_or_return(value) {
                        return None;
                    }
                    block.words.push(Word {
                        letter: letter.to_ascii_uppercase() as char,
                        value,
                        span: Span::new(line, start as u32 + 1, (self.pos - start) as u32),
                    });
                }
                _ => return None,
            }
        }
        Some(())
    }

    /// `#n = value` or `#<name> = value` (the `#` is consumed), recorded in the block.
    fn assignment(&mut self, line: u32, start: usize, block: &mut Block) -> Option<()> {
        let target = match self.peek()? {
            (b'<', i) => {
                self.pos = i + 1;
                let mut name = self.spare_names.pop().unwrap_or_default();
                name.clear();
                // A kept local that exists, read in place: one lookup, and never read-only
                // (only `_` names are).
                match self.local_name() {
                    true if self.params.get_local(self.name).is_some() => name.push_str(self.name),
                    _ => {
                        self.pos = i + 1;
                        self.read_name()?;
                        // A new name is defined while its line is read (later reads on the
                        // line see 0), and read-only names are errors: both for the full path.
                        if !self.params.exists_named(self.name)
                            || self.params.is_read_only(self.name)
                        {
                            return None;
                        }
                        name.push_str(self.name);
                    }
                }
                ParamRef::Named(name)
            }
            _ => {
                let v = self.real_value()?;
                ParamRef::Numbered(param_number(v)? as u32)
            }
        };
        self.eat(b'=')?;
        let value = self.simple_value()?;
        block.assignments.push(Assignment {
            target,
            value,
            span: Span::new(line, start as u32 + 1, (self.pos - start) as u32),
        });
        Some(())
    }

    /// A name after `<`, up to `>`: lower-cased and without blanks, as the compactor has it.
    fn read_name(&mut self) -> Option<()> {
        self.name.clear();
        // One pass, byte by byte: names are short, and a search for `>` before the copy
        // cost more than the copy.
        for (i, &b) in self.raw[self.pos..].iter().enumerate() {
            match b {
                b'>' => {
                    self.pos += i + 1;
                    return Some(());
                }
                b'(' | b';' | b'\n' | 0x80.. => return None,
                b if is_blank(b) => {}
                b => self.name.push(char::from(b.to_ascii_lowercase())),
            }
        }
        None
    }

    /// Whether the name after `<` is a local one written as it is kept (`scale`: lower
    /// case, digits and `_`, not first, no blanks); then it is in `name`, and `pos` moves
    /// past the `>`. Anything else is for [`Reader::read_name`].
    fn local_name(&mut self) -> bool {
        let rest = &self.raw[self.pos..];
        let Some(len) = rest
            .iter()
            .position(|&b| !(b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_'))
        else {
            return false;
        };
        if len == 0 || rest[0] == b'_' || rest[len] != b'>' {
            return false;
        }
        // Usually the name read last (`#<scale>` line after line): kept as it is. A
        // comparison costs less than turning the bytes into a `str` (a call to `from_utf8`).
        let bytes = &rest[..len];
        if self.name.as_bytes() != bytes {
            self.name.clear();
            self.name.extend(bytes.iter().map(|&b| char::from(b)));
        }
        self.pos += len + 1;
        true
    }

    /// An unsigned number at `pos`; a blank followed by more digits (a number with a blank
    /// inside) is for the full path.
    // Inlined: a call per number cost as much as a quarter of the number's own reading.
    #[inline(always)]
    fn number(&mut self) -> Option<f64> {
        let (v, len) = crate::lex::scan_number(&self.raw[self.pos..])?.ok()?;
        self.pos += len;
        // The number stopped at a byte that is neither a digit nor a point: only a blank
        // can hide more digits after it. Usually one blank and then the next token, told
        // apart here without the call to `peek`.
        if self.raw.get(self.pos).is_some_and(|&b| is_blank(b)) {
            let next = match self.raw.get(self.pos + 1) {
                Some(&c) if c > b' ' => Some(c),
                None => None,
                Some(_) => self.peek().map(|(c, _)| c),
            };
            if next.is_some_and(|c| c.is_ascii_digit() || c == b'.') {
                return None;
            }
        }
        Some(v)
    }

    /// A value as [`Reader::real_value`] reads it, taking the usual forms (a number, `-`
    /// and a number, `#n`) without its call and bookkeeping; anything else goes to it.
    /// Away from the nesting limit (where a sign or `#` adds a level that could exceed it)
    /// the usual forms need no depth bookkeeping.
    #[inline(always)]
    fn simple_value(&mut self) -> Option<f64> {
        if self.depth + 2 >= MAX_NESTING {
            return self.real_value();
        }
        let (b, i) = self.peek()?;
        let next = self.raw.get(i + 1).copied();
        match b {
            b'0'..=b'9' | b'.' => {
                self.pos = i;
                self.number()
            }
            b'-' if matches!(next, Some(b'0'..=b'9' | b'.')) => {
                self.pos = i + 1;
                Some(-self.number()?)
            }
            b'#' if next.is_some_and(|c| c.is_ascii_digit()) => {
                self.plain = false;
                match self.whole_number(i + 1) {
                    // As `compound_value` reads it.
                    Some(n) => ((1..=LAST_NUMBERED).contains(&n))
                        .then(|| self.params.get(n).ok())
                        .flatten(),
                    None => self.real_value(),
                }
            }
            // `#<scale>`, a local written as kept: as `compound_value` reads it.
            b'#' if next == Some(b'<') => {
                self.plain = false;
                self.pos = i + 2;
                match self.local_name() {
                    true => self.params.get_local(self.name),
                    false => {
                        self.pos = i;
                        self.real_value()
                    }
                }
            }
            b'[' => self.bracket_value(i),
            _ => self.real_value(),
        }
    }

    /// A value: number, `[expression]`, `#parameter`, unary sign, or function.
    fn real_value(&mut self) -> Option<f64> {
        // Each value counts one level of nesting, as in the full path; a plain number
        // (the usual value) only checks the limit, without the bookkeeping around a call.
        if self.depth >= MAX_NESTING {
            return None;
        }
        let (b, i) = self.peek()?;
        if b.is_ascii_digit() || b == b'.' {
            self.pos = i;
            return self.number();
        }
        // `-2.5` (a digit right after the sign): read as `compound_value` would, sign then
        // number one level down, without the bookkeeping of two calls.
        if b == b'-'
            && self.depth + 1 < MAX_NESTING
            && matches!(self.raw.get(i + 1), Some(b'0'..=b'9' | b'.'))
        {
            self.pos = i + 1;
            return Some(-self.number()?);
        }
        self.depth += 1;
        let v = self.compound_value(b, i);
        self.depth -= 1;
        v
    }

    /// A value that is not a plain number, its first byte `b` at `i`.
    fn compound_value(&mut self, b: u8, i: usize) -> Option<f64> {
        match b {
            b'[' => self.bracket(i),
            b'#' => {
                self.pos = i + 1;
                self.plain = false;
                match self.peek()? {
                    (b'<', j) => {
                        self.pos = j + 1;
                        if self.local_name() {
                            return self.params.get_local(self.name);
                        }
                        self.read_name()?;
                        // A system value not yet refreshed: the full path refreshes it.
                        if self.name.starts_with('_')
                            && self.params.system_stale()
                            && self.params.is_read_only(self.name)
                        {
                            return None;
                        }
                        self.params.get_named(self.name).ok()
                    }
                    (b'0'..=b'9', j) if self.depth < MAX_NESTING => {
                        // `#1`: the number as `real_value` would read it, one level down.
                        if let Some(n) = self.whole_number(j) {
                            return ((1..=LAST_NUMBERED).contains(&n))
                                .then(|| self.params.get(n).ok())
                                .flatten();
                        }
                        self.pos = j;
                        let n = param_number(self.number()?)?;
                        self.params.get(n).ok()
                    }
                    _ => {
                        let n = param_number(self.real_value()?)?;
                        self.params.get(n).ok()
                    }
                }
            }
            b'-' => {
                self.pos = i + 1;
                Some(-self.real_value()?)
            }
            b'+' => {
                self.pos = i + 1;
                self.real_value()
            }
            b'a'..=b'z' | b'A'..=b'Z' => {
                self.pos = i;
                self.plain = false;
                self.function()
            }
            _ => None,
        }
    }

    /// A bracket as [`Reader::real_value`] reads it (one level down), its `[` at `i`,
    /// without the two calls on the way.
    #[inline(always)]
    fn bracket_value(&mut self, i: usize) -> Option<f64> {
        if self.depth >= MAX_NESTING {
            return None;
        }
        self.depth += 1;
        let v = self.bracket(i);
        self.depth -= 1;
        v
    }

    /// A bracketed expression, its `[` at `i`, up to and including its `]`.
    #[inline(always)]
    fn bracket(&mut self, i: usize) -> Option<f64> {
        self.pos = i + 1;
        self.plain = false;
        let v = self.expression()?;
        // LinuxCNC checks each bracketed value (the full path reports it).
        v.is_finite().then_some(v)
    }

    /// The digits at `at` as an integer, read without the float reading of
    /// [`Reader::number`], when they are at most four (every parameter number) and end the
    /// number: not followed by a point or by a blank (which could hide more digits).
    /// `pos` moves past them only when they are taken.
    #[inline(always)]
    fn whole_number(&mut self, at: usize) -> Option<i64> {
        let rest = &self.raw[at..];
        // One digit (`#1`), the usual case, without the loops below.
        if let [d @ b'0'..=b'9', after @ ..] = rest {
            if !after
                .first()
                .is_some_and(|&b| b.is_ascii_digit() || b == b'.' || is_blank(b))
            {
                self.pos = at + 1;
                return Some(i64::from(d - b'0'));
            }
        }
        let digits = rest.iter().take_while(|b| b.is_ascii_digit()).count();
        if digits > 4 || rest.get(digits).is_some_and(|&b| b == b'.' || is_blank(b)) {
            return None;
        }
        self.pos = at + digits;
        Some(
            rest[..digits]
                .iter()
                .fold(0, |n, &d| n * 10 + i64::from(d - b'0')),
        )
    }

    /// The inside of a bracket up to and including its `]`, `pos` after the `[`. Most
    /// brackets hold one value or one operator (`[#1 + 2.5]`): read here without any stack;
    /// longer ones go on to [`Reader::expression_rest`].
    fn expression(&mut self) -> Option<f64> {
        let lhs = self.simple_value()?;
        let Some(op) = self.operator()? else {
            return Some(lhs);
        };
        let rhs = self.simple_value()?;
        match self.operator()? {
            None => apply(op, lhs, rhs),
            Some(next) => self.expression_rest([lhs, rhs], op, next),
        }
    }

    /// The operator after a value, consumed: `Some(None)` for the bracket's closing `]`
    /// (consumed too), `None` for anything else (blanks inside `M O D`, a letter that is no
    /// operator, the end of the line), which is the full path's to read or report.
    #[inline(always)]
    fn operator(&mut self) -> Option<Option<BinOp>> {
        let (b, i) = self.peek()?;
        let (op, len) = match b {
            b']' => {
                self.pos = i + 1;
                return Some(None);
            }
            b'+' => (BinOp::Add, 1),
            b'-' => (BinOp::Sub, 1),
            b'*' if self.raw.get(i + 1) == Some(&b'*') => (BinOp::Pow, 2),
            b'*' => (BinOp::Mul, 1),
            b'/' => (BinOp::Div, 1),
            _ => {
                let (name, op) = lookup(&WORD_OPS, &self.raw[i..])?;
                (op, name.len())
            }
        };
        self.pos = i + len;
        Some(Some(op))
    }

    /// The rest of a bracket after `a op b next`, `pos` after `next`: operator precedence
    /// without recursion (a shunting-yard over two small stacks). It gives the tree that
    /// `parse::Parser::expression` builds by precedence climbing, every operator
    /// left-associative, and so the same `binary` calls on the same operands in the same
    /// order: bit-identical values. Each operand is a value read one level down, as there.
    ///
    /// The stacks stay small: before an operator is pushed, every pending operator of the
    /// same or a higher precedence is applied, so the pending ones have strictly increasing
    /// precedences — at most one per level.
    #[inline(never)]
    fn expression_rest(&mut self, first: [f64; 2], op: BinOp, next: BinOp) -> Option<f64> {
        let mut values = [0.0; LEVELS + 1];
        let mut ops = [BinOp::Add; LEVELS];
        [values[0], values[1]] = first;
        ops[0] = op;
        let mut pending = 1;
        let mut op = Some(next);
        while let Some(next) = op {
            let precedence = next.precedence();
            while pending > 0 && ops[pending - 1].precedence() >= precedence {
                pending -= 1;
                values[pending] = apply(ops[pending], values[pending], values[pending + 1])?;
            }
            *ops.get_mut(pending)? = next;
            pending += 1;
            *values.get_mut(pending)? = self.simple_value()?;
            op = self.operator()?;
        }
        while pending > 0 {
            pending -= 1;
            values[pending] = apply(ops[pending], values[pending], values[pending + 1])?;
        }
        Some(values[0])
    }

    /// A function call, `pos` at its name.
    fn function(&mut self) -> Option<f64> {
        let rest = &self.raw[self.pos..];
        let (name, func) = lookup(&FUNCS, rest)?;
        self.pos += name.len();
        let Some((b'[', at)) = self.peek() else {
            return None;
        };
        match func {
            Some(f) => call(f, self.bracket_value(at)?, Span::default()).ok(),
            None => {
                // ATAN[y]/[x]
                let y = self.real_value()?;
                self.eat(b'/')?;
                if !matches!(self.peek(), Some((b'[', _))) {
                    return None;
                }
                let x = self.real_value()?;
                Some(degrees(y.atan2(x)))
            }
        }
    }
}

/// Precedence levels of binary operators (`BinOp::precedence` runs from 0 to 4).
const LEVELS: usize = 5;

/// `binary` without its call for the four usual operators; `None` on any error.
#[inline(always)]
fn apply(op: BinOp, a: f64, b: f64) -> Option<f64> {
    match op {
        BinOp::Add => Some(a + b),
        BinOp::Sub => Some(a - b),
        BinOp::Mul => Some(a * b),
        BinOp::Div if b != 0.0 => Some(a / b),
        _ => binary(op, a, b, Span::default()).ok(),
    }
}

/// A parameter number: an integer within 1e-4, from 1 to the last numbered parameter.
fn param_number(v: f64) -> Option<i64> {
    // Only 0.5 ≤ v < LAST + 0.5 can round into range (NaN fails too); there, truncating
    // v + 0.5 rounds without a call to `round`, differing only next to a half, which is
    // outside the tolerance either way.
    if !(v >= 0.5 && v < LAST_NUMBERED as f64 + 0.5) {
        return None;
    }
    let n = (v + 0.5) as i64;
    ((v - n as f64).abs() <= INTEGER_TOLERANCE && (1..=LAST_NUMBERED).contains(&n)).then_some(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn params() -> Params {
        let mut p = Params::new();
        p.set(1, 1.0).unwrap();
        p.set(2, 2.5).unwrap();
        p.set(3, -4.0).unwrap();
        p.set_named("a", 3.0).unwrap();
        p.set_named("b", -1.0).unwrap();
        p.set_named("_g", 4.0).unwrap();
        p.set_system("_x", 7.0);
        p
    }

    /// The parameters a test line can touch, for comparing two runs.
    fn touched(p: &Params) -> Vec<Option<f64>> {
        let mut v: Vec<_> = (1..=6).map(|n| p.get(n).ok()).collect();
        for name in ["a", "b", "_g", "_x", "new"] {
            v.push(p.get_named(name).ok());
        }
        v
    }

    /// When the fast path takes `src`, the full path takes it too, with the same block and
    /// the same parameters afterwards. Returns whether the fast path took it.
    fn agrees_with_full_path(src: &str) -> bool {
        let mut fast_params = params();
        let before = touched(&fast_params);
        let mut fast = Block::default();
        if !direct_line(
            src.as_bytes(),
            3,
            &mut fast_params,
            &mut fast,
            &mut Scratch::default(),
        ) {
            assert_eq!(touched(&fast_params), before, "{src}: declined but changed");
            return false;
        }
        let mut full_params = params();
        let full = crate::exec::full_path_of(src, 3, &mut full_params)
            .unwrap_or_else(|e| panic!("{src}: {e}"));
        assert_eq!(fast, full, "{src}");
        assert_eq!(touched(&fast_params), touched(&full_params), "{src}");
        true
    }

    #[test]
    fn ordinary_lines_match_the_full_path() {
        for s in [
            "G1 X[#1 + 2.5] Y#<a> Z-#2",
            "g1 x[1 mod 2] y[2**3**2] z[-2**2]",
            "#3 = [#2 * 2] #<a> = [#3 + #<_g>]",
            "#<b>=#<_G> X#<B>",
            "N10 G1 X[SIN[30]] Y[atan[1]/[-1]] Z[abs[-1] + fix[2.5] + round[2.5]]",
            "X[1 EQ 1.00001] Y[1 lt 2 and 0 or 1 xor 1] Z[7 MOD -3]",
            "X##1 Y#[1+1]",
            "X[ 1 + 2 ] Y - [ 3 ]",
            "G1 X[ABS[SIN[12]] * 0 + 1]",
            "X[1 + 2 * 3 ** 2 - 4 / 8 mod 3] Y[1 lt 2 + 3 and 4 eq 4 or 0] Z[2 ** 3 ** 2 * 2]",
            "X[#1 - #2 - #3 + #<a> * #<b> / 4 ** 2 ** 0.5]",
            "X#01 Y#0002 Z[#3 + #12] A#00001 B#1. C#5601",
        ] {
            assert!(agrees_with_full_path(s), "fast path declined {s}");
        }
    }

    #[test]
    fn unusual_lines_and_errors_are_declined() {
        for s in [
            "X[1 m o d 2]",
            "X[s in[30]]",
            "X[1 0]",
            "X[1/0]",
            "X[SQRT[-1]]",
            "X#<undefined>",
            "#<new>=1",
            "#<_x>=1",
            "#0=1",
            "X#0",
            "X#5603",
            "X#[1.5]",
            "X[EXISTS[#<a>]]",
            "G1 X[1] (comment)",
            "G1 X[1] ; comment",
            "/G1 X[1]",
            "o1 if [1]",
            "N1 N2 X[1]",
            "X[1",
            "X[0**-1]",
            "#1 5",
            "X1 µ",
            "M98 P[1000] L2",
            "G1 X[1] m99",
        ] {
            assert!(!agrees_with_full_path(s), "{s} should take the full path");
        }
    }

    #[test]
    fn stale_system_values_are_left_to_the_full_path() {
        let mut p = params();
        let mut block = Block::default();
        let mut scratch = Scratch::default();
        p.mark_system_stale();
        assert!(!direct_line(
            b"G1 X#<_x>",
            1,
            &mut p,
            &mut block,
            &mut scratch
        ));
        // A user global is read as usual, and so is every name once refreshed.
        assert!(direct_line(
            b"G1 X#<_g>",
            1,
            &mut p,
            &mut block,
            &mut scratch
        ));
        p.take_system_stale();
        assert!(direct_line(
            b"G1 X#<_x>",
            1,
            &mut p,
            &mut block,
            &mut scratch
        ));
        assert_eq!(block.get('X'), Some(7.0));
    }

    #[test]
    fn names_are_matched_in_any_case_and_only_as_letters() {
        // `starts_with_ci` relies on the tables holding lower-case letters only.
        let names = FUNCS
            .iter()
            .map(|(n, _)| *n)
            .chain(WORD_OPS.iter().map(|(n, _)| *n));
        for n in names {
            assert!(n.iter().all(u8::is_ascii_lowercase), "{n:?}");
        }
        assert!(starts_with_ci(b"SiN[", b"sin"));
        assert!(!starts_with_ci(b"s)n[", b"sin"));
        assert!(!starts_with_ci(b"si", b"sin"));
        assert_eq!(
            lookup(&FUNCS, b"ATAN[1]").map(|(n, _)| n),
            Some(&b"atan"[..])
        );
        assert_eq!(
            lookup(&WORD_OPS, b"Mod 2").map(|(_, op)| op),
            Some(BinOp::Mod)
        );
        // `{` is `[` with bit 5 set: not a letter.
        assert!(lookup(&FUNCS, b"{abs").is_none());
    }

    #[test]
    fn deep_brackets_are_read_once() {
        // Each level of a nesting that fails deep inside must not be read again per level
        // above it (2^64 readings would never end).
        let src = format!("X{}1 + [2 ** 1]{}", "[".repeat(63), "]".repeat(63));
        agrees_with_full_path(&src);
        let src = format!("X{}#1 ** 2{}", "[".repeat(70), "]".repeat(70));
        assert!(!agrees_with_full_path(&src));
        assert!(agrees_with_full_path(
            "G1 X[1 + #<_g>] Y[-2 * #2] Z[#<a> / 4]"
        ));
    }

    #[test]
    fn signs_count_towards_the_nesting_limit_as_in_the_full_path() {
        // A negative number read in one step must still fail exactly where the full path
        // runs out of nesting.
        let mut taken = 0;
        for n in MAX_NESTING.saturating_sub(3)..=MAX_NESTING + 1 {
            for src in [
                format!("X{}1.5", "-".repeat(n)),
                format!("X{}-1.5{}", "[".repeat(n), "]".repeat(n)),
                format!("X{}.5{}", "[-".repeat(n), "]".repeat(n)),
            ] {
                taken += usize::from(agrees_with_full_path(&src));
            }
        }
        assert!(taken > 0);
    }

    /// Expressions from the grammar, with blanks and case sprinkled in.
    fn expression() -> impl Strategy<Value = String> {
        let leaf = prop_oneof![
            "[0-9]{1,3}(\\.[0-9]{0,3})?",
            "#[1-7]",
            "#<(a|B|_g|_X| a |new)>",
            Just("#[1+1]".to_string()),
        ];
        leaf.prop_recursive(4, 24, 2, |inner| {
            prop_oneof![
                (
                    inner.clone(),
                    "( ?[-+*/] ?|\\*\\*| (mod|MOD|eq|ne|gt|ge|lt|le|and|or|xor|m od) )",
                    inner.clone()
                )
                    .prop_map(|(a, op, b)| format!("[{a}{op}{b}]")),
                // Chains of operators in one bracket: precedence and associativity.
                (
                    inner.clone(),
                    prop::collection::vec(
                        (
                            "( ?[-+*/] ?|\\*\\*| (mod|eq|ne|GT|ge|lt|le|and|or|xor) )",
                            inner.clone()
                        ),
                        2..6
                    )
                )
                    .prop_map(|(a, rest)| {
                        let rest: String =
                            rest.into_iter().map(|(op, b)| format!("{op}{b}")).collect();
                        format!("[{a}{rest}]")
                    }),
                (inner.clone(), "-|\\+| - ").prop_map(|(a, s)| format!("{s}{a}")),
                (
                    inner.clone(),
                    "(abs|sin|COS|tan|asin|acos|sqrt|ln|exp|fix|fup|round|exists)"
                )
                    .prop_map(|(a, f)| format!("{f}[{a}]")),
                (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("atan[{a}]/[{b}]")),
                inner.prop_map(|a| format!("#{a}")),
            ]
        })
    }

    fn line() -> impl Strategy<Value = String> {
        let item = prop_oneof![
            ("[gGxXyYfFzZnO]", " ?", expression()).prop_map(|(l, s, e)| format!("{l}{s}{e}")),
            ("#[1-6]|#<(a|b|_G|_x|new)>", " ?= ?", expression())
                .prop_map(|(t, eq, e)| format!("{t}{eq}{e}")),
            Just("(c)".to_string()),
        ];
        prop::collection::vec(item, 1..4).prop_map(|items| items.join(" "))
    }

    #[test]
    fn the_generated_lines_often_take_the_fast_path() {
        // Otherwise the properties below would compare nothing.
        let mut runner = proptest::test_runner::TestRunner::deterministic();
        let strategy = line();
        let taken = (0..1000)
            .filter(|_| {
                let src = proptest::strategy::ValueTree::current(
                    &strategy.new_tree(&mut runner).unwrap(),
                );
                agrees_with_full_path(&src)
            })
            .count();
        assert!(taken > 50, "only {taken} of 1000 lines took the fast path");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// Whatever the fast path takes, the full path takes too, with the same result.
        #[test]
        fn fast_path_never_disagrees_with_the_full_path(src in line()) {
            agrees_with_full_path(&src);
        }

        #[test]
        fn fast_path_never_disagrees_on_token_soup(src in "[gx#<>=\\[\\]+\\-*/0-9. abmodeqsinatn]{0,20}") {
            agrees_with_full_path(&src);
        }
    }
}
