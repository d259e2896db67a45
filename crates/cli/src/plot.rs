//! `oficina plot DESIGN --machine PROFILE -o OUT`: a drawing (SVG, DXF, HPGL, an image to
//! hatch, or text) becomes an optimised pen-plotter program, with a preview and a report.
//! `oficina plot --seed-check --machine polar-plotter` prints seed 003's timing table.

use crate::machine_profile;
use anyhow::Context;
use oficina_app::Feedback;
use oficina_app::{pen_machine, plot, FilledBy, Lift, PensBy, PlotFormat, PlotParams};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// The design: .svg, .dxf, HP-GL (.plt/.hpgl/.hpg/.hp or any file whose content is
    /// HP-GL, also inside PCL), or an image (.png/.jpg) to hatch.
    input: Option<PathBuf>,
    /// Machine profile: a TOML file or a bundled name (pen-plotter, polar-plotter,
    /// polargraph-wall, …).
    /// Without it: pen-plotter, and a drawing larger than its travel is written at its
    /// size with a note (a named machine refuses what it cannot reach).
    #[arg(long)]
    machine: Option<String>,
    /// Where to write the program.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Program format: gcode (Cartesian, grbl family), joint (X/Y = the two joints, for
    /// polar and hanging plotters driven by a plain controller), hpgl (vintage plotters),
    /// marlin (Marlin 2.x: M280 servo pen lift, G28 home, one command per line).
    #[arg(long, alias = "dialect", value_enum, default_value_t = PlotFormat::Gcode)]
    format: PlotFormat,
    /// Write an SVG preview with the pen-up moves dashed.
    #[arg(long)]
    preview: Option<PathBuf>,
    /// Text to draw in a single-stroke Hershey font (besides or instead of the input).
    #[arg(long)]
    text: Option<String>,
    /// Capital height of --text, mm.
    #[arg(long, default_value_t = 10.0)]
    text_height: f64,
    /// One pen per stroke colour or per layer (DXF layers, HPGL pens).
    #[arg(long, value_enum, default_value_t = PensBy::Color)]
    pens: PensBy,
    /// Pen lift: z (a Z axis), servo (M3 S<--servo-down> / M5; with --format marlin
    /// M280 P0 S<--servo-down> / S<--servo-up>), or command (--pen-down-cmd / --pen-up-cmd
    /// lines as given). Default: servo with --format marlin, else z.
    #[arg(long, value_enum)]
    pen: Option<Lift>,
    /// Servo value for pen down (S word; degrees on Marlin).
    #[arg(long, default_value_t = 30.0)]
    servo_down: f64,
    /// Servo angle for pen up on Marlin (M280 P0 S…), degrees.
    #[arg(long, default_value_t = 90.0)]
    servo_up: f64,
    #[arg(long)]
    pen_down_cmd: Option<String>,
    #[arg(long)]
    pen_up_cmd: Option<String>,
    /// Seconds to wait after each pen move (Marlin: 0.15 s where 0, written as G4 P<ms>).
    #[arg(long, default_value_t = 0.0)]
    pen_dwell: f64,
    /// Drawing feed, mm/min (default: the profile's default feed).
    #[arg(long)]
    feed: Option<f64>,
    /// Scale the drawing by this factor.
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// Put the lower-left corner of the drawing here, X,Y mm (work coordinates).
    #[arg(long, value_parser = parse_xy, allow_hyphen_values = true)]
    at: Option<[f64; 2]>,
    /// Paper size W,H mm; the drawing must fit on it (its corner at --at).
    #[arg(long, value_parser = parse_xy, conflicts_with = "layout")]
    paper: Option<[f64; 2]>,
    /// Lay the drawing out on a page as vpype's `layout` does: a4, a3, letter, … or WxH in mm
    /// (units allowed: 8.5x11in). Centred, scaled to fit inside --margin unless --no-fit; the
    /// page's lower-left corner at --at or at the machine's travel corner.
    #[arg(long)]
    layout: Option<String>,
    /// The --layout page in landscape (otherwise portrait, unless only landscape fits the machine).
    #[arg(long, requires = "layout")]
    landscape: bool,
    /// Margin of --layout when fitting, mm.
    #[arg(long, default_value_t = 10.0, requires = "layout")]
    margin: f64,
    /// --layout only centres the drawing, at its size.
    #[arg(long, requires = "layout")]
    no_fit: bool,
    /// Image hatching: pixel size on paper, mm.
    #[arg(long, default_value_t = 0.5)]
    pixel: f64,
    /// Image hatching: distance between hatch lines, mm.
    #[arg(long, default_value_t = 1.0)]
    pitch: f64,
    /// Image hatching: layers of hatching, 1…4 (with --fill: darkness bands, 1…8).
    #[arg(long, default_value_t = 3)]
    hatch_layers: usize,
    /// Image hatching: the layers' (bands') pens, lightest first, e.g. '#999999,#000000';
    /// the darker layers share the last pen.
    #[arg(long)]
    image_pens: Option<String>,
    /// Join strokes whose ends are this close, mm (0: no merging).
    #[arg(long, default_value_t = 0.05)]
    merge_tol: f64,
    /// Simplify strokes within this tolerance, mm (0: keep every point).
    #[arg(long, default_value_t = 0.01)]
    simplify_tol: f64,
    /// Draw strokes as given: no merging, ordering, simplifying or de-duplicating.
    #[arg(long)]
    no_optimise: bool,
    /// Refuse a profile whose joint acceleration ramps are shorter than this many steps.
    #[arg(long, default_value_t = 100.0)]
    min_ramp_steps: f64,
    /// Chord tolerance for curves, mm.
    #[arg(long, default_value_t = 0.02)]
    tolerance: f64,
    /// Join ends of the drawing's paths that meet within this distance, mm (a path ending
    /// on its start is closed; open pieces of a layer are chained).
    #[arg(long, default_value_t = oficina_io::JOIN_TOL)]
    join_tol: f64,
    /// Hatch the filled shapes; of an image, its darkness bands (--hatch-layers of them)
    /// filled alike, band k at --fill-spacing/k.
    #[arg(long)]
    fill: bool,
    /// Hatch direction, degrees counter-clockwise from +X.
    #[arg(long, default_value_t = 45.0, allow_hyphen_values = true)]
    fill_angle: f64,
    /// Distance between hatch lines on paper, mm.
    #[arg(long, default_value_t = 1.0)]
    fill_spacing: f64,
    /// Cross-hatch: a second set of lines at right angles.
    #[arg(long)]
    fill_cross: bool,
    /// Concentric rings instead of parallel lines.
    #[arg(long, conflicts_with = "fill_cross")]
    fill_concentric: bool,
    /// What counts as filled, for --fill and --occult: svg (a fill colour, holes by the fill
    /// rule), closed (every closed outline, as AxiDraw's Hatch Fill; an element's subpaths one
    /// shape with holes) or loops (every closed subpath a shape of its own, as vpype-occult).
    #[arg(long, value_enum, default_value_t = FilledBy::Svg)]
    filled: FilledBy,
    /// Hidden-line removal: a filled shape hides what its pen drew before it (vpype occult).
    #[arg(long)]
    occult: bool,
    /// Hidden-line removal across pens: a filled shape hides what any pen drew before it.
    #[arg(long)]
    occult_across: bool,
    /// Start each closed stroke at its vertex nearest the pen (after ordering).
    #[arg(long)]
    reloop: bool,
    /// Draw every stroke N times, the pen down between passes (closed strokes go round,
    /// open ones back and forth).
    #[arg(long, default_value_t = 1)]
    passes: usize,
    /// Crop to the paper (--paper or --layout) or to a box X0,Y0,X1,Y1 in mm (work
    /// coordinates); a stroke leaving the box is cut, the pen lifted between the pieces.
    #[arg(long, allow_hyphen_values = true)]
    crop: Option<String>,
    /// Print seed 003's test (squares, triangles, hexagons at five places) planned on
    /// --machine beside the seed's measured times, and exit.
    #[arg(long)]
    seed_check: bool,
}

fn parse_xy(s: &str) -> Result<[f64; 2], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{p}' is not a number"))
        })
        .collect::<Result<_, _>>()?;
    match v.as_slice() {
        [x, y] if x.is_finite() && y.is_finite() => Ok([*x, *y]),
        _ => Err(format!("expected X,Y (two numbers in mm), got '{s}'")),
    }
}

/// The form the application layer takes.
/// The profile a plot uses when no --machine is named.
const DEFAULT_MACHINE: &str = "pen-plotter";

fn params(a: &Args) -> PlotParams {
    PlotParams {
        default_machine: a.machine.is_none(),
        format: a.format,
        text: a.text.clone(),
        text_height: a.text_height,
        pens: a.pens,
        pen: a.pen.unwrap_or(match a.format {
            PlotFormat::Marlin => Lift::Servo,
            _ => Lift::Z,
        }),
        servo_down: a.servo_down,
        servo_up: a.servo_up,
        pen_down_cmd: a.pen_down_cmd.clone(),
        pen_up_cmd: a.pen_up_cmd.clone(),
        pen_dwell: a.pen_dwell,
        feed: a.feed,
        scale: a.scale,
        at: a.at,
        paper: a.paper,
        layout: a.layout.clone(),
        landscape: a.landscape,
        margin: a.margin,
        no_fit: a.no_fit,
        pixel: a.pixel,
        pitch: a.pitch,
        hatch_layers: a.hatch_layers,
        image_pens: a.image_pens.clone(),
        merge_tol: a.merge_tol,
        simplify_tol: a.simplify_tol,
        no_optimise: a.no_optimise,
        min_ramp_steps: a.min_ramp_steps,
        tolerance: a.tolerance,
        join_tol: a.join_tol,
        fill: a.fill,
        fill_angle: a.fill_angle,
        fill_spacing: a.fill_spacing,
        fill_cross: a.fill_cross,
        fill_concentric: a.fill_concentric,
        filled: a.filled,
        occult: a.occult,
        occult_across: a.occult_across,
        reloop: a.reloop,
        passes: a.passes,
        crop: a.crop.clone(),
    }
}

fn seed_check(a: &Args) -> anyhow::Result<ExitCode> {
    let profile = machine_profile::resolve(a.machine.as_deref().unwrap_or(DEFAULT_MACHINE))?;
    let m = pen_machine(&params(a), &profile)?;
    let rows = oficina_plot::seed_check(&profile, &m)?;
    println!(
        "seed 003 check on '{}' (pivot at the lower-left corner of the board; drawing feed {} mm/min)",
        profile.name, m.draw_feed
    );
    for r in oficina_plot::ramps(&profile) {
        println!("  ramp {r}");
    }
    println!(
        "seconds per set: planner = our look-ahead planner; stop-start = the seed's host model (rest to rest every {} mm); seed = its Table 1",
        oficina_plot::STOP_PIECE
    );
    println!(
        "{:<12} {:>6} | {:>26} | {:>26} | {:>26}",
        "place",
        "R mm",
        "squares plan/stop/seed",
        "triangles plan/stop/seed",
        "hexagons plan/stop/seed"
    );
    for r in &rows {
        let cell = |f: usize| {
            format!(
                "{:.1} / {:.1} / {:.0}",
                r.planned[f], r.stop_start[f], r.seed[f]
            )
        };
        println!(
            "{:<12} {:>6.0} | {:>26} | {:>26} | {:>26}",
            r.place,
            r.radius,
            cell(0),
            cell(1),
            cell(2)
        );
    }
    let ratio = |i: usize, f: usize| rows[i].planned[f] / rows[0].planned[f];
    let stop = |i: usize, f: usize| rows[i].stop_start[f] / rows[0].stop_start[f];
    println!(
        "lower-left / lower-right: planner {:.2} {:.2} {:.2}, stop-start {:.2} {:.2} {:.2}, seed {:.2} {:.2} {:.2}",
        ratio(4, 0),
        ratio(4, 1),
        ratio(4, 2),
        stop(4, 0),
        stop(4, 1),
        stop(4, 2),
        rows[4].seed[0] / rows[0].seed[0],
        rows[4].seed[1] / rows[0].seed[1],
        rows[4].seed[2] / rows[0].seed[2]
    );
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn run(a: Args) -> anyhow::Result<ExitCode> {
    if a.seed_check {
        return seed_check(&a);
    }
    if let Some(out) = &a.output {
        oficina_app::check_output("plot", "-o", out, oficina_app::plot_extensions(a.format))?;
    }
    let profile = machine_profile::resolve(a.machine.as_deref().unwrap_or(DEFAULT_MACHINE))?;
    let r = plot(a.input.as_deref(), &params(&a), &profile, Feedback::none())?;
    for n in &r.notes {
        eprintln!("note: {n}");
    }
    let p = &r.prepared;
    println!("machine: {}", profile.name);
    for (i, pen) in p.plot.pens.iter().enumerate() {
        println!(
            "pen {}: {} ({} strokes)",
            i + 1,
            pen.name,
            pen.strokes.len()
        );
    }
    if let Some(pl) = &p.placed {
        println!(
            "page: {} x {} mm, drawing scaled by {:.4}",
            pl.page.0, pl.page.1, pl.scale
        );
    }
    let b = p.bounds;
    println!(
        "drawing: {:.2} x {:.2} mm at ({:.2}, {:.2})",
        b[2] - b[0],
        b[3] - b[1],
        b[0],
        b[1]
    );
    if let Some(r) = &p.report {
        println!(
            "strokes {} -> {} ({} duplicates dropped), points {} -> {}",
            r.before.strokes, r.after.strokes, r.duplicates, r.points_before, r.points_after
        );
        println!(
            "pen-down {:.1} -> {:.1} mm, pen-up {:.1} -> {:.1} mm",
            r.before.pen_down, r.after.pen_down, r.before.pen_up, r.after.pen_up
        );
    }
    println!("planned time: {:.1} s", r.seconds);
    if let Some(out) = &a.output {
        std::fs::write(out, &p.program).with_context(|| format!("writing {}", out.display()))?;
        println!("wrote {}", out.display());
    } else {
        print!("{}", p.program);
    }
    if let Some(pv) = &a.preview {
        std::fs::write(pv, &p.preview).with_context(|| format!("writing {}", pv.display()))?;
        println!("preview {}", pv.display());
    }
    Ok(ExitCode::SUCCESS)
}
