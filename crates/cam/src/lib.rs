//! Machine-neutral CAM: cutting tools, toolpaths and the relief (heightmap) strategies.

pub mod lane_max;
pub mod library;
pub mod memory;
pub mod ops;
pub mod raster;
pub mod regions;
pub mod relief;
pub mod seed004;
pub mod sliding_max;
pub mod stock;
pub mod surface;
pub mod tool;
pub mod toolpath;

pub use library::Library;
pub use tool::{Shape, Tool, ToolError};
pub use toolpath::{Drill, Move, Operation, PathMode, Toolpath};
