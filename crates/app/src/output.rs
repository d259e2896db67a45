//! The file written is the format asked for: an output whose extension names a format the
//! command does not write (`-o part.dxf`, `-o x.svg` beside the SVG preview, `-o x.pes`) is
//! refused before any work, with the extensions it can write.

use crate::Error;
use std::path::Path;

/// Extensions of G-code programs (every post writes text G-code; Sinumerik's `.mpf`).
pub const PROGRAM_EXTENSIONS: &[&str] =
    &["nc", "ngc", "gcode", "gc", "g", "tap", "cnc", "txt", "mpf"];

/// Extensions of HPGL files, as plotters and their drivers name them.
pub const HPGL_EXTENSIONS: &[&str] = &["hpgl", "plt", "hpg", "hgl"];

/// What `oficina plot --format FORMAT` writes.
pub fn plot_extensions(format: crate::PlotFormat) -> &'static [&'static str] {
    match format {
        crate::PlotFormat::Hpgl => HPGL_EXTENSIONS,
        crate::PlotFormat::Gcode | crate::PlotFormat::Joint | crate::PlotFormat::Marlin => {
            PROGRAM_EXTENSIONS
        }
    }
}

/// Refuses `output` (given with `flag`) when its extension is not one of `can`; a name
/// without an extension claims no format and is taken.
pub fn check_output(command: &str, flag: &str, output: &Path, can: &[&str]) -> Result<(), Error> {
    let Some(ext) = output.extension().and_then(|e| e.to_str()) else {
        return Ok(());
    };
    if can.iter().any(|c| c.eq_ignore_ascii_case(ext)) {
        return Ok(());
    }
    let what = if can == HPGL_EXTENSIONS {
        "HPGL"
    } else {
        "G-code programs"
    };
    Err(Error(format!(
        "{flag} {}: oficina {command} cannot write .{ext} files here; it writes {what}: .{}",
        output.display(),
        can.join(", .")
    )))
}

/// Refuses outputs that would overwrite the input drawing (`mill part.svg -o part.nc` writes
/// its preview to `part.svg`).
pub fn refuse_overwriting_drawing(input: &Path, outputs: &[&Path]) -> Result<(), Error> {
    match outputs.iter().find(|o| same_file(o, input)) {
        Some(o) => Err(Error(format!(
            "{} is the input drawing: choose another output name (-o / --preview)",
            o.display()
        ))),
        None => Ok(()),
    }
}

/// True when both paths name one existing file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Refuses an output folder (`oficina sole -o DIR`) that is an existing file.
pub fn check_output_dir(command: &str, flag: &str, dir: &Path) -> Result<(), Error> {
    if dir.is_file() {
        return Err(Error(format!(
            "{flag} {}: oficina {command} writes a folder of programs, and this is a file",
            dir.display()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_extensions_pass_and_others_are_refused_with_the_list() {
        for ok in ["x.nc", "X.NGC", "a/b.gcode", "noext", "p.mpf"] {
            assert!(
                check_output("mill", "-o", Path::new(ok), PROGRAM_EXTENSIONS).is_ok(),
                "{ok}"
            );
        }
        for bad in ["part.dxf", "x.svg", "x.pes", "x.stock.png"] {
            let e = check_output("mill", "-o", Path::new(bad), PROGRAM_EXTENSIONS)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(bad) && e.contains("cannot write") && e.contains(".ngc"),
                "{e}"
            );
        }
        let e = check_output(
            "plot",
            "-o",
            Path::new("p.plt"),
            plot_extensions(crate::PlotFormat::Gcode),
        );
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("writes G-code programs"));
        assert!(check_output(
            "plot",
            "-o",
            Path::new("p.plt"),
            plot_extensions(crate::PlotFormat::Hpgl)
        )
        .is_ok());
        let e = check_output(
            "plot",
            "-o",
            Path::new("p.nc"),
            plot_extensions(crate::PlotFormat::Hpgl),
        );
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("writes HPGL: .hpgl, .plt"));
        let file = std::env::temp_dir().join(format!("oficina-out-{}", std::process::id()));
        std::fs::write(&file, "x").unwrap();
        let r = check_output_dir("sole", "-o", &file);
        std::fs::remove_file(&file).unwrap();
        assert!(r.unwrap_err().to_string().contains("is a file"));
        assert!(check_output_dir("sole", "-o", Path::new("no/such/dir")).is_ok());
    }
}
