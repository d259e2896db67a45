//! Jogging (`$J=`): single steps, and continuous jogging as the grbl wiki describes it:
//! while a key is held, keep a few short incremental jogs queued, each long enough that the
//! planner never has to slow down (dt > v² / (2·a·(N−1))), and end with the jog-cancel byte,
//! which stops the motion and flushes what is queued.

use crate::sender::Sender;
use std::io;

/// The `$J=` line for a relative move of `distance` mm along `axis` at `feed` mm/min.
pub fn step_line(axis: char, distance: f64, feed: f64) -> Result<String, String> {
    let axis = axis.to_ascii_uppercase();
    if !matches!(axis, 'X' | 'Y' | 'Z') {
        return Err(format!("jog axis '{axis}': grbl jogs X, Y or Z"));
    }
    if !(distance.is_finite() && feed.is_finite() && feed > 0.0) {
        return Err(format!(
            "jog {axis}{distance} F{feed}: distance must be a number and feed positive"
        ));
    }
    Ok(format!("$J=G91G21{axis}{distance:.4}F{feed:.1}"))
}

/// What the operator asked for, e.g. `X+10 F500` (a 10 mm step) or `X- F1000` (continuous).
#[derive(Clone, Debug, PartialEq)]
pub enum JogRequest {
    /// A jog by a fixed distance.
    Step {
        /// Axis letter.
        axis: char,
        /// Distance, mm (signed).
        distance: f64,
        /// Feed, mm/min.
        feed: f64,
    },
    /// A jog that runs until stopped.
    Continuous {
        /// Axis letter.
        axis: char,
        /// +1 or −1.
        direction: f64,
        /// Feed, mm/min.
        feed: f64,
    },
}

/// Parses `AXIS[+|-][DISTANCE] [F<feed>]`; the feed defaults to `default_feed`.
pub fn parse_request(text: &str, default_feed: f64) -> Result<JogRequest, String> {
    let mut parts = text.split_whitespace();
    let motion = parts
        .next()
        .ok_or("jog what? e.g. X+10 F500 (step) or X- F1000 (continuous)")?;
    let mut feed = default_feed;
    for p in parts {
        let v = p
            .strip_prefix(['F', 'f'])
            .ok_or_else(|| format!("jog: '{p}' is not a feed like F500"))?;
        feed = v
            .parse()
            .map_err(|_| format!("jog: feed '{v}' is not a number"))?;
    }
    let mut chars = motion.chars();
    let axis = chars
        .next()
        .map(|c| c.to_ascii_uppercase())
        .filter(|c| matches!(c, 'X' | 'Y' | 'Z'))
        .ok_or_else(|| format!("jog '{motion}': start with the axis X, Y or Z"))?;
    let rest: String = chars.collect();
    if !(feed.is_finite() && feed > 0.0) {
        return Err(format!("jog: feed {feed} must be positive"));
    }
    match rest.as_str() {
        "+" => Ok(JogRequest::Continuous {
            axis,
            direction: 1.0,
            feed,
        }),
        "-" => Ok(JogRequest::Continuous {
            axis,
            direction: -1.0,
            feed,
        }),
        r => {
            let distance: f64 = r.parse().map_err(|_| {
                format!("jog '{motion}': '{r}' is not a distance (or + / - for continuous)")
            })?;
            Ok(JogRequest::Step {
                axis,
                distance,
                feed,
            })
        }
    }
}

/// Seconds of motion per continuous-jog increment for `feed` mm/min, acceleration `accel`
/// mm/s² and `blocks` planner blocks; never below 25 ms so the serial line keeps up.
pub(crate) fn increment_seconds(feed: f64, accel: f64, blocks: usize) -> f64 {
    let v = feed / 60.0;
    let n = blocks.saturating_sub(1).max(1) as f64;
    (v * v / (2.0 * accel.max(1e-3) * n)).max(0.025)
}

/// A continuous jog in progress: call [`ContinuousJog::keep_up`] often (every ~10 ms), then
/// [`ContinuousJog::stop`].
pub struct ContinuousJog {
    line: String,
    /// Increments sent and not yet acknowledged.
    outstanding: usize,
    /// Increments sent so far.
    pub increments_sent: usize,
}

/// Increments kept queued ahead of the motion.
const AHEAD: usize = 3;

impl ContinuousJog {
    /// `direction` is +1 or −1; acceleration and planner size come from the machine.
    pub fn start(
        sender: &Sender,
        axis: char,
        direction: f64,
        feed: f64,
    ) -> Result<ContinuousJog, String> {
        let accel_setting = match axis.to_ascii_uppercase() {
            'X' => 120,
            'Y' => 121,
            _ => 122,
        };
        let accel = sender.settings.get(&accel_setting).copied().unwrap_or(10.0);
        let dt = increment_seconds(feed, accel, sender.planner_blocks);
        let line = step_line(axis, direction.signum() * feed / 60.0 * dt, feed)?;
        Ok(ContinuousJog {
            line,
            outstanding: 0,
            increments_sent: 0,
        })
    }

    /// Tops the queue up to a few increments; `acks` is how many `ok`s arrived since the
    /// last call.
    pub fn keep_up(&mut self, sender: &mut Sender, acks: usize) -> io::Result<()> {
        self.outstanding = self.outstanding.saturating_sub(acks);
        while self.outstanding < AHEAD {
            sender.link().send_line(&self.line)?;
            self.outstanding += 1;
            self.increments_sent += 1;
        }
        Ok(())
    }

    /// Jog cancel: grbl decelerates to a stop and drops the queued increments.
    pub fn stop(self, sender: &mut Sender) -> io::Result<()> {
        sender.realtime(crate::realtime::Realtime::JogCancel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_lines_and_increment_length() {
        assert_eq!(
            step_line('x', -1.5, 500.0).unwrap(),
            "$J=G91G21X-1.5000F500.0"
        );
        assert!(step_line('A', 1.0, 100.0).is_err());
        assert!(step_line('X', 1.0, 0.0).is_err());
        // 3000 mm/min = 50 mm/s at 100 mm/s² with 15 blocks: 2500 / (2·100·14) = 0.893 s.
        assert!((increment_seconds(3000.0, 100.0, 15) - 2500.0 / 2800.0).abs() < 1e-12);
        assert_eq!(increment_seconds(60.0, 1000.0, 15), 0.025);
        assert_eq!(
            parse_request("x+10 F500", 100.0),
            Ok(JogRequest::Step {
                axis: 'X',
                distance: 10.0,
                feed: 500.0
            })
        );
        assert_eq!(
            parse_request("Z-0.1", 100.0),
            Ok(JogRequest::Step {
                axis: 'Z',
                distance: -0.1,
                feed: 100.0
            })
        );
        assert_eq!(
            parse_request("Y- F1000", 100.0),
            Ok(JogRequest::Continuous {
                axis: 'Y',
                direction: -1.0,
                feed: 1000.0
            })
        );
        assert!(parse_request("A+", 100.0).is_err());
        assert!(parse_request("X+ F-3", 100.0).is_err());
        assert!(parse_request("X+ S3", 100.0).is_err());
        assert!(parse_request("", 100.0).is_err());
    }
}
