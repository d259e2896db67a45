//! SIN, COS and TAN of an angle in degrees, as precise as LinuxCNC's.
//!
//! LinuxCNC evaluates `sin((x * M_PIl) / 180.0)` in long double: C++ picks `sinl` for the
//! long double argument, so conversion and function both run with a 64-bit mantissa and the
//! result is the double nearest the true value. Plain `f64` arithmetic is one rounding
//! short: SIN[30] would be 0.49999999999999994 instead of 0.5, and `FIX[SIN[30]*2]` 0
//! instead of 1. Here the angle is reduced exactly in degrees, converted to radians as a
//! double-double and the series summed in double-double, then rounded once.

/// An unevaluated sum `hi + lo` with `|lo| <= ulp(hi)/2`: about 106 bits.
#[derive(Clone, Copy, Debug)]
struct Dd {
    hi: f64,
    lo: f64,
}

impl Dd {
    fn new(hi: f64) -> Dd {
        Dd { hi, lo: 0.0 }
    }

    /// Knuth's two-sum, then renormalise.
    fn add(self, o: Dd) -> Dd {
        let s = self.hi + o.hi;
        let bb = s - self.hi;
        let err = (self.hi - (s - bb)) + (o.hi - bb);
        let lo = err + self.lo + o.lo;
        let hi = s + lo;
        Dd {
            hi,
            lo: lo - (hi - s),
        }
    }

    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }

    fn mul(self, o: Dd) -> Dd {
        let p = self.hi * o.hi;
        let err = self.hi.mul_add(o.hi, -p) + (self.hi * o.lo + self.lo * o.hi);
        let hi = p + err;
        Dd {
            hi,
            lo: err - (hi - p),
        }
    }

    fn div(self, o: Dd) -> Dd {
        let q1 = self.hi / o.hi;
        let r = self.add(o.mul(Dd::new(q1)).neg());
        let q2 = r.hi / o.hi;
        Dd::new(q1).add(Dd::new(q2))
    }
}

/// π as a double-double.
const PI: Dd = Dd {
    hi: std::f64::consts::PI,
    lo: 1.2246467991473532e-16,
};

/// sin and cos of `t` radians, `|t| <= π/4`, by their Taylor series in double-double.
fn sin_cos_small(t: Dd) -> (Dd, Dd) {
    let t2 = t.mul(t);
    // Terms fall below 1e-33 of the sum by n = 27 for |t| <= π/4.
    let (mut sin, mut cos) = (t, Dd::new(1.0));
    let (mut s_term, mut c_term) = (t, Dd::new(1.0));
    let mut n = 1.0;
    while n < 27.0 {
        c_term = c_term.mul(t2).div(Dd::new(-(n * (n + 1.0))));
        s_term = s_term.mul(t2).div(Dd::new(-((n + 1.0) * (n + 2.0))));
        cos = cos.add(c_term);
        sin = sin.add(s_term);
        n += 2.0;
    }
    (sin, cos)
}

/// sin and cos of `deg` degrees (finite).
fn sin_cos_deg(deg: f64) -> (Dd, Dd) {
    // Exact reduction: fmod is exact, and the quadrant subtraction is exact because the
    // remainder and the multiple of 90 are within a factor of two (Sterbenz).
    // Negative angles by symmetry: adding 360 would round.
    let d = deg.abs() % 360.0;
    let quadrant = (d / 90.0).round();
    let y = d - quadrant * 90.0;
    let t = Dd::new(y).mul(PI).div(Dd::new(180.0));
    let (s, c) = sin_cos_small(t);
    let (s, c) = match quadrant as i64 % 4 {
        0 => (s, c),
        1 => (c, s.neg()),
        2 => (s.neg(), c.neg()),
        _ => (c.neg(), s),
    };
    if deg < 0.0 {
        (s.neg(), c)
    } else {
        (s, c)
    }
}

pub fn sin_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    let v = sin_cos_deg(x).0;
    v.hi + v.lo
}

pub fn cos_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    let v = sin_cos_deg(x).1;
    v.hi + v.lo
}

/// Infinite (an error for the caller) at odd multiples of 90°, where LinuxCNC returns a
/// huge number that depends on its rounding of π.
pub fn tan_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    let (s, c) = sin_cos_deg(x);
    if c.hi == 0.0 {
        return f64::INFINITY;
    }
    let v = s.div(c);
    v.hi + v.lo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_at_the_special_angles() {
        assert_eq!(sin_deg(30.0), 0.5);
        assert_eq!(cos_deg(60.0), 0.5);
        assert_eq!(sin_deg(90.0), 1.0);
        assert_eq!(sin_deg(180.0), 0.0);
        assert_eq!(cos_deg(90.0), 0.0);
        assert_eq!(tan_deg(45.0), 1.0);
        assert_eq!(tan_deg(-45.0), -1.0);
        assert_eq!(sin_deg(-30.0), -0.5);
        assert_eq!(sin_deg(390.0), 0.5);
        assert!(tan_deg(90.0).is_infinite());
    }

    #[test]
    fn agrees_with_f64_within_its_rounding_of_the_angle() {
        let mut x = -1000.0;
        while x < 1000.0 {
            let r = x * std::f64::consts::PI / 180.0;
            // The f64 reference carries the rounding of r: about |r| ulps of 1.
            let tol = 2.5e-16 * (1.0 + r.abs());
            assert!((sin_deg(x) - r.sin()).abs() < tol, "sin {x}");
            assert!((cos_deg(x) - r.cos()).abs() < tol, "cos {x}");
            x += 0.37;
        }
    }

    #[test]
    fn large_angles_reduce_exactly() {
        // sin(12345678901°) = sin(181°); rs274 prints -0.017452406433 (×1e6: -17452.406433).
        assert!((sin_deg(12345678901.0) - -0.017452406437283512).abs() < 1e-17);
    }
}
