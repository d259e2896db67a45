//! Barudan U01. A 256-byte header (pyembroidery writes 128 × `0` then the extents, the record
//! count and the last point, 16/32-bit LE); then 3-byte records `ctrl, |dy|, |dx|` in 0.1 mm:
//! ctrl bit 7 always set, bit 6 = y goes down, bit 5 = x goes left, bits 0..4 the command:
//! 0 stitch, 1 jump, 2/3 fast stitch/jump, 4/5 slow stitch/jump, 6/7 trim (and a jump if it
//! moves), 8 a stop, 9..0x17 needle 1..15 (a colour change), 0x18 the end.
//!
//! Barudan machines are multi-needle: a colour change selects the next needle (needle n + 1
//! for block n, wrapping after 15), and the first block's needle is selected before it.

use super::bytes::{put_u16le, put_u32le, Reader};
use super::records::{self, Op, Rec, TrimRule};
use super::{Format, FormatError};
use crate::plan::StitchPlan;

pub(super) const MAX_STEP: i32 = 127;
const HEADER: usize = 0x100;

fn rec(cmd: u8, dx: i32, dy: i32) -> [u8; 3] {
    let mut c = 0x80 | cmd;
    if dy <= 0 {
        c |= 0x40;
    }
    if dx <= 0 {
        c |= 0x20;
    }
    [c, dy.unsigned_abs() as u8, dx.unsigned_abs() as u8]
}

pub(super) fn write(plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
    let recs = records::to_records(plan, MAX_STEP, Format::U01)?;
    let mut out = vec![b'0'; 0x80];
    let ([x0, y0, x1, y1], (lx, ly)) = records::extents(&recs);
    let v16 = |v: i64| v.clamp(i16::MIN as i64, i16::MAX as i64) as i16 as u16;
    // Left, top, right, bottom with y down, as the machine counts.
    for v in [x0, -y1, x1, -y0] {
        put_u16le(&mut out, v16(v));
    }
    put_u32le(&mut out, 0);
    put_u32le(&mut out, recs.len() as u32 + 1);
    put_u16le(&mut out, v16(lx));
    put_u16le(&mut out, v16(-ly));
    out.resize(HEADER, 0);
    let mut needle = 1u8;
    out.extend_from_slice(&rec(0x08 + needle, 0, 0));
    for r in &recs {
        match r.op {
            Op::Stitch => out.extend_from_slice(&rec(0, r.dx, r.dy)),
            Op::Jump => out.extend_from_slice(&rec(1, r.dx, r.dy)),
            Op::Trim => out.extend_from_slice(&rec(7, 0, 0)),
            Op::Stop => out.extend_from_slice(&rec(8, 0, 0)),
            Op::ColorChange => {
                needle = needle % 15 + 1;
                out.extend_from_slice(&rec(0x08 + needle, 0, 0));
            }
            Op::End => out.extend_from_slice(&[0xF8, 0, 0]),
        }
    }
    Ok(out)
}

pub(super) fn read(bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
    let mut r = Reader::new(bytes, Format::U01);
    if bytes.is_empty() {
        return Err(r.err(0, "the file is empty"));
    }
    r.seek(HEADER, "the stitches (after the 256-byte header)")?;
    let mut recs = Vec::new();
    let mut any_stitch = false;
    while r.remaining() > 0 {
        let at = r.pos;
        if r.remaining() < 3 {
            return Err(r.err(
                at,
                format!(
                    "a record is cut after {} of 3 bytes: the file is truncated",
                    r.remaining()
                ),
            ));
        }
        let b = r.take(3, "a record")?;
        let (ctrl, mut dy, mut dx) = (b[0], b[1] as i32, b[2] as i32);
        if ctrl & 0x20 != 0 {
            dx = -dx;
        }
        if ctrl & 0x40 != 0 {
            dy = -dy;
        }
        let moves = dx != 0 || dy != 0;
        match ctrl & 0x1F {
            0 => recs.push(Rec::new(dx, dy, Op::Stitch)),
            1 => recs.push(Rec::new(dx, dy, Op::Jump)),
            2 | 4 if moves => recs.push(Rec::new(dx, dy, Op::Stitch)),
            3 | 5 if moves => recs.push(Rec::new(dx, dy, Op::Jump)),
            2..=5 => {}
            c @ (6..=8) => {
                recs.push(Rec::new(0, 0, if c == 8 { Op::Stop } else { Op::Trim }));
                if moves {
                    recs.push(Rec::new(dx, dy, Op::Jump));
                }
            }
            0x09..=0x17 => {
                // The needle chosen before anything is sewn is the first thread, not a change.
                if any_stitch {
                    recs.push(Rec::new(0, 0, Op::ColorChange));
                }
                if moves {
                    recs.push(Rec::new(dx, dy, Op::Jump));
                }
            }
            // 0x18 is the end; anything else (machines' own postfix data) ends it too, as
            // pyembroidery reads it.
            _ => break,
        }
        any_stitch |= recs.last().is_some_and(|r| r.op == Op::Stitch);
    }
    recs.push(Rec::new(0, 0, Op::End));
    let mut plan = records::to_plan(&recs, TrimRule::Explicit);
    plan.name = name.to_string();
    Ok(plan)
}
