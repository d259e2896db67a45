//! G96 (constant surface speed, D the top speed) and G97 (rev/min), as LinuxCNC's
//! `convert_spindle_mode` sets them: the mode is a canonical call of its own, and the S word
//! keeps its number (a surface speed under G96).

use super::words::{g_group as G, Decoded};
use super::{Interpreter, Sink};
use crate::diag::Diagnostic;
use oficina_canon::{CanonOp, SpindleMode};

impl Interpreter {
    /// G96 (`code` 960) or G97 (970).
    pub(super) fn set_spindle_mode(
        &mut self,
        d: &Decoded,
        code: u16,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let mode = if code == 960 {
            if !d.has('S') {
                return Err(self
                    .fail(d.g_span(G::SPINDLE_MODE), "S word missing with G96", 0)
                    .with_help("G96 takes the surface speed in its S word"));
            }
            // rs274 takes D's magnitude.
            SpindleMode::SurfaceSpeed {
                max_rpm: d.get('D').map(f64::abs),
            }
        } else {
            SpindleMode::Rpm
        };
        self.modal.spindle_mode = mode;
        self.emit(sink, CanonOp::SetSpindleMode(mode));
        Ok(())
    }
}
