//! Cutting tools as radial profiles.
//!
//! Every tool is a solid of revolution that is closed upwards: its lower surface is
//! `z = tip + profile(ρ)` for radial distance `ρ`. The cutter occupies `ρ ≤ cutting radius`,
//! the shank (when wider) sits `flute_length` above the tip. Drop-cutter and the stock
//! simulator need nothing else.

use serde::{Deserialize, Serialize};
use std::fmt;

/// The cutting end's shape.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum CutterShape {
    /// Flat end mill.
    Flat,
    /// Ball nose: radius = diameter / 2.
    Ball,
    /// V bit with this included angle (degrees); `diameter` is the widest cutting diameter.
    V {
        /// Included angle, degrees.
        angle: f64,
    },
    /// Bull nose (flat with rounded corners of this radius).
    Bull {
        /// Corner radius, mm.
        corner_radius: f64,
    },
    /// Tapered ball: `diameter` is the tip ball's diameter, the flanks open at `angle`
    /// degrees per side.
    Taper {
        /// Flank angle per side, degrees.
        angle: f64,
    },
}

/// A cutter's shape and size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tool {
    /// The cutting end's shape.
    pub shape: CutterShape,
    /// Cutting diameter in mm (the tip ball's for a tapered ball).
    pub diameter: f64,
    /// Length of the cutting part, mm: above it the shank begins.
    pub flute_length: f64,
    /// Shank (or holder) diameter, mm. Only matters when wider than the cutter.
    pub shank_diameter: f64,
}

/// Why a tool spec is refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ToolError {
    /// The spec does not parse.
    #[error("tool '{text}': {problem}. Write shape:diameter, e.g. ball:6, flat:12, v:12:60, bull:10:2, taper:1:3")]
    Syntax {
        /// The spec as given.
        text: String,
        /// What is wrong with it.
        problem: String,
    },
    /// The sizes do not make a cutter; says why.
    #[error("tool: {0}")]
    Invalid(String),
}

impl Tool {
    /// A tool of `shape` and `diameter` (mm), flute and shank from the diameter.
    pub fn new(shape: CutterShape, diameter: f64) -> Result<Tool, ToolError> {
        let mut tool = Tool {
            shape,
            diameter,
            flute_length: 0.0,
            shank_diameter: 0.0,
        };
        // Defaults: flutes long enough for the cone/taper to reach its full width, at least
        // 25 mm (seed 004's default) and the shank no wider than the cutter.
        tool.flute_length = match shape {
            CutterShape::V { angle } => {
                (diameter / 2.0 / (angle.to_radians() / 2.0).tan()).max(25.0)
            }
            _ => 25.0,
        };
        tool.shank_diameter = tool.cutting_radius() * 2.0;
        tool.validate()?;
        tool.shank_diameter = tool.cutting_radius() * 2.0;
        Ok(tool)
    }

    /// Checks every dimension; call after editing fields.
    pub fn validate(&self) -> Result<(), ToolError> {
        let bad = |what: &str, v: f64| {
            ToolError::Invalid(format!("{what} must be a finite number above 0, got {v}"))
        };
        let positive = |what: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(bad(what, v))
            }
        };
        positive("diameter", self.diameter)?;
        positive("flute length", self.flute_length)?;
        if self.diameter > 200.0 {
            return Err(ToolError::Invalid(format!(
                "diameter {} mm is larger than any router bit (max 200)",
                self.diameter
            )));
        }
        match self.shape {
            CutterShape::V { angle } if !(angle > 0.0 && angle < 180.0) => {
                Err(ToolError::Invalid(format!("V angle must be between 0 and 180 degrees, got {angle}")))
            }
            CutterShape::Taper { angle } if !(angle > 0.0 && angle < 60.0) => {
                Err(ToolError::Invalid(format!("taper angle per side must be between 0 and 60 degrees, got {angle}")))
            }
            CutterShape::Bull { corner_radius } if !(corner_radius > 0.0 && corner_radius <= self.diameter / 2.0) => Err(
                ToolError::Invalid(format!("corner radius must be above 0 and at most half the diameter, got {corner_radius}")),
            ),
            _ => {
                if self.shank_diameter.is_finite() && self.shank_diameter >= 0.0 && self.shank_diameter <= 400.0 {
                    Ok(())
                } else {
                    Err(bad("shank diameter", self.shank_diameter))
                }
            }
        }
    }

    /// Radius, mm.
    pub fn radius(&self) -> f64 {
        self.diameter / 2.0
    }

    /// Widest radius of the cutting part.
    pub fn cutting_radius(&self) -> f64 {
        match self.shape {
            CutterShape::Taper { angle } => {
                let (r, a) = (self.radius(), angle.to_radians());
                let (rho_t, z_t) = (r * a.cos(), r - r * a.sin());
                (rho_t + (self.flute_length - z_t).max(0.0) * a.tan()).max(rho_t)
            }
            _ => self.radius(),
        }
    }

    /// Radius of everything that can touch the work: cutter or shank.
    pub fn reach_radius(&self) -> f64 {
        self.cutting_radius().max(self.shank_diameter / 2.0)
    }

    /// Height above the tip of the tool's lower surface at radial distance `rho`, or `None`
    /// outside the tool.
    pub fn profile(&self, rho: f64) -> Option<f64> {
        let rc = self.cutting_radius();
        if rho <= rc {
            Some(
                self.cutter_profile(rho)
                    .min(self.flute_length.max(self.cutter_profile(rc))),
            )
        } else if rho <= self.shank_diameter / 2.0 {
            Some(self.flute_length.max(self.cutter_profile(rc)))
        } else {
            None
        }
    }

    fn cutter_profile(&self, rho: f64) -> f64 {
        let r = self.radius();
        match self.shape {
            CutterShape::Flat => 0.0,
            CutterShape::Ball => r - (r * r - rho * rho).max(0.0).sqrt(),
            CutterShape::V { angle } => rho / (angle.to_radians() / 2.0).tan(),
            CutterShape::Bull { corner_radius: rc } => {
                let flat = r - rc;
                if rho <= flat {
                    0.0
                } else {
                    let u = rho - flat;
                    rc - (rc * rc - u * u).max(0.0).sqrt()
                }
            }
            CutterShape::Taper { angle } => {
                let a = angle.to_radians();
                let rho_t = r * a.cos();
                if rho <= rho_t {
                    r - (r * r - rho * rho).max(0.0).sqrt()
                } else {
                    (r - r * a.sin()) + (rho - rho_t) / a.tan()
                }
            }
        }
    }

    /// Radius of the flat bottom (0 for pointed or round tips).
    pub fn flat_radius(&self) -> f64 {
        match self.shape {
            CutterShape::Flat => self.radius(),
            CutterShape::Bull { corner_radius } => self.radius() - corner_radius,
            _ => 0.0,
        }
    }

    /// Step-over (mm) that leaves scallops of at most `h` mm between parallel passes on a
    /// flat floor: twice the radius where the profile rises to `h`. For a ball this is
    /// `2·sqrt(2·r·h − h²)`; capped at 90 % of the cutting diameter so passes still overlap.
    pub fn stepover_for_scallop(&self, h: f64) -> f64 {
        let cap = 1.8 * self.cutting_radius();
        if !(h > 0.0) {
            return 0.0;
        }
        let (mut lo, mut hi) = (0.0f64, self.cutting_radius());
        if self.cutter_profile(hi) <= h {
            return cap;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.cutter_profile(mid) <= h {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (2.0 * lo).min(cap)
    }

    /// The `shape:diameter[:param]` text this tool parses from.
    pub fn spec(&self) -> String {
        match self.shape {
            CutterShape::Flat => format!("flat:{}", self.diameter),
            CutterShape::Ball => format!("ball:{}", self.diameter),
            CutterShape::V { angle } => format!("v:{}:{}", self.diameter, angle),
            CutterShape::Bull { corner_radius } => {
                format!("bull:{}:{}", self.diameter, corner_radius)
            }
            CutterShape::Taper { angle } => format!("taper:{}:{}", self.diameter, angle),
        }
    }
}

impl fmt::Display for Tool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} (flutes {} mm, shank {} mm)",
            self.spec(),
            self.flute_length,
            self.shank_diameter
        )
    }
}

impl std::str::FromStr for Tool {
    type Err = ToolError;

    /// `flat:12`, `ball:6`, `v:12:60`, `bull:10:2`, `taper:1:3`; optional trailing
    /// `,flute=L,shank=D`.
    fn from_str(text: &str) -> Result<Tool, ToolError> {
        let syntax = |problem: String| ToolError::Syntax {
            text: text.to_string(),
            problem,
        };
        let mut parts = text.split(',');
        let head = parts.next().unwrap_or("");
        let fields: Vec<&str> = head.split(':').map(str::trim).collect();
        let number = |i: usize, what: &str| -> Result<f64, ToolError> {
            let s = fields
                .get(i)
                .ok_or_else(|| syntax(format!("missing {what}")))?;
            s.parse::<f64>()
                .map_err(|_| syntax(format!("{what} '{s}' is not a number")))
        };
        let arity = |n: usize| {
            if fields.len() == n {
                Ok(())
            } else {
                Err(syntax(format!(
                    "expected {} fields separated by ':', got {}",
                    n,
                    fields.len()
                )))
            }
        };
        let shape = match fields[0].to_ascii_lowercase().as_str() {
            "flat" | "end" => {
                arity(2)?;
                CutterShape::Flat
            }
            "ball" => {
                arity(2)?;
                CutterShape::Ball
            }
            "v" | "vee" => {
                arity(3)?;
                CutterShape::V {
                    angle: number(2, "angle")?,
                }
            }
            "bull" => {
                arity(3)?;
                CutterShape::Bull {
                    corner_radius: number(2, "corner radius")?,
                }
            }
            "taper" => {
                arity(3)?;
                CutterShape::Taper {
                    angle: number(2, "angle per side")?,
                }
            }
            other => {
                return Err(syntax(format!(
                    "unknown shape '{other}' (flat, ball, v, bull, taper)"
                )))
            }
        };
        let mut tool = Tool::new(shape, number(1, "diameter")?)?;
        for option in parts {
            let (key, value) = option
                .split_once('=')
                .ok_or_else(|| syntax(format!("option '{option}' needs key=value")))?;
            let value: f64 = value.trim().parse().map_err(|_| {
                syntax(format!(
                    "option '{}' value '{}' is not a number",
                    key.trim(),
                    value.trim()
                ))
            })?;
            match key.trim() {
                "flute" => tool.flute_length = value,
                "shank" => tool.shank_diameter = value,
                other => return Err(syntax(format!("unknown option '{other}' (flute, shank)"))),
            }
        }
        tool.validate()?;
        Ok(tool)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_issue_syntax() {
        let t: Tool = "ball:6".parse().unwrap();
        assert_eq!(t.shape, CutterShape::Ball);
        assert_eq!(t.diameter, 6.0);
        let v: Tool = "v:12:60".parse().unwrap();
        assert_eq!(v.shape, CutterShape::V { angle: 60.0 });
        let b: Tool = "bull:10:2,flute=30,shank=12".parse().unwrap();
        assert_eq!((b.flute_length, b.shank_diameter), (30.0, 12.0));
        assert!("ball".parse::<Tool>().is_err());
        assert!("ball:x".parse::<Tool>().is_err());
        assert!("cone:3".parse::<Tool>().is_err());
        assert!("ball:-3".parse::<Tool>().is_err());
        assert!("v:6:200".parse::<Tool>().is_err());
        assert!("bull:6:4".parse::<Tool>().is_err());
    }

    #[test]
    fn profiles_match_the_shapes() {
        let ball: Tool = "ball:6".parse().unwrap();
        assert!((ball.profile(3.0).unwrap() - 3.0).abs() < 1e-12);
        assert!((ball.profile(0.0).unwrap()).abs() < 1e-12);
        assert!(ball.profile(3.01).is_none());
        let v: Tool = "v:10:90".parse().unwrap();
        assert!((v.profile(2.0).unwrap() - 2.0).abs() < 1e-12);
        let bull: Tool = "bull:10:2".parse().unwrap();
        assert_eq!(bull.profile(3.0), Some(0.0));
        assert!((bull.profile(5.0).unwrap() - 2.0).abs() < 1e-12);
        // The taper is continuous and tangent at the ball/cone joint.
        let taper: Tool = "taper:2:10".parse().unwrap();
        let rho_t = 1.0 * 10f64.to_radians().cos();
        let (a, b) = (
            taper.profile(rho_t - 1e-7).unwrap(),
            taper.profile(rho_t + 1e-7).unwrap(),
        );
        assert!((a - b).abs() < 1e-5);
        assert!(taper.cutting_radius() > 1.0 + 20.0 * 10f64.to_radians().tan());
    }

    #[test]
    fn shank_wider_than_cutter_sits_at_flute_length() {
        let t: Tool = "flat:3,flute=10,shank=6".parse().unwrap();
        assert_eq!(t.profile(1.0), Some(0.0));
        assert_eq!(t.profile(2.0), Some(10.0));
        assert_eq!(t.profile(3.5), None);
        assert_eq!(t.reach_radius(), 3.0);
    }

    #[test]
    fn ball_stepover_matches_the_closed_form() {
        let ball: Tool = "ball:6".parse().unwrap();
        for h in [0.001f64, 0.01, 0.05, 0.2] {
            let exact = 2.0 * (2.0 * 3.0 * h - h * h).sqrt();
            assert!(
                (ball.stepover_for_scallop(h) - exact).abs() < 1e-9,
                "h = {h}"
            );
        }
        let v: Tool = "v:10:90".parse().unwrap();
        assert!((v.stepover_for_scallop(0.1) - 0.2).abs() < 1e-9);
    }
}
