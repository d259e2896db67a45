//! The needle-synchronised XY table (seed §10.3): the needle is the master, the hoop moves
//! only while the needle is out of the cloth, about half of each stitch cycle. A stitch at
//! n stitches/min has a cycle of 60/n s and a window of `needle_up`·60/n s; the hoop's move
//! to the next point must end inside it, or the needle comes down on a moving hoop (the
//! firmware's "ponto longo demais" fault). Jumps stop the needle up, move, and restart at the
//! speed of before (the seed's long point).
//!
//! Each stitch is a rest-to-rest straight move limited by the table's speed v and
//! acceleration a: over d ≤ v²/a the profile is a triangle, t = 2·√(d/a); longer, a
//! trapezoid, t = d/v + v/a.
//!
//! The head speed of a section (stitches between jumps, trims, stops and colour changes) is
//! the seed's: the fastest code whose range holds the section's longest stitch (§8), or the
//! operator's fixed speed (the seed ran EMC and PATO at 350 ppm).

use crate::plan::{Kind, StitchPlan};
use crate::speed::{sections, speed_code, SPEED_CODES};

/// An XY embroidery table with its needle.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The table's name.
    pub name: String,
    /// mm/s.
    pub max_speed: f64,
    /// mm/s².
    pub acceleration: f64,
    /// Share of the stitch cycle with the needle out of the cloth.
    pub needle_up: f64,
    /// [min x, min y, max x, max y] of the hoop centre's travel about Zero-Máquina, mm.
    pub travel: [f64; 4],
}

impl Table {
    /// `embroidery-table`: the seed's table (350 × 220 mm travel, 50 % needle-up) with the
    /// limits its head-speed table implies. Each code's longest stitch L in its window
    /// w = 0.5·60/ppm needs a ≥ 4L/w² on a triangle: code 12 (2.5 mm in 27.3 ms) asks the
    /// most, 13,444 mm/s²; with a = 13,500, code 5 (11.3 mm in 82.2 ms) then needs
    /// v ≥ ~170 mm/s. So a = 13,500 mm/s² and v = 200 mm/s sew every code of the table.
    pub fn embroidery_table() -> Table {
        Table {
            name: "embroidery-table".into(),
            max_speed: 200.0,
            acceleration: 13_500.0,
            needle_up: 0.5,
            travel: [-175.0, -110.0, 175.0, 110.0],
        }
    }

    /// Rest-to-rest time of a straight move of `d` mm.
    pub fn move_time(&self, d: f64) -> f64 {
        let (v, a) = (self.max_speed, self.acceleration);
        if d <= 0.0 {
            0.0
        } else if d <= v * v / a {
            2.0 * (d / a).sqrt()
        } else {
            d / v + v / a
        }
    }

    fn check(&self) -> Result<(), String> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !(ok(self.max_speed)
            && ok(self.acceleration)
            && ok(self.needle_up)
            && self.needle_up <= 1.0)
        {
            return Err(format!(
                "table {}: speed {} mm/s, acceleration {} mm/s², needle-up share {} must be > 0 (share ≤ 1)",
                self.name, self.max_speed, self.acceleration, self.needle_up
            ));
        }
        Ok(())
    }
}

/// Head speed: the seed's table per section, or one fixed speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HeadSpeed {
    /// The seed's speed table, by stitch length.
    Table,
    /// One speed, stitches per minute.
    Fixed(f64),
}

/// Seconds for the parts of a run that are not sewing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pauses {
    /// One trim, seconds.
    pub trim: f64,
    /// One colour change, seconds.
    pub color_change: f64,
    /// One stop, seconds.
    pub stop: f64,
}

impl Default for Pauses {
    /// A trim cycle of ~2 s; a manual thread change on the seed's one-needle head ~30 s.
    fn default() -> Pauses {
        Pauses {
            trim: 2.0,
            color_change: 30.0,
            stop: 10.0,
        }
    }
}

/// A stitch the table could not finish in its needle-up window.
#[derive(Clone, Debug, PartialEq)]
pub struct Fault {
    /// Index of the entry in sewing order (from 0).
    pub index: usize,
    /// Index of its colour block.
    pub block: usize,
    /// Stitch length, mm.
    pub length: f64,
    /// Head speed, stitches per minute.
    pub ppm: f64,
    /// Time the move needs, seconds.
    pub move_seconds: f64,
    /// Time the needle is up, seconds.
    pub window_seconds: f64,
}

/// What a run on the table took and where it failed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunReport {
    /// Needle running: Σ 60/ppm over sewn stitches.
    pub sewing_seconds: f64,
    /// Hoop moves with the needle stopped.
    pub jump_seconds: f64,
    /// Trims, stops and colour changes, seconds.
    pub pause_seconds: f64,
    /// The whole run, seconds.
    pub total_seconds: f64,
    /// Sewn stitches per speed code (code, stitches, ppm), fastest first.
    pub by_code: Vec<(u8, usize, f64)>,
    /// Stitches the table could not finish in time.
    pub faults: Vec<Fault>,
    /// Points beyond the table's travel: (entry index, x, y).
    pub out_of_travel: Vec<(usize, f64, f64)>,
    /// Stitches longer than the machine sews (12.4 mm), sewn at code 4's speed.
    pub too_long: usize,
}

/// Runs the plan on the table, stitch by stitch.
pub fn run(
    plan: &StitchPlan,
    table: &Table,
    speed: HeadSpeed,
    pauses: Pauses,
) -> Result<RunReport, String> {
    table.check()?;
    if let HeadSpeed::Fixed(ppm) = speed {
        if !(ppm.is_finite() && (1.0..=5000.0).contains(&ppm)) {
            return Err(format!("head speed {ppm} stitches/min is outside 1..5000"));
        }
    }
    let entries: Vec<(usize, crate::plan::Stitch)> = plan.entries().map(|(b, s)| (b, *s)).collect();
    let mut r = RunReport::default();
    let mut prev = (0.0f64, 0.0f64);
    let mut lengths = Vec::with_capacity(entries.len());
    for (_, s) in &entries {
        lengths.push((s.x - prev.0).hypot(s.y - prev.1));
        prev = (s.x, s.y);
    }
    let mut secs = sections(plan).into_iter();
    let mut counts: Vec<usize> = vec![0; SPEED_CODES.len()];
    let mut i = 0;
    while i < entries.len() {
        let (block, s) = entries[i];
        if i > 0 && entries[i - 1].0 != block {
            r.pause_seconds += pauses.color_change;
        }
        let [x0, y0, x1, y1] = table.travel;
        if !(s.x >= x0 && s.x <= x1 && s.y >= y0 && s.y <= y1) {
            r.out_of_travel.push((i, s.x, s.y));
        }
        match s.kind {
            Kind::Jump => r.jump_seconds += table.move_time(lengths[i]),
            Kind::Trim => r.pause_seconds += pauses.trim,
            Kind::Stop => r.pause_seconds += pauses.stop,
            Kind::Stitch => {
                // The section this stitch opens (consecutive stitches of one block).
                let Some(sec) = secs.next().filter(|s| s.start == i) else {
                    return Err(format!("entry {i}: a stitch outside the plan's sections"));
                };
                let (j, longest) = (sec.end, sec.longest);
                let (ppm, code) = match speed {
                    HeadSpeed::Fixed(ppm) => (ppm, None),
                    HeadSpeed::Table => match speed_code(longest) {
                        Some(c) => (c.ppm, Some(c)),
                        None => {
                            r.too_long += lengths[i..j]
                                .iter()
                                .filter(|&&l| speed_code(l).is_none())
                                .count();
                            let c = SPEED_CODES[SPEED_CODES.len() - 1];
                            (c.ppm, Some(c))
                        }
                    },
                };
                if let Some(c) = code {
                    let k = SPEED_CODES
                        .iter()
                        .position(|x| x.code == c.code)
                        .unwrap_or(0);
                    counts[k] += j - i;
                }
                let cycle = 60.0 / ppm;
                let window = table.needle_up * cycle;
                for k in i..j {
                    r.sewing_seconds += cycle;
                    let t = table.move_time(lengths[k]);
                    if t > window * (1.0 + 1e-9) {
                        r.faults.push(Fault {
                            index: k,
                            block,
                            length: lengths[k],
                            ppm,
                            move_seconds: t,
                            window_seconds: window,
                        });
                    }
                    let e = entries[k].1;
                    if !(e.x >= x0 && e.x <= x1 && e.y >= y0 && e.y <= y1) && k > i {
                        r.out_of_travel.push((k, e.x, e.y));
                    }
                }
                i = j;
                continue;
            }
        }
        i += 1;
    }
    r.by_code = SPEED_CODES
        .iter()
        .zip(&counts)
        .filter(|(_, &n)| n > 0)
        .map(|(c, &n)| (c.code, n, c.ppm))
        .collect();
    r.total_seconds = r.sewing_seconds + r.jump_seconds + r.pause_seconds;
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embroidery_table_sews_every_code_of_the_seed() {
        let t = Table::embroidery_table();
        for c in SPEED_CODES {
            let window = 0.5 * 60.0 / c.ppm;
            assert!(
                t.move_time(c.max_stitch) <= window,
                "code {}: {} > {window}",
                c.code,
                t.move_time(c.max_stitch)
            );
        }
    }

    #[test]
    fn move_time_is_continuous_at_the_triangle_limit() {
        let t = Table::embroidery_table();
        let d = t.max_speed * t.max_speed / t.acceleration;
        assert!((t.move_time(d - 1e-9) - t.move_time(d + 1e-9)).abs() < 1e-6);
    }
}
