//! `oficina level probe` / `oficina level apply`, and the levelling flags of `oficina run`:
//! parsing and printing over `oficina_app`'s levelling.

use crate::gcode_input::{read_program, DEFAULT_MAX_PROGRAM_MB};
use anyhow::Context;
use oficina_app::{LevelTuning, MapSource, ProbeRequest};
use oficina_grbl::{Area, GridSpec, HeightMap, LevelReport, ProbeMotion};
use std::path::PathBuf;
use std::process::ExitCode;

/// Where and how each point is probed (work coordinates).
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct ProbeFlags {
    /// Rectangle to probe, X0,Y0,X1,Y1 in work mm (default: the program's feed moves).
    #[arg(long, allow_hyphen_values = true)]
    area: Option<Area>,
    /// Added around the area on every side, mm.
    #[arg(long, default_value_t = 2.0)]
    margin: f64,
    /// Work Z each probe starts from and retracts to (above the stock everywhere), mm.
    #[arg(long, default_value_t = 3.0, allow_hyphen_values = true)]
    probe_clearance: f64,
    /// Deepest work Z a probe may reach before it counts as no contact, mm.
    #[arg(long, default_value_t = -3.0, allow_hyphen_values = true)]
    probe_depth: f64,
    /// Probing feed, mm/min.
    #[arg(long, default_value_t = 60.0)]
    probe_feed: f64,
}

impl ProbeFlags {
    fn request(&self, grid: GridSpec) -> ProbeRequest {
        ProbeRequest {
            grid,
            area: self.area,
            margin: self.margin,
            motion: ProbeMotion {
                clearance: self.probe_clearance,
                max_depth: self.probe_depth,
                feed: self.probe_feed,
            },
        }
    }
}

/// How the program is levelled.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct TuningFlags {
    /// Longest piece a move is cut into (XY), mm [default: 1, or half the grid spacing if less].
    #[arg(long)]
    max_segment: Option<f64>,
    /// Largest distance between an arc and its chords, mm [default: 0.01].
    #[arg(long)]
    arc_tolerance: Option<f64>,
    /// Moves at or above this work Z are left alone, mm [default: the map's probe clearance].
    #[arg(long, allow_hyphen_values = true)]
    clearance: Option<f64>,
}

impl TuningFlags {
    fn tuning(&self) -> LevelTuning {
        LevelTuning {
            max_segment: self.max_segment,
            arc_tolerance: self.arc_tolerance,
            clearance: self.clearance,
        }
    }
}

/// The levelling flags of `oficina run`.
#[derive(clap::Args, Debug, Clone)]
pub(crate) struct RunFlags {
    /// Probe a height map over the program first (grid: `5x5` points, or a spacing in mm
    /// such as `10`) and run the program levelled by it (grbl firmware only).
    #[arg(long, value_name = "GRID", conflicts_with = "level")]
    level_probe: Option<GridSpec>,
    /// Save the map probed by --level-probe to this file.
    #[arg(long, value_name = "MAP.json", requires = "level_probe")]
    level_save: Option<PathBuf>,
    /// Run the program levelled by this saved height map (grbl firmware only).
    #[arg(long, value_name = "MAP.json")]
    level: Option<PathBuf>,
    #[command(flatten)]
    probe: ProbeFlags,
    #[command(flatten)]
    tuning: TuningFlags,
}

impl RunFlags {
    /// Where the run's map comes from, when it is levelled.
    pub(crate) fn source(&self) -> Option<MapSource> {
        if let Some(path) = &self.level {
            return Some(MapSource::File(path.clone()));
        }
        self.level_probe
            .map(|g| MapSource::Probe(self.probe.request(g), self.level_save.clone()))
    }

    pub(crate) fn tuning(&self) -> LevelTuning {
        self.tuning.tuning()
    }
}

#[derive(clap::Subcommand)]
pub(crate) enum Command {
    /// Probe a height map on grbl firmware over a program (or --area) and save it as JSON.
    Probe(ProbeArgs),
    /// Level a program with a saved height map into a file any sender can run.
    Apply(ApplyArgs),
}

#[derive(clap::Args)]
pub(crate) struct ProbeArgs {
    /// The program to probe under (its feed moves set the area; it is also checked to be
    /// levellable before the probe moves). Optional with --area.
    file: Option<PathBuf>,
    /// grbl firmware: `grbl:/dev/ttyUSB0[@baud]` or `tcp://HOST:PORT`.
    #[arg(long)]
    machine: String,
    /// Points along X and Y (`5x5`) or the largest spacing in mm (`10`).
    #[arg(long, default_value = "5x5")]
    grid: GridSpec,
    #[command(flatten)]
    probe: ProbeFlags,
    /// The map file to write.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(clap::Args)]
pub(crate) struct ApplyArgs {
    /// The program to level.
    file: PathBuf,
    /// The height map (from `oficina level probe` or `oficina run --level-save`).
    #[arg(long)]
    map: PathBuf,
    #[command(flatten)]
    tuning: TuningFlags,
    /// The levelled program to write.
    #[arg(short, long)]
    output: PathBuf,
}

pub(crate) fn run(cmd: Command) -> anyhow::Result<ExitCode> {
    match cmd {
        Command::Probe(args) => probe(args),
        Command::Apply(args) => apply(args),
    }
}

fn probe(args: ProbeArgs) -> anyhow::Result<ExitCode> {
    if !oficina_app::is_firmware(&args.machine) {
        anyhow::bail!(
            "--machine {}: probing needs grbl firmware (grbl:/dev/… or tcp://…)",
            args.machine
        );
    }
    let text = match &args.file {
        Some(f) => Some(read_program(f, DEFAULT_MAX_PROGRAM_MB)?),
        None => None,
    };
    let req = args.probe.request(args.grid);
    let grid = oficina_app::probe_grid(text.as_deref(), &req).map_err(anyhow::Error::msg)?;
    let mut machine = oficina_app::open_machine(&args.machine, None).map_err(anyhow::Error::msg)?;
    let info = machine.connect().map_err(|e| anyhow::anyhow!("{e}"))?;
    eprintln!(
        "{}: probing {} × {} points, {:.2} × {:.2} mm apart, from X{:.3} Y{:.3}",
        info.name,
        grid.nx,
        grid.ny,
        grid.spacing[0],
        grid.spacing[1],
        grid.origin[0],
        grid.origin[1]
    );
    let map = oficina_app::probe_map(
        &mut *machine,
        text.as_deref(),
        &req,
        &mut |d, n, x, y, z| eprintln!("probe {d}/{n}: X{x:.3} Y{y:.3} Z{z:.4}"),
    )
    .map_err(anyhow::Error::msg)?;
    machine.disconnect();
    oficina_app::save_map(&args.output, &map).map_err(anyhow::Error::msg)?;
    print_map(&map);
    println!("saved {}", args.output.display());
    Ok(ExitCode::SUCCESS)
}

fn apply(args: ApplyArgs) -> anyhow::Result<ExitCode> {
    let text = read_program(&args.file, DEFAULT_MAX_PROGRAM_MB)?;
    let map = oficina_app::load_map(&args.map).map_err(anyhow::Error::msg)?;
    let (out, report) = oficina_app::level_file(
        &text,
        &args.file.display().to_string(),
        &map,
        &args.map.display().to_string(),
        &args.tuning.tuning(),
    )
    .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
    std::fs::write(&args.output, out)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    print_map(&map);
    print_report(&report);
    println!("wrote {}", args.output.display());
    Ok(ExitCode::SUCCESS)
}

/// The map in one line: grid, area, height range.
pub(crate) fn print_map(map: &HeightMap) {
    let (lo, hi) = map.z_range();
    let [x1, y1] = map.max_corner();
    println!(
        "height map: {} × {} points over X{:.3}…{x1:.3} Y{:.3}…{y1:.3}{}, Z {lo:.4} … {hi:.4} (span {:.4} mm)",
        map.nx,
        map.ny,
        map.origin[0],
        map.origin[1],
        map.wcs.as_deref().map(|w| format!(" ({w})")).unwrap_or_default(),
        hi - lo
    );
}

/// What the transform did, and its warnings on stderr.
pub(crate) fn print_report(r: &LevelReport) {
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "levelled: {} moves into {} lines, Z offsets {:.4} … {:.4} mm",
        r.levelled_moves, r.lines, r.offset_range.0, r.offset_range.1
    );
}
