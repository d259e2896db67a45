//! The posts' programs: grbl's tool-change pauses and settings, the printed moves against the toolpath, and the interpreter reading them back.
use oficina_cam::{Move, Operation, Tool, Toolpath};
use oficina_canon::CanonOp;
use oficina_post::{program_text, PostDialect, PostOptions};

fn two_tool_path() -> Toolpath {
    let op = |n: u32, spec: &str, moves: Vec<Move>| Operation {
        name: format!("op{n}"),
        tool_number: n,
        tool: spec.parse::<Tool>().unwrap(),
        spindle_rpm: 18000.0,
        moves,
    };
    Toolpath {
        safe_z: 5.0,
        operations: vec![
            op(
                1,
                "flat:12",
                vec![
                    Move::Rapid {
                        to: [1.0, 2.0, 5.0],
                    },
                    Move::Line {
                        to: [1.0, 2.0, -1.25],
                        feed: 500.0 / 60.0,
                    },
                    Move::Line {
                        to: [10.0, 2.0, -1.25],
                        feed: 2000.0 / 60.0,
                    },
                    Move::Line {
                        to: [10.0, 2.0, -1.25],
                        feed: 2000.0 / 60.0,
                    },
                    Move::Arc {
                        to: [12.0, 4.0, -1.25],
                        center: [10.0, 4.0],
                        ccw: true,
                        feed: 2000.0 / 60.0,
                    },
                    Move::Dwell(0.5),
                    Move::Rapid {
                        to: [12.0, 4.0, 5.0],
                    },
                ],
            ),
            op(
                2,
                "ball:3",
                vec![
                    Move::Rapid {
                        to: [0.0, 0.0, 5.0],
                    },
                    Move::Line {
                        to: [0.5, 0.25, -0.00004],
                        feed: 10.0,
                    },
                ],
            ),
        ],
    }
}

fn options(dialect: PostDialect) -> PostOptions {
    PostOptions {
        dialect,
        allow_m6: false,
        title: "test (relief)".into(),
        settings: vec![
            ("image".into(), "x.png".into()),
            ("tool".into(), "ball:3".into()),
        ],
    }
}

/// An independent reading of the few words the post writes: modal G0/G1/G2/G3 with X Y Z.
fn endpoints(text: &str) -> Vec<(char, [f64; 3])> {
    let mut pos = [f64::NAN; 3];
    let mut modal = ' ';
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with('(') {
            continue;
        }
        let mut moved = false;
        for word in line.split_whitespace() {
            let (letter, value) = word.split_at(1);
            match letter {
                "G" if ["0", "1", "2", "3"].contains(&value) => {
                    modal = if value == "0" { 'r' } else { 'f' }
                }
                "X" | "Y" | "Z" => {
                    let k = "XYZ".find(letter).unwrap();
                    pos[k] = value.parse().unwrap();
                    moved = true;
                }
                _ => {}
            }
        }
        if moved {
            out.push((modal, pos));
        }
    }
    out
}

#[test]
fn grbl_program_pauses_for_tool_changes_and_documents_settings() {
    let text = program_text(&two_tool_path(), &options(PostDialect::Grbl)).unwrap();
    assert!(text.contains("(image = x.png)"));
    assert!(text.contains("(test [relief])"));
    assert!(text.contains("G21 G90 G94 G17"));
    assert!(
        !text
            .lines()
            .any(|l| !l.starts_with('(') && l.contains("M6")),
        "{text}"
    );
    assert!(text.contains("M0"));
    assert!(text.contains("(MSG, Change to T2: ball:3"));
    assert!(text.contains("G3 X12 Y4 I0 J2"));
    assert!(text.contains("G4 P0.5"));
    assert!(
        text.contains("Y0.25 Z0 F600"),
        "a depth under 0.05 µm prints as 0, never -0: {text}"
    );
    assert!(text.trim_end().ends_with("M30"));
    let linuxcnc = program_text(
        &two_tool_path(),
        &PostOptions {
            allow_m6: false,
            ..options(PostDialect::LinuxCnc)
        },
    )
    .unwrap();
    assert!(linuxcnc.contains("T1 M6") && linuxcnc.contains("T2 M6"));
}

#[test]
fn printed_moves_are_the_toolpaths_moves() {
    let tp = two_tool_path();
    let text = program_text(&tp, &options(PostDialect::Grbl)).unwrap();
    let printed = endpoints(&text);
    let mut wanted = vec![('r', [f64::NAN, f64::NAN, 5.0])];
    let mut pos = [f64::NAN, f64::NAN, 5.0];
    for c in tp.canon() {
        let (kind, to) = match c.op {
            CanonOp::StraightTraverse { to } => ('r', to),
            CanonOp::StraightFeed { to } | CanonOp::ArcFeed { end: to, .. } => ('f', to),
            _ => continue,
        };
        let to = [to.x, to.y, to.z];
        if to == pos {
            continue; // zero-length moves are dropped
        }
        if kind == 'r' && to[2] == 5.0 && pos[2] == 5.0 && to[0] == pos[0] && to[1] == pos[1] {
            continue;
        }
        wanted.push((kind, to));
        pos = to;
    }
    // Retracts the post adds before a tool change and at the end.
    let filtered: Vec<_> = printed
        .iter()
        .filter(|(k, p)| !(*k == 'r' && p[2] == 5.0))
        .collect();
    let wanted: Vec<_> = wanted
        .iter()
        .filter(|(k, p)| !(*k == 'r' && p[2] == 5.0))
        .collect();
    assert_eq!(filtered.len(), wanted.len(), "{text}");
    for (a, b) in filtered.iter().zip(&wanted) {
        assert_eq!(a.0, b.0);
        for k in 0..3 {
            assert!((a.1[k] - b.1[k]).abs() < 1e-4, "{a:?} vs {b:?}");
        }
    }
}

/// The interpreter reads back exactly the toolpath's moves and tool changes, in both
/// dialects, without a single diagnostic.
#[test]
fn interpreter_reads_back_the_toolpath() {
    use oficina_gcode::{canon_of, RunOptions};
    let tp = two_tool_path();
    let motions = |ops: Vec<oficina_canon::Canon>| -> Vec<(char, [f64; 3])> {
        let mut out = Vec::new();
        for c in ops {
            let (kind, to) = match c.op {
                CanonOp::StraightTraverse { to } => ('r', to),
                CanonOp::StraightFeed { to } => ('f', to),
                CanonOp::ArcFeed { end, .. } => ('a', end),
                CanonOp::SelectTool(n) => ('t', oficina_canon::Pos::xyz(n as f64, 0.0, 0.0)),
                _ => continue,
            };
            let p = [to.x, to.y, to.z];
            // Retracts and repeated positions are the post's own additions.
            if kind == 'r' && p[2] == tp.safe_z {
                continue;
            }
            if out
                .last()
                .is_some_and(|l: &(char, [f64; 3])| l.1 == p && l.0 == kind)
            {
                continue;
            }
            out.push((kind, p));
        }
        out
    };
    let want = motions(tp.canon());
    for (dialect, gdialect) in [
        (PostDialect::Grbl, oficina_gcode::Dialect::Grbl),
        (PostDialect::LinuxCnc, oficina_gcode::Dialect::LinuxCnc),
    ] {
        let text = program_text(&tp, &options(dialect)).unwrap();
        let (ops, diags) = canon_of(
            &text,
            &RunOptions {
                dialect: gdialect,
                ..RunOptions::default()
            },
        );
        assert!(diags.is_empty(), "{dialect:?}: {diags:?}\n{text}");
        let got = motions(ops);
        assert_eq!(got.len(), want.len(), "{dialect:?}: {got:?} vs {want:?}");
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(g.0, w.0);
            for k in 0..3 {
                assert!(
                    (g.1[k] - w.1[k]).abs() < 1e-4,
                    "{dialect:?}: {g:?} vs {w:?}"
                );
            }
        }
    }
}
