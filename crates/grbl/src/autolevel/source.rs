//! What a source line says beyond its canonical operations: the words that change the work
//! frame (refused), the moves in machine coordinates (passed through as written), the axes
//! it names (so a move from an unknown position sends only what the program gave).

use crate::gline;

/// How the levelled program treats one source line.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct LineInfo {
    /// The cleaned text, for lines passed through as written.
    pub(super) clean: String,
    /// G53, G28 or G30: moves in machine coordinates, sent as written; afterwards the
    /// work position of the axes they move is unknown.
    pub(super) machine_move: bool,
    /// G28 / G30 (all axes end unknown) rather than G53 (the named ones).
    pub(super) goes_home: bool,
    /// X, Y, Z words on the line.
    pub(super) names: [bool; 3],
    /// The distance mode after the line: G91 (true) or G90.
    pub(super) incremental: bool,
    /// M2 / M30: the interpreter's resets that come with it are grbl's own at program end.
    pub(super) ends_program: bool,
}

/// Reads `text` (source line `line`, 1-based), `incremental` being the distance mode before
/// it. Words that would move the work frame under the map are an error naming the line.
pub(super) fn classify(text: &str, line: u32, incremental: bool) -> Result<LineInfo, String> {
    let at = |what: String| format!("line {line}: {what}");
    let clean = gline::clean(text).map_err(|_| {
        at(format!(
            "longer than grbl's {}-character line buffer",
            gline::MAX_LINE
        ))
    })?;
    let mut info = LineInfo {
        incremental,
        ..LineInfo::default()
    };
    let words = gline::words(&clean).unwrap_or_default();
    for &(letter, value) in &words {
        match letter {
            'X' => info.names[0] = true,
            'Y' => info.names[1] = true,
            'Z' => info.names[2] = true,
            'M' if value == 2.0 || value == 30.0 => info.ends_program = true,
            'G' => {
                // G-numbers in tenths: 92.1 → 921.
                match (value * 10.0).round() as i64 {
                    900 => info.incremental = false,
                    910 => info.incremental = true,
                    530 => info.machine_move = true,
                    280 | 300 => {
                        info.machine_move = true;
                        info.goes_home = true;
                    }
                    100 => return Err(at("G10 changes a work offset: levelling needs the work frame the map was probed in; set offsets before probing, not in the program".into())),
                    920..=923 => return Err(at("G92 moves the work frame away from the one the map was probed in: remove it (set work zero before probing)".into())),
                    431 => return Err(at("G43.1 changes the tool length offset under the map: set it before probing, not in the program".into())),
                    380..=389 => return Err(at("probing (G38) inside a program cannot be levelled".into())),
                    930 => return Err(at("G93 inverse time: splitting a move would change its duration; post the program in G94 (units per minute)".into())),
                    _ => {}
                }
            }
            _ => {}
        }
    }
    info.clean = clean;
    Ok(info)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_classified_and_frame_changes_refused() {
        let i = classify("G0 G53 Z-1 (up)", 4, false).unwrap();
        assert!(i.machine_move && !i.goes_home);
        assert_eq!(i.names, [false, false, true]);
        assert_eq!(i.clean, "G0G53Z-1");
        let i = classify("G91 G28 X0", 5, false).unwrap();
        assert!(i.goes_home && i.incremental);
        assert!(!classify("G90", 6, true).unwrap().incremental);
        assert!(classify("m30", 7, false).unwrap().ends_program);
        for (text, says) in [
            ("G92 X0", "G92"),
            ("G92.1", "G92"),
            ("G10 L20 P1 Z0", "G10"),
            ("G43.1 Z2", "G43.1"),
            ("G38.2 Z-5 F50", "G38"),
            ("G93 G1 X1 F2", "G93"),
        ] {
            let e = classify(text, 9, false).unwrap_err();
            assert!(e.starts_with("line 9: ") && e.contains(says), "{e}");
        }
    }
}
