//! G2/G3 centres from the two ways a block gives them (centre I J K, or radius R) through the
//! one arc module, `oficina_geom`, with LinuxCNC's tolerances for the program's units
//! (interp_arc.cc). Lengths are the program's plane coordinates (first, second axis), mm.

use oficina_canon::Units;
use oficina_geom::Point;
pub(crate) use oficina_geom::{ArcError, ArcTolerance};

/// LinuxCNC's tolerances for programs in `units`, in mm. The √2 and the "both exceeded"
/// rule were measured against `rs274` (see tests).
pub(crate) fn tolerance(units: Units) -> ArcTolerance {
    match units {
        Units::Inch => ArcTolerance::LINUXCNC_INCH,
        Units::Mm => ArcTolerance::LINUXCNC_MM,
    }
}

fn pt(p: [f64; 2]) -> Point {
    Point::new(p[0], p[1])
}

/// Centre from the start point and a centre given absolutely (G90.1) or as an offset.
pub(crate) fn center_from_offsets(
    start: [f64; 2],
    end: [f64; 2],
    center: [f64; 2],
    tol: &ArcTolerance,
) -> Result<[f64; 2], ArcError> {
    if surely_within(start, end, center, tol) {
        return Ok(center);
    }
    oficina_geom::center_from_offsets(pt(start), pt(end), pt(center), tol).map(|c| [c.x, c.y])
}

/// Whether the arc module's check certainly accepts `center` (both radii finite and at
/// least `tol.radius`, radii differing by at most `tol.min_abs`), decided on the squared
/// radii d1, d2, without its two square roots. Any doubt answers false and the caller
/// runs the check itself, so the answer (Ok of the same centre) never changes.
///
/// Radius floor: d ≥ 1.000001·radius² gives √d ≥ 1.0000005·radius, which rounding (one
/// ulp, 1e-16 relative) cannot take below `radius`.
/// Difference: |r1 − r2| = |d1 − d2| / (r1 + r2), and (r1 + r2)² ≥ d1 + d2, so
/// (d1 − d2)² ≤ (min_abs / 2)²·(d1 + d2) bounds it by min_abs / 2. With d ≤ 1e20 (r ≤ 1e10
/// mm) the roundings of the arc module's √ and subtraction stay below 1e-5 mm, far inside
/// the other half of min_abs (≥ 0.0025 mm for every tolerance in use).
fn surely_within(start: [f64; 2], end: [f64; 2], center: [f64; 2], tol: &ArcTolerance) -> bool {
    let sq = |p: [f64; 2]| {
        let (dx, dy) = (p[0] - center[0], p[1] - center[1]);
        dx * dx + dy * dy
    };
    let (d1, d2) = (sq(start), sq(end));
    let floor = tol.radius * tol.radius * 1.000001;
    let half = 0.5 * tol.min_abs;
    let diff = d1 - d2;
    // NaN fails every comparison: false.
    d1 >= floor && d2 >= floor && d1 <= 1e20 && d2 <= 1e20 && diff * diff <= half * half * (d1 + d2)
}

/// Centre from a radius: positive R gives the arc of at most a half circle, negative R the
/// longer one (NCMS p. 21). `clockwise` is G2.
pub(crate) fn center_from_radius(
    start: [f64; 2],
    end: [f64; 2],
    radius: f64,
    clockwise: bool,
    tol: &ArcTolerance,
) -> Result<[f64; 2], ArcError> {
    oficina_geom::center_from_radius(pt(start), pt(end), radius, clockwise, tol).map(|c| [c.x, c.y])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_form_picks_short_and_long_arcs() {
        let tol = tolerance(Units::Mm);
        // Quarter circle from (0,0) to (10,10), R10: CW short arc has its centre at (10,0).
        let c = center_from_radius([0.0, 0.0], [10.0, 10.0], 10.0, true, &tol).unwrap();
        assert!((c[0] - 10.0).abs() < 1e-9 && c[1].abs() < 1e-9);
        let c = center_from_radius([0.0, 0.0], [10.0, 10.0], -10.0, true, &tol).unwrap();
        assert!(c[0].abs() < 1e-9 && (c[1] - 10.0).abs() < 1e-9);
        let c = center_from_radius([0.0, 0.0], [10.0, 10.0], 10.0, false, &tol).unwrap();
        assert!(c[0].abs() < 1e-9 && (c[1] - 10.0).abs() < 1e-9);
        assert!(matches!(
            center_from_radius([0.0, 0.0], [2.0, 0.0], 0.9985, true, &tol),
            Err(ArcError::RadiusTooSmall { .. })
        ));
        assert!(center_from_radius([0.0, 0.0], [2.0, 0.0], 0.999, true, &tol).is_ok());
    }

    proptest::proptest! {
        /// The squared-radius shortcut says yes only where the arc module's check accepts:
        /// radii near the zero-radius floor, differences near min_abs, huge coordinates.
        #[test]
        fn the_shortcut_accepts_only_what_the_check_accepts(
            scale in proptest::sample::select(vec![1e-3, 1.0, 1e3, 1e9, 1e12]),
            cx in -1.0..1.0f64, cy in -1.0..1.0f64,
            angle in 0.0..6.3f64, angle2 in 0.0..6.3f64,
            r in 0.0..2.0f64,
            dr in -0.05..0.05f64,
            inch in proptest::bool::ANY,
        ) {
            let tol = tolerance(if inch { Units::Inch } else { Units::Mm });
            let c = [cx * scale, cy * scale];
            let r = r * scale.min(1.0);
            let on = |a: f64, r: f64| [c[0] + r * a.cos(), c[1] + r * a.sin()];
            let (start, end) = (on(angle, r), on(angle2, r + dr));
            let exact = oficina_geom::center_from_offsets(pt(start), pt(end), pt(c), &tol)
                .map(|p| [p.x, p.y]);
            if surely_within(start, end, c, &tol) {
                proptest::prop_assert_eq!(exact.clone(), Ok(c));
            }
            proptest::prop_assert_eq!(center_from_offsets(start, end, c, &tol), exact);
        }
    }

    #[test]
    fn the_shortcut_takes_ordinary_arcs_and_leaves_the_edges_to_the_check() {
        let tol = tolerance(Units::Mm);
        assert!(surely_within([0.0, 0.0], [10.0, 10.0], [10.0, 0.0], &tol));
        assert!(surely_within([0.0, 0.0], [20.01, 0.0], [10.0, 0.0], &tol));
        // 0.02 mm apart: accepted by the check (under 0.02·√2) but not surely.
        assert!(!surely_within([0.0, 0.0], [20.02, 0.0], [10.0, 0.0], &tol));
        assert!(center_from_offsets([0.0, 0.0], [20.02, 0.0], [10.0, 0.0], &tol).is_ok());
        // At the zero-radius floor, and not finite.
        assert!(!surely_within(
            [0.0, 0.0],
            [0.00254, 0.0],
            [0.00127, 0.0],
            &tol
        ));
        assert!(!surely_within(
            [f64::NAN, 0.0],
            [2.0, 0.0],
            [1.0, 0.0],
            &tol
        ));
        assert!(!surely_within(
            [-1e300, 0.0],
            [1e300, 0.0],
            [0.0, 0.0],
            &tol
        ));
    }

    #[test]
    fn spiral_tolerance_is_absolute_and_relative_as_measured_on_rs274() {
        let tol = tolerance(Units::Mm);
        let ok = |end: f64, c: f64| center_from_offsets([0.0, 0.0], [end, 0.0], [c, 0.0], &tol);
        // rs274: r=1: 2.0282 passes, 2.0284 fails; r=100: 200.1 passes, 200.15 fails.
        assert!(ok(2.0282, 1.0).is_ok());
        assert!(ok(2.0284, 1.0).is_err());
        assert!(ok(200.1, 100.0).is_ok());
        assert!(ok(200.15, 100.0).is_err());
        assert!(ok(2001.0, 1000.0).is_ok());
        assert!(ok(2001.1, 1000.0).is_err());
        let inch = tolerance(Units::Inch);
        let ok = |end: f64| center_from_offsets([0.0, 0.0], [end * 25.4, 0.0], [25.4, 0.0], &inch);
        assert!(ok(2.0025).is_ok());
        assert!(ok(2.003).is_err());
    }
}
