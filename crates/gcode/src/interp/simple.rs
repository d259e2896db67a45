//! The short way through the interpreter for the block that makes up most programs: a
//! straight move (`G0`/`G1`, or the modal one) with axis words and perhaps an `F`, in the
//! LinuxCNC dialect, without cutter compensation or inverse-time feed.
//!
//! It does exactly what the full path does for such a block (set the feed, set the motion
//! mode, move, refresh the position parameters) and declines (`None`, nothing changed)
//! whenever the block holds anything else or would be an error, so every other case and
//! every message keep their single implementation in the full path.

use super::state::Motion;
use super::{Flow, Interpreter, Sink};
use crate::block::Block;
use crate::params::Params;
use crate::Dialect;
use oficina_canon::{CanonOp, FeedMode};

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
        {
            return None;
        }
        let mut motion = self.modal.motion;
        let mut g_seen = false;
        let mut feed = None;
        // Axis values in `Pos` order, and which were given.
        let mut axes = [0.0; 6];
        let mut given = 0u8;
        for w in &block.words {
            let axis = match w.letter {
                'G' if !g_seen => {
                    g_seen = true;
                    motion = match w.value {
                        0.0 => Motion::Rapid,
                        1.0 => Motion::Linear,
                        _ => return None,
                    };
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
        let k = self.k();
        let new_feed = feed.map(|f| f * k);
        let feeding = match motion {
            Motion::Rapid => false,
            // "Cannot do g1 with zero feed rate" is the full path's to report.
            Motion::Linear if new_feed.unwrap_or(self.modal.feed) > 0.0 => true,
            _ => return None,
        };
        if given == 0 {
            return None;
        }
        // Committed: the full path's steps for this block, in its order.
        self.line = block.line;
        if let Some(f) = new_feed {
            self.modal.feed = f;
            self.emit(sink, CanonOp::SetFeedRate(f));
        }
        self.modal.motion = motion;
        self.cycle.reset();
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
        self.emit_straight(sink, feeding, end);
        self.pos = end;
        self.update_params(params);
        Some(Flow::Continue)
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
            Just(1.0000001),
            Just(20.0),
            Just(21.0),
            Just(90.0),
            Just(91.0),
            Just(93.0),
            Just(94.0),
            Just(-1.0),
            -100.0..100.0f64,
        ];
        ("[GGGXYZAFMN]", value).prop_map(|(l, v)| (l.chars().next().unwrap(), v))
    }

    proptest! {
        /// A run of blocks gives the same operations, errors and state whether simple moves
        /// take the short way or not.
        #[test]
        fn the_short_way_changes_nothing(blocks in prop::collection::vec(prop::collection::vec(word(), 0..5), 1..25)) {
            let make = || Interpreter::new(Dialect::LinuxCnc, &StartState::default(), ToolTable::default());
            let (mut fast, mut full) = (make(), make());
            let (mut fast_params, mut full_params) = (Params::new(), Params::new());
            let (mut fast_ops, mut full_ops) = (Vec::<Canon>::new(), Vec::<Canon>::new());
            for (n, words) in blocks.iter().enumerate() {
                let block = Block {
                    line: n as u32 + 1,
                    words: words
                        .iter()
                        .map(|&(letter, value)| Word { letter, value, span: Span::new(n as u32 + 1, 1, 2) })
                        .collect(),
                    ..Block::default()
                };
                let a = fast.execute(&block, &mut fast_params, &mut |c| fast_ops.push(c));
                let b = full.execute_full(&block, &mut full_params, &mut |c| full_ops.push(c));
                prop_assert_eq!(format!("{a:?}"), format!("{b:?}"));
                prop_assert_eq!(&fast_ops, &full_ops);
                prop_assert_eq!(state(&fast, &fast_params), state(&full, &full_params));
            }
        }
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
            &[('G', 2.0), ('X', 1.0)][..],
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
