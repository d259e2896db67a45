//! What a program says about itself in its opening comments: `(machine: hotwire-xy)` names
//! the machine profile it was written for, so a command run without `--machine` can use it.

use std::io::BufRead;

/// How far the opening comments are looked at: a header is short.
const HEADER_BYTES: u64 = 64 * 1024;

/// The machine a program asks for, and the line that asks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MachineHint {
    /// The machine's name as the program writes it.
    pub name: String,
    /// The line that names it.
    pub line: u32,
}

/// The `(machine: NAME)` (or `; machine: NAME`) comment among the lines before the first
/// line with code; the key is read in any case, the name is trimmed.
pub fn machine_hint(source: impl BufRead) -> Option<MachineHint> {
    for (index, line) in std::io::Read::take(source, HEADER_BYTES)
        .split(b'\n')
        .enumerate()
    {
        let line = line.ok()?;
        let number = u32::try_from(index + 1).ok()?;
        let text = crate::text::decode(&line);
        let text = text.trim();
        if text.is_empty() || text == "%" {
            continue;
        }
        let body = if let Some(rest) = text.strip_prefix(';') {
            rest
        } else if let Some(rest) = text.strip_prefix('(') {
            match rest.strip_suffix(')') {
                Some(body) if !body.contains(['(', ')']) => body,
                _ => return None,
            }
        } else {
            return None;
        };
        if let Some((key, value)) = body.split_once(':') {
            let name = value.trim();
            if key.trim().eq_ignore_ascii_case("machine") && !name.is_empty() {
                return Some(MachineHint {
                    name: name.to_string(),
                    line: number,
                });
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hint(s: &str) -> Option<(String, u32)> {
        machine_hint(s.as_bytes()).map(|h| (h.name, h.line))
    }

    #[test]
    fn the_opening_comments_name_the_machine() {
        assert_eq!(
            hint("(a pinwheel)\n\n( Machine : hotwire-xy )\nG1 X1\n"),
            Some(("hotwire-xy".into(), 3))
        );
        assert_eq!(
            hint("%\n;machine: polar-plotter\nM2\n"),
            Some(("polar-plotter".into(), 2))
        );
    }

    #[test]
    fn only_before_the_first_code_and_only_whole_comments() {
        assert_eq!(hint("G21\n(machine: hotwire-xy)\n"), None);
        assert_eq!(hint("(machine: hotwire-xy) G21\n"), None);
        assert_eq!(hint("(machine:)\nM2\n"), None);
        assert_eq!(hint("(tool: 3 mm)\nM2\n"), None);
        assert_eq!(hint(""), None);
    }
}
