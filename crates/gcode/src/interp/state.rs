//! The modal state the interpreter carries from block to block.

use oficina_canon::{FeedMode, PathControlMode, Plane, SpindleDir, SpindleMode, Units};

/// The active motion of group 1 (G0 G1 G2 G3 G73 G80–G89).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    Rapid,
    Linear,
    Clockwise,
    CounterClockwise,
    /// A canned cycle by its G number in tenths (730, 810 … 890).
    Cycle(u16),
    /// G80: no motion mode; axis words alone are an error.
    Off,
    /// G33: spindle-synchronised straight feed.
    SpindleSync,
    /// G33.1: rigid tapping.
    RigidTap,
    /// G76: the multi-pass threading cycle (lathe).
    Threading,
    /// G5, G5.1, G5.2, G5.3 by their G number in tenths (50 … 53).
    Spline(u16),
    /// G38.2 … G38.5 (straight probing) by their G number in tenths (382 … 385).
    Probe(u16),
}

impl Motion {
    pub fn from_tenths(t: u16) -> Motion {
        match t {
            0 => Motion::Rapid,
            10 => Motion::Linear,
            20 => Motion::Clockwise,
            30 => Motion::CounterClockwise,
            800 => Motion::Off,
            330 => Motion::SpindleSync,
            331 => Motion::RigidTap,
            760 => Motion::Threading,
            50..=53 => Motion::Spline(t),
            382..=385 => Motion::Probe(t),
            other => Motion::Cycle(other),
        }
    }
}

/// Cutter radius compensation side (G40 / G41 / G42).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

/// Everything modal. Lengths mm, feed mm/min (1/min in inverse time), angles degrees.
#[derive(Clone, Debug)]
pub struct Modal {
    pub motion: Motion,
    pub plane: Plane,
    pub incremental: bool,
    /// G91.1 (LinuxCNC default): I J K are offsets from the start point.
    pub arc_incremental: bool,
    pub feed_mode: FeedMode,
    pub units: Units,
    pub feed: f64,
    pub speed: f64,
    /// G96 / G97.
    pub spindle_mode: SpindleMode,
    /// M3/M4 turning, or `None`: stopped (M5) or held at an orientation (M19).
    pub spindle: Option<SpindleDir>,
    pub mist: bool,
    pub flood: bool,
    /// 1 = G54 … 9 = G59.3.
    pub coord_system: u8,
    pub control: PathControlMode,
    pub blend_tolerance: f64,
    pub naive_tolerance: f64,
    /// G98: retract to the old Z; G99: to R.
    pub retract_to_old_z: bool,
    pub tool_selected: u32,
    pub tool_in_spindle: u32,
    pub tool_length_on: bool,
    /// M48/M50: the feed override switch (M2 turns it back on).
    pub feed_override: bool,
    /// M48/M51: the spindle speed override switch.
    pub speed_override: bool,
    /// M52: adaptive feed.
    pub adaptive_feed: bool,
    /// M53: the feed hold switch.
    pub feed_hold: bool,
    pub comp: Option<Side>,
    /// Radius of compensation, mm.
    pub comp_radius: f64,
    /// G7 (lathe diameter mode): X words are diameters, the X axis moves half of them.
    pub diameter_mode: bool,
}

impl Modal {
    pub fn new(units: Units) -> Modal {
        Modal {
            motion: Motion::Off,
            plane: Plane::XY,
            incremental: false,
            arc_incremental: true,
            feed_mode: FeedMode::UnitsPerMinute,
            units,
            feed: 0.0,
            speed: 0.0,
            spindle_mode: SpindleMode::Rpm,
            spindle: None,
            mist: false,
            flood: false,
            coord_system: 1,
            control: PathControlMode::Continuous,
            blend_tolerance: 0.0,
            naive_tolerance: 0.0,
            // rs274 starts in G99 (retract to R).
            retract_to_old_z: false,
            tool_selected: 0,
            tool_in_spindle: 0,
            tool_length_on: false,
            feed_override: true,
            speed_override: true,
            adaptive_feed: false,
            feed_hold: true,
            comp: None,
            comp_radius: 0.0,
            diameter_mode: false,
        }
    }
}
