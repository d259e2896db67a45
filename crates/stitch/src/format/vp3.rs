//! Pfaff / Husqvarna VP3. Big-endian throughout. `%vsm%\0`, a UTF-16 "produced by" string,
//! `00 02 00` and the length to the file's end, a settings string, the extents (right, −top,
//! left, −bottom in µm), the stitch count, the colour count, `0C 00`, the design count (1);
//! the design: `00 03 00` and its length, its centre (µm, y up), its extents and size, two
//! strings and a transform, `xxPP\x01\0`, a string, the colour-block count; each colour
//! block: `00 05 00` and its length, its start relative to the centre (µm, y up), the thread
//! (colour count, transition, RGB, parts, length, type, weight, then catalogue number, name
//! and brand as length-prefixed strings), its shift (µm), `00 01 00` and the stitches'
//! length, `0A F6 00`, then the stitches: two signed bytes (dx, dy in 0.1 mm, y down),
//! `80 01 dx dy 80 02` with 16-bit dx, dy for a long stitch, `80 03` a trim.
//!
//! VP3 has no jump. Each colour block starts where its first stitch is; after a trim, the
//! move to where sewing resumes is one long record, which Oficina reads as a jump (machines
//! do not sew it; pyembroidery reads it as a stitch); a move without a trim is sewn into the
//! next stitch, as pyembroidery writes it. Stops are not kept (VP3 has none; pyembroidery
//! drops them the same way).

use super::bytes::{patch_u32be, put_i32be, put_u16be, Reader};
use super::records::{self, Op, TrimRule};
use super::{Format, FormatError, Rec};
use crate::plan::{StitchPlan, Thread};

/// Stitches are split to ±255 units as pyembroidery's writer does; longer moves are long
/// stitches of up to ±32767.
pub(super) const MAX_STEP: i32 = 255;

fn put_string16(out: &mut Vec<u8>, s: &str) {
    let units: Vec<u16> = s.encode_utf16().collect();
    put_u16be(out, (units.len() * 2) as u16);
    for u in units {
        put_u16be(out, u);
    }
}

fn put_string8(out: &mut Vec<u8>, s: &str) {
    let b: Vec<u8> = s.bytes().take(u16::MAX as usize).collect();
    put_u16be(out, b.len() as u16);
    out.extend_from_slice(&b);
}

/// Patches the 32-bit length at `at` to count from after it to the current end.
fn close(out: &mut [u8], at: usize) {
    let len = out.len() - at - 4;
    patch_u32be(out, at, len as u32);
}

/// One stitch of (dx, dy) 0.1 mm (y down): two bytes, or the long form `80 01 dx dy 80 02`
/// when it does not fit a byte or `long` asks for it.
fn put_stitch(out: &mut Vec<u8>, dx: i64, dy: i64, long: bool) -> Result<(), FormatError> {
    if !long && dx.abs() <= 127 && dy.abs() <= 127 {
        out.extend_from_slice(&[dx as i8 as u8, dy as i8 as u8]);
    } else if dx.abs() <= 32767 && dy.abs() <= 32767 {
        out.extend_from_slice(&[0x80, 0x01]);
        put_u16be(out, dx as i16 as u16);
        put_u16be(out, dy as i16 as u16);
        out.extend_from_slice(&[0x80, 0x02]);
    } else {
        return Err(FormatError::new(
            Format::Vp3,
            out.len(),
            format!(
                "a move of ({}, {}) mm: VP3 moves at most 3276.7 mm at once",
                dx as f64 / 10.0,
                -dy as f64 / 10.0
            ),
        ));
    }
    Ok(())
}

const PRODUCER: &str = "Produced by     Software Ltd";

pub(super) fn write(plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
    let recs = records::to_records(plan, MAX_STEP, Format::Vp3)?;
    let ([x0, y0, x1, y1], _) = records::extents(&recs);
    let (cx, cy) = ((x0 + x1).div_euclid(2), (y0 + y1).div_euclid(2));
    let um = |v: i64| (v * 100).clamp(i32::MIN as i64, i32::MAX as i64) as i32;
    // Colour blocks: records between colour changes (stops dropped), with their thread.
    let mut blocks: Vec<(Thread, Vec<Rec>)> = Vec::new();
    let mut threads = plan.blocks.iter().map(|b| b.thread.clone());
    let first = threads.next().unwrap_or_else(|| Thread::rgb(0, 0, 0));
    blocks.push((first.clone(), Vec::new()));
    for r in &recs {
        match r.op {
            Op::ColorChange => {
                let t = threads.next().unwrap_or_else(|| first.clone());
                blocks.push((t, Vec::new()));
            }
            Op::Stop => {}
            _ => blocks.last_mut().map_or((), |b| b.1.push(*r)),
        }
    }
    let mut out = b"%vsm%\0".to_vec();
    put_string16(&mut out, PRODUCER);
    out.extend_from_slice(&[0, 2, 0]);
    let file_len_at = out.len();
    out.extend_from_slice(&[0; 4]);
    put_string16(&mut out, "");
    for v in [x1, -y1, x0, -y0] {
        put_i32be(&mut out, um(v));
    }
    let count = recs.iter().filter(|r| r.op != Op::End).count();
    put_i32be(&mut out, count as i32);
    out.extend_from_slice(&[0, blocks.len().min(255) as u8, 12, 0, 1]);
    out.extend_from_slice(&[0, 3, 0]);
    let design_len_at = out.len();
    out.extend_from_slice(&[0; 4]);
    put_i32be(&mut out, um(cx));
    put_i32be(&mut out, um(cy));
    out.extend_from_slice(&[0, 0, 0]);
    let (hw, hh) = ((x1 - x0) / 2, (y1 - y0) / 2);
    for v in [-hw, hw, -hh, hh, x1 - x0, y1 - y0] {
        put_i32be(&mut out, um(v));
    }
    put_string16(&mut out, "");
    out.extend_from_slice(&[0x64, 0x64]);
    for v in [4096, 0, 0, 4096] {
        put_i32be(&mut out, v);
    }
    out.extend_from_slice(b"xxPP\x01\x00");
    put_string16(&mut out, PRODUCER);
    if blocks.len() > u16::MAX as usize {
        return Err(FormatError::new(
            Format::Vp3,
            out.len(),
            format!("{} colour blocks: VP3 holds at most 65535", blocks.len()),
        ));
    }
    put_u16be(&mut out, blocks.len() as u16);
    // Absolute position of the needle (last stitch) and of the hoop (after jumps).
    let (mut hx, mut hy) = (0i64, 0i64);
    let mut needle = (0i64, 0i64);
    let mut sewn = false;
    for (thread, recs) in &blocks {
        out.extend_from_slice(&[0, 5, 0]);
        let block_len_at = out.len();
        out.extend_from_slice(&[0; 4]);
        // The block starts where the hoop is after the block's leading jumps; its first
        // stitch is sewn from there.
        for r in recs.iter().take_while(|r| r.op == Op::Jump) {
            hx += r.dx as i64;
            hy += r.dy as i64;
        }
        let lead = recs.iter().take_while(|r| r.op == Op::Jump).count();
        // pyembroidery moves to a block's start only when neither coordinate is 0: such a
        // start is written at the needle, and the move after it as a trim and a long record.
        let jumped = (hx, hy);
        let odd = (jumped.0 == 0) != (jumped.1 == 0) && jumped != needle;
        let start = if odd { needle } else { jumped };
        put_i32be(&mut out, um(start.0 - cx));
        put_i32be(&mut out, um(start.1 - cy));
        out.extend_from_slice(&[1, 0, thread.rgb[0], thread.rgb[1], thread.rgb[2]]);
        out.extend_from_slice(&[0, 0, 0, 5, 0x28]);
        put_string8(&mut out, "");
        let label = if thread.name.is_empty() {
            thread.hex()
        } else {
            thread.name.clone()
        };
        put_string8(&mut out, &label);
        put_string8(&mut out, "");
        let shift_at = out.len();
        out.extend_from_slice(&[0; 8]);
        out.extend_from_slice(&[0, 1, 0]);
        let stitches_len_at = out.len();
        out.extend_from_slice(&[0; 4]);
        out.extend_from_slice(&[0x0A, 0xF6, 0x00]);
        let (mut sx, mut sy) = start;
        let mut trimmed = false;
        if odd {
            out.extend_from_slice(&[0x80, 0x03]);
            put_stitch(&mut out, jumped.0 - sx, -(jumped.1 - sy), true)?;
            (sx, sy) = jumped;
        }
        for r in &recs[lead..] {
            match r.op {
                Op::Jump => {
                    hx += r.dx as i64;
                    hy += r.dy as i64;
                }
                Op::Stitch => {
                    // After a trim, the move to where sewing resumes is its own long record
                    // (read back as a jump); elsewhere a jump is sewn into the next stitch.
                    if trimmed && (hx, hy) != (sx, sy) {
                        put_stitch(&mut out, hx - sx, -(hy - sy), true)?;
                        (sx, sy) = (hx, hy);
                    }
                    trimmed = false;
                    sewn = true;
                    hx += r.dx as i64;
                    hy += r.dy as i64;
                    put_stitch(&mut out, hx - sx, -(hy - sy), false)?;
                    (sx, sy) = (hx, hy);
                }
                Op::Trim => {
                    out.extend_from_slice(&[0x80, 0x03]);
                    trimmed = true;
                }
                // The machine does not cut at the end by itself: a trim ends what was sewn.
                Op::End => {
                    if sewn && !trimmed {
                        out.extend_from_slice(&[0x80, 0x03]);
                    }
                }
                Op::ColorChange | Op::Stop => {}
            }
        }
        needle = (sx, sy);
        close(&mut out, stitches_len_at);
        let shift = [um(sx - start.0), um(-(sy - start.1))];
        out[shift_at..shift_at + 4].copy_from_slice(&shift[0].to_be_bytes());
        out[shift_at + 4..shift_at + 8].copy_from_slice(&shift[1].to_be_bytes());
        out.push(0);
        close(&mut out, block_len_at);
        // Jumps at a block's end carry into the next block's start.
    }
    close(&mut out, design_len_at);
    close(&mut out, file_len_at);
    Ok(out)
}

fn skip_string(r: &mut Reader, what: &str) -> Result<(), FormatError> {
    let n = r.u16be(what)? as usize;
    r.skip(n, what)
}

fn string8(r: &mut Reader, what: &str) -> Result<String, FormatError> {
    let n = r.u16be(what)? as usize;
    Ok(String::from_utf8_lossy(r.take(n, what)?).to_string())
}

pub(super) fn read(bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
    let mut r = Reader::new(bytes, Format::Vp3);
    if bytes.is_empty() {
        return Err(r.err(0, "the file is empty"));
    }
    if !bytes.starts_with(b"%vsm%") {
        return Err(r.err(0, "the file does not start with \"%vsm%\": not a VP3 file"));
    }
    r.skip(6, "the signature")?;
    skip_string(&mut r, "the producer string")?;
    r.skip(7, "the file block's header")?;
    skip_string(&mut r, "the settings string")?;
    r.skip(32, "the design's extents")?;
    let cx = r.i32be("the design's centre")? as i64;
    let cy = r.i32be("the design's centre")? as i64;
    r.skip(27, "the design block")?;
    skip_string(&mut r, "the design's notes")?;
    r.skip(24, "the design's transform")?;
    skip_string(&mut r, "the producer string")?;
    let count_at = r.pos;
    let blocks = r.u16be("the colour-block count")? as usize;
    // A colour block takes at least 40 bytes.
    if blocks > r.remaining() / 40 + 1 {
        return Err(r.err(
            count_at,
            format!(
                "{blocks} colour blocks cannot fit the {} bytes left: a corrupt header",
                r.remaining()
            ),
        ));
    }
    // Centre and starts are in µm; the stitches in 0.1 mm.
    let unit = |v: i64| (v as f64 / 100.0).round() as i64;
    let (cx, cy) = (unit(cx), unit(cy));
    let mut recs = Vec::new();
    let mut threads = Vec::new();
    let (mut x, mut y) = (0i64, 0i64);
    for b in 0..blocks {
        let at = r.pos;
        r.skip(3, "a colour block's tag")?;
        let len = r.i32be("a colour block's length")? as u32 as usize;
        let end = r.pos.saturating_add(len);
        if end > bytes.len() {
            return Err(r.err(
                at,
                format!(
                    "colour block {} claims {len} bytes, beyond the file's end: the file is truncated",
                    b + 1
                ),
            ));
        }
        if b > 0 {
            recs.push(Rec::new(0, 0, Op::ColorChange));
        }
        let sx = unit(r.i32be("a block's start")? as i64) + cx;
        let sy = unit(r.i32be("a block's start")? as i64) + cy;
        if (sx, sy) != (x, y) {
            recs.push(Rec::new((sx - x) as i32, (sy - y) as i32, Op::Jump));
            (x, y) = (sx, sy);
        }
        let colours = r.u8("the thread's colour count")?;
        r.skip(1, "the thread's transition")?;
        let mut rgb = [0u8; 3];
        for _ in 0..colours {
            let c = r.take(3, "a thread colour")?;
            rgb = [c[0], c[1], c[2]];
            r.skip(3, "a thread colour's parts and length")?;
        }
        r.skip(2, "the thread's type and weight")?;
        string8(&mut r, "the thread's catalogue number")?;
        let tname = string8(&mut r, "the thread's name")?;
        string8(&mut r, "the thread's brand")?;
        threads.push(Thread { rgb, name: tname });
        r.skip(15, "the block's shift and stitch header")?;
        r.skip(3, "the stitches' tag")?;
        // Stitch pairs up to the block's end; an odd last byte is padding.
        let mut moving = false;
        while r.pos + 1 < end {
            let at = r.pos;
            let p = r.take(2, "a stitch")?;
            let (a, c) = (p[0], p[1]);
            if a != 0x80 {
                let (dx, dy) = (a as i8 as i64, -(c as i8 as i64));
                recs.push(Rec::new(dx as i32, dy as i32, Op::Stitch));
                (x, y) = (x + dx, y + dy);
                moving = false;
                continue;
            }
            match c {
                0x01 => {
                    if r.pos + 6 > end {
                        return Err(r.err(at, "a long stitch is cut by its block's end"));
                    }
                    let dx = r.u16be("a long stitch")? as i16 as i64;
                    let dy = -(r.u16be("a long stitch")? as i16 as i64);
                    r.skip(2, "a long stitch's end")?;
                    // A long record right after a trim is the move to where sewing
                    // resumes: the machine does not sew it.
                    let op = if moving { Op::Jump } else { Op::Stitch };
                    recs.push(Rec::new(dx as i32, dy as i32, op));
                    (x, y) = (x + dx, y + dy);
                }
                0x03 => {
                    recs.push(Rec::new(0, 0, Op::Trim));
                    moving = true;
                    continue;
                }
                _ => {}
            }
            moving = false;
        }
        r.seek(end, "the next colour block")?;
    }
    recs.push(Rec::new(0, 0, Op::End));
    let mut plan = records::to_plan(&recs, TrimRule::Explicit);
    records::set_threads(&mut plan, &threads);
    plan.name = name.to_string();
    Ok(plan)
}
