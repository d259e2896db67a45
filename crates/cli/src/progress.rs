//! The spinner the long jobs (carve, mill, sole) show their stages on.

use indicatif::{ProgressBar, ProgressStyle};
use oficina_app::Feedback;
use std::sync::atomic::AtomicBool;

pub(crate) fn progress_bar() -> ProgressBar {
    let bar = ProgressBar::new(100);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed_precise} {wide_msg}")
            .expect("static template"),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// Runs `job` with the stages shown on a spinner (nobody cancels a command-line job: ^C does).
pub(crate) fn with_bar<T>(job: impl FnOnce(Feedback) -> T) -> (T, ProgressBar) {
    let bar = progress_bar();
    let never = AtomicBool::new(false);
    let show = |stage: &str, _: f64| bar.set_message(stage.to_string());
    let out = job(Feedback {
        progress: &show,
        cancel: &never,
    });
    (out, bar)
}
