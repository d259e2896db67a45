//! Which line the machine is on, from where it is: every status report's position is
//! matched against the programmed path of the lines sent, moving forward only.
//!
//! Counting planner blocks (`Bf:`) cannot tell this on every firmware: grblHAL frees a
//! block once its steps are prepared, up to ~100 ms before it has run, so a count says a
//! line finished while the machine is still on it. A position on the path can not lie.

use crate::interp::{self, Interp};
use crate::job::StreamProgram;
use crate::resume::{self, point_segment_distance, POSITION_TOLERANCE};
use std::collections::VecDeque;

/// One sent line's path in work coordinates: its start, then each block's end.
struct Traced {
    index: usize,
    points: Vec<[f64; 3]>,
}

/// Where a reported position was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Seen {
    /// The job line holding the position.
    pub index: usize,
    /// The position is the line's end point (the line is done).
    pub at_end: bool,
}

pub(crate) struct PathTracker {
    interp: Interp,
    lines: VecDeque<Traced>,
    /// Lines before this index are done (the machine was seen past them).
    pub done_before: usize,
}

impl PathTracker {
    /// A tracker for streaming `job` from line `from`, with the firmware's `$12`.
    pub(crate) fn new(job: &StreamProgram, from: usize, arc_tolerance: f64) -> PathTracker {
        let mut interp = resume::replay(job, from);
        interp.arc_tolerance = arc_tolerance;
        PathTracker {
            interp,
            lines: VecDeque::new(),
            done_before: from,
        }
    }

    /// Line `index` (text `text`) went to the firmware.
    pub(crate) fn sent(&mut self, index: usize, text: &str) {
        if text.starts_with('$') {
            return;
        }
        let start = self.interp.pos;
        let Ok(effect) = self.interp.execute(text) else {
            return;
        };
        if effect.segments.is_empty() {
            return;
        }
        let wco = self.interp.wco();
        let work = |p: [f64; 3]| [p[0] - wco[0], p[1] - wco[1], p[2] - wco[2]];
        let mut points = vec![work(start)];
        points.extend(effect.segments.iter().map(|s| work(s.to)));
        self.lines.push_back(Traced { index, points });
    }

    /// The machine reports it is at `work_pos` (mm): the first sent line, from the one it
    /// was last seen on, whose path holds the position. `None`: not on the path sent
    /// (a jog, a position read mid-reset); nothing changes.
    pub(crate) fn observe(&mut self, work_pos: [f64; 3]) -> Option<Seen> {
        let (k, seen) = self.lines.iter().enumerate().find_map(|(k, t)| {
            let last = t.points.len() - 1;
            t.points.windows(2).enumerate().find_map(|(s, w)| {
                (point_segment_distance(work_pos, w[0], w[1]) <= POSITION_TOLERANCE).then(|| {
                    let at_end = s + 1 == last
                        && interp::dist(&work_pos, &t.points[last]) <= POSITION_TOLERANCE;
                    (
                        k,
                        Seen {
                            index: t.index,
                            at_end,
                        },
                    )
                })
            })
        })?;
        self.lines.drain(..k);
        self.done_before = self.done_before.max(seen.index + usize::from(seen.at_end));
        Some(seen)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_the_path_forward_only() {
        // Two passes over the same square at different depths, then back to the start.
        let text = "G0X0Y0Z0\nG1Z-1F100\nX10\nY10\nX0\nY0\nZ-2\nX10\nY10\nX0\nY0\nG0Z5\n";
        let job = StreamProgram::from_text("t", text).unwrap();
        let mut t = PathTracker::new(&job, 0, 0.002);
        for (i, l) in job.lines.iter().enumerate() {
            t.sent(i, &l.text);
        }
        let seen = |t: &mut PathTracker, p: [f64; 3]| t.observe(p).map(|s| (s.index, s.at_end));
        assert_eq!(seen(&mut t, [5.0, 0.0, -1.0]), Some((2, false)));
        assert_eq!(seen(&mut t, [10.0, 10.0, -1.0]), Some((3, true)));
        assert_eq!(t.done_before, 4);
        // Second pass: (5,0) at Z-2 is line 7, never line 2 again.
        assert_eq!(seen(&mut t, [5.0, 0.0, -2.0]), Some((7, false)));
        // Not on the path: no change.
        assert_eq!(seen(&mut t, [50.0, 0.0, 0.0]), None);
        assert_eq!(t.done_before, 7);
        // The first pass's points are behind: (10,5,-1) is nowhere ahead.
        assert_eq!(seen(&mut t, [10.0, 5.0, -1.0]), None);
        assert_eq!(seen(&mut t, [0.0, 0.0, 3.0]), Some((11, false)));
    }

    #[test]
    fn arcs_are_followed_by_their_chords() {
        let job =
            StreamProgram::from_text("t", "G0X10Y0\nG3X-10Y0I-10J0F100\nG1X-10Y-5\n").unwrap();
        let mut t = PathTracker::new(&job, 0, 0.002);
        for (i, l) in job.lines.iter().enumerate() {
            t.sent(i, &l.text);
        }
        let p = [0.0, 10.0 - 0.001, 0.0];
        assert_eq!(
            t.observe(p),
            Some(Seen {
                index: 1,
                at_end: false
            })
        );
    }
}
