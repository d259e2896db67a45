//! Which grbl-family firmware the emulator claims to be, and what differs between them on
//! the wire: buffer sizes, the reset banner, the `$I` report, boot messages, whether a TCP
//! client is greeted, and what `Bf:` counts.
//!
//! Sources: grbl 1.1h (`report.c`, `config.h`); grblHAL as its own Simulator answers
//! (banner, `$I`, `Bf:100,1023` at rest, 100 planner blocks and a 1024-byte RX buffer);
//! FluidNC's serial log (banner `Grbl 3.x [FluidNC vX (variant) '$' for help]`, `[MSG:INFO:
//! …]` lines, Grbl_ESP32's 16-block planner and 256-byte RX buffer).

use std::fmt;
use std::str::FromStr;

/// Which grbl-family firmware the emulator answers as.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Flavor {
    /// grbl 1.1h on an ATmega328P.
    #[default]
    Grbl,
    /// grblHAL (core 2026xxxx), as its Simulator builds it.
    GrblHal,
    /// FluidNC on an ESP32.
    FluidNc,
}

impl Flavor {
    /// The version string this firmware reports.
    pub fn version(self) -> &'static str {
        match self {
            Flavor::Grbl => "1.1h",
            Flavor::GrblHal => "1.1f",
            Flavor::FluidNc => "3.7",
        }
    }

    /// (usable planner blocks, RX buffer bytes).
    pub fn buffers(self) -> (usize, usize) {
        match self {
            Flavor::Grbl => (15, 128),
            Flavor::GrblHal => (100, 1024),
            Flavor::FluidNc => (15, 256),
        }
    }

    /// The line a reset prints (without the blank line before it).
    pub fn banner(self, version: &str) -> String {
        match self {
            Flavor::Grbl => format!("Grbl {version} ['$' for help]"),
            Flavor::GrblHal => format!("GrblHAL {version} ['$' or '$HELP' for help]"),
            Flavor::FluidNc => {
                format!("Grbl {version} [FluidNC v{version}.12 (noradio) '$' for help]")
            }
        }
    }

    /// Lines a (re)boot prints after the banner.
    pub fn boot_messages(self) -> Vec<String> {
        match self {
            Flavor::FluidNc => vec![
                "[MSG:INFO: FluidNC v3.7.12 https://github.com/bdring/FluidNC]".into(),
                "[MSG:INFO: Machine Oficina emulator]".into(),
            ],
            _ => Vec::new(),
        }
    }

    /// The `$I` report before its `ok`.
    pub fn build_info(self, version: &str, blocks: usize, rx: usize) -> Vec<String> {
        match self {
            Flavor::Grbl => vec![
                format!("[VER:{version}.20190830:]"),
                format!("[OPT:V,{blocks},{rx}]"),
            ],
            Flavor::GrblHal => vec![
                format!("[VER:{version}.20260817:]"),
                format!("[OPT:VNML+,{blocks},{rx},3,0]"),
                "[AXS:3:XYZ]".into(),
                "[NEWOPT:ENUMS,RT+,TC,SED]".into(),
                "[FIRMWARE:grblHAL]".into(),
                "[DRIVER:Oficina emulator]".into(),
            ],
            // FluidNC's `[OPT:]` carries option letters only: a sender must learn the RX
            // size from an idle `Bf:` or fall back to send-response.
            Flavor::FluidNc => vec![
                format!("[VER:{version} FluidNC v{version}.12:]"),
                "[OPT:PH]".into(),
                "[MSG: Machine: Oficina emulator]".into(),
            ],
        }
    }

    /// A feedback message as the firmware words it: grbl's `[MSG:Caution: Unlocked]`,
    /// FluidNC's `[MSG:INFO: Caution: Unlocked]` (every message of its log carries a level).
    pub fn message(self, text: &str) -> String {
        match self {
            Flavor::FluidNc => format!("[MSG:INFO: {text}]"),
            _ => format!("[MSG:{text}]"),
        }
    }

    /// A network client is greeted with the banner only by classic grbl emulations; grblHAL
    /// and FluidNC say nothing until spoken to.
    pub fn greets_tcp_clients(self) -> bool {
        self == Flavor::Grbl
    }

    /// grblHAL frees a planner block (and so counts it out of `Bf:`) once its steps are
    /// prepared, up to this many seconds before the block has run; grbl and FluidNC keep it
    /// until it completes. grblHAL prepares 10 segments of ~10 ms each ahead of the steppers.
    pub fn prepared_ahead(self) -> f64 {
        match self {
            Flavor::GrblHal => 0.1,
            _ => 0.0,
        }
    }
}

impl FromStr for Flavor {
    type Err = String;
    fn from_str(s: &str) -> Result<Flavor, String> {
        match s.to_ascii_lowercase().as_str() {
            "grbl" => Ok(Flavor::Grbl),
            "grblhal" => Ok(Flavor::GrblHal),
            "fluidnc" => Ok(Flavor::FluidNc),
            _ => Err(format!(
                "unknown firmware flavor `{s}`: use grbl, grblhal or fluidnc"
            )),
        }
    }
}

impl fmt::Display for Flavor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Flavor::Grbl => "grbl",
            Flavor::GrblHal => "grblhal",
            Flavor::FluidNc => "fluidnc",
        })
    }
}
