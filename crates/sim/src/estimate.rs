//! Time estimate from programmed feeds alone. The motion planner's estimate (with
//! acceleration and junction speeds) replaces it where available; this is a lower bound.

use oficina_canon::Summarizer;
use oficina_canon::{Canon, Pos};

/// Seconds for `ops`: feed moves at their programmed feed, rapids with every axis at
/// `rapid_mm_min` (the slowest axis sets the time), dwells
/// as written, starting from `start`.
pub fn feed_only_estimate<'a>(
    ops: impl IntoIterator<Item = &'a Canon>,
    start: [f64; 3],
    rapid_mm_min: f64,
) -> f64 {
    let mut s = Summarizer::new(Pos::xyz(start[0], start[1], start[2]), [rapid_mm_min; 3]);
    for c in ops {
        s.add(&c.op);
    }
    let sum = s.finish();
    sum.feed_rate_seconds
}
