//! Properties of `close_and_chain` on random pieces: lines, arcs and Béziers on a coarse grid
//! (so ends meet often, within and outside the tolerance), random directions and layers. It
//! never panics, drops nothing, leaves every path continuous, and counts what it made.

use oficina_io::close_and_chain;
use oficina_io::geom::kurbo::CubicBez;
use oficina_io::geom::{Arc, Drawing, Path, Point, Segment};
use proptest::prelude::*;

/// A piece from grid point `a` to grid point `b` (2 mm grid) nudged by up to ±`jitter` mm:
/// kind 0 a line, 1 a Bézier, 2 a half circle on the chord.
fn piece(a: (i8, i8), b: (i8, i8), kind: u8, nudge: (f64, f64)) -> Option<Segment> {
    let p = Point::new(a.0 as f64 * 2.0 + nudge.0, a.1 as f64 * 2.0 + nudge.1);
    let q = Point::new(b.0 as f64 * 2.0, b.1 as f64 * 2.0);
    if p.distance(q) < 1e-6 {
        return None;
    }
    Some(match kind {
        0 => Segment::line(p, q),
        1 => Segment::Cubic(CubicBez::new(
            p,
            p.lerp(q, 0.3) + (0.5, 0.5),
            p.lerp(q, 0.7),
            q,
        )),
        _ => {
            let c = p.midpoint(q);
            Segment::Arc(Arc::new(
                c,
                p.distance(q) / 2.0,
                (p - c).atan2(),
                std::f64::consts::PI,
            ))
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn nothing_dropped_every_path_continuous_counts_consistent(
        pieces in prop::collection::vec(
            ((-3i8..3, -3i8..3), (-3i8..3, -3i8..3), 0u8..3, (-0.02f64..0.02, -0.02f64..0.02), 0u8..2),
            0..60,
        ),
        tol in prop_oneof![Just(0.0), Just(0.01), 0.0f64..0.05, Just(10.0), Just(f64::NAN)],
    ) {
        let mut d = Drawing::new();
        let mut segments_in = 0;
        let mut length_in = 0.0;
        for (a, b, kind, nudge, layer) in pieces {
            if let Some(s) = piece(a, b, kind, nudge) {
                segments_in += 1;
                length_in += s.length();
                d.push(if layer == 0 { "a" } else { "b" }, Path::new(vec![s], false));
            }
        }
        let paths_in = d.path_count();
        let r = close_and_chain(&mut d, tol);
        let paths_out = d.path_count();
        // Every piece is in some path (a joining line between arcs may be added).
        let segments_out: usize = d.paths().map(|p| p.segments.len()).sum();
        prop_assert!(segments_out >= segments_in);
        // Ends move by at most the tolerance: lengths change little (a joining line or a
        // nudged end adds or removes at most 2 × tolerance per junction).
        let length_out: f64 = d.paths().map(|p| p.length()).sum();
        let t = if tol.is_finite() { tol.clamp(0.0, 10.0) } else { 0.01 };
        prop_assert!((length_out - length_in).abs() <= 2.0 * t * segments_in as f64 + 1e-6);
        // Each result path is one loop or one open chain; the counts add up.
        prop_assert_eq!(r.loops() + r.open_paths(), paths_out);
        prop_assert!(paths_out <= paths_in);
        prop_assert_eq!(r.closed_in_file, 0);
        for p in d.paths() {
            for w in p.segments.windows(2) {
                prop_assert!(w[0].end().distance(w[1].start()) < 1e-6, "{:?}", p);
            }
            if p.closed {
                prop_assert!(p.start().unwrap().distance(p.end().unwrap()) < 1e-6, "{:?}", p);
            }
        }
        for o in &r.open {
            prop_assert!(o.largest_gap >= o.smallest_gap && o.smallest_gap >= 0.0, "{:?}", o);
            prop_assert!(o.paths > 0);
        }
    }
}
