//! Auto-levelling as the CLI and the workbench use it: a height map probed on a machine
//! over a program (or loaded from its file), a program levelled into a file for any sender,
//! and a levelled run on grbl firmware whose progress names the program's own lines. The
//! probing and the transform are `oficina_grbl`'s; this is the glue (files, order, checks).

use crate::Error;
use oficina_gcode::Dialect;
use oficina_grbl::{
    feed_area, level_stream, level_text, Area, GrblDevice, GridSpec, HeightMap, LevelOptions,
    LevelReport, MachineProbe, ProbeGrid, ProbeLink, ProbeMotion, ToolChange,
};
use oficina_machine::{Machine, MachineInfo};
use std::path::{Path, PathBuf};

/// Where and how to probe a height map.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeRequest {
    /// Grid density: points per axis or largest spacing.
    pub grid: GridSpec,
    /// The rectangle to probe (work mm); `None`: the program's feed moves.
    pub area: Option<Area>,
    /// Added around the area on every side, mm.
    pub margin: f64,
    /// Clearance, deepest Z and feed of each probe.
    pub motion: ProbeMotion,
}

/// How a transform is tuned; `None` fields take their defaults from the map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LevelTuning {
    /// Longest piece in XY, mm; default the smaller of 1 mm and half the grid spacing.
    pub max_segment: Option<f64>,
    /// Chord tolerance of arcs, mm; default 0.01.
    pub arc_tolerance: Option<f64>,
    /// Work Z at and above which moves are left alone; default the map's clearance.
    pub clearance: Option<f64>,
}

/// Where a levelled run's map comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum MapSource {
    /// A saved map file.
    File(PathBuf),
    /// Probed on the machine before the run, and saved to the path when given.
    Probe(ProbeRequest, Option<PathBuf>),
}

/// The transform's options for `map`.
pub fn level_options(map: &HeightMap, tuning: &LevelTuning) -> LevelOptions {
    let d = LevelOptions::default();
    LevelOptions {
        max_segment: tuning
            .max_segment
            .unwrap_or_else(|| d.max_segment.min(0.5 * map.spacing[0].min(map.spacing[1]))),
        arc_tolerance: tuning.arc_tolerance.unwrap_or(d.arc_tolerance),
        clearance: tuning.clearance,
        ..d
    }
}

/// Reads a map file, naming the file in any error.
pub fn load_map(path: &Path) -> Result<HeightMap, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error(format!("cannot read {}: {e}", path.display())))?;
    HeightMap::from_json(&text).map_err(|e| Error(format!("{}: {e}", path.display())))
}

/// Writes a map file.
pub fn save_map(path: &Path, map: &HeightMap) -> Result<(), Error> {
    std::fs::write(path, map.to_json())
        .map_err(|e| Error(format!("cannot write {}: {e}", path.display())))
}

/// The grid `req` asks for over `program` (its feed moves) or the given area.
pub fn probe_grid(program: Option<&str>, req: &ProbeRequest) -> Result<ProbeGrid, Error> {
    let area = match (req.area, program) {
        (Some(a), _) => a,
        (None, Some(text)) => feed_area(text, Dialect::Grbl).map_err(Error)?,
        (None, None) => {
            return Err(Error(
                "no program and no --area: nothing says where to probe".into(),
            ))
        }
    };
    ProbeGrid::over(area, req.margin, req.grid).map_err(Error)
}

/// Probes a height map on `machine` (any [`ProbeLink`]: a machine idle, connected, probe
/// attached, or a routine's link): over `program`'s
/// feed moves or `req.area`. When a program is given it is first levelled against a flat
/// map of the same grid, so what cannot be levelled is refused before the probe moves.
/// `progress(done, total, x, y, z)` hears each contact.
pub fn probe_map<L: ProbeLink + ?Sized>(
    machine: &mut L,
    program: Option<&str>,
    req: &ProbeRequest,
    progress: &mut dyn FnMut(usize, usize, f64, f64, f64),
) -> Result<HeightMap, Error> {
    let grid = probe_grid(program, req)?;
    if let Some(text) = program {
        // M6 is let through here as under the sender's default policy: the run checks the
        // program again under the machine's own policy before it starts.
        let opts = LevelOptions {
            tool_change: Some(ToolChange::default()),
            ..LevelOptions::default()
        };
        oficina_grbl::level_program(text, &flat_map(&grid, req)?, &opts, &mut |_| {})
            .map_err(Error)?;
    }
    let mut probe = MachineProbe::new(machine, req.motion).map_err(Error)?;
    let wcs = probe.wcs.clone();
    let mut map = grid
        .probe(&mut probe, req.motion.clearance, progress)
        .map_err(Error)?;
    map.wcs = Some(wcs);
    Ok(map)
}

/// A map of `grid` at height 0 everywhere: what a program is levelled against to be checked
/// before anything is probed.
fn flat_map(grid: &ProbeGrid, req: &ProbeRequest) -> Result<HeightMap, Error> {
    HeightMap::new(
        grid.origin,
        grid.spacing,
        grid.nx,
        grid.ny,
        vec![0.0; grid.nx * grid.ny],
        req.motion.clearance,
    )
    .map_err(Error)
}

/// `program` levelled into the text of a file for any sender, with a header naming the
/// source and the map.
pub fn level_file(
    program: &str,
    source_name: &str,
    map: &HeightMap,
    map_name: &str,
    tuning: &LevelTuning,
) -> Result<(String, LevelReport), Error> {
    let opts = level_options(map, tuning);
    let header = format!(
        "{source_name} levelled by oficina with {map_name}\nmax segment {} mm, arc tolerance {} mm",
        opts.max_segment, opts.arc_tolerance
    );
    level_text(program, map, &opts, &header).map_err(Error)
}

/// What a levelled run started with.
pub struct LevelledRun {
    /// The machine, running the job: drive it with events as any other.
    pub machine: Box<dyn Machine>,
    /// What answered the connection.
    pub info: MachineInfo,
    /// The map the program follows.
    pub map: HeightMap,
    /// What levelling did.
    pub report: LevelReport,
}

/// Connects to grbl firmware at `spec`, gets the map (probing it, and saving it when
/// asked), levels `text` and starts it from `start_line` with `tool_change` as the sender's
/// policy at `M6` (as a plain job's); `notify` hears each step.
#[allow(clippy::too_many_arguments)]
pub fn run_levelled(
    spec: &str,
    name: &str,
    text: &str,
    start_line: Option<u32>,
    source: &MapSource,
    tuning: &LevelTuning,
    tool_change: ToolChange,
    notify: &mut dyn FnMut(String),
) -> Result<LevelledRun, Error> {
    tool_change.validate().map_err(Error)?;
    let options = |map: &HeightMap| LevelOptions {
        tool_change: Some(tool_change.clone()),
        ..level_options(map, tuning)
    };
    if !crate::is_firmware(spec) || crate::is_marlin(spec) {
        return Err(Error(format!(
            "--machine {spec}: levelling runs on grbl firmware (grbl:/dev/… or tcp://…); for other machines write a levelled file with `oficina level apply`"
        )));
    }
    // The program is checked against the map (or a flat one of the grid to probe) under the
    // tool-change policy before anything moves.
    let loaded = match source {
        MapSource::File(path) => Some(load_map(path)?),
        MapSource::Probe(..) => None,
    };
    match (&loaded, source) {
        (Some(map), _) => {
            level_stream(name, text, map, &options(map)).map_err(Error)?;
        }
        // A map to probe: the program checked under this policy against a flat one first.
        (None, MapSource::Probe(req, _)) => {
            let flat = flat_map(&probe_grid(Some(text), req)?, req)?;
            level_stream(name, text, &flat, &options(&flat)).map_err(Error)?;
        }
        (None, MapSource::File(_)) => {}
    }
    let mut dev = GrblDevice::new(spec).map_err(|e| Error(format!("--machine {spec}: {e}")))?;
    dev.settings.tool_change = tool_change.clone();
    let info = dev.connect().map_err(Error::from_display)?;
    let map = match (loaded, source) {
        (Some(map), _) => map,
        (None, MapSource::Probe(req, save)) => {
            let grid = probe_grid(Some(text), req)?;
            notify(format!(
                "probing {} × {} points, {:.2} × {:.2} mm apart, from X{:.3} Y{:.3}",
                grid.nx, grid.ny, grid.spacing[0], grid.spacing[1], grid.origin[0], grid.origin[1]
            ));
            let map = probe_map(&mut dev, Some(text), req, &mut |done, total, x, y, z| {
                notify(format!("probe {done}/{total}: X{x:.3} Y{y:.3} Z{z:.4}"))
            })?;
            if let Some(path) = save {
                save_map(path, &map)?;
                notify(format!("height map saved to {}", path.display()));
            }
            map
        }
        (None, MapSource::File(path)) => load_map(path)?,
    };
    let (program, report) =
        level_stream(&format!("{name}.levelled"), text, &map, &options(&map)).map_err(Error)?;
    dev.start_program(program, start_line)
        .map_err(Error::from_display)?;
    Ok(LevelledRun {
        machine: Box::new(dev),
        info,
        map,
        report,
    })
}
