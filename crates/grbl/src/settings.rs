//! `$$` settings, read and written with their names and units. A write is checked here
//! first (known number, boolean 0/1, whole masks, no negatives) so the user hears what is
//! wrong before the firmware's bare `error:N`, then grbl's own verdict is reported.

use crate::messages::{self, SettingInfo};
use crate::response::Response;
use crate::sender::Sender;

/// One `$N=value` setting as the firmware reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    /// `$` number.
    pub number: u16,
    /// Its value.
    pub value: f64,
    /// Name, unit and default for settings grbl 1.1 defines (forks add others).
    pub info: Option<&'static SettingInfo>,
}

impl Setting {
    /// `$N=value (name, unit)`, or the bare setting when unknown.
    pub fn describe(&self) -> String {
        match self.info {
            Some(i) => format!("${}={} ({}, {})", self.number, self.value, i.name, i.unit),
            None => format!("${}={} (not a grbl 1.1 setting)", self.number, self.value),
        }
    }
}

/// Reads every setting with `$$` (the machine must be idle or in alarm).
pub fn read(sender: &mut Sender) -> Result<Vec<Setting>, String> {
    let reply = sender.command("$$").map_err(|e| e.to_string())?;
    if let Some(code) = reply.error {
        return Err(format!("$$ refused: {}", messages::describe_error(code)));
    }
    Ok(reply
        .lines
        .iter()
        .filter_map(|l| match Response::parse(l) {
            Response::Setting { number, value } => value.parse().ok().map(|value| Setting {
                number,
                value,
                info: messages::setting_info(number),
            }),
            _ => None,
        })
        .collect())
}

/// Checks a value against the setting's kind before it is sent.
pub(crate) fn validate(number: u16, value: f64) -> Result<&'static SettingInfo, String> {
    let info = messages::setting_info(number)
        .ok_or_else(|| format!("${number}: grbl 1.1 has no such setting"))?;
    if !value.is_finite() || value < 0.0 {
        return Err(format!(
            "${number} ({}): {value} must be zero or positive",
            info.name
        ));
    }
    match info.unit {
        "boolean" if value != 0.0 && value != 1.0 => {
            Err(format!("${number} ({}) is a boolean: 0 or 1", info.name))
        }
        "mask" if value.fract() != 0.0 || value > 255.0 => Err(format!(
            "${number} ({}) is a bit mask: a whole number 0-255",
            info.name
        )),
        _ => Ok(info),
    }
}

/// Writes `$number=value` and reads it back.
pub fn write(sender: &mut Sender, number: u16, value: f64) -> Result<Setting, String> {
    let info = validate(number, value)?;
    let reply = sender
        .command(&format!("${number}={value}"))
        .map_err(|e| e.to_string())?;
    if let Some(code) = reply.error {
        return Err(format!(
            "${number} ({}) = {value} refused: {}",
            info.name,
            messages::describe_error(code)
        ));
    }
    read(sender)?
        .into_iter()
        .find(|s| s.number == number)
        .ok_or_else(|| format!("${number} was accepted but is missing from $$"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_setting() {
        assert!(validate(110, 5000.0).is_ok());
        assert!(validate(21, 2.0)
            .unwrap_err()
            .contains("Hard limits enable"));
        assert!(validate(3, 1.5).unwrap_err().contains("bit mask"));
        assert!(validate(120, -1.0)
            .unwrap_err()
            .contains("zero or positive"));
        assert!(validate(7, 1.0).unwrap_err().contains("no such setting"));
    }
}
