//! Tajima DST. A 512-byte header of `KEY:value\r` fields (LA name, ST records, CO colour
//! changes, ±X/±Y extents, AX/AY last point, MX/MY, PD) ended by 0x1A and padded with
//! spaces; then 3-byte records. Each axis increment d ∈ [−121, 121] is written in balanced
//! ternary, d = Σ tₖ·3ᵏ with tₖ ∈ {−1, 0, 1} for k = 0..4 (1 + 3 + 9 + 27 + 81 = 121), each
//! digit a pair of bits (+, −). Byte 2's bits 0 and 1 are always set; bit 7 marks a jump,
//! bits 7 + 6 a colour change, 0xF3 the end (which some writers leave out: the
//! records then end with the file). DST has no trim: three jumps are one (the
//! writer emits +0.2, −0.4, +0.2 mm, as pyembroidery does).

use super::records::{Op, Rec};
use super::{Format, FormatError};

pub(super) const MAX_STEP: i32 = 121;
const HEADER: usize = 512;

/// Bit positions of the digits 3⁰..3⁴ as (byte, plus bit, minus bit), per axis.
const X_BITS: [(usize, u8, u8); 5] = [(0, 0, 1), (1, 0, 1), (0, 2, 3), (1, 2, 3), (2, 2, 3)];
const Y_BITS: [(usize, u8, u8); 5] = [(0, 7, 6), (1, 7, 6), (0, 5, 4), (1, 5, 4), (2, 5, 4)];

fn encode_axis(mut d: i32, bits: &[(usize, u8, u8); 5], b: &mut [u8; 3]) {
    // Greedy from the largest digit: |d| ≤ 121 = Σ 3ᵏ guarantees the rest fits below.
    for k in (0..5).rev() {
        let w = 3i32.pow(k as u32);
        let half = (w - 1) / 2; // Σ of the smaller digits' weights
        let (byte, plus, minus) = bits[k];
        if d > half {
            b[byte] |= 1 << plus;
            d -= w;
        } else if d < -half {
            b[byte] |= 1 << minus;
            d += w;
        }
    }
    debug_assert_eq!(d, 0);
}

fn decode_axis(b: &[u8; 3], bits: &[(usize, u8, u8); 5]) -> i32 {
    bits.iter()
        .enumerate()
        .fold(0, |acc, (k, &(byte, plus, minus))| {
            let w = 3i32.pow(k as u32);
            acc + w * (((b[byte] >> plus) & 1) as i32 - ((b[byte] >> minus) & 1) as i32)
        })
}

fn encode(r: &Rec) -> [u8; 3] {
    let mut b = [0u8, 0, 0b0000_0011];
    match r.op {
        Op::Stitch | Op::Jump => {
            encode_axis(r.dx, &X_BITS, &mut b);
            encode_axis(r.dy, &Y_BITS, &mut b);
            if r.op == Op::Jump {
                b[2] |= 0x80;
            }
        }
        Op::ColorChange | Op::Stop => b[2] = 0b1100_0011,
        Op::End => b[2] = 0b1111_0011,
        // `write` expands trims into jumps before encoding.
        Op::Trim => {}
    }
    b
}

pub(super) fn write(name: &str, recs: &[Rec]) -> Vec<u8> {
    // Expand trims to three jumps that return to the same point.
    let mut expanded = Vec::with_capacity(recs.len());
    for r in recs {
        if r.op == Op::Trim {
            expanded.push(Rec::new(2, 2, Op::Jump));
            expanded.push(Rec::new(-4, -4, Op::Jump));
            expanded.push(Rec::new(2, 2, Op::Jump));
        } else {
            expanded.push(*r);
        }
    }
    let (mut x, mut y) = (0i64, 0i64);
    let (mut min_x, mut max_x, mut min_y, mut max_y) = (0i64, 0i64, 0i64, 0i64);
    for r in &expanded {
        x += r.dx as i64;
        y += r.dy as i64;
        (min_x, max_x, min_y, max_y) = (min_x.min(x), max_x.max(x), min_y.min(y), max_y.max(y));
    }
    let label: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_graphic() || c == ' ' {
                c
            } else {
                '_'
            }
        })
        .take(16)
        .collect();
    let records = expanded.iter().filter(|r| r.op != Op::End).count();
    let colors = expanded.iter().filter(|r| r.op == Op::ColorChange).count();
    let sign = |v: i64| if v < 0 { '-' } else { '+' };
    let mut h = String::new();
    h += &format!("LA:{label:<16}\r");
    h += &format!("ST:{records:>7}\r");
    h += &format!("CO:{colors:>3}\r");
    h += &format!("+X:{:>5}\r-X:{:>5}\r", max_x, -min_x);
    h += &format!("+Y:{:>5}\r-Y:{:>5}\r", max_y, -min_y);
    h += &format!(
        "AX:{}{:>5}\rAY:{}{:>5}\r",
        sign(x),
        x.abs(),
        sign(y),
        y.abs()
    );
    h += "MX:+    0\rMY:+    0\rPD:******\r";
    let mut out = h.into_bytes();
    out.push(0x1a);
    out.resize(HEADER, b' ');
    for r in &expanded {
        out.extend_from_slice(&encode(r));
    }
    out
}

fn err(offset: usize, message: impl Into<String>) -> FormatError {
    FormatError::new(Format::Dst, offset, message)
}

/// Header fields that must hold a number when present.
const NUMERIC: [&str; 10] = ["ST", "CO", "+X", "-X", "+Y", "-Y", "AX", "AY", "MX", "MY"];
/// Largest header number accepted: 9,999,999 fits the 7-digit ST field.
const MAX_FIELD: i64 = 9_999_999;

/// The header's name (LA) and the records up to END.
pub(super) fn read(bytes: &[u8]) -> Result<(Option<String>, Vec<Rec>), FormatError> {
    if bytes.is_empty() {
        return Err(err(0, "the file is empty"));
    }
    if bytes.len() < HEADER {
        return Err(err(
            bytes.len(),
            format!(
                "the file is {} bytes, shorter than the 512-byte header: truncated or not a DST file",
                bytes.len()
            ),
        ));
    }
    if &bytes[..3] != b"LA:" {
        return Err(err(
            0,
            "the header does not start with \"LA:\": not a DST file",
        ));
    }
    let head = &bytes[..HEADER];
    let end = head.iter().position(|&b| b == 0x1a).unwrap_or(HEADER);
    let mut name = None;
    let mut offset = 0;
    for field in head[..end].split(|&b| b == b'\r' || b == b'\n') {
        let at = offset;
        offset += field.len() + 1;
        let text = String::from_utf8_lossy(field);
        let Some((key, value)) = text.split_once(':') else {
            continue;
        };
        let (key, value) = (key.trim(), value.trim());
        if key == "LA" {
            name = Some(value.to_string()).filter(|v| !v.is_empty());
        } else if NUMERIC.contains(&key) {
            let digits = value.replace(' ', "");
            match digits.parse::<i64>() {
                Ok(v) if v.abs() <= MAX_FIELD => {}
                Ok(v) => return Err(err(at, format!("header field {key}: {v} is absurd"))),
                Err(_) => {
                    return Err(err(
                        at,
                        format!("header field {key}: {value:?} is not a number"),
                    ))
                }
            }
        }
    }
    let body = &bytes[HEADER..];
    let mut recs = Vec::with_capacity(body.len() / 3 + 1);
    for (i, c) in body.chunks_exact(3).enumerate() {
        let b = [c[0], c[1], c[2]];
        let (dx, dy) = (decode_axis(&b, &X_BITS), decode_axis(&b, &Y_BITS));
        // The same precedence as the format's masks: end, colour change, sequin, jump.
        let op = if b[2] & 0xF3 == 0xF3 {
            Op::End
        } else if b[2] & 0xC3 == 0xC3 {
            Op::ColorChange
        } else if b[2] & 0x43 == 0x43 {
            return Err(err(
                HEADER + 3 * i,
                "a sequin-mode record: sequins are not supported",
            ));
        } else if b[2] & 0x83 == 0x83 {
            Op::Jump
        } else {
            Op::Stitch
        };
        recs.push(Rec::new(dx, dy, op));
        if op == Op::End {
            return Ok((name, recs));
        }
    }
    // No END record: machines and pyembroidery sew what is there (PEmbroider writes no END),
    // and a DOS end-of-file mark (0x1A) may follow; any other partial record is a cut file.
    let rest = &body[body.len() / 3 * 3..];
    if !rest.is_empty() && rest.iter().any(|&b| b != 0x1A) {
        return Err(err(
            HEADER + body.len() / 3 * 3,
            format!(
                "the last record has {} of 3 bytes: the file is truncated",
                rest.len()
            ),
        ));
    }
    recs.push(Rec::new(0, 0, Op::End));
    Ok((name, recs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_increment_round_trips() {
        for dx in -121..=121 {
            for dy in [-121, -40, -13, -1, 0, 1, 5, 41, 121] {
                for op in [Op::Stitch, Op::Jump] {
                    let b = encode(&Rec::new(dx, dy, op));
                    assert_eq!(decode_axis(&b, &X_BITS), dx);
                    assert_eq!(decode_axis(&b, &Y_BITS), dy);
                }
            }
        }
    }
}
