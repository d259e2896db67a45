//! Pen plotting (seed 003 and the plotters our users own): a `Drawing` becomes pens of
//! pen-down strokes, the strokes are merged, simplified, de-duplicated and ordered for the
//! least pen-up travel, checked against the machine, and written as G-code (Cartesian or
//! joint space), HPGL or an SVG preview.

mod canon;
mod clean;
mod emit;
mod hatch;
mod job;
mod machine;
mod merge;
mod optimise;
mod order;
mod preview;
mod seed_check;
mod strokes;
mod text;

pub use canon::to_canon;
pub use clean::{dedupe, simplify};
pub use emit::{gcode, hpgl, joint_gcode};
pub use hatch::{hatch, load_gray, Gray, HatchError, Hatching};
pub use job::{prepare, Format, Prepared, Settings};
pub use machine::{
    arm_limited_feed, check_paper, check_ramps, check_reach, ramps, PenLift, PenMachine, PlotError,
    Ramp,
};
pub use merge::merge;
pub use optimise::{optimise, Optimise, Report};
pub use order::{nearest_neighbour, two_opt};
pub use preview::svg as preview_svg;
pub use seed_check::{
    figures, seed_check, stop_start_seconds, Row as SeedRow, FIGURES, PLACES, SEED_SECONDS,
    STOP_PIECE,
};
pub use strokes::{polyline_length, Lengths, Pen, PenBy, Plot, Stroke};
pub use text::text_strokes;
