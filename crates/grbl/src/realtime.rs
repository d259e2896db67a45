//! grbl's real-time command bytes. They bypass the RX buffer and the planner: the firmware
//! picks them off in the serial interrupt, so they act at once even when the buffer is full.

/// A real-time command: one byte, acted on at once, outside the line protocol.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Realtime {
    /// `?`: status report.
    StatusQuery,
    /// `!`: feed hold.
    FeedHold,
    /// `~`: cycle start / resume.
    CycleStart,
    /// Ctrl-X: soft reset.
    SoftReset,
    /// 0x84: safety door.
    SafetyDoor,
    /// 0x85: jog cancel.
    JogCancel,
    /// 0x90: feed override 100 %.
    FeedOverrideReset,
    /// 0x91: feed override +10 %.
    FeedOverridePlus10,
    /// 0x92: feed override −10 %.
    FeedOverrideMinus10,
    /// 0x93: feed override +1 %.
    FeedOverridePlus1,
    /// 0x94: feed override −1 %.
    FeedOverrideMinus1,
    /// 0x95: rapid override 100 %.
    RapidOverride100,
    /// 0x96: rapid override 50 %.
    RapidOverride50,
    /// 0x97: rapid override 25 %.
    RapidOverride25,
    /// 0x99: spindle override 100 %.
    SpindleOverrideReset,
    /// 0x9A: spindle override +10 %.
    SpindleOverridePlus10,
    /// 0x9B: spindle override −10 %.
    SpindleOverrideMinus10,
    /// 0x9C: spindle override +1 %.
    SpindleOverridePlus1,
    /// 0x9D: spindle override −1 %.
    SpindleOverrideMinus1,
    /// 0x9E: spindle stop (in a hold).
    SpindleStopToggle,
    /// 0xA0: flood coolant toggle.
    FloodToggle,
    /// 0xA1: mist coolant toggle.
    MistToggle,
}

const TABLE: &[(Realtime, u8)] = &[
    (Realtime::StatusQuery, b'?'),
    (Realtime::FeedHold, b'!'),
    (Realtime::CycleStart, b'~'),
    (Realtime::SoftReset, 0x18),
    (Realtime::SafetyDoor, 0x84),
    (Realtime::JogCancel, 0x85),
    (Realtime::FeedOverrideReset, 0x90),
    (Realtime::FeedOverridePlus10, 0x91),
    (Realtime::FeedOverrideMinus10, 0x92),
    (Realtime::FeedOverridePlus1, 0x93),
    (Realtime::FeedOverrideMinus1, 0x94),
    (Realtime::RapidOverride100, 0x95),
    (Realtime::RapidOverride50, 0x96),
    (Realtime::RapidOverride25, 0x97),
    (Realtime::SpindleOverrideReset, 0x99),
    (Realtime::SpindleOverridePlus10, 0x9A),
    (Realtime::SpindleOverrideMinus10, 0x9B),
    (Realtime::SpindleOverridePlus1, 0x9C),
    (Realtime::SpindleOverrideMinus1, 0x9D),
    (Realtime::SpindleStopToggle, 0x9E),
    (Realtime::FloodToggle, 0xA0),
    (Realtime::MistToggle, 0xA1),
];

/// Operator names for the override and accessory bytes, as typed in the console:
/// `f+10 f-10 f+1 f-1 f100` (feed), `r100 r50 r25` (rapids), `s+10 s-10 s+1 s-1 s100`
/// (spindle), `sstop`, `flood`, `mist`.
pub fn override_by_name(name: &str) -> Option<Realtime> {
    Some(match name {
        "f+10" => Realtime::FeedOverridePlus10,
        "f-10" => Realtime::FeedOverrideMinus10,
        "f+1" => Realtime::FeedOverridePlus1,
        "f-1" => Realtime::FeedOverrideMinus1,
        "f100" => Realtime::FeedOverrideReset,
        "r100" => Realtime::RapidOverride100,
        "r50" => Realtime::RapidOverride50,
        "r25" => Realtime::RapidOverride25,
        "s+10" => Realtime::SpindleOverridePlus10,
        "s-10" => Realtime::SpindleOverrideMinus10,
        "s+1" => Realtime::SpindleOverridePlus1,
        "s-1" => Realtime::SpindleOverrideMinus1,
        "s100" => Realtime::SpindleOverrideReset,
        "sstop" => Realtime::SpindleStopToggle,
        "flood" => Realtime::FloodToggle,
        "mist" => Realtime::MistToggle,
        _ => return None,
    })
}

impl Realtime {
    /// The byte sent for this command.
    pub fn byte(self) -> u8 {
        TABLE
            .iter()
            .find(|(r, _)| *r == self)
            .map(|(_, b)| *b)
            .unwrap_or(b'?')
    }

    /// The command a byte stands for, if any.
    pub fn from_byte(b: u8) -> Option<Realtime> {
        TABLE.iter().find(|(_, x)| *x == b).map(|(r, _)| *r)
    }

    /// Whether the firmware swallows this byte before the line buffer. Extended-ASCII bytes
    /// (≥ 0x80) never reach the line buffer in grbl 1.1, even unknown ones.
    pub fn is_realtime_byte(b: u8) -> bool {
        b >= 0x80 || matches!(b, b'?' | b'!' | b'~' | 0x18)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_round_trip() {
        for (r, b) in TABLE {
            assert_eq!(r.byte(), *b);
            assert_eq!(Realtime::from_byte(*b), Some(*r));
            assert!(Realtime::is_realtime_byte(*b));
        }
        assert!(!Realtime::is_realtime_byte(b'G'));
        assert_eq!(override_by_name("f+10").map(Realtime::byte), Some(0x91));
        assert_eq!(override_by_name("r25").map(Realtime::byte), Some(0x97));
        assert_eq!(override_by_name("s-1").map(Realtime::byte), Some(0x9D));
        assert_eq!(override_by_name("x"), None);
    }
}
