//! HP-GL/2 `PE` (polyline encoded): coordinates packed as base-64 (or, after the `7` flag,
//! base-32) digits, as the HP-GL/2 reference (The HP-GL/2 and HP RTL Reference Guide, PE)
//! describes them.
//!
//! A value is first made an integer: multiplied by 2^f (f fractional bits, flag `>`) and
//! rounded; then its sign goes into the low bit (n ≥ 0 → 2n, n < 0 → 2|n| + 1); then it is
//! written least significant digit first. In base 64 a digit d is the byte 63 + d, except the
//! last, 191 + d; in base 32 (7-bit channels) 63 + d and, last, 95 + d. Decoding reverses it:
//! v = ±(u >> 1) / 2^f. Flags before a pair: `:` pen n, `<` the next move is pen-up, `=` the
//! next pair is absolute (otherwise relative to the current point), `>` f, `7` base 32.

use super::scan::Scanner;
use crate::import::ImportError;

/// One move or pen change of a `PE` instruction, coordinates in current units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum PeOp {
    Pen(f64),
    Move {
        up: bool,
        absolute: bool,
        x: f64,
        y: f64,
    },
}

struct Flags {
    seven_bit: bool,
    fraction: i32,
}

/// Reads a `PE` body up to its `;` (consumed).
pub(super) fn read(sc: &mut Scanner) -> Result<Vec<PeOp>, ImportError> {
    let mut fl = Flags {
        seven_bit: false,
        fraction: 0,
    };
    let mut ops = Vec::new();
    let (mut up, mut absolute) = (false, false);
    loop {
        let Some(c) = sc.look() else {
            // Some writers end the file without the final ';'; only a cut inside a pair or
            // after a flag is an error.
            if up || absolute {
                return Err(sc.err(
                    "PE",
                    "the file ends after a flag, before its coordinates".into(),
                ));
            }
            return Ok(ops);
        };
        let c7 = if fl.seven_bit { c & 0x7f } else { c };
        match c7 {
            b';' => {
                sc.raw();
                return Ok(ops);
            }
            b'\r' | b'\n' | b' ' | b'\t' => {
                sc.raw();
            }
            b'7' => {
                sc.raw();
                fl.seven_bit = true;
            }
            b':' => {
                sc.raw();
                ops.push(PeOp::Pen(value(sc, &fl, 0)?));
            }
            b'>' => {
                sc.raw();
                let f = value(sc, &fl, 0)?;
                if !(0.0..=26.0).contains(&f) {
                    return Err(sc.err("PE", format!("{f} fractional bits: use 0…26")));
                }
                fl.fraction = f as i32;
            }
            b'<' => {
                sc.raw();
                up = true;
            }
            b'=' => {
                sc.raw();
                absolute = true;
            }
            63.. => {
                let x = value(sc, &fl, fl.fraction)?;
                let y = value(sc, &fl, fl.fraction)?;
                ops.push(PeOp::Move { up, absolute, x, y });
                up = false;
                absolute = false;
            }
            _ => {
                return Err(sc.err(
                    "PE",
                    format!(
                    "byte {c:#04x} is neither a PE flag nor an encoded number (a PE ends with ';')"
                ),
                ))
            }
        }
        if ops.len() > 10_000_000 {
            return Err(sc.err("PE", "more than ten million encoded values".into()));
        }
    }
}

/// One encoded number, divided by 2^`fraction`.
fn value(sc: &mut Scanner, fl: &Flags, fraction: i32) -> Result<f64, ImportError> {
    let (bits, last) = if fl.seven_bit { (5, 95u8) } else { (6, 191u8) };
    let mut u: u64 = 0;
    let mut shift = 0u32;
    loop {
        let Some(c) = sc.look() else {
            return Err(sc.err(
                "PE",
                "the file ends inside an encoded number (truncated PE)".into(),
            ));
        };
        let c = if fl.seven_bit { c & 0x7f } else { c };
        if matches!(c, b'\r' | b'\n') {
            sc.raw();
            continue;
        }
        let (digit, end) = if fl.seven_bit {
            match c {
                63..=94 => (c - 63, false),
                95..=126 => (c - last, true),
                _ => return Err(bad(sc, c)),
            }
        } else {
            match c {
                63..=126 => (c - 63, false),
                191..=254 => (c - last, true),
                _ => return Err(bad(sc, c)),
            }
        };
        sc.raw();
        if shift > 60 {
            return Err(sc.err("PE", "an encoded number longer than 60 bits".into()));
        }
        u |= u64::from(digit) << shift;
        shift += bits;
        if end {
            break;
        }
    }
    let magnitude = (u >> 1) as f64 / f64::powi(2.0, fraction);
    let v = if u & 1 == 1 { -magnitude } else { magnitude };
    if v.abs() > super::scan::MAX_COORD {
        return Err(sc.err(
            "PE",
            format!("encoded value {v} is beyond ±{}", super::scan::MAX_COORD),
        ));
    }
    Ok(v)
}

fn bad(sc: &Scanner, c: u8) -> ImportError {
    sc.err(
        "PE",
        format!("byte {c:#04x} inside an encoded number (the number was cut short)"),
    )
}
