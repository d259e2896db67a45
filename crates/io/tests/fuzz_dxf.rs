//! Fuzzing of the DXF reader: it must never panic, and whatever it reads must be finite. Three
//! sources of bad input: group-level edits of a file that holds every kind read (block, insert
//! array, polyline with vertices, spline, hatch with edge and polyline paths, ellipse), byte
//! edits of real ASCII and binary files, and hand-made files that ask for absurd amounts.

use oficina_io::{dxf_from_bytes, read_dxf, DxfOptions, Imported};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::path::Path;

fn pairs(p: &[(&str, &str)]) -> String {
    p.iter().map(|(c, v)| format!("{c}\n{v}\n")).collect()
}

fn base() -> String {
    pairs(&[
        ("999", "made by hand"),
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
        ("0", "POLYLINE"),
        ("8", "a"),
        ("66", "1"),
        ("70", "1"),
        ("0", "VERTEX"),
        ("10", "0"),
        ("20", "20"),
        ("42", "1"),
        ("0", "VERTEX"),
        ("10", "5"),
        ("20", "20"),
        ("0", "SEQEND"),
        ("0", "INSERT"),
        ("8", "0"),
        ("2", "B"),
        ("10", "5"),
        ("20", "5"),
        ("30", "0"),
        ("41", "2"),
        ("50", "45"),
        ("70", "3"),
        ("71", "2"),
        ("44", "4"),
        ("45", "4"),
        ("0", "SPLINE"),
        ("8", "a"),
        ("70", "4"),
        ("71", "2"),
        ("72", "6"),
        ("73", "3"),
        ("40", "0"),
        ("40", "0"),
        ("40", "0"),
        ("40", "1"),
        ("40", "1"),
        ("40", "1"),
        ("41", "1"),
        ("41", "0.7"),
        ("41", "1"),
        ("10", "0"),
        ("20", "0"),
        ("10", "5"),
        ("20", "5"),
        ("10", "10"),
        ("20", "0"),
        ("0", "ELLIPSE"),
        ("8", "a"),
        ("10", "30"),
        ("20", "0"),
        ("11", "10"),
        ("21", "0"),
        ("40", "0.5"),
        ("41", "0"),
        ("42", "3"),
        ("230", "-1"),
        ("0", "HATCH"),
        ("8", "h"),
        ("10", "0"),
        ("20", "0"),
        ("30", "0"),
        ("2", "SOLID"),
        ("70", "1"),
        ("71", "0"),
        ("91", "2"),
        ("92", "1"),
        ("93", "2"),
        ("72", "1"),
        ("10", "0"),
        ("20", "0"),
        ("11", "10"),
        ("21", "0"),
        ("72", "2"),
        ("10", "5"),
        ("20", "0"),
        ("40", "5"),
        ("50", "0"),
        ("51", "180"),
        ("73", "0"),
        ("97", "0"),
        ("92", "2"),
        ("72", "1"),
        ("73", "1"),
        ("93", "3"),
        ("10", "0"),
        ("20", "0"),
        ("42", "0.3"),
        ("10", "4"),
        ("20", "0"),
        ("10", "4"),
        ("20", "4"),
        ("97", "0"),
        ("75", "0"),
        ("76", "1"),
        ("98", "0"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ])
}

/// What a successful read must be: finite everywhere.
fn finite(i: &Imported) -> bool {
    i.drawing.paths().all(|p| {
        p.segments.iter().all(|s| {
            let b = s.bounding_box();
            [b.x0, b.y0, b.x1, b.y1].iter().all(|v| v.is_finite())
        })
    }) && i.points.iter().all(|p| p.is_finite())
}

#[test]
fn the_base_file_reads_every_kind() {
    let i = dxf_from_bytes(base().as_bytes(), "base.dxf").unwrap();
    // LINE, ARC, LWPOLYLINE, POLYLINE, 6 inserted circles, SPLINE, ELLIPSE, 2 hatch paths.
    assert_eq!(i.drawing.path_count(), 14, "{:?}", i.unsupported);
    assert!(i.unsupported.is_empty(), "{}", i.unsupported);
}

#[test]
fn group_edits_never_panic() {
    let lines: Vec<String> = base().lines().map(String::from).collect();
    let n = lines.len();
    let values = prop::sample::select(vec![
        "0",
        "-1",
        "1e308",
        "-1e308",
        "nan",
        "inf",
        "999999",
        "2147483647",
        "-2147483648",
        "9223372036854775807",
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
        "-0.5",
        "EOF",
        "BLOCK",
        "ENDBLK",
        "POLYLINE",
        "VERTEX",
        "SEQEND",
        "HATCH",
        "SPLINE",
        "91",
        "92",
        "93",
        "97",
        "72",
        "330",
        "1e-300",
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
    let cases = 10_000;
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let started = std::time::Instant::now();
    let ok = std::cell::Cell::new(0usize);
    runner
        .run(&strategy, |s| {
            if let Ok(i) = dxf_from_bytes(s.as_bytes(), "f.dxf") {
                prop_assert!(finite(&i), "non-finite geometry from:\n{s}");
                ok.set(ok.get() + 1);
            }
            Ok(())
        })
        .unwrap();
    let ok = ok.get();
    eprintln!(
        "fuzz dxf groups: {cases} cases in {:.2} s, {ok} still read",
        started.elapsed().as_secs_f64()
    );
    assert!(ok > 0 && ok < cases as usize, "{ok} of {cases} read");
}

#[test]
fn byte_edits_of_real_ascii_and_binary_files_never_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dxf");
    let mut total = 0;
    for name in [
        "ezdxf_bin_dxf_r12.dxf",
        "ezdxf_bin_dxf_r13.dxf",
        "ezdxf_no_layouts.dxf",
        "ezdxf_clockwise_arcs_hatch.dxf",
        "ezdxf_multi_insert_with_attribs.dxf",
    ] {
        let bytes = std::fs::read(dir.join(name)).unwrap();
        let opts = DxfOptions {
            max_size_mm: f64::INFINITY,
            ..DxfOptions::default()
        };
        assert!(read_dxf(&bytes, name, &opts).is_ok());
        let len = bytes.len();
        let strategy =
            prop::collection::vec((0..len, any::<u8>(), 0u8..4), 1..6).prop_map(move |edits| {
                let mut b = bytes.clone();
                for (at, byte, op) in edits {
                    let i = at % b.len().max(1);
                    match op {
                        0 if !b.is_empty() => b[i] = byte,
                        1 => b.insert(i.min(b.len()), byte),
                        2 => b.truncate(i),
                        _ if i < b.len() => {
                            b.remove(i);
                        }
                        _ => {}
                    }
                }
                b
            });
        let mut runner = TestRunner::new(Config {
            cases: 600,
            failure_persistence: None,
            ..Config::default()
        });
        runner
            .run(&strategy, |b| {
                if let Ok(r) = read_dxf(&b, name, &opts) {
                    prop_assert!(finite(&r.imported));
                }
                Ok(())
            })
            .unwrap();
        total += 600;
    }
    eprintln!("fuzz dxf bytes: {total} cases over 5 real files");
}

#[test]
fn absurd_counts_and_expansions_are_errors_not_allocations() {
    let b = base();
    // A hatch that announces two billion paths, then one with four billion edges.
    for (from, to) in [
        ("91\n2\n", "91\n2000000000\n"),
        ("93\n2\n72", "93\n4000000000\n72"),
    ] {
        let s = b.replacen(from, to, 1);
        assert_ne!(s, b);
        let i = dxf_from_bytes(s.as_bytes(), "h.dxf").unwrap();
        assert!(
            i.unsupported.to_string().contains("HATCH"),
            "{}",
            i.unsupported
        );
    }
    // An array of 10⁶ × 10⁶ inserts.
    let s = b.replacen("70\n3\n71\n2\n", "70\n1000000\n71\n1000000\n", 1);
    let e = dxf_from_bytes(s.as_bytes(), "a.dxf").unwrap_err();
    assert!(e.message.contains("1000000 × 1000000"), "{e}");
    // A block inserting itself.
    let s = b.replacen("0\nENDBLK\n", "0\nINSERT\n2\nB\n0\nENDBLK\n", 1);
    let e = dxf_from_bytes(s.as_bytes(), "self.dxf").unwrap_err();
    assert!(e.message.contains("nested deeper"), "{e}");
    // A dimension whose block holds the dimension itself.
    let s = b.replacen("0\nENDBLK\n", "0\nDIMENSION\n2\nB\n0\nENDBLK\n", 1);
    let e = dxf_from_bytes(s.as_bytes(), "dim.dxf").unwrap_err();
    assert!(e.message.contains("nested deeper"), "{e}");
    // 20 doublings of an array of 2 × 2: 4²⁰ entities.
    let mut s = pairs(&[("0", "SECTION"), ("2", "BLOCKS")]);
    s += &pairs(&[
        ("0", "BLOCK"),
        ("2", "B0"),
        ("10", "0"),
        ("20", "0"),
        ("0", "LINE"),
        ("11", "1"),
        ("0", "ENDBLK"),
    ]);
    for k in 1..=20 {
        let (name, inner) = (format!("B{k}"), format!("B{}", k - 1));
        s += &pairs(&[
            ("0", "BLOCK"),
            ("2", &name),
            ("10", "0"),
            ("20", "0"),
            ("0", "INSERT"),
            ("2", &inner),
            ("70", "2"),
            ("71", "2"),
            ("44", "1"),
            ("45", "1"),
            ("0", "ENDBLK"),
        ]);
    }
    s += &pairs(&[
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "INSERT"),
        ("2", "B11"),
        ("0", "ENDSEC"),
    ]);
    let e = dxf_from_bytes(s.as_bytes(), "bomb.dxf").unwrap_err();
    assert!(e.message.contains("more than 1000000 entities"), "{e}");
    // Coordinates that overflow once in mm.
    let s = b.replacen("$INSUNITS\n70\n4", "$INSUNITS\n70\n20", 1);
    let e = dxf_from_bytes(s.as_bytes(), "pc.dxf").unwrap_err();
    assert_eq!(e.location, "units", "{e}");
}
