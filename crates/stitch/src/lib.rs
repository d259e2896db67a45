//! Embroidery (seed 000): a `Drawing` becomes a [`StitchPlan`] of running, satin and tatami
//! fill stitches; the plan is checked against the hoops, summed up in a production sheet,
//! sewn on the needle-synchronised table, and written as Tajima DST or Melco EXP.

mod format;
mod generate;
mod plan;

pub use format::{Format, FormatError, Op, Rec};
pub use generate::{generate, running, GenerateError, Generated, Params, ShapeKind};
pub use plan::{ColorBlock, Counts, Kind, Stitch, StitchPlan, Thread};
