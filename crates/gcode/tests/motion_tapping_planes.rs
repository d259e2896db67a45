//! G84 / G74 tapping in the G18 and G19 planes, where rs274 2.9 feeds away from the hole and
//! Oficina does the same on purpose (docs/linuxcnc-differences.md, "Tapping in G18/G19").
//!
//! rs274 positions the tap correctly but prints the two tapping feeds with their
//! coordinates permuted once more than the plane asks: with the cycle's in-plane
//! coordinates (aa, bb) and drilling axis cc,
//! - G18 (aa = Z, bb = X, cc = Y): it prints (cc, aa, bb) where (x, y, z) = (bb, cc, aa);
//! - G19 (aa = Y, bb = Z, cc = X): it prints (bb, cc, aa) where (x, y, z) = (cc, aa, bb).
//!
//! LinuxCNC's own tests (tests/interp/g84/g18, g19) expect exactly that, so a LinuxCNC
//! machine moves so: this test checks every move is rs274's verbatim.

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

fn numbers(line: &str) -> Vec<f64> {
    line[line.find('(').unwrap() + 1..line.rfind(')').unwrap()]
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect()
}

#[test]
fn taps_in_g18_and_g19_feed_where_rs274_feeds() {
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
        assert_eq!(o.split('(').next(), t.split('(').next(), "call {i}");
        for (x, y) in numbers(o).iter().zip(&numbers(t)) {
            assert!((x - y).abs() < 1e-4, "call {i}:\n ours   {o}\n rs274  {t}");
        }
    }
    // The first tap in G18 (X10 Z0, down Y to -10) feeds to X -10 Y 0 Z 10, as rs274 does.
    assert_eq!(numbers(&ours[3])[..3], [-10.0, 0.0, 10.0]);
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
