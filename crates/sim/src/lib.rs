//! The stock simulator: replays canonical operations on a height-field stock with the real
//! tool shapes, then compares the result with the design (gouge, leftover, scallop),
//! renders a preview and gives a time estimate.
//!
//! ```
//! use oficina_cam::{CutterShape, Tool};
//! use oficina_canon::{Canon, CanonOp, Pos};
//! use oficina_io::Heightmap;
//! use std::collections::HashMap;
//!
//! // A 20 × 10 mm stock, top at Z 0, sampled every 0.5 mm; a 4 mm flat end mill as T1.
//! let mut stock = Heightmap::flat(41, 21, 0.5, 0.0);
//! let tools = HashMap::from([(1, Tool::new(CutterShape::Flat, 4.0).unwrap())]);
//! let ops = [
//!     CanonOp::ChangeTool(1),
//!     CanonOp::StraightTraverse { to: Pos::xyz(2.0, 5.0, 1.0) },
//!     CanonOp::StraightFeed { to: Pos::xyz(2.0, 5.0, -1.0) },
//!     CanonOp::StraightFeed { to: Pos::xyz(18.0, 5.0, -1.0) },
//! ];
//! let ops: Vec<Canon> = ops.into_iter().map(|op| Canon { line: 1, op }).collect();
//! let end = oficina_sim::replay(&ops, &tools, &mut stock, [0.0, 0.0, 5.0]).unwrap();
//! assert_eq!(end, [18.0, 5.0, -1.0]);
//! // A 4 mm wide slot 1 mm deep along Y = 5; the stock 3 mm off the slot's centre is untouched.
//! assert_eq!(stock.at(20, 10), -1.0); // (10, 5)
//! assert_eq!(stock.at(20, 4), 0.0); // (10, 2)
//! assert_eq!(stock.range(), (-1.0, 0.0));
//! ```

// `carve` stays a namespace: `carve::evaluate`, `carve::Settings` read well only behind it.
pub mod carve;
mod engagement;
mod estimate;
mod mill;
mod render;
mod replay;
mod report;
pub mod stock_box;

pub use carve::to_machine;
pub use engagement::{engagement, Engagement, EngagementStock};
pub use estimate::feed_only_estimate;
pub use mill::{check_mill, Design, MillCheck};
pub use render::{png_bytes, render_png, shade};
pub use replay::{replay, replay_watched, Move, MoveKind, SimError};
pub use report::{compare, ideal_surface, Report};
