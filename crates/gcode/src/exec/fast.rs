//! Which fast path reads a line: the plain one (letters and numbers only) while lines are
//! plain, the direct one (expressions, parameters) otherwise. Both give what the full path
//! gives, or decline; the plain one is quicker but wasted on lines with expressions.

use super::{direct, plain};
use crate::block::Block;
use crate::params::Params;

/// The fast paths' state kept from line to line.
pub(super) struct FastPaths {
    /// Buffers of the direct path.
    scratch: direct::Scratch,
    /// The last line taken by a fast path was plain: try the plain path first.
    plain_lines: bool,
    /// Plain lines the direct path has taken in a row since the plain path last failed.
    plain_run: u8,
}

impl Default for FastPaths {
    fn default() -> FastPaths {
        FastPaths {
            scratch: direct::Scratch::default(),
            plain_lines: true,
            plain_run: 0,
        }
    }
}

impl FastPaths {
    /// One line through the plain or the direct path, with the line's length when one
    /// takes it; `raw` and `in_place` as for [`direct::direct_line_upto`].
    pub(super) fn line(
        &mut self,
        raw: &[u8],
        in_place: Option<usize>,
        number: u32,
        params: &mut Params,
        block: &mut Block,
    ) -> Option<usize> {
        let ended = |len: usize| {
            in_place.is_none_or(|max_len| raw.get(len) == Some(&b'\n') && len <= max_len)
        };
        let scratch = &mut self.scratch;
        if self.plain_lines {
            if let Some(len) = plain::plain_line_upto(raw, number, block).filter(|&l| ended(l)) {
                return Some(len);
            }
            self.plain_lines = false;
            self.plain_run = 0;
            direct::direct_line_upto(raw, in_place, number, params, block, scratch)
        } else {
            let len = direct::direct_line_upto(raw, in_place, number, params, block, scratch)?;
            // Back to the plain path only after two plain lines in a row: a lone plain
            // line between lines with expressions would make the next line fail the plain
            // path first, wasting its reading.
            // (`plain_lines` is false here: only a plain line can set it.)
            if scratch.was_plain {
                self.plain_run = self.plain_run.saturating_add(1);
                self.plain_lines = self.plain_run >= 2;
            } else {
                self.plain_run = 0;
            }
            Some(len)
        }
    }
}
