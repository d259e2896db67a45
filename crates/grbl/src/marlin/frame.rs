//! Marlin's line protocol, both directions: the numbered, checksummed line a host sends
//! (`N<n> <command>*<checksum>`) and the replies Marlin 2.x prints (`ok`, `Resend: N`,
//! `echo:busy: …`, `Error:…`, the `M114` position).

/// Marlin's `MAX_CMD_SIZE`: a received line (number, command and checksum) longer than
/// this minus one byte is cut, so the checksum would be lost.
pub const MAX_CMD_SIZE: usize = 96;

/// XOR of every byte, as Marlin's `get_serial_commands` folds the bytes before `*`.
pub fn checksum(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, b| a ^ b)
}

/// `N<n> <command>*<checksum>`: the checksum covers `N<n> <command>`.
pub fn frame(n: u32, command: &str) -> String {
    let body = format!("N{n} {command}");
    let sum = checksum(body.as_bytes());
    format!("{body}*{sum}")
}

/// A line Marlin printed, classified.
#[derive(Clone, Debug, PartialEq)]
pub enum Reply {
    /// `ok` (with `ADVANCED_OK`'s `N.. P.. B..` after it, ignored): one received line done.
    Ok,
    /// `Resend: N` or `rs N`: send again from line `N`.
    Resend(u32),
    /// `echo:busy: processing` (a long command) or `echo:busy: paused for user` (`M0`);
    /// the text after `busy: `.
    Busy(String),
    /// `Error:…`: the text after `Error:`.
    Error(String),
    /// `start`: the firmware (re)booted.
    Start,
    /// An `M114` report `X:… Y:… Z:…` (mm).
    Position([f64; 3]),
    /// Anything else (`echo:` notes, the banner, `M115`'s `FIRMWARE_NAME:`).
    Other(String),
}

impl Reply {
    /// Classifies one line (without its line end).
    pub fn parse(line: &str) -> Reply {
        let t = line.trim();
        if t == "ok" || t.starts_with("ok ") {
            return Reply::Ok;
        }
        if let Some(n) = t
            .strip_prefix("Resend:")
            .or_else(|| t.strip_prefix("rs "))
            .and_then(|n| n.trim().parse().ok())
        {
            return Reply::Resend(n);
        }
        if let Some(b) = t
            .strip_prefix("echo:busy:")
            .or_else(|| t.strip_prefix("busy:"))
        {
            return Reply::Busy(b.trim().to_string());
        }
        if let Some(e) = t.strip_prefix("Error:").or_else(|| t.strip_prefix("!!")) {
            return Reply::Error(e.trim().to_string());
        }
        if t == "start" {
            return Reply::Start;
        }
        if let Some(p) = position(t) {
            return Reply::Position(p);
        }
        Reply::Other(t.to_string())
    }
}

/// `X:10.00 Y:20.00 Z:0.00 E:0.00 Count X:… Y:… Z:…`: the first X, Y and Z (the logical
/// position; the stepper counts follow `Count`).
fn position(t: &str) -> Option<[f64; 3]> {
    if !t.starts_with("X:") {
        return None;
    }
    let mut p = [None; 3];
    for word in t.split_whitespace() {
        if word == "Count" {
            break;
        }
        if let Some((k, v)) = word.split_once(':') {
            if let (Some(i), Ok(v)) = (["X", "Y", "Z"].iter().position(|a| *a == k), v.parse()) {
                p[i].get_or_insert(v);
            }
        }
    }
    Some([p[0]?, p[1]?, p[2]?])
}

/// The command of a Marlin line as Marlin's reader keeps it: the text before a `;`
/// comment, trimmed.
pub fn strip_comment(line: &str) -> &str {
    match line.find(';') {
        Some(i) => &line[..i],
        None => line,
    }
    .trim()
}

/// The G or M code a command starts with (`('M', 280)`), if any.
pub fn code_of(command: &str) -> Option<(char, u32)> {
    let mut chars = command.trim_start().chars();
    let letter = chars.next()?.to_ascii_uppercase();
    if letter != 'G' && letter != 'M' {
        return None;
    }
    let digits: String = chars.take_while(|c| c.is_ascii_digit()).collect();
    Some((letter, digits.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replies_classify() {
        assert_eq!(Reply::parse("ok"), Reply::Ok);
        assert_eq!(Reply::parse("ok N12 P15 B3"), Reply::Ok);
        assert_eq!(Reply::parse("Resend: 7"), Reply::Resend(7));
        assert_eq!(Reply::parse("rs 7"), Reply::Resend(7));
        assert_eq!(
            Reply::parse("echo:busy: paused for user"),
            Reply::Busy("paused for user".into())
        );
        assert!(
            matches!(Reply::parse("Error:checksum mismatch, Last Line: 3"), Reply::Error(e) if e.starts_with("checksum"))
        );
        assert_eq!(
            Reply::parse("X:10.00 Y:-2.50 Z:0.00 E:0.00 Count X:800 Y:-200 Z:0"),
            Reply::Position([10.0, -2.5, 0.0])
        );
        assert_eq!(Reply::parse("start"), Reply::Start);
        assert_eq!(code_of("M280 P0 S90"), Some(('M', 280)));
        assert_eq!(code_of("X1"), None);
        assert_eq!(strip_comment("G1 X1 ; to x"), "G1 X1");
    }
}
