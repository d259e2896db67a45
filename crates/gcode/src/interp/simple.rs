//! The short way through the interpreter for the blocks that make up most programs: a
//! move (`G0`…`G3`, or the modal one) with axis words, perhaps an `F` and, for arcs, the
//! centre or radius words, in the LinuxCNC dialect, without cutter compensation or
//! inverse-time feed; and the blocks with no word at all (lines of parameter assignments).
//!
//! It does exactly what the full path does for such a block (set the feed, set the motion
//! mode, move, refresh the position parameters) and declines (`None`, nothing changed)
//! whenever the block holds anything else or would be an error, so every other case and
//! every message keep their single implementation in the full path.

use super::arcs;
use super::state::Motion;
use super::words::Decoded;
use super::{Flow, Interpreter, Sink};
use crate::block::Block;
use crate::params::Params;
use crate::Dialect;
use oficina_canon::{CanonOp, FeedMode, Plane};

impl Interpreter {
    pub(super) fn simple_move(
        &mut self,
        block: &Block,
        params: &mut Params,
        sink: Sink,
    ) -> Option<Flow> {
        if self.dialect != Dialect::LinuxCnc
            || !block.notes.is_empty()
            || self.modal.comp.is_some()
            || self.modal.feed_mode != FeedMode::UnitsPerMinute
            || self.modal.diameter_mode
        {
            return None;
        }
        if block.words.is_empty() && block.n.is_none() {
            // A line of assignments only: all the full path does with it is forget a
            // canned cycle's memory (unless a cycle is the motion mode) and refresh the
            // position parameters.
            self.line = block.line;
            if !matches!(self.modal.motion, Motion::Cycle(_)) {
                self.cycle.reset();
            }
            self.update_params(params);
            return Some(Flow::Continue);
        }
        let mut motion = self.modal.motion;
        let mut g_seen = false;
        let mut feed = None;
        // Axis values in `Pos` order, and which were given.
        let mut axes = [0.0; 6];
        let mut given = 0u8;
        let mut arc_words = false;
        // I J K values, and which were given (bit i), for the centre form read here.
        let mut offsets = [0.0; 3];
        let mut offsets_given = 0u8;
        // R or P, or an arc word twice: the centre is left to the full path's code.
        let mut other_arc_words = false;
        for w in &block.words {
            let axis = match w.letter {
                'G' if !g_seen => {
                    g_seen = true;
                    motion = match w.value {
                        0.0 => Motion::Rapid,
                        1.0 => Motion::Linear,
                        2.0 => Motion::Clockwise,
                        3.0 => Motion::CounterClockwise,
                        _ => return None,
                    };
                    continue;
                }
                // Arc words: checked against the motion below, read by the arc code.
                'I' | 'J' | 'K' => {
                    arc_words = true;
                    let i = (w.letter as u8 - b'I') as usize;
                    other_arc_words |= offsets_given & (1 << i) != 0;
                    offsets_given |= 1 << i;
                    offsets[i] = w.value;
                    continue;
                }
                'R' | 'P' => {
                    arc_words = true;
                    other_arc_words = true;
                    continue;
                }
                'F' if feed.is_none() && w.value >= 0.0 => {
                    feed = Some(w.value);
                    continue;
                }
                'X' => 0,
                'Y' => 1,
                'Z' => 2,
                'A' => 3,
                'B' => 4,
                'C' => 5,
                _ => return None,
            };
            if given & (1 << axis) != 0 {
                return None;
            }
            given |= 1 << axis;
            axes[axis] = w.value;
        }
        let new_feed = feed.map(|f| f * self.k());
        let feed_ok = new_feed.unwrap_or(self.modal.feed) > 0.0;
        // A zero feed, and I J K R P without an arc, are the full path's to report.
        let arc = match motion {
            Motion::Rapid | Motion::Linear if arc_words => return None,
            Motion::Rapid => false,
            Motion::Linear if feed_ok => false,
            Motion::Clockwise | Motion::CounterClockwise if feed_ok => true,
            _ => return None,
        };
        if given == 0 {
            return None;
        }
        let end = self.target(&axes, given);
        // An arc's centre and turns, or the error that sends the block the full way.
        let arc = if arc {
            Some(
                match self.offsets_arc(motion, end, offsets, offsets_given) {
                    Some(geometry) if !other_arc_words => geometry,
                    _ => self.arc_geometry(block, motion, end)?,
                },
            )
        } else {
            None
        };
        // Committed: the full path's steps for this block, in its order.
        self.line = block.line;
        if let Some(f) = new_feed {
            self.modal.feed = f;
            self.emit(sink, CanonOp::SetFeedRate(f));
        }
        self.modal.motion = motion;
        self.cycle.reset();
        match arc {
            Some((center, turns)) => self.emit_arc(sink, end, center, turns),
            None => self.emit_straight(sink, motion == Motion::Linear, end),
        }
        self.pos = end;
        self.update_params(params);
        Some(Flow::Continue)
    }

    /// The end point of a move to the `given` axes (bit i for `axes[i]`), as
    /// `axis_target` computes it.
    fn target(&self, axes: &[f64; 6], given: u8) -> [f64; 6] {
        let k = self.k();
        let mut end = self.pos;
        for (i, &v) in axes.iter().enumerate() {
            if given & (1 << i) != 0 {
                let v = if i < 3 { v * k } else { v };
                end[i] = if self.modal.incremental {
                    self.pos[i] + v
                } else {
                    v
                };
            }
        }
        end
    }

    /// Centre and turns of an arc given by its centre offsets alone (no R, no P): what
    /// `arc_center`'s I J K branch computes, without decoding the block again. `None` for
    /// anything that branch would refuse (an off-plane word, no offset in the plane, a bad
    /// arc) or that it does not handle: the caller then takes the full path's code.
    fn offsets_arc(
        &self,
        motion: Motion,
        end: [f64; 6],
        offsets: [f64; 3],
        given: u8,
    ) -> Option<([f64; 2], i32)> {
        // Offset indices (I = 0, J = 1, K = 2) of the plane's first and second axes.
        let (o0, o1, off_axis) = match self.modal.plane {
            Plane::XY => (0, 1, 2),
            Plane::XZ => (2, 0, 1),
            Plane::YZ => (1, 2, 0),
        };
        if given & (1 << off_axis) != 0 || given & (1 << o0 | 1 << o1) == 0 {
            return None;
        }
        let (a0, a1, _) = self.modal.plane.axes();
        let start = [self.pos[a0], self.pos[a1]];
        let k = self.k();
        let (i, j) = (offsets[o0] * k, offsets[o1] * k);
        let center = if self.modal.arc_incremental {
            [start[0] + i, start[1] + j]
        } else {
            [i, j]
        };
        let tol = arcs::tolerance(self.modal.units);
        let center = arcs::center_from_offsets(start, [end[a0], end[a1]], center, &tol).ok()?;
        Some((center, if motion == Motion::Clockwise { -1 } else { 1 }))
    }

    /// Centre and turns of the arc of `block` to `end` in the current plane, by the full
    /// path's own code (which reads the direction from the motion mode, so `motion` is set
    /// while it runs); `None`, with nothing changed, on any error.
    fn arc_geometry(
        &mut self,
        block: &Block,
        motion: Motion,
        end: [f64; 6],
    ) -> Option<([f64; 2], i32)> {
        let previous = std::mem::replace(&mut self.modal.motion, motion);
        let (a0, a1, _) = self.modal.plane.axes();
        let mut d = self
            .decoded
            .take()
            .unwrap_or_else(|| Box::new(Decoded::empty()));
        let geometry = d.fill(block).ok().and_then(|_| {
            let center = self
                .arc_center(&d, [self.pos[a0], self.pos[a1]], [end[a0], end[a1]])
                .ok()?;
            Some((center, self.arc_turns(&d).ok()?))
        });
        self.decoded = Some(d);
        if geometry.is_none() {
            self.modal.motion = previous;
        }
        geometry
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::Word;
    use crate::diag::Span;
    use crate::interp::tool_table::ToolTable;
    use crate::interp::StartState;
    use oficina_canon::Canon;
    use proptest::prelude::*;

    /// Everything a block can change, as text.
    fn state(i: &Interpreter, p: &Params) -> String {
        let here: Vec<_> = (5420..5426).map(|n| p.get(n).unwrap()).collect();
        format!("{:?} {:?} {:?} {here:?}", i.modal, i.pos, i.line)
    }

    fn word() -> impl Strategy<Value = (char, f64)> {
        let value = prop_oneof![
            Just(0.0),
            Just(-0.0),
            Just(1.0),
            Just(2.0),
            Just(3.0),
            Just(1.0000001),
            Just(17.0),
            Just(18.0),
            Just(19.0),
            Just(20.0),
            Just(21.0),
            Just(90.1),
            Just(91.1),
            Just(90.0),
            Just(91.0),
            Just(93.0),
            Just(94.0),
            Just(-1.0),
            -100.0..100.0f64,
        ];
        ("[GGGXYZAFMNIJKRP]", value).prop_map(|(l, v)| (l.chars().next().unwrap(), v))
    }

    /// Runs `blocks` with and without the short way, checking after each block that the
    /// operations, errors and state agree; returns how many blocks took the short way.
    fn run_both(blocks: &[Vec<(char, f64)>]) -> Result<usize, TestCaseError> {
        let make = || {
            Interpreter::new(
                Dialect::LinuxCnc,
                &StartState::default(),
                ToolTable::default(),
            )
        };
        let (mut fast, mut full) = (make(), make());
        let (mut fast_params, mut full_params) = (Params::new(), Params::new());
        let (mut fast_ops, mut full_ops) = (Vec::<Canon>::new(), Vec::<Canon>::new());
        let mut short = 0;
        for (n, words) in blocks.iter().enumerate() {
            let block = Block {
                line: n as u32 + 1,
                words: words
                    .iter()
                    .map(|&(letter, value)| Word {
                        letter,
                        value,
                        span: Span::new(n as u32 + 1, 1, 2),
                    })
                    .collect(),
                ..Block::default()
            };
            let a = match fast.simple_move(&block, &mut fast_params, &mut |c| fast_ops.push(c)) {
                Some(flow) => {
                    short += 1;
                    Ok(flow)
                }
                None => fast.execute_full(&block, &mut fast_params, &mut |c| fast_ops.push(c)),
            };
            let b = full.execute_full(&block, &mut full_params, &mut |c| full_ops.push(c));
            prop_assert_eq!(format!("{a:?}"), format!("{b:?}"), "block {}", n + 1);
            prop_assert_eq!(&fast_ops, &full_ops, "block {}", n + 1);
            prop_assert_eq!(state(&fast, &fast_params), state(&full, &full_params));
        }
        Ok(short)
    }

    proptest! {
        /// A run of blocks gives the same operations, errors and state whether simple moves
        /// take the short way or not.
        #[test]
        fn the_short_way_changes_nothing(blocks in prop::collection::vec(prop::collection::vec(word(), 0..5), 1..25)) {
            run_both(&blocks)?;
        }
    }

    #[test]
    fn arcs_the_short_way_match_the_full_path() {
        let b = |words: &[(char, f64)]| words.to_vec();
        let blocks = [
            b(&[('G', 1.0), ('X', 0.0), ('Y', 0.0), ('F', 100.0)]),
            b(&[('G', 2.0), ('X', 10.0), ('Y', 0.0), ('I', 5.0), ('J', 0.0)]),
            b(&[('G', 3.0), ('X', 0.0), ('Y', 0.0), ('I', -5.0), ('J', 0.0)]),
            b(&[('G', 2.0), ('X', 10.0), ('Y', 0.0), ('R', 5.0)]),
            b(&[('G', 3.0), ('X', 0.0), ('Y', 0.0), ('R', -5.0), ('P', 2.0)]),
            b(&[('X', 10.0), ('Y', 0.0), ('R', 5.0), ('Z', -1.0)]),
            b(&[('G', 2.0), ('X', 10.0), ('Y', 0.0), ('I', 7.0), ('J', 0.0)]),
            b(&[('G', 2.0), ('X', 0.0), ('I', 5.0), ('P', 1.5)]),
            b(&[('G', 3.0), ('X', 10.0), ('I', 5.0), ('K', 1.0)]),
        ];
        let short = run_both(&blocks).unwrap();
        // Block 7 is a whole circle (it ends where it starts); 8 and 9 are errors.
        assert_eq!(short, 7, "the last two blocks are errors for the full path");
    }

    #[test]
    fn simple_moves_take_the_short_way() {
        let mut i = Interpreter::new(
            Dialect::LinuxCnc,
            &StartState::default(),
            ToolTable::default(),
        );
        let mut p = Params::new();
        let block = |words: &[(char, f64)]| Block {
            line: 1,
            words: words
                .iter()
                .map(|&(letter, value)| Word {
                    letter,
                    value,
                    span: Span::default(),
                })
                .collect(),
            ..Block::default()
        };
        let mut ops = Vec::new();
        assert!(i
            .simple_move(
                &block(&[('G', 1.0), ('X', 1.0), ('F', 100.0)]),
                &mut p,
                &mut |c| ops.push(c)
            )
            .is_some());
        assert!(i
            .simple_move(&block(&[('Y', 2.0)]), &mut p, &mut |c| ops.push(c))
            .is_some());
        assert_eq!(ops.len(), 3, "{ops:?}");
        for declined in [
            &[('G', 4.0), ('X', 1.0)][..],
            &[('G', 1.0), ('X', 1.0), ('I', 1.0)],
            &[('X', 1.0), ('X', 2.0)],
            &[('F', -1.0), ('X', 1.0)],
            &[('G', 1.0)],
            &[('M', 3.0), ('X', 1.0)],
        ] {
            assert!(
                i.simple_move(&block(declined), &mut p, &mut |c| ops.push(c))
                    .is_none(),
                "{declined:?}"
            );
        }
        assert_eq!(ops.len(), 3, "a declined block emits nothing");
    }
}
