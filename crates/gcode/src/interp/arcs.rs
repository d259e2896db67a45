//! Arc centres from the two ways G2/G3 give them: centre offsets (I J K) or a radius (R),
//! with LinuxCNC's tolerances (interp_arc.cc). All lengths in the program's plane
//! coordinates (first, second axis), mm.

use oficina_canon::Units;

/// Tolerances of LinuxCNC, in program units, converted to mm by the caller's units.
pub struct ArcTolerance {
    /// Start or end radius below this is a zero-radius arc; also the slack for R arcs.
    pub radius: f64,
    /// End radius may differ from start radius by this much (absolute) …
    pub spiral_abs: f64,
    /// … or by this fraction of the larger radius: only when both are exceeded is it an error.
    pub spiral_rel: f64,
}

impl ArcTolerance {
    /// LinuxCNC: 0.00005 in (radius), 0.002·√2 in or 0.02·√2 mm and 0.1 % (spiral).
    /// The √2 and the "both exceeded" rule were measured against `rs274` (see tests).
    pub fn for_units(units: Units) -> ArcTolerance {
        match units {
            Units::Inch => ArcTolerance {
                radius: 0.00005 * 25.4,
                spiral_abs: 0.002 * std::f64::consts::SQRT_2 * 25.4,
                spiral_rel: 0.001,
            },
            Units::Mm => ArcTolerance {
                radius: 0.00127,
                spiral_abs: 0.02 * std::f64::consts::SQRT_2,
                spiral_rel: 0.001,
            },
        }
    }
}

/// Why an arc cannot be made, with the numbers the message needs.
#[derive(Debug, Clone, PartialEq)]
pub enum ArcError {
    ZeroRadius { r1: f64, r2: f64, center: [f64; 2] },
    RadiiDiffer { r1: f64, r2: f64, center: [f64; 2] },
    SameEndPoint,
    RadiusTooSmall { radius: f64, half_chord: f64 },
}

/// Centre from the start point and a centre given absolutely (G90.1) or as an offset.
pub fn center_from_offsets(
    start: [f64; 2],
    end: [f64; 2],
    center: [f64; 2],
    tol: &ArcTolerance,
) -> Result<[f64; 2], ArcError> {
    let r1 = (center[0] - start[0]).hypot(center[1] - start[1]);
    let r2 = (center[0] - end[0]).hypot(center[1] - end[1]);
    if r1 < tol.radius || r2 < tol.radius {
        return Err(ArcError::ZeroRadius { r1, r2, center });
    }
    let abs_err = (r1 - r2).abs();
    let rel_err = abs_err / r1.max(r2);
    if abs_err > tol.spiral_abs && rel_err > tol.spiral_rel {
        return Err(ArcError::RadiiDiffer { r1, r2, center });
    }
    Ok(center)
}

/// Centre from a radius: positive R gives the arc of at most a half circle, negative R the
/// longer one (NCMS p. 21). `clockwise` is G2.
pub fn center_from_radius(
    start: [f64; 2],
    end: [f64; 2],
    radius: f64,
    clockwise: bool,
    tol: &ArcTolerance,
) -> Result<[f64; 2], ArcError> {
    if start == end {
        return Err(ArcError::SameEndPoint);
    }
    let r = radius.abs();
    let mid = [(start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0];
    let mut half = (mid[0] - end[0]).hypot(mid[1] - end[1]);
    if half - r > tol.radius {
        return Err(ArcError::RadiusTooSmall {
            radius: r,
            half_chord: half,
        });
    }
    // A chord a hair longer than the diameter is taken as a half circle.
    if half / r > 1.0 - 1e-12 {
        half = r;
    }
    let chord_angle = (end[1] - start[1]).atan2(end[0] - start[0]);
    let theta = if clockwise == (radius > 0.0) {
        chord_angle - std::f64::consts::FRAC_PI_2
    } else {
        chord_angle + std::f64::consts::FRAC_PI_2
    };
    let offset = r * (half / r).asin().cos();
    Ok([mid[0] + offset * theta.cos(), mid[1] + offset * theta.sin()])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_form_picks_short_and_long_arcs() {
        let tol = ArcTolerance::for_units(Units::Mm);
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
        let tol = ArcTolerance::for_units(Units::Mm);
        let ok = |end: f64, c: f64| center_from_offsets([0.0, 0.0], [end, 0.0], [c, 0.0], &tol);
        // rs274: r=1: 2.0282 passes, 2.0284 fails; r=100: 200.1 passes, 200.15 fails.
        assert!(ok(2.0282, 1.0).is_ok());
        assert!(ok(2.0284, 1.0).is_err());
        assert!(ok(200.1, 100.0).is_ok());
        assert!(ok(200.15, 100.0).is_err());
        assert!(ok(2001.0, 1000.0).is_ok());
        assert!(ok(2001.1, 1000.0).is_err());
        let inch = ArcTolerance::for_units(Units::Inch);
        let ok = |end: f64| center_from_offsets([0.0, 0.0], [end * 25.4, 0.0], [25.4, 0.0], &inch);
        assert!(ok(2.0025).is_ok());
        assert!(ok(2.003).is_err());
    }
}
