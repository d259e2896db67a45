//! Melco EXP: no header; a record is two signed bytes (dx, dy) in 0.1 mm, y up. 0x80 in the
//! first byte escapes a command: 80 01 00 00 colour change (also the stop), 80 04 dx dy
//! jump, 80 80 07 00 trim, 80 02 dx dy a stitch. The file ends where the data ends.

use super::records::{Op, Rec};
use super::{Format, FormatError};

/// ±127: −128 would read as the 0x80 escape.
pub(super) const MAX_STEP: i32 = 127;

pub(super) fn write(recs: &[Rec]) -> Vec<u8> {
    let mut out = Vec::with_capacity(recs.len() * 2);
    for r in recs {
        let (x, y) = (r.dx as i8 as u8, r.dy as i8 as u8);
        match r.op {
            Op::Stitch => out.extend_from_slice(&[x, y]),
            Op::Jump => out.extend_from_slice(&[0x80, 0x04, x, y]),
            Op::Trim => out.extend_from_slice(&[0x80, 0x80, 0x07, 0x00]),
            Op::ColorChange | Op::Stop => out.extend_from_slice(&[0x80, 0x01, 0x00, 0x00]),
            Op::End => {}
        }
    }
    out
}

pub(super) fn read(bytes: &[u8]) -> Result<Vec<Rec>, FormatError> {
    let err = |offset, message: String| FormatError::new(Format::Exp, offset, message);
    if bytes.is_empty() {
        return Err(err(0, "the file is empty".into()));
    }
    let mut recs = Vec::with_capacity(bytes.len() / 2 + 1);
    let mut i = 0;
    while i < bytes.len() {
        if i + 2 > bytes.len() {
            // A DOS end-of-file mark after the last record.
            if bytes[i] == 0x1A {
                break;
            }
            return Err(err(
                i,
                "a record is cut after 1 of 2 bytes: the file is truncated".into(),
            ));
        }
        let (a, b) = (bytes[i], bytes[i + 1]);
        if a != 0x80 {
            recs.push(Rec::new(a as i8 as i32, b as i8 as i32, Op::Stitch));
            i += 2;
            continue;
        }
        if i + 4 > bytes.len() {
            return Err(err(
                i,
                format!("command 80 {b:02X} lacks its 2 data bytes: the file is truncated"),
            ));
        }
        let (x, y) = (bytes[i + 2] as i8 as i32, bytes[i + 3] as i8 as i32);
        let rec = match b {
            0x01 => Rec::new(x, y, Op::ColorChange),
            0x02 => Rec::new(x, y, Op::Stitch),
            0x04 => Rec::new(x, y, Op::Jump),
            0x80 => Rec::new(0, 0, Op::Trim),
            _ => return Err(err(i, format!("unknown command 80 {b:02X}"))),
        };
        recs.push(rec);
        i += 4;
    }
    recs.push(Rec::new(0, 0, Op::End));
    Ok(recs)
}
