//! A pen machine: how the pen is lifted, the feeds, and the checks made before drawing
//! (workspace and joint limits, paper, acceleration ramps).

use oficina_geom::Point;
use oficina_motion::KinematicsKind;
use oficina_motion::Profile;
use oficina_motion::{for_profile, Kinematics};
use std::fmt;

/// How the pen goes down and up.
#[derive(Clone, Debug, PartialEq)]
pub enum PenLift {
    /// A Z axis: `down` and `up` heights, mm.
    Z {
        /// Drawing height, mm.
        down: f64,
        /// Lifted height, mm.
        up: f64,
    },
    /// A hobby servo on the spindle PWM (grbl): `M3 S<down>` to draw, `M5` to lift.
    Servo {
        /// The S value that puts the pen down.
        down: f64,
    },
    /// Lines of G-code sent as they are (e.g. `M280 P0 S30` on Marlin).
    Command {
        /// The line that puts the pen down.
        down: String,
        /// The line that lifts it.
        up: String,
    },
}

/// What the generated programs and the checks need to know about the machine.
#[derive(Clone, Debug, PartialEq)]
pub struct PenMachine {
    /// How the pen goes down and up.
    pub lift: PenLift,
    /// Drawing feed, mm/min.
    pub draw_feed: f64,
    /// Seconds to wait after the pen moves (the servo or solenoid settles).
    pub lift_dwell: f64,
    /// Where every program starts and ends, mm (the profile's start position).
    pub home: Point,
    /// Pause (M0) between pens so the operator can change it.
    pub pause_between_pens: bool,
    /// Servo angle that lifts the pen, degrees (Marlin's `M280 P0 S…`).
    pub servo_up: f64,
}

impl PenMachine {
    /// Defaults from a profile: the pen on Z (down at the bottom of Z travel, up at the
    /// top), drawing at the profile's default feed, homed at its start position.
    pub fn for_profile(p: &Profile) -> PenMachine {
        PenMachine {
            lift: PenLift::Z {
                down: p.travel[2][0],
                up: p.travel[2][1],
            },
            draw_feed: p.default_feed * 60.0,
            lift_dwell: 0.0,
            home: Point::new(p.start[0] - p.work_offset[0], p.start[1] - p.work_offset[1]),
            pause_between_pens: true,
            servo_up: 90.0,
        }
    }
}

/// Why a plot cannot be drawn on this machine.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlotError {
    /// A point the machine cannot reach.
    #[error("pen '{pen}', stroke {stroke}: point ({x:.3}, {y:.3}) mm {why}")]
    OutOfReach {
        /// The pen's name.
        pen: String,
        /// Stroke index within the pen.
        stroke: usize,
        /// X, mm.
        x: f64,
        /// Y, mm.
        y: f64,
        /// Why it is out of reach.
        why: String,
    },
    /// The drawing does not fit on the paper.
    #[error("the drawing ({w:.1} × {h:.1} mm at {x0:.1}, {y0:.1}) does not fit the paper {pw} × {ph} mm at the origin")]
    OffPaper {
        /// Drawing width, mm.
        w: f64,
        /// Drawing height, mm.
        h: f64,
        /// Drawing's lower-left X, mm.
        x0: f64,
        /// Drawing's lower-left Y, mm.
        y0: f64,
        /// Paper width, mm.
        pw: f64,
        /// Paper height, mm.
        ph: f64,
    },
    /// A joint's acceleration ramp is too short for a steady arm.
    #[error("joint {joint}: the acceleration ramp to full speed is {steps:.0} steps, fewer than the {min} the plot needs (raise max_rate or lower acceleration in the profile; a short ramp makes a heavy arm oscillate, seed 003)")]
    ShortRamp {
        /// The joint's name.
        joint: &'static str,
        /// Steps of the ramp.
        steps: f64,
        /// Steps the plot needs at least.
        min: f64,
    },
    /// The drawing has no strokes.
    #[error("nothing to draw: the drawing has no strokes")]
    Empty,
    /// The page layout cannot be made.
    #[error("layout: {0}")]
    Layout(String),
    /// A drawing setting (crop, passes, fill) out of range; says which.
    #[error("{0}")]
    Settings(String),
}

/// How far outside the travel a point may lie and still be on its edge, mm: a micron, far
/// below any step, so that y = −0.000 (a rounding of the layout or of the file) is inside.
pub const TRAVEL_TOL: f64 = 1e-3;

/// Moves points that lie within [`TRAVEL_TOL`] outside the Cartesian travel onto its edge, so
/// the program never asks for Y-0.0004 of a machine whose travel starts at 0.
pub fn snap_to_travel(plot: &mut crate::Plot, profile: &Profile) {
    let off = profile.work_offset;
    let snap = |v: f64, [lo, hi]: [f64; 2], o: f64| {
        let m = v + o;
        if m < lo && m >= lo - TRAVEL_TOL {
            lo - o
        } else if m > hi && m <= hi + TRAVEL_TOL {
            hi - o
        } else {
            v
        }
    };
    plot.map_points(|p| {
        Point::new(
            snap(p.x, profile.travel[0], off[0]),
            snap(p.y, profile.travel[1], off[1]),
        )
    });
}

/// Checks every point and segment of every stroke, and every pen-up move between them,
/// against the profile's Cartesian travel, kinematic reach and joint limits. Segments are
/// checked at points no more than `step` mm apart (a polar arm can leave its joint range
/// between two reachable ends).
pub fn check_reach(plot: &crate::Plot, profile: &Profile, step: f64) -> Result<(), PlotError> {
    let k = for_profile(profile);
    let off = profile.work_offset;
    let check = |pen: &str, stroke: usize, p: Point, near: &mut Option<[f64; 3]>| {
        let m = [p.x + off[0], p.y + off[1], profile.travel[2][1]];
        let bad = |why: String| PlotError::OutOfReach {
            pen: pen.to_string(),
            stroke,
            x: p.x,
            y: p.y,
            why,
        };
        for (i, axis) in ["x", "y"].iter().enumerate() {
            let [lo, hi] = profile.travel[i];
            if !(m[i] >= lo - TRAVEL_TOL && m[i] <= hi + TRAVEL_TOL) {
                return Err(bad(format!(
                    "lies outside the machine travel {axis} [{lo}, {hi}] (fit it on a page: --layout a3, or a smaller --scale)"
                )));
            }
        }
        let q = match near {
            Some(n) => k.joints_near(m, *n),
            None => k.joints(m),
        }
        .map_err(&bad)?;
        for (i, j) in profile.joints.iter().enumerate().take(2) {
            if let Some(lim) = j.as_ref().and_then(|j| j.limits) {
                if q[i] < lim[0] - 1e-9 || q[i] > lim[1] + 1e-9 {
                    let name = profile.kinematics.joint_names()[i];
                    let (v, lo, hi) = if profile.kinematics.is_angular(i) {
                        (q[i].to_degrees(), lim[0].to_degrees(), lim[1].to_degrees())
                    } else {
                        (q[i], lim[0], lim[1])
                    };
                    return Err(bad(format!(
                        "needs joint {name} = {v:.3}, outside its limits [{lo}, {hi}]"
                    )));
                }
            }
        }
        *near = Some(q);
        Ok(())
    };
    let mut near = None;
    let mut last = Point::new(profile.start[0] - off[0], profile.start[1] - off[1]);
    for pen in &plot.pens {
        for (si, s) in pen.strokes.iter().enumerate() {
            // The pen-up move to the stroke, then the stroke itself.
            for (a, b) in std::iter::once((last, s[0])).chain(s.windows(2).map(|w| (w[0], w[1]))) {
                let n = ((a.distance(b) / step).ceil() as usize).clamp(1, 1_000_000);
                for i in 1..=n {
                    check(&pen.name, si + 1, a.lerp(b, i as f64 / n as f64), &mut near)?;
                }
            }
            last = *s.last().unwrap();
        }
    }
    Ok(())
}

/// Checks that the drawing lies on a `w` × `h` mm sheet whose corner is the origin.
pub fn check_paper(plot: &crate::Plot, w: f64, h: f64) -> Result<(), PlotError> {
    let b = plot.bounds().ok_or(PlotError::Empty)?;
    if b[0] < -1e-9 || b[1] < -1e-9 || b[2] > w + 1e-9 || b[3] > h + 1e-9 {
        return Err(PlotError::OffPaper {
            w: b[2] - b[0],
            h: b[3] - b[1],
            x0: b[0],
            y0: b[1],
            pw: w,
            ph: h,
        });
    }
    Ok(())
}

/// One joint's acceleration ramp from rest to full speed: v/a seconds over v²/(2a) units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ramp {
    /// The joint's name.
    pub joint: &'static str,
    /// Ramp time, seconds.
    pub seconds: f64,
    /// In the joint's file units (degrees for the polar arm, mm otherwise).
    pub distance: f64,
    /// Ramp length in motor steps.
    pub steps: f64,
}

impl fmt::Display for Ramp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {:.3} s, {:.3} units, {:.0} steps",
            self.joint, self.seconds, self.distance, self.steps
        )
    }
}

/// The ramps of the XY joints of a profile.
pub fn ramps(profile: &Profile) -> Vec<Ramp> {
    let names = profile.kinematics.joint_names();
    (0..2)
        .filter_map(|i| {
            let j = profile.joints[i].as_ref()?;
            let d = j.max_rate * j.max_rate / (2.0 * j.acceleration);
            let unit = if profile.kinematics.is_angular(i) {
                d.to_degrees()
            } else {
                d
            };
            Some(Ramp {
                joint: names[i],
                seconds: j.max_rate / j.acceleration,
                distance: unit,
                steps: d * j.steps_per_unit,
            })
        })
        .collect()
}

/// Refuses a profile whose ramps are shorter than `min_steps` motor steps: the seed 003 arm
/// oscillated when braked until its ramps were given more steps.
pub fn check_ramps(profile: &Profile, min_steps: f64) -> Result<Vec<Ramp>, PlotError> {
    let r = ramps(profile);
    if let Some(bad) = r.iter().find(|r| r.steps < min_steps) {
        return Err(PlotError::ShortRamp {
            joint: bad.joint,
            steps: bad.steps,
            min: min_steps,
        });
    }
    Ok(r)
}

/// The highest drawing feed (mm/min) at which a stroke keeps the polar arm within its rate:
/// a Cartesian speed v moves the arm at most at ω = v / r_pen (r_pen = distance of the pen
/// from the pivot, dθ = (−sinθ dx + cosθ dy)/R and |.| ≤ v/R with R ≤ r), so v ≤ ω_max · R_min.
/// Other kinematics: `feed` unchanged.
pub fn arm_limited_feed(profile: &Profile, stroke: &[Point], feed: f64) -> f64 {
    let KinematicsKind::Polar { pen_offset } = profile.kinematics else {
        return feed;
    };
    let Some(theta) = profile.joints[0].as_ref() else {
        return feed;
    };
    let off = profile.work_offset;
    let r_min = stroke
        .iter()
        .map(|p| {
            let r2 = (p.x + off[0]).powi(2) + (p.y + off[1]).powi(2) - pen_offset * pen_offset;
            r2.max(0.0).sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    feed.min(theta.max_rate * r_min * 60.0).max(1.0)
}
