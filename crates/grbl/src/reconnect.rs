//! The connection's life: connecting, connected, lost, and trying again. A USB adapter
//! that re-enumerates or a Wi-Fi board that drops takes seconds to come back, so a lost
//! link is retried with a growing pause until a deadline, reporting each state change.

use crate::sender::{Sender, SenderOptions};
use crate::transport::Endpoint;
use std::io;
use std::time::{Duration, Instant};

/// Where reconnecting stands, for the operator.
#[derive(Clone, Debug, PartialEq)]
pub enum LinkState {
    /// Attempt number `attempt` under way.
    Connecting {
        /// From 1.
        attempt: u32,
    },
    /// The firmware answered.
    Connected {
        /// Its welcome line.
        firmware: String,
    },
    /// The last attempt failed; the next one comes after `retry_in`.
    Waiting {
        /// Why it failed.
        error: String,
        /// Time to the next attempt.
        retry_in: Duration,
    },
    /// The deadline passed.
    GaveUp {
        /// The last error.
        error: String,
    },
}

/// How hard to try.
#[derive(Clone, Debug, PartialEq)]
pub struct RetryPolicy {
    /// Give up when this much time has passed since the first attempt.
    pub deadline: Duration,
    /// Pause after the first failed attempt; later pauses grow up to `max_pause`.
    pub first_pause: Duration,
    /// Longest pause between attempts.
    pub max_pause: Duration,
}

impl Default for RetryPolicy {
    fn default() -> Self {
        RetryPolicy {
            deadline: Duration::from_secs(30),
            first_pause: Duration::from_millis(250),
            max_pause: Duration::from_secs(3),
        }
    }
}

/// Connects (handshake included), retrying per `policy`; every state goes to `on_state`.
pub fn connect_with_retry(
    endpoint: &Endpoint,
    options: &SenderOptions,
    policy: &RetryPolicy,
    on_state: &mut dyn FnMut(&LinkState),
) -> io::Result<Sender> {
    let start = Instant::now();
    let mut pause = policy.first_pause;
    let mut attempt = 0;
    loop {
        attempt += 1;
        on_state(&LinkState::Connecting { attempt });
        match Sender::connect(endpoint, options.clone()) {
            Ok(s) => {
                on_state(&LinkState::Connected {
                    firmware: s.firmware.clone(),
                });
                return Ok(s);
            }
            Err(e) => {
                if start.elapsed() + pause > policy.deadline {
                    let error = format!(
                        "{e} (gave up after {attempt} attempts in {:.0} s)",
                        start.elapsed().as_secs_f64()
                    );
                    on_state(&LinkState::GaveUp {
                        error: error.clone(),
                    });
                    return Err(io::Error::new(e.kind(), error));
                }
                on_state(&LinkState::Waiting {
                    error: e.to_string(),
                    retry_in: pause,
                });
                std::thread::sleep(pause);
                pause = (pause * 2).min(policy.max_pause);
            }
        }
    }
}
