//! 2.5D operations: drawings → [`Operation`]s of tool-centre moves.
//!
//! - [`profile`]: inside / outside / on the line, depth passes, a finishing pass at full
//!   depth, tabs, a tangent lead-out;
//! - [`pocket`]: contour-parallel from the centre out (seed 001 §4.4) or zig-zag, islands and
//!   pockets that split, pre-finish allowance, finishing pass at the tool radius;
//! - [`adaptive`]: clearing at a bounded engagement angle (material model, trochoidal
//!   loops where a wall or neck needs them);
//! - [`drill`]: canned cycles at circle centres;
//! - [`chamfer`]: a V bit along the top edge of parts (outside) and holes (inside);
//! - [`dogbones`]: notches of the tool's radius in the inside corners of pockets and holes;
//! - [`rest`]: a smaller tool pockets what a larger one could not reach;
//! - [`vcarve`]: V-carving of closed shapes (depth from the distance to the outline) and
//!   single-line strokes;
//! - [`Entry`]: how a cut goes down into material: ramp along the path, helix, or a plunge
//!   only where the user says the tool can.
//!
//! Z: the stock top is `top` (usually 0) and cuts go down to `top − depth`.

mod adaptive;
mod adaptive_corners;
mod adaptive_model;
mod chain;
pub(crate) use chain::inside;
mod chamfer;
mod dogbone;
mod drill;
mod entry;
mod groove;
mod mill;
mod pocket;
mod preview;
mod profile;
mod rest;
mod sole;
mod vcarve;

pub use adaptive::{adaptive, AdaptiveParams};
pub use chain::{Chain, Piece};
pub use chamfer::{chamfer, chamfer_regions, ChamferParams};
pub use dogbone::{dogbones, Notch};
pub use drill::{drill, DrillParams};
pub use entry::Entry;
pub use groove::groove_region;
pub use mill::{allowed_region, operation, toolpath, MillOp, GOUGE_TOL};
pub use pocket::{pocket, PocketParams, Strategy};
pub use preview::{preview_canon_svg, preview_svg};
pub use profile::{profile, Comp, ProfileParams, Side, Tabs, DEFAULT_LEAD_IN};
pub use rest::{rest, rest_machining, rest_pocket};
pub use sole::{
    graded_feet, sole_job, Foot, GradedFeet, Part, SoleJob, SoleProgram, SoleResult, TREAD_DEPTH,
};
pub use vcarve::{half_tan, vcarve, VCarveParams};

use crate::{Move, Operation, Tool};

/// Why an operation cannot be made.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum OpError {
    /// A parameter out of range; says which.
    #[error("{0}")]
    Invalid(String),
    /// The shapes cannot be cut as asked; says where.
    #[error("geometry: {0}")]
    Geometry(String),
    /// The operation would cut nothing; says why.
    #[error("nothing to cut: {0}")]
    Empty(String),
}

/// The technology of one operation: tool, speeds, depths, planes, entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Cut {
    /// Tool number in the program.
    pub tool_number: u32,
    /// The cutter.
    pub tool: Tool,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// Cutting feed, mm/s.
    pub feed: f64,
    /// Feed for ramps, helices and plunges, mm/s.
    pub plunge_feed: f64,
    /// Z of the stock top.
    pub top: f64,
    /// How deep below the top, mm (> 0).
    pub depth: f64,
    /// Largest depth of one pass, mm (> 0); passes are equal.
    pub stepdown: f64,
    /// Retraction plane: rapids between cuts happen here (seed 001's "plano de retração").
    pub clear_z: f64,
    /// How cuts go down into material.
    pub entry: Entry,
}

/// A gap (mm) above the last cut floor to which rapids may come down before a ramp.
pub const RAPID_GAP: f64 = 0.5;

impl Cut {
    /// The operation these moves make with this cut's tool and spindle.
    pub(crate) fn operation(&self, name: &str, moves: Vec<Move>) -> Operation {
        Operation {
            name: name.into(),
            tool_number: self.tool_number,
            tool: self.tool.clone(),
            spindle_rpm: self.spindle_rpm,
            moves,
        }
    }

    /// Refuses values no machine could use, naming the parameter.
    pub fn validate(&self) -> Result<(), OpError> {
        let pos = |v: f64, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(OpError::Invalid(format!(
                    "{what} must be above 0 (got {v})"
                )))
            }
        };
        pos(self.depth, "depth")?;
        pos(self.stepdown, "stepdown")?;
        pos(self.feed, "feed")?;
        pos(self.plunge_feed, "plunge feed")?;
        pos(self.tool.diameter, "tool diameter")?;
        if !(self.top.is_finite() && self.clear_z.is_finite() && self.clear_z > self.top) {
            return Err(OpError::Invalid(format!(
                "the retraction plane Z{} must be above the stock top Z{}",
                self.clear_z, self.top
            )));
        }
        if self.depth > 1000.0 || self.depth / self.stepdown > 10_000.0 {
            return Err(OpError::Invalid(format!(
                "depth {} mm in passes of {} mm is beyond any machine",
                self.depth, self.stepdown
            )));
        }
        if self.tool.flute_length > 0.0 && self.depth > self.tool.flute_length {
            return Err(OpError::Invalid(format!(
                "depth {} mm is more than the flute length {} mm of {}",
                self.depth,
                self.tool.flute_length,
                self.tool.spec()
            )));
        }
        self.entry.validate()
    }

    /// Z of each pass, top down, equal passes no deeper than `stepdown`, the last at full
    /// depth.
    pub fn levels(&self) -> Vec<f64> {
        let n = (self.depth / self.stepdown - 1e-9).ceil().max(1.0) as usize;
        (1..=n)
            .map(|k| self.top - self.depth * k as f64 / n as f64)
            .collect()
    }

    /// Z of the bottom of the cut, mm.
    pub fn bottom(&self) -> f64 {
        self.top - self.depth
    }

    /// Tool radius, mm.
    pub fn radius(&self) -> f64 {
        self.tool.diameter / 2.0
    }
}

/// Moves being built, knowing where the tool is.
pub(crate) struct Builder {
    pub moves: Vec<Move>,
    pub at: [f64; 3],
}

impl Builder {
    pub(crate) fn new(clear_z: f64) -> Builder {
        Builder {
            moves: vec![],
            at: [f64::NAN, f64::NAN, clear_z],
        }
    }

    pub(crate) fn push(&mut self, m: Move) {
        if let Some(to) = m.end() {
            self.at = to;
        }
        self.moves.push(m);
    }

    pub(crate) fn extend(&mut self, ms: Vec<Move>) {
        for m in ms {
            self.push(m);
        }
    }

    /// Up to the retraction plane, across, and down to `z` (all rapids).
    pub(crate) fn travel(&mut self, clear_z: f64, to: [f64; 2], z: f64) {
        if self.at[2] < clear_z {
            self.push(Move::Rapid {
                to: [self.at[0], self.at[1], clear_z],
            });
        }
        self.push(Move::Rapid {
            to: [to[0], to[1], clear_z],
        });
        if z < clear_z {
            self.push(Move::Rapid {
                to: [to[0], to[1], z],
            });
        }
    }

    pub(crate) fn line(&mut self, to: [f64; 3], feed: f64) {
        self.push(Move::Line { to, feed });
    }

    pub(crate) fn finish(mut self, clear_z: f64) -> Vec<Move> {
        if self.at[2] < clear_z {
            self.push(Move::Rapid {
                to: [self.at[0], self.at[1], clear_z],
            });
        }
        self.moves
    }
}
