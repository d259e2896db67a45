//! Property fuzzing of the DXF importer (its own test binary: it counts panics inside the dxf
//! crate, which the importer turns into errors, with a process-wide panic hook).

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::sync::atomic::{AtomicUsize, Ordering};

static CAUGHT: AtomicUsize = AtomicUsize::new(0);

fn base() -> String {
    let p = [
        ("0", "SECTION"),
        ("2", "HEADER"),
        ("9", "$INSUNITS"),
        ("70", "4"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "BLOCKS"),
        ("0", "BLOCK"),
        ("8", "0"),
        ("2", "B"),
        ("70", "0"),
        ("10", "0"),
        ("20", "0"),
        ("30", "0"),
        ("0", "CIRCLE"),
        ("8", "0"),
        ("10", "1"),
        ("20", "1"),
        ("30", "0"),
        ("40", "1"),
        ("0", "ENDBLK"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "LINE"),
        ("8", "a"),
        ("10", "0"),
        ("20", "0"),
        ("30", "0"),
        ("11", "10"),
        ("21", "0"),
        ("31", "0"),
        ("0", "ARC"),
        ("8", "a"),
        ("10", "0"),
        ("20", "0"),
        ("30", "0"),
        ("40", "5"),
        ("50", "0"),
        ("51", "90"),
        ("0", "LWPOLYLINE"),
        ("8", "a"),
        ("90", "3"),
        ("70", "1"),
        ("10", "0"),
        ("20", "0"),
        ("42", "0.5"),
        ("10", "10"),
        ("20", "0"),
        ("10", "10"),
        ("20", "10"),
        ("0", "INSERT"),
        ("8", "0"),
        ("2", "B"),
        ("10", "5"),
        ("20", "5"),
        ("30", "0"),
        ("41", "2"),
        ("50", "45"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ];
    p.iter().map(|(c, v)| format!("{c}\n{v}\n")).collect()
}

#[test]
fn dxf_never_panics() {
    let lines: Vec<String> = base().lines().map(String::from).collect();
    let n = lines.len();
    let values = prop::sample::select(vec![
        "0",
        "-1",
        "1e308",
        "nan",
        "999999",
        "ENDSEC",
        "SECTION",
        "LINE",
        "INSERT",
        "B",
        "70",
        "10",
        "abc",
        "",
        "42",
        "2147483648",
        "-0.5",
        "EOF",
        "BLOCK",
        "POLYLINE",
        "VERTEX",
        "SEQEND",
    ]);
    let strategy = prop::collection::vec((0..n, 0u8..3, values), 1..8).prop_map(move |edits| {
        let mut l = lines.clone();
        for (at, op, v) in edits {
            if l.is_empty() {
                break;
            }
            let i = at % l.len();
            match op {
                0 => l[i] = v.to_string(),
                1 => l.insert(i, v.to_string()),
                _ => {
                    l.remove(i);
                }
            }
        }
        l.join("\n")
    });
    std::panic::set_hook(Box::new(|_| {
        CAUGHT.fetch_add(1, Ordering::SeqCst);
    }));
    let cases = 10000;
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let started = std::time::Instant::now();
    let ok = AtomicUsize::new(0);
    let result = runner.run(&strategy, |s| {
        if oficina_io::dxf_from_bytes(s.as_bytes(), "f.dxf").is_ok() {
            ok.fetch_add(1, Ordering::SeqCst);
        }
        Ok(())
    });
    let _ = std::panic::take_hook();
    result.unwrap();
    eprintln!(
        "fuzz dxf: {} of the mutated files still import",
        ok.load(Ordering::SeqCst)
    );
    eprintln!(
        "fuzz dxf mutated: {cases} cases, {:.2} s, {} panics inside the dxf crate caught and reported as errors",
        started.elapsed().as_secs_f64(),
        CAUGHT.load(Ordering::SeqCst)
    );
}
