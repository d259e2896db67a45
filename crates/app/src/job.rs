//! What every job pipeline is handed besides its parameters: where to report progress and
//! the flag that cancels it. Pipelines look at the flag between stages and inside long
//! loops that report progress.

use crate::Error;
use std::sync::atomic::{AtomicBool, Ordering};

/// `progress(stage, fraction)`: a job's progress report.
pub type ProgressFn<'a> = &'a (dyn Fn(&str, f64) + Sync);

#[derive(Clone, Copy)]
/// What a running job reports to, and the flag that cancels it.
pub struct Feedback<'a> {
    /// `progress(stage, fraction)`, fraction in 0…1 within the stage.
    pub progress: ProgressFn<'a>,
    /// Set to stop the job at its next check.
    pub cancel: &'a AtomicBool,
}

static NEVER: AtomicBool = AtomicBool::new(false);

impl Feedback<'static> {
    /// Nobody listens and nobody cancels.
    pub fn none() -> Feedback<'static> {
        Feedback {
            progress: &|_, _| {},
            cancel: &NEVER,
        }
    }
}

impl Feedback<'_> {
    /// A new stage begins: reported, unless the job was cancelled.
    pub fn stage(&self, name: &str) -> Result<(), Error> {
        self.check()?;
        (self.progress)(name, 0.0);
        Ok(())
    }

    /// The cancelled error once the flag is set.
    pub fn check(&self) -> Result<(), Error> {
        if self.cancel.load(Ordering::Relaxed) {
            Err(Error::cancelled())
        } else {
            Ok(())
        }
    }

    /// True once the flag is set.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}
