//! grbl's real-time command bytes. They bypass the RX buffer and the planner: the firmware
//! picks them off in the serial interrupt, so they act at once even when the buffer is full.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Realtime {
    StatusQuery,
    FeedHold,
    CycleStart,
    SoftReset,
    SafetyDoor,
    JogCancel,
    FeedOverrideReset,
    FeedOverridePlus10,
    FeedOverrideMinus10,
    FeedOverridePlus1,
    FeedOverrideMinus1,
    RapidOverride100,
    RapidOverride50,
    RapidOverride25,
    SpindleOverrideReset,
    SpindleOverridePlus10,
    SpindleOverrideMinus10,
    SpindleOverridePlus1,
    SpindleOverrideMinus1,
    SpindleStopToggle,
    FloodToggle,
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
    pub fn byte(self) -> u8 {
        TABLE
            .iter()
            .find(|(r, _)| *r == self)
            .map(|(_, b)| *b)
            .unwrap_or(b'?')
    }

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
