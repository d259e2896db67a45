//! Auto-levelling end to end on the grbl emulator: a 5 × 5 height map probed with G38.2
//! over an engraving program on the emulator's tilted and warped stock, the levelled
//! program streamed to it, and the tool tip's depth below the true surface (the formula,
//! evaluated here) at every point the emulated machine reached, within 0.02 mm of the
//! programmed depth.

use oficina_app::{level_options, probe_map, LevelTuning, ProbeRequest};
use oficina_grbl::{level_stream, Endpoint, GrblDevice, GridSpec, ProbeMotion, SenderOptions};
use oficina_grbl_emu::{Config, Emulator, ProbeModel, Stock};
use oficina_machine::{Event, Machine};
use std::f64::consts::TAU;
use std::time::Duration;

/// Text engraved 0.1 mm deep: strokes, an arc, a circle, travels at Z1 between them.
const ENGRAVING: &str = "\
G21 G90 G17
G0 Z5
G0 X2 Y2
G0 Z1
G1 Z-0.1 F1500
G1 X38 Y2 F4000
G1 X38 Y28
G2 X18 Y28 I-10 J0
G1 X2 Y2
G0 Z1
G0 X20 Y15
G1 Z-0.1 F1500
G3 X20 Y15 I-6 J0 F4000
G0 Z1
G0 X30 Y8
G1 Z-0.1
G1 X10 Y22
G0 Z5
G0 X0 Y0
M2
";

/// Programmed depths below the clearance: the cuts and the travels.
const CUT: f64 = -0.1;
const TRAVEL: f64 = 1.0;
/// Work zero in machine coordinates, set on the emulator with G10 L2.
const WCO: [f64; 3] = [-50.0, -40.0, -30.0];

/// The stock's top in machine coordinates: `top + tilt·(x, y) + warp·sin(2πx/λ)·sin(2πy/λ)`,
/// written out here rather than taken from the emulator.
#[derive(Clone, Copy)]
struct Surface {
    top: f64,
    tilt: [f64; 2],
    warp: f64,
    wavelength: f64,
}

impl Surface {
    /// Work Z of the surface at work (x, y).
    fn work_z(&self, x: f64, y: f64) -> f64 {
        let (mx, my) = (x + WCO[0], y + WCO[1]);
        let k = TAU / self.wavelength;
        let machine = self.top
            + self.tilt[0] * mx
            + self.tilt[1] * my
            + self.warp * (k * mx).sin() * (k * my).sin();
        machine - WCO[2]
    }

    fn stock(&self) -> Stock {
        Stock {
            min: [-70.0, -60.0],
            max: [10.0, 10.0],
            top: self.top,
            tilt: self.tilt,
            warp: self.warp,
            wavelength: self.wavelength,
        }
    }
}

fn emulator(surface: &Surface) -> (Emulator, Endpoint) {
    let emu = Emulator::start(Config {
        probe: ProbeModel {
            stock: Some(surface.stock()),
            ..ProbeModel::default()
        },
        settings: vec![
            (110, 60000.0),
            (111, 60000.0),
            (112, 60000.0),
            (120, 3000.0),
            (121, 3000.0),
            (122, 3000.0),
        ],
        record_motion: true,
        ..Config::default()
    });
    let addr = emu.serve_tcp("127.0.0.1:0").expect("bind loopback");
    (
        emu,
        Endpoint::Tcp {
            addr: addr.to_string(),
        },
    )
}

fn request() -> ProbeRequest {
    ProbeRequest {
        grid: GridSpec::Count(5, 5),
        area: None,
        margin: 2.0,
        motion: ProbeMotion {
            clearance: 3.0,
            max_depth: -3.0,
            feed: 600.0,
        },
    }
}

/// Probes, levels and streams on a fresh emulator; returns the worst deviation from the
/// programmed depth and how many cut points were checked.
fn run_on(surface: &Surface) -> (f64, usize) {
    let (emu, ep) = emulator(surface);
    let options = SenderOptions {
        status_interval: Duration::from_millis(50),
        reply_timeout: Duration::from_secs(20),
        ..SenderOptions::default()
    };
    let mut dev = GrblDevice::at(ep, options);
    dev.settings.journal = Some(std::env::temp_dir().join(format!(
        "oficina-level-e2e-{}-{:p}.journal",
        std::process::id(),
        surface
    )));
    dev.connect().unwrap();
    let set = format!("G10L2P1X{}Y{}Z{}", WCO[0], WCO[1], WCO[2]);
    assert_eq!(dev.raw_line(&set).unwrap().error, None);

    // G38.2 at each grid point, in serpentine order.
    let req = request();
    let mut touched = Vec::new();
    let map = probe_map(&mut dev, Some(ENGRAVING), &req, &mut |_, _, x, y, z| {
        touched.push((x, y, z))
    })
    .unwrap();
    assert_eq!((map.nx, map.ny, map.wcs.as_deref()), (5, 5, Some("G54")));
    for (x, y, z) in touched {
        assert!(
            (z - surface.work_z(x, y)).abs() < 1e-3,
            "contact at X{x} Y{y} Z{z}"
        );
    }
    // From here on the record is the program's motion only.
    emu.with_core(|c| c.motion_record.clear());

    let opts = level_options(&map, &LevelTuning::default());
    let (program, report) = level_stream("engraving.nc", ENGRAVING, &map, &opts).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let source_lines = ENGRAVING.lines().count();
    assert!(program.lines.iter().all(|l| l.file_line <= source_lines));
    dev.start_program(program, None).unwrap();
    let mut last_line = 0;
    let completed = loop {
        match dev.next_event(Duration::from_secs(60)).expect("an event") {
            Event::Status(s) => last_line = last_line.max(s.line),
            Event::JobEnd { completed, .. } => break completed,
            Event::Alarm(a) => panic!("alarm: {a}"),
            Event::Message(_) => {}
            Event::ToolChange { prompt, .. } => {
                panic!("a levelled program has no tool change: {prompt}")
            }
        }
    };
    assert!(completed);
    // Progress names the program's own lines, not the levelled program's.
    assert!(last_line as usize <= source_lines, "line {last_line}");

    // Where the machine went, in work coordinates, against the true surface.
    let pieces = emu.with_core(|c| c.motion_record.clone());
    assert!(!pieces.is_empty());
    let (mut worst, mut cuts) = (0.0f64, 0);
    for (_, to) in &pieces {
        let [x, y, z] = [to[0] - WCO[0], to[1] - WCO[1], to[2] - WCO[2]];
        if z >= req.motion.clearance {
            continue;
        }
        let depth = z - surface.work_z(x, y);
        let programmed = if (depth - TRAVEL).abs() < 0.5 {
            TRAVEL
        } else {
            CUT
        };
        if programmed == CUT {
            cuts += 1;
        }
        worst = worst.max((depth - programmed).abs());
    }
    let end = pieces.last().unwrap().1;
    assert!(
        (end[0] - WCO[0]).abs() < 1e-3 && (end[1] - WCO[1]).abs() < 1e-3,
        "{end:?}"
    );
    (worst, cuts)
}

#[test]
fn engraving_follows_a_tilted_surface_on_the_emulator() {
    let tilted = Surface {
        top: -29.8,
        tilt: [0.006, -0.009],
        warp: 0.0,
        wavelength: 100.0,
    };
    let (worst, cuts) = run_on(&tilted);
    eprintln!("tilted: worst {worst} mm over {cuts} cut points");
    assert!(cuts > 150, "{cuts} cut points");
    // A plane is bilinear: only the probe's 3-decimal report and the 4-decimal output are left.
    assert!(worst < 2e-3, "worst deviation {worst} mm");
}

#[test]
fn engraving_follows_a_warped_surface_on_the_emulator() {
    // Tilted and warped: w·sin(2πx/λ)·sin(2πy/λ) with w = 0.15 mm, λ = 90 mm.
    let warped = Surface {
        top: -29.9,
        tilt: [0.004, 0.003],
        warp: 0.15,
        wavelength: 90.0,
    };
    let (worst, cuts) = run_on(&warped);
    eprintln!("warped: worst {worst} mm over {cuts} cut points");
    assert!(cuts > 150, "{cuts} cut points");
    assert!(worst <= 0.02, "worst deviation {worst} mm");
}

#[test]
fn a_probe_that_finds_no_surface_stops_the_map_naming_the_point() {
    // The stock lies far from where the program is.
    let away = Surface {
        top: -29.8,
        tilt: [0.0; 2],
        warp: 0.0,
        wavelength: 100.0,
    };
    let (_emu, ep) = emulator(&Surface { top: -45.0, ..away });
    let mut dev = GrblDevice::at(ep, SenderOptions::default());
    dev.connect().unwrap();
    let set = format!("G10L2P1X{}Y{}Z{}", WCO[0], WCO[1], WCO[2]);
    assert_eq!(dev.raw_line(&set).unwrap().error, None);
    let e = probe_map(
        &mut dev,
        Some(ENGRAVING),
        &request(),
        &mut |_, _, _, _, _| {},
    )
    .unwrap_err()
    .0;
    assert!(
        e.starts_with("probing point 1 of 25 at X0.000 Y0.000"),
        "{e}"
    );
    assert!(e.contains("ALARM") || e.contains("alarm"), "{e}");
}

#[test]
fn a_levelled_run_resumes_from_a_source_line() {
    let tilted = Surface {
        top: -29.8,
        tilt: [0.006, -0.009],
        warp: 0.0,
        wavelength: 100.0,
    };
    let (emu, ep) = emulator(&tilted);
    let mut dev = GrblDevice::at(ep, SenderOptions::default());
    dev.settings.resume.spindle_delay = 0.0;
    dev.settings.journal = Some(std::env::temp_dir().join(format!(
        "oficina-level-resume-{}.journal",
        std::process::id()
    )));
    dev.connect().unwrap();
    let set = format!("G10L2P1X{}Y{}Z{}", WCO[0], WCO[1], WCO[2]);
    assert_eq!(dev.raw_line(&set).unwrap().error, None);
    let map = probe_map(
        &mut dev,
        Some(ENGRAVING),
        &request(),
        &mut |_, _, _, _, _| {},
    )
    .unwrap();
    emu.with_core(|c| c.motion_record.clear());
    let opts = level_options(&map, &LevelTuning::default());
    let (program, _) = level_stream("engraving.nc", ENGRAVING, &map, &opts).unwrap();
    // Line 16 is the last plunge (at X30 Y8), line 17 the last stroke.
    dev.start_program(program, Some(16)).unwrap();
    let completed = loop {
        match dev.next_event(Duration::from_secs(60)).expect("an event") {
            Event::JobEnd { completed, .. } => break completed,
            Event::Alarm(a) => panic!("alarm: {a}"),
            _ => {}
        }
    };
    assert!(completed);
    let pieces = emu.with_core(|c| c.motion_record.clone());
    let mut cuts = 0;
    for (_, to) in &pieces {
        let [x, y, z] = [to[0] - WCO[0], to[1] - WCO[1], to[2] - WCO[2]];
        if z >= 3.0 {
            continue;
        }
        let depth = z - tilted.work_z(x, y);
        let programmed = if (depth - TRAVEL).abs() < 0.5 {
            TRAVEL
        } else {
            CUT
        };
        assert!((depth - programmed).abs() < 2e-3, "X{x} Y{y} Z{z}: {depth}");
        if programmed == CUT {
            cuts += 1;
            // Only the last stroke, from (30, 8) to (10, 22): the earlier lines were skipped.
            assert!(
                (8.0 - 1e-6..=22.0 + 1e-6).contains(&y) && x >= 10.0 - 1e-6,
                "{x} {y}"
            );
        }
    }
    // ⌈24.4 mm / 1 mm⌉ pieces of the stroke and the plunge's end.
    assert!(cuts >= 25, "{cuts} cut points");
}
