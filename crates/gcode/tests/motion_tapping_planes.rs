//! G84 / G74 tapping in the G18 and G19 planes: the one place where Oficina differs from
//! rs274 on purpose (docs/linuxcnc-differences.md, "Tapping in G18/G19").
//!
//! rs274 2.9 positions the tap correctly (its traverses agree with ours) but prints the two
//! tapping feeds with their coordinates permuted once more than the plane asks: with the
//! cycle's in-plane coordinates (aa, bb) and drilling axis cc,
//! - G18 (aa = Z, bb = X, cc = Y): it prints (cc, aa, bb) where (x, y, z) = (bb, cc, aa);
//! - G19 (aa = Y, bb = Z, cc = X): it prints (bb, cc, aa) where (x, y, z) = (cc, aa, bb).
//!
//! The feeds would leave the hole (X −10 instead of X 10 below). Oficina taps along the
//! drilling axis; this test checks that its feeds are rs274's with that extra permutation
//! undone, and that every other move is rs274's verbatim.

#[path = "interp_support.rs"]
mod support;

use oficina_gcode::Dialect;
use oficina_gcode::StartState;

/// `rs274 -g` on the program below (motion lines, pasted verbatim). `F` marks the feeds.
const RS274: &str = "\
STRAIGHT_TRAVERSE(10.0000, 5.0000, 5.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_TRAVERSE(10.0000, 5.0000, 0.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_TRAVERSE(10.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_FEED(-10.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
DWELL(0.0000)
STRAIGHT_FEED(5.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_TRAVERSE(5.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_TRAVERSE(5.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_TRAVERSE(1.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
STRAIGHT_FEED(2.0000, -1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
DWELL(0.0000)
STRAIGHT_FEED(2.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)
";

const PROGRAM: &str = "G21 G90\nS300 M3\nG18 G0 X10 Z5 Y5\nG98 G84 X10 Y-10 Z0 R2 F150\nG80\nG19 M4 G0 X5 Y0 Z0\nG99 G74 Y1 Z2 X-1 R1\nG80\nM2\n";

/// rs274's feed with the extra permutation undone, for the plane it was made in.
fn undo(plane: &str, v: [f64; 3]) -> [f64; 3] {
    match plane {
        // printed (cc, aa, bb) = (y, z, x)
        "G18" => [v[2], v[0], v[1]],
        // printed (bb, cc, aa) = (z, x, y)
        _ => [v[1], v[2], v[0]],
    }
}

fn numbers(line: &str) -> Vec<f64> {
    line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()]
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect()
}

#[test]
fn taps_run_along_the_drilling_axis_in_g18_and_g19() {
    let r = support::run_with(
        PROGRAM,
        Dialect::LinuxCnc,
        Default::default(),
        StartState::default(),
    );
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    let ours = support::motion_text(&r.ops);
    let theirs: Vec<&str> = RS274.lines().collect();
    assert_eq!(ours.len(), theirs.len(), "{}", ours.join("\n"));
    for (i, (o, t)) in ours.iter().zip(&theirs).enumerate() {
        let (a, mut b) = (numbers(o), numbers(t));
        if t.starts_with("STRAIGHT_FEED") {
            let plane = if i < 6 { "G18" } else { "G19" };
            let fixed = undo(plane, [b[0], b[1], b[2]]);
            b[..3].copy_from_slice(&fixed);
        }
        assert_eq!(o.split('(').next(), t.split('(').next(), "call {i}");
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x - y).abs() < 1e-4,
                "call {i}:\n ours   {o}\n rs274  {t} (undone {b:?})"
            );
        }
    }
    // The first tap in G18 goes down to Y −10 at X 10 Z 0 and back out to Y 5 (G98).
    assert_eq!(numbers(&ours[3])[..3], [10.0, -10.0, 0.0]);
    assert_eq!(numbers(&ours[5])[..3], [10.0, 5.0, 0.0]);
    // The G19 tap goes to X −1 at Y 1 Z 2 and back to R (X 1, G99).
    assert_eq!(numbers(&ours[9])[..3], [-1.0, 1.0, 2.0]);
    assert_eq!(numbers(&ours[11])[..3], [1.0, 1.0, 2.0]);
}

#[test]
fn polar_words_and_diameter_mode_reach_the_end_point() {
    // @ radius ^ angle about the program origin (G91: added to the current ones); G7
    // halves X words only. Expected: rs274 -g on the same program.
    let (calls, diags) = support::rs274_calls(
        "G21 G90\nG0 @10 ^90\nG91 G0 ^90\nG90 G18 G7 G0 X20 Z1\nG8 G0 X20\nM2\n",
    );
    assert!(diags.is_empty(), "{diags:?}");
    let moves: Vec<&String> = calls.iter().filter(|c| c.starts_with("STRAIGHT")).collect();
    let want = [
        [0.0, 10.0, 0.0],
        [-10.0, 0.0, 0.0],
        [10.0, 0.0, 1.0],
        [20.0, 0.0, 1.0],
    ];
    assert_eq!(moves.len(), want.len(), "{moves:?}");
    for (m, w) in moves.iter().zip(want) {
        let n = numbers(m);
        assert!(
            n[..3].iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-4),
            "{m} vs {w:?}"
        );
    }
}
