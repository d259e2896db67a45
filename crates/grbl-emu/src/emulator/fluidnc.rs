//! FluidNC's own `$` commands beside the grbl-compatible ones, as its wiki ("Commands and
//! Settings") and its command table document them: settings have names (`$Config/Filename`,
//! `$Message/Level`, `$Report/StatusReport`, the last also grbl's `$10`), matched without regard to
//! case; `$Name` shows one as `$Name=value`, `$Name=value` sets it; `$S` (`$Settings/List`)
//! lists them; the machine's YAML configuration is dumped by `$CD` (`$Config/Dump`) and each
//! item of it is a setting too, named by its path (`$/axes/x/max_rate_mm_per_min=5000`). An
//! unknown name is error 3, as in grbl.
//!
//! The emulator's YAML is the part grbl numbers: per axis `steps_per_mm` ($100+a),
//! `max_rate_mm_per_min` ($110+a), `acceleration_mm_per_sec2` ($120+a) and `max_travel_mm`
//! ($130+a). Setting one goes through the `$N=value` path, so its checks are grbl's.

use std::collections::BTreeMap;

const AXES: [&str; 3] = ["x", "y", "z"];

/// FluidNC's YAML name of each axis item and the grbl setting it is (for axis 0).
const AXIS_ITEMS: [(&str, u16); 4] = [
    ("steps_per_mm", 100),
    ("max_rate_mm_per_min", 110),
    ("acceleration_mm_per_sec2", 120),
    ("max_travel_mm", 130),
];

/// FluidNC's `Message/Level` choices.
const LEVELS: [&str; 6] = ["None", "Error", "Warning", "Info", "Debug", "Verbose"];

/// The named settings that are not grbl's numbers.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Named {
    pub config_filename: String,
    pub message_level: &'static str,
}

impl Default for Named {
    fn default() -> Self {
        Named {
            config_filename: "config.yaml".into(),
            message_level: "Info",
        }
    }
}

/// What a `$…` line comes to on FluidNC.
#[derive(Debug, PartialEq)]
pub(super) enum Outcome {
    /// Lines to print before `ok`.
    Say(Vec<String>),
    Error(u8),
    /// Set grbl setting `$N` to this value text (through grbl's own checks).
    SetNumbered(u16, String),
    /// Not a FluidNC name: the grbl command set decides.
    NotFluid,
}

/// `cmd` is the line after its `$`. `idle`: the machine may change settings; `in_cycle`:
/// a job runs or holds (FluidNC refuses long listings then).
pub(super) fn command(
    cmd: &str,
    named: &mut Named,
    settings: &BTreeMap<u16, f64>,
    idle: bool,
    in_cycle: bool,
) -> Outcome {
    let (key, value) = match cmd.split_once('=') {
        Some((k, v)) => (k.trim(), Some(v)),
        None => (cmd.trim(), None),
    };
    let is = |a: &str| key.eq_ignore_ascii_case(a);
    if value.is_none() && (is("S") || is("Settings/List")) {
        if in_cycle {
            return Outcome::Error(8);
        }
        return Outcome::Say(list(named, settings));
    }
    if value.is_none() && (is("CD") || is("Config/Dump")) {
        return Outcome::Say(dump(settings));
    }
    if let Some(path) = key.strip_prefix('/') {
        let Some(n) = yaml_setting(path) else {
            return Outcome::Error(3);
        };
        return match value {
            None => Outcome::Say(vec![format!("${key}={:.3}", setting(settings, n))]),
            Some(v) => Outcome::SetNumbered(n, v.to_string()),
        };
    }
    if is("Report/StatusReport") {
        return match value {
            None => Outcome::Say(vec![format!(
                "$Report/StatusReport={}",
                setting(settings, 10) as i64
            )]),
            Some(v) => Outcome::SetNumbered(10, v.to_string()),
        };
    }
    let named_key = is("Config/Filename") || is("Message/Level");
    if !named_key {
        return Outcome::NotFluid;
    }
    let Some(v) = value else {
        let shown = if is("Config/Filename") {
            format!("$Config/Filename={}", named.config_filename)
        } else {
            format!("$Message/Level={}", named.message_level)
        };
        return Outcome::Say(vec![shown]);
    };
    if !idle {
        return Outcome::Error(8);
    }
    if is("Config/Filename") {
        let v = v.trim();
        if v.is_empty() {
            return Outcome::Error(3);
        }
        named.config_filename = v.to_string();
    } else {
        match LEVELS.iter().find(|l| l.eq_ignore_ascii_case(v.trim())) {
            Some(l) => named.message_level = l,
            None => return Outcome::Error(3),
        }
    }
    Outcome::Say(Vec::new())
}

fn setting(settings: &BTreeMap<u16, f64>, n: u16) -> f64 {
    settings.get(&n).copied().unwrap_or(0.0)
}

/// `axes/x/max_rate_mm_per_min` → 110 (any case).
fn yaml_setting(path: &str) -> Option<u16> {
    let mut parts = path.split('/');
    let (Some(group), Some(axis), Some(item), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return None;
    };
    if !group.eq_ignore_ascii_case("axes") {
        return None;
    }
    let a = AXES.iter().position(|x| x.eq_ignore_ascii_case(axis))? as u16;
    let (_, base) = AXIS_ITEMS
        .iter()
        .find(|(name, _)| name.eq_ignore_ascii_case(item))?;
    Some(base + a)
}

/// `$S`: every named setting as `$Name=value`.
fn list(named: &Named, settings: &BTreeMap<u16, f64>) -> Vec<String> {
    vec![
        format!("$Config/Filename={}", named.config_filename),
        format!("$Message/Level={}", named.message_level),
        format!("$Report/StatusReport={}", setting(settings, 10) as i64),
    ]
}

/// `$CD`: the configuration as YAML, two spaces a level, numbers with three decimals.
fn dump(settings: &BTreeMap<u16, f64>) -> Vec<String> {
    let mut out = vec![
        "name: Oficina emulator".to_string(),
        "board: Oficina emulator".to_string(),
        "axes:".to_string(),
    ];
    for (a, axis) in AXES.iter().enumerate() {
        out.push(format!("  {axis}:"));
        for (name, base) in AXIS_ITEMS {
            out.push(format!(
                "    {name}: {:.3}",
                setting(settings, base + a as u16)
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn defaults() -> BTreeMap<u16, f64> {
        [(10, 1.0), (110, 500.0), (131, 200.0)]
            .into_iter()
            .collect()
    }

    #[test]
    fn yaml_paths_are_grbl_numbers() {
        assert_eq!(yaml_setting("axes/x/steps_per_mm"), Some(100));
        assert_eq!(yaml_setting("Axes/Y/Max_Rate_mm_per_min"), Some(111));
        assert_eq!(yaml_setting("axes/z/max_travel_mm"), Some(132));
        assert_eq!(yaml_setting("axes/a/max_travel_mm"), None);
        assert_eq!(yaml_setting("axes/x"), None);
        assert_eq!(yaml_setting("axes/x/steps_per_mm/more"), None);
    }

    #[test]
    fn named_settings_show_set_and_refuse() {
        let mut n = Named::default();
        let s = defaults();
        let mut run = |c: &str, idle| command(c, &mut n, &s, idle, !idle);
        assert_eq!(
            run("config/filename", true),
            Outcome::Say(vec!["$Config/Filename=config.yaml".into()])
        );
        assert_eq!(run("Config/Filename=mill.yaml", true), Outcome::Say(vec![]));
        assert_eq!(run("Message/Level=debug", true), Outcome::Say(vec![]));
        assert_eq!(run("Message/Level=loud", true), Outcome::Error(3));
        assert_eq!(run("Config/Filename=x.yaml", false), Outcome::Error(8));
        assert_eq!(run("S", false), Outcome::Error(8));
        assert_eq!(
            run("/axes/x/max_rate_mm_per_min=5000", true),
            Outcome::SetNumbered(110, "5000".into())
        );
        assert_eq!(run("/axes/w/max_rate_mm_per_min", true), Outcome::Error(3));
        assert_eq!(run("110=5000", true), Outcome::NotFluid);
        assert_eq!(
            run("Settings/List", true),
            Outcome::Say(vec![
                "$Config/Filename=mill.yaml".into(),
                "$Message/Level=Debug".into(),
                "$Report/StatusReport=1".into(),
            ])
        );
    }
}
