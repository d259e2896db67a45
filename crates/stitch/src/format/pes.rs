//! Brother PES: a PE-Design header, then the PEC section machines sew from (see pec.rs).
//! `#PES` and a 4-digit version, the PEC section's offset (32-bit LE), the version's header,
//! and the design as `CEmbOne`/`CSewSeg` blocks (segments of stitches or jumps, each with its
//! colour); from version 5 the header lists the threads (catalogue number, RGB, name, brand,
//! chart), so colours are exact, where version 1 has only the PEC chart's 64 threads.
//!
//! Oficina writes version 1 and version 6 (as pyembroidery does) and reads every version's
//! PEC section, with the thread list of versions 5 to 10 when the header holds no
//! programmable fills, motifs or feather patterns (past those the header cannot be walked,
//! and the PEC chart colours are used, as pyembroidery does).

use super::bytes::{patch_u32le, put_f32le, put_u16le, put_u32le, Reader};
use super::pec;
use super::records;
use super::{Format, FormatError};
use crate::plan::{Kind, StitchPlan, Thread};

/// Which PES header to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Version {
    V1,
    V6,
}

fn put_string8(out: &mut Vec<u8>, s: &str) {
    let b: Vec<u8> = s.bytes().take(255).collect();
    out.push(b.len() as u8);
    out.extend_from_slice(&b);
}

fn put_string16(out: &mut Vec<u8>, s: &str) {
    put_u16le(out, s.len() as u16);
    out.extend_from_slice(s.as_bytes());
}

/// One `CSewSeg` segment: stitches (flag 0) or a jump (flag 1), its colour code and points.
struct Segment {
    jump: bool,
    colour: u16,
    points: Vec<(i64, i64)>,
}

/// The plan's segments in PES coordinates (0.1 mm, y down, from the design's left and
/// bottom): runs of stitches, and jumps from the last stitch to the jump's end. `codes`
/// gives each colour entry's code (blocks and stops advance it, as the PEC list does).
fn segments(plan: &StitchPlan, codes: &[u16]) -> Vec<Segment> {
    let u = |v: f64| (v * 10.0).round() as i64;
    let Some([x0, y0, _, _]) = plan.bounds() else {
        return Vec::new();
    };
    let (ox, oy) = (u(x0), u(y0));
    let at = |x: f64, y: f64| (u(x) - ox, oy - u(y));
    let mut segs: Vec<Segment> = Vec::new();
    let mut entry = 0usize;
    // A jump from before any stitch starts at the origin.
    let mut last = at(0.0, 0.0);
    let mut in_stitches = false;
    for (b, block) in plan.blocks.iter().enumerate() {
        if b > 0 {
            entry += 1;
            in_stitches = false;
        }
        for s in &block.stitches {
            let code = codes.get(entry).copied().unwrap_or(0);
            match s.kind {
                Kind::Stitch => {
                    last = at(s.x, s.y);
                    match segs.last_mut() {
                        Some(seg) if in_stitches => seg.points.push(last),
                        _ => segs.push(Segment {
                            jump: false,
                            colour: code,
                            points: vec![last],
                        }),
                    }
                    in_stitches = true;
                }
                Kind::Jump => {
                    segs.push(Segment {
                        jump: true,
                        colour: code,
                        points: vec![last, at(s.x, s.y)],
                    });
                    in_stitches = false;
                }
                Kind::Stop => {
                    entry += 1;
                    in_stitches = false;
                }
                Kind::Trim => in_stitches = false,
            }
        }
    }
    segs
}

/// `CEmbOne` and `CSewSeg` with the segments; returns the colour log (section, code).
fn put_blocks(out: &mut Vec<u8>, segs: &[Segment], width: i64, height: i64) -> Vec<(u16, u16)> {
    put_string16(out, "CEmbOne");
    out.extend_from_slice(&[0; 16]);
    // The placement transform PE-Design expects: identity, translated into its 130 × 180 mm
    // page.
    let (w, h) = (width as f32, height as f32);
    for v in [
        1.0,
        0.0,
        0.0,
        1.0,
        350.0 + 650.0 - w / 2.0,
        100.0 + h + 900.0 - h / 2.0,
    ] {
        put_f32le(out, v);
    }
    for v in [1u16, 0, 0] {
        put_u16le(out, v);
    }
    put_u16le(out, width.clamp(0, u16::MAX as i64) as u16);
    put_u16le(out, height.clamp(0, u16::MAX as i64) as u16);
    out.extend_from_slice(&[0; 8]);
    put_u16le(out, segs.len().min(u16::MAX as usize) as u16);
    put_u16le(out, 0xFFFF);
    put_u16le(out, 0);
    put_string16(out, "CSewSeg");
    let mut log: Vec<(u16, u16)> = Vec::new();
    for (i, s) in segs.iter().enumerate() {
        if i > 0 {
            put_u16le(out, 0x8003);
        }
        if log.last().is_none_or(|&(_, c)| c != s.colour) {
            log.push((i as u16, s.colour));
        }
        put_u16le(out, s.jump as u16);
        put_u16le(out, s.colour);
        put_u16le(out, s.points.len().min(u16::MAX as usize) as u16);
        for &(x, y) in s.points.iter().take(u16::MAX as usize) {
            put_u16le(out, x as i16 as u16);
            put_u16le(out, y as i16 as u16);
        }
    }
    put_u16le(out, log.len() as u16);
    for &(sec, c) in &log {
        put_u16le(out, sec);
        put_u16le(out, c);
    }
    put_u32le(out, 0);
    log
}

pub(super) fn write(plan: &StitchPlan, version: Version) -> Result<Vec<u8>, FormatError> {
    let recs = records::to_records(plan, pec::MAX_STEP, Format::Pes)?;
    let ([x0, y0, x1, y1], _) = records::extents(&recs);
    let (width, height) = (x1 - x0, y1 - y0);
    // The PEC section first: it fixes the colour entries and their chart indices.
    let section = pec::write_section(plan, &recs, &plan.name)?;
    let mut out = Vec::new();
    let empty = plan.is_empty();
    match version {
        Version::V1 => {
            out.extend_from_slice(b"#PES0001");
            put_u32le(&mut out, 0);
            for v in [1u16, 1, !empty as u16] {
                put_u16le(&mut out, v);
            }
        }
        Version::V6 => {
            out.extend_from_slice(b"#PES0060");
            put_u32le(&mut out, 0);
            put_u16le(&mut out, 1);
            out.extend_from_slice(b"02");
            put_string8(&mut out, &plan.name);
            // Empty category, author, keywords and comments.
            out.extend_from_slice(&[0; 4]);
            // Hoop, page and grid settings of PE-Design 6.
            for v in [
                0u16, 0, 0x64, 0x64, 0, 0xC8, 0xC8, 0x64, 0x64, 0x64, 0x07, 0x13, 1, 1, 0, 100, 1,
                0,
            ] {
                put_u16le(&mut out, v);
            }
            out.push(0); // no image file
            for v in [1.0f32, 0.0, 0.0, 1.0, 0.0, 0.0] {
                put_f32le(&mut out, v);
            }
            for _ in 0..3 {
                put_u16le(&mut out, 0); // programmable fills, motifs, feather patterns
            }
            put_u16le(&mut out, section.threads.len() as u16);
            for t in &section.threads {
                put_string8(&mut out, "");
                out.extend_from_slice(&[t.rgb[0], t.rgb[1], t.rgb[2], 0]);
                put_u32le(&mut out, 0xA); // a custom colour
                put_string8(&mut out, &t.name);
                put_string8(&mut out, "");
                put_string8(&mut out, "");
            }
            put_u16le(&mut out, !empty as u16);
        }
    }
    if empty {
        put_u32le(&mut out, 0);
    } else {
        put_u16le(&mut out, 0xFFFF);
        put_u16le(&mut out, 0);
        let codes: Vec<u16> = match version {
            Version::V1 => section.indices.iter().map(|&i| i as u16).collect(),
            Version::V6 => (0..section.threads.len() as u16).collect(),
        };
        let log = put_blocks(&mut out, &segments(plan, &codes), width, height);
        if version == Version::V6 {
            put_u32le(&mut out, 0);
            put_u32le(&mut out, 0);
            for i in 0..log.len() as u32 {
                put_u32le(&mut out, i);
                put_u32le(&mut out, 0);
            }
        }
    }
    let at = out.len();
    patch_u32le(&mut out, 8, at as u32);
    out.extend_from_slice(&section.bytes);
    if version == Version::V6 {
        out.extend_from_slice(&section.indices);
        out.resize(
            out.len() + 128usize.saturating_sub(section.indices.len()),
            0x20,
        );
        for _ in &section.threads {
            out.extend_from_slice(&[0; 0x90]);
        }
        for t in &section.threads {
            out.extend_from_slice(&[t.rgb[2], t.rgb[1], t.rgb[0]]);
        }
        put_u16le(&mut out, 0);
    }
    Ok(out)
}

fn string8(r: &mut Reader, what: &str) -> Result<String, FormatError> {
    let n = r.u8(what)? as usize;
    Ok(String::from_utf8_lossy(r.take(n, what)?).to_string())
}

/// The design's name and thread list from a version's header, where it can be walked.
fn header(r: &mut Reader, version: u32) -> Result<(Option<String>, Vec<Thread>), FormatError> {
    // Bytes to skip: before the image name, after it (versions 5 to 10).
    let (hoop_name, before, after) = match version {
        50 | 55 | 56 => (false, 24, 24),
        60 | 70 => (false, 36, 24),
        80 => (false, 38, 26),
        90 => (true, 30, 34),
        100 => (true, 38, 34),
        40 => (false, 0, 0),
        _ => return Ok((None, Vec::new())),
    };
    r.skip(4, "the PES header")?;
    let name = string8(r, "the design's name")?;
    for what in ["category", "author", "keywords", "comments"] {
        string8(r, what)?;
    }
    let name = Some(name).filter(|n| !n.is_empty());
    if version == 40 {
        return Ok((name, Vec::new()));
    }
    if hoop_name {
        r.skip(14, "the PES header")?;
        string8(r, "the hoop's name")?;
    }
    r.skip(before, "the PES header")?;
    string8(r, "the image file's name")?;
    r.skip(after, "the PES header")?;
    for what in ["programmable fills", "motifs", "feather patterns"] {
        if r.u16le(what)? != 0 {
            return Ok((name, Vec::new()));
        }
    }
    let n = r.u16le("the thread count")? as usize;
    let mut threads = Vec::new();
    for _ in 0..n {
        string8(r, "a thread's catalogue number")?;
        let c = r.take(3, "a thread's colour")?;
        let rgb = [c[0], c[1], c[2]];
        r.skip(5, "a thread")?;
        let name = string8(r, "a thread's name")?;
        string8(r, "a thread's brand")?;
        string8(r, "a thread's chart")?;
        threads.push(Thread { rgb, name });
    }
    Ok((name, threads))
}

pub(super) fn read(bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
    let mut r = Reader::new(bytes, Format::Pes);
    if bytes.is_empty() {
        return Err(r.err(0, "the file is empty"));
    }
    if bytes.starts_with(b"#PEC0001") {
        let (label, recs, indices) = pec::read_section(&mut r, 8)?;
        return Ok(pec::finish(recs, pec::chart_threads(&indices), label, name));
    }
    let magic = r.take(8, "the \"#PES\" signature")?;
    if !magic.starts_with(b"#PES") {
        return Err(r.err(0, "the file does not start with \"#PES\": not a PES file"));
    }
    let version = std::str::from_utf8(&magic[4..])
        .ok()
        .and_then(|v| v.parse::<u32>().ok());
    let pec_at = r.u32le("the PEC section's offset")? as usize;
    if pec_at < 12 || pec_at >= bytes.len() {
        return Err(r.err(
            8,
            format!(
                "the PEC section's offset {pec_at} is outside the file's {} bytes",
                bytes.len()
            ),
        ));
    }
    // The header's thread list is a bonus: a header we cannot walk leaves the PEC colours.
    let (pes_name, chart) = version
        .map(|v| {
            let mut h = Reader::new(&bytes[..pec_at], Format::Pes);
            h.pos = 12;
            header(&mut h, v).unwrap_or((None, Vec::new()))
        })
        .unwrap_or((None, Vec::new()));
    let (label, recs, indices) = pec::read_section(&mut r, pec_at)?;
    let threads = colours(&indices, chart);
    Ok(pec::finish(recs, threads, pes_name.or(label), name))
}

/// The threads of the PEC colour list given the header's chart: one for one when the chart
/// is as long, else each distinct PEC index takes the chart's next thread (PE-Design's
/// allocation, as pyembroidery reads it), else the PEC chart.
fn colours(indices: &[u8], mut chart: Vec<Thread>) -> Vec<Thread> {
    if chart.is_empty() {
        return pec::chart_threads(indices);
    }
    if chart.len() >= indices.len() {
        return chart;
    }
    let mut map: Vec<(u8, Thread)> = Vec::new();
    let pec = pec::chart_threads(indices);
    indices
        .iter()
        .zip(pec)
        .map(|(&i, fallback)| {
            if let Some((_, t)) = map.iter().find(|(j, _)| *j == i % 65) {
                return t.clone();
            }
            let t = if chart.is_empty() {
                fallback
            } else {
                chart.remove(0)
            };
            map.push((i % 65, t.clone()));
            t
        })
        .collect()
}
