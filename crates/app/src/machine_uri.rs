//! Machines named by a URI: real grbl-family firmware by its link address, Marlin by
//! `marlin:PORT[@baud]` or `marlin+tcp://HOST:PORT`, anything else a profile of the built-in
//! virtual machine.

use crate::{profile, Error};
use oficina_gcode::ToolTable;
use oficina_machine::{Machine, VirtualMachine};

/// Real firmware is named by a link address; anything else is a virtual machine profile.
pub fn is_firmware(machine: &str) -> bool {
    machine.starts_with("grbl:")
        || machine.starts_with("tcp://")
        || machine.starts_with("/dev/")
        || is_marlin(machine)
}

/// Marlin firmware (a Makelangelo): `marlin:/dev/ttyUSB0[@baud]`, `marlin+tcp://HOST:PORT`.
pub fn is_marlin(machine: &str) -> bool {
    machine.starts_with("marlin:") || machine.starts_with("marlin+")
}

/// Open the machine `spec` names (`virtual` is the default profile); the work offset applies
/// to the virtual machine only (real firmware keeps its own).
pub fn open_machine(spec: &str, work_offset: Option<[f64; 3]>) -> Result<Box<dyn Machine>, Error> {
    open_machine_with(spec, work_offset, oficina_gcode::DEFAULT_MAX_LINE_LEN)
}

/// [`open_machine`] with the longest program line the virtual machine accepts, in bytes.
pub fn open_machine_with(
    spec: &str,
    work_offset: Option<[f64; 3]>,
    max_line_len: usize,
) -> Result<Box<dyn Machine>, Error> {
    if is_firmware(spec) {
        if work_offset.is_some() {
            return Err(Error("--work-offset is for the virtual machine; real firmware keeps its own G54 (set it with G10 L20 in the console)".into()));
        }
        return open_firmware(spec, oficina_grbl::ToolChange::default());
    }
    open_machine_with_tools(spec, work_offset, max_line_len, None)
}

/// Real firmware at `spec` (`grbl:/dev/ttyUSB0`, `tcp://HOST:PORT`) whose sender handles
/// `M6` as `tool_change` says.
pub fn open_firmware(
    spec: &str,
    tool_change: oficina_grbl::ToolChange,
) -> Result<Box<dyn Machine>, Error> {
    tool_change.validate().map_err(Error)?;
    if is_marlin(spec) {
        // Marlin interprets M6 itself (or refuses it): no tool-change policy to apply.
        let device = oficina_grbl::MarlinDevice::new(spec)
            .map_err(|e| Error(format!("--machine {spec}: {e}")))?;
        return Ok(Box::new(device));
    }
    let mut device =
        oficina_grbl::GrblDevice::new(spec).map_err(|e| Error(format!("--machine {spec}: {e}")))?;
    device.settings.tool_change = tool_change;
    Ok(Box::new(device))
}

/// [`open_machine_with`] and a tool table for the virtual machine's interpreter (G43, M6).
/// Real firmware interprets the program itself and has no tool table: refused there.
pub fn open_machine_with_tools(
    spec: &str,
    work_offset: Option<[f64; 3]>,
    max_line_len: usize,
    tools: Option<ToolTable>,
) -> Result<Box<dyn Machine>, Error> {
    if is_firmware(spec) {
        if tools.is_some() {
            return Err(Error("--tool-table is for the virtual machine; real firmware has no tool table (grbl ignores G43 H)".into()));
        }
        return open_machine_with(spec, work_offset, max_line_len);
    }
    let profile = profile::resolve_with_offset(virtual_name(spec), work_offset)?;
    // No table given: the one the profile names, if any.
    let tools = match tools {
        Some(t) => Some(t),
        None => profile::tool_table(&profile, spec, oficina_canon::Units::Mm)?,
    };
    let vm = VirtualMachine::new(profile).with_max_line_len(max_line_len);
    Ok(Box::new(match tools {
        Some(t) => vm.with_tool_table(t),
        None => vm,
    }))
}

/// `virtual` (and `virtual:NAME`) name the bundled profiles.
pub(crate) fn virtual_name(spec: &str) -> &str {
    match spec.strip_prefix("virtual") {
        Some("") => profile::DEFAULT,
        Some(rest) => rest.strip_prefix(':').unwrap_or(spec),
        None => spec,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_pick_the_machine_kind() {
        assert!(is_firmware("grbl:/dev/ttyUSB0@115200"));
        assert!(is_firmware("tcp://127.0.0.1:2323"));
        assert!(is_firmware("marlin:/dev/ttyUSB0") && is_marlin("marlin+tcp://10.0.0.2:23"));
        assert!(!is_marlin("grbl:/dev/ttyUSB0"));
        assert!(!is_firmware("virtual"));
        assert_eq!(virtual_name("virtual"), profile::DEFAULT);
        assert_eq!(virtual_name("virtual:hotwire-xy"), "hotwire-xy");
        assert_eq!(virtual_name("grbl-router"), "grbl-router");
    }

    #[test]
    fn unknown_profiles_and_offsets_on_firmware_are_refused() {
        let e = open_machine("no-such-profile", None).err().unwrap().0;
        assert!(e.contains("no-such-profile"), "{e}");
        let e = open_machine("tcp://127.0.0.1:1", Some([0.0; 3]))
            .err()
            .unwrap()
            .0;
        assert!(e.contains("work-offset"), "{e}");
        assert!(open_machine("virtual", None).is_ok());
    }
}
