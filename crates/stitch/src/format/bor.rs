//! The seed's ASCII embroidery program `.BOR` (§5.2, Appendix III): what CAMbor wrote to disk
//! and sent down the RS-232 line. One record a line, decimal, units table steps of 0.2 mm.
//!
//! The thesis lost the header (its Appendix III starts at the body), so Oficina's header is
//! three lines carrying the elements the thesis calls indispensable (L2178-2193), in the order
//! of the machine's RAM program (§5.3):
//!
//! ```text
//! 000 1        start of program, program number
//! 5200 4800    Zero-Peça from Zero-Máquina, steps, each + 5000 (here +200, −200 = +40, −40 mm)
//! 007          minimum hoop: 001–011 round (C01–C11), 101–106 oval (O01–O06), 000 none
//! ```
//!
//! Body, as the thesis gives it: `XXX YYY` a short stitch (3 digits each, + 500), `XXXX YYYY`
//! a long point (4 digits each, + 5000: the needle stops up, the hoop moves), `998 c` a
//! colour-change stop (new colour c; the same colour again is a plain stop), `98 n` head
//! speed code n (the thesis's "98 n", L1756, kept literally: its width tells it from a
//! stitch), and `999` on its own line, then the number of stitch records (short and long) on
//! the next. The reader checks that count, so a cut file is refused.
//!
//! Short stitches are at most 62 steps (12.4 mm), per axis and Euclidean; a longer sewn
//! stitch is split into equal short stitches on the step grid, a jump is long points of at
//! most 4999 steps per axis. The seed has no trim (the operator cuts joining threads): trims
//! are left out.

use super::seed_ram::{SeedHeader, STEP};
use super::{Format, FormatError};
use crate::hoop::{Hoop, HoopShape, HOOPS};
use crate::plan::{ColorBlock, Kind, Stitch, StitchPlan, Thread};
use crate::speed::speed_code;
use std::fmt::Write;

/// Longest short stitch, steps (12.4 mm).
const SHORT: i64 = 62;
/// Longest long point per axis, steps.
const LONG: i64 = 4999;

fn hoop_number(h: Option<Hoop>) -> u32 {
    let Some(h) = h else { return 0 };
    let n: u32 = h.code[1..].parse().unwrap_or(0);
    match h.shape {
        HoopShape::Round { .. } => n,
        HoopShape::Oval { .. } => 100 + n,
    }
}

fn hoop_of(n: u32) -> Option<Hoop> {
    let code = if n > 100 {
        format!("O{:02}", n - 100)
    } else {
        format!("C{n:02}")
    };
    HOOPS.iter().find(|h| h.code == code).copied()
}

/// The program text. Errors if the Zero-Peça leaves the header's ±4999 steps.
pub(crate) fn write(plan: &StitchPlan, h: &SeedHeader) -> Result<Vec<u8>, FormatError> {
    let err = |m: String| FormatError::new(Format::Bor, 0, m);
    let steps = |v: f64| -> Result<i64, FormatError> {
        let s = (v / STEP).round();
        if s.is_finite() && s.abs() < 1.0e9 {
            Ok(s as i64)
        } else {
            Err(err(format!("{v} mm is not a coordinate")))
        }
    };
    let (sx, sy) = (steps(h.start[0])?, steps(h.start[1])?);
    if sx.abs() > LONG || sy.abs() > LONG {
        return Err(err(format!(
            "Zero-Peça ({}, {}) mm is beyond the header's ±999.8 mm",
            h.start[0], h.start[1]
        )));
    }
    let mut out = String::new();
    let _ = writeln!(out, "000 {}", h.program);
    let _ = writeln!(out, "{:04} {:04}", sx + 5000, sy + 5000);
    let _ = writeln!(out, "{:03}", hoop_number(h.hoop));
    let mut count = 0usize;
    let mut cur = (0i64, 0i64);
    let mut speed: Option<u8> = None;
    let entries: Vec<(usize, Stitch)> = plan.entries().map(|(b, s)| (b, *s)).collect();
    let mut block = usize::MAX;
    for (i, &(b, s)) in entries.iter().enumerate() {
        if b != block {
            block = b;
            let _ = writeln!(out, "998 {:02}", b + 1);
        }
        let target = (steps(s.x)?, steps(s.y)?);
        let (dx, dy) = (target.0 - cur.0, target.1 - cur.1);
        match s.kind {
            Kind::Trim => continue,
            Kind::Stop => {
                let _ = writeln!(out, "998 {:02}", b + 1);
                continue;
            }
            Kind::Jump => {
                let n = (dx.abs().max(dy.abs()) + LONG - 1) / LONG;
                let mut prev = cur;
                for k in 1..=n.max(1) {
                    let p = (cur.0 + dx * k / n.max(1), cur.1 + dy * k / n.max(1));
                    let _ = writeln!(out, "{:04} {:04}", p.0 - prev.0 + 5000, p.1 - prev.1 + 5000);
                    count += 1;
                    prev = p;
                }
            }
            Kind::Stitch => {
                // The speed of the section this stitch opens: its longest stitch's code.
                if i == 0 || entries[i - 1].1.kind != Kind::Stitch || entries[i - 1].0 != b {
                    // Measured on the step grid, as the program holds the stitches, so a
                    // program read back and written again is the same text.
                    let mut longest: f64 = 0.0;
                    let mut prev = cur;
                    for (bb, e) in &entries[i..] {
                        if e.kind != Kind::Stitch || *bb != b {
                            break;
                        }
                        let q = (steps(e.x)?, steps(e.y)?);
                        let d = ((q.0 - prev.0) as f64).hypot((q.1 - prev.1) as f64) * STEP;
                        longest = longest.max(d);
                        prev = q;
                    }
                    let code = speed_code(longest.min(12.4)).map_or(4, |c| c.code);
                    if speed != Some(code) {
                        let _ = writeln!(out, "98 {code}");
                        speed = Some(code);
                    }
                }
                let len = ((dx * dx + dy * dy) as f64).sqrt();
                let n = ((len / SHORT as f64).ceil() as i64).max(1);
                let mut prev = cur;
                for k in 1..=n {
                    let p = (cur.0 + dx * k / n, cur.1 + dy * k / n);
                    let _ = writeln!(out, "{:03} {:03}", p.0 - prev.0 + 500, p.1 - prev.1 + 500);
                    count += 1;
                    prev = p;
                }
            }
        }
        cur = target;
    }
    let _ = writeln!(out, "999");
    let _ = writeln!(out, "{count}");
    Ok(out.into_bytes())
}

/// Reads a program: the plan (positions from Zero-Peça, mm) and its header. Errors name the
/// line.
pub(crate) fn read(bytes: &[u8]) -> Result<(StitchPlan, SeedHeader), FormatError> {
    let err = |o: usize, line: usize, m: &str| {
        FormatError::new(Format::Bor, o, format!("line {line}: {m}"))
    };
    if bytes.is_empty() {
        return Err(FormatError::new(Format::Bor, 0, "the file is empty"));
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|e| FormatError::new(Format::Bor, e.valid_up_to(), "not ASCII text"))?;
    // (byte offset, line number, fields) of each non-blank line; a DOS 0x1A ends the text.
    let text = text.split('\u{1a}').next().unwrap_or("");
    let mut lines = Vec::new();
    let mut off = 0;
    for (n, l) in text.split('\n').enumerate() {
        let f: Vec<&str> = l.split_whitespace().collect();
        if !f.is_empty() {
            lines.push((off, n + 1, f));
        }
        off += l.len() + 1;
    }
    let mut it = lines.into_iter();
    let end_off = text.len();
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit());
    let int = |s: &str, o: usize, n: usize, what: &str| -> Result<i64, FormatError> {
        if !digits(s) || s.len() > 9 {
            return Err(err(o, n, &format!("{what} '{s}' is not a decimal number")));
        }
        Ok(s.parse::<i64>().unwrap_or(0))
    };
    let Some((o, n, f)) = it.next() else {
        return Err(FormatError::new(Format::Bor, 0, "the file is empty"));
    };
    if f.len() != 2 || f[0] != "000" {
        return Err(err(
            o,
            n,
            "does not start with '000 <program number>': not a .BOR program",
        ));
    }
    let program = int(f[1], o, n, "program number")?;
    let program = u16::try_from(program)
        .map_err(|_| err(o, n, &format!("program number {program} is beyond 65535")))?;
    let Some((o, n, f)) = it.next() else {
        return Err(err(
            end_off,
            n + 1,
            "no Zero-Peça line: the file is truncated",
        ));
    };
    if f.len() != 2 || f[0].len() != 4 || f[1].len() != 4 {
        return Err(err(
            o,
            n,
            "the Zero-Peça line is not 'XXXX YYYY' (steps + 5000)",
        ));
    }
    let start = [
        (int(f[0], o, n, "Zero-Peça X")? - 5000) as f64 * STEP,
        (int(f[1], o, n, "Zero-Peça Y")? - 5000) as f64 * STEP,
    ];
    let Some((o, n, f)) = it.next() else {
        return Err(err(end_off, n + 1, "no hoop line: the file is truncated"));
    };
    if f.len() != 1 {
        return Err(err(o, n, "the hoop line is not one number"));
    }
    let hn = int(f[0], o, n, "hoop")?;
    let hoop = hoop_of(hn as u32);
    if hn != 0 && hoop.is_none() {
        return Err(err(
            o,
            n,
            &format!("hoop {hn} is none of 001–011 (round) or 101–106 (oval)"),
        ));
    }
    let header = SeedHeader {
        program,
        start,
        hoop,
    };
    let palette = super::records::PALETTE;
    let new_block = |c: i64| {
        let [r, g, b] = palette[(c.max(1) as usize - 1) % palette.len()];
        let mut t = Thread::rgb(r, g, b);
        t.name = format!("colour {c}");
        ColorBlock {
            thread: t,
            stitches: vec![],
        }
    };
    let mut blocks: Vec<ColorBlock> = Vec::new();
    let mut colour: Option<i64> = None;
    let (mut x, mut y) = (0i64, 0i64);
    let mm = |v: i64| v as f64 * STEP;
    let mut count = 0usize;
    let mut last = n;
    while let Some((o, n, f)) = it.next() {
        last = n;
        match (f.as_slice(), f.first().map_or(0, |s| s.len())) {
            (["999"], _) => {
                let Some((o2, n2, f2)) = it.next() else {
                    return Err(err(
                        end_off,
                        n + 1,
                        "no stitch count after the end record 999: the file is truncated",
                    ));
                };
                if f2.len() != 1 {
                    return Err(err(o2, n2, "the stitch count is not one number"));
                }
                let want = int(f2[0], o2, n2, "stitch count")?;
                if want as usize != count {
                    return Err(err(
                        o2,
                        n2,
                        &format!("the program says {want} stitches, its records hold {count}"),
                    ));
                }
                if let Some((o3, n3, _)) = it.next() {
                    return Err(err(o3, n3, "text after the end of the program"));
                }
                if blocks.is_empty() {
                    blocks.push(new_block(1));
                }
                return Ok((
                    StitchPlan {
                        name: format!("program {program}"),
                        blocks,
                    },
                    header,
                ));
            }
            (["998", c], _) => {
                let c = int(c, o, n, "colour")?;
                if colour == Some(c) {
                    let b = blocks.last_mut().expect("a colour has its block");
                    b.stitches.push(Stitch::new(mm(x), mm(y), Kind::Stop));
                } else {
                    blocks.push(new_block(c));
                    colour = Some(c);
                }
            }
            (["98", c], _) => {
                let c = int(c, o, n, "speed code")?;
                if !(1..=12).contains(&c) {
                    return Err(err(o, n, &format!("speed code {c} is not 1–12")));
                }
            }
            ([a, b], w @ (3 | 4)) if b.len() == w => {
                let off = if w == 3 { 500 } else { 5000 };
                x += int(a, o, n, "X")? - off;
                y += int(b, o, n, "Y")? - off;
                if blocks.is_empty() {
                    blocks.push(new_block(1));
                    colour = Some(1);
                }
                let kind = if w == 3 { Kind::Stitch } else { Kind::Jump };
                blocks
                    .last_mut()
                    .expect("made above")
                    .stitches
                    .push(Stitch::new(mm(x), mm(y), kind));
                count += 1;
            }
            _ => {
                return Err(err(
                    o,
                    n,
                    &format!(
                        "'{}' is no record (XXX YYY, XXXX YYYY, 998 c, 98 n, 999)",
                        f.join(" ")
                    ),
                ))
            }
        }
    }
    Err(err(
        end_off,
        last + 1,
        "no end record 999: the file is truncated",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan() -> StitchPlan {
        let s = |x: f64, y: f64, k| Stitch::new(x, y, k);
        StitchPlan {
            name: "t".into(),
            blocks: vec![
                ColorBlock {
                    thread: Thread::rgb(0, 0, 0),
                    stitches: vec![
                        s(1.0, -1.0, Kind::Stitch),
                        s(2.4, -2.2, Kind::Stitch),
                        s(40.0, -48.2, Kind::Jump),
                        s(43.4, -45.8, Kind::Stitch),
                        s(43.4, -45.8, Kind::Stop),
                        s(44.0, -45.8, Kind::Stitch),
                    ],
                },
                ColorBlock {
                    thread: Thread::rgb(1, 2, 3),
                    stitches: vec![s(-300.0, 0.0, Kind::Jump), s(-290.0, 0.0, Kind::Stitch)],
                },
            ],
        }
    }

    #[test]
    fn writes_the_records_the_thesis_gives_and_reads_them_back() {
        let h = SeedHeader {
            program: 3,
            start: [40.0, -40.0],
            hoop: hoop_of(7),
        };
        let bytes = write(&plan(), &h).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(&lines[..4], ["000 3", "5200 4800", "007", "998 01"]);
        // +5, −5 steps; then +7, −6 (1.4, −1.2 mm).
        assert_eq!(&lines[5..7], ["505 495", "507 494"]);
        // The jump from (12, −11) to (200, −241) steps: one long point.
        assert_eq!(lines[7], "5188 4770");
        assert_eq!(lines[lines.len() - 2], "999");
        let (back, h2) = read(&bytes).unwrap();
        assert_eq!(h2, h);
        assert_eq!(back.blocks.len(), 2);
        for (a, b) in back.blocks.iter().zip(plan().blocks) {
            assert_eq!(a.stitches.len(), b.stitches.len());
            for (p, q) in a.stitches.iter().zip(&b.stitches) {
                assert_eq!(p.kind, q.kind);
                assert!(
                    (p.x - q.x).abs() < 1e-9 && (p.y - q.y).abs() < 1e-9,
                    "{p:?} {q:?}"
                );
            }
        }
        assert_eq!(lines.last(), Some(&"7"));
    }

    #[test]
    fn long_sewn_stitches_split_on_the_grid() {
        let p = StitchPlan {
            name: "l".into(),
            blocks: vec![ColorBlock {
                thread: Thread::rgb(0, 0, 0),
                stitches: vec![Stitch::new(30.0, 0.0, Kind::Stitch)],
            }],
        };
        let bytes = write(
            &p,
            &SeedHeader {
                program: 1,
                start: [0.0; 2],
                hoop: None,
            },
        )
        .unwrap();
        let (back, _) = read(&bytes).unwrap();
        // 150 steps in ⌈150/62⌉ = 3 stitches of 50.
        let xs: Vec<f64> = back.blocks[0].stitches.iter().map(|s| s.x).collect();
        assert_eq!(xs, [10.0, 20.0, 30.0]);
    }

    #[test]
    fn bad_programs_name_their_line() {
        let h = SeedHeader {
            program: 1,
            start: [0.0; 2],
            hoop: None,
        };
        let good = String::from_utf8(write(&plan(), &h).unwrap()).unwrap();
        let lines: Vec<&str> = good.lines().collect();
        // Truncated: the end record and count gone, or only the count.
        let cut = lines[..lines.len() - 2].join("\n");
        let e = read(cut.as_bytes()).unwrap_err();
        assert!(e.to_string().contains("truncated"), "{e}");
        let cut = lines[..lines.len() - 1].join("\n");
        assert!(read(cut.as_bytes())
            .unwrap_err()
            .to_string()
            .contains("truncated"));
        // A lost stitch line: the count disagrees.
        let mut lost = lines.clone();
        lost.remove(5);
        let e = read(lost.join("\n").as_bytes()).unwrap_err();
        assert!(e.to_string().contains("its records hold"), "{e}");
        // A damaged record names its line.
        let mut bad = lines.clone();
        bad[5] = "50x 495";
        let e = read(bad.join("\n").as_bytes()).unwrap_err();
        assert!(e.to_string().contains("line 6"), "{e}");
        let e = read(b"hello").unwrap_err();
        assert!(e.to_string().contains("not a .BOR"), "{e}");
        assert!(read(b"").unwrap_err().to_string().contains("empty"));
    }
}
