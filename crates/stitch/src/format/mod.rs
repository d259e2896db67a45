//! Embroidery machine files. Both formats store increments in 0.1 mm with y up; a plan is
//! quantised on absolute positions (round(x / 0.1 mm)) and the differences written, so
//! rounding never accumulates. A move longer than a record can hold is split into equal
//! records of the same kind (a sewn stitch into shorter stitches, a jump into jumps).

mod dst;
mod exp;
mod records;
pub(crate) mod seed_ram;

use crate::plan::StitchPlan;
use std::fmt;

pub use records::{Op, Rec};

/// The file formats Oficina writes and reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Tajima DST: 512-byte header, 3-byte balanced-ternary records of ±121 units.
    Dst,
    /// Melco EXP: 2-byte signed records of ±127 units, 0x80 escapes for commands.
    Exp,
    /// The seed's machine program (§5.3): 0.2 mm steps, short and long points, colour stops,
    /// head-speed codes. Extension `.ram`.
    SeedRam,
}

impl Format {
    /// The industry formats (pyembroidery reads and writes both).
    pub const ALL: [Format; 2] = [Format::Dst, Format::Exp];
    /// Every format Oficina writes and reads.
    pub const EVERY: [Format; 3] = [Format::Dst, Format::Exp, Format::SeedRam];

    /// The format's name for messages ("DST").
    pub fn name(self) -> &'static str {
        match self {
            Format::Dst => "DST",
            Format::Exp => "EXP",
            Format::SeedRam => "seed RAM program",
        }
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Dst => "dst",
            Format::Exp => "exp",
            Format::SeedRam => "ram",
        }
    }

    /// The format a file name's extension names (case-insensitive).
    pub fn from_path(path: &std::path::Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Format::EVERY.into_iter().find(|f| f.extension() == ext)
    }

    /// The largest increment per axis of one record, in 0.1 mm.
    pub fn max_step(self) -> i32 {
        match self {
            Format::Dst => dst::MAX_STEP,
            Format::Exp => exp::MAX_STEP,
            // 62 steps of 0.2 mm.
            Format::SeedRam => 124,
        }
    }

    /// The plan as a file of this format.
    pub fn write(self, plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
        Ok(match self {
            Format::Dst => dst::write(&plan.name, &records::to_records(plan, dst::MAX_STEP, self)?),
            Format::Exp => exp::write(&records::to_records(plan, exp::MAX_STEP, self)?),
            Format::SeedRam => {
                // Program 1, started where the design's origin is, in its smallest hoop.
                let header = seed_ram::SeedHeader {
                    program: 1,
                    start: [0.0, 0.0],
                    hoop: crate::hoop::smallest_hoop(plan).ok(),
                };
                seed_ram::write(plan, &header)?
            }
        })
    }

    /// Reads a file; `name` names the design when the file carries no name.
    pub fn read(self, bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
        let (file_name, recs) = match self {
            Format::Dst => dst::read(bytes)?,
            Format::Exp => (None, exp::read(bytes)?),
            Format::SeedRam => {
                let (mut plan, _) = seed_ram::read(bytes)?;
                plan.name = name.to_string();
                return Ok(plan);
            }
        };
        let mut plan = records::to_plan(&recs, self == Format::Dst);
        plan.name = file_name.unwrap_or_else(|| name.to_string());
        Ok(plan)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A file that cannot be written or read: the format, the byte offset and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{format} file: byte {offset}: {message}")]
pub struct FormatError {
    /// The file's format.
    pub format: Format,
    /// Byte offset of the problem.
    pub offset: usize,
    /// What is wrong.
    pub message: String,
}

impl FormatError {
    fn new(format: Format, offset: usize, message: impl Into<String>) -> FormatError {
        FormatError {
            format,
            offset,
            message: message.into(),
        }
    }
}
