//! Expression evaluation with LinuxCNC's rules: angles in degrees, EQ/NE within 1e-4,
//! MOD with the sign of a positive divisor, ROUND half away from zero, parameter numbers
//! that must be integers within 1e-4, and clear errors instead of NaN or infinity.

mod trig;

use crate::ast::{BinOp, Expr, Func};
use crate::diag::{Diagnostic, Span};
use crate::params::{ParamError, Params};

/// LinuxCNC's TOLERANCE_EQUAL: EQ and NE compare within this.
const EQUAL_TOLERANCE: f64 = 0.0001;
/// How far from an integer a parameter number may be (LinuxCNC's read_integer_value).
const INTEGER_TOLERANCE: f64 = 0.0001;
/// LinuxCNC rejects #0 and everything from #5602 on (RS274NGC_MAX_PARAMETERS is 5602).
pub(crate) const LAST_NUMBERED: i64 = 5601;

pub(crate) fn eval(e: &Expr, p: &Params) -> Result<f64, Diagnostic> {
    match e {
        Expr::Num(v) => Ok(*v),
        Expr::Param(index, span) => {
            let n = param_number(index, *span, p)?;
            p.get(n).map_err(|err| param_error(err, *span))
        }
        Expr::Named(name, span) => p.get_named(name).map_err(|err| param_error(err, *span)),
        Expr::Exists(name) => Ok(if p.exists_named(name) { 1.0 } else { 0.0 }),
        Expr::ExistsNumbered(index, span) => {
            let n = integer(index, *span, p)?;
            Ok(if (1..=LAST_NUMBERED).contains(&n) {
                1.0
            } else {
                0.0
            })
        }
        Expr::Neg(inner) => Ok(-eval(inner, p)?),
        Expr::Call(f, arg, span) => call(*f, eval(arg, p)?, *span),
        Expr::Atan(y, x) => Ok(degrees(eval(y, p)?.atan2(eval(x, p)?))),
        Expr::Binary(op, a, b, span) => binary(*op, eval(a, p)?, eval(b, p)?, *span),
        Expr::Group(inner, span) => {
            let v = eval(inner, p)?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(not_finite(v, *span))
            }
        }
    }
}

/// Evaluate the number of a numbered parameter (`#expr`): an integer within 1e-4.
pub(crate) fn param_number(index: &Expr, span: Span, p: &Params) -> Result<i64, Diagnostic> {
    let n = integer(index, span, p)?;
    if !(1..=LAST_NUMBERED).contains(&n) {
        return Err(param_error(ParamError::OutOfRange(n), span));
    }
    Ok(n)
}

/// A parameter number before its range is checked: an integer within 1e-4.
fn integer(index: &Expr, span: Span, p: &Params) -> Result<i64, Diagnostic> {
    let v = eval(index, p)?;
    let r = v.round();
    if (v - r).abs() > INTEGER_TOLERANCE || !r.is_finite() {
        return Err(
            Diagnostic::error(span, format!("parameter number {v} is not an integer")).with_help(
                "numbered parameters are #1 to #5601; use FIX[…] or ROUND[…] on computed numbers",
            ),
        );
    }
    Ok(r.clamp(i64::MIN as f64, i64::MAX as f64) as i64)
}

pub(crate) fn param_error(err: ParamError, span: Span) -> Diagnostic {
    let help = match &err {
        ParamError::OutOfRange(n) => {
            format!("numbered parameters are #1 to #{LAST_NUMBERED}, not #{n}")
        }
        ParamError::Undefined(name) => {
            format!("assign it first (#<{name}>=…) or test it with EXISTS[#<{name}>]")
        }
        ParamError::ReadOnly(_) => "parameters set by the interpreter can only be read".to_string(),
    };
    let message = match &err {
        ParamError::OutOfRange(n) => format!("parameter #{n} is out of range"),
        other => other.to_string(),
    };
    Diagnostic::error(span, message).with_help(help)
}

const PI_HI: f64 = std::f64::consts::PI;
const PI_LO: f64 = 1.2246467991473532e-16;

/// `r·180/π`, rounded once (LinuxCNC: `(r * 180.0) / M_PIl` in long double).
pub(crate) fn degrees(r: f64) -> f64 {
    let hi = r * 180.0;
    let lo = r.mul_add(180.0, -hi);
    let q = hi / PI_HI;
    let rem = (-q).mul_add(PI_HI, hi) + lo - q * PI_LO;
    q + rem / PI_HI
}

fn not_finite(v: f64, span: Span) -> Diagnostic {
    let what = if v.is_nan() {
        "not a number"
    } else {
        "infinity"
    };
    Diagnostic::error(span, format!("calculation resulted in {what}"))
        .with_help("look for a huge power or EXP, or a zero to a negative power")
}

pub(crate) fn call(f: Func, x: f64, span: Span) -> Result<f64, Diagnostic> {
    let v = match f {
        Func::Abs => x.abs(),
        Func::Acos | Func::Asin if !(-1.0..=1.0).contains(&x) => {
            let name = if f == Func::Acos { "ACOS" } else { "ASIN" };
            return Err(Diagnostic::error(
                span,
                format!("argument {x} of {name} is outside -1 to 1"),
            ));
        }
        Func::Acos => degrees(x.acos()),
        Func::Asin => degrees(x.asin()),
        Func::Cos => trig::cos_deg(x),
        Func::Sin => trig::sin_deg(x),
        Func::Tan => trig::tan_deg(x),
        Func::Exp => x.exp(),
        Func::Fix => x.floor(),
        Func::Fup => x.ceil(),
        // Half away from zero, as LinuxCNC's (int)(x ± 0.5) (whose overflow to
        // -2147483648 beyond ±2^31 is not copied).
        Func::Round => (x + if x < 0.0 { -0.5 } else { 0.5 }).trunc(),
        Func::Ln if x <= 0.0 => {
            return Err(Diagnostic::error(
                span,
                format!("LN of {x}: the argument must be positive"),
            ))
        }
        Func::Ln => x.ln(),
        Func::Sqrt if x < 0.0 => {
            return Err(Diagnostic::error(
                span,
                format!("SQRT of negative number {x}"),
            ))
        }
        Func::Sqrt => x.sqrt(),
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(not_finite(v, span))
    }
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

pub(crate) fn binary(op: BinOp, a: f64, b: f64, span: Span) -> Result<f64, Diagnostic> {
    let v = match op {
        BinOp::Pow => {
            if a < 0.0 && b.floor() != b {
                return Err(Diagnostic::error(
                    span,
                    format!("{a} ** {b}: a negative number raised to a non-integer power"),
                )
                .with_help("the result would be a complex number"));
            }
            a.powf(b)
        }
        BinOp::Mul => a * b,
        BinOp::Div if b == 0.0 => {
            return Err(Diagnostic::error(
                span,
                format!("division by zero in {a} {} 0", op.symbol()),
            ))
        }
        BinOp::Div => a / b,
        // MOD by zero is NaN, caught (or not) by the bracket check, as in LinuxCNC.
        BinOp::Mod => {
            let r = a % b;
            if r < 0.0 {
                r + b.abs()
            } else {
                r
            }
        }
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Eq => truth((a - b).abs() < EQUAL_TOLERANCE),
        BinOp::Ne => truth((a - b).abs() >= EQUAL_TOLERANCE),
        BinOp::Gt => truth(a > b),
        BinOp::Ge => truth(a >= b),
        BinOp::Lt => truth(a < b),
        BinOp::Le => truth(a <= b),
        BinOp::And => truth(a != 0.0 && b != 0.0),
        BinOp::Or => truth(a != 0.0 || b != 0.0),
        BinOp::Xor => truth((a != 0.0) != (b != 0.0)),
    };
    // Not checked here: LinuxCNC lets infinity pass between operators and checks each
    // bracketed result (see `Expr::Group`).
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ast::Item;
    use crate::lex::Compact;
    use crate::parse::parse_line;
    use crate::Dialect;

    fn value(src: &str, p: &Params) -> Result<f64, Diagnostic> {
        let mut c = Compact::new();
        c.load(format!("X[{src}]").as_bytes(), 1)?;
        let mut line = crate::ast::Line::default();
        parse_line(&c, Dialect::LinuxCnc, &mut line)?;
        match &line.items[0] {
            Item::Word { value, .. } => eval(value, p),
            _ => unreachable!(),
        }
    }

    fn v(src: &str) -> f64 {
        value(src, &Params::new()).unwrap_or_else(|e| panic!("{src}: {e}"))
    }

    #[test]
    fn arithmetic_matches_linuxcnc() {
        // Figures from LinuxCNC's rs274 -g on the same expressions.
        assert_eq!(v("2**3**2"), 64.0);
        assert_eq!(v("-2**2"), 4.0);
        assert_eq!(v("1+2*3**2"), 19.0);
        assert_eq!(v("5 - 2 - 1"), 2.0);
        assert_eq!(v("8/2/2"), 2.0);
        assert_eq!(v("-7 MOD 3"), 2.0);
        assert_eq!(v("7 MOD -3"), 1.0);
        assert_eq!(v("7.5 MOD 2"), 1.5);
        assert_eq!(v("0**0"), 1.0);
        assert_eq!(v("- -3"), 3.0);
    }

    #[test]
    fn logic_and_comparison_match_linuxcnc() {
        assert_eq!(v("1 EQ 1.00001"), 1.0);
        assert_eq!(v("1 EQ 1.001"), 0.0);
        assert_eq!(v("1 NE 1.00001"), 0.0);
        assert_eq!(v("1 GE 1.00001"), 0.0);
        assert_eq!(v("1 LT 1.00001"), 1.0);
        assert_eq!(v("0 OR 3"), 1.0);
        assert_eq!(v("3 XOR 0"), 1.0);
        assert_eq!(
            v("0 OR 1 AND 0"),
            0.0,
            "AND/OR/XOR share one level, left to right"
        );
        assert_eq!(v("1 + 2 EQ 3"), 1.0);
        assert_eq!(v("1 GT 0 + 1"), 0.0);
    }

    #[test]
    fn angle_conversion_is_as_precise_as_linuxcncs_long_double() {
        // rs274: SIN[12345678901]*1000000 prints -17452.406433; the exact value is
        // sin(181°)·1e6 = -17452.406437; plain f64 conversion gives -17452.426526.
        let s = v("SIN[12345678901]*1000000");
        assert!((s - -17452.406433).abs() < 2e-5, "{s}");
        assert_eq!(v("ASIN[1]"), 90.0);
        assert_eq!(v("ATAN[1]/[1]"), 45.0);
        // rs274: SIN[30]*1e15 prints 500000000000000.000000 (plain f64: 0.49999999999999994).
        assert_eq!(v("SIN[30]"), 0.5);
        assert_eq!(v("COS[60]"), 0.5);
        assert_eq!(v("TAN[45]"), 1.0);
    }

    #[test]
    fn functions_in_degrees() {
        assert!((v("COS[60]") - 0.5).abs() < 1e-12);
        assert!((v("ACOS[0.5]") - 60.0).abs() < 1e-12);
        assert!((v("ATAN[1]/[-1]") - 135.0).abs() < 1e-12);
        assert!((v("TAN[45]") - 1.0).abs() < 1e-12);
        assert_eq!(v("ROUND[2.5]"), 3.0);
        assert_eq!(v("ROUND[-2.5]"), -3.0);
        assert_eq!(v("FIX[-2.5]"), -3.0);
        assert_eq!(v("FUP[-2.5]"), -2.0);
        assert_eq!(v("EXISTS[#<nope>]"), 0.0);
    }

    #[test]
    fn domain_errors_say_what() {
        let p = Params::new();
        let msg = |s: &str| value(s, &p).unwrap_err().message;
        assert!(msg("1/0").contains("division by zero"));
        assert!(msg("1 MOD 0").contains("not a number"));
        assert_eq!(
            v("1 MOD 0 LT 1"),
            0.0,
            "rs274 lets the NaN through a comparison"
        );
        assert!(msg("SQRT[-1]").contains("SQRT of negative"));
        assert!(msg("LN[0]").contains("LN"));
        assert!(msg("ASIN[2]").contains("ASIN"));
        assert!(msg("-8**[1/3]").contains("non-integer power"));
        assert!(msg("0**-1").contains("infinity"));
        assert!(msg("0**-1 * 0").contains("not a number"));
        // Deliberate: rs274 gives -39867976298117103616 (a by-product of rounding π).
        assert!(msg("TAN[90]").contains("infinity"));
        assert!(msg("EXP[1000] GT 1").contains("infinity"));
        assert!(msg("[0**-1] NE 5").contains("infinity"));
        // rs274: infinity between operators of one bracket is let through.
        assert_eq!(v("0**-1 NE 5"), 1.0);
        assert_eq!(v("10**400 GT 1"), 1.0);
        assert!(msg("#<foo>").contains("#<foo>"));
    }

    #[test]
    fn parameter_numbers_must_be_integers_in_range() {
        let mut p = Params::new();
        p.set(1, 1.00001).unwrap();
        p.set(2, 1.00011).unwrap();
        assert_eq!(value("##1", &p).unwrap(), 1.00001);
        assert!(value("##2", &p)
            .unwrap_err()
            .message
            .contains("not an integer"));
        assert!(value("#0", &p)
            .unwrap_err()
            .message
            .contains("out of range"));
        assert!(value("#5602", &p)
            .unwrap_err()
            .message
            .contains("out of range"));
        assert!(value("#5601", &p).is_ok());
        assert!(value("#-1", &p)
            .unwrap_err()
            .message
            .contains("out of range"));
        assert!(value("#[1+1]", &p).is_ok());
    }
}
