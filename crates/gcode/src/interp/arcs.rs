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
    oficina_geom::center_from_offsets(pt(start), pt(end), pt(center), tol).map(|c| [c.x, c.y])
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
