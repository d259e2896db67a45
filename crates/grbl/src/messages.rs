//! grbl 1.1's numbered messages: `error:N`, `ALARM:N` and the `$N` settings, with the texts
//! of grbl's doc/csv tables, so a user reads what the firmware meant, not a bare number.

/// (code, short name, description) of every grbl 1.1 `error:N`.
const ERRORS: &[(u8, &str, &str)] = &[
    (1, "Expected command letter", "G-code words consist of a letter and a value. Letter was not found."),
    (2, "Bad number format", "Missing the expected G-code word value or numeric value format is not valid."),
    (3, "Invalid statement", "Grbl '$' system command was not recognized or supported."),
    (4, "Value < 0", "Negative value received for an expected positive value."),
    (5, "Setting disabled", "Homing cycle failure. Homing is not enabled via settings."),
    (6, "Value < 3 usec", "Minimum step pulse time must be greater than 3usec."),
    (7, "EEPROM read fail. Using defaults", "An EEPROM read failed. Auto-restoring affected EEPROM to default values."),
    (8, "Not idle", "Grbl '$' command cannot be used unless Grbl is IDLE. Ensures smooth operation during a job."),
    (9, "G-code lock", "G-code commands are locked out during alarm or jog state."),
    (10, "Homing not enabled", "Soft limits cannot be enabled without homing also enabled."),
    (11, "Line overflow", "Max characters per line exceeded. Received command line was not executed."),
    (12, "Step rate > 30kHz", "Grbl '$' setting value cause the step rate to exceed the maximum supported."),
    (13, "Check Door", "Safety door detected as opened and door state initiated."),
    (14, "Line length exceeded", "Build info or startup line exceeded EEPROM line length limit. Line not stored."),
    (15, "Travel exceeded", "Jog target exceeds machine travel. Jog command has been ignored."),
    (16, "Invalid jog command", "Jog command has no '=' or contains prohibited g-code."),
    (17, "Setting disabled", "Laser mode requires PWM output."),
    (20, "Unsupported command", "Unsupported or invalid g-code command found in block."),
    (21, "Modal group violation", "More than one g-code command from same modal group found in block."),
    (22, "Undefined feed rate", "Feed rate has not yet been set or is undefined."),
    (23, "Invalid gcode ID:23", "G-code command in block requires an integer value."),
    (24, "Invalid gcode ID:24", "More than one g-code command that requires axis words found in block."),
    (25, "Invalid gcode ID:25", "Repeated g-code word found in block."),
    (26, "Invalid gcode ID:26", "No axis words found in block for g-code command or current modal state which requires them."),
    (27, "Invalid gcode ID:27", "Line number value is invalid."),
    (28, "Invalid gcode ID:28", "G-code command is missing a required value word."),
    (29, "Invalid gcode ID:29", "G59.x work coordinate systems are not supported."),
    (30, "Invalid gcode ID:30", "G53 only allowed with G0 and G1 motion modes."),
    (31, "Invalid gcode ID:31", "Axis words found in block when no command or current modal state uses them."),
    (32, "Invalid gcode ID:32", "G2 and G3 arcs require at least one in-plane axis word."),
    (33, "Invalid gcode ID:33", "Motion command target is invalid."),
    (34, "Invalid gcode ID:34", "Arc radius value is invalid."),
    (35, "Invalid gcode ID:35", "G2 and G3 arcs require at least one in-plane offset word."),
    (36, "Invalid gcode ID:36", "Unused value words found in block."),
    (37, "Invalid gcode ID:37", "G43.1 dynamic tool length offset is not assigned to configured tool length axis."),
    (38, "Invalid gcode ID:38", "Tool number greater than max supported value."),
];

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
    pub number: u16,
    pub name: &'static str,
    pub unit: &'static str,
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
    s(10, "Status report options", "mask", 1.0),
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
pub fn error_text(code: u8) -> Option<(&'static str, &'static str)> {
    lookup(ERRORS, code)
}

/// Name and description of `ALARM:code`, if grbl 1.1 defines it.
pub fn alarm_text(code: u8) -> Option<(&'static str, &'static str)> {
    lookup(ALARMS, code)
}

/// Every defined error code, in order (for documentation and tests).
pub fn error_codes() -> impl Iterator<Item = u8> {
    ERRORS.iter().map(|e| e.0)
}

/// Every defined alarm code, in order.
pub fn alarm_codes() -> impl Iterator<Item = u8> {
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
