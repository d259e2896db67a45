//! gc_execute_line STEP 3: the block's commands and values checked against each other and the
//! modes in force, before anything changes. What needs the motion's geometry (arc radius,
//! probe target) is checked where the motion is computed, as grbl does too.

use super::parse::{Block, NonModal};
use super::*;

/// What the checks decided about the line.
pub(super) struct Plan {
    /// mm per program unit (G20: 25.4).
    pub scale: f64,
    pub any_axis: bool,
    /// The motion mode the line runs in: its own command or the modal one.
    pub motion_mode: MotionMode,
    /// The line moves: a motion command, or axis words no other command claimed.
    pub uses_motion: bool,
    /// The feed in force after the line, mm/min (1/min in inverse time).
    pub feed: f64,
}

/// STEP 3. `s` is the state before the line.
pub(super) fn check(s: &Interp, b: &Block) -> Result<Plan, u8> {
    if let Some(n) = b.value('N') {
        if n > 9_999_999.0 {
            return Err(E_INVALID_LINE_NUMBER);
        }
    }
    if let Some(t) = b.value('T') {
        if t > 255.0 {
            return Err(E_TOOL_NUMBER);
        }
    }
    let scale = if b.inches { 25.4 } else { 1.0 };
    let any_axis = b.axes().iter().any(|a| a.is_some()) || b.a().is_some();

    // Axis words with no explicit command fall to the modal motion mode.
    let motion_mode = b.motion.unwrap_or(s.modal.motion);
    let uses_motion = b.motion.is_some() || (any_axis && !b.axis_word_command);
    let non_modal_uses_axes = matches!(
        b.non_modal,
        NonModal::SetCoord | NonModal::Home28 | NonModal::Home30 | NonModal::SetG92
    ) || b.tlo == Some(true);
    if any_axis && !non_modal_uses_axes && motion_mode == MotionMode::None {
        return Err(E_AXIS_UNUSED);
    }
    if b.non_modal == NonModal::AbsOverride
        && uses_motion
        && !matches!(motion_mode, MotionMode::Rapid | MotionMode::Linear)
    {
        return Err(E_G53_MODE);
    }

    // Feed: in inverse time F must be on every feed move; otherwise it is modal.
    let mut feed = s.feed;
    if let Some(f) = b.value('F') {
        feed = if b.inverse_time { f } else { f * scale };
    } else if b.inverse_time && !s.modal.inverse_time {
        feed = 0.0;
    }
    let feeding = uses_motion
        && matches!(
            motion_mode,
            MotionMode::Linear | MotionMode::ArcCw | MotionMode::ArcCcw | MotionMode::Probe(_)
        );
    if feeding && (feed <= 0.0 || (b.inverse_time && b.value('F').is_none())) {
        return Err(E_UNDEFINED_FEED);
    }
    Ok(Plan {
        scale,
        any_axis,
        motion_mode,
        uses_motion,
        feed,
    })
}
