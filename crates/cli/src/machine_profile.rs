//! Finding a machine profile: a path to a TOML file, or the name of a profile bundled in the
//! binary (so `oficina` works from any folder, with no install step).

use anyhow::Context;
use oficina_motion::Profile;
use std::path::Path;

/// The profiles of `profiles/`, compiled in: (name, TOML text).
pub const BUNDLED: &[(&str, &str)] = &[
    (
        "grbl-router",
        include_str!("../../../profiles/grbl-router.toml"),
    ),
    (
        "hotwire-xy",
        include_str!("../../../profiles/hotwire-xy.toml"),
    ),
    (
        "polar-plotter",
        include_str!("../../../profiles/polar-plotter.toml"),
    ),
    (
        "polargraph-wall",
        include_str!("../../../profiles/polargraph-wall.toml"),
    ),
    (
        "embroidery-xy",
        include_str!("../../../profiles/embroidery-xy.toml"),
    ),
];

/// The profile used when none is named: the seed 004 grbl router.
pub const DEFAULT: &str = "grbl-router";

/// Load `spec`: an existing file path, or a bundled name (with or without `.toml`).
pub fn resolve(spec: &str) -> anyhow::Result<Profile> {
    let path = Path::new(spec);
    if path.is_file() {
        return Profile::load(path).map_err(|e| anyhow::anyhow!("{e}"));
    }
    let name = spec.trim_end_matches(".toml");
    let name = name.rsplit('/').next().unwrap_or(name);
    let (_, text) = BUNDLED.iter().find(|(n, _)| *n == name).with_context(|| {
        let names: Vec<&str> = BUNDLED.iter().map(|(n, _)| *n).collect();
        format!(
            "no profile file '{spec}' and no bundled profile of that name (bundled: {})",
            names.join(", ")
        )
    })?;
    Profile::parse(text, &format!("<bundled {name}>")).map_err(|e| anyhow::anyhow!("{e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bundled_profile_parses() {
        for (name, _) in BUNDLED {
            resolve(name).unwrap_or_else(|e| panic!("bundled profile {name}: {e}"));
        }
    }

    #[test]
    fn unknown_names_list_the_bundled_ones() {
        let e = resolve("no-such-machine").unwrap_err().to_string();
        assert!(
            e.contains("grbl-router") && e.contains("no-such-machine"),
            "{e}"
        );
    }
}
