//! grbl 1.1's numbered messages: `error:N`, `ALARM:N` and the `$N` settings, with the texts
//! of grbl's doc/csv tables, so a user reads what the firmware meant, not a bare number.
//! The error table is the G-code interpreter's ([`oficina_gcode::grbl_errors`]): one copy.

/// (code, short name, description) of every grbl 1.1 `ALARM:N`.
const ALARMS: &[(u8, &str, &str)] = &[
    (1, "Hard limit", "Hard limit has been triggered. Machine position is likely lost due to sudden halt. Re-homing is highly recommended."),
    (2, "Soft limit", "Soft limit alarm. G-code motion target exceeds machine travel. Machine position retained. Alarm may be safely unlocked."),
    (3, "Abort during cycle", "Reset while in motion. Machine position is likely lost due to sudden halt. Re-homing is highly recommended."),
    (4, "Probe fail", "Probe fail. Probe is not in the expected initial state before starting probe cycle when G38.2 and G38.3 is not triggered and G38.4 and G38.5 is triggered."),
    (5, "Probe fail", "Probe fail. Probe did not contact the workpiece within the programmed travel for G38.2 and G38.4."),
    (6, "Homing fail", "Homing fail. The active homing cycle was reset."),
    (7, "Homing fail", "Homing fail. Safety door was opened during homing cycle."),
    (8, "Homing fail", "Homing fail. Pull off travel failed to clear limit switch. Try increasing pull-off setting or check wiring."),
    (9, "Homing fail", "Homing fail. Could not find limit switch within search distances. Try increasing max travel, decreasing pull-off distance, or check wiring."),
    (10, "Homing fail", "Homing fail. Second dual axis limit switch failed to trigger within configured search distance after first."),
];

/// One `$N` setting: its number, name, unit and grbl's generic default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettingInfo {
    /// `$` number.
    pub number: u16,
    /// Its name.
    pub name: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// grbl's generic default.
    pub default: f64,
}

const fn s(number: u16, name: &'static str, unit: &'static str, default: f64) -> SettingInfo {
    SettingInfo {
        number,
        name,
        unit,
        default,
    }
}

/// grbl 1.1's settings with the defaults of `DEFAULTS_GENERIC` (defaults.h).
pub const SETTINGS: &[SettingInfo] = &[
    s(0, "Step pulse time", "microseconds", 10.0),
    s(1, "Step idle delay", "milliseconds", 25.0),
    s(2, "Step pulse invert", "mask", 0.0),
    s(3, "Step direction invert", "mask", 0.0),
    s(4, "Invert step enable pin", "boolean", 0.0),
    s(5, "Invert limit pins", "boolean", 0.0),
    s(6, "Invert probe pin", "boolean", 0.0),
    s(10, "StatusReport report options", "mask", 1.0),
    s(11, "Junction deviation", "millimeters", 0.010),
    s(12, "Arc tolerance", "millimeters", 0.002),
    s(13, "Report in inches", "boolean", 0.0),
    s(20, "Soft limits enable", "boolean", 0.0),
    s(21, "Hard limits enable", "boolean", 0.0),
    s(22, "Homing cycle enable", "boolean", 0.0),
    s(23, "Homing direction invert", "mask", 0.0),
    s(24, "Homing locate feed rate", "mm/min", 25.0),
    s(25, "Homing search seek rate", "mm/min", 500.0),
    s(26, "Homing switch debounce delay", "milliseconds", 250.0),
    s(27, "Homing switch pull-off distance", "millimeters", 1.0),
    s(30, "Maximum spindle speed", "RPM", 1000.0),
    s(31, "Minimum spindle speed", "RPM", 0.0),
    s(32, "Laser-mode enable", "boolean", 0.0),
    s(100, "X-axis travel resolution", "step/mm", 250.0),
    s(101, "Y-axis travel resolution", "step/mm", 250.0),
    s(102, "Z-axis travel resolution", "step/mm", 250.0),
    s(110, "X-axis maximum rate", "mm/min", 500.0),
    s(111, "Y-axis maximum rate", "mm/min", 500.0),
    s(112, "Z-axis maximum rate", "mm/min", 500.0),
    s(120, "X-axis acceleration", "mm/sec^2", 10.0),
    s(121, "Y-axis acceleration", "mm/sec^2", 10.0),
    s(122, "Z-axis acceleration", "mm/sec^2", 10.0),
    s(130, "X-axis maximum travel", "millimeters", 200.0),
    s(131, "Y-axis maximum travel", "millimeters", 200.0),
    s(132, "Z-axis maximum travel", "millimeters", 200.0),
];

fn lookup(
    table: &[(u8, &'static str, &'static str)],
    code: u8,
) -> Option<(&'static str, &'static str)> {
    table
        .iter()
        .find(|(c, _, _)| *c == code)
        .map(|(_, n, d)| (*n, *d))
}

/// Name and description of `error:code`, if grbl 1.1 defines it.
pub(crate) fn error_text(code: u8) -> Option<(&'static str, &'static str)> {
    oficina_gcode::grbl_errors::error_text(u16::from(code))
}

/// Name and description of `ALARM:code`, if grbl 1.1 defines it.
pub(crate) fn alarm_text(code: u8) -> Option<(&'static str, &'static str)> {
    lookup(ALARMS, code)
}

/// Every defined error code, in order (for documentation and tests).
#[cfg(test)]
fn error_codes() -> impl Iterator<Item = u8> {
    oficina_gcode::grbl_errors::error_codes()
}

/// Every defined alarm code, in order.
#[cfg(test)]
fn alarm_codes() -> impl Iterator<Item = u8> {
    ALARMS.iter().map(|a| a.0)
}

/// A one-line human reading of `error:code`, e.g. `error:22 (Undefined feed rate: …)`.
pub fn describe_error(code: u8) -> String {
    match error_text(code) {
        Some((name, desc)) => format!("error:{code} ({name}: {desc})"),
        None => {
            format!("error:{code} (not a grbl 1.1 error code; the firmware may be a grbl fork)")
        }
    }
}

/// A one-line human reading of `ALARM:code`.
pub fn describe_alarm(code: u8) -> String {
    match alarm_text(code) {
        Some((name, desc)) => format!("ALARM:{code} ({name}: {desc})"),
        None => {
            format!("ALARM:{code} (not a grbl 1.1 alarm code; the firmware may be a grbl fork)")
        }
    }
}

/// Name, unit and default of setting `$number`, for settings grbl 1.1 defines.
pub fn setting_info(number: u16) -> Option<&'static SettingInfo> {
    SETTINGS.iter().find(|s| s.number == number)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_grbl_error_and_alarm_has_text() {
        // grbl 1.1 defines errors 1..=17 and 20..=38, alarms 1..=10.
        let errors: Vec<u8> = error_codes().collect();
        let expected: Vec<u8> = (1..=17).chain(20..=38).collect();
        assert_eq!(errors, expected);
        assert_eq!(
            alarm_codes().collect::<Vec<_>>(),
            (1..=10).collect::<Vec<_>>()
        );
        assert!(describe_error(22).contains("Undefined feed rate"));
        assert!(describe_alarm(3).contains("Reset while in motion"));
        assert!(describe_error(99).contains("not a grbl 1.1"));
    }

    #[test]
    fn settings_have_units() {
        assert_eq!(setting_info(110).unwrap().unit, "mm/min");
        assert_eq!(setting_info(120).unwrap().unit, "mm/sec^2");
        assert!(setting_info(7).is_none());
    }
}
