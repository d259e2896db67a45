//! `oficina design`: the design editor's file (`*.oficina.json`) from the command line —
//! export it as SVG / DXF, offset its closed contours. (Every drawing command, `mill`,
//! `plot`, `embroider`, reads the design file itself like an SVG or a DXF.)

use anyhow::Context;
use oficina_app::design;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Subcommand)]
pub(crate) enum Command {
    /// Write the design as SVG and/or DXF (the importers read both back as the same geometry).
    Export(ExportArgs),
    /// Offset closed contours by a distance; the new contours are added to the design.
    Offset(OffsetArgs),
    /// Fit a digitised closed contour (a point list) by one of `oficina fit`'s methods and add
    /// it to a design (made when missing).
    Fit(FitArgs),
}

#[derive(clap::Args)]
pub(crate) struct FitArgs {
    /// Point list: x,y per line (CSV or whitespace), header optional.
    points: PathBuf,
    /// biarc, tangent circles, B-spline, Bezier or interpolation.
    #[arg(long, default_value = "biarc")]
    method: String,
    /// Fitting tolerance, mm.
    #[arg(long, default_value_t = 0.3)]
    tol: f64,
    /// The design to add the contour to (made when missing).
    #[arg(long, short)]
    output: PathBuf,
}

#[derive(clap::Args)]
pub(crate) struct ExportArgs {
    /// The design file.
    file: PathBuf,
    /// Write SVG here.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Write DXF here.
    #[arg(long)]
    dxf: Option<PathBuf>,
}

#[derive(clap::Args)]
pub(crate) struct OffsetArgs {
    /// The design file.
    file: PathBuf,
    /// Entity ids to offset, e.g. 1,4.
    #[arg(long, value_delimiter = ',', required = true)]
    ids: Vec<u64>,
    /// Distance, mm: > 0 outwards, < 0 inwards.
    #[arg(long, allow_hyphen_values = true)]
    distance: f64,
    /// Write the design with the new contours here (default: the file itself).
    #[arg(long, short)]
    output: Option<PathBuf>,
}

pub(crate) fn run(cmd: Command) -> anyhow::Result<ExitCode> {
    match cmd {
        Command::Export(a) => {
            let d = design::read(&a.file)?;
            if a.svg.is_none() && a.dxf.is_none() {
                anyhow::bail!("give --svg OUT and/or --dxf OUT");
            }
            for (out, format) in [(a.svg, "svg"), (a.dxf, "dxf")] {
                if let Some(out) = out {
                    std::fs::write(&out, design::export(&d, format)?)
                        .with_context(|| format!("writing {}", out.display()))?;
                    println!(
                        "{}: {} entities → {}",
                        a.file.display(),
                        d.entities.len(),
                        out.display()
                    );
                }
            }
        }
        Command::Offset(a) => {
            let mut d = design::read(&a.file)?;
            let added = design::offset(&d, &a.ids, a.distance)?;
            for e in &added {
                println!(
                    "entity {} on layer {}: offset {} mm",
                    e.id, e.layer, a.distance
                );
            }
            d.entities.extend(added);
            let out = a.output.unwrap_or(a.file);
            std::fs::write(&out, design::design_to_string(&d))
                .with_context(|| format!("writing {}", out.display()))?;
        }
        Command::Fit(a) => {
            let pts = oficina_io::load_points(&a.points).context("reading the points")?;
            let xy: Vec<[f64; 2]> = pts.iter().map(|p| [p.x, p.y]).collect();
            let f = design::fit(&xy, &a.method, a.tol)?;
            let mut d = if a.output.exists() {
                design::read(&a.output)?
            } else {
                design::Design::new()
            };
            let id = d.entities.iter().map(|e| e.id).max().unwrap_or(0) + 1;
            let layer = d
                .layers
                .first()
                .map_or_else(|| "0".to_string(), |l| l.name.clone());
            println!(
                "{} points → entity {id}: {} blocks, largest deviation {:.4} mm",
                pts.len(),
                f.blocks,
                f.max_deviation
            );
            d.entities.push(design::Entity {
                id,
                layer,
                shape: f.shape,
            });
            std::fs::write(&a.output, design::design_to_string(&d))
                .with_context(|| format!("writing {}", a.output.display()))?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
