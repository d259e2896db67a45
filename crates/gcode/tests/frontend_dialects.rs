//! The front end in each dialect, through the executor: grbl 1.1's lexical rules and error
//! numbers (from grbl's protocol.c / gcode.c / report.c: 1 expected command letter, 2 bad
//! number format, 4 negative value, 11 line overflow, 20 unsupported command, 25 repeated
//! word, 27 invalid line number), and the 2006 legacy dialect read as LinuxCNC reads it.

use oficina_gcode::Block;
use oficina_gcode::Executor;
use oficina_gcode::Params;
use oficina_gcode::{Diagnostic, Dialect};

fn run(text: &str, dialect: Dialect) -> Vec<Result<Block, Diagnostic>> {
    let mut exec = Executor::from_text(text, dialect);
    let mut params = Params::new();
    std::iter::from_fn(|| exec.next_block(&mut params))
        .take(10_000)
        .collect()
}

fn words(b: &Block) -> Vec<(char, f64)> {
    b.words.iter().map(|w| (w.letter, w.value)).collect()
}

#[test]
fn grbl_reads_plain_words_and_ignores_what_grbl_ignores() {
    let out = run(
        "g1x1y-2.5f100\n(comment) G0 X1 ; tail\n/G0 X3\n\nN5 G1 X1 0\n",
        Dialect::Grbl,
    );
    let blocks: Vec<&Block> = out.iter().map(|r| r.as_ref().unwrap()).collect();
    assert_eq!(
        words(blocks[0]),
        vec![('G', 1.0), ('X', 1.0), ('Y', -2.5), ('F', 100.0)]
    );
    assert_eq!(words(blocks[1]), vec![('G', 0.0), ('X', 1.0)]);
    // grbl has no block delete: the slash is dropped and the line runs.
    assert_eq!(words(blocks[2]), vec![('G', 0.0), ('X', 3.0)]);
    // Blanks are removed before parsing, also inside numbers.
    assert_eq!(blocks[3].n, Some(5.0));
    assert_eq!(words(blocks[3]), vec![('G', 1.0), ('X', 10.0)]);
}

#[test]
fn grbl_rejects_with_its_error_numbers() {
    let cases = [
        ("#1=2", 1),
        ("G1 X[1+2]", 2),
        ("G1 X#1", 2),
        ("G1 X", 2),
        ("G1 X-", 2),
        ("o100 sub", 20),
        ("G1 A5", 20),
        ("G1 E5", 20),
        ("%", 1),
        ("G1 X1.2.3", 1),
        ("N-5 G1", 4),
        ("N1 N2", 25),
        ("N99999999 G1", 27),
    ];
    for (line, code) in cases {
        let out = run(line, Dialect::Grbl);
        let err = out[0].as_ref().expect_err(line);
        assert_eq!(err.code, Some(code), "{line}: {}", err.message);
        assert_eq!(err.span.line, 1);
    }
    // 80 characters after removing blanks and comments overflow grbl's line buffer (79 fit).
    let long = format!("G1 X{} (a comment does not count)", "1".repeat(77));
    assert_eq!(
        run(&long, Dialect::Grbl)[0].as_ref().unwrap_err().code,
        Some(11)
    );
    let fits = format!(
        "G1 X{}   (blanks and comments do not count)",
        "1".repeat(75)
    );
    assert!(run(&fits, Dialect::Grbl)[0].is_ok());
}

#[test]
fn grbl_errors_do_not_stop_the_stream() {
    let out = run("G1 X1 F10\nG1 X#1\nG1 X2", Dialect::Grbl);
    assert_eq!(out.len(), 3);
    assert!(out[0].is_ok() && out[1].is_err() && out[2].is_ok());
    // Plain-looking lines further down get grbl's checks too.
    let out = run("G1 X1 F10\nG1 A5\nG1 E5\n", Dialect::Grbl);
    assert_eq!(
        out.iter()
            .map(|r| r.as_ref().err().and_then(|e| e.code))
            .collect::<Vec<_>>(),
        vec![None, Some(20), Some(20)]
    );
}

#[test]
fn legacy_2006_test_1_program_reads_as_written() {
    // Seed 002, Table 15, program 1 (verbatim, mixed case, integers only).
    let program = "g90\ny-80\nG2 x-80 y0 i0 j0\nG90\nx-160 y0\nG2 x0 y160 i0 j0\nG90\ny80\nG2 x80 y0 i0 j0\nG90\nx160\nG2 x0 y-160 i0 j0\ng90\ny-80\n";
    let out = run(program, Dialect::Legacy2006);
    let blocks: Vec<Block> = out.into_iter().map(|r| r.unwrap()).collect();
    assert_eq!(blocks.len(), 14);
    assert_eq!(
        words(&blocks[2]),
        vec![('G', 2.0), ('X', -80.0), ('Y', 0.0), ('I', 0.0), ('J', 0.0)]
    );
    assert_eq!(blocks[13].line, 14);
    assert_eq!(words(&blocks[13]), vec![('Y', -80.0)]);
}

#[test]
fn spans_point_at_the_words_and_errors() {
    let out = run("G1  X1 0.5 Y[1+#2]\nG1 X[1/0]", Dialect::LinuxCnc);
    let b = out[0].as_ref().unwrap();
    let x = b.words_of('X').next().unwrap();
    assert_eq!((x.span.line, x.span.col, x.span.len), (1, 5, 6));
    let y = b.words_of('Y').next().unwrap();
    assert_eq!((y.span.col, y.span.len), (12, 7));
    let e = out[1].as_ref().unwrap_err();
    assert_eq!(
        (e.span.line, e.span.col, e.span.len),
        (2, 6, 3),
        "the division 1/0"
    );
    assert!(e.message.contains("division by zero"));
}
