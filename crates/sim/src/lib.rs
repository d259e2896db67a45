//! The stock simulator: replays canonical operations on a height-field stock with the real
//! tool shapes, then compares the result with the design (gouge, leftover, scallop),
//! renders a preview and gives a time estimate.

pub mod carve;
pub mod estimate;
pub mod mill;
pub mod render;
pub mod replay;
pub mod report;

pub use carve::to_machine;
pub use estimate::feed_only_estimate;
pub use mill::{check_mill, Design, MillCheck};
pub use render::{render_png, shade};
pub use replay::{replay, SimError};
pub use report::{compare, ideal_surface, Report};
