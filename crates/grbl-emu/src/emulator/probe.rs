//! What the emulated probe input touches, in machine coordinates (mm): a stock block with a
//! tilted and warped top, a touch plate lying on it, a tool length setter, and the tool in
//! the spindle. The probe closes when the tool touches any of them (everything conducts,
//! as a plate clipped to the tool and a grounded block do together).
//!
//! The tool's tip is `length` below the machine Z (the spindle's reference point), on the
//! spindle axis; its side is a cylinder of `diameter`. Contact from above is judged at the
//! axis (exact for a flat top and for a pointed probe; on a warped top a wide flat tool
//! would touch the highest point under it first); contact from the side at the cylinder.

use std::f64::consts::TAU;

/// Diameter of a tool length setter's pad, mm (a common 10 mm button).
pub const SETTER_PAD: f64 = 10.0;

/// Most looks along one probing move (beyond 4 m of travel the steps grow).
const MAX_SAMPLES: f64 = 400_000.0;
/// Step along the move between the looks for a change, mm; bisection then finds the
/// change to far below a micron.
const SAMPLE_STEP: f64 = 0.01;

/// The tool in the spindle, as the probe sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tool {
    /// How far the tip is below the machine Z, mm: after a change to a longer tool the same
    /// surface is touched at a higher machine Z.
    pub length: f64,
    /// Diameter, mm: the side touches a block's side with the axis this far / 2 away.
    pub diameter: f64,
}

/// The stock: a block from `min` to `max` in X and Y, down to the table, whose top is
/// `top + tilt·(x, y) + warp·sin(2πx/λ)·sin(2πy/λ)` (machine mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stock {
    /// Lower X, Y corner.
    pub min: [f64; 2],
    /// Upper X, Y corner.
    pub max: [f64; 2],
    /// Machine Z of the top at machine X0 Y0 (the plane's constant).
    pub top: f64,
    /// The top's slope in X and Y (mm of Z per mm).
    pub tilt: [f64; 2],
    /// Amplitude of the warp, mm (0: flat).
    pub warp: f64,
    /// The warp's wavelength λ, mm.
    pub wavelength: f64,
}

impl Stock {
    /// A flat, level block.
    pub fn flat(min: [f64; 2], max: [f64; 2], top: f64) -> Stock {
        Stock {
            min,
            max,
            top,
            tilt: [0.0; 2],
            warp: 0.0,
            wavelength: 100.0,
        }
    }

    /// Machine Z of the top at machine (x, y).
    pub fn top_at(&self, x: f64, y: f64) -> f64 {
        let k = TAU / self.wavelength;
        self.top + self.tilt[0] * x + self.tilt[1] * y + self.warp * (k * x).sin() * (k * y).sin()
    }
}

/// A touch plate lying on the stock: its top is the stock's top under it plus `thickness`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TouchPlate {
    /// Lower X, Y corner.
    pub min: [f64; 2],
    /// Upper X, Y corner.
    pub max: [f64; 2],
    /// Thickness, mm.
    pub thickness: f64,
}

/// A tool length setter: a round pad ([`SETTER_PAD`] across) centred at `at`, its top at
/// machine Z `top`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthSetter {
    /// Machine X, Y of the pad's centre.
    pub at: [f64; 2],
    /// Machine Z of the pad's top.
    pub top: f64,
}

/// Everything the probe can touch, and the tool that touches it. The default touches
/// nothing: every probe misses, as on a board without a probe wired.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ProbeModel {
    /// The stock block.
    pub stock: Option<Stock>,
    /// A touch plate on the stock (needs the stock).
    pub plate: Option<TouchPlate>,
    /// A tool length setter.
    pub setter: Option<LengthSetter>,
    /// The tool in the spindle.
    pub tool: Tool,
}

impl ProbeModel {
    /// Refuses a model that cannot be: non-finite numbers, empty rectangles, a plate with
    /// no stock under it, a negative thickness or tool, a warp without a wavelength.
    pub fn check(&self) -> Result<(), String> {
        let finite = |what: &str, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(format!("{what}: every number must be finite, got {v:?}"))
            }
        };
        let rect = |what: &str, min: [f64; 2], max: [f64; 2]| {
            finite(what, &[min[0], min[1], max[0], max[1]])?;
            if min[0] < max[0] && min[1] < max[1] {
                Ok(())
            } else {
                Err(format!(
                    "{what}: the first corner ({}, {}) must be below and left of the second ({}, {})",
                    min[0], min[1], max[0], max[1]
                ))
            }
        };
        if let Some(s) = &self.stock {
            rect("stock block", s.min, s.max)?;
            finite(
                "stock top",
                &[s.top, s.tilt[0], s.tilt[1], s.warp, s.wavelength],
            )?;
            if s.wavelength < 1.0 {
                return Err(format!(
                    "stock warp: the wavelength must be at least 1 mm, got {}",
                    s.wavelength
                ));
            }
        }
        if let Some(p) = &self.plate {
            rect("touch plate", p.min, p.max)?;
            finite("touch plate thickness", &[p.thickness])?;
            if p.thickness < 0.0 {
                return Err(format!(
                    "touch plate: the thickness cannot be negative, got {}",
                    p.thickness
                ));
            }
            if self.stock.is_none() {
                return Err("a touch plate lies on the stock: give the stock block too".into());
            }
        }
        if let Some(s) = &self.setter {
            finite("tool length setter", &[s.at[0], s.at[1], s.top])?;
        }
        finite("tool", &[self.tool.length, self.tool.diameter])?;
        if self.tool.diameter < 0.0 {
            return Err(format!(
                "tool: the diameter cannot be negative, got {}",
                self.tool.diameter
            ));
        }
        Ok(())
    }

    /// Whether the probe is closed with the machine at `p` (machine mm).
    pub fn touching(&self, p: [f64; 3]) -> bool {
        let r = self.tool.diameter / 2.0;
        let tip = p[2] - self.tool.length;
        let stock = self.stock.is_some_and(|s| {
            let (x, y) = clamp(p, s.min, s.max);
            reach(p, x, y) <= r && tip <= s.top_at(x, y)
        });
        let plate = match (&self.plate, &self.stock) {
            (Some(pl), Some(s)) => {
                let (x, y) = clamp(p, pl.min, pl.max);
                // It rests on the stock's top (an overhang stays at the edge's height).
                let (sx, sy) = clamp([x, y, 0.0], s.min, s.max);
                let base = s.top_at(sx, sy);
                reach(p, x, y) <= r && tip <= base + pl.thickness && tip >= base
            }
            _ => false,
        };
        let setter = self
            .setter
            .is_some_and(|s| reach(p, s.at[0], s.at[1]) <= r + SETTER_PAD / 2.0 && tip <= s.top);
        stock || plate || setter
    }

    /// The first point of the straight move `from` → `to` where the probe is no longer as
    /// it was at `from` (it closes, or for a move away it opens); `None` if it never
    /// changes. The move is looked along in 0.01 mm steps, then the change is
    /// bisected to 1e-7 mm; the point returned is on the changed side.
    pub fn first_change(&self, from: [f64; 3], to: [f64; 3]) -> Option<[f64; 3]> {
        let at = |t: f64| {
            [
                from[0] + (to[0] - from[0]) * t,
                from[1] + (to[1] - from[1]) * t,
                from[2] + (to[2] - from[2]) * t,
            ]
        };
        let start = self.touching(from);
        let length = oficina_grbl::dist(&from, &to);
        let n = (length / SAMPLE_STEP).ceil().clamp(1.0, MAX_SAMPLES) as usize;
        let mut before = 0.0;
        for k in 1..=n {
            let t = k as f64 / n as f64;
            if self.touching(at(t)) == start {
                before = t;
                continue;
            }
            let (mut lo, mut hi) = (before, t);
            while (hi - lo) * length > 1e-7 {
                let mid = (lo + hi) / 2.0;
                if self.touching(at(mid)) == start {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Some(at(hi));
        }
        None
    }
}

/// The point of the rectangle nearest to `p` in X and Y.
fn clamp(p: [f64; 3], min: [f64; 2], max: [f64; 2]) -> (f64, f64) {
    (p[0].clamp(min[0], max[0]), p[1].clamp(min[1], max[1]))
}

/// Distance in X and Y from the spindle axis at `p` to (x, y).
fn reach(p: [f64; 3], x: f64, y: f64) -> f64 {
    (p[0] - x).hypot(p[1] - y)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> ProbeModel {
        ProbeModel {
            stock: Some(Stock::flat([10.0, 20.0], [110.0, 80.0], -50.0)),
            plate: Some(TouchPlate {
                min: [50.0, 40.0],
                max: [70.0, 60.0],
                thickness: 12.7,
            }),
            setter: Some(LengthSetter {
                at: [-20.0, -20.0],
                top: -70.0,
            }),
            tool: Tool::default(),
        }
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-6)
    }

    #[test]
    fn straight_down_onto_stock_plate_and_setter() {
        let m = model();
        let hit = m.first_change([30.0, 30.0, -10.0], [30.0, 30.0, -80.0]);
        assert!(close(hit.unwrap(), [30.0, 30.0, -50.0]), "{hit:?}");
        let hit = m.first_change([60.0, 50.0, -10.0], [60.0, 50.0, -80.0]);
        assert!(close(hit.unwrap(), [60.0, 50.0, -37.3]), "{hit:?}");
        // On the setter's pad 4 mm off its centre; and a tool 12.5 mm longer.
        let mut long = m;
        long.tool.length = 12.5;
        let hit = long.first_change([-16.0, -20.0, 0.0], [-16.0, -20.0, -100.0]);
        assert!(close(hit.unwrap(), [-16.0, -20.0, -57.5]), "{hit:?}");
        // Beside the pad: nothing.
        assert_eq!(
            m.first_change([-14.0, -20.0, 0.0], [-14.0, -20.0, -100.0]),
            None
        );
    }

    #[test]
    fn the_side_is_touched_by_the_cylinder_and_away_opens() {
        let mut m = model();
        m.tool.diameter = 6.0;
        let hit = m.first_change([0.0, 30.0, -55.0], [30.0, 30.0, -55.0]);
        assert!(close(hit.unwrap(), [7.0, 30.0, -55.0]), "{hit:?}");
        // Starting in contact, the change is where contact is lost.
        assert!(m.touching([30.0, 30.0, -50.0]));
        let off = m.first_change([30.0, 30.0, -50.0], [30.0, 30.0, -40.0]);
        assert!(off.unwrap()[2] > -50.0 && off.unwrap()[2] < -50.0 + 1e-6);
    }

    #[test]
    fn tilted_and_warped_top() {
        let mut m = model();
        m.plate = None;
        let s = m.stock.as_mut().unwrap();
        s.tilt = [0.01, -0.02];
        s.warp = 0.3;
        s.wavelength = 40.0;
        let (x, y) = (37.0, 51.0);
        let expected =
            -50.0 + 0.01 * x - 0.02 * y + 0.3 * (TAU * x / 40.0).sin() * (TAU * y / 40.0).sin();
        let hit = m.first_change([x, y, 0.0], [x, y, -100.0]).unwrap();
        assert!((hit[2] - expected).abs() < 1e-6, "{hit:?} vs {expected}");
        // A slanted move hits the top where its line crosses the surface.
        let hit = m
            .first_change([20.0, 30.0, -40.0], [60.0, 70.0, -60.0])
            .unwrap();
        let top = m.stock.unwrap().top_at(hit[0], hit[1]);
        assert!((hit[2] - top).abs() < 1e-6);
    }

    #[test]
    fn impossible_models_are_refused() {
        let mut m = model();
        m.stock = None;
        assert!(m.check().unwrap_err().contains("stock"));
        let mut m = model();
        m.plate.as_mut().unwrap().thickness = -1.0;
        assert!(m.check().unwrap_err().contains("negative"));
        let mut m = model();
        m.stock.as_mut().unwrap().max = [0.0, 0.0];
        assert!(m.check().is_err());
        let mut m = model();
        m.tool.length = f64::NAN;
        assert!(m.check().unwrap_err().contains("finite"));
        assert!(model().check().is_ok());
        // Nothing to touch: nothing changes, and nothing panics on absurd numbers.
        let none = ProbeModel::default();
        assert_eq!(none.first_change([0.0; 3], [0.0, 0.0, -1e9]), None);
        assert_eq!(m.first_change([0.0; 3], [f64::NAN; 3]), None);
    }
}
