//! Machine profiles: the TOML description of a machine (joints, kinematics, travel and
//! planner settings), validated into [`Profile`] with every value in internal units
//! (mm, s, rad). See docs/machine-profiles.md for the format.

use crate::kinematics::{Check, RawKinematics};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

pub(crate) use crate::kinematics::KinematicsKind;

/// A bad profile: the file, the key (dotted path) and what is wrong with it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct ProfileError {
    /// The profile file.
    pub file: String,
    /// The key (dotted path) at fault.
    pub key: String,
    /// What is wrong with it.
    pub message: String,
}

impl fmt::Display for ProfileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}: {}: {}", self.file, self.key, self.message)
        }
    }
}

/// The velocity profile of every block: how speed changes between two feeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum VelocityProfile {
    /// Constant acceleration: speed ramps linearly (grbl).
    #[default]
    Trapezoid,
    /// Jerk-limited: acceleration ramps linearly, so it is continuous.
    SCurve,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HomingDirection {
    Negative,
    Positive,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homing {
    pub direction: HomingDirection,
    /// Fast search speed, unit/s.
    pub seek_rate: f64,
    /// Slow locate speed, unit/s.
    pub feed_rate: f64,
    /// Distance backed off the switch after homing, unit.
    pub pull_off: f64,
}

/// One motor-driven joint in internal units (mm or rad; seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint {
    /// Joint name (`x`, `y`, `z`, `a`...).
    pub name: &'static str,
    /// Motor steps per unit (mm, or rad inside; per degree for rotary joints in the file).
    pub steps_per_unit: f64,
    /// Top speed, units/s.
    pub max_rate: f64,
    /// Acceleration limit, units/s².
    pub acceleration: f64,
    /// Jerk limit, units/s³ (S-curve only).
    pub jerk: Option<f64>,
    /// Play taken up on each reversal, units.
    pub backlash: f64,
    /// The motor turns the other way (DIR level inverted).
    pub invert_direction: bool,
    /// Joint travel limits (besides the Cartesian ones), if any.
    pub limits: Option<[f64; 2]>,
    /// How the joint homes, if it does.
    pub homing: Option<Homing>,
}

/// A rotary joint: its motor and limits in degrees, and whether it turns without end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotary {
    /// Its motor and limits, degrees.
    pub joint: Joint,
    /// Turns without end (a 4th axis chuck): no travel limits, and the position shown to
    /// the operator is taken modulo 360° ([`Rotary::shown`]); the planner keeps counting
    /// whole turns so the motor never unwinds. Not wrapping: `joint.limits` (if any) hold.
    pub wrap: bool,
}

impl Rotary {
    /// The position shown for a joint at `deg`: in [0, 360) when it wraps.
    pub fn shown(&self, deg: f64) -> f64 {
        if self.wrap {
            deg.rem_euclid(360.0)
        } else {
            deg
        }
    }
}

/// Names of the rotary joints in a profile's `[joints.*]` tables, in A, B, C order.
pub(crate) const ROTARY_NAMES: [&str; 3] = ["a", "b", "c"];

/// A validated machine profile.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// The profile's name.
    pub name: String,
    /// Which kinematics, with its parameters.
    pub kinematics: KinematicsKind,
    /// Joint i drives `kinematics.joint_names()[i]`; `None` = that joint does not exist and
    /// must never move.
    pub joints: [Option<Joint>; 3],
    /// Rotary joints A, B, C (a router's 4th axis, a trunnion): each drives its axis one to
    /// one, in **degrees** as canon gives them (rates °/s, accelerations °/s² inside);
    /// `None` = no such axis, and a program that turns it is refused.
    pub rotary: [Option<Rotary>; 3],
    /// Cartesian soft limits [min, max] for X, Y, Z in mm.
    pub travel: [[f64; 2]; 3],
    /// Cartesian position at power-up (after homing), mm.
    pub start: [f64; 3],
    /// Corner blending tolerance (grbl's $11), mm.
    pub junction_deviation: f64,
    /// Largest chord sag when arcs become straight pieces, mm.
    pub arc_tolerance: f64,
    /// Largest distance of joint-linear motion from the Cartesian line, mm.
    pub path_tolerance: f64,
    /// How speed changes between feeds: trapezoid or S-curve.
    pub shape: VelocityProfile,
    /// Look-ahead horizon, seconds of motion.
    pub horizon: f64,
    /// Highest step rate of any motor, steps/s.
    pub max_step_rate: f64,
    /// Feed used until the program sets one, mm/s.
    pub default_feed: f64,
    /// The G54 work offset the machine keeps between jobs (grbl's EEPROM, LinuxCNC's .var),
    /// mm: where work zero sits in machine coordinates before a program sets its own.
    pub work_offset: [f64; 3],
    /// The machine's LinuxCNC tool table (`tool_table = "tools.tbl"`), relative to the
    /// profile file's folder once loaded by [`Profile::load`]; read by the commands that run
    /// programs when no `--tool-table` is given.
    pub tool_table: Option<std::path::PathBuf>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProfile {
    name: String,
    #[serde(default)]
    #[allow(dead_code)]
    description: Option<String>,
    kinematics: RawKinematics,
    travel: RawTravel,
    planner: RawPlanner,
    joints: BTreeMap<String, RawJoint>,
    #[serde(default)]
    work: Option<RawWork>,
    #[serde(default)]
    tool_table: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWork {
    g54: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTravel {
    x: [f64; 2],
    y: [f64; 2],
    #[serde(default)]
    z: Option<[f64; 2]>,
    start: Option<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlanner {
    junction_deviation: f64,
    arc_tolerance: f64,
    path_tolerance: Option<f64>,
    #[serde(default)]
    velocity_profile: Option<String>,
    horizon: Option<f64>,
    max_step_rate: f64,
    default_feed: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawJoint {
    steps_per_unit: f64,
    max_rate: f64,
    acceleration: f64,
    jerk: Option<f64>,
    #[serde(default)]
    backlash: f64,
    #[serde(default)]
    invert_direction: bool,
    limits: Option<[f64; 2]>,
    homing: Option<RawHoming>,
    /// Rotary joints only: turns without end.
    wrap: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawHoming {
    direction: String,
    seek_rate: f64,
    feed_rate: f64,
    #[serde(default)]
    pull_off: f64,
}

/// The stored G54 offset: work zero must lie inside the travel, or nothing could reach it.
fn work_offset(
    file: &str,
    work: Option<&RawWork>,
    travel: &[[f64; 2]; 3],
) -> Result<[f64; 3], ProfileError> {
    let Some(w) = work else { return Ok([0.0; 3]) };
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        let [lo, hi] = travel[i];
        if !w.g54[i].is_finite() || w.g54[i] < lo || w.g54[i] > hi {
            return Err(err(
                file,
                "work.g54",
                format!(
                    "{axis} = {} lies outside travel.{axis} [{lo}, {hi}]",
                    w.g54[i]
                ),
            ));
        }
    }
    Ok(w.g54)
}

impl Profile {
    /// Top speed of X, Y and Z in mm/min for a feed-rate figure; on machines whose joints
    /// are not the Cartesian axes (polar, polargraph, CoreXY) the slowest linear joint stands
    /// in. (`JointBound` gives the tighter joint-space bound.)
    pub fn axis_rapid_rates(&self) -> [f64; 3] {
        let rate = |j: &Option<Joint>| j.as_ref().map(|j| j.max_rate * 60.0);
        if self.kinematics == KinematicsKind::Cartesian {
            return [0, 1, 2].map(|i| rate(&self.joints[i]).unwrap_or(0.0));
        }
        let slowest = (0..3)
            .filter(|&i| !self.kinematics.is_angular(i))
            .filter_map(|i| rate(&self.joints[i]))
            .fold(f64::INFINITY, f64::min);
        if slowest.is_finite() {
            [slowest; 3]
        } else {
            [0.0; 3]
        }
    }

    /// The parameter values the machine holds at power-up, for the interpreter: the stored
    /// G54 offset in #5221…#5223 (LinuxCNC's numbering), in mm.
    pub fn initial_params(&self) -> Vec<(i64, f64)> {
        (0..3)
            .map(|i| (5221 + i as i64, self.work_offset[i]))
            .collect()
    }

    /// Reads and validates a profile file.
    pub fn load(path: &Path) -> Result<Profile, ProfileError> {
        let file = path.display().to_string();
        let meta = std::fs::metadata(path).map_err(|e| err(&file, "", e.to_string()))?;
        // Profiles are a few kB; refuse anything absurd before reading it whole.
        if meta.len() > 1 << 20 {
            return Err(err(
                &file,
                "",
                "file is larger than 1 MiB; not a machine profile".into(),
            ));
        }
        let text = std::fs::read_to_string(path).map_err(|e| err(&file, "", e.to_string()))?;
        let mut profile = Profile::parse(&text, &file)?;
        // A tool table named by the profile lives beside it, wherever the command runs.
        if let (Some(table), Some(dir)) = (&profile.tool_table, path.parent()) {
            profile.tool_table = Some(dir.join(table));
        }
        Ok(profile)
    }

    /// Parses and validates profile text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Profile, ProfileError> {
        let raw: RawProfile = toml::from_str(text).map_err(|e| {
            let msg = e.message().to_string();
            let at = e
                .span()
                .map(|s| {
                    let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
                    format!(" (line {line})")
                })
                .unwrap_or_default();
            err(file, "", format!("{msg}{at}"))
        })?;
        validate(raw, file)
    }

    /// Every joint in one list: the three of the kinematics (X, Y, Z on a Cartesian
    /// machine), then the rotary A, B, C.
    pub fn all_joints(&self) -> [Option<&Joint>; 6] {
        std::array::from_fn(|i| {
            if i < 3 {
                self.joints[i].as_ref()
            } else {
                self.rotary[i - 3].as_ref().map(|r| &r.joint)
            }
        })
    }

    /// Number of joints that exist.
    pub fn joint(&self, i: usize) -> Option<&Joint> {
        self.joints[i].as_ref()
    }
}

/// The profiles of the repository's `profiles/`, compiled in: (name, TOML text). Every
/// command finds a machine by these names, from any folder and with no install step.
pub const BUNDLED: &[(&str, &str)] = &[
    (
        "grbl-router",
        include_str!("../../../profiles/grbl-router.toml"),
    ),
    (
        "hotwire-xy",
        include_str!("../../../profiles/hotwire-xy.toml"),
    ),
    (
        "polar-plotter",
        include_str!("../../../profiles/polar-plotter.toml"),
    ),
    (
        "polargraph-wall",
        include_str!("../../../profiles/polargraph-wall.toml"),
    ),
    (
        "embroidery-xy",
        include_str!("../../../profiles/embroidery-xy.toml"),
    ),
    (
        "pen-plotter",
        include_str!("../../../profiles/pen-plotter.toml"),
    ),
    (
        "router-4axis",
        include_str!("../../../profiles/router-4axis.toml"),
    ),
];

/// The profile used when none is named: the seed 004 grbl router.
pub const DEFAULT: &str = "grbl-router";

/// The bundled profile `name` (with or without `.toml` or a leading folder), parsed.
pub fn bundled(name: &str) -> Option<Result<Profile, ProfileError>> {
    let name = name.trim_end_matches(".toml");
    let name = name.rsplit(['/', '\\']).next().unwrap_or(name);
    BUNDLED
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(n, text)| Profile::parse(text, &format!("<bundled {n}>")))
}

/// Finds a machine. A name (no folder, no `.toml`) is a bundled profile first, so what it
/// means never depends on the current folder; a file of that name is the fallback. A path
/// (with a folder or `.toml`) stays a path: a missing file is an error, never silently the
/// bundled profile of the same file name.
pub fn resolve(spec: &str) -> Result<Profile, ProfileError> {
    let path = Path::new(spec);
    let names = || {
        BUNDLED
            .iter()
            .map(|(n, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let is_path = spec.contains(['/', '\\']) || spec.ends_with(".toml");
    if !is_path {
        if let Some(p) = bundled(spec) {
            return p;
        }
    }
    if path.is_file() {
        return Profile::load(path);
    }
    let message = if is_path {
        let hint = bundled(spec)
            .map(|_| {
                let stem = spec.trim_end_matches(".toml");
                let stem = stem.rsplit(['/', '\\']).next().unwrap_or(stem);
                format!(
                    " (the bundled profile of that name is `{stem}`, without a folder or .toml)"
                )
            })
            .unwrap_or_default();
        format!("no such profile file{hint}; bundled profiles: {}", names())
    } else {
        format!(
            "no such profile file, and no bundled profile of that name (bundled: {})",
            names()
        )
    };
    Err(err(spec, "", message))
}

fn err(file: &str, key: &str, message: String) -> ProfileError {
    ProfileError {
        file: file.to_string(),
        key: key.to_string(),
        message,
    }
}

/// A rate, size or count: > 0, and within a range where times and distances computed from it
/// stay finite (the fuzzer found max_rate = 1e-308 making a move last forever).
fn positive(file: &str, key: &str, v: f64) -> Result<f64, ProfileError> {
    if v.is_finite() && (1e-9..=1e15).contains(&v) {
        Ok(v)
    } else {
        Err(err(
            file,
            key,
            format!("must be a number from 1e-9 to 1e15, > 0 (got {v})"),
        ))
    }
}

fn non_negative(file: &str, key: &str, v: f64) -> Result<f64, ProfileError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(err(
            file,
            key,
            format!("must be a finite number >= 0 (got {v})"),
        ))
    }
}

/// A chord or path tolerance, mm: below 0.1 µm no machine can tell, and moves would be cut
/// into pieces without end (the fuzzer found 5e-324).
fn tolerance(file: &str, key: &str, v: f64) -> Result<f64, ProfileError> {
    const MIN: f64 = 1e-4;
    if positive(file, key, v)? < MIN {
        return Err(err(
            file,
            key,
            format!("must be at least {MIN} mm (got {v})"),
        ));
    }
    Ok(v)
}

fn range(file: &str, key: &str, r: [f64; 2]) -> Result<[f64; 2], ProfileError> {
    if r.iter().all(|v| v.is_finite()) && r[0] <= r[1] {
        Ok(r)
    } else {
        Err(err(
            file,
            key,
            format!("must be [min, max] with min <= max (got {r:?})"),
        ))
    }
}

/// The checks above, lent to the kinematics settings readers.
struct FileCheck<'a>(&'a str);

impl Check for FileCheck<'_> {
    type Error = ProfileError;
    fn error(&self, key: &str, message: String) -> ProfileError {
        err(self.0, key, message)
    }
    fn positive(&self, key: &str, v: f64) -> Result<f64, ProfileError> {
        positive(self.0, key, v)
    }
    fn non_negative(&self, key: &str, v: f64) -> Result<f64, ProfileError> {
        non_negative(self.0, key, v)
    }
}

impl AsRef<KinematicsKind> for Profile {
    fn as_ref(&self) -> &KinematicsKind {
        &self.kinematics
    }
}

/// One `[joints.<name>]` table in internal units: lengths × `unit` (1 for mm and degrees,
/// π/180 for an angular joint kept in radians).
fn read_joint(
    file: &str,
    name: &'static str,
    j: &RawJoint,
    unit: f64,
    shape: VelocityProfile,
    max_step_rate: f64,
) -> Result<Joint, ProfileError> {
    let key = |f: &str| format!("joints.{name}.{f}");
    let steps_per_unit = positive(file, &key("steps_per_unit"), j.steps_per_unit)? / unit;
    let max_rate = positive(file, &key("max_rate"), j.max_rate)? / 60.0 * unit;
    let acceleration = positive(file, &key("acceleration"), j.acceleration)? * unit;
    let jerk = match j.jerk {
        Some(v) => Some(positive(file, &key("jerk"), v)? * unit),
        None if shape == VelocityProfile::SCurve => {
            return Err(err(
                file,
                &key("jerk"),
                "required when planner.velocity_profile = \"scurve\"".into(),
            ))
        }
        None => None,
    };
    let rate_hz = max_rate * steps_per_unit;
    if rate_hz > max_step_rate * (1.0 + 1e-9) {
        return Err(err(
            file,
            &key("max_rate"),
            format!(
                "{} per minute at {} steps per unit needs {:.0} steps/s, above \
                 planner.max_step_rate = {max_step_rate}",
                j.max_rate, j.steps_per_unit, rate_hz
            ),
        ));
    }
    let homing = match &j.homing {
        None => None,
        Some(h) => Some(Homing {
            direction: match h.direction.as_str() {
                "negative" => HomingDirection::Negative,
                "positive" => HomingDirection::Positive,
                other => {
                    return Err(err(
                        file,
                        &key("homing.direction"),
                        format!("{other:?}: use \"negative\" or \"positive\""),
                    ))
                }
            },
            seek_rate: positive(file, &key("homing.seek_rate"), h.seek_rate)? / 60.0 * unit,
            feed_rate: positive(file, &key("homing.feed_rate"), h.feed_rate)? / 60.0 * unit,
            pull_off: non_negative(file, &key("homing.pull_off"), h.pull_off)? * unit,
        }),
    };
    let limits = match j.limits {
        Some(r) => {
            let r = range(file, &key("limits"), r)?;
            Some([r[0] * unit, r[1] * unit])
        }
        None => None,
    };
    Ok(Joint {
        name,
        steps_per_unit,
        max_rate,
        acceleration,
        jerk,
        backlash: non_negative(file, &key("backlash"), j.backlash)? * unit,
        invert_direction: j.invert_direction,
        limits,
        homing,
    })
}

fn kinematics_allows_rotary(k: KinematicsKind) -> bool {
    matches!(k, KinematicsKind::Cartesian)
}

fn validate(raw: RawProfile, file: &str) -> Result<Profile, ProfileError> {
    let kinematics = KinematicsKind::from_settings(&raw.kinematics, &FileCheck(file))?;
    let p = &raw.planner;
    let shape = match p.velocity_profile.as_deref().unwrap_or("trapezoid") {
        "trapezoid" => VelocityProfile::Trapezoid,
        "scurve" => VelocityProfile::SCurve,
        other => {
            return Err(err(
                file,
                "planner.velocity_profile",
                format!("unknown profile {other:?}; use \"trapezoid\" or \"scurve\""),
            ))
        }
    };
    let max_step_rate = positive(file, "planner.max_step_rate", p.max_step_rate)?;
    let names = kinematics.joint_names();
    for key in raw.joints.keys() {
        if !names.contains(&key.as_str()) && !ROTARY_NAMES.contains(&key.as_str()) {
            return Err(err(
                file,
                &format!("joints.{key}"),
                format!(
                    "no such joint for this kinematics; expected {} (and rotary a, b, c)",
                    names.join(", ")
                ),
            ));
        }
    }
    let mut joints = [None, None, None];
    for (i, name) in names.iter().enumerate() {
        let Some(j) = raw.joints.get(*name) else {
            if i < 2 {
                return Err(err(
                    file,
                    &format!("joints.{name}"),
                    "missing joint table".into(),
                ));
            }
            continue;
        };
        if j.wrap.is_some() {
            return Err(err(
                file,
                &format!("joints.{name}.wrap"),
                "only rotary joints (a, b, c) wrap".into(),
            ));
        }
        // Angular joints are written in degrees; convert to radians once, here.
        let unit = if kinematics.is_angular(i) {
            std::f64::consts::PI / 180.0
        } else {
            1.0
        };
        joints[i] = Some(read_joint(file, name, j, unit, shape, max_step_rate)?);
    }
    // Rotary joints stay in degrees (unit 1): canon and the program speak degrees, and the
    // joint is the axis, so nothing converts.
    let mut rotary = [None, None, None];
    for (i, name) in ROTARY_NAMES.iter().enumerate() {
        // CoreXY names its two motors a and b: those tables are its joints, read above.
        if names.contains(name) {
            continue;
        }
        let Some(j) = raw.joints.get(*name) else {
            continue;
        };
        if !kinematics_allows_rotary(kinematics) {
            return Err(err(
                file,
                &format!("joints.{name}"),
                "rotary joints need cartesian kinematics".into(),
            ));
        }
        let joint = read_joint(file, name, j, 1.0, shape, max_step_rate)?;
        let wrap = j.wrap.unwrap_or(false);
        if wrap && joint.limits.is_some() {
            return Err(err(
                file,
                &format!("joints.{name}.limits"),
                "a wrapping rotary joint has no limits; drop one of them".into(),
            ));
        }
        rotary[i] = Some(Rotary { joint, wrap });
    }
    let t = &raw.travel;
    let z = match (t.z, joints[2].is_some()) {
        (Some(z), true) => range(file, "travel.z", z)?,
        (None, false) => [0.0, 0.0],
        (None, true) => {
            return Err(err(
                file,
                "travel.z",
                "required when joints.z exists".into(),
            ))
        }
        (Some(_), false) => {
            return Err(err(
                file,
                "travel.z",
                "given but the profile has no joints.z".into(),
            ))
        }
    };
    let travel = [
        range(file, "travel.x", t.x)?,
        range(file, "travel.y", t.y)?,
        z,
    ];
    let start = t
        .start
        .unwrap_or([travel[0][0], travel[1][0], travel[2][1]]);
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        if !(start[i] >= travel[i][0] && start[i] <= travel[i][1]) {
            return Err(err(
                file,
                "travel.start",
                format!(
                    "{axis} = {} lies outside travel.{axis} {:?}",
                    start[i], travel[i]
                ),
            ));
        }
    }
    let profile = Profile {
        name: raw.name,
        kinematics,
        joints,
        rotary,
        travel,
        start,
        junction_deviation: non_negative(file, "planner.junction_deviation", p.junction_deviation)?,
        arc_tolerance: tolerance(file, "planner.arc_tolerance", p.arc_tolerance)?,
        path_tolerance: tolerance(
            file,
            "planner.path_tolerance",
            p.path_tolerance.unwrap_or(0.01),
        )?,
        shape,
        horizon: positive(file, "planner.horizon", p.horizon.unwrap_or(2.0))?,
        max_step_rate,
        default_feed: positive(file, "planner.default_feed", p.default_feed)? / 60.0,
        work_offset: work_offset(file, raw.work.as_ref(), &travel)?,
        tool_table: match raw.tool_table {
            Some(t) if t.trim().is_empty() => {
                return Err(err(
                    file,
                    "tool_table",
                    "empty file name; name a LinuxCNC tool table such as \"tools.tbl\"".into(),
                ))
            }
            t => t.map(std::path::PathBuf::from),
        },
    };
    use crate::kinematics::Kinematics;
    let kin = crate::kinematics::for_profile(&profile);
    kin.joints(profile.start).map_err(|why| {
        err(
            file,
            "travel.start",
            format!("the start position is unreachable: {why}"),
        )
    })?;
    Ok(profile)
}

#[cfg(test)]
mod bundled_tests {
    use super::*;

    #[test]
    fn every_bundled_profile_parses_by_name_and_by_file_name() {
        for (name, _) in BUNDLED {
            resolve(name).unwrap_or_else(|e| panic!("bundled profile {name}: {e}"));
            assert!(bundled(&format!("profiles/{name}.toml")).is_some());
        }
        assert!(BUNDLED.iter().any(|(n, _)| *n == DEFAULT));
    }

    #[test]
    fn a_named_tool_table_is_found_beside_the_profile_file() {
        let router = BUNDLED.iter().find(|(n, _)| *n == DEFAULT).unwrap().1;
        let text = format!("tool_table = \"tools/mill.tbl\"\n{router}");
        assert_eq!(
            Profile::parse(&text, "t.toml").unwrap().tool_table,
            Some("tools/mill.tbl".into())
        );
        let dir = std::env::temp_dir().join(format!("oficina-profile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("router.toml");
        std::fs::write(&path, &text).unwrap();
        let loaded = Profile::load(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(loaded.tool_table, Some(dir.join("tools/mill.tbl")));
        assert_eq!(resolve(DEFAULT).unwrap().tool_table, None);
        let e = Profile::parse(&format!("tool_table = \" \"\n{router}"), "t.toml").unwrap_err();
        assert_eq!(e.key, "tool_table", "{e}");
    }

    #[test]
    fn rotary_joints_are_read_in_degrees_and_checked() {
        let p = resolve("router-4axis").unwrap();
        let a = p.rotary[0].expect("router-4axis has an A axis");
        // Degrees stay degrees: 10800 °/min is 180 °/s; 20 steps per degree.
        assert_eq!(a.joint.max_rate, 180.0);
        assert_eq!(a.joint.steps_per_unit, 20.0);
        assert!(a.wrap && p.rotary[1].is_none() && p.rotary[2].is_none());
        assert_eq!(a.shown(725.0), 5.0);
        let text = BUNDLED
            .iter()
            .find(|(n, _)| *n == "router-4axis")
            .unwrap()
            .1;
        // A wrapping joint has no limits.
        let both = text.replace("wrap = true", "wrap = true\nlimits = [0.0, 90.0]");
        let e = Profile::parse(&both, "t.toml").unwrap_err();
        assert_eq!(e.key, "joints.a.limits", "{e}");
        // Only rotary joints wrap.
        let e = Profile::parse(
            &text.replace(
                "backlash = 0.05\n\n[joints.y]",
                "backlash = 0.05\nwrap = true\n\n[joints.y]",
            ),
            "t.toml",
        )
        .unwrap_err();
        assert_eq!(e.key, "joints.x.wrap", "{e}");
        // A CoreXY machine's joints a and b are its motors, not rotary axes.
        let corexy = text
            .replace("type = \"cartesian\"", "type = \"corexy\"")
            .replace("[joints.x]", "[joints.x_]")
            .replace("[joints.y]", "[joints.b]")
            .replace("[joints.a]", "[joints.c]")
            .replace("[joints.x_]", "[joints.a]");
        let e = Profile::parse(&corexy, "t.toml").unwrap_err();
        assert_eq!(e.key, "joints.c", "{e}");
        assert!(e.message.contains("cartesian"), "{e}");
    }

    #[test]
    fn names_are_bundled_first_and_paths_stay_paths() {
        // A file called like a bundled profile, with other contents.
        let dir = std::env::temp_dir().join(format!("oficina-resolve-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let router = BUNDLED.iter().find(|(n, _)| *n == DEFAULT).unwrap().1;
        let mine = router.replacen("name = ", "name = \"mine\"\n# was: ", 1);
        let file = dir.join("grbl-router");
        std::fs::write(&file, &mine).unwrap();
        // The bare name is the bundled profile (the CLI's tests run it from a folder holding
        // such a file; the current folder is not changed in a unit test).
        assert_eq!(
            resolve("grbl-router").unwrap().name,
            "grbl router (seed 004)"
        );
        // A path to that file is the file.
        let as_path = resolve(file.to_str().unwrap());
        let missing = resolve(dir.join("profiles/grbl-router.toml").to_str().unwrap());
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(as_path.unwrap().name, "mine");
        // A missing path is an error that names the bundled profile, not the profile itself.
        let e = missing.unwrap_err().to_string();
        assert!(
            e.contains("no such profile file") && e.contains("`grbl-router`"),
            "{e}"
        );
    }

    #[test]
    fn unknown_names_list_the_bundled_ones() {
        let e = resolve("no-such-machine").unwrap_err().to_string();
        assert!(
            e.contains("grbl-router") && e.contains("no-such-machine"),
            "{e}"
        );
    }
}
