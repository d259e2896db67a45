//! `oficina fit POINTS.csv [--tol MM]`: fits a digitised closed contour by every method
//! (the seed's tangent circles, biarcs, B-spline, Bézier, interpolation) and prints, for each,
//! the NC blocks it makes and its largest deviation from the points.

use anyhow::{bail, Context};
use oficina_io::geom::fit::fit_all;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Point list: x,y per line (CSV or whitespace), header optional.
    file: PathBuf,
    /// Fitting tolerance, mm.
    #[arg(long, default_value_t = 0.1)]
    tol: f64,
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    if !(args.tol > 0.0 && args.tol.is_finite()) {
        bail!("--tol must be a positive number of mm, got {}", args.tol);
    }
    let pts = oficina_io::load_points(&args.file).context("reading the points")?;
    println!(
        "{} points from {}, tolerance {} mm",
        pts.len(),
        args.file.display(),
        args.tol
    );
    println!(
        "{:<28} {:>8} {:>6} {:>6} {:>8} {:>14}",
        "method", "control", "blocks", "arcs", "lines", "max dev (mm)"
    );
    let mut failed = false;
    for (method, result) in fit_all(&pts, args.tol) {
        match result {
            Ok(f) => {
                let (lines, arcs, _) = f.path.counts();
                println!(
                    "{:<28} {:>8} {:>6} {:>6} {:>8} {:>14.4}",
                    method.name(),
                    f.control_points,
                    f.blocks,
                    arcs,
                    lines,
                    f.max_deviation
                );
            }
            Err(e) => {
                failed = true;
                println!("{:<28} failed: {e}", method.name());
            }
        }
    }
    Ok(if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
