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
        initial_params: profile.initial_params(),
        start: StartState {
            feed,
            ..StartState::default()
        },
        ..RunOptions::default()
    }
}
