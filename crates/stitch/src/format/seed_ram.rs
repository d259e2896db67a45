//! The seed's compact machine program (§5.3, Appendix IV): what the 8085 held in RAM and
//! what its EPROM cartridges were to hold. Units are table steps of 0.2 mm; the start is
//! absolute, everything after incremental.
//!
//! Header: `00 00`, program number (u16 LE), start X and Y from Zero-Máquina (u16 LE,
//! excess 0x8000), minimum hoop (1 byte: round hoops 01–11 as the seed; ovals 0x81–0x86, a
//! choice the seed leaves open). Body, by first byte: `01` long point (dX, dY as u16 LE
//! excess 0x8000: the needle stops up, the hoop moves), `02 c` colour stop (new colour c),
//! `FE n` head speed level n, `FF FF` end; any other pair is a short stitch (0x80 + dX,
//! 0x80 + dY). Short stitches are at most 62 steps (12.4 mm) per axis and Euclidean, which
//! also keeps their bytes clear of the codes 00, 01, 02, FE, FF; longer moves are long
//! points. The seed has no trim (the operator cuts the joining threads); a stop is a colour
//! stop with the same colour.

use super::{Format, FormatError};
use crate::hoop::{Hoop, HoopShape, HOOPS};
use crate::plan::{ColorBlock, Kind, Stitch, StitchPlan, Thread};
use crate::speed::speed_code;

/// mm per table step.
pub const STEP: f64 = 0.2;
/// Longest short stitch, steps (12.4 mm).
const SHORT: i64 = 62;

/// The program's header fields besides the stitches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeedHeader {
    /// The program number.
    pub program: u16,
    /// Zero-Peça from Zero-Máquina, mm (rounded to steps).
    pub start: [f64; 2],
    /// The hoop the program names, if any.
    pub hoop: Option<Hoop>,
}

fn hoop_byte(h: Option<Hoop>) -> u8 {
    let Some(h) = h else { return 0 };
    let n: u8 = h.code[1..].parse().unwrap_or(0);
    match h.shape {
        HoopShape::Round { .. } => n,
        HoopShape::Oval { .. } => 0x80 | n,
    }
}

fn hoop_of(b: u8) -> Option<Hoop> {
    let code = if b & 0x80 != 0 {
        format!("O{:02}", b & 0x7f)
    } else {
        format!("C{b:02}")
    };
    HOOPS.iter().find(|h| h.code == code).copied()
}

fn excess16(v: i64) -> [u8; 2] {
    ((v + 0x8000) as u16).to_le_bytes()
}

/// The program bytes. Errors if a coordinate leaves the 16-bit step range (±6.5 m).
pub(crate) fn write(plan: &StitchPlan, h: &SeedHeader) -> Result<Vec<u8>, FormatError> {
    let err = |m: String| FormatError::new(Format::SeedRam, 0, m);
    let steps = |v: f64| -> Result<i64, FormatError> {
        let s = (v / STEP).round();
        if s.is_finite() && s.abs() < 32_000.0 {
            Ok(s as i64)
        } else {
            Err(err(format!("{v} mm is beyond the program's ±6.4 m range")))
        }
    };
    let mut out = vec![0, 0];
    out.extend_from_slice(&h.program.to_le_bytes());
    let (sx, sy) = (steps(h.start[0])?, steps(h.start[1])?);
    out.extend_from_slice(&excess16(sx));
    out.extend_from_slice(&excess16(sy));
    out.push(hoop_byte(h.hoop));
    let mut cur = (0i64, 0i64);
    let mut speed: Option<u8> = None;
    let entries: Vec<(usize, Stitch)> = plan.entries().map(|(b, s)| (b, *s)).collect();
    let mut block = usize::MAX;
    for (i, &(b, s)) in entries.iter().enumerate() {
        if b != block {
            block = b;
            // Colours numbered from 1 in the plan's order.
            out.extend_from_slice(&[0x02, (b + 1).min(255) as u8]);
        }
        let target = (steps(s.x)?, steps(s.y)?);
        let (dx, dy) = (target.0 - cur.0, target.1 - cur.1);
        match s.kind {
            Kind::Trim => continue,
            Kind::Stop => {
                out.extend_from_slice(&[0x02, (b + 1).min(255) as u8]);
                continue;
            }
            Kind::Jump => {
                out.push(0x01);
                out.extend_from_slice(&excess16(dx));
                out.extend_from_slice(&excess16(dy));
            }
            Kind::Stitch => {
                // The speed of the section this stitch opens: its longest stitch's code.
                if i == 0 || entries[i - 1].1.kind != Kind::Stitch || entries[i - 1].0 != b {
                    let mut longest: f64 = 0.0;
                    let mut prev = (cur.0 as f64 * STEP, cur.1 as f64 * STEP);
                    for (bb, e) in &entries[i..] {
                        if e.kind != Kind::Stitch || *bb != b {
                            break;
                        }
                        longest = longest.max((e.x - prev.0).hypot(e.y - prev.1));
                        prev = (e.x, e.y);
                    }
                    let code = speed_code(longest).map_or(4, |c| c.code);
                    if speed != Some(code) {
                        out.extend_from_slice(&[0xFE, code]);
                        speed = Some(code);
                    }
                }
                if dx.abs() <= SHORT
                    && dy.abs() <= SHORT
                    && ((dx * dx + dy * dy) as f64).sqrt() <= SHORT as f64
                {
                    out.extend_from_slice(&[(0x80 + dx) as u8, (0x80 + dy) as u8]);
                } else {
                    out.push(0x01);
                    out.extend_from_slice(&excess16(dx));
                    out.extend_from_slice(&excess16(dy));
                }
            }
        }
        cur = target;
    }
    out.extend_from_slice(&[0xFF, 0xFF]);
    Ok(out)
}

/// Reads a program: the plan (positions from Zero-Peça, mm) and its header.
pub(crate) fn read(bytes: &[u8]) -> Result<(StitchPlan, SeedHeader), FormatError> {
    let err = |o: usize, m: &str| FormatError::new(Format::SeedRam, o, m.to_string());
    if bytes.is_empty() {
        return Err(err(0, "the file is empty"));
    }
    if bytes.len() < 9 {
        return Err(err(
            bytes.len(),
            "shorter than the 9-byte header: truncated",
        ));
    }
    if bytes[0] != 0 || bytes[1] != 0 {
        return Err(err(
            0,
            "does not start with the start code 00 00: not a seed program",
        ));
    }
    let u16le = |i: usize| u16::from_le_bytes([bytes[i], bytes[i + 1]]) as i64;
    let header = SeedHeader {
        program: u16le(2) as u16,
        start: [
            (u16le(4) - 0x8000) as f64 * STEP,
            (u16le(6) - 0x8000) as f64 * STEP,
        ],
        hoop: hoop_of(bytes[8]),
    };
    let mut blocks: Vec<ColorBlock> = Vec::new();
    let palette = super::records::PALETTE;
    let (mut x, mut y) = (0i64, 0i64);
    let mut i = 9;
    let mm = |v: i64| v as f64 * STEP;
    let need = |i: usize, n: usize, what: &str| {
        if i + n > bytes.len() {
            Err(err(i, &format!("{what} cut short: the file is truncated")))
        } else {
            Ok(())
        }
    };
    loop {
        need(i, 2, "a record")?;
        let (a, b) = (bytes[i], bytes[i + 1]);
        if blocks.is_empty() && a != 0x02 {
            let [r, g, bl] = palette[0];
            blocks.push(ColorBlock {
                thread: Thread::rgb(r, g, bl),
                stitches: vec![],
            });
        }
        match a {
            0xFF if b == 0xFF => break,
            0x01 => {
                need(i, 5, "a long point")?;
                x += u16le(i + 1) - 0x8000;
                y += u16le(i + 3) - 0x8000;
                let block = blocks.last_mut().unwrap();
                // A long point after a stitch sews at its end once the hoop is there: our
                // jump then a needle point; a long point before a stitch is the travel.
                block.stitches.push(Stitch::new(mm(x), mm(y), Kind::Jump));
                i += 5;
                continue;
            }
            0x02 => {
                let new_block = blocks.last().is_none_or(|bl| !bl.stitches.is_empty());
                if new_block {
                    let [r, g, bl] = palette[(b as usize).saturating_sub(1) % palette.len()];
                    let mut t = Thread::rgb(r, g, bl);
                    t.name = format!("colour {b}");
                    blocks.push(ColorBlock {
                        thread: t,
                        stitches: vec![],
                    });
                }
            }
            0xFE => {}
            0x00 | 0xFF => {
                return Err(err(
                    i,
                    &format!("code {a:02X} {b:02X} is not a record here"),
                ))
            }
            _ => {
                x += a as i64 - 0x80;
                y += b as i64 - 0x80;
                blocks
                    .last_mut()
                    .unwrap()
                    .stitches
                    .push(Stitch::new(mm(x), mm(y), Kind::Stitch));
            }
        }
        i += 2;
    }
    Ok((
        StitchPlan {
            name: format!("program {}", header.program),
            blocks,
        },
        header,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The seed's worked example (§5.3, L2217-2250), byte for byte.
    const EXAMPLE: [u8; 32] = [
        0x00, 0x00, 0x01, 0x00, 0xC8, 0x80, 0x38, 0x7F, 0x07, 0x02, 0x03, 0xFE, 0x05, 0x85, 0x7B,
        0x87, 0x7A, 0x85, 0x80, 0x72, 0x74, 0x81, 0x71, 0x82, 0x87, 0x01, 0x14, 0x80, 0x18, 0x7F,
        0x91, 0x8C,
    ];

    #[test]
    fn the_seeds_example_decodes() {
        let mut bytes = EXAMPLE.to_vec();
        bytes.extend_from_slice(&[0xFF, 0xFF]);
        let (plan, h) = read(&bytes).unwrap();
        assert_eq!(h.program, 1);
        assert_eq!(h.start, [40.0, -40.0]);
        assert_eq!(h.hoop.unwrap().name(), "round-190");
        let s = &plan.blocks[0].stitches;
        let steps: Vec<(i64, i64)> = s
            .iter()
            .map(|p| ((p.x / STEP).round() as i64, (p.y / STEP).round() as i64))
            .collect();
        // +5,−5; +7,−6; +5,0; −14,−12; +1,−15; +2,+7; long +20,−232; +17,+12 (cumulative).
        assert_eq!(
            steps,
            [
                (5, -5),
                (12, -11),
                (17, -11),
                (3, -23),
                (4, -38),
                (6, -31),
                (26, -263),
                (43, -251)
            ]
        );
        assert_eq!(s[6].kind, Kind::Jump);
        assert_eq!(plan.blocks[0].thread.name, "colour 3");
    }

    #[test]
    fn write_then_read_keeps_every_point_on_the_step_grid() {
        let (plan, h) = {
            let mut b = EXAMPLE.to_vec();
            b.extend_from_slice(&[0xFF, 0xFF]);
            read(&b).unwrap()
        };
        let bytes = write(&plan, &h).unwrap();
        let (back, h2) = read(&bytes).unwrap();
        assert_eq!(h, h2);
        assert_eq!(back.blocks[0].stitches, plan.blocks[0].stitches);
        // A speed record at the start: the first section's longest stitch is the long
        // point's neighbour, 15 steps = 3 mm → code 11.
        assert!(bytes.windows(2).any(|w| w == [0xFE, 11]));
        let e = read(&bytes[..bytes.len() - 3]).unwrap_err();
        assert!(e.to_string().contains("truncated"), "{e}");
    }
}
