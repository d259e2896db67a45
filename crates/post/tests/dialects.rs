//! Every dialect's program read back by Oficina's interpreter (and LinuxCNC's by `rs274`),
//! and one golden text per format option on a tiny toolpath.

use oficina_cam::{Drill, Move, Operation, PathMode, Tool, Toolpath};
use oficina_canon::CanonOp;
use oficina_post::{
    program_text, program_text_with, read_back, sinumerik_to_ngc, Format, LineNumbers, Numbers,
    PostDialect, PostOptions, Units,
};

fn op(n: u32, spec: &str, rpm: f64, moves: Vec<Move>) -> Operation {
    Operation {
        name: format!("op{n}"),
        tool_number: n,
        tool: spec.parse::<Tool>().unwrap(),
        spindle_rpm: rpm,
        moves,
    }
}

/// Everything a post must write: lines, a CW arc, a helix, a dwell, path modes, a plain
/// and a peck drill, two tools.
fn sample() -> Toolpath {
    let f = 600.0 / 60.0;
    Toolpath {
        safe_z: 40.0,
        operations: vec![
            op(
                1,
                "flat:16",
                1600.0,
                vec![
                    Move::PathMode(PathMode::Continuous),
                    Move::Rapid {
                        to: [100.0, 100.0, 40.0],
                    },
                    Move::Rapid {
                        to: [100.0, 100.0, 5.0],
                    },
                    Move::Line {
                        to: [100.0, 100.0, -5.0],
                        feed: f,
                    },
                    // Seed 001 Table 3: centre (150, 100), R 50, over the top, clockwise.
                    Move::Arc {
                        to: [200.0, 100.0, -5.0],
                        center: [150.0, 100.0],
                        ccw: false,
                        feed: f,
                    },
                    // A helix down one more mm on a full circle.
                    Move::Arc {
                        to: [200.0, 100.0, -6.0],
                        center: [190.0, 100.0],
                        ccw: true,
                        feed: f / 2.0,
                    },
                    Move::Dwell(0.5),
                    Move::Rapid {
                        to: [200.0, 100.0, 5.0],
                    },
                ],
            ),
            op(
                2,
                "flat:6",
                2000.0,
                vec![
                    Move::PathMode(PathMode::ExactStop),
                    Move::Drill(Drill {
                        at: [20.0, 30.0],
                        bottom: -4.0,
                        r: 2.0,
                        peck: None,
                        dwell: 0.0,
                        feed: 170.0 / 60.0,
                    }),
                    Move::Drill(Drill {
                        at: [40.0, 30.0],
                        bottom: -7.5,
                        r: 2.0,
                        peck: Some(3.0),
                        dwell: 0.0,
                        feed: 170.0 / 60.0,
                    }),
                ],
            ),
        ],
    }
}

fn options(dialect: PostDialect) -> PostOptions {
    PostOptions {
        dialect,
        allow_m6: false,
        title: "dialect test".into(),
        settings: vec![],
    }
}

/// End points of the cutting moves, in order.
fn feed_ends(canon: &[oficina_canon::Canon]) -> Vec<[f64; 3]> {
    canon
        .iter()
        .filter_map(|c| match c.op {
            CanonOp::StraightFeed { to } | CanonOp::ArcFeed { end: to, .. } => {
                Some([to.x, to.y, to.z])
            }
            _ => None,
        })
        .collect()
}

fn assert_same_path(got: &[[f64; 3]], want: &[[f64; 3]], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}\nvs {want:?}");
    for (g, w) in got.iter().zip(want) {
        for k in 0..3 {
            assert!((g[k] - w[k]).abs() <= tol, "{what}: {g:?} vs {w:?}");
        }
    }
}

#[test]
fn every_dialect_reads_back_as_the_toolpath() {
    let tp = sample();
    let want = feed_ends(&tp.canon());
    assert!(want.len() >= 8, "{want:?}");
    for dialect in [
        PostDialect::LinuxCnc,
        PostDialect::Grbl,
        PostDialect::Sinumerik,
        PostDialect::Legacy2006,
    ] {
        let text = program_text(&tp, &options(dialect)).unwrap();
        let canon = read_back(&text, &options(dialect))
            .unwrap_or_else(|e| panic!("{dialect:?}: {e}\n{text}"));
        // Sinumerik words are 0.001 mm; the others print 3 or 4 decimals.
        assert_same_path(&feed_ends(&canon), &want, 1e-3, &format!("{dialect:?}"));
        // Arcs stay arcs, with the toolpath's direction.
        let dirs: Vec<i32> = canon
            .iter()
            .filter_map(|c| match c.op {
                CanonOp::ArcFeed { turns, .. } => Some(turns.signum()),
                _ => None,
            })
            .collect();
        assert_eq!(dirs, vec![-1, 1], "{dialect:?}");
    }
}

/// rs274's canonical calls for `text` (which it must accept) with this file's tool table.
fn rs274(text: &str) -> String {
    oficina_testkit::rs274::accepts(text, Some("T1 P1 D16 Z0\nT2 P2 D6 Z0\nT99 P99 D0 Z0\n"))
}

/// The end points of rs274's STRAIGHT_FEED and ARC_FEED calls. ARC_FEED's arguments are
/// (first_end, second_end, first_axis, second_axis, rotation, axis_end_point, …).
fn rs274_feed_ends(out: &str) -> Vec<[f64; 3]> {
    let mut ends = Vec::new();
    for line in out.lines() {
        // "   21 N..... CALL(…)" or, for numbered blocks, "   21 N30    CALL(…)".
        let rest = line
            .trim_start()
            .trim_start_matches(|c: char| c.is_ascii_digit());
        let Some(rest) = rest.trim_start().strip_prefix('N') else {
            continue;
        };
        let call = rest
            .trim_start_matches(|c: char| c == '.' || c.is_ascii_digit())
            .trim_start();
        let args = |s: &str| -> Vec<f64> {
            let inner = &s[s.find('(').unwrap() + 1..s.rfind(')').unwrap()];
            inner
                .split(',')
                .map(|a| a.trim().parse::<f64>().unwrap_or(f64::NAN))
                .collect()
        };
        if call.starts_with("STRAIGHT_FEED(") {
            let a = args(call);
            ends.push([a[0], a[1], a[2]]);
        } else if call.starts_with("ARC_FEED(") {
            let a = args(call);
            ends.push([a[0], a[1], a[5]]);
        }
    }
    ends
}

#[test]
fn rs274_accepts_the_linuxcnc_program_and_cuts_the_same_path() {
    let tp = sample();
    let want = feed_ends(&tp.canon());
    let text = program_text(&tp, &options(PostDialect::LinuxCnc)).unwrap();
    assert!(text.contains("G99 G81 X20 Y30 Z-4 R2 F170"), "{text}");
    assert!(text.contains("G99 G83 X40 Y30 Z-7.5 R2 Q3 F170"), "{text}");
    let out = rs274(&text);
    // rs274 runs canned cycles itself: its peck moves must be Drill::moves'.
    assert_same_path(&rs274_feed_ends(&out), &want, 1e-4, "rs274");
    // The Sinumerik program, rewritten word for word in NGC, passes rs274 too.
    let sin = program_text(&tp, &options(PostDialect::Sinumerik)).unwrap();
    let ngc = sinumerik_to_ngc(&sin).unwrap();
    assert_same_path(
        &rs274_feed_ends(&rs274(&ngc)),
        &want,
        1e-3,
        "rs274 sinumerik",
    );
}

#[test]
fn sinumerik_writes_the_seeds_blocks() {
    let text = program_text(&sample(), &options(PostDialect::Sinumerik)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "%", "{text}");
    for want in [
        "G00 G40 G53 G90 Z600000",
        "G53 X450000 Y150000 M05",
        "T01 M06",
        "G00 G54 G43 D01 G64 Z40000 S1600 M03",
        "M08",
        "G00 X100000 Y100000",
        "Z5000",
        "G01 Z-5000 F600",
        // I J incremental from the arc start: (150 − 100, 100 − 100).
        "G02 X200000 Y100000 I50000 J0",
        "G03 X200000 Y100000 Z-6000 I-10000 J0 F300",
        "G04 F0.5",
        "M09",
        "G40 G53 X450000 Y150000 Z600000 M05",
        "T02 M06",
        "G60",
        "T99 M06",
        "M30",
    ] {
        assert!(
            lines
                .iter()
                .any(|l| l.split_once(' ').map(|x| x.1) == Some(want)),
            "missing '{want}':\n{text}"
        );
    }
    // Block numbers count up by one from N10 on every block.
    let numbers: Vec<u32> = lines
        .iter()
        .filter(|l| l.starts_with('N'))
        .map(|l| l[1..l.find(' ').unwrap()].parse().unwrap())
        .collect();
    assert!(numbers.windows(2).all(|w| w[1] == w[0] + 1));
    // No decimal point in any word outside comments.
    for l in lines
        .iter()
        .filter(|l| !l.starts_with('(') && !l.contains("G04"))
    {
        assert!(!l.contains('.'), "{l}");
    }
}

#[test]
fn legacy_uses_g90_feeds_absolute_centres_and_no_f() {
    let text = program_text(&sample(), &options(PostDialect::Legacy2006)).unwrap();
    assert!(text.contains("G90 Z-5\n"), "{text}");
    // I J are the centre itself.
    assert!(text.contains("G2 X200 Y100 I150 J100\n"), "{text}");
    assert!(text.contains("G3 X200 Y100 Z-6 I190 J100\n"), "{text}");
    assert!(
        text.contains("set the machine feed to 170 mm/min"),
        "{text}"
    );
    for l in text.lines().filter(|l| !l.starts_with('(')) {
        assert!(
            !l.contains('F') && !l.contains('M') && !l.contains("G1"),
            "{l}"
        );
    }
}

/// One arc and two lines: the tiny toolpath of the golden tests.
fn tiny() -> Toolpath {
    Toolpath {
        safe_z: 5.0,
        operations: vec![op(
            1,
            "flat:6",
            10000.0,
            vec![
                Move::Rapid {
                    to: [1.0, 2.0, 5.0],
                },
                Move::Line {
                    to: [1.0, 2.0, -1.0],
                    feed: 5.0,
                },
                Move::Line {
                    to: [11.123456, 2.0, -1.0],
                    feed: 20.0,
                },
                Move::Arc {
                    to: [13.123456, 4.0, -1.0],
                    center: [11.123456, 4.0],
                    ccw: true,
                    feed: 20.0,
                },
            ],
        )],
    }
}

fn body(text: &str) -> String {
    text.lines()
        .filter(|l| !l.starts_with('(') && !l.contains("] ("))
        .collect::<Vec<_>>()
        .join("\n")
}

fn golden(format: Format) -> String {
    let opts = options(PostDialect::LinuxCnc);
    let text = program_text_with(&tiny(), &opts, &format).unwrap();
    read_back(&text, &opts).unwrap_or_else(|e| panic!("{e}\n{text}"));
    rs274(&text);
    body(&text)
}

#[test]
fn golden_default() {
    assert_eq!(
        golden(Format::DEFAULT),
        "G21 G90 G94 G17\nT1 M6\nG0 Z5\nS10000 M3\nG0 X1 Y2\nG1 Z-1 F300\n\
         X11.1235 F1200\nG3 X13.1235 Y4 I0 J2\nG0 Z5\nM5\nM30"
    );
}

#[test]
fn golden_precision() {
    let f = Format {
        numbers: Numbers::Decimal { places: 2 },
        ..Format::DEFAULT
    };
    assert_eq!(
        golden(f),
        "G21 G90 G94 G17\nT1 M6\nG0 Z5\nS10000 M3\nG0 X1 Y2\nG1 Z-1 F300\n\
         X11.12 F1200\nG3 X13.12 Y4 I0 J2\nG0 Z5\nM5\nM30"
    );
}

#[test]
fn golden_inches() {
    let f = Format {
        units: Units::Inch,
        ..Format::DEFAULT
    };
    // 1 mm = 0.0394 in; 300 mm/min = 11.811 in/min.
    assert_eq!(
        golden(f),
        "G20 G90 G94 G17\nT1 M6\nG0 Z0.1969\nS10000 M3\nG0 X0.0394 Y0.0787\n\
         G1 Z-0.0394 F11.811\nX0.4379 F47.2441\nG3 X0.5167 Y0.1575 I0 J0.0787\nG0 Z0.1969\nM5\nM30"
    );
}

#[test]
fn golden_line_numbers() {
    let f = Format {
        line_numbers: Some(LineNumbers {
            start: 100,
            step: 5,
        }),
        ..Format::DEFAULT
    };
    assert_eq!(
        golden(f),
        "N100 G21 G90 G94 G17\nN105 T1 M6\nN110 G0 Z5\nN115 S10000 M3\nN120 G0 X1 Y2\n\
         N125 G1 Z-1 F300\nN130 X11.1235 F1200\nN135 G3 X13.1235 Y4 I0 J2\nN140 G0 Z5\n\
         N145 M5\nN150 M30"
    );
}

#[test]
fn golden_without_modal_suppression() {
    let f = Format {
        modal: false,
        ..Format::DEFAULT
    };
    assert_eq!(
        golden(f),
        "G21 G90 G94 G17\nT1 M6\nG0 Z5\nS10000 M3\nG0 X1 Y2 Z5\nG1 X1 Y2 Z-1 F300\n\
         G1 X11.1235 Y2 Z-1 F1200\nG3 X13.1235 Y4 Z-1 I0 J2 F1200\nG0 X13.1235 Y4 Z5\nM5\nM30"
    );
}

#[test]
fn formats_a_dialect_cannot_write_are_refused_with_the_reason() {
    let inch = Format {
        units: Units::Inch,
        ..Format::DEFAULT
    };
    let e = program_text_with(&tiny(), &options(PostDialect::Sinumerik), &inch).unwrap_err();
    assert!(e.contains("millimetres only"), "{e}");
    let e = program_text_with(&tiny(), &options(PostDialect::Legacy2006), &inch).unwrap_err();
    assert!(e.contains("no unit word"), "{e}");
    let wild = Format {
        numbers: Numbers::Decimal { places: 9 },
        ..Format::DEFAULT
    };
    let e = program_text_with(&tiny(), &options(PostDialect::LinuxCnc), &wild).unwrap_err();
    assert!(e.contains("precision 9"), "{e}");
}

#[test]
fn sinumerik_reader_names_a_bad_word() {
    let e = sinumerik_to_ngc("N10 G01 X12.5\n").unwrap_err();
    assert_eq!(e, "line 1: cannot read word 'X12.5'");
}

#[test]
fn sinumerik_end_puts_the_tool_away_after_the_last_motion() {
    let text = program_text(&sample(), &options(PostDialect::Sinumerik)).unwrap();
    let ngc = sinumerik_to_ngc(&text).unwrap();
    let canon = read_back(&text, &options(PostDialect::Sinumerik)).unwrap();
    let last_motion = canon.iter().rposition(|c| c.op.is_motion()).unwrap();
    let put_away = canon
        .iter()
        .rposition(|c| c.op == CanonOp::ChangeTool(99))
        .unwrap_or_else(|| panic!("{ngc}"));
    assert!(put_away > last_motion, "{ngc}\n{:?}", &canon[last_motion..]);
}
