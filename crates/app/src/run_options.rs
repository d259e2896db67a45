//! The interpreter's options for running a program on a machine.

use oficina_gcode::{Dialect, RunOptions, StartState};
use oficina_motion::Profile;

/// Options for `dialect` on `profile`: the machine's stored offsets, and for seed 002's
/// dialect, whose feed comes from the machine configuration, the profile's default feed
/// (mm/s → mm/min).
pub fn run_options_for(profile: &Profile, dialect: Dialect, max_line_len: usize) -> RunOptions {
    let feed = if dialect == Dialect::Legacy2006 {
        profile.default_feed * 60.0
    } else {
        0.0
    };
    RunOptions {
        dialect,
        max_line_len,
        initial_params: initial_params_for(profile, dialect),
        start: StartState {
            feed,
            ..StartState::default()
        },
        ..RunOptions::default()
    }
}

/// The parameters a program starts with on `profile`: its stored work offset, and in the
/// Marlin dialect its home (#5161…, where `G28` goes) at the profile's start point, where the
/// machine stands after homing.
pub(crate) fn initial_params_for(profile: &Profile, dialect: Dialect) -> Vec<(i64, f64)> {
    let mut params = profile.initial_params();
    if dialect == Dialect::Marlin {
        params.extend((0..3).map(|i| (5161 + i as i64, profile.start[i])));
    }
    params
}
