//! Where a stopped Marlin job continues, from its journal and where Marlin says it is.
//!
//! Marlin answers `ok` once a move is planned, not drawn, and its planner holds
//! `BLOCK_BUFFER_SIZE` (16) moves; with one line in flight, the lines acknowledged last may
//! still have been waiting when the job stopped (`M410` drops them). So the lines before
//! `acked − 17` certainly ran, and the machine's `M114` position on the path of the lines
//! after that says which one it stopped in (the grbl resume's `locate`, on the program's
//! motion model).

use super::program::model;
use crate::job::StreamProgram;
use crate::journal::JournalState;
use crate::resume::{locate_within, replay};

/// How far the `M114` position may be from the path: it prints two decimals, so each axis
/// is off by up to 0.005 mm and a point in the plane by up to 0.005·√2 ≈ 0.0071 mm.
const M114_TOLERANCE: f64 = 0.0075;

/// Marlin's planner depth plus the line in flight.
const PLANNED_LINES: usize = 16 + 1;

/// Settling time of a hobby servo pen lift, ms (the plot writer's default dwell).
const SERVO_MS: u32 = 150;

/// Where to continue and how to get there.
#[derive(Clone, Debug, PartialEq)]
pub struct MarlinResume {
    /// The program line to send first.
    pub index: usize,
    /// Sent before it: pen up, travel to where the line starts (or where the machine
    /// stopped inside it), the pen as it was there.
    pub preamble: Vec<String>,
    /// Why there, for the operator.
    pub reason: String,
}

/// The restart of `job` after a run recorded in `journal` stopped with Marlin at
/// `position` (mm, `M114`).
pub fn plan_resume(
    job: &StreamProgram,
    journal: &JournalState,
    position: [f64; 3],
) -> MarlinResume {
    let motion = model(job);
    let certain = journal
        .completed
        .max(journal.acked_end.saturating_sub(PLANNED_LINES));
    let at = locate_within(
        &motion,
        certain,
        journal.sent_end,
        journal.acked_end,
        position,
        M114_TOLERANCE,
    );
    let state = replay(&motion, at.index);
    let target = at.entry.unwrap_or(state.pos);
    // Pen commands: the program's first is "up" (the plot writer lifts before homing),
    // the last before the restart line is the pen as it was there.
    let pens: Vec<&str> = job.lines[..at.index]
        .iter()
        .map(|l| l.text.as_str())
        .filter(|t| t.to_ascii_uppercase().starts_with("M280"))
        .collect();
    let mut preamble = vec!["G21".to_string(), "G90".to_string()];
    if let Some(up) = job
        .lines
        .iter()
        .find(|l| l.text.to_ascii_uppercase().starts_with("M280"))
    {
        preamble.push(up.text.clone());
        preamble.push(format!("G4 P{SERVO_MS}"));
    }
    let feed = if state.feed > 0.0 {
        format!(" F{}", state.feed)
    } else {
        String::new()
    };
    preamble.push(format!("G0 X{:.3} Y{:.3}{feed}", target[0], target[1]));
    if let Some(pen) = pens.last() {
        preamble.push(pen.to_string());
        preamble.push(format!("G4 P{SERVO_MS}"));
    }
    MarlinResume {
        index: at.index,
        preamble,
        reason: at.reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restarts_inside_the_stroke_with_the_pen_down() {
        let text = "G21\nG90\nM280 P0 S90\nG4 P150\nG28\nG0 X10 Y10 F3000\nM280 P0 S30\nG4 P150\nG1 X20 Y10 F1000\nG1 X20 Y20\nM280 P0 S90\n";
        let job = super::super::program::marlin_program("t", text).unwrap();
        let journal = JournalState {
            sent_end: 10,
            acked_end: 10,
            ..Default::default()
        };
        // Stopped half-way along G1 X20 Y20 (line index 9).
        let r = plan_resume(&job, &journal, [20.0, 15.0, 0.0]);
        assert_eq!(r.index, 9, "{r:?}");
        assert_eq!(
            r.preamble,
            [
                "G21",
                "G90",
                "M280 P0 S90",
                "G4 P150",
                "G0 X20.000 Y15.000 F1000",
                "M280 P0 S30",
                "G4 P150"
            ]
        );
    }
}
