//! A whole job through grbl's own check mode (`$C`): the firmware parses every line at full
//! serial speed without moving, so a program is proven against the real firmware's parser
//! before any cut.

use crate::job::StreamProgram;
use crate::link::LinkEvent;
use crate::messages;
use crate::response::Response;
use crate::sender::{Mode, Sender};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

impl Sender {
    /// Runs `job` through grbl's own check mode (`$C`): the firmware parses every line at
    /// full serial speed without moving, and every rejected line is collected as
    /// (job index, error code). Check mode is left again (grbl resets when it is).
    pub fn check_job(&mut self, job: &StreamProgram) -> Result<Vec<(usize, u8)>, String> {
        let on = self.command("$C").map_err(|e| e.to_string())?;
        if let Some(code) = on.error {
            return Err(format!(
                "check mode ($C) refused: {}",
                messages::describe_error(code)
            ));
        }
        let capacity = match self.mode {
            Mode::CharCounting(n) => n,
            Mode::SendResponse => 0,
        };
        let mut rejected = Vec::new();
        let mut inflight: VecDeque<(usize, usize)> = VecDeque::new();
        let mut used = 0;
        let mut next = 0;
        let mut last_reply = Instant::now();
        while next < job.len() || !inflight.is_empty() {
            while next < job.len() {
                let len = job.lines[next].text.len() + 1;
                if !(inflight.is_empty() || used + len <= capacity) {
                    break;
                }
                self.link
                    .send_line(&job.lines[next].text)
                    .map_err(|e| e.to_string())?;
                inflight.push_back((next, len));
                used += len;
                next += 1;
            }
            match self.link.recv(Duration::from_millis(20)) {
                Some(LinkEvent::Line(r @ (Response::Ok | Response::Error(_)), _)) => {
                    last_reply = Instant::now();
                    if let Some((i, len)) = inflight.pop_front() {
                        used -= len;
                        if let Response::Error(code) = r {
                            rejected.push((i, code));
                        }
                    }
                }
                Some(LinkEvent::Closed(why)) => return Err(why),
                _ => {
                    if last_reply.elapsed() > self.options.reply_timeout {
                        return Err(format!(
                            "check mode: no reply for {:?}",
                            self.options.reply_timeout
                        ));
                    }
                }
            }
        }
        // `$C` again leaves check mode; grbl answers and soft-resets.
        let off = self.command("$C").map_err(|e| e.to_string())?;
        if let Some(code) = off.error {
            return Err(format!(
                "leaving check mode refused: {}",
                messages::describe_error(code)
            ));
        }
        let _ = self.wait_at_rest();
        Ok(rejected)
    }
}
