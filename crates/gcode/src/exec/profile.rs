//! Reading a subroutine as a G70–G72 profile: rs274 calls `O<Q> CALL` and reads the body's
//! blocks (running their o-word flow) until the call returns, instead of running them.

use super::Executor;
use crate::ast::{Keyword, OWord};
use crate::diag::{Diagnostic, Span};
use crate::params::Params;
use std::io::{BufRead, Seek};

/// The call depth a profile read returns to, and whether it has.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ProfileCall {
    depth: Option<usize>,
    returned: bool,
}

impl<R: BufRead + Seek> Executor<R> {
    /// Call subroutine `label` (the cycle's Q) from `line`; blocks are then read from it
    /// until it returns, when reading answers "no block" and [`Executor::take_profile_returned`]
    /// says so.
    pub fn call_for_profile(
        &mut self,
        label: &str,
        line: u32,
        params: &mut Params,
    ) -> Result<(), Diagnostic> {
        let depth = self.calls.len();
        let o = OWord {
            label: label.to_string(),
            label_expr: None,
            keyword: Keyword::Call,
            args: Vec::new(),
            span: Span::line(line),
        };
        self.call(&o, params)?;
        self.profile = ProfileCall {
            depth: Some(depth),
            returned: false,
        };
        Ok(())
    }

    /// After an o-word line: whether it returned from the profile's call.
    pub(super) fn profile_returned(&mut self) -> bool {
        match self.profile.depth {
            Some(d) if self.calls.len() <= d => {
                self.profile = ProfileCall {
                    depth: None,
                    returned: true,
                };
                true
            }
            _ => false,
        }
    }

    /// Whether the profile's call returned (rather than the program ending); clears it.
    pub fn take_profile_returned(&mut self) -> bool {
        let r = self.profile.returned;
        self.profile = ProfileCall::default();
        r
    }
}
