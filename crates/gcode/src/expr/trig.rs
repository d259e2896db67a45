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

/// 1/n! for n = 0…27 as double-doubles (exact to about 106 bits, from exact fractions).
const INV_FACTORIAL: [Dd; 28] = [
    Dd { hi: 1.0, lo: 0.0 },
    Dd { hi: 1.0, lo: 0.0 },
    Dd { hi: 0.5, lo: 0.0 },
    Dd {
        hi: 0.16666666666666666,
        lo: 9.25185853854297e-18,
    },
    Dd {
        hi: 0.041666666666666664,
        lo: 2.3129646346357427e-18,
    },
    Dd {
        hi: 0.008333333333333333,
        lo: 1.1564823173178714e-19,
    },
    Dd {
        hi: 0.001388888888888889,
        lo: -5.300543954373577e-20,
    },
    Dd {
        hi: 0.0001984126984126984,
        lo: 1.7209558293420705e-22,
    },
    Dd {
        hi: 2.48015873015873e-05,
        lo: 2.1511947866775882e-23,
    },
    Dd {
        hi: 2.7557319223985893e-06,
        lo: -1.858393274046472e-22,
    },
    Dd {
        hi: 2.755731922398589e-07,
        lo: 2.3767714622250297e-23,
    },
    Dd {
        hi: 2.505210838544172e-08,
        lo: -1.448814070935912e-24,
    },
    Dd {
        hi: 2.08767569878681e-09,
        lo: -1.20734505911326e-25,
    },
    Dd {
        hi: 1.6059043836821613e-10,
        lo: 1.2585294588752098e-26,
    },
    Dd {
        hi: 1.1470745597729725e-11,
        lo: 2.0655512752830745e-28,
    },
    Dd {
        hi: 7.647163731819816e-13,
        lo: 7.03872877733453e-30,
    },
    Dd {
        hi: 4.779477332387385e-14,
        lo: 4.399205485834081e-31,
    },
    Dd {
        hi: 2.8114572543455206e-15,
        lo: 1.6508842730861433e-31,
    },
    Dd {
        hi: 1.5619206968586225e-16,
        lo: 1.1910679660273754e-32,
    },
    Dd {
        hi: 8.22063524662433e-18,
        lo: 2.2141894119604265e-34,
    },
    Dd {
        hi: 4.110317623312165e-19,
        lo: 1.4412973378659527e-36,
    },
    Dd {
        hi: 1.9572941063391263e-20,
        lo: -1.3643503830087908e-36,
    },
    Dd {
        hi: 8.896791392450574e-22,
        lo: -7.911402614872376e-38,
    },
    Dd {
        hi: 3.868170170630684e-23,
        lo: -8.843177655482344e-40,
    },
    Dd {
        hi: 1.6117375710961184e-24,
        lo: -3.6846573564509766e-41,
    },
    Dd {
        hi: 6.446950284384474e-26,
        lo: -1.9330404233703465e-42,
    },
    Dd {
        hi: 2.4795962632247976e-27,
        lo: -1.2953730964765229e-43,
    },
    Dd {
        hi: 9.183689863795546e-29,
        lo: 1.4303150396787322e-45,
    },
];

/// `Σ (-1)^k u^k / (first + 2k)!` for k = 0…13, by Horner's rule: with u = t², the series
/// of cos t (first = 0) and of sin t / t (first = 1). Terms fall below 1e-33 of the sum by
/// k = 13 for |t| <= π/4.
fn series(u: Dd, first: usize) -> Dd {
    let term = |k: usize| {
        let c = INV_FACTORIAL[first + 2 * k];
        if k.is_multiple_of(2) {
            c
        } else {
            c.neg()
        }
    };
    (0..13)
        .rev()
        .fold(term(13), |acc, k| acc.mul(u).add(term(k)))
}

fn sin_small(t: Dd) -> Dd {
    t.mul(series(t.mul(t), 1))
}

fn cos_small(t: Dd) -> Dd {
    series(t.mul(t), 0)
}

/// `deg` degrees (finite) reduced exactly: the quadrant (0…3) and the angle within it in
/// radians (|t| <= π/4), and whether `deg` was negative.
fn reduce(deg: f64) -> (i64, Dd, bool) {
    // Exact reduction: fmod is exact, and the quadrant subtraction is exact because the
    // remainder and the multiple of 90 are within a factor of two (Sterbenz).
    // Negative angles by symmetry: adding 360 would round.
    let d = deg.abs() % 360.0;
    let quadrant = (d / 90.0).round();
    let y = d - quadrant * 90.0;
    let t = Dd::new(y).mul(PI).div(Dd::new(180.0));
    (quadrant as i64 % 4, t, deg < 0.0)
}

/// sin and cos of `deg` degrees (finite).
fn sin_cos_deg(deg: f64) -> (Dd, Dd) {
    let (quadrant, t, negative) = reduce(deg);
    let (s, c) = (sin_small(t), cos_small(t));
    let (s, c) = match quadrant {
        0 => (s, c),
        1 => (c, s.neg()),
        2 => (s.neg(), c.neg()),
        _ => (c.neg(), s),
    };
    if negative {
        (s.neg(), c)
    } else {
        (s, c)
    }
}

pub fn sin_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    // Only the series the quadrant needs.
    let (quadrant, t, negative) = reduce(x);
    let v = match quadrant {
        0 => sin_small(t),
        1 => cos_small(t),
        2 => sin_small(t).neg(),
        _ => cos_small(t).neg(),
    };
    let v = if negative { v.neg() } else { v };
    v.hi + v.lo
}

pub fn cos_deg(x: f64) -> f64 {
    if !x.is_finite() {
        return f64::NAN;
    }
    let (quadrant, t, _) = reduce(x);
    let v = match quadrant {
        0 => cos_small(t),
        1 => sin_small(t).neg(),
        2 => cos_small(t).neg(),
        _ => sin_small(t),
    };
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
