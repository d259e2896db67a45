//! The syntax of one line before evaluation: what the parser builds and the executor runs.

use crate::diag::Span;

/// A unary function of LinuxCNC's expression language (angles in degrees).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Round,
    Ln,
    Sin,
    Sqrt,
    Tan,
}

/// Binary operators. Precedence (high to low): `**`; `*` `/` MOD; `+` `-`;
/// EQ NE GT GE LT LE; AND OR XOR. Equal precedence associates left (so `2**3**2` is 64).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl BinOp {
    pub fn precedence(self) -> u8 {
        match self {
            BinOp::Pow => 4,
            BinOp::Mul | BinOp::Div | BinOp::Mod => 3,
            BinOp::Add | BinOp::Sub => 2,
            BinOp::Eq | BinOp::Ne | BinOp::Gt | BinOp::Ge | BinOp::Lt | BinOp::Le => 1,
            BinOp::And | BinOp::Or | BinOp::Xor => 0,
        }
    }

    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Pow => "**",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "MOD",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Eq => "EQ",
            BinOp::Ne => "NE",
            BinOp::Gt => "GT",
            BinOp::Ge => "GE",
            BinOp::Lt => "LT",
            BinOp::Le => "LE",
            BinOp::And => "AND",
            BinOp::Or => "OR",
            BinOp::Xor => "XOR",
        }
    }
}

/// An expression; every node that can fail at evaluation keeps its span.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Num(f64),
    /// `#expr`: the numbered parameter whose number is the (integer) value of the operand.
    Param(Box<Expr>, Span),
    /// `#<name>`, name lower-cased without blanks.
    Named(String, Span),
    /// `EXISTS[#<name>]`
    Exists(String),
    /// `EXISTS[#expr]`: 1 when the number is a parameter's (1 to 5601), as rs274's
    /// `read_parameter` answers it; the number must still be an integer.
    ExistsNumbered(Box<Expr>, Span),
    Neg(Box<Expr>),
    Call(Func, Box<Expr>, Span),
    /// `ATAN[y]/[x]`
    Atan(Box<Expr>, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>, Span),
    /// `[expr]`: LinuxCNC checks that a bracketed value is finite (not between operators,
    /// so `[0**-1 NE 5]` is 1 but `[[0**-1] NE 5]` is an error).
    Group(Box<Expr>, Span),
}

/// A parameter being assigned.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// `#expr=`: the number is evaluated like any parameter number.
    Numbered(Box<Expr>),
    Named(String),
}

/// What a comment says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommentKind {
    Plain,
    /// `(MSG,…)`
    Message,
    /// `(DEBUG,…)`: parameters are substituted when the line runs.
    Debug,
    /// `(PRINT,…)`: like DEBUG, but rs274 writes it to its output, not as a canonical call.
    Print,
    /// `(ABORT,…)`: the program stops with this text (parameters substituted) as its error.
    Abort,
}

/// One element of a line, in source order (order matters: LinuxCNC evaluates left to right
/// and a named parameter being assigned counts as defined for the rest of its line).
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    Word {
        letter: char,
        value: Expr,
        span: Span,
    },
    Assign {
        target: Target,
        value: Expr,
        span: Span,
    },
    Comment {
        kind: CommentKind,
        text: String,
    },
}

/// O-word keywords.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keyword {
    Sub,
    EndSub,
    Call,
    Return,
    If,
    ElseIf,
    Else,
    EndIf,
    Do,
    While,
    EndWhile,
    Repeat,
    EndRepeat,
    Break,
    Continue,
}

impl Keyword {
    pub fn from_name(name: &[u8]) -> Option<Keyword> {
        Some(match name {
            b"sub" => Keyword::Sub,
            b"endsub" => Keyword::EndSub,
            b"call" => Keyword::Call,
            b"return" => Keyword::Return,
            b"if" => Keyword::If,
            b"elseif" => Keyword::ElseIf,
            b"else" => Keyword::Else,
            b"endif" => Keyword::EndIf,
            b"do" => Keyword::Do,
            b"while" => Keyword::While,
            b"endwhile" => Keyword::EndWhile,
            b"repeat" => Keyword::Repeat,
            b"endrepeat" => Keyword::EndRepeat,
            b"break" => Keyword::Break,
            b"continue" => Keyword::Continue,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Keyword::Sub => "sub",
            Keyword::EndSub => "endsub",
            Keyword::Call => "call",
            Keyword::Return => "return",
            Keyword::If => "if",
            Keyword::ElseIf => "elseif",
            Keyword::Else => "else",
            Keyword::EndIf => "endif",
            Keyword::Do => "do",
            Keyword::While => "while",
            Keyword::EndWhile => "endwhile",
            Keyword::Repeat => "repeat",
            Keyword::EndRepeat => "endrepeat",
            Keyword::Break => "break",
            Keyword::Continue => "continue",
        }
    }
}

/// `o100 while [#1 LT 3]`, `o<name> call [1] [2]`: a control-flow line.
#[derive(Clone, Debug, PartialEq)]
pub struct OWord {
    /// The label as LinuxCNC matches it: `o0100` and `o100` are both "100", `o<My Sub>` is
    /// "mysub".
    pub label: String,
    /// `o[expression]`: the label is the value of this expression, found when the line runs
    /// (`label` is empty until then).
    pub label_expr: Option<Expr>,
    pub keyword: Keyword,
    /// Bracketed arguments: the condition, the repeat count, call arguments, return value.
    pub args: Vec<Expr>,
    pub span: Span,
}

impl OWord {
    /// How the label is shown in messages: `o100` or `o<name>`.
    pub fn display_label(label: &str) -> String {
        if !label.is_empty() && label.bytes().all(|b| b.is_ascii_digit()) {
            format!("o{label}")
        } else {
            format!("o<{label}>")
        }
    }
}

/// One parsed line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Line {
    /// 1-based source line.
    pub line: u32,
    /// Starts with `/`.
    pub block_delete: bool,
    /// `%` alone: a program start/end marker.
    pub percent: bool,
    /// The `N` word's value, if any.
    pub n: Option<f64>,
    /// The O-word (control flow: sub, call, if, while, …), if any.
    pub oword: Option<OWord>,
    /// Words, assignments and comments, in source order.
    pub items: Vec<Item>,
}

impl Line {
    /// Empty the line for reuse as source line `line` (keeps the buffers).
    pub fn clear(&mut self, line: u32) {
        self.line = line;
        self.block_delete = false;
        self.percent = false;
        self.n = None;
        self.oword = None;
        self.items.clear();
    }

    /// Nothing to run: blank or only a block-delete slash.
    pub fn is_blank(&self) -> bool {
        !self.percent && self.n.is_none() && self.oword.is_none() && self.items.is_empty()
    }
}
