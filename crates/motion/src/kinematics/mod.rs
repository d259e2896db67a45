//! Cartesian ↔ joint maps behind one trait. Joint 2 is always Z and maps straight through;
//! the machines differ in how the first two joints move the XY point. Each machine has its own
//! file, with its map, its derivation and the reading of its `[kinematics]` profile settings;
//! this module holds what they share. The profile reader depends on this module, never the
//! other way round: it lends its value checks through [`Check`].

mod cartesian;
mod corexy;
mod polar;
mod polargraph;

pub(crate) use cartesian::Cartesian;
pub(crate) use corexy::CoreXy;
pub(crate) use polar::Polar;
pub(crate) use polargraph::Polargraph;

use serde::Deserialize;

/// Maps Cartesian positions (mm) to joint values and back.
pub trait Kinematics {
    /// Inverse kinematics; `Err` says why the point cannot be reached.
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String>;
    /// Forward kinematics.
    fn forward(&self, q: [f64; 3]) -> [f64; 3];
    /// True when joints are a linear function of Cartesian position (straight lines stay
    /// straight in joint space, so no extra segmentation is needed).
    fn is_linear(&self) -> bool;
    /// Inverse kinematics choosing, for periodic joints, the value nearest `near` (unwrap).
    fn joints_near(&self, p: [f64; 3], _near: [f64; 3]) -> Result<[f64; 3], String> {
        self.joints(p)
    }
    /// Checks that the whole straight move a → b stays reachable.
    fn check_line(&self, a: [f64; 3], b: [f64; 3]) -> Result<(), String> {
        self.joints(a)?;
        self.joints(b).map(|_| ())
    }
}

/// Which kinematics the machine has, with its parameters (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KinematicsKind {
    /// Joints are X, Y, Z.
    Cartesian,
    /// CoreXY: motors A = X + Y, B = X − Y.
    CoreXy,
    /// Seed 003: an arm rotating about the origin, carriage at radius R, pen offset `h`.
    Polar {
        /// Pen offset `h` from the arm's axis, mm.
        pen_offset: f64,
    },
    /// Two motors at (0, 0) and (`motor_distance`, 0) with the pen hanging below (y < 0).
    Polargraph {
        /// Distance between the two motors, mm.
        motor_distance: f64,
        /// Least drop of the pen below the motors' line, mm.
        min_drop: f64,
    },
}

impl KinematicsKind {
    /// Joint names in order; the third joint is always Z (pen lift, spindle axis).
    pub fn joint_names(self) -> [&'static str; 3] {
        match self {
            KinematicsKind::Cartesian => Cartesian::JOINTS,
            KinematicsKind::CoreXy => CoreXy::JOINTS,
            KinematicsKind::Polar { .. } => Polar::JOINTS,
            KinematicsKind::Polargraph { .. } => Polargraph::JOINTS,
        }
    }

    /// True for joints measured in degrees in the file (radians inside).
    pub fn is_angular(self, joint: usize) -> bool {
        matches!(self, KinematicsKind::Polar { .. }) && joint == 0
    }

    /// Reads a profile's `[kinematics]` table: `type` picks the machine, whose file reads the
    /// rest. Keys another type uses are ignored.
    pub(crate) fn from_settings<C: Check>(raw: &RawKinematics, c: &C) -> Result<Self, C::Error> {
        match raw.kind.as_str() {
            "cartesian" => Ok(KinematicsKind::Cartesian),
            "corexy" => Ok(KinematicsKind::CoreXy),
            "polar" => Polar::settings(raw, c),
            "polargraph" => Polargraph::settings(raw, c),
            other => Err(c.error(
                "kinematics.type",
                format!("unknown kinematics {other:?}; use cartesian, corexy, polar or polargraph"),
            )),
        }
    }
}

/// A profile's `[kinematics]` table as written: every type's keys in one table, so an unknown
/// key is refused whatever the type.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawKinematics {
    #[serde(rename = "type")]
    kind: String,
    pen_offset: Option<f64>,
    motor_distance: Option<f64>,
    min_drop: Option<f64>,
}

/// The profile reader's value checks and error, lent to the kinematics settings readers so a
/// bad value is reported (file, dotted key, message) like every other profile key.
pub(crate) trait Check {
    type Error;
    fn error(&self, key: &str, message: String) -> Self::Error;
    /// A finite number > 0 (within the reader's sane range).
    fn positive(&self, key: &str, v: f64) -> Result<f64, Self::Error>;
    /// A finite number ≥ 0.
    fn non_negative(&self, key: &str, v: f64) -> Result<f64, Self::Error>;
}

/// The kinematics of a profile, dispatched without a heap allocation.
pub enum AnyKinematics {
    /// Cartesian: joints are X, Y, Z.
    Cartesian(Cartesian),
    /// CoreXY belts.
    CoreXy(CoreXy),
    /// Polar arm (seed 003).
    Polar(Polar),
    /// Hanging-pen polargraph.
    Polargraph(Polargraph),
}

/// The kinematics of anything that names its kind, such as a [`Profile`](crate::Profile).
pub fn for_profile(profile: &impl AsRef<KinematicsKind>) -> AnyKinematics {
    from_kind(*profile.as_ref())
}

pub(crate) fn from_kind(kind: KinematicsKind) -> AnyKinematics {
    match kind {
        KinematicsKind::Cartesian => AnyKinematics::Cartesian(Cartesian),
        KinematicsKind::CoreXy => AnyKinematics::CoreXy(CoreXy),
        KinematicsKind::Polar { pen_offset } => AnyKinematics::Polar(Polar { h: pen_offset }),
        KinematicsKind::Polargraph {
            motor_distance,
            min_drop,
        } => AnyKinematics::Polargraph(Polargraph {
            w: motor_distance,
            min_drop,
        }),
    }
}

macro_rules! dispatch {
    ($self:ident, $k:ident => $e:expr) => {
        match $self {
            AnyKinematics::Cartesian($k) => $e,
            AnyKinematics::CoreXy($k) => $e,
            AnyKinematics::Polar($k) => $e,
            AnyKinematics::Polargraph($k) => $e,
        }
    };
}

impl Kinematics for AnyKinematics {
    fn joints(&self, p: [f64; 3]) -> Result<[f64; 3], String> {
        dispatch!(self, k => k.joints(p))
    }
    fn forward(&self, q: [f64; 3]) -> [f64; 3] {
        dispatch!(self, k => k.forward(q))
    }
    fn is_linear(&self) -> bool {
        dispatch!(self, k => k.is_linear())
    }
    fn joints_near(&self, p: [f64; 3], near: [f64; 3]) -> Result<[f64; 3], String> {
        dispatch!(self, k => k.joints_near(p, near))
    }
    fn check_line(&self, a: [f64; 3], b: [f64; 3]) -> Result<(), String> {
        dispatch!(self, k => k.check_line(a, b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inverse then forward must give the point back.
    pub(crate) fn round_trip(k: &dyn Kinematics, p: [f64; 3]) {
        let q = k.joints(p).unwrap();
        let b = k.forward(q);
        for i in 0..3 {
            assert!((b[i] - p[i]).abs() < 1e-9, "{p:?} → {q:?} → {b:?}");
        }
    }
}
