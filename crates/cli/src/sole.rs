//! `oficina sole`: seed 001's mold job in one command: digitised size-N contour → graded,
//! fitted, mirrored insert and cavity programs for both feet, each checked and timed.

use crate::mill::{judge, print_judged, progress_bar, PostArgs};
use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use oficina_cam::ops::{preview_svg, sole_job, Part, SoleJob, GOUGE_TOL};
use oficina_geom::{offset_areas, to_ring, Area, SizeSystem};
use oficina_sim::Design;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Digitised contour of the pattern size: CSV or whitespace x y per line, header or not.
    pub points: PathBuf,
    #[arg(long)]
    pub from_size: f64,
    #[arg(long)]
    pub to_size: f64,
    /// Size system: br (Brazilian/French, Paris point) or us (English/American).
    #[arg(long, default_value = "br")]
    pub system: String,
    /// Material shrinkage, percent.
    #[arg(long, default_value_t = 2.0)]
    pub shrink: f64,
    /// Fitting tolerance, mm.
    #[arg(long, default_value_t = 0.3)]
    pub fit_tolerance: f64,
    /// Output directory.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub out: PostArgs,
    /// Grid of the stock simulation, mm.
    #[arg(long, default_value_t = 0.5)]
    pub check_pixel: f64,
    /// Machine profile for the planner's time estimate.
    #[arg(long, default_value = "profiles/grbl-router.toml")]
    pub profile: PathBuf,
}

pub fn run(args: Args) -> Result<std::process::ExitCode> {
    let points = oficina_io::load_points(&args.points)?;
    let Some(system) = SizeSystem::parse(&args.system) else {
        bail!(
            "--system {}: use br (Brazilian/French) or us (English/American)",
            args.system
        );
    };
    if !(0.0..=20.0).contains(&args.shrink) {
        bail!("--shrink {} %: use 0 to 20", args.shrink);
    }
    let job = SoleJob {
        system,
        shrink: args.shrink / 100.0,
        fit_tolerance: args.fit_tolerance,
        ..SoleJob::seed(args.from_size, args.to_size)
    };
    let bar = progress_bar();
    bar.set_message("grading, fitting, mirroring, toolpaths");
    let result = sole_job(&points, &job)?;
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the directory", args.output.display()))?;
    let (a, b) = result.factors;
    let ext = match args.out.post.to_ascii_lowercase().as_str() {
        "sinumerik" | "sinumerik-7m" => "mpf",
        _ => "ngc",
    };
    let mut lines = vec![format!(
        "size {} → {} ({}), shrinkage {} %: α = {a:.4} (width), β = {b:.4} (length), about the heel point ({:.2}, {:.2})",
        args.from_size, args.to_size, system.name, args.shrink, result.grading.reference.x, result.grading.reference.y
    )];
    lines.push(format!(
        "contour: {} with {} blocks, max deviation {:.3} mm from the graded points{}",
        result.fit.method,
        result.fit.blocks,
        result.fit.max_deviation,
        result
            .fallback
            .as_ref()
            .map(|w| format!(" (tangent circles: {w})"))
            .unwrap_or_default()
    ));
    let mut worst = 0.0f64;
    for prog in &result.programs {
        bar.set_message(format!("{}: post, read back, simulate, time", prog.name()));
        let settings = vec![
            ("points".into(), args.points.display().to_string()),
            (
                "job".into(),
                format!(
                    "{} size {} from {} ({}), shrink {} %",
                    prog.name(),
                    args.to_size,
                    args.from_size,
                    system.name,
                    args.shrink
                ),
            ),
            (
                "block".into(),
                format!(
                    "{:.1} x {:.1} x {:.1} mm, part zero at its lower-left top corner",
                    prog.block[0], prog.block[1], prog.block[2]
                ),
            ),
        ];
        let (post, format) = args
            .out
            .options(&format!("Oficina sole mold: {}", prog.name()), settings)?;
        // Insert: everything outside the (clearance-reduced) outline may go; cavity: inside.
        let area = Area::from_paths(std::slice::from_ref(&prog.contour));
        let (dist, cut_inside) = match prog.part {
            Part::Insert => (-GOUGE_TOL, false),
            Part::Cavity => (GOUGE_TOL, true),
        };
        let rings: Vec<Vec<[f64; 2]>> = offset_areas(&area, dist, 0.001)?
            .iter()
            .flat_map(|a| {
                a.paths()
                    .map(|p| to_ring(&p.flatten(1e-4)))
                    .collect::<Vec<_>>()
            })
            .collect();
        let design = Design {
            rings,
            cut_inside,
            top: 0.0,
            floor: -prog.depth,
        };
        let judged = judge(
            &prog.toolpath,
            &post,
            &format,
            Some(design),
            args.check_pixel,
            &args.profile,
            &bar,
        )?;
        let file = args.output.join(format!("{}.{ext}", prog.name()));
        std::fs::write(&file, &judged.program)
            .with_context(|| format!("{}: cannot write", file.display()))?;
        let svg = args.output.join(format!("{}.svg", prog.name()));
        std::fs::write(
            &svg,
            preview_svg(std::slice::from_ref(&prog.contour), &prog.toolpath),
        )?;
        if let Some(stock) = &judged.stock_png {
            oficina_sim::render_png(
                stock,
                &args.output.join(format!("{}.stock.png", prog.name())),
            )
            .map_err(anyhow::Error::msg)?;
        }
        worst = worst.max(judged.gouge.map_or(0.0, |g| g.0));
        bar.suspend(|| {
            println!(
                "{} ({} operations, {} moves)",
                file.display(),
                prog.toolpath.operations.len(),
                prog.toolpath.move_count()
            );
            print_judged(&judged);
        });
    }
    bar.finish_and_clear();
    for l in &lines {
        println!("{l}");
    }
    Ok(if worst > 1e-3 {
        std::process::ExitCode::from(2)
    } else {
        std::process::ExitCode::SUCCESS
    })
}
