//! Embroidery machine files. Every format stores increments in 0.1 mm; a plan is quantised
//! on absolute positions (round(x / 0.1 mm)) and the differences written, so rounding never
//! accumulates. A move longer than a record can hold is split into equal records of the same
//! kind (a sewn stitch into shorter stitches, a jump into jumps). Each format is one file;
//! pyembroidery (MIT) is the reference reader the tests compare with.

mod bor;
mod bytes;
mod dst;
mod exp;
mod jef;
mod pec;
mod pes;
mod records;
pub(crate) mod seed_ram;
mod threads;
mod u01;
mod vp3;
mod xxx;

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
    /// Brother PES version 6: PE-Design header with the exact thread colours, then the PEC
    /// block machines sew.
    Pes,
    /// Brother PES version 1: the same PEC block, colours from the 64-thread PEC chart.
    PesV1,
    /// Brother PEC alone (`#PEC0001`): 12-bit records, colours from the PEC chart.
    Pec,
    /// Janome JEF: 2-byte records of ±127, colours from the Janome chart.
    Jef,
    /// Pfaff / Husqvarna VP3: colour blocks with RGB threads, no jumps (long stitches).
    Vp3,
    /// Singer XXX: 2-byte records of ±123, RGB colours at the end.
    Xxx,
    /// Barudan U01: 3-byte records of ±127, needle changes.
    U01,
    /// The seed's machine program (§5.3): 0.2 mm steps, short and long points, colour stops,
    /// head-speed codes. Extension `.ram`.
    SeedRam,
    /// The seed's ASCII program `.BOR` (§5.2): the same records as decimal text lines.
    Bor,
}

/// The seed's `.BOR` program text of `plan` with `header` (program number, Zero-Peça, hoop).
pub fn write_bor(plan: &StitchPlan, header: &seed_ram::SeedHeader) -> Result<Vec<u8>, FormatError> {
    bor::write(plan, header)
}

/// A `.BOR` program's plan (positions from its Zero-Peça) and header.
pub fn read_bor(bytes: &[u8]) -> Result<(StitchPlan, seed_ram::SeedHeader), FormatError> {
    bor::read(bytes)
}

impl Format {
    /// The industry formats (pyembroidery reads and writes each).
    pub const ALL: [Format; 9] = [
        Format::Dst,
        Format::Exp,
        Format::Pes,
        Format::PesV1,
        Format::Pec,
        Format::Jef,
        Format::Vp3,
        Format::Xxx,
        Format::U01,
    ];
    /// Every format Oficina writes and reads.
    pub const EVERY: [Format; 11] = [
        Format::Dst,
        Format::Exp,
        Format::Pes,
        Format::PesV1,
        Format::Pec,
        Format::Jef,
        Format::Vp3,
        Format::Xxx,
        Format::U01,
        Format::SeedRam,
        Format::Bor,
    ];

    /// The format's name for messages ("DST").
    pub fn name(self) -> &'static str {
        match self {
            Format::Dst => "DST",
            Format::Exp => "EXP",
            Format::Pes => "PES",
            Format::PesV1 => "PES v1",
            Format::Pec => "PEC",
            Format::Jef => "JEF",
            Format::Vp3 => "VP3",
            Format::Xxx => "XXX",
            Format::U01 => "U01",
            Format::SeedRam => "seed RAM program",
            Format::Bor => "seed BOR program",
        }
    }

    /// The format's short identifier for options (`dst`, `pes-v1`, `seed-ram`).
    pub fn id(self) -> &'static str {
        match self {
            Format::PesV1 => "pes-v1",
            Format::SeedRam => "seed-ram",
            f => f.extension(),
        }
    }

    /// The format an identifier (as [`Format::id`] gives, or an extension) names.
    pub fn from_id(id: &str) -> Option<Format> {
        let id = id.trim().trim_start_matches('.').to_ascii_lowercase();
        Format::EVERY
            .into_iter()
            .find(|f| f.id() == id || f.extension() == id)
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Dst => "dst",
            Format::Exp => "exp",
            Format::Pes | Format::PesV1 => "pes",
            Format::Pec => "pec",
            Format::Jef => "jef",
            Format::Vp3 => "vp3",
            Format::Xxx => "xxx",
            Format::U01 => "u01",
            Format::SeedRam => "ram",
            Format::Bor => "bor",
        }
    }

    /// The format a file name's extension names (case-insensitive); `.pes` is version 6.
    pub fn from_path(path: &std::path::Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Format::EVERY.into_iter().find(|f| f.extension() == ext)
    }

    /// The format a file's first bytes (a few hundred suffice) show, where they show one:
    /// `#PES`, `#PEC`, `%vsm%`, a DST header (`LA:`, 512 bytes), a JEF header (its stitches'
    /// offset 0x74 + 8 per colour, flags 0x14 or 0x0A). EXP, XXX, U01 and the seed's program
    /// carry no signature: their extension decides.
    pub fn sniff(bytes: &[u8]) -> Option<Format> {
        if bytes.starts_with(b"#PES") {
            return Some(Format::Pes);
        }
        if bytes.starts_with(b"#PEC") {
            return Some(Format::Pec);
        }
        if bytes.starts_with(b"%vsm%") {
            return Some(Format::Vp3);
        }
        if bytes.starts_with(b"LA:") && bytes.len() >= 512 {
            return Some(Format::Dst);
        }
        if bytes.len() >= 0x74 {
            let u =
                |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
            let (start, colours) = (u(0) as usize, u(24) as usize);
            if colours < 1000 && start == 0x74 + 8 * colours && matches!(u(4), 0x0A | 0x14) {
                return Some(Format::Jef);
            }
        }
        None
    }

    /// The largest increment per axis of one record, in 0.1 mm.
    pub fn max_step(self) -> i32 {
        match self {
            Format::Dst => dst::MAX_STEP,
            Format::Exp => exp::MAX_STEP,
            Format::Pes | Format::PesV1 | Format::Pec => pec::MAX_STEP,
            Format::Jef => jef::MAX_STEP,
            Format::Vp3 => vp3::MAX_STEP,
            Format::Xxx => xxx::MAX_STEP,
            Format::U01 => u01::MAX_STEP,
            // 62 steps of 0.2 mm.
            Format::SeedRam | Format::Bor => 124,
        }
    }

    /// The plan as a file of this format.
    pub fn write(self, plan: &StitchPlan) -> Result<Vec<u8>, FormatError> {
        Ok(match self {
            Format::Dst => dst::write(&plan.name, &records::to_records(plan, dst::MAX_STEP, self)?),
            Format::Exp => exp::write(&records::to_records(plan, exp::MAX_STEP, self)?),
            Format::Pes => pes::write(plan, pes::Version::V6)?,
            Format::PesV1 => pes::write(plan, pes::Version::V1)?,
            Format::Pec => pec::write(plan)?,
            Format::Jef => jef::write(plan)?,
            Format::Vp3 => vp3::write(plan)?,
            Format::Xxx => xxx::write(plan)?,
            Format::U01 => u01::write(plan)?,
            Format::SeedRam => {
                // Program 1, started where the design's origin is, in its smallest hoop.
                let header = seed_ram::SeedHeader {
                    program: 1,
                    start: [0.0, 0.0],
                    hoop: crate::hoop::smallest_hoop(plan).ok(),
                };
                seed_ram::write(plan, &header)?
            }
            Format::Bor => bor::write(
                plan,
                &seed_ram::SeedHeader {
                    program: 1,
                    start: [0.0, 0.0],
                    hoop: crate::hoop::smallest_hoop(plan).ok(),
                },
            )?,
        })
    }

    /// Whether the file keeps each block's thread colour (exactly or as a chart thread).
    pub fn stores_colours(self) -> bool {
        !matches!(
            self,
            Format::Dst | Format::Exp | Format::U01 | Format::SeedRam | Format::Bor
        )
    }

    /// Reads a file; `name` names the design when the file carries no name.
    pub fn read(self, bytes: &[u8], name: &str) -> Result<StitchPlan, FormatError> {
        let (file_name, recs, rule) = match self {
            Format::Dst => {
                let (n, recs) = dst::read(bytes)?;
                (n, recs, records::TrimRule::Jumps(3))
            }
            Format::Exp => (None, exp::read(bytes)?, records::TrimRule::Explicit),
            Format::Pes | Format::PesV1 => return pes::read(bytes, name),
            Format::Pec => return pec::read(bytes, name),
            Format::Jef => return jef::read(bytes, name),
            Format::Vp3 => return vp3::read(bytes, name),
            Format::Xxx => return xxx::read(bytes, name),
            Format::U01 => return u01::read(bytes, name),
            Format::SeedRam => {
                let (mut plan, _) = seed_ram::read(bytes)?;
                plan.name = name.to_string();
                return Ok(plan);
            }
            Format::Bor => {
                let (mut plan, _) = bor::read(bytes)?;
                plan.name = name.to_string();
                return Ok(plan);
            }
        };
        let mut plan = records::to_plan(&recs, rule);
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
