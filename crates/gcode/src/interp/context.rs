//! M70–M73: saving and restoring the modal state (rs274's `save_settings`,
//! `restore_settings`, `gen_settings`, `gen_m_codes` in interp_convert.cc). The state is kept
//! per call level: M70 saves it, M71 forgets it, M72 restores it, M73 saves it to be restored
//! when the subroutine returns. A restore runs blocks made from the difference, as rs274
//! does, so the same canonical calls come out: the units first, then one block with F
//! (rounded to 0.1, rs274's `F%.1f`), S (`S%.0f`) and the G codes that differ, then one block
//! per M code that differs. The motion mode and cutter compensation are not restored.

use super::state::Modal;
use super::{Interpreter, Sink};
use crate::block::{Block, Word};
use crate::diag::{Diagnostic, Span};
use crate::params::Params;
use oficina_canon::{FeedMode, PathControlMode, Plane, SpindleDir, Units};

/// A saved state and whether it comes back on return (M73).
#[derive(Clone, Debug)]
pub(crate) struct Saved {
    modal: Modal,
    on_return: bool,
}

/// The saved states, by call level.
#[derive(Clone, Debug, Default)]
pub(crate) struct Contexts {
    levels: Vec<Option<Saved>>,
}

impl Contexts {
    fn slot(&mut self, level: usize) -> &mut Option<Saved> {
        if self.levels.len() <= level {
            self.levels.resize(level + 1, None);
        }
        &mut self.levels[level]
    }
}

impl Interpreter {
    /// M70 (`auto` false) or M73 (`auto` true, restored on return; at the top level there is
    /// nothing to return to and it is kept as M70's).
    pub(super) fn save_context(&mut self, params: &Params, auto: bool) {
        let level = params.call_depth();
        let modal = self.modal.clone();
        *self.contexts.slot(level) = Some(Saved {
            modal,
            on_return: auto && level > 0,
        });
    }

    /// M71: forget the state saved at this level.
    pub(super) fn invalidate_context(&mut self, params: &Params) {
        *self.contexts.slot(params.call_depth()) = None;
    }

    /// M72: restore the state saved at this level.
    pub(super) fn restore_context(
        &mut self,
        params: &mut Params,
        span: Span,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let level = params.call_depth();
        let Some(saved) = self.contexts.slot(level).clone() else {
            return Err(Diagnostic::error(
                span,
                "Cannot restore context from invalid stack frame - missing M70/M73?",
            ));
        };
        self.apply_saved(&saved.modal, params, sink)
    }

    /// After a subroutine returned to `depth`: a state saved by M73 in the subroutine
    /// (level `depth + 1`) comes back; the deeper levels are forgotten.
    pub fn left_call(&mut self, params: &mut Params, sink: Sink) -> Result<(), Diagnostic> {
        let depth = params.call_depth();
        let mut restore = None;
        for level in depth + 1..self.contexts.levels.len() {
            if let Some(s) = self.contexts.levels[level].take() {
                if level == depth + 1 && s.on_return {
                    restore = Some(s.modal);
                }
            }
        }
        match restore {
            Some(m) => self.apply_saved(&m, params, sink),
            None => Ok(()),
        }
    }

    /// Whether any state is saved below the top level (a return may have to restore it).
    pub fn has_saved_contexts(&self) -> bool {
        self.contexts.levels.iter().skip(1).any(Option::is_some)
    }

    fn apply_saved(
        &mut self,
        s: &Modal,
        params: &mut Params,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let line = self.line;
        let w = |letter: char, value: f64| Word {
            letter,
            value,
            span: Span::line(line),
        };
        let run = |me: &mut Interpreter, words: Vec<Word>, params: &mut Params, sink: Sink| {
            let block = Block {
                line,
                words,
                ..Block::default()
            };
            me.execute(&block, params, sink).map(|_| ())
        };
        let cur = self.modal.clone();
        if cur.units != s.units {
            let g = if s.units == Units::Inch { 20.0 } else { 21.0 };
            run(self, vec![w('G', g)], params, sink)?;
        }
        let mut words = vec![
            // rs274 prints the saved values with F%.1f and S%.0f and reads them back.
            w('F', (s.feed / s.units.mm() * 10.0).round() / 10.0),
            w('S', s.speed.round()),
        ];
        if cur.plane != s.plane {
            words.push(w(
                'G',
                match s.plane {
                    Plane::XY => 17.0,
                    Plane::XZ => 18.0,
                    _ => 19.0,
                },
            ));
        }
        if cur.incremental != s.incremental {
            words.push(w('G', if s.incremental { 91.0 } else { 90.0 }));
        }
        if cur.feed_mode != s.feed_mode {
            words.push(w(
                'G',
                match s.feed_mode {
                    FeedMode::InverseTime => 93.0,
                    FeedMode::UnitsPerRev => 95.0,
                    _ => 94.0,
                },
            ));
        }
        if cur.coord_system != s.coord_system {
            let g = [54.0, 55.0, 56.0, 57.0, 58.0, 59.0, 59.1, 59.2, 59.3];
            if let Some(&v) = g.get(usize::from(s.coord_system).wrapping_sub(1)) {
                words.push(w('G', v));
            }
        }
        if cur.tool_length_on != s.tool_length_on {
            words.push(w('G', if s.tool_length_on { 43.0 } else { 49.0 }));
        }
        if cur.retract_to_old_z != s.retract_to_old_z {
            words.push(w('G', if s.retract_to_old_z { 98.0 } else { 99.0 }));
        }
        if cur.arc_incremental != s.arc_incremental {
            words.push(w('G', if s.arc_incremental { 91.1 } else { 90.1 }));
        }
        if cur.diameter_mode != s.diameter_mode {
            words.push(w('G', if s.diameter_mode { 7.0 } else { 8.0 }));
        }
        if cur.control != s.control
            || (s.control == PathControlMode::Continuous
                && (cur.blend_tolerance != s.blend_tolerance
                    || cur.naive_tolerance != s.naive_tolerance))
        {
            match s.control {
                PathControlMode::ExactStop => words.push(w('G', 61.1)),
                PathControlMode::ExactPath => words.push(w('G', 61.0)),
                PathControlMode::Continuous => {
                    words.push(w('G', 64.0));
                    if s.blend_tolerance > 0.0 {
                        words.push(w('P', s.blend_tolerance / s.units.mm()));
                        if s.naive_tolerance > 0.0 {
                            words.push(w('Q', s.naive_tolerance / s.units.mm()));
                        }
                    }
                }
            }
        }
        let mut m = Vec::new();
        if cur.spindle != s.spindle {
            m.push(match s.spindle {
                Some(SpindleDir::Clockwise) => 3.0,
                Some(_) => 4.0,
                None => 5.0,
            });
        }
        // rs274's write_m_codes: mist is 7, or 9 when neither is on, or -1 (nothing) when
        // only flood is; flood is 8 or -1. A -1 is never restored.
        let mist = |m: &Modal| {
            if m.mist {
                7
            } else if m.flood {
                -1
            } else {
                9
            }
        };
        let flood = |m: &Modal| if m.flood { 8 } else { -1 };
        if mist(&cur) != mist(s) && mist(s) != -1 {
            m.push(f64::from(mist(s)));
        }
        if flood(&cur) != flood(s) && flood(s) != -1 {
            m.push(8.0);
        }
        if (cur.feed_override, cur.speed_override) != (s.feed_override, s.speed_override) {
            m.push(if s.feed_override && s.speed_override {
                48.0
            } else {
                49.0
            });
        }
        // gen_settings ends without a newline: the first M code shares the G codes' block.
        let mut m = m.into_iter();
        if let Some(first) = m.next() {
            words.push(w('M', first));
        }
        run(self, words, params, sink)?;
        for code in m {
            run(self, vec![w('M', code)], params, sink)?;
        }
        Ok(())
    }
}
