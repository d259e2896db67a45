//! The grbl and seed-002 (2006) dialects.

#[path = "interp_support.rs"]
mod support;

use oficina_canon::{CanonOp, Pos};
use oficina_gcode::Dialect;
use oficina_gcode::StartState;
use support::{run_with, Run};

fn legacy(text: &str) -> Run {
    run_with(
        text,
        Dialect::Legacy2006,
        Default::default(),
        StartState::default(),
    )
}

fn sample(name: &str) -> String {
    let path = format!(
        "{}/../../samples/legacy-2006/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(path).unwrap()
}

/// (kind, end) of every motion: 'R' rapid, 'F' feed, 'A' arc.
fn moves(r: &Run) -> Vec<(char, [f64; 2])> {
    r.ops
        .iter()
        .filter_map(|c| match &c.op {
            CanonOp::StraightTraverse { to } => Some(('R', [to.x, to.y])),
            CanonOp::StraightFeed { to } => Some(('F', [to.x, to.y])),
            CanonOp::ArcFeed { end, .. } => Some(('A', [end.x, end.y])),
            _ => None,
        })
        .collect()
}

#[test]
fn table7_triangle_runs_the_same_in_g90_and_g91() {
    let want = vec![
        ('R', [15.0, 10.0]),
        ('F', [35.0, 10.0]),
        ('F', [25.0, 17.0]),
        ('F', [15.0, 10.0]),
    ];
    for name in [
        "table7-triangle-absolute.nc",
        "table7-triangle-incremental.nc",
    ] {
        let r = legacy(&sample(name));
        assert!(r.errors.is_empty(), "{name}: {:?}", r.errors);
        assert_eq!(moves(&r), want, "{name}");
    }
}

#[test]
fn table10_arcs_use_absolute_centres() {
    // Seed: "G2 X11 Y2 I1 J1 from X2 Y11 has its centre at X1 Y1" (L1268).
    for (name, turns) in [("table10-arc-cw.nc", -1), ("table10-arc-ccw.nc", 1)] {
        let r = legacy(&sample(name));
        assert!(r.errors.is_empty(), "{name}: {:?}", r.errors);
        let arc = r.ops.iter().find_map(|c| match &c.op {
            CanonOp::ArcFeed { center, turns, .. } => Some((*center, *turns)),
            _ => None,
        });
        assert_eq!(arc, Some(([1.0, 1.0], turns)), "{name}");
    }
}

#[test]
fn table15_test1_programs_run_unchanged() {
    for n in 1..=4 {
        let name = format!("table15-test1-program{n}.nc");
        let r = legacy(&sample(&name));
        assert!(r.errors.is_empty(), "{name}: {:?}", r.errors);
        let m = moves(&r);
        assert_eq!(m.iter().filter(|(k, _)| *k == 'A').count(), 4, "{name}");
        // Every arc is a quarter circle about the origin with radius 80 or 160.
        let mut prev = [0.0f64, 0.0];
        for (kind, end) in &m {
            if *kind == 'A' {
                let (r0, r1) = (prev[0].hypot(prev[1]), end[0].hypot(end[1]));
                assert!(
                    (r0 - r1).abs() < 1e-9 && (r0 == 80.0 || r0 == 160.0),
                    "{name}"
                );
                assert!(
                    (prev[0] * end[0] + prev[1] * end[1]).abs() < 1e-9,
                    "quarter: {name}"
                );
            }
            prev = *end;
        }
    }
    // Program 1 closes its contour where it began.
    let r = legacy(&sample("table15-test1-program1.nc"));
    assert_eq!(moves(&r).first().unwrap().1, [0.0, -80.0]);
    assert_eq!(moves(&r).last().unwrap().1, [0.0, -80.0]);
}

#[test]
fn legacy_feed_comes_from_the_start_state() {
    let start = StartState {
        feed: 1234.0,
        ..StartState::default()
    };
    let r = run_with("G90 X1\n", Dialect::Legacy2006, Default::default(), start);
    assert!(r.ops.iter().any(|c| c.op == CanonOp::SetFeedRate(1234.0)));
    assert!(r.ops.iter().any(|c| c.op
        == CanonOp::StraightFeed {
            to: Pos::xyz(1.0, 0.0, 0.0)
        }));
}

fn grbl_code(text: &str) -> Option<u16> {
    let r = run_with(
        text,
        Dialect::Grbl,
        Default::default(),
        StartState::default(),
    );
    r.errors.first().and_then(|e| e.code)
}

#[test]
fn grbl_rejects_what_grbl_rejects_with_its_numbers() {
    assert_eq!(grbl_code("G59.1\n"), Some(29));
    assert_eq!(grbl_code("G0 Z5\nG81 X1 Y1 Z-1 R2 F100\n"), Some(20));
    assert_eq!(grbl_code("F100 G53 G2 X1 I1\n"), Some(30));
    assert_eq!(grbl_code("G41 D1\n"), Some(20));
    assert_eq!(grbl_code("M6 T1\n"), Some(20));
    // Two axis commands: gcode.c fails on the axis conflict (24) before the modal group
    // (21), as grblHAL's Simulator answers.
    assert_eq!(grbl_code("G0 G1 X1\n"), Some(24));
    assert_eq!(grbl_code("G17 G18\n"), Some(21));
    assert_eq!(grbl_code("X1 X2\n"), Some(25));
    assert_eq!(grbl_code("G1 X1\n"), Some(22));
    assert_eq!(grbl_code("G80 X1\n"), Some(31));
    assert_eq!(grbl_code("F100 G2 Z1 I1\n"), Some(32));
    assert_eq!(grbl_code("F100 G2 X20 R5\n"), Some(34));
    assert_eq!(grbl_code("F100 G2 X10 Y0\n"), Some(35));
    assert_eq!(grbl_code("G1 F100 X1\nG2 X5 Y0 I1 J0\nM2\n"), Some(33));
    // What grbl accepts runs.
    assert_eq!(grbl_code("G21 G90 G54 G17 G94\nG1 F100 X1 Y1\nG2 X3 Y1 I1 J0\nG4 P0.5\nG10 L20 P1 X0\nG28\nG92 X0\nG43.1 Z1\nM3 S1000\nM8\nM5 M9\nM2\n"), None);
    let r = run_with(
        "G59.1\n",
        Dialect::Grbl,
        Default::default(),
        StartState::default(),
    );
    assert!(r.errors[0]
        .help
        .as_deref()
        .unwrap()
        .contains("G59.x work coordinate systems are not supported."));
}

fn grbl(text: &str) -> Run {
    run_with(
        text,
        Dialect::Grbl,
        Default::default(),
        StartState::default(),
    )
}

#[test]
fn grbl_starts_in_g0_so_bare_axis_words_move() {
    // grbl's gc_init zeroes the modal state: motion mode G0, so `G91 X1` is a rapid.
    let r = grbl("G91 X1\nY2\n");
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    assert_eq!(moves(&r), vec![('R', [1.0, 0.0]), ('R', [1.0, 2.0])]);
    // LinuxCNC has no motion mode at start: the same block is an error there.
    let r = run_with(
        "G91 X1\n",
        Dialect::LinuxCnc,
        Default::default(),
        StartState::default(),
    );
    assert!(
        r.errors[0].message.contains("without a g code"),
        "{:?}",
        r.errors
    );
}

#[test]
fn grbl_g10_checks_axis_words_before_l_and_p() {
    assert_eq!(grbl_code("G10 L2 P1\n"), Some(26));
    assert_eq!(grbl_code("G10 L20 P1\n"), Some(26));
    assert_eq!(grbl_code("G10 L3 P1\n"), Some(26));
    assert_eq!(grbl_code("G10 L2 X1\n"), Some(28));
    assert_eq!(grbl_code("G10 P1 X1\n"), Some(28));
    assert_eq!(grbl_code("G10 L2 P7 X1\n"), Some(29));
    assert_eq!(grbl_code("G10 L3 P1 X1\n"), Some(20));
    assert_eq!(grbl_code("G10 L2 P1 R5 X1\n"), Some(20));
    // The offset is still set when the block is whole.
    let r = grbl("G10 L2 P1 X10\nG54 G0 X0\n");
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    assert_eq!(moves(&r).last(), Some(&('R', [10.0, 0.0])));
}

#[test]
fn grbl_probes_feed_straight_to_the_target() {
    for code in ["G38.2", "G38.3", "G38.4", "G38.5"] {
        let r = grbl(&format!("G21 G90 F100\n{code} Z-5\nX2\n"));
        assert!(r.errors.is_empty(), "{code}: {:?}", r.errors);
        let feeds: Vec<Pos> = r
            .ops
            .iter()
            .filter_map(|c| match &c.op {
                CanonOp::StraightFeed { to } => Some(*to),
                _ => None,
            })
            .collect();
        // No probe input: the move ends at the target; the motion mode then is G1.
        assert_eq!(
            feeds,
            vec![Pos::xyz(0.0, 0.0, -5.0), Pos::xyz(2.0, 0.0, -5.0)],
            "{code}"
        );
    }
    // grbl's G38 errors, in gcode.c's order: feed, axis words, target.
    assert_eq!(grbl_code("G38.2 Z-5\n"), Some(22));
    assert_eq!(grbl_code("F100 G38.2\n"), Some(26));
    assert_eq!(grbl_code("F100 G38.2 Z0\n"), Some(33));
    assert_eq!(grbl_code("F100 G91 G38.2 Z0 X0\n"), Some(33));
    // Inverse time wants F in the probing block itself.
    assert_eq!(grbl_code("F100\nG93 G38.2 Z-5\n"), Some(22));
    assert_eq!(grbl_code("G93 G38.2 Z-5 F100\n"), None);
    assert_eq!(grbl_code("F100 G38.1 Z-5\n"), Some(20));
}

#[test]
fn the_legacy_dialect_still_refuses_probing() {
    let r = run_with(
        "G21 G90 F100\nG38.2 Z-5\n",
        Dialect::Legacy2006,
        Default::default(),
        StartState::default(),
    );
    assert_eq!(r.errors.len(), 1);
    let e = &r.errors[0];
    assert_eq!(e.message, "Unknown g code used: G38.2");
    assert_eq!(e.span.line, 2);
    assert!(e.help.as_deref().unwrap().contains("probing"));
}

/// LinuxCNC's dialect probes as the standalone rs274 does (the corpus program
/// `lcnc_probe_straight` compares the printed calls): one `StraightProbe` to the target, then
/// the feeds the machine makes, to the target and back 0.254 mm (saicanon's 0.01 in) towards
/// the start, where the next move begins.
#[test]
fn linuxcnc_probes_to_the_target_and_backs_off() {
    let r = run_with(
        "G21 G90 F100\nG0 X3 Z4\nG38.2 Z-5\nG91 G1 X1\n",
        Dialect::LinuxCnc,
        Default::default(),
        StartState::default(),
    );
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    let probe: Vec<&CanonOp> = r
        .ops
        .iter()
        .filter(|c| c.line == 3)
        .map(|c| &c.op)
        .collect();
    assert_eq!(
        probe,
        [
            &CanonOp::StraightProbe {
                to: Pos::xyz(3.0, 0.0, -5.0),
                feeds: 2
            },
            &CanonOp::StraightFeed {
                to: Pos::xyz(3.0, 0.0, -5.0)
            },
            &CanonOp::StraightFeed {
                to: Pos::xyz(3.0, 0.0, -5.0 + 0.254)
            },
        ]
    );
    let next = r.ops.iter().find(|c| c.line == 4).map(|c| &c.op);
    assert_eq!(
        next,
        Some(&CanonOp::StraightFeed {
            to: Pos::xyz(4.0, 0.0, -5.0 + 0.254)
        })
    );
}
