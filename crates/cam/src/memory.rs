//! What relief planning will hold in memory, estimated before it is allocated, so an absurd
//! pixel size, depth or step is refused with a figure instead of growing until the kernel
//! kills the process.
//!
//! The estimates count the large buffers only (grids, rows of samples, kernel tables, moves);
//! they are upper bounds for grids and lower bounds for moves (each row visited at a level
//! costs at least a travel and a feed), so a refusal is never premature for moves, and the
//! move count is also checked as it grows.

use crate::lane_max::LANES;
use crate::toolpath::Move;

/// A memory budget for planning, and what each move will cost in all (the caller may keep
/// its G-code text, canonical operations and so on: it says how much per move).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Bytes allowed in all.
    pub bytes: u64,
    /// Bytes the caller holds or will hold besides the plan's (its own grids).
    pub reserved: u64,
    /// Bytes each move costs the caller besides its own size.
    pub per_move: u64,
}

impl Budget {
    /// No limit: each move costs its own size.
    pub const UNLIMITED: Budget = Budget {
        bytes: u64::MAX,
        reserved: 0,
        per_move: std::mem::size_of::<Move>() as u64,
    };
}

/// What makes an estimate smaller, for the message (the CLI names its option).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lever {
    /// Fewer grid points (a smaller picture), or a kernel of fewer pixels (a coarser pixel
    /// size).
    PixelSize,
    /// Fewer depth levels: a larger step-down or a shallower relief.
    Levels,
    /// Fewer rows and moves: a larger step-over, step-down or tolerance.
    Moves,
}

impl Lever {
    /// What to change, in words, for the message.
    pub fn describe(self) -> &'static str {
        match self {
            Lever::PixelSize => {
                "fewer grid points (a smaller picture) or fewer pixels across the tool (a coarser pixel size)"
            }
            Lever::Levels => "a larger step-down or a shallower depth",
            Lever::Moves => "a larger step-over or step-down",
        }
    }
}

/// A refusal: what would not fit, its estimate and what to change.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "{what} would need about {} MB, over the memory budget of {} MB; use {} or a larger budget",
    show_mb(*.needed),
    show_mb(*.budget),
    .lever.describe()
)]
pub struct OverBudget {
    /// What would not fit.
    pub what: String,
    /// Bytes it would need.
    pub needed: u64,
    /// Bytes allowed.
    pub budget: u64,
    /// What to change.
    pub lever: Lever,
}

/// Bytes as MB for a message: tenths below 10 MB, so a refusal never reads "1 MB, over the
/// budget of 1 MB".
pub fn show_mb(bytes: u64) -> String {
    let mb = bytes as f64 / (1u64 << 20) as f64;
    if mb < 10.0 {
        format!("{mb:.1}")
    } else {
        format!("{mb:.0}")
    }
}

/// `Err` when `needed` exceeds `budget`.
pub fn check(
    what: impl FnOnce() -> String,
    needed: u64,
    budget: u64,
    lever: Lever,
) -> Result<(), OverBudget> {
    if needed > budget {
        Err(OverBudget {
            what: what(),
            needed,
            budget,
            lever,
        })
    } else {
        Ok(())
    }
}

/// Products saturate: an absurd size must compare as absurd, never wrap to a small one.
fn mul(a: u64, b: u64) -> u64 {
    a.saturating_mul(b)
}

/// Bytes of one f32 grid of `width` × `height`.
pub fn grid_bytes(width: usize, height: usize) -> u64 {
    mul(mul(width as u64, height as u64), 4)
}

/// Bytes of one drop-cutter kernel's tables reaching `reach` pixels: every offset of the
/// square footprint listed once with its lift (12 bytes) and once more in its row's curved
/// part (8 bytes).
pub fn kernel_bytes(reach: usize) -> u64 {
    let side = 2 * reach as u64 + 1;
    mul(mul(side, side), 20)
}

/// The shape of one pass in one raster direction, as the planner will lay it out.
pub struct PassShape {
    /// Grid points along and across the rows (after transposing for rows along Y).
    pub width: usize,
    /// Grid points across the rows.
    pub height: usize,
    /// Kernel reach, pixels.
    pub reach: usize,
    /// Raster rows visited.
    pub rows: usize,
    /// Tip heights per pixel along a row.
    pub sub: usize,
    /// Earlier passes left a stock to start from.
    pub has_stock: bool,
    /// Only the regions earlier passes left are cut.
    pub rest_only: bool,
}

impl PassShape {
    /// Largest memory the pass holds at once besides its moves.
    pub fn bytes(&self) -> u64 {
        let grid = grid_bytes(self.width, self.height);
        let padded = grid_bytes(self.width + 2 * self.reach + LANES, self.height);
        let samples = ((self.width.max(1) - 1) as u64).saturating_mul(self.sub as u64) + 1;
        let row_samples = mul(self.rows as u64, samples);
        // The grid copy, the stock carried to the next pass, the target tip heights (rows of
        // samples, computed through a padded copy), the rows of a block (target, free height,
        // allowed flag) and one level's copy of them.
        let mut total = mul(grid, 2)
            .saturating_add(padded)
            .saturating_add(mul(row_samples, 4))
            .saturating_add(mul(row_samples, 2 * 9))
            .saturating_add(mul(kernel_bytes(self.reach), self.sub as u64 + 2));
        if self.has_stock {
            // The stock (transposed) copy, its padded copy and its dilation, row by row and
            // joined.
            total = total.saturating_add(mul(grid, 3)).saturating_add(padded);
        }
        if self.rest_only {
            // The full dilation (padded, rows, joined), the mask, its grown copy and labels.
            total = total
                .saturating_add(padded)
                .saturating_add(mul(grid, 2))
                .saturating_add(mul(mul(self.width as u64, self.height as u64), 1 + 1 + 4));
        }
        total
    }
}
