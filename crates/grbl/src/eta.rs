//! Time left in a job. Each line's machine time is the grbl timing model (length over the
//! programmed feed, capped per axis by `$110…`; rapids at those caps), summed once before
//! the stream; while it runs, the estimate is scaled by how fast the machine has really
//! gone so far (acceleration, overrides and holds make it slower than the model).

use crate::interp::{Interp, Rate};
use crate::job::StreamProgram;
use std::collections::BTreeMap;

/// Seconds of machine time before each line: `cumulative[i]` is the time of lines `0..i`;
/// the last entry is the whole job.
pub(crate) fn cumulative_seconds(job: &StreamProgram, settings: &BTreeMap<u16, f64>) -> Vec<f64> {
    let max_rate = |axis: u16| {
        settings
            .get(&(110 + axis))
            .copied()
            .filter(|v| *v > 0.0)
            .unwrap_or(500.0)
            / 60.0
    };
    let caps = [max_rate(0), max_rate(1), max_rate(2)];
    let mut interp = Interp {
        arc_tolerance: settings.get(&12).copied().unwrap_or(0.002),
        a_axis: true,
        ..Interp::default()
    };
    let mut out = Vec::with_capacity(job.len() + 1);
    let mut t = 0.0;
    out.push(0.0);
    for line in &job.lines {
        let mut from = interp.pos;
        if let Ok(effect) = interp.execute(&line.text) {
            t += effect.dwell;
            for seg in &effect.segments {
                let d: Vec<f64> = (0..3).map(|a| (seg.to[a] - from[a]).abs()).collect();
                let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                // The slowest axis at its own maximum rate bounds the move's time.
                let axis_bound = (0..3).map(|a| d[a] / caps[a]).fold(0.0, f64::max);
                let feed_time = match seg.rate {
                    Rate::Rapid => 0.0,
                    Rate::Feed(f) if f > 0.0 => len / (f / 60.0),
                    Rate::Feed(_) => 0.0,
                };
                t += feed_time.max(axis_bound);
                from = seg.to;
            }
        }
        out.push(t);
    }
    out
}

/// Seconds left after line `done` (exclusive) given `elapsed` real seconds since line
/// `started`, scaled by the observed pace once enough machine time has passed to judge it.
pub(crate) fn remaining(cumulative: &[f64], started: usize, done: usize, elapsed: f64) -> f64 {
    let total = *cumulative.last().unwrap_or(&0.0);
    let at = |i: usize| cumulative.get(i).copied().unwrap_or(total);
    let model_left = (total - at(done)).max(0.0);
    let model_done = at(done) - at(started);
    let pace = if model_done > 2.0 && elapsed > 0.0 {
        (elapsed / model_done).max(1.0)
    } else {
        1.0
    };
    model_left * pace
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_by_hand() {
        let job = StreamProgram::from_text("t", "G21G90\nG1X30F600\nG1Y40F1200\nG4P1.5\nG0X0Y0\n")
            .unwrap();
        let settings: BTreeMap<u16, f64> = [(110, 6000.0), (111, 3000.0), (112, 500.0)].into();
        let c = cumulative_seconds(&job, &settings);
        // 30 mm at 10 mm/s = 3 s; 40 mm at 20 mm/s = 2 s; dwell 1.5 s; rapid back: X 30 mm at
        // 100 mm/s = 0.3 s, Y 40 mm at 50 mm/s = 0.8 s, so 0.8 s.
        let expect = [0.0, 0.0, 3.0, 5.0, 6.5, 7.3];
        for (a, b) in c.iter().zip(expect) {
            assert!((a - b).abs() < 1e-9, "{c:?}");
        }
        assert!((remaining(&c, 0, 3, 0.0) - 2.3).abs() < 1e-9);
        // Half the model's pace so far: the rest takes twice as long too.
        assert!((remaining(&c, 0, 3, 10.0) - 4.6).abs() < 1e-9);
    }
}
