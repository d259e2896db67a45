//! `oficina sole`: seed 001's mold job in one command: digitised size-N contour → graded,
//! fitted, mirrored insert and cavity programs for both feet, each checked and timed.

use crate::mill::{estimate_profile, print_judged, PostArgs};
use crate::progress::with_bar;
use anyhow::{Context, Result};
use clap::Args as ClapArgs;
use oficina_app::GOUGE_REPORTED;
use oficina_app::{sole, SoleParams};
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub(crate) struct Args {
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
    /// The insert's tread details (slots, letters): an SVG/DXF of closed shapes in the
    /// points' frame, graded and mirrored with the contour, cut 2 mm deep by the 6 mm mill
    /// and the 1 mm bit (seed 001 §7).
    #[arg(long)]
    pub tread: Option<PathBuf>,
    /// Output directory.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also add the graded contour of each foot (before placing on the block) to this design
    /// file (`*.oficina.json`, made when missing) on layers `size N left` / `size N right`.
    #[arg(long)]
    pub contours: Option<PathBuf>,
    #[command(flatten)]
    pub out: PostArgs,
    /// Grid of the stock simulation, mm.
    #[arg(long, default_value_t = 0.5)]
    pub check_pixel: f64,
    /// Machine profile for the planner's time estimate: a bundled name or a TOML file.
    #[arg(long, default_value = crate::machine_profile::DEFAULT)]
    pub profile: String,
    /// Join ends of the tread drawing's paths that meet within this distance, mm.
    #[arg(long, default_value_t = oficina_io::JOIN_TOL)]
    pub join_tol: f64,
}

pub(crate) fn run(args: Args) -> Result<std::process::ExitCode> {
    oficina_app::check_output_dir("sole", "-o", &args.output)?;
    let params = SoleParams {
        from_size: args.from_size,
        to_size: args.to_size,
        system: args.system.clone(),
        shrink: args.shrink,
        fit_tolerance: args.fit_tolerance,
        check_pixel: args.check_pixel,
        tread: args.tread.clone(),
        join_tol: args.join_tol,
        post: args.out.params(),
    };
    let profile = estimate_profile(&args.profile);
    let (result, bar) = with_bar(|fb| sole(&args.points, &params, &profile, fb));
    let result = result?;
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the directory", args.output.display()))?;
    let ext = params.post.extension();
    for prog in &result.programs {
        let file = args.output.join(format!("{}.{ext}", prog.name));
        std::fs::write(&file, &prog.judged.program)
            .with_context(|| format!("{}: cannot write", file.display()))?;
        let svg = args.output.join(format!("{}.svg", prog.name));
        std::fs::write(&svg, &prog.preview_svg)?;
        if let Some(stock) = &prog.judged.stock {
            oficina_sim::render_png(stock, &args.output.join(format!("{}.stock.png", prog.name)))
                .map_err(anyhow::Error::msg)?;
        }
        bar.suspend(|| {
            println!(
                "{} ({} operations, {} moves)",
                file.display(),
                prog.operations,
                prog.moves
            );
            print_judged(&prog.judged);
        });
    }
    bar.finish_and_clear();
    if let Some(file) = &args.contours {
        let feet = oficina_app::design::feet_shapes(&result.feet)?;
        let mut d = if file.exists() {
            oficina_app::design::read(file)?
        } else {
            oficina_app::design::Design::new()
        };
        oficina_app::design::add_graded(&mut d, args.to_size, feet);
        std::fs::write(file, oficina_app::design::design_to_string(&d))
            .with_context(|| format!("{}: cannot write", file.display()))?;
        println!("{}: size {} left and right", file.display(), args.to_size);
    }
    for l in &result.summary {
        println!("{l}");
    }
    Ok(if result.worst_gouge() > GOUGE_REPORTED {
        std::process::ExitCode::from(2)
    } else {
        std::process::ExitCode::SUCCESS
    })
}
