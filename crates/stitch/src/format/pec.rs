//! Brother PEC: the stitch block every Brother machine reads (alone as a `.pec` file, or
//! inside a PES file). Layout of the section, from its "LA:" label:
//!
//! - 0x00 `LA:` and a 16-character label ended by `\r`; 12 spaces, `FF 00`; the icon's byte
//!   stride (6) and height (38); 12 spaces.
//! - 0x30 the number of colours − 1, then one PEC chart index per colour (a stop is a change to
//!   the same index again), padded with spaces to 0x200.
//! - 0x200 `00 00`, the stitch block's length (24-bit LE, from 0x200), `31 FF F0`, width and
//!   height (16-bit LE, 0.1 mm), `E0 01 B0 01`; the stitches from 0x210.
//! - after the stitches, 1 + colours monochrome icons of 48 × 38 pixels (6 bytes a row, bit 0
//!   leftmost): the whole design, then each colour.
//!
//! Stitches are increments in 0.1 mm, y down, per axis: one byte (7-bit two's complement,
//! −64..63) or, with bit 7 set, two bytes holding a 12-bit two's complement value (−2048..2047)
//! and flags in the first byte: 0x10 a jump, 0x20 a trim then a jump. `FE B0 xx` changes colour,
//! `FF` ends. PEC has no trim of its own: a trim is the flag on the jump that follows it (a
//! trim-jump of zero length when nothing follows).

use super::bytes::{patch_u24le, put_u16le, Reader};
use super::records::{Op, Rec};
use super::threads::{nearest, thread_at, PEC_THREADS};
use super::{Format, FormatError};
use crate::plan::{StitchPlan, Thread};

pub(super) const MAX_STEP: i32 = 2047;
const ICON_STRIDE: usize = 6;
const ICON_HEIGHT: usize = 38;
const ICON_BYTES: usize = ICON_STRIDE * ICON_HEIGHT;
const JUMP: u8 = 0x10;
const TRIM: u8 = 0x20;
const LONG: u8 = 0x80;

/// What a PES file needs from the PEC section it holds.
pub(super) struct Section {
    pub(super) bytes: Vec<u8>,
    /// The PEC chart index of each colour entry (one per block and per stop).
    pub(super) indices: Vec<u8>,
    /// The thread of each entry.
    pub(super) threads: Vec<Thread>,
}

/// PEC indices for a thread sequence: each distinct colour takes the nearest chart entry no
/// other colour took (as pyembroidery's writer does, so distinct threads stay distinct), the
/// nearest overall once the chart is used up.
fn indices(threads: &[Thread]) -> Vec<u8> {
    let mut taken: Vec<([u8; 3], usize)> = Vec::new();
    threads
        .iter()
        .map(|t| {
            if let Some(&(_, i)) = taken.iter().find(|(c, _)| *c == t.rgb) {
                return i as u8;
            }
            let free = nearest(t.rgb, &PEC_THREADS, &|i| taken.iter().any(|&(_, j)| j == i));
            let i = free
                .or_else(|| nearest(t.rgb, &PEC_THREADS, &|_| false))
                .unwrap_or(20);
            taken.push((t.rgb, i));
            i as u8
        })
        .collect()
}

fn put_value(out: &mut Vec<u8>, v: i32, long: bool, flag: u8) {
    if !long && (-63..=62).contains(&v) {
        out.push((v & 0x7F) as u8);
    } else {
        let w = (v & 0x0FFF) as u16 | ((LONG | flag) as u16) << 8;
        out.extend_from_slice(&w.to_be_bytes());
    }
}

/// The PEC section of a plan whose records (split to ±2047) are `recs`.
pub(super) fn write_section(
    plan: &StitchPlan,
    recs: &[Rec],
    name: &str,
) -> Result<Section, FormatError> {
    let threads = super::records::thread_sequence(recs, plan);
    if threads.len() > 255 {
        return Err(FormatError::new(
            Format::Pec,
            0x30,
            format!("{} colours and stops: PEC holds at most 255", threads.len()),
        ));
    }
    let idx = indices(&threads);
    let mut out = Vec::new();
    let label: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_graphic() || c == ' ' {
                c
            } else {
                '_'
            }
        })
        .take(8)
        .collect();
    out.extend_from_slice(format!("LA:{label:<16}\r").as_bytes());
    out.extend_from_slice(&[b' '; 12]);
    out.extend_from_slice(&[0xFF, 0x00, ICON_STRIDE as u8, ICON_HEIGHT as u8]);
    out.extend_from_slice(&[b' '; 12]);
    out.push((idx.len() - 1) as u8);
    out.extend_from_slice(&idx);
    out.resize(0x200, b' ');
    let ([x0, y0, x1, y1], _) = super::records::extents(recs);
    let dim = |v: i64| v.clamp(0, u16::MAX as i64) as u16;
    out.extend_from_slice(&[0, 0, 0, 0, 0, 0x31, 0xFF, 0xF0]);
    put_u16le(&mut out, dim(x1 - x0));
    put_u16le(&mut out, dim(y1 - y0));
    put_u16le(&mut out, 0x1E0);
    put_u16le(&mut out, 0x1B0);
    let mut second = true;
    for (i, r) in recs.iter().enumerate() {
        match r.op {
            Op::Stitch => {
                put_value(&mut out, r.dx, false, 0);
                put_value(&mut out, -r.dy, false, 0);
            }
            Op::Jump => {
                let after_trim = i > 0 && recs[i - 1].op == Op::Trim;
                let flag = if after_trim { TRIM } else { JUMP };
                put_value(&mut out, r.dx, true, flag);
                put_value(&mut out, -r.dy, true, flag);
            }
            Op::Trim => {
                if recs.get(i + 1).is_none_or(|n| n.op != Op::Jump) {
                    put_value(&mut out, 0, true, TRIM);
                    put_value(&mut out, 0, true, TRIM);
                }
            }
            Op::ColorChange | Op::Stop => {
                out.extend_from_slice(&[0xFE, 0xB0, if second { 2 } else { 1 }]);
                second = !second;
            }
            Op::End => break,
        }
    }
    out.push(0xFF);
    let block_len = out.len() - 0x200;
    if block_len > 0xFF_FFFF {
        return Err(FormatError::new(
            Format::Pec,
            0x202,
            format!("{block_len} bytes of stitches: PEC holds at most 16 MB"),
        ));
    }
    patch_u24le(&mut out, 0x202, block_len as u32);
    out.extend_from_slice(&icons(recs, idx.len()));
    Ok(Section {
        bytes: out,
        indices: idx,
        threads,
    })
}

/// The design's icon and one per colour: a rounded frame and the stitches scaled into it.
fn icons(recs: &[Rec], colours: usize) -> Vec<u8> {
    let frame = || {
        let mut g = [0u8; ICON_BYTES];
        let mark = |g: &mut [u8; ICON_BYTES], x: usize, y: usize| {
            g[y * ICON_STRIDE + x / 8] |= 1 << (x % 8)
        };
        for x in 4..=43 {
            mark(&mut g, x, 1);
            mark(&mut g, x, ICON_HEIGHT - 2);
        }
        for (y, l) in [(2, 3), (3, 2), (ICON_HEIGHT - 3, 3), (ICON_HEIGHT - 4, 2)] {
            mark(&mut g, l, y);
            mark(&mut g, 47 - l, y);
        }
        for y in 4..ICON_HEIGHT - 4 {
            mark(&mut g, 1, y);
            mark(&mut g, 46, y);
        }
        g
    };
    let ([x0, y0, x1, y1], _) = super::records::extents(recs);
    let (w, h) = ((x1 - x0).max(1) as f64, (y1 - y0).max(1) as f64);
    // Inside the frame: x 4..=43, y 4..=33.
    let scale = (38.0 / w).min(28.0 / h);
    let (cx, cy) = ((x0 + x1) as f64 / 2.0, (y0 + y1) as f64 / 2.0);
    let mut all = frame();
    let mut each: Vec<[u8; ICON_BYTES]> = (0..colours).map(|_| frame()).collect();
    let (mut x, mut y) = (0i64, 0i64);
    let mut c = 0;
    for r in recs {
        x += r.dx as i64;
        y += r.dy as i64;
        match r.op {
            Op::Stitch => {
                let px = (23.5 + (x as f64 - cx) * scale).floor().clamp(4.0, 43.0) as usize;
                // y up in the records, row 0 at the top of the icon.
                let py = (18.5 - (y as f64 - cy) * scale).floor().clamp(4.0, 33.0) as usize;
                let bit = 1 << (px % 8);
                all[py * ICON_STRIDE + px / 8] |= bit;
                if let Some(g) = each.get_mut(c) {
                    g[py * ICON_STRIDE + px / 8] |= bit;
                }
            }
            Op::ColorChange | Op::Stop => c += 1,
            _ => {}
        }
    }
    let mut out = all.to_vec();
    for g in each {
        out.extend_from_slice(&g);
    }
    out
}

fn signed12(v: u16) -> i32 {
    let v = (v & 0x0FFF) as i32;
    if v > 0x7FF {
        v - 0x1000
    } else {
        v
    }
}

fn signed7(v: u8) -> i32 {
    if v > 63 {
        v as i32 - 128
    } else {
        v as i32
    }
}

/// A PEC section read from `start` (its "LA:"): the label, the records (y up) and the chart
/// index of each colour entry.
pub(super) fn read_section(
    r: &mut Reader,
    start: usize,
) -> Result<(Option<String>, Vec<Rec>, Vec<u8>), FormatError> {
    r.seek(start, "the PEC section")?;
    r.skip(3, "the PEC label's \"LA:\"")?;
    let label = String::from_utf8_lossy(r.take(16, "the PEC label")?)
        .trim()
        .to_string();
    r.skip(15, "the PEC header")?;
    r.skip(2, "the PEC icon size")?;
    r.skip(12, "the PEC header")?;
    let changes = r.u8("the PEC colour count")? as usize;
    let indices = r.take(changes + 1, "the PEC colour list")?.to_vec();
    r.seek(start + 0x202, "the PEC stitch block")?;
    let len_at = r.pos;
    let block_len = r.u24le("the PEC stitch block's length")? as usize;
    let block_end = start + 0x200 + block_len;
    if block_len < 0x10 || block_end > r.buf.len() {
        return Err(r.err(
            len_at,
            format!(
                "the stitch block's length {block_len} does not fit the file's {} bytes after byte {}",
                r.buf.len().saturating_sub(start + 0x200),
                start + 0x200
            ),
        ));
    }
    r.skip(0x0B, "the PEC stitch block header")?;
    let mut recs = Vec::new();
    loop {
        if r.remaining() == 0 || r.pos >= block_end {
            // No end code where the block or the file ends: read what is there, as
            // machines and pyembroidery do.
            break;
        }
        let a = r.u8("a stitch")?;
        if a == 0xFF && r.buf.get(r.pos).is_none_or(|&b| b == 0x00) {
            break;
        }
        let b = r.u8("a stitch's second byte")?;
        if a == 0xFE && b == 0xB0 {
            r.skip(1, "a colour change's third byte")?;
            recs.push(Rec::new(0, 0, Op::ColorChange));
            continue;
        }
        let (mut jump, mut trim) = (false, false);
        let (x, yb) = if a & LONG != 0 {
            trim |= a & TRIM != 0;
            jump |= a & JUMP != 0;
            let c = r.u8("a long stitch's y")?;
            (signed12(u16::from_be_bytes([a, b])), c)
        } else {
            (signed7(a), b)
        };
        let y = if yb & LONG != 0 {
            trim |= yb & TRIM != 0;
            jump |= yb & JUMP != 0;
            let c = r.u8("a long stitch's second y byte")?;
            signed12(u16::from_be_bytes([yb, c]))
        } else {
            signed7(yb)
        };
        if jump {
            recs.push(Rec::new(x, -y, Op::Jump));
        } else if trim {
            recs.push(Rec::new(0, 0, Op::Trim));
            recs.push(Rec::new(x, -y, Op::Jump));
        } else {
            recs.push(Rec::new(x, -y, Op::Stitch));
        }
    }
    recs.push(Rec::new(0, 0, Op::End));
    Ok((Some(label).filter(|l| !l.is_empty()), recs, indices))
}

/// Threads of PEC chart indices.
pub(super) fn chart_threads(indices: &[u8]) -> Vec<Thread> {
    indices
        .iter()
        .map(|&i| thread_at(&PEC_THREADS, i as usize).unwrap_or_else(|| Thread::rgb(0, 0, 0)))
        .collect()
}

/// A whole `.pec` file: `#PEC0001` and the section.
pub(super) fn write(plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
    let recs = super::records::to_records(plan, MAX_STEP, Format::Pec)?;
    let mut out = b"#PEC0001".to_vec();
    out.extend_from_slice(&write_section(plan, &recs, &plan.name)?.bytes);
    Ok(out)
}

pub(super) fn read(bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
    let mut r = Reader::new(bytes, Format::Pec);
    if bytes.is_empty() {
        return Err(r.err(0, "the file is empty"));
    }
    if !bytes.starts_with(b"#PEC") {
        return Err(r.err(0, "the file does not start with \"#PEC\": not a PEC file"));
    }
    let (label, recs, indices) = read_section(&mut r, 8)?;
    Ok(finish(recs, chart_threads(&indices), label, name))
}

/// The plan of PEC records with their threads (a change to the same thread is a stop).
pub(super) fn finish(
    mut recs: Vec<Rec>,
    mut threads: Vec<Thread>,
    label: Option<String>,
    name: &str,
) -> StitchPlan {
    super::records::duplicates_as_stops(&mut recs, &mut threads);
    let mut plan = super::records::to_plan(&recs, super::records::TrimRule::Explicit);
    super::records::set_threads(&mut plan, &threads);
    plan.name = label.unwrap_or_else(|| name.to_string());
    plan
}
