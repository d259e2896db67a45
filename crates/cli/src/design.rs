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
    /// Grade a digitised sole contour (a point list) to sizes and mirror it for the other
    /// foot, as `oficina sole` does; each size's feet are added on layers `size N left|right`.
    Grade(GradeArgs),
}

#[derive(clap::Args)]
pub(crate) struct GradeArgs {
    /// Point list: x,y per line (CSV or whitespace), header optional.
    points: PathBuf,
    /// The size the points were digitised at.
    #[arg(long)]
    from_size: f64,
    /// The sizes to make, e.g. 38,39,40.
    #[arg(long, value_delimiter = ',', required = true)]
    to_size: Vec<f64>,
    /// Size system: br (Brazilian/French, Paris point) or us (English/American).
    #[arg(long, default_value = "br")]
    system: String,
    /// Material shrinkage, percent.
    #[arg(long, default_value_t = 2.0)]
    shrink: f64,
    /// Fitting tolerance, mm.
    #[arg(long, default_value_t = 0.3)]
    fit_tolerance: f64,
    /// The design to add the contours to (made when missing).
    #[arg(long, short)]
    output: PathBuf,
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
    /// Write seed 001's graphic file here.
    #[arg(long)]
    seed001: Option<PathBuf>,
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
            if a.svg.is_none() && a.dxf.is_none() && a.seed001.is_none() {
                anyhow::bail!("give --svg OUT, --dxf OUT and/or --seed001 OUT");
            }
            for (out, format) in [(a.svg, "svg"), (a.dxf, "dxf"), (a.seed001, "seed001")] {
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
        Command::Grade(a) => {
            let xy = read_points(&a.points)?;
            let graded = design::grade(
                &xy,
                &design::GradeParams {
                    from_size: a.from_size,
                    sizes: a.to_size,
                    system: a.system,
                    shrink: a.shrink,
                    tol: a.fit_tolerance,
                },
            )?;
            let mut d = read_or_new(&a.output)?;
            for g in graded {
                println!(
                    "size {}: {} with {} blocks, largest deviation {:.4} mm, left and right",
                    g.size, g.method, g.blocks, g.max_deviation
                );
                design::add_graded(&mut d, g.size, g.feet);
            }
            std::fs::write(&a.output, design::design_to_string(&d))
                .with_context(|| format!("writing {}", a.output.display()))?;
        }
        Command::Fit(a) => {
            let xy = read_points(&a.points)?;
            let f = design::fit(&xy, &a.method, a.tol)?;
            let mut d = read_or_new(&a.output)?;
            let id = d.entities.iter().map(|e| e.id).max().unwrap_or(0) + 1;
            let layer = d
                .layers
                .first()
                .map_or_else(|| "0".to_string(), |l| l.name.clone());
            println!(
                "{} points → entity {id}: {} blocks, largest deviation {:.4} mm",
                xy.len(),
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

fn read_points(file: &std::path::Path) -> anyhow::Result<Vec<[f64; 2]>> {
    let pts = oficina_io::load_points(file).context("reading the points")?;
    Ok(pts.iter().map(|p| [p.x, p.y]).collect())
}

/// The design in `file`, or a new one when there is no such file.
fn read_or_new(file: &std::path::Path) -> anyhow::Result<design::Design> {
    Ok(if file.exists() {
        design::read(file)?
    } else {
        design::Design::new()
    })
}
