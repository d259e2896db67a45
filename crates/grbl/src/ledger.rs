//! Which acknowledged lines still have blocks in the firmware's planner. Each line is run
//! through the same grbl interpreter as it is sent, so the sender knows how many planner
//! blocks it makes (an arc makes many); a status report's `Bf:` then says how many blocks
//! are left, and so exactly which line the machine is executing.

use crate::interp::Interp;
use crate::job::Job;
use crate::resume;
use std::collections::VecDeque;

pub struct BlockLedger {
    tracker: Interp,
    /// (line index, blocks) sent but not yet acknowledged.
    in_flight: VecDeque<(usize, usize)>,
    /// (line index, blocks) acknowledged and possibly not finished.
    queued: VecDeque<(usize, usize)>,
    queued_blocks: usize,
}

impl BlockLedger {
    /// A ledger for streaming `job` from line `from`, with the firmware's arc tolerance ($12).
    pub fn new(job: &Job, from: usize, arc_tolerance: f64) -> BlockLedger {
        let mut tracker = resume::replay(job, from);
        tracker.arc_tolerance = arc_tolerance;
        BlockLedger {
            tracker,
            in_flight: VecDeque::new(),
            queued: VecDeque::new(),
            queued_blocks: 0,
        }
    }

    pub fn sent(&mut self, index: usize, text: &str) {
        let blocks = if text.starts_with('$') {
            0
        } else {
            self.tracker
                .execute(text)
                .map(|e| e.segments.len())
                .unwrap_or(0)
        };
        self.in_flight.push_back((index, blocks));
    }

    pub fn acked(&mut self) {
        if let Some((i, b)) = self.in_flight.pop_front() {
            self.queued.push_back((i, b));
            self.queued_blocks += b;
        }
    }

    /// `planner_used` blocks remain in the firmware: the first acknowledged line that still
    /// has blocks there (every line before it finished). `None`: every acknowledged line
    /// finished.
    pub fn executing(&mut self, planner_used: usize) -> Option<usize> {
        while let Some(&(i, b)) = self.queued.front() {
            // The lines after this one hold every block still queued: it is done.
            if self.queued_blocks - b >= planner_used {
                self.queued.pop_front();
                self.queued_blocks -= b;
            } else {
                return Some(i);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_blocks_including_arcs() {
        let job = Job::from_text("t", "G0X9\nG1X10F100\nF200\nG3X-10Y0I-10J0\nG1X0\n").unwrap();
        let mut l = BlockLedger::new(&job, 0, 0.002);
        for (i, line) in job.lines.iter().enumerate() {
            l.sent(i, &line.text);
            l.acked();
        }
        // The arc from (10,0) around to (-10,0) is many chords; one line after it.
        let arc_blocks = l.queued.iter().find(|(i, _)| *i == 3).unwrap().1;
        assert!(arc_blocks > 50, "{arc_blocks}");
        let total = 2 + arc_blocks + 1;
        assert_eq!(l.executing(total), Some(0));
        assert_eq!(l.executing(total - 1), Some(1));
        // Inside the arc: lines 0..3 finished (the modal F200 line too).
        assert_eq!(l.executing(arc_blocks), Some(3));
        assert_eq!(l.executing(1), Some(4));
        assert_eq!(l.executing(0), None);
    }
}
