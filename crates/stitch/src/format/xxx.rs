//! Singer XXX. A 256-byte header: the record count (32-bit LE at 0x17), the colour count
//! (at 0x27), the design's width, height, last point and left/top (16-bit LE, 0.1 mm), and the
//! end of the stitches (32-bit LE at 0xFC). Records from 0x100: two signed bytes (dx, dy in
//! 0.1 mm, y up); `7F 01 dx dy` a jump, `7F 03 dx dy` a trim (and a jump if it moves),
//! `7F 08 dx dy` (or `7F 0A`..`7F 17`) a colour change, `7D`/`7E` and two 16-bit LE values a
//! long jump, `7F 7F` or `7F 18` the end. After the end, 2 bytes, then one colour per thread
//! (32-bit BE, 0x00RRGGBB).
//!
//! A colour change's displacement is not applied (as pyembroidery reads it), so Oficina
//! writes changes in place. Stitches are split to ±123: `7D` would start a byte in 7D..7F.

use super::bytes::{patch_u32le, put_u16le, put_u32le, Reader};
use super::records::{self, Op, Rec, TrimRule};
use super::{Format, FormatError};
use crate::plan::{StitchPlan, Thread};

pub(super) const MAX_STEP: i32 = 123;
const HEADER: usize = 0x100;

pub(super) fn write(plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
    let recs = records::to_records(plan, MAX_STEP, Format::Xxx)?;
    let threads: Vec<Thread> = plan.blocks.iter().map(|b| b.thread.clone()).collect();
    let ([x0, y0, x1, y1], (lx, ly)) = records::extents(&recs);
    let mut out = vec![0u8; 0x17];
    put_u32le(
        &mut out,
        recs.iter().filter(|r| r.op != Op::End).count() as u32,
    );
    out.resize(0x27, 0);
    put_u32le(&mut out, threads.len() as u32);
    put_u16le(&mut out, 0);
    let v16 = |v: i64| v.clamp(i16::MIN as i64, i16::MAX as i64) as i16 as u16;
    for v in [x1 - x0, y1 - y0, lx, ly, -x0, y1] {
        put_u16le(&mut out, v16(v));
    }
    out.resize(0xF2, 0);
    put_u16le(&mut out, 0x20);
    out.resize(HEADER, 0);
    for r in &recs {
        let (x, y) = (r.dx as i8 as u8, r.dy as i8 as u8);
        match r.op {
            Op::Stitch => out.extend_from_slice(&[x, y]),
            Op::Jump => out.extend_from_slice(&[0x7F, 0x01, x, y]),
            Op::Trim => out.extend_from_slice(&[0x7F, 0x03, 0, 0]),
            Op::ColorChange | Op::Stop => out.extend_from_slice(&[0x7F, 0x08, 0, 0]),
            Op::End => break,
        }
    }
    let end = out.len();
    patch_u32le(&mut out, 0xFC, end as u32);
    out.extend_from_slice(&[0x7F, 0x7F, 0x02, 0x14, 0, 0]);
    for t in &threads {
        out.extend_from_slice(&[0, t.rgb[0], t.rgb[1], t.rgb[2]]);
    }
    for _ in threads.len()..21 {
        put_u32le(&mut out, 0);
    }
    put_u32le(&mut out, 0xFFFF_FF00);
    out.extend_from_slice(&[0, 1]);
    Ok(out)
}

pub(super) fn read(bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
    let mut r = Reader::new(bytes, Format::Xxx);
    if bytes.is_empty() {
        return Err(r.err(0, "the file is empty"));
    }
    r.seek(0x27, "the colour count")?;
    let colours = r.u16le("the colour count")? as usize;
    r.seek(HEADER, "the stitches (after the 256-byte header)")?;
    let mut recs = Vec::new();
    let mut ended = false;
    while r.remaining() > 0 {
        let at = r.pos;
        let a = r.u8("a record")?;
        if a == 0x7D || a == 0x7E {
            let x = r.u16le("a long jump's x")? as i16 as i32;
            let y = r.u16le("a long jump's y")? as i16 as i32;
            recs.push(Rec::new(x, y, Op::Jump));
            continue;
        }
        let b = r.u8("a record's second byte")?;
        if a != 0x7F {
            recs.push(Rec::new(a as i8 as i32, b as i8 as i32, Op::Stitch));
            continue;
        }
        if b == 0x7F || b == 0x18 {
            // The end record is 4 bytes (`7F 7F 02 14`), then 2 more before the colours.
            ended = true;
            let _ = r.skip(2, "the end record");
            break;
        }
        let d = r.take(2, "a command's displacement")?;
        let (x, y) = (d[0] as i8 as i32, d[1] as i8 as i32);
        match b {
            0x01 => recs.push(Rec::new(x, y, Op::Jump)),
            0x03 => {
                recs.push(Rec::new(0, 0, Op::Trim));
                if x != 0 || y != 0 {
                    recs.push(Rec::new(x, y, Op::Jump));
                }
            }
            0x08 | 0x0A..=0x17 => recs.push(Rec::new(0, 0, Op::ColorChange)),
            // Other commands carry nothing Oficina or pyembroidery knows.
            _ => {
                let _ = at;
            }
        }
    }
    if !ended {
        return Err(r.err(bytes.len(), "no end record (7F 7F): the file is truncated"));
    }
    recs.push(Rec::new(0, 0, Op::End));
    // The colours follow the end's 2 further bytes; a short list leaves the defaults.
    let mut threads = Vec::new();
    if r.skip(2, "the colour list").is_ok() {
        for _ in 0..colours.min(r.remaining() / 4) {
            let c = r.take(4, "a colour")?;
            threads.push(Thread::rgb(c[1], c[2], c[3]));
        }
    }
    let mut plan = records::to_plan(&recs, TrimRule::Explicit);
    records::set_threads(&mut plan, &threads);
    plan.name = name.to_string();
    Ok(plan)
}
