//! Macros: named G-code snippets the page keeps (as `macros.json` in the job folder) and
//! runs through typed lines. Their parameters in brackets are replaced first, from where the
//! machine is: `[x]` `[y]` `[z]` (work position), `[mx]` `[my]` `[mz]` (machine position),
//! `[prb_x]` `[prb_y]` `[prb_z]` (the last probe, machine coordinates), with `+ - * /`,
//! parentheses and numbers, e.g. `G0 X[x+1] Z[prb_z - 2]`.

use crate::offsets::Probe;
use crate::Error;
use serde::{Deserialize, Serialize};

/// The file the macros are kept in, in the job folder.
pub const MACROS_FILE: &str = "macros.json";
/// Most macros kept.
const MAX_MACROS: usize = 100;
/// Longest macro name, characters.
const MAX_NAME: usize = 40;
/// Longest macro text, bytes.
const MAX_TEXT: usize = 10_000;

/// One macro: a name for its button and the G-code it sends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Macro {
    /// The button's label.
    pub name: String,
    /// G-code lines (or `$` commands), with bracketed parameters.
    pub text: String,
}

/// The values a macro's parameters take.
#[derive(Clone, Debug, PartialEq)]
pub struct MacroValues {
    /// Work position, mm.
    pub work: [f64; 3],
    /// Machine position, mm.
    pub machine: [f64; 3],
    /// The last probe, when the machine reported one.
    pub probe: Option<Probe>,
}

/// Checks a list of macros before it is kept: names given, short and unique, texts of a
/// sensible size, and every parameter one the expansion knows.
pub fn check_macros(macros: &[Macro]) -> Result<(), Error> {
    if macros.len() > MAX_MACROS {
        return Err(Error(format!(
            "{} macros: at most {MAX_MACROS}",
            macros.len()
        )));
    }
    for (i, m) in macros.iter().enumerate() {
        let name = m.name.trim();
        if name.is_empty() || name.chars().count() > MAX_NAME || name.chars().any(char::is_control)
        {
            return Err(Error(format!(
                "macro {}: a name of 1 to {MAX_NAME} characters, one line",
                i + 1
            )));
        }
        if macros[..i].iter().any(|o| o.name.trim() == name) {
            return Err(Error(format!("macro {name:?}: two macros have that name")));
        }
        if m.text.len() > MAX_TEXT {
            return Err(Error(format!(
                "macro {name:?}: {} bytes of text, at most {MAX_TEXT}",
                m.text.len()
            )));
        }
        // Every parameter is known (values are the machine's, any will do here).
        let values = MacroValues {
            work: [0.0; 3],
            machine: [0.0; 3],
            probe: Some(Probe {
                pos: [0.0; 3],
                touched: true,
            }),
        };
        expand(&m.text, &values).map_err(|e| Error(format!("macro {name:?}: {}", e.0)))?;
    }
    Ok(())
}

/// The lines a macro sends: parameters replaced, blank lines dropped, comments kept as
/// typed. An unknown parameter, a probe value without a probe, or a bad expression is an
/// error naming the line.
pub fn expand(text: &str, values: &MacroValues) -> Result<Vec<String>, Error> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let expanded =
            expand_line(line, values).map_err(|e| Error(format!("line {}: {e}", n + 1)))?;
        out.push(expanded);
    }
    Ok(out)
}

fn expand_line(line: &str, values: &MacroValues) -> Result<String, String> {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    while let Some(i) = rest.find(['[', '(', ';']) {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        match rest.as_bytes()[i] {
            // Comments go as they are.
            b';' => {
                out.push_str(&rest[i..]);
                return Ok(out);
            }
            b'(' => {
                let end = after.find(')').map_or(after.len(), |e| e + 1);
                out.push_str(&rest[i..i + 1 + end]);
                rest = &after[end..];
            }
            _ => {
                let end = after
                    .find(']')
                    .ok_or_else(|| format!("`[{after}`: no closing ]"))?;
                let v = eval(&after[..end], values)?;
                out.push_str(&number(v));
                rest = &after[end + 1..];
            }
        }
    }
    out.push_str(rest);
    Ok(out)
}

/// A value as G-code writes it: up to 4 decimals, no trailing zeros, never `-0`.
fn number(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

const NAMES: &str =
    "x, y, z (work position), mx, my, mz (machine position), prb_x, prb_y, prb_z (last probe)";

fn param(name: &str, v: &MacroValues) -> Result<f64, String> {
    let name = name.to_ascii_lowercase();
    let axis = |s: &str| ["x", "y", "z"].iter().position(|a| *a == s);
    if let Some(i) = axis(&name) {
        return Ok(v.work[i]);
    }
    if let Some(i) = name.strip_prefix('m').and_then(axis) {
        return Ok(v.machine[i]);
    }
    if let Some(i) = name.strip_prefix("prb_").and_then(axis) {
        return match &v.probe {
            Some(p) if p.touched => Ok(p.pos[i]),
            Some(_) => Err(format!(
                "[{name}]: the last probe did not touch anything; probe again first"
            )),
            None => Err(format!("[{name}]: this machine has reported no probe yet")),
        };
    }
    Err(format!("unknown parameter [{name}]: use {NAMES}"))
}

/// `+ - * /`, unary minus, parentheses, numbers and parameter names.
fn eval(expr: &str, values: &MacroValues) -> Result<f64, String> {
    let mut p = Parser {
        s: expr.as_bytes(),
        at: 0,
        values,
        expr,
    };
    let v = p.sum()?;
    p.space();
    if p.at != p.s.len() {
        return Err(format!("[{expr}]: unexpected `{}`", &expr[p.at..]));
    }
    if !v.is_finite() {
        return Err(format!("[{expr}]: not a finite number"));
    }
    Ok(v)
}

struct Parser<'a> {
    s: &'a [u8],
    at: usize,
    values: &'a MacroValues,
    expr: &'a str,
}

impl Parser<'_> {
    fn space(&mut self) {
        while self.s.get(self.at).is_some_and(u8::is_ascii_whitespace) {
            self.at += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.space();
        self.s.get(self.at).copied()
    }

    fn sum(&mut self) -> Result<f64, String> {
        let mut v = self.product()?;
        while let Some(op @ (b'+' | b'-')) = self.peek() {
            self.at += 1;
            let r = self.product()?;
            v = if op == b'+' { v + r } else { v - r };
        }
        Ok(v)
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.factor()?;
        while let Some(op @ (b'*' | b'/')) = self.peek() {
            self.at += 1;
            let r = self.factor()?;
            v = if op == b'*' { v * r } else { v / r };
        }
        Ok(v)
    }

    fn factor(&mut self) -> Result<f64, String> {
        match self.peek() {
            Some(b'-') => {
                self.at += 1;
                Ok(-self.factor()?)
            }
            Some(b'+') => {
                self.at += 1;
                self.factor()
            }
            Some(b'(') => {
                self.at += 1;
                let v = self.sum()?;
                if self.peek() != Some(b')') {
                    return Err(format!("[{}]: a ( without its )", self.expr));
                }
                self.at += 1;
                Ok(v)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                let start = self.at;
                while self
                    .s
                    .get(self.at)
                    .is_some_and(|c| c.is_ascii_digit() || *c == b'.')
                {
                    self.at += 1;
                }
                let text = &self.expr[start..self.at];
                text.parse()
                    .map_err(|_| format!("[{}]: `{text}` is not a number", self.expr))
            }
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => {
                let start = self.at;
                while self
                    .s
                    .get(self.at)
                    .is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_')
                {
                    self.at += 1;
                }
                param(&self.expr[start..self.at], self.values)
            }
            _ => Err(format!(
                "[{}]: a number or a parameter expected ({NAMES})",
                self.expr
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values() -> MacroValues {
        MacroValues {
            work: [1.5, -2.0, 3.0],
            machine: [11.5, 8.0, -7.0],
            probe: Some(Probe {
                pos: [4.0, 5.0, -12.25],
                touched: true,
            }),
        }
    }

    #[test]
    fn parameters_and_expressions_are_replaced() {
        let text = "G0 X[x+1] Y[y]\n\n  G53 G0 Z[mz]\nG0 Z[prb_z - 2] (probe [z])\nG1 X[(x + 0.5) * 2] F[100/4] ; at [x]\n";
        assert_eq!(
            expand(text, &values()).unwrap(),
            [
                "G0 X2.5 Y-2",
                "G53 G0 Z-7",
                "G0 Z-14.25 (probe [z])",
                "G1 X4 F25 ; at [x]"
            ]
        );
        assert_eq!(
            expand("G0 X[-x] Y[PRB_Y]", &values()).unwrap(),
            ["G0 X-1.5 Y5"]
        );
        assert_eq!(number(-0.00001), "0");
        assert_eq!(number(1.23456), "1.2346");
    }

    #[test]
    fn unknown_parameters_and_bad_expressions_are_named() {
        let e = expand("G0 X0\nG0 X[foo]", &values()).unwrap_err().0;
        assert!(e.starts_with("line 2: unknown parameter [foo]"), "{e}");
        assert!(e.contains("prb_x"), "{e}");
        for bad in [
            "G0 X[x",
            "G0 X[x+]",
            "G0 X[1/0]",
            "G0 X[(x]",
            "G0 X[x y]",
            "G0 X[]",
        ] {
            assert!(expand(bad, &values()).is_err(), "{bad}");
        }
        let mut v = values();
        v.probe = None;
        let e = expand("G0 Z[prb_z]", &v).unwrap_err().0;
        assert!(e.contains("no probe"), "{e}");
        v.probe = Some(Probe {
            pos: [0.0; 3],
            touched: false,
        });
        assert!(expand("G0 Z[prb_z]", &v)
            .unwrap_err()
            .0
            .contains("did not touch"));
    }

    #[test]
    fn lists_are_checked_before_they_are_kept() {
        let m = |name: &str, text: &str| Macro {
            name: name.into(),
            text: text.into(),
        };
        assert!(check_macros(&[m("Park", "G53 G0 Z-1"), m("Probe", "G0 Z[prb_z]")]).is_ok());
        assert!(check_macros(&[m("", "G0")]).is_err());
        assert!(check_macros(&[m("a", "G0"), m("a", "G1")])
            .unwrap_err()
            .0
            .contains("two macros"));
        let e = check_macros(&[m("Bad", "G0 X[q]")]).unwrap_err().0;
        assert!(e.contains("\"Bad\"") && e.contains("[q]"), "{e}");
        assert!(check_macros(&[m("Big", &"G0\n".repeat(5000))]).is_err());
    }
}
