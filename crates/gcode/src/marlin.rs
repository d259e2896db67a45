//! Marlin 2.x, as pen plotters and lasers running it read G-code (Makelangelo polargraphs):
//! each line is rewritten into the LinuxCNC line that means the same, and the common
//! interpreter runs that.
//!
//! Marlin's serial reader and `GcodeSuite::process_parsed_command` decide what a line is:
//! - `;` starts a comment; `N… … *NN` carries a line number and the XOR checksum of the bytes
//!   before `*` (checked here: a mismatch is an error naming the line).
//! - One command per line: the first G or M word; later G/M words are ignored (a warning).
//! - `M0`/`M1 <text>`, `M117 <text>`, `M118 <text>`: the rest of the line is a message.
//! - `G4 P` is milliseconds (`G4 S` seconds) — LinuxCNC's P is seconds.
//! - `G28 [X] [Y] [Z]` homes the named axes (all without one; values are ignored): a rapid straight to
//!   the stored home (#5161…, the profile's, else machine 0) of those axes.
//! - `M280 P<servo> S<angle> [T<ms>]` moves a servo, the pen lift: the first angle of the
//!   program is taken as pen up (Makelangelo programs start with the pen up), every other angle
//!   as pen down. Pen down is read as `M3 S<angle>` and pen up as `M5`, as the plotter's grbl
//!   servo lift is (what the planner and preview know); `T` (Makelangelo's servo time) is a
//!   dwell of that many milliseconds.
//! - `M17`/`M18`/`M84` (motors), `M106`/`M107` (fan), `M400` (wait): no motion, a note.
//! - `E` words (extruder) on a plotter: ignored, with a note the first time.
//! - Parameters `#`, expressions `[…]`, o-words, and the G codes Marlin lacks (cutter
//!   compensation, tool length, canned cycles, work offsets …): errors with a hint.

use crate::diag::{Diagnostic, Span};
use std::fmt::Write as _;
use std::io::Write as _;

/// What the rewriting remembers from line to line.
#[derive(Debug, Default)]
pub(crate) struct MarlinState {
    /// The servo angle read as pen up (the first M280's).
    servo_up: Option<f64>,
    /// G91 is in force (G28 names its intermediate point by it).
    incremental: bool,
    /// G20 is in force (#5161… are millimetres).
    inches: bool,
    /// An E word was noted already.
    e_noted: bool,
}

/// A word of a Marlin line: letter, value (if it parses) and 1-based column.
struct Word {
    letter: char,
    value: Option<f64>,
    col: u32,
}

fn words(s: &str, col0: u32) -> Vec<Word> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'(' {
            // A parenthesised comment (PAREN_COMMENTS): skipped.
            while i < b.len() && b[i] != b')' {
                i += 1;
            }
            i += 1;
            continue;
        }
        if !c.is_ascii_alphabetic() {
            i += 1;
            continue;
        }
        let col = col0 + i as u32;
        i += 1;
        while i < b.len() && b[i] == b' ' {
            i += 1;
        }
        let start = i;
        while i < b.len() && (b[i].is_ascii_digit() || b"+-.".contains(&b[i])) {
            i += 1;
        }
        out.push(Word {
            letter: c.to_ascii_uppercase() as char,
            value: s[start..i].parse().ok(),
            col,
        });
    }
    out
}

fn get(ws: &[Word], l: char) -> Option<f64> {
    ws.iter().find(|w| w.letter == l).and_then(|w| w.value)
}

fn num(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

fn marlin_error(line: u32, col: u32, len: u32, msg: String, hint: &str) -> Diagnostic {
    Diagnostic::error(Span::new(line, col, len), msg).with_help(hint)
}

/// A message made safe inside a LinuxCNC comment.
fn comment_text(s: &str) -> String {
    s.trim().replace('(', "[").replace(')', "]")
}

/// Rewrite Marlin line `raw` (line `line`) into `out`, the LinuxCNC line with its meaning;
/// `notes` gets notes and warnings for what Marlin does without motion.
pub(crate) fn rewrite(
    raw: &[u8],
    line: u32,
    st: &mut MarlinState,
    out: &mut Vec<u8>,
    notes: &mut Vec<Diagnostic>,
) -> Result<(), Diagnostic> {
    out.clear();
    let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
    let text = String::from_utf8_lossy(raw);
    // Marlin's reader stops at ';' (the checksum covers the bytes before '*' only).
    let code = match text.find(';') {
        Some(i) => &text[..i],
        None => &text[..],
    };
    let code = match code.find('*') {
        Some(star) => {
            let digits = code[star + 1..].trim();
            let given: Option<u8> = digits.parse().ok();
            let sum = code.as_bytes()[..star].iter().fold(0u8, |a, b| a ^ b);
            let col = star as u32 + 1;
            if !code.trim_start().starts_with(['N', 'n']) {
                return Err(marlin_error(
                    line,
                    col,
                    1,
                    format!("line {line}: a checksum without a line number"),
                    "Marlin answers \"No Line Number with checksum\": write N<number> before the command",
                ));
            }
            match given {
                Some(g) if g == sum => {}
                Some(g) => {
                    return Err(marlin_error(
                        line,
                        col,
                        digits.len() as u32 + 1,
                        format!(
                            "checksum mismatch on line {line}: the line says *{g}, its bytes give *{sum}"
                        ),
                        "Marlin refuses the line and asks for it again (Resend); the line was changed after its checksum was written",
                    ))
                }
                None => {
                    return Err(marlin_error(
                        line,
                        col,
                        1,
                        format!("line {line}: '*' without a checksum number"),
                        "a checksum is '*' and the XOR of the bytes before it, 0 to 255",
                    ))
                }
            }
            &code[..star]
        }
        None => code,
    };
    let lead = code.len() - code.trim_start().len();
    let mut body = code.trim_start();
    let mut col0 = lead as u32 + 1;
    let mut number = String::new();
    // N<number>
    if body.starts_with(['N', 'n']) {
        let digits = body[1..]
            .find(|c: char| !(c.is_ascii_digit() || c == ' '))
            .map_or(body.len(), |i| i + 1);
        number = format!("N{} ", body[1..digits].trim());
        let rest = &body[digits..];
        let skipped = body.len() - rest.trim_start().len();
        col0 += skipped as u32;
        body = rest.trim_start();
    }
    let body = body.trim_end();
    if body.is_empty() {
        // A comment line: kept as a comment so it is read as one.
        if let Some(i) = text.find(';') {
            let c = comment_text(&text[i + 1..]);
            if !c.is_empty() {
                let _ = write!(out, "{number}({c})");
            }
        }
        return Ok(());
    }
    let b = body.as_bytes();
    if !b[0].is_ascii() {
        return Err(marlin_error(
            line,
            col0,
            1,
            format!("'{body}' has no G or M command; Marlin needs one on every line"),
            "a Marlin line is a command (G… or M…) and its words",
        ));
    }
    let letter = b[0].to_ascii_uppercase();
    let digits_end = body[1..]
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .map_or(body.len(), |i| i + 1);
    let cmd_len = digits_end as u32;
    let code_num: Option<f64> = body[1..digits_end].parse().ok();
    let rest = &body[digits_end..];
    let rest_col = col0 + digits_end as u32;
    if body.starts_with('(') {
        // A parenthesised comment alone on its line.
        let _ = write!(out, "{number}{body}");
        return Ok(());
    }
    if letter == b'O' {
        return Err(marlin_error(
            line,
            col0,
            1,
            "o-words (subroutines, loops, conditions) are not Marlin's".into(),
            "Marlin runs one command per line with plain numbers: expand the program in the CAM or the post",
        ));
    }
    if letter.is_ascii_alphabetic() && !matches!(letter, b'G' | b'M' | b'T') {
        // GcodeSuite::process_parsed_command: "Unknown command", and the line is dropped.
        notes.push(
            Diagnostic::warning(
                Span::new(line, col0, body.len() as u32),
                format!("'{body}' has no G or M command: Marlin answers \"Unknown command\" and ignores the line"),
            )
            .with_help(if letter == b'F' {
                "a feed alone on its line sets nothing on Marlin: put the F on the G0/G1 line"
            } else {
                "Marlin does not repeat the last motion for a line of coordinates alone: write G1 (or G0) before them"
            }),
        );
        return Ok(());
    }
    let (Some(n), b'G' | b'M') = (code_num, letter) else {
        if letter == b'T' {
            return Err(marlin_error(
                line,
                col0,
                cmd_len,
                format!("{body} is not a Marlin command for this machine"),
                "Marlin's T selects an extruder: for a pen change use M0 with a message",
            ));
        }
        return Err(marlin_error(
            line,
            col0,
            1,
            format!("'{body}' has no G or M command; Marlin needs one on every line"),
            "Marlin does not repeat the last motion for a line of coordinates alone: write G1 (or G0) before them",
        ));
    };
    let name = format!("{}{}", letter as char, num(n));
    // The message commands: the rest of the line is text, not words.
    if letter == b'M' && matches!(n as u32, 0 | 1 | 117 | 118) && n.fract() == 0.0 {
        // `M0 (MSG, text)`, as a post for LinuxCNC writes it: Marlin shows it all; the text
        // is what matters.
        let bare = rest.trim();
        let bare = bare
            .strip_prefix('(')
            .and_then(|b| b.strip_suffix(')'))
            .map(|b| b.trim_start())
            .and_then(|b| {
                b.get(..4)
                    .filter(|m| m.eq_ignore_ascii_case("msg,"))
                    .map(|_| &b[4..])
            })
            .unwrap_or(bare);
        let msg = comment_text(bare);
        match n as u32 {
            0 | 1 => {
                let _ = write!(out, "{number}{name}");
                if !msg.is_empty() {
                    let _ = write!(out, " (MSG,{msg})");
                    notes.push(Diagnostic::note(
                        Span::line(line),
                        format!("{name} pause: {msg}"),
                    ));
                } else {
                    notes.push(Diagnostic::note(Span::line(line), format!("{name} pause")));
                }
            }
            _ => {
                if !msg.is_empty() {
                    let _ = write!(out, "{number}(MSG,{msg})");
                }
            }
        }
        return Ok(());
    }
    // What no Marlin line may hold.
    for (i, c) in rest.char_indices() {
        let col = rest_col + i as u32;
        match c {
            '#' => {
                return Err(marlin_error(
                    line,
                    col,
                    1,
                    "parameters ('#') are not Marlin's".into(),
                    "Marlin reads plain numbers only: have the post write the values (a LinuxCNC post writes parameters)",
                ))
            }
            '[' => {
                return Err(marlin_error(
                    line,
                    col,
                    1,
                    "expressions ('[…]') are not Marlin's".into(),
                    "Marlin reads plain numbers only: have the post write the values",
                ))
            }
            '(' => break,
            _ => {}
        }
    }
    let mut ws = words(rest, rest_col);
    // Marlin runs the first command only: later G/M words are parameters it ignores.
    let extra: Vec<&Word> = ws
        .iter()
        .filter(|w| matches!(w.letter, 'G' | 'M'))
        .collect();
    if let Some(first) = extra.first() {
        let names: Vec<String> = extra
            .iter()
            .map(|w| format!("{}{}", w.letter, w.value.map_or(String::new(), num)))
            .collect();
        notes.push(
            Diagnostic::warning(
                Span::new(line, first.col, 1),
                format!(
                    "Marlin runs one command per line: {name} runs, {} on the same line {} ignored",
                    names.join(" "),
                    if names.len() == 1 { "is" } else { "are" }
                ),
            )
            .with_help("put each G or M command on a line of its own"),
        );
    }
    ws.retain(|w| !matches!(w.letter, 'G' | 'M'));
    let mut e_note = |st: &mut MarlinState| {
        if ws.iter().any(|w| w.letter == 'E') && !st.e_noted {
            st.e_noted = true;
            notes.push(Diagnostic::note(
                Span::line(line),
                "E words (the extruder) are ignored: a plotter has none",
            ));
        }
    };
    // The words passed through, E left out.
    let plain = |ws: &[Word]| -> String {
        let mut s = String::new();
        for w in ws.iter().filter(|w| w.letter != 'E') {
            let _ = write!(s, " {}{}", w.letter, w.value.map_or(String::new(), num));
        }
        s
    };
    let tenths = (n * 10.0).round() as u32;
    let note = |notes: &mut Vec<Diagnostic>, t: &str| {
        notes.push(Diagnostic::note(Span::line(line), format!("{name}: {t}")));
    };
    match (letter, tenths) {
        (b'G', 0 | 10 | 20 | 30 | 920) => {
            e_note(st);
            let _ = write!(out, "{number}{name}{}", plain(&ws));
        }
        (b'G', 200 | 210) => {
            st.inches = tenths == 200;
            let _ = write!(out, "{number}{name}");
        }
        (b'G', 170 | 180 | 190) => {
            let _ = write!(out, "{number}{name}");
        }
        (b'G', 900) => {
            st.incremental = false;
            let _ = write!(out, "{number}G90");
        }
        (b'G', 910) => {
            st.incremental = true;
            let _ = write!(out, "{number}G91");
        }
        (b'G', 40) => {
            // P milliseconds, S seconds.
            let secs = match (get(&ws, 'P'), get(&ws, 'S')) {
                (Some(ms), _) => ms / 1000.0,
                (None, Some(s)) => s,
                (None, None) => 0.0,
            };
            let _ = write!(out, "{number}G4 P{}", num(secs));
        }
        (b'G', 280) => {
            let named: Vec<char> = ws
                .iter()
                .map(|w| w.letter)
                .filter(|l| matches!(l, 'X' | 'Y' | 'Z'))
                .collect();
            let axes: &[char] = if named.is_empty() {
                &['X', 'Y', 'Z']
            } else {
                &named
            };
            // A rapid straight to the stored home in machine coordinates. LinuxCNC refuses
            // G53 under G91: there `G28 X0` (through the current point, then home) is the
            // same move.
            if st.incremental {
                let _ = write!(out, "{number}G28");
                for a in axes {
                    let _ = write!(out, " {a}0");
                }
            } else {
                let _ = write!(out, "{number}G53 G0");
                for a in axes {
                    let i = match a {
                        'X' => 1,
                        'Y' => 2,
                        _ => 3,
                    };
                    if st.inches {
                        let _ = write!(out, " {a}[#{}/25.4]", 5160 + i);
                    } else {
                        let _ = write!(out, " {a}#{}", 5160 + i);
                    }
                }
            }
        }
        (b'M', 30 | 40 | 50) => {
            // Marlin's laser/spindle: S power (or O 0–255), I inline mode: S passes.
            let mut s = format!("{number}{name}");
            if let Some(v) = get(&ws, 'S') {
                let _ = write!(s, " S{}", num(v));
            } else if let Some(o) = get(&ws, 'O') {
                let _ = write!(s, " S{}", num(o));
            }
            if ws.iter().any(|w| w.letter == 'I') {
                note(notes, "inline laser mode (I): power follows each move");
            }
            out.extend_from_slice(s.as_bytes());
        }
        (b'M', 170) => note(notes, "motors on (no motion)"),
        (b'M', 180 | 840) => note(notes, "motors off (no motion)"),
        (b'M', 1060) => note(notes, "fan on (no motion)"),
        (b'M', 1070) => note(notes, "fan off (no motion)"),
        (b'M', 4000) => note(notes, "waits for the moves to finish"),
        (b'M', 820 | 830) => note(notes, "extruder mode (no effect on a plotter)"),
        (b'M', 2800) => {
            let servo = get(&ws, 'P').unwrap_or(0.0);
            let Some(angle) = get(&ws, 'S') else {
                // M280 P0 alone reports the angle.
                note(notes, "reports the servo's angle");
                return Ok(());
            };
            let up = *st.servo_up.get_or_insert_with(|| {
                notes.push(Diagnostic::note(
                    Span::line(line),
                    format!(
                        "M280 P{} S{}: the first servo angle is read as pen up, other angles as pen down",
                        num(servo),
                        num(angle)
                    ),
                ));
                angle
            });
            if angle == up {
                let _ = write!(out, "{number}M5");
            } else {
                let _ = write!(out, "{number}M3 S{}", num(angle));
            }
            if let Some(t) = get(&ws, 'T').filter(|t| *t > 0.0) {
                let _ = write!(out, " G4 P{}", num(t / 1000.0));
            }
        }
        (b'M', 20 | 300) => {
            // GcodeSuite: "Unknown command" (M30 deletes an SD file when it names one).
            notes.push(
                Diagnostic::warning(
                    Span::new(line, col0, cmd_len),
                    format!("{name}: Marlin has no program end; it answers \"Unknown command\" and ignores the line"),
                )
                .with_help(if tenths == 300 {
                    "Marlin's M30 deletes a file on the SD card: remove it; the program ends with the file"
                } else {
                    "remove it: the program ends with the file"
                }),
            );
        }
        _ => {
            let hint = match (letter, tenths) {
                (b'G', 400..=429) => "Marlin has no cutter radius compensation: let the CAM offset the path",
                (b'G', 430..=499) => "Marlin has no tool length offsets (a LinuxCNC or Fanuc post): remove it",
                (b'G', 730..=890) => "Marlin has no canned cycles: have the post expand them into G0/G1 moves",
                (b'G', 530..=593) => "work offsets need Marlin's CNC_COORDINATE_SYSTEMS, which plotter builds leave out: use G92",
                (b'G', 50..=53) => "Marlin's G5 is a Bézier, not LinuxCNC's spline: have the CAM write arcs and lines",
                (b'M', 60) => "Marlin's tool change is an extruder's: use M0 with a message for a pen change",
                _ => "Marlin answers \"Unknown command\" and goes on; a plotter program needs G0 G1 G2 G3 G4 G28 G90 G91 G92, M0 M3 M5 M280",
            };
            return Err(marlin_error(
                line,
                col0,
                cmd_len,
                format!("{name} is not a Marlin command for this machine"),
                hint,
            ));
        }
    }
    Ok(())
}
