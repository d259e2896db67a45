//! Fuzzing the front end (lexer, parser, expressions, executor) with proptest: random bytes,
//! random G-code-like token soup and mutated lines of the G-code corpus, in every dialect.
//!
//! Asserted for every input: no panic; the executor reaches the end within a step bound
//! that follows from its limits; every error and every word has a span inside the input.
//!
//! The number of cases per property is proptest's `PROPTEST_CASES` (default 256), e.g. a
//! long run: `PROPTEST_CASES=200000 cargo test --release -p oficina-gcode --test fuzz_frontend`.

use oficina_gcode::parse_line;
use oficina_gcode::Compact;
use oficina_gcode::Line;
use oficina_gcode::Params;
use oficina_gcode::{Dialect, Span};
use oficina_gcode::{Driver, RunOptions};
use oficina_gcode::{Executor, Limits};
use proptest::prelude::*;
use std::io::Cursor;
use std::sync::OnceLock;

const DIALECTS: [Dialect; 3] = [Dialect::LinuxCnc, Dialect::Grbl, Dialect::Legacy2006];

const LIMITS: Limits = Limits {
    max_call_depth: 8,
    max_loop_iterations: 200,
    max_idle_iterations: 50,
    max_total_jumps: 2_000,
};

/// Lines of the repository's G-code corpus plus hand-picked control-flow lines, so the
/// mutations start from something close to valid.
fn corpus() -> &'static Vec<String> {
    static CORPUS: OnceLock<Vec<String>> = OnceLock::new();
    CORPUS.get_or_init(|| {
        let mut programs: Vec<String> = [
            "o100 sub\nG0 X#1 Y#2\no100 return [#1*10]\no100 endsub\no100 call [3] [4]\nG1 X#<_value> F100\nM2",
            "#1=0\no1 while [#1 LT 3]\nG1 X#1 F100\n#1=[#1+1]\no1 endwhile\nM2",
            "#1=0\no1 do\n#1=[#1+1]\no2 if [#1 EQ 2]\no1 continue\no2 elseif [#1 GT 4]\no1 break\no2 else\nG0 X#1\no2 endif\no1 while [#1 LT 9]\nM2",
            "o<r> sub\no1 if [#1 GT 0]\no<r> call [#1-1]\no1 endif\no<r> endsub\no<r> call [5]\nM2",
            "%\n(MSG, hi)\n#<a>=[SIN[30]*2] (debug,#<a>)\nG0 X[ATAN[1]/[1]] Y[2**3] Z-#<a>\no2 repeat [3]\nG91 G1 X1 F[100*2]\no2 endrepeat\n%",
            "N10 G21 G90 G17\nN20 G0 X0 Y0 Z5\nN30 G1 Z-1 F200\nN40 G2 X10 Y0 I5 J0\n/N50 G1 X0\nN60 M2",
            "G0 X1 0.5 (comment) ; tail\n#5=[#4 MOD 3 AND 1 OR 0 XOR 1]\nG1 X[FIX[2.5]+FUP[2.5]+ROUND[2.5]+ABS[-1]+SQRT[4]+EXP[0]+LN[1]] F1",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus");
        if let Ok(entries) = std::fs::read_dir(&dir) {
            let mut paths: Vec<_> = entries.flatten().map(|e| e.path()).collect();
            paths.sort();
            for p in paths {
                if p.extension().is_some_and(|e| e == "ngc") {
                    if let Ok(text) = std::fs::read_to_string(&p) {
                        programs.push(text);
                    }
                }
            }
        }
        programs
    })
}

/// Columns as the lexer counts them: characters, i.e. bytes that do not continue a UTF-8
/// sequence (a continuation byte with no lead byte before it counts as one).
fn columns(line: &[u8]) -> u32 {
    (0..line.len())
        .filter(|&i| line[i] & 0xC0 != 0x80 || i == 0 || line[i - 1] < 0x80)
        .count() as u32
}

fn assert_span_inside(span: Span, lines: &[&[u8]], what: &str) {
    let count = lines.len().max(1) as u32;
    assert!(
        span.line >= 1 && span.line <= count,
        "{what}: line {} of {count}",
        span.line
    );
    let cols = lines.get(span.line as usize - 1).map_or(0, |l| columns(l));
    assert!(span.col >= 1, "{what}: column 0");
    // One past the end is allowed: "missing value at end of line".
    assert!(
        span.col + span.len <= cols + 2,
        "{what}: columns {}..{} on a line of {cols} characters",
        span.col,
        span.col + span.len
    );
}

/// Run a whole program through the executor in one dialect and check the invariants.
fn run_program(text: &[u8], dialect: Dialect) {
    let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
    let mut exec = Executor::new(Cursor::new(text.to_vec()), dialect);
    exec.set_limits(LIMITS);
    exec.set_max_line_len(2048);
    let mut params = Params::new();
    // Each backward jump can re-run every line once; errors and blocks are one step each.
    let bound = (lines.len() as u64 + 2) * (LIMITS.max_total_jumps + 2) * 2;
    let mut steps = 0u64;
    while let Some(result) = exec.next_block(&mut params) {
        steps += 1;
        assert!(steps <= bound, "no end after {steps} steps");
        match result {
            Ok(block) => {
                for w in &block.words {
                    assert_span_inside(w.span, &lines, "word");
                    // A letter, or the polar radius `@` and angle `^`.
                    let letter = w.letter.is_ascii_uppercase() || matches!(w.letter, '@' | '^');
                    assert!(letter && w.letter != 'N' && w.letter != 'O');
                }
            }
            Err(e) => assert_span_inside(e.span, &lines, &e.message),
        }
    }
    // After the end it stays ended.
    assert!(exec.next_block(&mut params).is_none());
}

/// Run a whole program through the driver (interpreter included) as `oficina_gcode::run`
/// does, in check mode so every line is read: the fast paths' stretches of usual lines and
/// the slow path alternate however the input falls. No panic, and every diagnostic names a
/// line of the input (or the line just after it, for a missing program end).
fn run_pipeline(text: &[u8], dialect: Dialect) {
    let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
    let mut exec = Executor::new(Cursor::new(text.to_vec()), dialect);
    exec.set_limits(LIMITS);
    exec.set_max_line_len(2048);
    let opts = RunOptions::check(dialect);
    let mut sink = |_| {};
    for d in Driver::new(&opts, &mut sink).run(&mut exec, &mut sink) {
        assert!(
            d.span.line as usize <= lines.len() + 1,
            "{}: {d:?}",
            d.message
        );
    }
}

/// Lex and parse one line in every dialect.
fn parse_one(line: &[u8]) {
    let mut c = Compact::new();
    let mut ast = Line::default();
    for d in DIALECTS {
        let loaded = if d == Dialect::Grbl {
            c.load_grbl(line, 1);
            Ok(())
        } else {
            c.load(line, 1)
        };
        match loaded {
            Ok(()) => {
                if let Err(e) = parse_line(&c, d, &mut ast) {
                    assert_span_inside(e.span, &[line], &e.message);
                }
            }
            Err(e) => assert_span_inside(e.span, &[line], &e.message),
        }
    }
}

const TOKENS: &[&str] = &[
    "G",
    "g",
    "X",
    "Y",
    "Z",
    "F",
    "N",
    "O",
    "o",
    "M",
    "#",
    "##",
    "#<",
    ">",
    "<a>",
    "<_value>",
    "[",
    "]",
    "[[",
    "]]",
    "(",
    ")",
    "(MSG,",
    "(debug,#1",
    ";",
    "%",
    "/",
    "=",
    "-",
    "+",
    "*",
    "**",
    "/",
    ".",
    "..",
    "0",
    "1",
    "2",
    "9",
    "0.5",
    "100",
    "5601",
    "5602",
    "99999999999999999999",
    " ",
    " ",
    "\t",
    "\n",
    "\n",
    "\r\n",
    "MOD",
    "EQ",
    "NE",
    "GT",
    "LE",
    "AND",
    "OR",
    "XOR",
    "SIN[",
    "ATAN[",
    "]/[",
    "SQRT[",
    "LN[",
    "EXISTS[",
    "sub",
    "endsub",
    "call",
    "return",
    "if",
    "elseif",
    "else",
    "endif",
    "do",
    "while",
    "endwhile",
    "repeat",
    "endrepeat",
    "break",
    "continue",
    "o1 ",
    "o2 ",
    "o<s> ",
    "µ",
    "\u{0}",
    "\u{ff}",
];

fn token_soup() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(prop::sample::select(TOKENS), 0..80).prop_map(|t| t.concat().into_bytes())
}

#[derive(Clone, Debug)]
enum Mutation {
    Insert(usize, u8),
    Delete(usize),
    Replace(usize, u8),
    /// Copy a run of bytes elsewhere (duplicates lines, o-words, brackets).
    Splice(usize, usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let byte = prop::sample::select(b"[]#<>()=;%/-+*.0123456789 \nGXYZONoMF".to_vec());
    prop_oneof![
        (any::<usize>(), byte.clone()).prop_map(|(i, b)| Mutation::Insert(i, b)),
        any::<usize>().prop_map(Mutation::Delete),
        (any::<usize>(), byte).prop_map(|(i, b)| Mutation::Replace(i, b)),
        (any::<usize>(), 1usize..40, any::<usize>())
            .prop_map(|(a, n, b)| Mutation::Splice(a, n, b)),
    ]
}

fn mutate(mut text: Vec<u8>, mutations: &[Mutation]) -> Vec<u8> {
    for m in mutations {
        let len = text.len();
        match *m {
            Mutation::Insert(i, b) => text.insert(i % (len + 1), b),
            Mutation::Delete(i) if len > 0 => {
                text.remove(i % len);
            }
            Mutation::Replace(i, b) if len > 0 => text[i % len] = b,
            Mutation::Splice(from, n, to) if len > 0 => {
                let from = from % len;
                let piece: Vec<u8> = text[from..(from + n).min(len)].to_vec();
                let to = to % (len + 1);
                text.splice(to..to, piece);
            }
            _ => {}
        }
    }
    text
}

fn mutated_corpus() -> impl Strategy<Value = Vec<u8>> {
    (
        any::<prop::sample::Index>(),
        prop::collection::vec(mutation(), 0..12),
    )
        .prop_map(|(i, m)| mutate(i.get(corpus()).clone().into_bytes(), &m))
}

/// Run a property for `PROPTEST_CASES` cases (proptest's default config reads it), shrink
/// a failure to a minimal input, and print how many cases ran.
fn check<S: Strategy>(name: &str, strategy: S, property: impl Fn(&S::Value))
where
    S::Value: std::fmt::Debug,
{
    let config = ProptestConfig {
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    let mut runner = proptest::test_runner::TestRunner::new(config);
    let cases = std::cell::Cell::new(0u64);
    let started = std::time::Instant::now();
    let result = runner.run(&strategy, |value| {
        property(&value);
        cases.set(cases.get() + 1);
        Ok(())
    });
    eprintln!(
        "{name}: {} cases in {:.1} s",
        cases.get(),
        started.elapsed().as_secs_f64()
    );
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

#[test]
fn random_bytes_never_break_the_lexer_parser_or_executor() {
    check(
        "random bytes",
        prop::collection::vec(any::<u8>(), 0..400),
        |bytes| {
            for line in bytes.split(|&b| b == b'\n') {
                parse_one(line);
            }
            for d in DIALECTS {
                run_program(bytes, d);
                run_pipeline(bytes, d);
            }
        },
    );
}

#[test]
fn gcode_token_soup_never_breaks_the_front_end() {
    check("token soup", token_soup(), |text| {
        for line in text.split(|&b| b == b'\n') {
            parse_one(line);
        }
        for d in DIALECTS {
            run_program(text, d);
            run_pipeline(text, d);
        }
    });
}

#[test]
fn mutated_corpus_programs_never_break_the_front_end() {
    check("mutated corpus", mutated_corpus(), |text| {
        for d in DIALECTS {
            run_program(text, d);
            run_pipeline(text, d);
        }
    });
}

#[test]
fn the_corpus_itself_runs_through_the_executor() {
    assert!(corpus().len() > 7, "the repository corpus was found");
    for program in corpus() {
        run_program(program.as_bytes(), Dialect::LinuxCnc);
    }
}
