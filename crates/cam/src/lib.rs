//! Machine-neutral CAM: cutting tools, toolpaths and the relief (heightmap) strategies.
//!
//! ```
//! use oficina_cam::{Move, Operation, CutterShape, Tool, Toolpath};
//! use oficina_canon::{CanonOp, Pos};
//!
//! // A 6 mm ball nose: passes 2·√(2·3·0.1 − 0.1²) ≈ 1.54 mm apart leave 0.1 mm scallops.
//! let ball = Tool::new(CutterShape::Ball, 6.0).unwrap();
//! assert!((ball.stepover_for_scallop(0.1) - 2.0 * 0.59f64.sqrt()).abs() < 1e-9);
//!
//! // One operation: down into the stock and a cut along X at 10 mm/s.
//! let moves = vec![
//!     Move::Rapid { to: [0.0, 0.0, 2.0] },
//!     Move::Line { to: [0.0, 0.0, -1.0], feed: 5.0 },
//!     Move::Line { to: [50.0, 0.0, -1.0], feed: 10.0 },
//! ];
//! let op = Operation { name: "slot".into(), tool_number: 1, tool: ball, spindle_rpm: 18e3, moves };
//! let path = Toolpath { safe_z: 5.0, operations: vec![op] };
//! assert_eq!(path.move_count(), 3);
//! // The canonical operations feed the simulator and estimator; feeds become mm/min.
//! let canon: Vec<CanonOp> = path.canon().into_iter().map(|c| c.op).collect();
//! assert!(canon.contains(&CanonOp::SetFeedRate(600.0)));
//! assert!(canon.contains(&CanonOp::StraightFeed { to: Pos::xyz(50.0, 0.0, -1.0) }));
//! ```

// `memory`, `ops`, `relief` and `seed004` stay public namespaces: their names (`check`,
// `plan`, `check`, `profile`, `pocket`) read well only behind the module, and new operations
// are being added under `ops`. The rest is the flat list below.
mod lane_max;
mod library;
pub mod memory;
pub mod mesh;
pub mod ops;
mod raster;
mod regions;
pub mod relief;
pub mod seed004;
mod sliding_max;
mod stock;
mod surface;
mod tool;
mod toolpath;

pub use library::{feed_rate, surface_speed, Library, LibraryTool, ToolFeeds};
pub use raster::Feeds;
pub use stock::{apply_moves, sweep_arc, sweep_line};
pub use surface::{surface_grid, surface_rows, Kernel};
pub use tool::{CutterShape, Tool, ToolError};
pub use toolpath::{CompSide, Drill, Move, Operation, PathMode, Toolpath};
