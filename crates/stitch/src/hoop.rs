//! The seed's hoops (§4.3, Appendix I): the 17 MARCO hoops, 11 round and 6 oval, and the
//! choice of the smallest one a design fits in. The design's origin is the hoop centre.
//! Ovals lie with their long axis along X: the table's Y travel is 220 mm, exactly the short
//! side of the three largest ovals, while X has 350 mm. The needle keeps `CLEARANCE` from
//! the ring (the seed gives no figure; the presser foot and the ring's lip need room).

use crate::plan::StitchPlan;
use std::fmt;

/// mm kept between any needle point and the inside of the ring.
pub const CLEARANCE: f64 = 5.0;

/// The inside of a hoop's ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HoopShape {
    /// A round ring.
    Round {
        /// Inside diameter, mm.
        diameter: f64,
    },
    /// Inside sizes, `width` along X ≥ `height` along Y.
    Oval {
        /// Inside width along X, mm.
        width: f64,
        /// Inside height along Y, mm.
        height: f64,
    },
}

/// A hoop of the seed's list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hoop {
    /// The seed's code: C01..C11 round, O01..O06 oval.
    pub code: &'static str,
    /// The MARCO type number.
    pub marco_type: u8,
    /// The ring's inside.
    pub shape: HoopShape,
}

const fn round(code: &'static str, marco_type: u8, diameter: f64) -> Hoop {
    Hoop {
        code,
        marco_type,
        shape: HoopShape::Round { diameter },
    }
}

const fn oval(code: &'static str, marco_type: u8, height: f64, width: f64) -> Hoop {
    Hoop {
        code,
        marco_type,
        shape: HoopShape::Oval { width, height },
    }
}

/// Appendix I's values (the menu's OCR reads 0 as 8; these are the reliable ones).
pub const HOOPS: [Hoop; 17] = [
    round("C01", 3, 100.0),
    round("C02", 4, 120.0),
    round("C03", 5, 135.0),
    round("C04", 6, 150.0),
    round("C05", 7, 165.0),
    round("C06", 8, 175.0),
    round("C07", 9, 190.0),
    round("C08", 10, 200.0),
    round("C09", 11, 225.0),
    round("C10", 12, 285.0),
    round("C11", 13, 325.0),
    oval("O01", 1, 110.0, 160.0),
    oval("O02", 2, 180.0, 240.0),
    oval("O03", 3, 220.0, 280.0),
    oval("O04", 4, 200.0, 300.0),
    oval("O05", 5, 220.0, 340.0),
    oval("O06", 6, 220.0, 360.0),
];

impl Hoop {
    /// `round-190`, `oval-220x340`.
    pub fn name(&self) -> String {
        match self.shape {
            HoopShape::Round { diameter } => format!("round-{diameter}"),
            HoopShape::Oval { width, height } => format!("oval-{height}x{width}"),
        }
    }

    /// Area inside the ring, mm².
    pub fn area(&self) -> f64 {
        match self.shape {
            HoopShape::Round { diameter } => std::f64::consts::PI * diameter * diameter / 4.0,
            HoopShape::Oval { width, height } => std::f64::consts::PI * width * height / 4.0,
        }
    }

    /// How far (mm, along the ray from the centre) the point lies beyond the sewing field,
    /// ≤ 0 inside.
    pub fn overflow(&self, x: f64, y: f64) -> f64 {
        let r = x.hypot(y);
        match self.shape {
            HoopShape::Round { diameter } => r - (diameter / 2.0 - CLEARANCE),
            HoopShape::Oval { width, height } => {
                let (a, b) = (width / 2.0 - CLEARANCE, height / 2.0 - CLEARANCE);
                if r == 0.0 {
                    return -b;
                }
                // The field's boundary along the ray: ρ·(cos, sin) with (ρc/a)² + (ρs/b)² = 1.
                let (c, s) = (x / r, y / r);
                r - 1.0 / ((c / a).powi(2) + (s / b).powi(2)).sqrt()
            }
        }
    }

    /// Where the plan leaves the field: the farthest point and by how much, if anywhere.
    pub fn check(&self, plan: &StitchPlan) -> Result<(), HoopError> {
        let worst = plan
            .entries()
            .map(|(_, s)| (self.overflow(s.x, s.y), s.x, s.y))
            .fold(None, |acc: Option<(f64, f64, f64)>, v| match acc {
                Some(a) if a.0 >= v.0 => Some(a),
                _ => Some(v),
            });
        match worst {
            Some((over, x, y)) if over > 0.0 => Err(HoopError {
                hoop: self.name(),
                x,
                y,
                overflow: over,
            }),
            _ => Ok(()),
        }
    }

    /// A hoop by name (`round-190`), seed code (`C07`) or `marco-9`-style round type.
    pub fn by_name(name: &str) -> Option<Hoop> {
        let n = name.trim().to_ascii_lowercase();
        HOOPS
            .iter()
            .find(|h| h.name() == n || h.code.to_ascii_lowercase() == n)
            .copied()
    }
}

impl fmt::Display for Hoop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.shape {
            HoopShape::Round { diameter } => {
                write!(
                    f,
                    "{} (round Ø{diameter} mm, MARCO type {})",
                    self.code, self.marco_type
                )
            }
            HoopShape::Oval { width, height } => write!(
                f,
                "{} (oval {height} × {width} mm, MARCO type {})",
                self.code, self.marco_type
            ),
        }
    }
}

/// A design that leaves a hoop's sewing field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("the design leaves hoop {hoop}: the point ({x:.1}, {y:.1}) mm is {overflow:.1} mm beyond its sewing field ({CLEARANCE} mm inside the ring)")]
pub struct HoopError {
    /// The hoop's code.
    pub hoop: String,
    /// X of the point, mm.
    pub x: f64,
    /// Y of the point, mm.
    pub y: f64,
    /// How far beyond the sewing field, mm.
    pub overflow: f64,
}

/// The smallest hoop (by area) the design fits, or the refusal of the largest, naming the
/// overflow.
pub fn smallest_hoop(plan: &StitchPlan) -> Result<Hoop, HoopError> {
    let mut hoops = HOOPS.to_vec();
    hoops.sort_by(|a, b| a.area().total_cmp(&b.area()));
    let mut last = None;
    for h in hoops {
        match h.check(plan) {
            Ok(()) => return Ok(h),
            Err(e) => {
                // Report the hoop that misses by the least.
                if last
                    .as_ref()
                    .is_none_or(|l: &HoopError| e.overflow < l.overflow)
                {
                    last = Some(e);
                }
            }
        }
    }
    Err(last.unwrap_or(HoopError {
        hoop: "none".into(),
        x: 0.0,
        y: 0.0,
        overflow: 0.0,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{ColorBlock, Kind, Stitch, Thread};

    fn square(half: f64) -> StitchPlan {
        let s = [(-half, -half), (half, -half), (half, half), (-half, half)]
            .map(|(x, y)| Stitch::new(x, y, Kind::Stitch))
            .to_vec();
        StitchPlan {
            name: "sq".into(),
            blocks: vec![ColorBlock {
                thread: Thread::rgb(0, 0, 0),
                stitches: s,
            }],
        }
    }

    #[test]
    fn the_smallest_fitting_hoop_is_chosen() {
        // A 60 mm square: corners 42.4 mm from the centre; round 100 gives 45 mm of field.
        assert_eq!(smallest_hoop(&square(30.0)).unwrap().code, "C01");
        // 80 mm square: corner radius 56.6 mm, too far for round 100 and 120 (55 mm field);
        // the 110 × 160 oval (field half-axes 75 × 50: (40/75)² + (40/50)² = 0.92 ≤ 1) is
        // smaller than round 135 and holds it.
        assert_eq!(smallest_hoop(&square(40.0)).unwrap().code, "O01");
        // 90 mm square: out of that oval ((45/50)² + (45/75)² = 1.17); round 135 (62.5 mm
        // field) misses the 63.6 mm corners; round 150 (70 mm) holds them.
        assert_eq!(smallest_hoop(&square(45.0)).unwrap().code, "C04");
    }

    #[test]
    fn a_design_too_big_is_refused_naming_the_overflow() {
        let e = smallest_hoop(&square(160.0)).unwrap_err();
        assert!(e.overflow > 0.0);
        assert!(e.to_string().contains("beyond its sewing field"), "{e}");
        let e = Hoop::by_name("round-100")
            .unwrap()
            .check(&square(40.0))
            .unwrap_err();
        assert!(
            (e.overflow - (40.0 * 2f64.sqrt() - 45.0)).abs() < 1e-9,
            "{e}"
        );
        assert_eq!(Hoop::by_name("c07").unwrap().name(), "round-190");
        assert_eq!(Hoop::by_name("oval-220x340").unwrap().code, "O05");
    }
}
