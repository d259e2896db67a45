//! The head-speed table of the seed (§8, Fig 3.14): the EFKA positioner's 12 levels and the
//! stitch lengths each may sew. The seed picks, per figure, the fastest code whose range
//! holds the figure's longest stitch. The ranges are written on a 0.1 mm grid with gaps
//! (2.5 | 2.6, and 6.6 mm is missing): a length in a gap takes the next slower code, so a
//! stitch never runs faster than the table allows for its length (2.52 mm → code 11, 6.6 →
//! code 8). Over 12.4 mm the needle stops: a long point (jump).

use crate::generate::MAX_STITCHES;
use crate::plan::{Kind, Stitch, StitchPlan};

/// One speed level: code, head speed in stitches per minute, longest stitch (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedCode {
    /// The speed code.
    pub code: u8,
    /// Head speed, stitches per minute.
    pub ppm: f64,
    /// Longest stitch at this speed, mm.
    pub max_stitch: f64,
}

/// Codes 4–12 from the fastest; codes 1–3 (80, 160, 235 ppm) also sew up to 12.4 mm but are
/// never the fastest choice.
pub const SPEED_CODES: [SpeedCode; 9] = [
    SpeedCode {
        code: 12,
        ppm: 1100.0,
        max_stitch: 2.5,
    },
    SpeedCode {
        code: 11,
        ppm: 630.0,
        max_stitch: 5.9,
    },
    SpeedCode {
        code: 10,
        ppm: 615.0,
        max_stitch: 6.1,
    },
    SpeedCode {
        code: 9,
        ppm: 580.0,
        max_stitch: 6.5,
    },
    SpeedCode {
        code: 8,
        ppm: 560.0,
        max_stitch: 6.9,
    },
    SpeedCode {
        code: 7,
        ppm: 510.0,
        max_stitch: 7.7,
    },
    SpeedCode {
        code: 6,
        ppm: 465.0,
        max_stitch: 8.6,
    },
    SpeedCode {
        code: 5,
        ppm: 365.0,
        max_stitch: 11.3,
    },
    SpeedCode {
        code: 4,
        ppm: 300.0,
        max_stitch: 12.4,
    },
];

/// The longest stitch the machine sews with the needle running (mm).
pub const MAX_SEWN: f64 = 12.4;

/// The fastest code for a figure whose longest stitch is `len` mm; None above 12.4 mm.
pub fn speed_code(len: f64) -> Option<SpeedCode> {
    SPEED_CODES
        .iter()
        .copied()
        .find(|c| len <= c.max_stitch + 1e-9)
}

/// A section: consecutive sewn stitches of one block (jumps, trims, stops and colour changes
/// end one), the unit the seed gives one head speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// Its first entry, counted over the whole plan in sewing order.
    pub start: usize,
    /// One past its last entry.
    pub end: usize,
    /// Its longest stitch, mm (a stitch's length is from the previous point of the plan).
    pub longest: f64,
    /// The code the seed picks for it: the fastest whose range holds `longest`; None above
    /// 12.4 mm (a stitch the machine cannot sew).
    pub code: Option<u8>,
}

/// Every section of `plan` in sewing order.
pub fn sections(plan: &StitchPlan) -> Vec<Section> {
    let mut out: Vec<Section> = Vec::new();
    let (mut prev, mut prev_block) = ((0.0f64, 0.0f64), usize::MAX);
    let mut open = false;
    for (i, (b, s)) in plan.entries().enumerate() {
        let len = (s.x - prev.0).hypot(s.y - prev.1);
        prev = (s.x, s.y);
        let same_block = b == prev_block;
        prev_block = b;
        if s.kind != Kind::Stitch {
            open = false;
            continue;
        }
        match out.last_mut() {
            Some(sec) if open && same_block => {
                sec.end = i + 1;
                sec.longest = sec.longest.max(len);
            }
            _ => out.push(Section {
                start: i,
                end: i + 1,
                longest: len,
                code: None,
            }),
        }
        open = true;
    }
    for sec in &mut out {
        sec.code = speed_code(sec.longest).map(|c| c.code);
    }
    out
}

/// How much shorter than a code's longest stitch a split stitch is made: the writers round
/// each end to the files' 0.1 mm grid, moving each coordinate by up to 0.05 mm, so a length
/// grows by at most 2·0.05·√2 ≈ 0.141 mm.
const ROUNDING_MARGIN: f64 = 0.15;

/// The plan with the section holding entry `entry` sewn at speed `code`: the files carry no
/// speed (the machine picks the fastest code its longest stitch allows), so a faster code is
/// had by splitting each of its stitches longer than the code allows into equal stitches
/// along the same line. A slower code than the machine's pick, a code outside 4–12 or an
/// entry that is no sewn stitch is refused, naming it.
pub fn sew_at_speed(plan: &StitchPlan, entry: usize, code: u8) -> Result<StitchPlan, String> {
    let Some(target) = SPEED_CODES.iter().find(|c| c.code == code) else {
        return Err(format!(
            "speed code {code}: the table has codes 4 to 12 (1–3 sew as 4, slower)"
        ));
    };
    let Some(sec) = sections(plan)
        .into_iter()
        .find(|s| (s.start..s.end).contains(&entry))
    else {
        return Err(format!(
            "entry {entry}: not a sewn stitch (jumps, trims and stops have no head speed)"
        ));
    };
    if sec.code.is_some_and(|c| {
        // A slower code's table row comes after the current one.
        let at = |k: u8| SPEED_CODES.iter().position(|s| s.code == k);
        at(code) > at(c)
    }) {
        return Err(format!(
            "speed code {code}: entries {}–{} sew at code {} (their longest stitch is {:.2} mm) and the files carry no speed, so only a faster code (shorter stitches) can be given",
            sec.start,
            sec.end - 1,
            sec.code.unwrap_or(0),
            sec.longest
        ));
    }
    let max = target.max_stitch - ROUNDING_MARGIN;
    // The pieces each stitch of the section becomes, counted before anything is allocated.
    let pieces = |d: f64| (d / max).ceil().max(1.0);
    let (mut prev, mut added) = ((0.0f64, 0.0f64), 0.0f64);
    for (i, (_, s)) in plan.entries().enumerate() {
        if (sec.start..sec.end).contains(&i) {
            added += pieces((s.x - prev.0).hypot(s.y - prev.1)) - 1.0;
        }
        prev = (s.x, s.y);
    }
    let total = plan.entries().count() as f64 + added;
    if total > MAX_STITCHES as f64 {
        return Err(format!(
            "speed code {code}: the design would have {total} entries, more than {MAX_STITCHES}"
        ));
    }
    let mut out = plan.clone();
    let (mut prev, mut i) = ((0.0f64, 0.0f64), 0usize);
    for block in &mut out.blocks {
        let mut kept = Vec::with_capacity(block.stitches.len());
        for s in &block.stitches {
            if (sec.start..sec.end).contains(&i) {
                let (dx, dy) = (s.x - prev.0, s.y - prev.1);
                let n = pieces(dx.hypot(dy)) as usize;
                for k in 1..n {
                    let t = k as f64 / n as f64;
                    kept.push(Stitch::new(prev.0 + t * dx, prev.1 + t * dy, Kind::Stitch));
                }
            }
            kept.push(*s);
            prev = (s.x, s.y);
            i += 1;
        }
        block.stitches = kept;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_seeds_worked_example() {
        // Widths 8.0 and 5.0 mm: level 6 at the start, level 11 for the second polyline.
        assert_eq!(speed_code(8.0).unwrap().code, 6);
        assert_eq!(speed_code(5.0).unwrap().code, 11);
        assert_eq!(speed_code(2.5).unwrap().code, 12);
        assert_eq!(speed_code(2.52).unwrap().code, 11);
        assert_eq!(speed_code(2.6).unwrap().code, 11);
        assert_eq!(speed_code(6.6).unwrap().code, 8);
        assert_eq!(speed_code(12.4).unwrap().code, 4);
        assert!(speed_code(12.5).is_none());
    }

    #[test]
    fn a_faster_code_splits_only_its_sections_long_stitches() {
        let s = |x, kind| Stitch::new(x, 0.0, kind);
        let plan = StitchPlan {
            name: "row".into(),
            blocks: vec![crate::plan::ColorBlock {
                thread: crate::plan::Thread::rgb(0, 0, 0),
                // A section 0–2 (longest 6 mm: code 9), a jump, a section 4–5 (2 mm: code 12).
                stitches: vec![
                    s(2.0, Kind::Stitch),
                    s(8.0, Kind::Stitch),
                    s(10.0, Kind::Stitch),
                    s(30.0, Kind::Jump),
                    s(32.0, Kind::Stitch),
                    s(34.0, Kind::Stitch),
                ],
            }],
        };
        let secs = sections(&plan);
        assert_eq!(
            secs.iter()
                .map(|s| (s.start, s.end, s.code))
                .collect::<Vec<_>>(),
            [(0, 3, Some(10)), (4, 6, Some(12))]
        );
        // Code 12 (2.5 mm): the 6 mm stitch becomes three of 2 mm (6 / 2.35 → 3 pieces).
        let fast = sew_at_speed(&plan, 1, 12).unwrap();
        let xs: Vec<f64> = fast.entries().map(|(_, s)| s.x).collect();
        assert_eq!(xs, [2.0, 4.0, 6.0, 8.0, 10.0, 30.0, 32.0, 34.0]);
        assert_eq!(sections(&fast)[0].code, Some(12));
        assert!(sew_at_speed(&plan, 4, 5)
            .unwrap_err()
            .contains("only a faster code"));
        assert!(sew_at_speed(&plan, 3, 12).unwrap_err().contains("entry 3"));
        assert!(sew_at_speed(&plan, 0, 3)
            .unwrap_err()
            .contains("codes 4 to 12"));
    }
}
