//! A compacted line → its syntax ([`crate::ast::Line`]), following LinuxCNC's reader:
//! optional `/`, optional `N`, then either one O-word (with its bracketed arguments) or
//! words and parameter assignments in any order, with comments anywhere.
//!
//! The grbl dialect has its own, smaller grammar ([`parse_grbl`]): letters and plain
//! numbers only, with grbl's error numbers.

use crate::ast::{BinOp, CommentKind, Expr, Func, Item, Keyword, Line, OWord, Target};
use crate::diag::{Diagnostic, Span};
use crate::lex::{comment_text, scan_number, Compact};
use crate::Dialect;

/// Brackets, unary signs and `#` may nest this deep: deeper is an error, never a stack
/// overflow.
pub(crate) const MAX_NESTING: usize = 64;

/// Parse one compacted line into `out` (cleared first; its buffers are reused).
pub fn parse_line(c: &Compact, dialect: Dialect, out: &mut Line) -> Result<(), Diagnostic> {
    out.clear(c.line);
    match dialect {
        Dialect::Grbl => parse_grbl(c, out),
        Dialect::LinuxCnc | Dialect::Legacy2006 | Dialect::Marlin => Parser {
            c,
            pos: 0,
            depth: 0,
        }
        .line(out),
    }
}

struct Parser<'a> {
    c: &'a Compact,
    pos: usize,
    depth: usize,
}

/// Words LinuxCNC reads (it rejects nothing else as a letter; `n` and `o` have places of
/// their own). `u`, `v`, `w` are accepted as axes here (LinuxCNC builds with nine axes);
/// `@` and `^` are the polar radius and angle of an XY end point.
fn is_word_letter(b: u8) -> bool {
    (b.is_ascii_lowercase() && b != b'n' && b != b'o') || b == b'@' || b == b'^'
}

/// A function name: the unary ones, and the two with their own syntax.
#[derive(Clone, Copy)]
enum FuncName {
    Unary(Func),
    /// `ATAN[y]/[x]`
    Atan,
    /// `EXISTS[#<name>]`
    Exists,
}

const FUNCS: [(&[u8], FuncName); 14] = [
    (b"abs", FuncName::Unary(Func::Abs)),
    (b"acos", FuncName::Unary(Func::Acos)),
    (b"asin", FuncName::Unary(Func::Asin)),
    (b"atan", FuncName::Atan),
    (b"cos", FuncName::Unary(Func::Cos)),
    (b"exists", FuncName::Exists),
    (b"exp", FuncName::Unary(Func::Exp)),
    (b"fix", FuncName::Unary(Func::Fix)),
    (b"fup", FuncName::Unary(Func::Fup)),
    (b"ln", FuncName::Unary(Func::Ln)),
    (b"round", FuncName::Unary(Func::Round)),
    (b"sin", FuncName::Unary(Func::Sin)),
    (b"sqrt", FuncName::Unary(Func::Sqrt)),
    (b"tan", FuncName::Unary(Func::Tan)),
];

/// The word operators (`[a MOD b]`, `[a EQ b]` …), lower case; shared with the direct path.
pub(crate) const WORD_OPS: [(&[u8], BinOp); 10] = [
    (b"mod", BinOp::Mod),
    (b"and", BinOp::And),
    (b"xor", BinOp::Xor),
    (b"eq", BinOp::Eq),
    (b"ne", BinOp::Ne),
    (b"gt", BinOp::Gt),
    (b"ge", BinOp::Ge),
    (b"lt", BinOp::Lt),
    (b"le", BinOp::Le),
    (b"or", BinOp::Or),
];

impl<'a> Parser<'a> {
    fn peek(&self) -> Option<u8> {
        self.c.bytes.get(self.pos).copied()
    }

    fn rest(&self) -> &'a [u8] {
        &self.c.bytes[self.pos.min(self.c.bytes.len())..]
    }

    fn span(&self, start: usize) -> Span {
        self.c.span(start, self.pos)
    }

    fn here(&self) -> Span {
        self.c.span(self.pos, self.pos + 1)
    }

    fn err_here(&self, message: impl Into<String>) -> Diagnostic {
        Diagnostic::error(self.here(), message)
    }

    fn line(mut self, out: &mut Line) -> Result<(), Diagnostic> {
        let bytes = &self.c.bytes;
        if bytes.as_slice() == b"%" {
            out.percent = true;
            return Ok(());
        }
        if self.peek() == Some(b'/') {
            out.block_delete = true;
            self.pos += 1;
        }
        if self.peek() == Some(b'n') {
            self.pos += 1;
            out.n = Some(self.line_number()?);
        }
        if self.peek() == Some(b'o') {
            out.oword = Some(self.oword(out)?);
            return self.comments_only(out);
        }
        while let Some(b) = self.peek() {
            let start = self.pos;
            match b {
                b'(' | b';' => self.comment(out),
                b'#' => {
                    let target = self.assign_target()?;
                    if self.peek() != Some(b'=') {
                        return Err(self
                            .err_here("expected '=' after the parameter of an assignment")
                            .with_help("write #1=5 or #<name>=[#1*2]; to use a value, put it in a word such as X#1"));
                    }
                    self.pos += 1;
                    let value = self.real_value()?;
                    out.items.push(Item::Assign {
                        target,
                        value,
                        span: self.span(start),
                    });
                }
                b'n' => {
                    return Err(self
                        .err_here("the line number N must come first on the line")
                        .with_help("move N… to the start of the line (after an optional '/')"))
                }
                b'o' => {
                    return Err(self
                        .err_here("an O-word must start the line (after an optional N…)")
                        .with_help("put the o-word on a line of its own"))
                }
                b if is_word_letter(b) => {
                    self.pos += 1;
                    let value = self.real_value()?;
                    out.items.push(Item::Word {
                        letter: b.to_ascii_uppercase() as char,
                        value,
                        span: self.span(start),
                    });
                }
                b'%' => {
                    return Err(self.err_here("bad character '%'").with_help(
                        "'%' marks the start and end of a program and must be alone on its line, \
                         the start one being the first non-blank line",
                    ))
                }
                other => return Err(self.bad_character(other)),
            }
        }
        Ok(())
    }

    fn bad_character(&self, b: u8) -> Diagnostic {
        let shown = if b.is_ascii_graphic() {
            format!("'{}'", b as char)
        } else {
            format!("0x{b:02X}")
        };
        self.err_here(format!("bad character {shown}"))
            .with_help("a line holds words (letter and value), #parameter assignments and comments")
    }

    fn comment(&mut self, out: &mut Line) {
        let start = self.pos;
        let bytes = &self.c.bytes;
        let end = if bytes[start] == b';' {
            bytes.len()
        } else {
            // Compaction guarantees the closing parenthesis.
            bytes[start..]
                .iter()
                .position(|&b| b == b')')
                .map_or(bytes.len(), |i| start + i + 1)
        };
        self.pos = end;
        if bytes[start] == b';' {
            // LinuxCNC ignores ';' comments entirely (no COMMENT, never a message).
            return;
        }
        let text = comment_text(&bytes[start..end]);
        let (kind, text) = classify_comment(text);
        out.items.push(Item::Comment { kind, text });
    }

    fn comments_only(&mut self, out: &mut Line) -> Result<(), Diagnostic> {
        while let Some(b) = self.peek() {
            if b == b'(' || b == b';' {
                self.comment(out);
            } else {
                return Err(self.err_here("unexpected text after the O-word").with_help(
                    "an o-word line holds only the o-word, its [arguments] and comments",
                ));
            }
        }
        Ok(())
    }

    /// `N` value: an unsigned number (LinuxCNC accepts a decimal part and ignores it).
    fn line_number(&mut self) -> Result<f64, Diagnostic> {
        let start = self.pos;
        match scan_number(self.rest()) {
            Some(Ok((v, len))) => {
                self.pos += len;
                Ok(v)
            }
            Some(Err(len)) => {
                self.pos += len;
                Err(Diagnostic::error(
                    self.span(start),
                    "bad line number after N",
                ))
            }
            None => Err(self
                .err_here("N must be followed by an unsigned line number")
                .with_help("write N10, N20, …")),
        }
    }

    fn oword(&mut self, out: &mut Line) -> Result<OWord, Diagnostic> {
        let start = self.pos;
        self.pos += 1;
        let mut label_expr = None;
        let label = match self.peek() {
            Some(b'<') => self.angle_name()?,
            // rs274 reads the number with read_integer_value: `o#<sub> call` as `o[#<sub>]`.
            Some(b'[' | b'#') => {
                label_expr = Some(self.real_value()?);
                String::new()
            }
            Some(b'0'..=b'9') => {
                let digits_start = self.pos;
                while matches!(self.peek(), Some(b'0'..=b'9')) {
                    self.pos += 1;
                }
                numeric_label(&self.c.bytes[digits_start..self.pos])
            }
            _ => {
                return Err(self
                    .err_here("expected a number or <name> after O")
                    .with_help("write o100 sub or o<name> sub"))
            }
        };
        let kw_start = self.pos;
        while matches!(self.peek(), Some(b'a'..=b'z')) {
            self.pos += 1;
        }
        let name = &self.c.bytes[kw_start..self.pos];
        let keyword = match Keyword::from_name(name) {
            Some(k) => k,
            None if name.is_empty() => {
                return Err(self
                    .err_here(format!(
                        "missing keyword after {}",
                        OWord::display_label(&label)
                    ))
                    .with_help(KEYWORD_HELP))
            }
            None => {
                return Err(Diagnostic::error(
                    self.span(kw_start),
                    format!("unknown o-word keyword '{}'", String::from_utf8_lossy(name)),
                )
                .with_help(KEYWORD_HELP))
            }
        };
        let mut args = Vec::new();
        match keyword {
            Keyword::If | Keyword::ElseIf | Keyword::While | Keyword::Repeat => {
                if self.peek() != Some(b'[') {
                    return Err(self
                        .err_here(format!("'{}' needs a bracketed expression", keyword.name()))
                        .with_help(format!("write o100 {} [#1 LT 3]", keyword.name())));
                }
                args.push(self.real_value()?);
            }
            Keyword::Call | Keyword::Return | Keyword::EndSub => {
                // rs274 reads comments between a call's arguments (read_o: read_comment).
                while matches!(self.peek(), Some(b'[' | b'(')) {
                    if self.peek() == Some(b'(') {
                        if keyword != Keyword::Call {
                            break;
                        }
                        self.comment(out);
                        continue;
                    }
                    if args.len() == crate::params::CALL_ARGS {
                        return Err(self.err_here(format!(
                            "too many arguments: at most {} (#1 to #{})",
                            crate::params::CALL_ARGS,
                            crate::params::CALL_ARGS
                        )));
                    }
                    args.push(self.real_value()?);
                }
                if keyword != Keyword::Call && args.len() > 1 {
                    return Err(Diagnostic::error(
                        self.span(kw_start),
                        format!("'{}' takes at most one [value]", keyword.name()),
                    ));
                }
            }
            _ => {}
        }
        Ok(OWord {
            label,
            label_expr,
            keyword,
            args,
            span: self.span(start),
        })
    }

    /// `<name>` → the name without blanks, lower-case (compaction did both).
    fn angle_name(&mut self) -> Result<String, Diagnostic> {
        let start = self.pos;
        self.pos += 1;
        let rest = self.rest();
        match rest
            .iter()
            .position(|&b| b == b'>' || b == b'(' || b == b';')
        {
            Some(i) if rest[i] == b'>' => {
                let name = String::from_utf8_lossy(&rest[..i]).into_owned();
                self.pos += i + 1;
                Ok(name)
            }
            _ => Err(Diagnostic::error(
                self.c.span(start, self.c.bytes.len()),
                "name not terminated: missing '>'",
            )
            .with_help("names are written #<name> or o<name>")),
        }
    }

    fn assign_target(&mut self) -> Result<Target, Diagnostic> {
        self.pos += 1; // '#'
        if self.peek() == Some(b'<') {
            Ok(Target::Named(self.angle_name()?))
        } else {
            Ok(Target::Numbered(Box::new(self.real_value()?)))
        }
    }

    fn enter(&mut self) -> Result<(), Diagnostic> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(self.err_here(format!(
                "expression nested deeper than {MAX_NESTING} levels"
            )));
        }
        Ok(())
    }

    /// A value: number, `[expression]`, `#parameter`, unary sign, or function.
    fn real_value(&mut self) -> Result<Expr, Diagnostic> {
        self.enter()?;
        let result = self.real_value_inner();
        self.depth -= 1;
        result
    }

    fn real_value_inner(&mut self) -> Result<Expr, Diagnostic> {
        let start = self.pos;
        match self.peek() {
            Some(b'[') => {
                self.pos += 1;
                let e = self.expression(0)?;
                self.close_bracket(start)?;
                Ok(Expr::Group(Box::new(e), self.span(start)))
            }
            Some(b'#') => {
                self.pos += 1;
                if self.peek() == Some(b'<') {
                    let name = self.angle_name()?;
                    Ok(Expr::Named(name, self.span(start)))
                } else {
                    let inner = self.real_value()?;
                    Ok(Expr::Param(Box::new(inner), self.span(start)))
                }
            }
            Some(b'-') => {
                self.pos += 1;
                Ok(Expr::Neg(Box::new(self.real_value()?)))
            }
            Some(b'+') => {
                self.pos += 1;
                self.real_value()
            }
            Some(b'0'..=b'9' | b'.') => match scan_number(self.rest()) {
                Some(Ok((v, len))) => {
                    self.pos += len;
                    Ok(Expr::Num(v))
                }
                Some(Err(len)) => {
                    self.pos += len;
                    Err(Diagnostic::error(self.span(start), "bad number format")
                        .with_help("a number is digits with at most one decimal point, e.g. 12.5"))
                }
                None => Err(self.err_here("expected a number")),
            },
            Some(b'a'..=b'z') => self.function(),
            None => Err(self
                .err_here("missing value at end of line")
                .with_help("a word needs a value: a number, #parameter or [expression]")),
            Some(b'(' | b';') => Err(self
                .err_here("missing value before the comment")
                .with_help("a word needs a value: a number, #parameter or [expression]")),
            Some(b) => Err(self
                .err_here(format!("expected a value, found '{}'", b as char))
                .with_help(
                    "a value is a number, #parameter, [expression] or a function like SIN[30]",
                )),
        }
    }

    fn close_bracket(&mut self, open: usize) -> Result<(), Diagnostic> {
        match self.peek() {
            Some(b']') => {
                self.pos += 1;
                Ok(())
            }
            None | Some(b'(' | b';') => Err(Diagnostic::error(
                self.c.span(open, self.pos),
                "unclosed expression: missing ']'",
            )),
            Some(_) => {
                let word: String = self
                    .rest()
                    .iter()
                    .take_while(|b| b.is_ascii_alphabetic())
                    .map(|&b| b as char)
                    .collect();
                let what = if word.is_empty() {
                    format!("'{}'", self.rest()[0] as char)
                } else {
                    format!("'{word}'")
                };
                Err(self
                    .err_here(format!("expected an operator or ']', found {what}"))
                    .with_help("operators: ** * / MOD + - EQ NE GT GE LT LE AND OR XOR"))
            }
        }
    }

    /// Precedence climbing, all operators left-associative (as LinuxCNC evaluates).
    fn expression(&mut self, min_prec: u8) -> Result<Expr, Diagnostic> {
        let start = self.pos;
        let mut lhs = self.real_value()?;
        while let Some((op, len)) = self.peek_binop() {
            if op.precedence() < min_prec {
                break;
            }
            self.pos += len;
            let rhs = self.expression(op.precedence() + 1)?;
            lhs = Expr::Binary(op, Box::new(lhs), Box::new(rhs), self.span(start));
        }
        Ok(lhs)
    }

    fn peek_binop(&self) -> Option<(BinOp, usize)> {
        let rest = self.rest();
        match rest.first()? {
            b'*' if rest.get(1) == Some(&b'*') => Some((BinOp::Pow, 2)),
            b'*' => Some((BinOp::Mul, 1)),
            b'/' => Some((BinOp::Div, 1)),
            b'+' => Some((BinOp::Add, 1)),
            b'-' => Some((BinOp::Sub, 1)),
            _ => WORD_OPS
                .iter()
                .find(|(name, _)| rest.starts_with(name))
                .map(|&(name, op)| (op, name.len())),
        }
    }

    fn function(&mut self) -> Result<Expr, Diagnostic> {
        let start = self.pos;
        let rest = self.rest();
        let Some(&(name, func)) = FUNCS.iter().find(|(name, _)| rest.starts_with(name)) else {
            let word: String = rest
                .iter()
                .take_while(|b| b.is_ascii_alphabetic())
                .map(|&b| b as char)
                .collect();
            return Err(self
                .err_here(format!("unknown function '{word}'"))
                .with_help(
                    "functions: ABS ACOS ASIN ATAN COS EXP EXISTS FIX FUP LN ROUND SIN SQRT TAN",
                ));
        };
        self.pos += name.len();
        if self.peek() != Some(b'[') {
            return Err(self.err_here(format!(
                "'{}' must be followed by '['",
                String::from_utf8_lossy(name).to_uppercase()
            )));
        }
        match func {
            FuncName::Atan => {
                let y = self.real_value()?;
                if self.peek() != Some(b'/') {
                    return Err(self.err_here("ATAN needs two arguments: ATAN[y]/[x]"));
                }
                self.pos += 1;
                if self.peek() != Some(b'[') {
                    return Err(self.err_here("ATAN needs two arguments: ATAN[y]/[x]"));
                }
                let x = self.real_value()?;
                Ok(Expr::Atan(Box::new(y), Box::new(x)))
            }
            FuncName::Exists => {
                self.pos += 1;
                if self.peek() != Some(b'#') {
                    return Err(
                        self.err_here("EXISTS takes a parameter: EXISTS[#<name>] or EXISTS[#1]")
                    );
                }
                self.pos += 1;
                if self.peek() == Some(b'<') {
                    let name = self.angle_name()?;
                    self.close_bracket(start)?;
                    return Ok(Expr::Exists(name));
                }
                let inner = self.real_value()?;
                self.close_bracket(start)?;
                Ok(Expr::ExistsNumbered(Box::new(inner), self.span(start)))
            }
            FuncName::Unary(f) => {
                let arg = self.real_value()?;
                Ok(Expr::Call(f, Box::new(arg), self.span(start)))
            }
        }
    }
}

/// The label and keyword of an o-word line, if the line is one: all that matters while
/// skipping lines (a false `if`, a subroutine body, a loop being left). Arguments are not
/// parsed, so a broken skipped line cannot stop the search.
pub(crate) fn oword_head(c: &Compact) -> Option<(String, Keyword)> {
    let mut p = Parser {
        c,
        pos: 0,
        depth: 0,
    };
    if p.peek() == Some(b'/') {
        p.pos += 1;
    }
    if p.peek() == Some(b'n') {
        p.pos += 1;
        p.line_number().ok()?;
    }
    if p.peek() != Some(b'o') {
        return None;
    }
    p.pos += 1;
    let label = match p.peek() {
        Some(b'<') => p.angle_name().ok()?,
        Some(b'0'..=b'9') => {
            let start = p.pos;
            while matches!(p.peek(), Some(b'0'..=b'9')) {
                p.pos += 1;
            }
            numeric_label(&c.bytes[start..p.pos])
        }
        _ => return None,
    };
    let start = p.pos;
    while matches!(p.peek(), Some(b'a'..=b'z')) {
        p.pos += 1;
    }
    Keyword::from_name(&c.bytes[start..p.pos]).map(|k| (label, k))
}

/// The label of a Fanuc-style program or subprogram number line, `O0100` or `O100 (NAME)`:
/// an o-word with no keyword, at most a comment after it.
pub(crate) fn bare_oword(c: &Compact) -> Option<String> {
    let b = &c.bytes;
    let mut i = usize::from(b.first() == Some(&b'/'));
    if b.get(i) == Some(&b'n') {
        i += 1;
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
    }
    if b.get(i) != Some(&b'o') {
        return None;
    }
    let start = i + 1;
    // `O<name>`: a named program, as rs274 reads a bare o-word with a name.
    if b.get(start) == Some(&b'<') {
        let close = start + b[start..].iter().position(|&x| x == b'>')?;
        if close == start + 1 || !matches!(b.get(close + 1), None | Some(b'(' | b';')) {
            return None;
        }
        return Some(String::from_utf8_lossy(&b[start + 1..close]).into_owned());
    }
    let end = start + b[start..].iter().take_while(|d| d.is_ascii_digit()).count();
    if end == start || !matches!(b.get(end), None | Some(b'(' | b';')) {
        return None;
    }
    Some(numeric_label(&b[start..end]))
}

/// `0100` and `100` name the same o-word.
fn numeric_label(digits: &[u8]) -> String {
    let trimmed = match digits.iter().position(|&d| d != b'0') {
        Some(i) => &digits[i..],
        None => &digits[digits.len().saturating_sub(1)..],
    };
    String::from_utf8_lossy(trimmed).into_owned()
}

const KEYWORD_HELP: &str = "o-word keywords: sub endsub call return if elseif else endif do while endwhile repeat endrepeat break continue";

/// `(MSG,…)`, `(DEBUG,…)`, `(PRINT,…)` (case-insensitive, blanks allowed before the keyword)
/// become messages; the text after the comma is kept as written. A plain comment loses its
/// leading blanks, as rs274's `convert_comment` steps over them (`( note)` is `COMMENT("note")`).
fn classify_comment(text: String) -> (CommentKind, String) {
    let trimmed = text.trim_start_matches(|c: char| c.is_ascii_whitespace());
    for (key, kind) in [
        ("msg,", CommentKind::Message),
        ("debug,", CommentKind::Debug),
        ("print,", CommentKind::Print),
        ("abort,", CommentKind::Abort),
    ] {
        if trimmed.len() >= key.len()
            && trimmed.as_bytes()[..key.len()].eq_ignore_ascii_case(key.as_bytes())
        {
            return (kind, trimmed[key.len()..].to_string());
        }
    }
    (CommentKind::Plain, trimmed.to_string())
}

/// grbl 1.1's reader: comments and blanks dropped, `/` ignored, then letter + number pairs.
/// Anything else gets grbl's error number: 1 (expected command letter), 2 (bad number
/// format), 11 (line longer than grbl's 80-byte buffer), 20 (unsupported command letter).
fn parse_grbl(c: &Compact, out: &mut Line) -> Result<(), Diagnostic> {
    const LINE_BUFFER: usize = 80;
    let b = &c.bytes;
    // Count what grbl would keep in its line buffer (comments as `Compact::load_grbl` cut
    // them: to the first ')' or the end of the line).
    let mut kept = 0usize;
    let mut in_comment = false;
    for &x in b.iter() {
        match x {
            b'(' if !in_comment => in_comment = true,
            b')' if in_comment => in_comment = false,
            b';' if !in_comment => break,
            b'/' if !in_comment => {}
            _ if !in_comment => kept += 1,
            _ => {}
        }
    }
    if kept >= LINE_BUFFER {
        return Err(Diagnostic::error(
            Span::line(c.line),
            format!(
                "line overflow: {kept} characters, grbl keeps at most {}",
                LINE_BUFFER - 1
            ),
        )
        .with_help("split the line; grbl counts characters after removing blanks and comments")
        .with_code(11));
    }
    let mut i = 0;
    while i < b.len() {
        let start = i;
        match b[i] {
            b'/' => i += 1,
            b'(' => {
                let end = b[i..]
                    .iter()
                    .position(|&x| x == b')')
                    .map_or(b.len(), |k| i + k + 1);
                let (kind, text) = classify_comment(comment_text(&b[i..end]));
                // grbl drops comments; MSG is still shown to the operator by senders.
                out.items.push(Item::Comment { kind, text });
                i = end;
            }
            b';' => break,
            letter if letter.is_ascii_lowercase() => {
                i += 1;
                // grbl's read_float: optional sign, digits with one optional point.
                let mut j = i;
                let negative = matches!(b.get(j), Some(b'-'));
                if matches!(b.get(j), Some(b'-' | b'+')) {
                    j += 1;
                }
                let value = match scan_number(&b[j..]) {
                    Some(Ok((v, len))) => {
                        j += len;
                        if negative { -v } else { v }
                    }
                    Some(Err(len)) if b[j..j + len].iter().any(u8::is_ascii_digit) => {
                        // grbl stops at the second point; the point then is not a letter.
                        let ok = len - 1;
                        let v = scan_number(&b[j..j + ok]).and_then(Result::ok).map_or(0.0, |r| r.0);
                        j += ok;
                        if negative { -v } else { v }
                    }
                    _ => {
                        return Err(Diagnostic::error(c.span(start, j.max(i)), format!("bad number format after '{}'", letter.to_ascii_uppercase() as char))
                            .with_help("grbl needs a plain number after each letter: no #parameters or [expressions]")
                            .with_code(2))
                    }
                };
                i = j;
                let span = c.span(start, i);
                let upper = letter.to_ascii_uppercase() as char;
                match upper {
                    'N' => {
                        // grbl's order of checks: repeated word (25), negative (4), too big (27);
                        // a fraction is truncated.
                        if out.n.is_some() {
                            return Err(Diagnostic::error(span, "repeated N word")
                                .with_help("one line number per line")
                                .with_code(25));
                        }
                        if value < 0.0 {
                            return Err(Diagnostic::error(span, "negative line number")
                                .with_help("grbl line numbers are 0 to 10000000")
                                .with_code(4));
                        }
                        if value > 10_000_000.0 {
                            return Err(Diagnostic::error(span, "line number value is invalid")
                                .with_help("grbl line numbers are 0 to 10000000")
                                .with_code(27));
                        }
                        out.n = Some(value.trunc());
                    }
                    'G' | 'M' | 'F' | 'I' | 'J' | 'K' | 'L' | 'P' | 'R' | 'S' | 'T' | 'X' | 'Y'
                    | 'Z' => {
                        out.items.push(Item::Word {
                            letter: upper,
                            value: Expr::Num(value),
                            span,
                        });
                    }
                    _ => {
                        return Err(Diagnostic::error(
                            span,
                            format!("unsupported command letter '{upper}'"),
                        )
                        .with_help(grbl_letter_hint(upper))
                        .with_code(20))
                    }
                }
            }
            other => {
                let shown = if other.is_ascii_graphic() {
                    format!("'{}'", other as char)
                } else {
                    format!("0x{other:02X}")
                };
                let help = match other {
                    b'#' => "grbl has no #parameters",
                    b'[' | b']' => "grbl has no [expressions]",
                    b'%' => "grbl does not accept '%' program markers; remove the line",
                    _ => "grbl expects a letter followed by a number",
                };
                return Err(Diagnostic::error(
                    c.span(i, i + 1),
                    format!("expected command letter, found {shown}"),
                )
                .with_help(help)
                .with_code(1));
            }
        }
    }
    Ok(())
}

/// Why a post-processor writes a letter grbl 1.1 does not know, and what to do.
fn grbl_letter_hint(letter: char) -> &'static str {
    match letter {
        'H' => {
            "grbl 1.1 knows the letters F G I J K L M N P R S T X Y Z; H is a tool length offset \
             from a tool table (G43 H, a LinuxCNC or Fanuc post): remove it or choose a grbl post"
        }
        'D' => {
            "grbl 1.1 knows the letters F G I J K L M N P R S T X Y Z; D is a cutter \
             compensation register (G41/G42 D): let the CAM offset the path or choose a grbl post"
        }
        'O' => {
            "grbl 1.1 knows the letters F G I J K L M N P R S T X Y Z; O is a program number or \
             subroutine (a Fanuc or LinuxCNC post): remove the line or choose a grbl post"
        }
        _ => "grbl 1.1 knows the letters F G I J K L M N P R S T X Y Z",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(s: &str) -> Result<Line, Diagnostic> {
        parse_in(s, Dialect::LinuxCnc)
    }

    fn parse_in(s: &str, d: Dialect) -> Result<Line, Diagnostic> {
        let mut c = Compact::new();
        if d == Dialect::Grbl {
            c.load_grbl(s.as_bytes(), 1);
        } else {
            c.load(s.as_bytes(), 1)?;
        }
        let mut line = Line::default();
        parse_line(&c, d, &mut line)?;
        Ok(line)
    }

    fn word(line: &Line, i: usize) -> (char, Expr) {
        match &line.items[i] {
            Item::Word { letter, value, .. } => (*letter, value.clone()),
            other => panic!("not a word: {other:?}"),
        }
    }

    #[test]
    fn plain_words_with_spaces_inside_numbers() {
        let l = parse("n10 G 0 1 X1 0.5 y-2").unwrap();
        assert_eq!(l.n, Some(10.0));
        assert_eq!(word(&l, 0), ('G', Expr::Num(1.0)));
        assert_eq!(word(&l, 1), ('X', Expr::Num(10.5)));
        assert_eq!(word(&l, 2), ('Y', Expr::Neg(Box::new(Expr::Num(2.0)))));
        match &l.items[1] {
            Item::Word { span, .. } => assert_eq!(*span, Span::new(1, 11, 6)),
            _ => unreachable!(),
        }
    }

    #[test]
    fn precedence_and_left_associativity() {
        let ungroup = |e: Expr| match e {
            Expr::Group(inner, _) => *inner,
            other => other,
        };
        let l = parse("X[1+2*3**2]").unwrap();
        let e = ungroup(word(&l, 0).1);
        match e {
            Expr::Binary(BinOp::Add, _, rhs, _) => {
                assert!(matches!(*rhs, Expr::Binary(BinOp::Mul, ..)))
            }
            other => panic!("{other:?}"),
        }
        let l = parse("X[2**3**2]").unwrap();
        match ungroup(word(&l, 0).1) {
            Expr::Binary(BinOp::Pow, lhs, _, _) => {
                assert!(matches!(*lhs, Expr::Binary(BinOp::Pow, ..)))
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn operators_and_functions_are_found_by_prefix_without_spaces() {
        assert!(parse("X[1 EQ EXISTS[#<a>]]").is_ok());
        assert!(parse("X[#1lt3]").is_ok());
        assert!(parse("X[ATAN[1]/[2]]").is_ok());
        let e = parse("X[1 E 1]").unwrap_err();
        assert!(e.message.contains("operator"), "{}", e.message);
        let e = parse("X[FOO[1]]").unwrap_err();
        assert!(
            e.message.contains("unknown function 'foo'"),
            "{}",
            e.message
        );
    }

    #[test]
    fn assignments_comments_and_messages() {
        let l = parse("#1=2 #<My Var>=[#1*2] (MSG, hello) ; ignored").unwrap();
        assert!(matches!(
            &l.items[0],
            Item::Assign {
                target: Target::Numbered(_),
                ..
            }
        ));
        assert!(
            matches!(&l.items[1], Item::Assign { target: Target::Named(n), .. } if n == "myvar")
        );
        assert_eq!(
            l.items[2],
            Item::Comment {
                kind: CommentKind::Message,
                text: " hello".into()
            }
        );
        assert_eq!(l.items.len(), 3);
        let l = parse("( debug,x=#1)").unwrap();
        assert_eq!(
            l.items[0],
            Item::Comment {
                kind: CommentKind::Debug,
                text: "x=#1".into()
            }
        );
    }

    #[test]
    fn owords() {
        let l = parse("o0100 while [#1 LT 3] (loop)").unwrap();
        let o = l.oword.unwrap();
        assert_eq!(
            (o.label.as_str(), o.keyword, o.args.len()),
            ("100", Keyword::While, 1)
        );
        let l = parse("N5 o<My Sub> call [1] [2+3]").unwrap();
        let o = l.oword.unwrap();
        assert_eq!(
            (o.label.as_str(), o.keyword, o.args.len()),
            ("mysub", Keyword::Call, 2)
        );
        assert!(parse("o1 if 1").unwrap_err().message.contains("bracketed"));
        assert!(parse("o1 if [1] G0")
            .unwrap_err()
            .message
            .contains("after the O-word"));
        assert!(parse("o1 foo")
            .unwrap_err()
            .message
            .contains("unknown o-word keyword 'foo'"));
        assert!(parse("G0 o1 if [1]")
            .unwrap_err()
            .message
            .contains("must start the line"));
    }

    #[test]
    fn errors_name_the_place() {
        let e = parse("G0 X[1").unwrap_err();
        assert_eq!(
            (e.span.col, e.message.as_str()),
            (5, "unclosed expression: missing ']'")
        );
        let e = parse("G0 X").unwrap_err();
        assert_eq!(e.span.col, 5);
        let e = parse("G0 X1..2").unwrap_err();
        assert_eq!(e.span, Span::new(1, 5, 3));
        let e = parse("G0 N10").unwrap_err();
        assert_eq!(e.span.col, 4);
        let e = parse("G0 X1 %").unwrap_err();
        assert!(e.message.contains('%'));
        let deep = format!("X{}1{}", "[".repeat(100), "]".repeat(100));
        assert!(parse(&deep).unwrap_err().message.contains("nested"));
        let minus = format!("X{}1", "-".repeat(1000));
        assert!(parse(&minus).is_err());
    }

    #[test]
    fn grbl_accepts_plain_words_and_rejects_the_rest_with_codes() {
        let l = parse_in("N5 G1 X-1.5 Y+2 F100 (c) ; x", Dialect::Grbl).unwrap();
        assert_eq!(l.n, Some(5.0));
        assert_eq!(word(&l, 1), ('X', Expr::Num(-1.5)));
        let code = |s: &str| parse_in(s, Dialect::Grbl).unwrap_err().code;
        assert_eq!(code("G1 X#1"), Some(2));
        assert_eq!(code("G1 X[1]"), Some(2));
        assert_eq!(code("#1=2"), Some(1));
        assert_eq!(code("G1 A1"), Some(20));
        assert_eq!(code("o100 sub"), Some(20));
        assert_eq!(code("G1 X"), Some(2));
        assert_eq!(code("%"), Some(1));
        assert!(parse_in("G1 X1 (open comment", Dialect::Grbl).is_ok());
        assert_eq!(
            code("G1 (a(b)c) X1"),
            Some(2),
            "grbl: the comment ends at b), then C has no number"
        );
        assert_eq!(code("G1 X1 µ"), Some(1));
        assert_eq!(code(&format!("G1 X{}", "1".repeat(90))), Some(11));
        assert_eq!(code("N-1 G1 X1"), Some(4));
        assert_eq!(code("N20000000 G1 X1"), Some(27));
        assert_eq!(code("N1 G1 N2"), Some(25));
        assert_eq!(
            code("G1 X1.2.3"),
            Some(1),
            "grbl reads X1.2, then '.' is no letter"
        );
        assert_eq!(parse_in("N1.5 G1", Dialect::Grbl).unwrap().n, Some(1.0));
    }
}
