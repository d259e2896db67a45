//! Pen plotting (seed 003 and the plotters our users own): a `Drawing` becomes pens of
//! pen-down strokes, the strokes are merged, simplified, de-duplicated and ordered for the
//! least pen-up travel, checked against the machine, and written as G-code (Cartesian or
//! joint space), HPGL or an SVG preview.
//!
//! ```
//! use oficina_geom::Point;
//! use oficina_plot::{prepare, Pen, PenMachine, Plot, Settings};
//!
//! // Three strokes drawn in a wasteful order: the third continues the first.
//! let line = |x0: f64, x1: f64| vec![Point::new(x0, 10.0), Point::new(x1, 10.0)];
//! let strokes = vec![line(10.0, 20.0), line(100.0, 110.0), line(20.0, 30.0)];
//! let plot = Plot { pens: vec![Pen { name: "#000000".into(), strokes }] };
//! assert_eq!(plot.lengths().pen_up, 80.0 + 90.0);
//!
//! let profile = oficina_motion::resolve("pen-plotter").unwrap();
//! let machine = PenMachine::for_profile(&profile);
//! let prepared = prepare(plot, &profile, &machine, &Settings::default()).unwrap();
//! let report = prepared.report.unwrap();
//! assert!(report.after.pen_up < report.before.pen_up, "{report:?}");
//! assert!(prepared.program.lines().any(|l| l == "G1 X110 Y10"), "{}", prepared.program);
//! assert_eq!(prepared.bounds, [10.0, 10.0, 110.0, 10.0]);
//! ```

mod canon;
mod clean;
mod clip;
mod crop;
mod emit;
mod fill;
mod hatch;
mod job;
mod layout;
mod machine;
mod merge;
mod optimise;
mod order;
mod passes;
mod preview;
mod seed_check;
mod shade;
mod strokes;
mod text;

pub use canon::to_canon;
pub use clean::{dedupe, simplify};
pub use crop::crop;
pub use emit::{gcode, hpgl, joint_gcode, marlin};
pub use fill::{fill_regions, FillStyle, MAX_FILL_LINES, MIN_FILL_SPACING};
pub use hatch::{
    band_regions, fill_bands, hatch, load_gray, Gray, HatchError, Hatching, MAX_BANDS,
};
pub use job::{prepare, Crop, Format, Prepared, Settings};
pub use layout::{layout, page_size, Layout, Placed, PAGE_SIZES};
pub use machine::{
    arm_limited_feed, check_paper, check_ramps, check_reach, ramps, snap_to_travel, PenLift,
    PenMachine, PlotError, Ramp, TRAVEL_TOL,
};
pub use merge::merge;
pub use optimise::{optimise, Optimise, Report};
pub use order::{nearest_neighbour, two_opt};
pub use passes::{multipass, reloop, MAX_PASSES};
pub use preview::svg as preview_svg;
pub use seed_check::{
    figures, seed_check, stop_start_seconds, Row as SeedRow, FIGURES, PLACES, SEED_SECONDS,
    STOP_PIECE,
};
pub use shade::{shade, Filled, Occult, Shading};
pub use strokes::{polyline_length, Lengths, Pen, PenBy, Plot, Stroke};
pub use text::text_strokes;
