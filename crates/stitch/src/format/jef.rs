//! Janome JEF. Header (32-bit LE fields): the stitches' offset, flags (0x14), a 14-digit date
//! `YYYYMMDDhhmmss` and 2 zero bytes, the colour count, the record count, the hoop code
//! (0 = 110 × 110, 1 = 50 × 50, 2 = 140 × 200, 3 = 126 × 110, 4 = 200 × 200), the design's
//! half-width and half-height twice (0.1 mm from the hoop centre), the distances from the
//! edges of four hoops (−1 when it does not fit), then one Janome chart index per colour
//! (0 = a stop) and one thread type (0x0D) per colour. Stitches: two signed bytes (dx, dy in
//! 0.1 mm, y up); `80 01 dx dy` a colour change, `80 02 dx dy` a jump, `80 10` the end.
//!
//! JEF has no trim: machines cut before a long jump, and a run of jumps reaching more than
//! 3 mm on an axis reads as a trim (pyembroidery's reading); a trim before a shorter jump is
//! not kept. Colours are Janome chart indices: a thread is written as the nearest chart
//! thread, two successive colours that fall on the same index take the next nearest one. A
//! stop is a change to index 0.

use super::bytes::{put_i32le, put_u32le, Reader};
use super::records::{self, Op, Rec, TrimRule};
use super::threads::{nearest, thread_at, JEF_THREADS};
use super::{Format, FormatError};
use crate::plan::{StitchPlan, Thread};

pub(super) const MAX_STEP: i32 = 127;

/// Today's date and time (UTC) as the header writes it.
fn date() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + (m <= 2) as i64;
    format!(
        "{y:04}{m:02}{d:02}{:02}{:02}{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

fn hoop_code(w: i64, h: i64) -> i32 {
    if w < 500 && h < 500 {
        1
    } else if w < 1260 && h < 1100 {
        3
    } else if w < 1400 && h < 2000 {
        2
    } else if w < 2000 && h < 2000 {
        4
    } else {
        0
    }
}

pub(super) fn write(plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
    let recs = records::to_records(plan, MAX_STEP, Format::Jef)?;
    let threads = records::thread_sequence(&recs, plan);
    // Chart indices: a stop is a change to index 0 (no thread); a colour change takes the
    // nearest chart thread, the next nearest when the last colour took that index.
    let mut palette: Vec<i32> = Vec::new();
    let mut last: Option<(usize, [u8; 3])> = None;
    let mut k = 0;
    for (n, r) in std::iter::once(None)
        .chain(recs.iter().map(Some))
        .enumerate()
    {
        let stop = match r.map(|r| r.op) {
            None => false,
            Some(Op::ColorChange) => false,
            Some(Op::Stop) => true,
            _ => continue,
        };
        if n > 0 {
            k += 1;
        }
        if stop {
            palette.push(0);
            continue;
        }
        let rgb = threads[k.min(threads.len() - 1)].rgb;
        let mut i = nearest(rgb, &JEF_THREADS, &|_| false).unwrap_or(1);
        if let Some((li, lrgb)) = last {
            if li == i && lrgb != rgb {
                i = nearest(rgb, &JEF_THREADS, &|j| j == li).unwrap_or(i);
            }
        }
        last = Some((i, rgb));
        palette.push(i as i32);
    }
    let colours = palette.len();
    let count = 1 + recs
        .iter()
        .map(|r| match r.op {
            Op::Stitch => 1,
            Op::Jump | Op::ColorChange | Op::Stop => 2,
            Op::Trim | Op::End => 0,
        })
        .sum::<usize>();
    let ([x0, y0, x1, y1], _) = records::extents(&recs);
    let (w, h) = (x1 - x0, y1 - y0);
    let mut out = Vec::new();
    put_u32le(&mut out, (0x74 + colours * 8) as u32);
    put_u32le(&mut out, 0x14);
    out.extend_from_slice(date().as_bytes());
    out.extend_from_slice(&[0, 0]);
    put_u32le(&mut out, colours as u32);
    put_u32le(&mut out, count as u32);
    put_i32le(&mut out, hoop_code(w, h));
    let (hw, hh) = (((w + 1) / 2) as i32, ((h + 1) / 2) as i32);
    for v in [hw, hh, hw, hh] {
        put_i32le(&mut out, v);
    }
    for (hx, hy) in [(550, 550), (250, 250), (700, 1000), (700, 1000)] {
        let (ex, ey) = (hx - hw, hy - hh);
        let v = if ex.min(ey) >= 0 {
            [ex, ey, ex, ey]
        } else {
            [-1; 4]
        };
        for v in v {
            put_i32le(&mut out, v);
        }
    }
    for &p in &palette {
        put_i32le(&mut out, p);
    }
    for _ in 0..colours {
        put_u32le(&mut out, 0x0D);
    }
    for r in &recs {
        let (x, y) = (r.dx as i8 as u8, r.dy as i8 as u8);
        match r.op {
            Op::Stitch => out.extend_from_slice(&[x, y]),
            Op::Jump => out.extend_from_slice(&[0x80, 0x02, x, y]),
            Op::ColorChange | Op::Stop => out.extend_from_slice(&[0x80, 0x01, x, y]),
            Op::Trim => {}
            Op::End => out.extend_from_slice(&[0x80, 0x10]),
        }
    }
    Ok(out)
}

pub(super) fn read(bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
    let mut r = Reader::new(bytes, Format::Jef);
    if bytes.is_empty() {
        return Err(r.err(0, "the file is empty"));
    }
    let start = r.u32le("the stitches' offset")? as usize;
    r.skip(20, "the JEF header")?;
    let colours = r.u32le("the colour count")? as usize;
    // Each colour takes 8 header bytes before the stitches (index and type).
    if start < 0x74 || start > bytes.len() || colours > (start - 0x74) / 4 {
        return Err(r.err(
            if start < 0x74 || start > bytes.len() { 0 } else { 24 },
            format!(
                "the stitches' offset {start} and colour count {colours} do not fit the file's {} bytes: not a JEF file or a corrupt header",
                bytes.len()
            ),
        ));
    }
    r.seek(0x74, "the colour list")?;
    let mut indices = Vec::with_capacity(colours);
    for _ in 0..colours {
        indices.push((r.u32le("a colour index")? as i32).unsigned_abs() as usize);
    }
    r.seek(start, "the stitches")?;
    let mut recs = Vec::new();
    while r.remaining() > 0 {
        let at = r.pos;
        let b = r.take(2.min(r.remaining()), "a stitch")?;
        if b.len() < 2 {
            return Err(r.err(
                at,
                "a record is cut after 1 of 2 bytes: the file is truncated",
            ));
        }
        let (a, c) = (b[0], b[1]);
        if a != 0x80 {
            recs.push(Rec::new(a as i8 as i32, c as i8 as i32, Op::Stitch));
            continue;
        }
        if c == 0x10 {
            break;
        }
        let d = r.take(2, "a command's displacement")?;
        let (x, y) = (d[0] as i8 as i32, d[1] as i8 as i32);
        match c {
            0x02 => recs.push(Rec::new(x, y, Op::Jump)),
            // The change's own displacement is not applied (as pyembroidery reads it).
            0x01 => recs.push(Rec::new(0, 0, Op::ColorChange)),
            _ => return Err(r.err(at, format!("unknown command 80 {c:02X}"))),
        }
    }
    recs.push(Rec::new(0, 0, Op::End));
    // A change to index 0 is a stop (pyembroidery's reading); the others change colour.
    let mut threads: Vec<Thread> = Vec::new();
    let thread = |i: usize| thread_at(&JEF_THREADS, i).unwrap_or_else(|| Thread::rgb(0, 0, 0));
    let mut entries = indices.iter();
    if let Some(&i) = entries.next() {
        threads.push(thread(i));
    }
    let mut kept = Vec::with_capacity(recs.len());
    for rec in recs {
        if rec.op == Op::ColorChange {
            match entries.next() {
                Some(&i) if i % JEF_THREADS.len() == 0 => {
                    kept.push(Rec::new(0, 0, Op::Stop));
                    continue;
                }
                Some(&i) => threads.push(thread(i)),
                None => {}
            }
        }
        kept.push(rec);
    }
    let mut plan = records::to_plan(&kept, TrimRule::Distance(30));
    records::set_threads(&mut plan, &threads);
    plan.name = name.to_string();
    Ok(plan)
}
