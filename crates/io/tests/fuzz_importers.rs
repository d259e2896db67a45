//! Property fuzzing of the text importers: random and mutated inputs give a drawing or an
//! error, never a panic. Case counts are printed (`--nocapture`).

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100mm" height="50mm" viewBox="0 0 100 50"><defs><path id="p" d="M0 0 L10 0 Q 15 5 10 10 C 5 15 0 10 0 0 Z"/></defs><g transform="translate(10,5) rotate(30) scale(2,1)"><rect x="0" y="0" width="20" height="10" rx="2"/><use xlink:href="#p" x="5"/></g><circle cx="80" cy="40" r="5"/><ellipse cx="50" cy="25" rx="10" ry="4"/><polyline points="0,0 5,5 10,0"/><path d="m 10 10 h 5 v 5 a 3 3 0 1 1 -5 0 s 1 2 3 4 t 5 5 z"/><text>t</text></svg>"##;

const SEED: &str = "3\n0 0 400 300\n1 337.58 273.72 357.58 293.72\n4\n347.58 283.72\n357.58 283.72\n337.58 283.72\n10.0 1.0\n4 0 0 10 10\n3\n0 0\n10 0\n10 10\n6 0 0 2 2\n3\n1 1\n2 1\n6 0\n1\n5 5\n";

/// Mutations of a valid text: each step replaces, inserts or deletes a character at random.
fn mutated(base: &'static str) -> impl Strategy<Value = String> {
    let alphabet: Vec<char> = "0123456789 .-,;\t\n<>/=\"'#eEaAzZmMlLcChHvVxXyY()[]{}&%"
        .chars()
        .collect();
    prop::collection::vec(
        (0usize..10_000, 0u8..3, prop::sample::select(alphabet)),
        1..12,
    )
    .prop_map(move |edits| {
        let mut s: Vec<char> = base.chars().collect();
        for (at, op, c) in edits {
            if s.is_empty() {
                s.push(c);
                continue;
            }
            let i = at % s.len();
            match op {
                0 => s[i] = c,
                1 => s.insert(i, c),
                _ => {
                    s.remove(i);
                }
            }
        }
        s.into_iter().collect()
    })
}

fn run(name: &str, cases: u32, strategy: impl Strategy<Value = String>, f: impl Fn(&str)) {
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let started = std::time::Instant::now();
    runner
        .run(&strategy, |s| {
            f(&s);
            Ok(())
        })
        .unwrap();
    eprintln!(
        "fuzz {name}: {cases} cases, {:.2} s",
        started.elapsed().as_secs_f64()
    );
}

#[test]
fn points_never_panic() {
    let chars = "[0-9 .,;\t\n#xyXYabe+-]{0,400}";
    run("points random", 20000, chars, |s| {
        let _ = oficina_io::parse_points(s, "f.csv");
    });
    run(
        "points mutated",
        20000,
        mutated("x,y\n1.5,2\n3;4,5\n# c\n6 7\n"),
        |s| {
            let _ = oficina_io::parse_points(s, "f.csv");
        },
    );
}

#[test]
fn seed001_never_panics() {
    run("seed001 mutated", 20000, mutated(SEED), |s| {
        if let Ok(f) = oficina_io::parse_seed001(s, "f.dat") {
            let _ = f.to_imported("f.dat");
            let _ = f.to_text();
        }
    });
    run(
        "seed001 random numbers",
        10000,
        "[0-9 .\\-\n]{0,300}",
        |s| {
            if let Ok(f) = oficina_io::parse_seed001(s, "f.dat") {
                let _ = f.to_imported("f.dat");
            }
        },
    );
}

#[test]
fn svg_never_panics() {
    run("svg mutated", 10000, mutated(SVG), |s| {
        let _ = oficina_io::svg_from_bytes(s.as_bytes(), "f.svg");
    });
}
