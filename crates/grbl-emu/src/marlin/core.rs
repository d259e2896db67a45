//! Marlin 2.x's serial command reader and the few commands a pen plotter uses, without
//! I/O: [`MarlinCore::receive`] takes one received line and returns what Marlin prints.
//!
//! The reader follows `GCodeQueue::get_serial_commands` (Marlin/src/gcode/queue.cpp):
//! text from `;` on is a comment; a line starting with `N` must carry the last accepted
//! number + 1 (an `M110` line excepted, its second `N` is taken) — checked first — and a
//! `*checksum`, the XOR of the bytes before it. A refused line prints
//! `Error:<why>, Last Line: <last>`, `Resend: <last + 1>` and `ok`, and empties the input
//! buffer (the caller drops what it had queued). A line without `N` is taken unchecked.

use oficina_grbl::{clean_line, line_words, marlin_code};

/// Marlin's `MAX_CMD_SIZE`: the rest of a longer line is skipped.
const MAX_CMD_SIZE: usize = oficina_grbl::MARLIN_MAX_CMD_SIZE;

/// How the emulated board behaves.
#[derive(Clone, Debug, PartialEq)]
pub struct MarlinConfig {
    /// The first time line `N` arrives, one of its bytes is changed on the wire.
    pub corrupt_line: Option<u32>,
    /// Every K-th numbered line is lost on the wire (never reaches the reader).
    pub drop_every: Option<u32>,
    /// `G28` and `M400` take this long (ms), printing `busy: processing` keep-alives.
    pub busy_ms: u64,
    /// Keep-alive period (`M113`, Marlin's default 2 s), ms.
    pub keepalive_ms: u64,
    /// Where `G28` puts the machine, mm.
    pub home: [f64; 3],
}

impl Default for MarlinConfig {
    fn default() -> Self {
        MarlinConfig {
            corrupt_line: None,
            drop_every: None,
            busy_ms: 0,
            keepalive_ms: 2000,
            home: [0.0; 3],
        }
    }
}

/// One line Marlin executed: its number (if it had one) and its command.
#[derive(Clone, Debug, PartialEq)]
pub struct Executed {
    /// `N` of the line, `None` for an unnumbered command.
    pub n: Option<u32>,
    /// The command without number and checksum.
    pub command: String,
}

/// A straight move (G0, G1, G28) and the pen servo's angle while it ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Move {
    /// Start, mm.
    pub from: [f64; 3],
    /// End, mm.
    pub to: [f64; 3],
    /// The last `M280 P0 S…` angle before it, degrees.
    pub servo: Option<f64>,
}

/// Counters for reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MarlinStats {
    /// Lines that reached the reader.
    pub lines_received: u64,
    /// Lines executed.
    pub lines_executed: u64,
    /// Refusals: bad checksum, wrong number, no checksum.
    pub checksum_errors: u64,
    /// Refusals for a line number out of sequence.
    pub line_number_errors: u64,
    /// Lines lost on purpose (`drop_every`).
    pub dropped: u64,
    /// Lines changed on purpose (`corrupt_line`).
    pub corrupted: u64,
}

/// What Marlin does with a line once checked.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Print these lines (the last is `ok`).
    Reply(Vec<String>),
    /// The line was refused: print these, and drop the rest of the input buffer.
    Refused(Vec<String>),
    /// Busy for `ms` (keep-alives), then print these.
    Busy {
        /// How long, ms.
        ms: u64,
        /// Printed after.
        then: Vec<String>,
    },
    /// `M0`/`M1`: print the message, wait for `M108` (keep-alives), then `ok`.
    WaitForUser(String),
    /// `M112`: print this and halt.
    Kill(String),
}

/// The board's state.
#[derive(Clone, Debug)]
pub struct MarlinCore {
    /// How it behaves.
    pub config: MarlinConfig,
    last_n: i64,
    /// Position, mm.
    pub pos: [f64; 3],
    absolute: bool,
    inches: bool,
    servo: Option<f64>,
    /// Every executed line, in order.
    pub executed: Vec<Executed>,
    /// Every move, in order.
    pub moves: Vec<Move>,
    /// Counters.
    pub stats: MarlinStats,
    numbered_seen: u64,
    corrupted_once: bool,
}

impl MarlinCore {
    /// A board just booted.
    pub fn new(config: MarlinConfig) -> MarlinCore {
        MarlinCore {
            config,
            last_n: 0,
            pos: [0.0; 3],
            absolute: true,
            inches: false,
            servo: None,
            executed: Vec::new(),
            moves: Vec::new(),
            stats: MarlinStats::default(),
            numbered_seen: 0,
            corrupted_once: false,
        }
    }

    /// What the wire does to a line on its way in: `None` when it is lost.
    pub fn wire(&mut self, line: &str) -> Option<String> {
        let number = numbered(line);
        if number.is_some() {
            self.numbered_seen += 1;
            if let Some(k) = self.config.drop_every.filter(|k| *k > 0) {
                if self.numbered_seen.is_multiple_of(k as u64) {
                    self.stats.dropped += 1;
                    return None;
                }
            }
        }
        if !self.corrupted_once && number.is_some() && number == self.config.corrupt_line {
            // One bit of the byte before '*' flips, as line noise would.
            if let Some(star) = line.rfind('*').filter(|s| *s > 0) {
                self.corrupted_once = true;
                self.stats.corrupted += 1;
                let mut b = line.as_bytes().to_vec();
                b[star - 1] ^= 0x02;
                return Some(String::from_utf8_lossy(&b).into_owned());
            }
        }
        Some(line.to_string())
    }

    /// One line as the reader gets it (without its line end).
    pub fn receive(&mut self, raw: &str) -> Option<Action> {
        // process_stream_char: ';' starts a comment; an overlong line is cut.
        let mut line = match raw.find(';') {
            Some(i) => &raw[..i],
            None => raw,
        };
        if line.len() > MAX_CMD_SIZE - 1 {
            line = &line[..MAX_CMD_SIZE - 1];
        }
        let command = line.trim_start_matches(' ');
        if command.is_empty() {
            return None;
        }
        self.stats.lines_received += 1;
        let mut n = None;
        let mut body = command;
        if let Some(after_letter) = command.strip_prefix('N') {
            let is_m110 = command.contains("M110");
            let npos = match command.get(4..).and_then(|t| t.find('N')) {
                Some(i) if is_m110 => i + 4,
                _ => 0,
            };
            let gcode_n = leading_number(&command[npos + 1..]);
            if gcode_n != self.last_n + 1 && !is_m110 {
                self.stats.line_number_errors += 1;
                return Some(self.refuse("Line Number is not Last Line Number+1"));
            }
            let Some(star) = command.rfind('*') else {
                self.stats.checksum_errors += 1;
                return Some(self.refuse("No Checksum with line number"));
            };
            let sum = command.as_bytes()[..star].iter().fold(0u8, |a, b| a ^ b);
            if leading_number(&command[star + 1..]) != sum as i64 {
                self.stats.checksum_errors += 1;
                return Some(self.refuse("checksum mismatch"));
            }
            self.last_n = gcode_n;
            n = Some(gcode_n as u32);
            // The parser skips the N word; the checksum ends the command.
            let after_n = after_letter.trim_start_matches(|c: char| c.is_ascii_digit() || c == '-');
            body = after_n[..after_n.rfind('*').unwrap_or(after_n.len())].trim();
        }
        Some(self.execute(n, body.trim()))
    }

    fn refuse(&self, why: &str) -> Action {
        Action::Refused(vec![
            format!("Error:{why}, Last Line: {}", self.last_n),
            format!("Resend: {}", self.last_n + 1),
            "ok".into(),
        ])
    }

    fn execute(&mut self, n: Option<u32>, command: &str) -> Action {
        self.executed.push(Executed {
            n,
            command: command.to_string(),
        });
        self.stats.lines_executed += 1;
        let ok = || vec!["ok".to_string()];
        let words = clean_line(command)
            .ok()
            .and_then(|c| line_words(&c).ok())
            .unwrap_or_default();
        let value = |letter: char| {
            words
                .iter()
                .skip(1)
                .find(|(c, _)| *c == letter)
                .map(|w| w.1)
        };
        let scale = if self.inches { 25.4 } else { 1.0 };
        // The X, Y, Z words, in mm.
        let axes = ['X', 'Y', 'Z'].map(|letter| value(letter).map(|v| v * scale));
        match marlin_code(command) {
            Some(('G', 0 | 1)) => {
                let from = self.pos;
                for (a, v) in axes.iter().enumerate() {
                    if let Some(v) = v {
                        self.pos[a] = if self.absolute { *v } else { self.pos[a] + v };
                    }
                }
                self.moved(from);
                Action::Reply(ok())
            }
            Some(('G', 4)) => Action::Reply(ok()),
            Some(('G', g @ (20 | 21))) => {
                self.inches = g == 20;
                Action::Reply(ok())
            }
            Some(('G', 28)) => {
                let from = self.pos;
                self.pos = self.config.home;
                self.moved(from);
                Action::Busy {
                    ms: self.config.busy_ms,
                    then: ok(),
                }
            }
            Some(('G', g @ (90 | 91))) => {
                self.absolute = g == 90;
                Action::Reply(ok())
            }
            Some(('G', 92)) => {
                for (a, v) in axes.iter().enumerate() {
                    if let Some(v) = v {
                        self.pos[a] = *v;
                    }
                }
                Action::Reply(ok())
            }
            Some(('M', 0 | 1)) => {
                let text = command[2..].trim_start_matches(|c: char| c.is_ascii_digit()).trim();
                Action::WaitForUser(text.to_string())
            }
            Some(('M', 110)) => {
                if let Some(v) = value('N') {
                    self.last_n = v as i64;
                }
                Action::Reply(ok())
            }
            Some(('M', 112)) => Action::Kill("Error:Printer halted. kill() called!".into()),
            Some(('M', 114)) => Action::Reply(vec![
                format!(
                    "X:{:.2} Y:{:.2} Z:{:.2} E:0.00 Count X:{} Y:{} Z:{}",
                    self.pos[0],
                    self.pos[1],
                    self.pos[2],
                    (self.pos[0] * 80.0).round(),
                    (self.pos[1] * 80.0).round(),
                    (self.pos[2] * 400.0).round()
                ),
                "ok".into(),
            ]),
            Some(('M', 115)) => Action::Reply(vec![
                "FIRMWARE_NAME:Marlin 2.1.2 (Oficina emulator) SOURCE_CODE_URL:github.com/MarlinFirmware/Marlin PROTOCOL_VERSION:1.0 MACHINE_TYPE:Makelangelo EXTRUDER_COUNT:0".into(),
                "ok".into(),
            ]),
            Some(('M', 280)) => {
                if value('P').unwrap_or(0.0) == 0.0 {
                    self.servo = value('S');
                }
                Action::Reply(ok())
            }
            Some(('M', 400)) => Action::Busy {
                ms: self.config.busy_ms,
                then: ok(),
            },
            Some(('M', 17 | 18 | 84 | 108 | 113 | 117 | 118 | 220 | 410)) => Action::Reply(ok()),
            _ => Action::Reply(vec![
                format!("echo:Unknown command: \"{command}\""),
                "ok".into(),
            ]),
        }
    }

    fn moved(&mut self, from: [f64; 3]) {
        self.moves.push(Move {
            from,
            to: self.pos,
            servo: self.servo,
        });
    }
}

/// The `N` of a line that starts with one.
fn numbered(line: &str) -> Option<u32> {
    let t = line.trim_start_matches(' ').strip_prefix('N')?;
    let digits: String = t.chars().take_while(|c| c.is_ascii_digit()).collect();
    digits.parse().ok()
}

/// C's `strtol`: an optional sign and the digits that follow; 0 without any.
fn leading_number(s: &str) -> i64 {
    let s = s.trim_start();
    let (sign, rest) = match s.strip_prefix('-') {
        Some(r) => (-1, r),
        None => (1, s.strip_prefix('+').unwrap_or(s)),
    };
    let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    sign * digits.parse::<i64>().unwrap_or(0)
}

/// The command of a line with its number and checksum taken off (for the emergency
/// parser, which acts on `M108`, `M112` and `M410` as the bytes arrive).
pub(crate) fn command_of(line: &str) -> &str {
    let t = line.trim_start_matches(' ');
    let t = match t.strip_prefix('N') {
        Some(r) => r.trim_start_matches(|c: char| c.is_ascii_digit()),
        None => t,
    };
    t[..t.find(['*', ';']).unwrap_or(t.len())].trim()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sum(s: &str) -> String {
        // Independent of the host's framing: Python's functools.reduce(xor, b'N1 G28').
        let c = s.bytes().fold(0, |a, b| a ^ b);
        format!("{s}*{c}")
    }

    #[test]
    fn reader_checks_number_then_checksum() {
        let mut m = MarlinCore::new(MarlinConfig::default());
        assert_eq!(
            m.receive(&sum("N1 G28")),
            Some(Action::Busy {
                ms: 0,
                then: vec!["ok".into()]
            })
        );
        // Out of sequence: refused by number even with a bad checksum.
        let Some(Action::Refused(r)) = m.receive("N3 G1 X1*0") else {
            panic!()
        };
        assert_eq!(
            r[0],
            "Error:Line Number is not Last Line Number+1, Last Line: 1"
        );
        assert_eq!(r[1], "Resend: 2");
        let Some(Action::Refused(r)) = m.receive("N2 G1 X1*0") else {
            panic!()
        };
        assert!(r[0].starts_with("Error:checksum mismatch"));
        let Some(Action::Refused(r)) = m.receive("N2 G1 X1") else {
            panic!()
        };
        assert!(r[0].starts_with("Error:No Checksum"));
        assert!(matches!(
            m.receive(&sum("N2 G1 X1 Y2")),
            Some(Action::Reply(_))
        ));
        assert_eq!(m.pos, [1.0, 2.0, 0.0]);
        // M110 resets the numbering; its own N is exempt from the sequence check.
        assert!(matches!(
            m.receive(&sum("N0 M110 N0")),
            Some(Action::Reply(_))
        ));
        assert!(matches!(
            m.receive(&sum("N1 G1 X3")),
            Some(Action::Reply(_))
        ));
        assert_eq!(command_of("N7 M108*12"), "M108");
    }
}
