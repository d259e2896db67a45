//! M66, waiting on an input, as LinuxCNC's `convert_m` checks it and its standalone canon
//! answers it.
//!
//! Oficina's machines have no digital or analog inputs (as the standalone `rs274`'s canon,
//! whose `WAIT` returns at once): M66 emits nothing and the input read into #5399 is the
//! canon's default, `GET_EXTERNAL_DIGITAL_INPUT(index, #5399 ≠ 0)` for a digital input (1
//! or 0) and `#5399` unchanged for an analog one.

use super::words::{m_group as M, Decoded};
use super::Interpreter;
use crate::diag::Diagnostic;
use crate::params::Params;

/// #5399: the value M66 read.
const INPUT_VALUE: i64 = 5399;

impl Interpreter {
    /// M66 P… (digital) or E… (analog), L wait type, Q timeout (seconds).
    pub(super) fn wait_input(&self, d: &Decoded, params: &mut Params) -> Result<(), Diagnostic> {
        let span = d.m_span(M::IO);
        let round = |v: f64| v.round();
        let (p, e) = (d.get('P'), d.get('E'));
        let wait_type = d.get('L').map(round);
        let q = d.get('Q').unwrap_or(0.0);
        if p.is_some() && e.is_some() {
            return Err(self.fail(
                span,
                "Invalid to select both a digital and an analog input with M66",
                0,
            ));
        }
        if q <= 0.0 && wait_type.is_some_and(|l| l > 0.0) {
            return Err(self.fail(span, "Zero timeout with wait type != immediate return", 0));
        }
        if e.is_some() && wait_type.is_some_and(|l| l != 0.0) {
            return Err(self.fail(
                span,
                "Can't select analog input with wait type != immediate return",
                0,
            ));
        }
        let negative = |v: Option<f64>| v.is_some_and(|v| round(v) < 0.0);
        if negative(p) || negative(e) || (p.is_none() && e.is_none()) {
            return Err(self.fail(
                span,
                "Need to have either a valid P or a valid E word with M66",
                0,
            ));
        }
        if self.modal.comp.is_some() {
            let kind = if p.is_some() { "digital" } else { "analog" };
            return Err(self.fail(
                span,
                format!("Cannot wait for {kind} input with cutter radius compensation on"),
                0,
            ));
        }
        if p.is_some() {
            let was = params.get(INPUT_VALUE).unwrap_or(0.0);
            let _ = params.set(INPUT_VALUE, if was != 0.0 { 1.0 } else { 0.0 });
        }
        Ok(())
    }
}
