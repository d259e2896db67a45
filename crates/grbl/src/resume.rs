//! Resume after a stop: find the first line the machine did not finish, rebuild the modal
//! state there and approach its start point safely.
//!
//! The program is replayed through the same grbl interpreter the emulator uses, so a line
//! the firmware rejected is a no-op here too. Where the machine stopped is decided by its
//! reported work position against the path of the lines that may have been in the planner:
//! the first line whose path holds the position is the interrupted one.

use crate::interp::{self, Interp, MotionMode, Spindle};
use crate::job::StreamProgram;

/// Reported positions carry 3 decimals; a little more for rounding of MPos − WCO.
pub(crate) const POSITION_TOLERANCE: f64 = 0.005;

/// The interpreter state after running lines `0..index` of `job`.
pub fn replay(job: &StreamProgram, index: usize) -> Interp {
    // The host follows any firmware: A words are read (a 3-axis board refuses them itself).
    let mut i = Interp {
        a_axis: true,
        ..Interp::default()
    };
    for l in job.lines.iter().take(index) {
        if l.text.starts_with('$') {
            continue;
        }
        let _ = i.execute(&l.text);
    }
    i
}

/// The axes (X, Y, Z) the first `index` lines of `job` name: on the others the replayed
/// position is the interpreter's 0, not where the machine is (a program that changes tools
/// before it moves, a run that ends before an axis was ever programmed).
pub(crate) fn axes_named(job: &StreamProgram, index: usize) -> [bool; 3] {
    let mut named = [false; 3];
    for l in job.lines.iter().take(index) {
        if l.text.starts_with('$') {
            continue;
        }
        for (letter, _, _) in crate::gline::word_spans(l.text.as_bytes()).unwrap_or_default() {
            if let Some(a) = ['X', 'Y', 'Z'].iter().position(|c| *c == letter) {
                named[a] = true;
            }
        }
    }
    named
}

/// Where to resume and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Located {
    pub index: usize,
    pub reason: String,
    /// The machine stopped inside line `index` at this work position (mm), and that line
    /// can be finished from there: approach this point instead of the line's start, so
    /// the part of the line already cut is not cut again.
    pub entry: Option<[f64; 3]>,
}

/// Whether a line interrupted part-way can be finished by approaching the stop point and
/// sending the line itself: a single straight move to an absolute end point, at a feed
/// that does not depend on the move's length. Arcs, incremental moves, inverse-time feeds
/// and moves in other coordinates are run again from their start instead.
pub(crate) fn enterable_midway(after: &Interp, text: &str, effect: &interp::Effect) -> bool {
    effect.segments.len() == 1
        && after.modal.absolute
        && !after.modal.inverse_time
        && matches!(after.modal.motion, MotionMode::Rapid | MotionMode::Linear)
        && !["G53", "G28", "G30", "G92", "G10", "G38", "G4"]
            .iter()
            .any(|g| text.contains(g))
}

/// The first line not completed, given that lines before `certain` completed, nothing at or
/// after `sent_end` reached the firmware, and the machine now rests at `work_pos` (mm).
///
/// When the machine rests exactly at the end of a line, the modal-only lines after it that
/// were acknowledged (`acked_end`) already took effect and are not sent again.
pub(crate) fn locate(
    job: &StreamProgram,
    certain: usize,
    sent_end: usize,
    acked_end: usize,
    work_pos: [f64; 3],
) -> Located {
    locate_within(
        job,
        certain,
        sent_end,
        acked_end,
        work_pos,
        POSITION_TOLERANCE,
    )
}

/// [`locate`] for a position known to within `tolerance` mm (Marlin's `M114` prints two
/// decimals).
pub(crate) fn locate_within(
    job: &StreamProgram,
    certain: usize,
    sent_end: usize,
    acked_end: usize,
    work_pos: [f64; 3],
    tolerance: f64,
) -> Located {
    let mut st = replay(job, certain);
    let end = sent_end.min(job.len());
    for j in certain..end {
        let start = st.pos;
        let Ok(effect) = st.execute(&job.lines[j].text) else {
            continue;
        };
        if effect.segments.is_empty() {
            continue;
        }
        let wco = st.wco();
        let to_work = |p: [f64; 3]| [p[0] - wco[0], p[1] - wco[1], p[2] - wco[2]];
        let mut from = to_work(start);
        for (k, s) in effect.segments.iter().enumerate() {
            let to = to_work(s.to);
            if point_segment_distance(work_pos, from, to) <= tolerance {
                let at_end =
                    k + 1 == effect.segments.len() && interp::dist(&work_pos, &to) <= tolerance;
                let l = &job.lines[j];
                return if at_end {
                    let mut next = j + 1;
                    let mut probe = st.clone();
                    while next < acked_end.min(end) {
                        match probe.execute(&job.lines[next].text) {
                            Ok(e) if !e.segments.is_empty() => break,
                            _ => next += 1,
                        }
                    }
                    Located {
                        index: next,
                        reason: format!(
                            "machine rests at the end of file line {} ({})",
                            l.file_line, l.text
                        ),
                        entry: None,
                    }
                } else if enterable_midway(&st, &l.text, &effect) {
                    Located {
                        index: j,
                        reason: format!(
                            "machine stopped inside file line {} ({}) at {:.3},{:.3},{:.3}; the rest of it is cut from there",
                            l.file_line, l.text, work_pos[0], work_pos[1], work_pos[2]
                        ),
                        entry: Some(work_pos),
                    }
                } else {
                    Located { index: j, reason: format!("machine stopped inside file line {} ({}); it is run again from its start", l.file_line, l.text), entry: None }
                };
            }
            from = to;
        }
    }
    Located {
        index: certain,
        reason: format!(
            "position {:.3},{:.3},{:.3} is not on the path of the lines that were in flight; resuming from the last line known complete",
            work_pos[0], work_pos[1], work_pos[2]
        ),
        entry: None,
    }
}

pub(crate) fn point_segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + ab[0] * t, a[1] + ab[1] * t, a[2] + ab[2] * t];
    interp::dist(&p, &q)
}

/// How to get back into the cut.
#[derive(Clone, Debug, PartialEq)]
pub struct ResumeOptions {
    /// Work Z (mm) to travel at before approaching.
    pub safe_z: f64,
    /// Feed for the last approach move down to the start point (mm/min).
    pub plunge_feed: f64,
    /// Seconds to wait after starting the spindle.
    pub spindle_delay: f64,
}

impl Default for ResumeOptions {
    fn default() -> Self {
        ResumeOptions {
            safe_z: 5.0,
            plunge_feed: 300.0,
            spindle_delay: 2.0,
        }
    }
}

/// The lines to send before streaming `job` from `index`: modal state, spindle and coolant,
/// retract, approach, then the program's own units, distance mode, feed and motion mode.
pub fn preamble(
    job: &StreamProgram,
    index: usize,
    opts: &ResumeOptions,
) -> Result<Vec<String>, String> {
    preamble_at(job, index, None, opts)
}

/// [`preamble`], approaching `entry` (work mm, a point on line `index` where the machine
/// stopped, see [`Located::entry`]) instead of the line's start point.
pub(crate) fn preamble_at(
    job: &StreamProgram,
    index: usize,
    entry: Option<[f64; 3]>,
    opts: &ResumeOptions,
) -> Result<Vec<String>, String> {
    let st = replay(job, index);
    if st.g92 != [0.0; 3] || st.tool_length != 0.0 {
        return Err(format!(
            "the program sets a G92 offset or a G43.1 tool length offset before line {}; a firmware reset clears them, so resuming there is not safe. Resume from an earlier line where they are not active",
            job.lines.get(index).map(|l| l.file_line).unwrap_or(0)
        ));
    }
    let m = st.modal;
    if let Some(line) = job.lines.get(index) {
        let explicit_motion = line.text.contains("G2")
            || line.text.contains("G3")
            || line.text.contains("G0")
            || line.text.contains("G1");
        if matches!(m.motion, MotionMode::ArcCw | MotionMode::ArcCcw)
            && !explicit_motion
            && line.text.contains(['X', 'Y', 'Z'])
        {
            return Err(format!(
                "file line {} continues a modal arc without G2/G3; resume from the line that starts the arc",
                line.file_line
            ));
        }
    }
    let w = entry.unwrap_or_else(|| st.work_pos());
    let mut out = Vec::new();
    out.push(format!("G21G90G94G{}G{}", 54 + m.wcs, 17 + m.plane));
    if st.tool != 0 {
        out.push(format!("T{}", st.tool));
    }
    match m.spindle {
        Spindle::Off => out.push("M5".into()),
        s => {
            out.push(format!(
                "S{}{}",
                num(st.spindle_speed),
                if s == Spindle::Cw { "M3" } else { "M4" }
            ));
            if opts.spindle_delay > 0.0 {
                out.push(format!("G4P{}", num(opts.spindle_delay)));
            }
        }
    }
    match (m.mist, m.flood) {
        (false, false) => out.push("M9".into()),
        (mist, flood) => {
            if mist {
                out.push("M7".into());
            }
            if flood {
                out.push("M8".into());
            }
        }
    }
    let travel_z = opts.safe_z.max(w[2]);
    out.push(format!("G0Z{}", num(travel_z)));
    out.push(format!("G0X{}Y{}", num(w[0]), num(w[1])));
    if w[2] < travel_z {
        out.push(format!("G1Z{}F{}", num(w[2]), num(opts.plunge_feed)));
    }
    // Back to the program's own modes, last, so they govern the lines that follow.
    let mut modes = String::new();
    modes += if m.inches { "G20" } else { "G21" };
    modes += if m.absolute { "G90" } else { "G91" };
    modes += if m.inverse_time { "G93" } else { "G94" };
    match m.motion {
        MotionMode::Rapid => modes += "G0",
        MotionMode::Linear => modes += "G1",
        MotionMode::None => modes += "G80",
        _ => {}
    }
    if !m.inverse_time && st.feed > 0.0 {
        let f = if m.inches { st.feed / 25.4 } else { st.feed };
        modes += &format!("F{}", num(f));
    }
    out.push(modes);
    Ok(out)
}

pub(crate) fn num(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gline;

    fn job(text: &str) -> StreamProgram {
        StreamProgram::from_text("t.nc", text).unwrap()
    }

    #[test]
    fn only_named_axes_have_a_known_place() {
        let j = job("G21 G90\nT1\nG0 z5\nG0 X1 Y2\n");
        assert_eq!(axes_named(&j, 2), [false; 3]);
        assert_eq!(axes_named(&j, 3), [false, false, true]);
        assert_eq!(axes_named(&j, 4), [true; 3]);
    }

    #[test]
    fn locates_inside_and_at_end_of_lines() {
        let j = job("G21G90\nG0Z5\nG0X0Y0\nG1Z-1F100\nG1X10F500\nG1Y10\nG1X0\n");
        // Half way along G1Y10 (index 5).
        assert_eq!(locate(&j, 0, 7, 7, [10.0, 5.0, -1.0]).index, 5);
        // Exactly at the end of G1X10: resume after it.
        assert_eq!(locate(&j, 0, 7, 7, [10.0, 0.0, -1.0]).index, 5);
        // Acknowledged modal lines after the finished move are not sent again.
        let k = job("G0X0Y0\nG1X10F500\nF300\nM8\nG1Y10\n");
        assert_eq!(locate(&k, 0, 5, 4, [10.0, 0.0, 0.0]).index, 4);
        assert_eq!(locate(&k, 0, 5, 3, [10.0, 0.0, 0.0]).index, 3);
        // Nowhere on the path: fall back to the last line known complete.
        let l = locate(&j, 2, 7, 7, [50.0, 50.0, 0.0]);
        assert_eq!(l.index, 2);
        assert!(l.reason.contains("not on the path"));
    }

    #[test]
    fn preamble_restores_modal_state_and_approaches() {
        let j = job("G20G91\nG0Z0.2\nS12000M3\nM8\nG10L2P2X1\nG55\nG1X1F20\nX1\nX1\n");
        let p = preamble(
            &j,
            7,
            &ResumeOptions {
                safe_z: 5.0,
                plunge_feed: 200.0,
                spindle_delay: 1.0,
            },
        )
        .unwrap();
        assert_eq!(
            p,
            vec![
                "G21G90G94G55G17",
                "S12000M3",
                "G4P1",
                "M8",
                "G0Z5.08",
                "G0X0Y0",
                "G20G91G94G1F20",
            ]
        );
        // Verify independently: running the preamble then the rest ends where the program does.
        let mut direct = Interp::default();
        for l in &j.lines {
            direct.execute(&l.text).unwrap();
        }
        let mut resumed = replay(&j, 7);
        resumed.pos = [0.0, 0.0, 0.0]; // machine somewhere else after a stop
        resumed.modal = Default::default();
        for l in p
            .iter()
            .map(|s| gline::clean(s).unwrap())
            .chain(j.lines[7..].iter().map(|l| l.text.clone()))
        {
            resumed.execute(&l).unwrap();
        }
        for a in 0..3 {
            assert!(
                (resumed.pos[a] - direct.pos[a]).abs() < 1e-9,
                "{:?} vs {:?}",
                resumed.pos,
                direct.pos
            );
        }
        assert_eq!(resumed.modal, direct.modal);
    }

    #[test]
    fn refuses_what_it_cannot_restore() {
        let j = job("G0X5\nG92X0\nG1X1F100\n");
        assert!(preamble(&j, 2, &ResumeOptions::default())
            .unwrap_err()
            .contains("G92"));
        let k = job("G0X10Y0\nG2X0Y10I-10J0F100\nX-10Y0I0J-10\n");
        assert!(preamble(&k, 2, &ResumeOptions::default())
            .unwrap_err()
            .contains("modal arc"));
        assert!(preamble(&k, 1, &ResumeOptions::default()).is_ok());
    }
}
