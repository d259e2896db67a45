//! Grading the shipped size-34 pattern to every size 33–44 (seed 001 eq. 3.2, 3.3): the
//! graded contour's width and length against the seed's constants worked by hand — each size
//! adds VL = 1.66 mm of width and VC = 6.66 mm of length (Brazilian/French; 2.10 / 8.46
//! English/US), and shrinkage adds CTM of the pattern's own width and length.

mod common;

use common::sole_sample;

use oficina_geom::{Grading, Point, Reference, SizeSystem};

fn extent(pts: &[Point]) -> (f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in pts {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    (x1 - x0, y1 - y0)
}

#[test]
fn sizes_33_to_44_from_34_add_the_seed_constants() {
    let pts = sole_sample();
    let (lp, cp) = extent(&pts);
    for (system, vl, vc) in [
        (SizeSystem::BRAZILIAN, 1.66, 6.66),
        (SizeSystem::ENGLISH, 2.10, 8.46),
    ] {
        for shrink in [0.0, 0.02] {
            let g = Grading::for_points(&pts, system, 34.0, shrink, Reference::Heel).unwrap();
            eprintln!(
                "{} shrink {} %: pattern {lp:.2} × {cp:.2} mm",
                system.name,
                shrink * 100.0
            );
            eprintln!("| size | α | β | width mm | length mm |");
            for n in 33..=44 {
                let n = n as f64;
                let (a, b) = g.factors(n);
                let (w, l) = extent(&g.points(&pts, n).unwrap());
                eprintln!("| {n} | {a:.4} | {b:.4} | {w:.2} | {l:.2} |");
                let want_w = lp + (n - 34.0) * vl + shrink * lp;
                let want_l = cp + (n - 34.0) * vc + shrink * cp;
                assert!(
                    (w - want_w).abs() < 1e-9,
                    "{} {n}: {w} vs {want_w}",
                    system.name
                );
                assert!(
                    (l - want_l).abs() < 1e-9,
                    "{} {n}: {l} vs {want_l}",
                    system.name
                );
            }
        }
    }
}
