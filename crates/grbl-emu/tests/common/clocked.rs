//! A character-counting sender (grbl's recommended protocol) driving an emulator core on a
//! simulated clock: no socket, no wall-clock time.

use oficina_grbl::GrblState;
use oficina_grbl_emu::Core;
use std::collections::VecDeque;

/// One step of the simulated clock (s).
pub(crate) const TICK: f64 = 1e-3;

/// How a streamed job went.
pub(crate) struct Streamed {
    /// Simulated time when the job ended (the core idle with every line answered).
    pub(crate) seconds: f64,
    pub(crate) starvations: u64,
    pub(crate) starved_seconds: f64,
}

/// Streams `lines` into `c`, never more than grbl's 127-byte receive buffer in flight;
/// `pause(i)` says how long to wait before offering line `i`. Every reply must be `ok`.
pub(crate) fn stream(c: &mut Core, lines: &[String], pause: impl Fn(usize) -> f64) -> Streamed {
    let mut inflight: VecDeque<usize> = VecDeque::new();
    let mut next = 0;
    let mut ready_at = pause(0);
    let mut replies = String::new();
    for k in 0..10_000_000u64 {
        let t = k as f64 * TICK;
        while next < lines.len() && t >= ready_at {
            let len = lines[next].len() + 1;
            if inflight.iter().sum::<usize>() + len > 127 {
                break;
            }
            for b in lines[next].bytes().chain(std::iter::once(b'\n')) {
                c.receive(b);
            }
            inflight.push_back(len);
            next += 1;
            ready_at = t + pause(next);
        }
        c.tick(t);
        replies.extend(c.out.drain(..).map(char::from));
        while let Some(end) = replies.find("\r\n") {
            let reply: String = replies.drain(..end + 2).collect();
            assert!(!reply.starts_with("error"), "{reply}");
            if reply.starts_with("ok") {
                inflight.pop_front();
            }
        }
        if next == lines.len() && inflight.is_empty() && c.state == GrblState::Idle {
            return Streamed {
                seconds: t,
                starvations: c.stats.starvations,
                starved_seconds: c.stats.starved_seconds,
            };
        }
    }
    panic!("the job did not end in simulated time");
}
