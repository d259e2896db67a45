//! Fuzzing the Marlin program reader with proptest: lines of Marlin-ish text (commands,
//! comments, `%`, `*`, long runs, non-ASCII). Asserted for every input: no panic; a result
//! is either an error naming the file and a line of it, or lines that each fit Marlin's
//! line buffer once numbered and checksummed, hold no `*`, and point at a line of the file.
//!
//! Cases: `PROPTEST_CASES` (default 256).

use oficina_grbl::{marlin_frame, marlin_program, MARLIN_MAX_CMD_SIZE};
use proptest::prelude::*;

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        "(G[0-9]{1,2}|M[0-9]{1,3})( [XYZFSP]-?[0-9]{1,6}(\\.[0-9]{1,4})?){0,4}( ;[ -~]{0,20})?",
        "M117 [ -~]{0,120}",
        "[ -~]{0,200}",
        "\\PC{0,40}",
        Just("%".to_string()),
        Just(String::new()),
    ]
}

proptest! {
    #[test]
    fn a_program_is_read_or_refused_at_a_line(lines in prop::collection::vec(line(), 0..40)) {
        let text = lines.join("\n");
        let count = text.lines().count();
        match marlin_program("fuzz.gcode", &text) {
            Err(e) => prop_assert!(e.starts_with("fuzz.gcode:"), "{e}"),
            Ok(p) => {
                for l in &p.lines {
                    prop_assert!(l.file_line >= 1 && l.file_line <= count);
                    prop_assert!(!l.text.contains('*'), "{:?}", l.text);
                    // The longest line number the link sends is 7 digits.
                    let framed = marlin_frame(9_999_999, &l.text);
                    prop_assert!(framed.len() < MARLIN_MAX_CMD_SIZE, "{framed:?}");
                }
            }
        }
    }
}
