//! Finding a machine profile: a path to a TOML file, or the name of a profile bundled in the
//! binary (so `oficina` works from any folder, with no install step).

use crate::Error;
pub use oficina_motion::Profile;

/// The bundled profiles and the default live in `oficina_motion::profile`: one list for
/// every command and the server.
pub use oficina_motion::{BUNDLED, DEFAULT};

/// Load `spec`: an existing file path, or a bundled name (with or without `.toml`).
pub fn resolve(spec: &str) -> Result<Profile, Error> {
    oficina_motion::resolve(spec).map_err(Error::from_display)
}

/// The tool table `profile` names (`tool_table = "…"`, lengths in `units`), read; `None`
/// when it names none. `spec` is how the user named the profile: a missing or bad file is an
/// error naming it, the table's path, and the line and column of a bad line.
pub fn tool_table(
    profile: &Profile,
    spec: &str,
    units: oficina_canon::Units,
) -> Result<Option<oficina_gcode::ToolTable>, Error> {
    let Some(path) = &profile.tool_table else {
        return Ok(None);
    };
    let named =
        format!("the tool table named by machine profile {spec}; --tool-table overrides it");
    let bytes = std::fs::read(path)
        .map_err(|e| Error(format!("cannot read {} ({named}): {e}", path.display())))?;
    let text = oficina_gcode::text::decode(&bytes);
    oficina_gcode::ToolTable::parse(&text, units)
        .map(Some)
        .map_err(|d| {
            Error(format!(
                "{}:{}:{}: {} ({named})",
                path.display(),
                d.span.line,
                d.span.col,
                d.message
            ))
        })
}

/// `X,Y,Z` in mm, for `--work-offset`.
pub fn parse_xyz(text: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected X,Y,Z (three numbers in mm), got '{text}'"
        ));
    }
    let mut v = [0.0; 3];
    for (slot, p) in v.iter_mut().zip(&parts) {
        *slot = p
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("'{p}' is not a number (in '{text}')"))?;
    }
    Ok(v)
}

/// [`resolve`], then replace the stored work offset by the one given on the command line.
pub fn resolve_with_offset(spec: &str, work_offset: Option<[f64; 3]>) -> Result<Profile, Error> {
    let mut profile = resolve(spec)?;
    if let Some(w) = work_offset {
        profile.work_offset = w;
    }
    Ok(profile)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Every bundled profile parsing and the unknown-name message are motion's tests
    // (`resolve` here only changes the error type).

    #[test]
    fn work_offsets_parse_and_reject_garbage() {
        assert_eq!(parse_xyz("10, 20,-30.5"), Ok([10.0, 20.0, -30.5]));
        assert!(parse_xyz("1,2").is_err());
        assert!(parse_xyz("1,2,x").unwrap_err().contains("'x'"));
        assert!(parse_xyz("1,2,inf").is_err());
    }
}
