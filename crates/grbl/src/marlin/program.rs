//! A Marlin program ready to stream: each command as Marlin's reader keeps it (comment
//! dropped, trimmed; spaces and case kept, since `M117`/`M0` texts are printed as written),
//! tied to its file line. Its timing and path model is the same program in grbl's dialect
//! ([`model`]), line for line, so the grbl ETA and resume code read it.

use super::frame::{code_of, strip_comment, MAX_CMD_SIZE};
use crate::job::{StreamLine, StreamProgram};

/// `N<n> ` and `*<sum>` around a command: a line number up to 7 digits, a checksum up to 3.
const FRAME_BYTES: usize = "N1234567 *255".len();

/// Reads a Marlin program. A command too long for Marlin's line buffer once numbered is
/// an error naming the file line.
pub fn marlin_program(name: &str, text: &str) -> Result<StreamProgram, String> {
    let mut lines = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let cmd = strip_comment(raw);
        if cmd.is_empty() || cmd == "%" {
            continue;
        }
        if cmd.len() + FRAME_BYTES > MAX_CMD_SIZE - 1 {
            return Err(format!(
                "{name}:{}: command is {} bytes; with its line number and checksum it does not fit Marlin's {}-byte line buffer (MAX_CMD_SIZE)",
                i + 1,
                cmd.len(),
                MAX_CMD_SIZE
            ));
        }
        if cmd.contains('*') {
            return Err(format!(
                "{name}:{}: '*' starts the checksum on a Marlin line: it cannot be part of the command",
                i + 1
            ));
        }
        lines.push(StreamLine {
            file_line: i + 1,
            text: cmd.to_string(),
        });
    }
    Ok(StreamProgram {
        name: name.to_string(),
        lines,
        tool_change: Default::default(),
        tool_stops: Vec::new(),
    })
}

/// The program in grbl's dialect, line for line (same indices), for the motion model only:
/// `G0` is a feed move at the modal feed (Marlin has no separate rapid rate), `G4 P` is
/// milliseconds (grbl's P is seconds), `G28` goes to 0,0,0, and every other M code is a
/// no-op (an empty line).
pub(crate) fn model(program: &StreamProgram) -> StreamProgram {
    let lines = program
        .lines
        .iter()
        .map(|l| StreamLine {
            file_line: l.file_line,
            text: model_line(&l.text),
        })
        .collect();
    StreamProgram {
        lines,
        ..program.clone()
    }
}

fn model_line(cmd: &str) -> String {
    let Ok(clean) = crate::gline::clean(cmd) else {
        return String::new();
    };
    match code_of(&clean) {
        Some(('G', 0)) => clean.replacen("G0", "G1", 1),
        Some(('G', 4)) => {
            let secs = crate::gline::words(&clean)
                .unwrap_or_default()
                .iter()
                .find_map(|(c, v)| match c {
                    'P' => Some(v / 1000.0),
                    'S' => Some(*v),
                    _ => None,
                })
                .unwrap_or(0.0);
            format!("G4P{secs}")
        }
        Some(('G', 28)) => "G1X0Y0Z0".into(),
        Some(('G', 1 | 2 | 3 | 20 | 21 | 90 | 91 | 92)) => clean,
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_and_models() {
        let p = marlin_program(
            "p.gcode",
            "; head\nG28\nM280 P0 S90 ; up\nG4 P150\nG0 X10 Y5 F3000\nM0 Pen 2: red\n",
        )
        .unwrap();
        let texts: Vec<&str> = p.lines.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(
            texts,
            [
                "G28",
                "M280 P0 S90",
                "G4 P150",
                "G0 X10 Y5 F3000",
                "M0 Pen 2: red"
            ]
        );
        assert_eq!(p.lines[0].file_line, 2);
        let m = model(&p);
        let texts: Vec<&str> = m.lines.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(texts, ["G1X0Y0Z0", "", "G4P0.15", "G1X10Y5F3000", ""]);
        let long = format!("M117 {}", "x".repeat(90));
        assert!(marlin_program("q", &format!("G28\n{long}\n"))
            .unwrap_err()
            .starts_with("q:2:"));
        assert!(marlin_program("q", "M117 a*b\n")
            .unwrap_err()
            .contains("'*'"));
    }
}
