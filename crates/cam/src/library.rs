//! A tool library file (TOML): numbered tools with their shape, sizes and cutting data.
//!
//! ```toml
//! [[tool]]
//! number = 1
//! name = "12 mm flat"
//! shape = "flat"
//! diameter = 12.0
//! flute_length = 30.0
//! shank_diameter = 12.0
//! feed = 2000.0          # mm/min
//! plunge_feed = 500.0    # mm/min
//! spindle_rpm = 18000.0
//! flutes = 2
//! chip_load = { aluminium = 0.03, wood = 0.1 }   # mm per tooth, per material
//! ```
//!
//! With flutes and a chip load for the material, the feed is chip load × flutes × rpm
//! ([`feed_rate`]); the library's `feed` is the fallback.

use crate::tool::{CutterShape, Tool};
use serde::{Deserialize, Serialize};

/// One tool of the library.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LibraryTool {
    /// Its number: the T word, and how jobs name it.
    pub number: u32,
    /// What the workshop calls it.
    #[serde(default)]
    pub name: String,
    /// The cutting end.
    #[serde(flatten)]
    pub shape: CutterShape,
    /// Cutting diameter, mm.
    pub diameter: f64,
    /// Flute length, mm.
    pub flute_length: Option<f64>,
    /// Shank diameter, mm.
    pub shank_diameter: Option<f64>,
    /// Cutting feed, mm/min.
    pub feed: Option<f64>,
    /// Plunge feed, mm/min.
    pub plunge_feed: Option<f64>,
    /// Spindle speed, rev/min.
    pub spindle_rpm: Option<f64>,
    /// Cutting edges, for the feed from the chip load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flutes: Option<u32>,
    /// Chip load (mm per tooth) by material name.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub chip_load: std::collections::BTreeMap<String, f64>,
}

/// Feed (mm/min) that gives each of `flutes` edges a chip of `chip_load` mm at `rpm`.
pub fn feed_rate(chip_load: f64, flutes: u32, rpm: f64) -> f64 {
    chip_load * flutes as f64 * rpm
}

/// Cutting speed at the edge (m/min) of a `diameter` mm tool at `rpm`.
pub fn surface_speed(diameter: f64, rpm: f64) -> f64 {
    std::f64::consts::PI * diameter * rpm / 1000.0
}

/// Spindle speed, feed and plunge feed for one tool and material, and where they came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolFeeds {
    /// rev/min.
    pub rpm: f64,
    /// mm/min.
    pub feed: f64,
    /// mm/min.
    pub plunge_feed: f64,
    /// How the feed was found, for reports.
    pub source: String,
}

/// The workshop's tools by number, with their feeds and speeds.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Library {
    /// The tools, in file order.
    #[serde(default, rename = "tool")]
    pub tools: Vec<LibraryTool>,
}

#[derive(Debug, thiserror::Error)]
pub enum LibraryError {
    #[error("{path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    #[error("{path}: tool number {number}: {message}")]
    Tool {
        path: String,
        number: u32,
        message: String,
    },
}

impl LibraryTool {
    /// The feeds for `material`: chip load × flutes × rpm when the library has a chip load
    /// for it, else the tool's own feed; `None` when it has neither (or no rpm).
    pub fn feeds(&self, material: Option<&str>) -> Option<ToolFeeds> {
        let rpm = self.spindle_rpm?;
        let from_chip = material.and_then(|m| {
            let load = self
                .chip_load
                .iter()
                .find(|(k, _)| k.eq_ignore_ascii_case(m))?
                .1;
            let flutes = self.flutes?;
            Some((
                feed_rate(*load, flutes, rpm),
                format!("{load} mm/tooth × {flutes} flutes × {rpm} rpm ({m})"),
            ))
        });
        let (feed, source) = match from_chip {
            Some(f) => f,
            None => (self.feed?, "the library's feed".to_string()),
        };
        Some(ToolFeeds {
            rpm,
            feed,
            plunge_feed: self.plunge_feed.unwrap_or(feed / 3.0),
            source,
        })
    }

    /// The cutter this entry describes.
    pub fn tool(&self) -> Result<Tool, crate::tool::ToolError> {
        let mut tool = Tool::new(self.shape, self.diameter)?;
        if let Some(l) = self.flute_length {
            tool.flute_length = l;
        }
        if let Some(d) = self.shank_diameter {
            tool.shank_diameter = d;
        }
        tool.validate()?;
        Ok(tool)
    }
}

impl Library {
    /// Parses library text; `path` names the source in messages.
    pub fn parse(path: &str, text: &str) -> Result<Library, LibraryError> {
        let lib: Library = toml::from_str(text).map_err(|e| LibraryError::Parse {
            path: path.into(),
            message: e.to_string(),
        })?;
        let mut seen = std::collections::HashSet::new();
        for t in &lib.tools {
            if !seen.insert(t.number) {
                return Err(LibraryError::Tool {
                    path: path.into(),
                    number: t.number,
                    message: "listed twice".into(),
                });
            }
            t.tool().map_err(|e| LibraryError::Tool {
                path: path.into(),
                number: t.number,
                message: e.to_string(),
            })?;
            if t.flutes == Some(0) {
                return Err(LibraryError::Tool {
                    path: path.into(),
                    number: t.number,
                    message: "flutes must be 1 or more".into(),
                });
            }
            for (material, load) in &t.chip_load {
                if !(load.is_finite() && *load > 0.0 && *load < 5.0) {
                    return Err(LibraryError::Tool {
                        path: path.into(),
                        number: t.number,
                        message: format!(
                            "chip_load.{material} must be above 0 and below 5 mm, got {load}"
                        ),
                    });
                }
            }
            for (what, v) in [
                ("feed", t.feed),
                ("plunge_feed", t.plunge_feed),
                ("spindle_rpm", t.spindle_rpm),
            ] {
                if let Some(v) = v {
                    if !(v.is_finite() && v > 0.0) {
                        return Err(LibraryError::Tool {
                            path: path.into(),
                            number: t.number,
                            message: format!("{what} must be above 0, got {v}"),
                        });
                    }
                }
            }
        }
        Ok(lib)
    }

    /// Reads a tool library file (TOML, `[[tool]]` tables).
    pub fn load(path: &std::path::Path) -> Result<Library, LibraryError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| LibraryError::Read {
            path: name.clone(),
            source,
        })?;
        Library::parse(&name, &text)
    }

    /// The tool with `number`, if the library has it.
    pub fn get(&self, number: u32) -> Option<&LibraryTool> {
        self.tools.iter().find(|t| t.number == number)
    }

    /// The library as TOML, as [`Library::load`] reads it.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"
[[tool]]
number = 1
name = "12 mm flat"
shape = "flat"
diameter = 12.0
feed = 2000.0

[[tool]]
number = 2
shape = "v"
angle = 60.0
diameter = 6.0
shank_diameter = 6.0

[[tool]]
number = 3
shape = "bull"
corner_radius = 1.0
diameter = 6.0
flute_length = 15.0
"#;

    #[test]
    fn round_trips_and_builds_tools() {
        let lib = Library::parse("t.toml", TEXT).unwrap();
        assert_eq!(lib.tools.len(), 3);
        assert_eq!(
            lib.get(2).unwrap().tool().unwrap().shape,
            CutterShape::V { angle: 60.0 }
        );
        assert_eq!(lib.get(3).unwrap().tool().unwrap().flute_length, 15.0);
        let again = Library::parse("again", &lib.to_toml()).unwrap();
        assert_eq!(again, lib);
    }

    #[test]
    fn feeds_from_the_chip_load_else_the_tools_feed() {
        let lib = Library::parse(
            "t.toml",
            "[[tool]]\nnumber = 1\nshape = \"flat\"\ndiameter = 6.0\nflutes = 3\nspindle_rpm = 10000.0\nfeed = 700.0\nchip_load = { Wood = 0.05 }\n",
        )
        .unwrap();
        let t = lib.get(1).unwrap();
        // 0.05 mm × 3 teeth × 10000 rev/min; the material's case does not matter.
        let f = t.feeds(Some("wood")).unwrap();
        assert!((f.feed - 1500.0).abs() < 1e-9 && (f.plunge_feed - 500.0).abs() < 1e-9);
        assert_eq!(t.feeds(Some("steel")).unwrap().feed, 700.0);
        assert_eq!(t.feeds(None).unwrap().feed, 700.0);
        let err = Library::parse(
            "t.toml",
            "[[tool]]\nnumber = 2\nshape = \"flat\"\ndiameter = 6.0\nchip_load = { wood = -1.0 }\n",
        )
        .unwrap_err();
        assert!(err.to_string().contains("chip_load.wood"), "{err}");
    }

    #[test]
    fn bad_entries_name_the_tool() {
        let err = Library::parse(
            "t.toml",
            "[[tool]]\nnumber = 7\nshape = \"ball\"\ndiameter = -1.0\n",
        )
        .unwrap_err();
        assert!(err.to_string().contains("tool number 7"), "{err}");
        let err = Library::parse(
            "t.toml",
            "[[tool]]\nnumber = 7\nshape = \"cone\"\ndiameter = 1.0\n",
        )
        .unwrap_err();
        assert!(err.to_string().starts_with("t.toml"), "{err}");
    }
}
