//! The feeds-and-speeds calculator: feed = chip load × flutes × rpm, for a tool of the
//! library and a material, or for numbers given by hand.

use crate::Error;
use oficina_cam::{feed_rate, surface_speed, Library};
use std::path::Path;

/// What to compute the feeds of: a library tool, or a tool described by hand (each given
/// value overrides the library's).
#[derive(Clone, Debug, Default)]
pub struct FeedsQuery {
    /// Library file and tool number.
    pub library: Option<(std::path::PathBuf, u32)>,
    /// Material: picks the library's chip load.
    pub material: Option<String>,
    /// Diameter, mm.
    pub diameter: Option<f64>,
    /// Cutting edges.
    pub flutes: Option<u32>,
    /// Spindle speed, rev/min.
    pub rpm: Option<f64>,
    /// Chip load, mm per tooth.
    pub chip_load: Option<f64>,
}

/// The calculator's answer.
#[derive(Clone, Debug, PartialEq)]
pub struct FeedsAnswer {
    /// The tool, as the library names it or the spec.
    pub tool: String,
    /// Diameter, mm.
    pub diameter: f64,
    /// Flutes.
    pub flutes: u32,
    /// rev/min.
    pub rpm: f64,
    /// mm per tooth.
    pub chip_load: f64,
    /// mm/min.
    pub feed: f64,
    /// Cutting speed at the edge, m/min.
    pub surface_speed: f64,
}

/// Feed and cutting speed for `q`; says which value is missing.
pub fn tool_feeds(q: &FeedsQuery) -> Result<FeedsAnswer, Error> {
    let entry = match &q.library {
        Some((path, n)) => {
            let lib = Library::load(Path::new(path)).map_err(|e| Error(e.to_string()))?;
            let t = lib
                .get(*n)
                .cloned()
                .ok_or_else(|| Error(format!("{}: no tool number {n}", path.display())))?;
            Some(t)
        }
        None => None,
    };
    let name = entry.as_ref().map_or("the tool".to_string(), |t| {
        format!(
            "T{} {}",
            t.number,
            if t.name.is_empty() { "" } else { &t.name }
        )
        .trim()
        .to_string()
    });
    let diameter = q.diameter.or(entry.as_ref().map(|t| t.diameter));
    let flutes = q.flutes.or(entry.as_ref().and_then(|t| t.flutes));
    let rpm = q.rpm.or(entry.as_ref().and_then(|t| t.spindle_rpm));
    let chip_load = q.chip_load.or_else(|| {
        let m = q.material.as_deref()?;
        entry
            .as_ref()?
            .chip_load
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(m))
            .map(|(_, v)| *v)
    });
    let missing = |what: &str| Error(format!("{name}: no {what}: give --{what}"));
    let diameter = diameter.ok_or_else(|| missing("diameter"))?;
    let flutes = flutes.ok_or_else(|| missing("flutes"))?;
    let rpm = rpm.ok_or_else(|| missing("rpm"))?;
    let chip_load = match (chip_load, &q.material, &entry) {
        (Some(c), _, _) => c,
        (None, Some(m), Some(t)) => {
            let known: Vec<&str> = t.chip_load.keys().map(String::as_str).collect();
            return Err(Error(format!(
                "{name}: no chip load for {m:?} in the library (it has {}): give --chip-load",
                if known.is_empty() {
                    "none".into()
                } else {
                    known.join(", ")
                }
            )));
        }
        _ => return Err(missing("chip-load")),
    };
    for (what, v) in [
        ("diameter", diameter),
        ("rpm", rpm),
        ("chip-load", chip_load),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error(format!("--{what} {v}: must be above 0")));
        }
    }
    if flutes == 0 {
        return Err(Error("--flutes 0: a tool has at least one".into()));
    }
    Ok(FeedsAnswer {
        tool: name,
        diameter,
        flutes,
        rpm,
        chip_load,
        feed: feed_rate(chip_load, flutes, rpm),
        surface_speed: surface_speed(diameter, rpm),
    })
}

/// A library tool for `oficina mill --library … --tool N`: its spec (with flutes and
/// shank) and its feeds for `material`, if the library has them.
#[derive(Clone, Debug, PartialEq)]
pub struct LibraryChoice {
    /// The tool as a spec `oficina mill --tool` takes.
    pub spec: String,
    /// Spindle speed and feeds, when the library gives them.
    pub feeds: Option<oficina_cam::ToolFeeds>,
}

/// Tool `number` of the library at `path`, or why not (the numbers it has).
pub fn library_tool(
    path: &Path,
    number: u32,
    material: Option<&str>,
) -> Result<LibraryChoice, Error> {
    let lib = Library::load(path).map_err(|e| Error(e.to_string()))?;
    let t = lib.get(number).ok_or_else(|| {
        let have: Vec<String> = lib.tools.iter().map(|t| t.number.to_string()).collect();
        Error(format!(
            "--tool {number}: not in the library {} (it has {})",
            path.display(),
            if have.is_empty() {
                "no tools".into()
            } else {
                have.join(", ")
            }
        ))
    })?;
    let tool = t
        .tool()
        .map_err(|e| Error(format!("{}: tool {number}: {e}", path.display())))?;
    Ok(LibraryChoice {
        spec: tool.spec(),
        feeds: t.feeds(material),
    })
}
