//! Auto-levelling (PCB isolation, engraving on warped stock): probe a grid of surface
//! heights, then stream the program with every cut following the surface.
//!
//! - [`ProbeGrid`] places a grid over a program's feed extents ([`feed_area`]) or a given
//!   [`Area`], with a margin, by count or spacing ([`GridSpec`]), and probes it in
//!   serpentine order through any [`SurfaceProbe`] (a closure, or [`MachineProbe`]: G38.2
//!   on grbl firmware) into a [`HeightMap`] (saved and read as JSON).
//! - [`level_program`] is the streaming transform: moves below the clearance become pieces
//!   of at most `max_segment` mm (arcs first become chords within `arc_tolerance`), each end
//!   Z raised by the bilinear height under it; [`level_stream`] gives a [`crate::StreamProgram`]
//!   whose lines keep the source line numbers, [`level_text`] a file for any sender.

mod extents;
mod grid;
mod machine_probe;
mod map;
mod source;
mod transform;

pub use extents::feed_area;
pub use grid::{Area, GridSpec, ProbeGrid, SurfaceProbe};
pub use machine_probe::{MachineProbe, ProbeMotion};
pub use map::{HeightMap, MAX_GRID};
pub use transform::{level_program, level_stream, level_text, LevelOptions, LevelReport};
