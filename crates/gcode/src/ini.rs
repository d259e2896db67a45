//! What a LinuxCNC INI file tells the interpreter beyond the subroutine settings:
//! `[RS274NGC]ORIENT_OFFSET` (added to every M19 angle) and, with `[RS274NGC]INI_VARS`
//! (on unless set to 0, as in `rs274ngc_pre.cc`), every numeric entry as the read-only
//! parameter `#<_ini[section]name>` (`interp_namedparams.cc`, `fetch_ini_param`).

/// The interpreter's settings read from an INI file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IniSettings {
    /// Degrees added to M19's R (or taken alone when R is absent).
    pub orient_offset: f64,
    /// `[RS274NGC]DISABLE_G92_PERSISTENCE`: the saved G92 parameters (#5210–#5219) are
    /// cleared at start instead of put back in force.
    pub disable_g92_persistence: bool,
    /// `(name, value)`: names as `_ini[section]name`, lower-case (parameter names are
    /// compared lower-case; rs274 upper-cases both parts before its look-up).
    pub values: Vec<(String, f64)>,
}

impl IniSettings {
    /// Read an INI file's text. Lines are `[SECTION]`, `NAME = VALUE`, or comments (`#`,
    /// `;`); a value that is not a number is not a parameter (rs274's `findReal` fails on
    /// it too). Nothing here is an error: LinuxCNC ignores what it does not understand.
    pub fn parse(text: &str) -> IniSettings {
        let mut out = IniSettings::default();
        let mut section = String::new();
        let mut ini_vars = true;
        for line in text.lines() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with(';') {
                continue;
            }
            if let Some(rest) = line.strip_prefix('[') {
                if let Some(end) = rest.find(']') {
                    section = rest[..end].trim().to_ascii_uppercase();
                }
                continue;
            }
            let Some((name, value)) = line.split_once('=') else {
                continue;
            };
            let name = name.trim().to_ascii_uppercase();
            let value = value.trim();
            let number = value.parse::<f64>().ok().filter(|v| v.is_finite());
            if section == "RS274NGC" {
                match name.as_str() {
                    "ORIENT_OFFSET" => out.orient_offset = number.unwrap_or(0.0),
                    "INI_VARS" => ini_vars = truth(value),
                    "DISABLE_G92_PERSISTENCE" => out.disable_g92_persistence = truth(value),
                    _ => {}
                }
            }
            if let Some(v) = number {
                // The first entry of a name wins, as IniFile::Find returns the first.
                let key = format!(
                    "_ini[{}]{}",
                    section.to_ascii_lowercase(),
                    name.to_ascii_lowercase()
                );
                if !out.values.iter().any(|(k, _)| *k == key) {
                    out.values.push((key, v));
                }
            }
        }
        if !ini_vars {
            out.values.clear();
        }
        out
    }
}

/// An INI boolean as IniFile::findBoolV reads it: 1/true/yes/on, any case.
fn truth(value: &str) -> bool {
    matches!(
        value.to_ascii_lowercase().as_str(),
        "1" | "true" | "yes" | "on"
    )
}

/// A LinuxCNC parameter file (`.var`): lines `NUMBER VALUE`, anything else ignored (as
/// rs274's `read_parameter_file` skips lines it cannot read as two numbers).
pub fn parse_var_file(text: &str) -> Vec<(i64, f64)> {
    text.lines()
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            let n = it.next()?.parse::<i64>().ok()?;
            let v = it.next()?.parse::<f64>().ok().filter(|v| v.is_finite())?;
            (1..=5601).contains(&n).then_some((n, v))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_orient_offset_and_values() {
        let s = IniSettings::parse(
            "[RS274NGC]\nORIENT_OFFSET = 42.0\n# c\n[VARS]\nTOOLCHANGE_X = 10\nname = text\n",
        );
        assert_eq!(s.orient_offset, 42.0);
        assert!(s
            .values
            .contains(&("_ini[vars]toolchange_x".to_string(), 10.0)));
        assert!(!s.values.iter().any(|(k, _)| k == "_ini[vars]name"));
    }

    #[test]
    fn ini_vars_off_hides_values() {
        let s = IniSettings::parse("[RS274NGC]\nINI_VARS = 0\n[VARS]\nX = 1\n");
        assert!(s.values.is_empty());
    }
}
