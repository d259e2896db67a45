//! Auto-levelling end to end on the grbl emulator: a 5 × 5 height map over an engraving
//! program on a tilted and on a warped surface, the levelled program streamed to the
//! emulator, and the tool tip's depth below the true surface (the formula, evaluated here)
//! at every point the emulated machine reached, within 0.02 mm of the programmed depth.

use oficina_app::{level_options, probe_grid, LevelTuning, ProbeRequest};
use oficina_grbl::{level_stream, Endpoint, GridSpec, GrblDevice, ProbeMotion, SenderOptions};
use oficina_grbl_emu::{Config, Emulator};
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

fn emulator() -> (Emulator, Endpoint) {
    let emu = Emulator::start(Config {
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
fn run_on(surface: &dyn Fn(f64, f64) -> f64) -> (f64, usize) {
    let (emu, ep) = emulator();
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

    // The probe: the surface formula at each grid point (an in-process probe standing in
    // for G38.2 until the emulator touches a surface).
    let req = request();
    let grid = probe_grid(Some(ENGRAVING), &req).unwrap();
    assert_eq!((grid.nx, grid.ny), (5, 5));
    let mut probe = |x: f64, y: f64| Ok(surface(x, y));
    let map = grid
        .probe(&mut probe, req.motion.clearance, &mut |_, _, _, _, _| {})
        .unwrap();

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
        let depth = z - surface(x, y);
        let programmed = if (depth - TRAVEL).abs() < 0.5 { TRAVEL } else { CUT };
        if programmed == CUT {
            cuts += 1;
        }
        worst = worst.max((depth - programmed).abs());
    }
    let end = pieces.last().unwrap().1;
    assert!((end[0] - WCO[0]).abs() < 1e-3 && (end[1] - WCO[1]).abs() < 1e-3, "{end:?}");
    (worst, cuts)
}

#[test]
fn engraving_follows_a_tilted_surface_on_the_emulator() {
    let tilted = |x: f64, y: f64| 0.25 + 0.006 * x - 0.009 * y;
    let (worst, cuts) = run_on(&tilted);
    eprintln!("tilted: worst {worst} over {cuts} cuts");
    assert!(cuts > 150, "{cuts} cut points");
    // A plane is bilinear: only the 4-decimal output rounding is left.
    assert!(worst < 1e-3, "worst deviation {worst} mm");
}

#[test]
fn engraving_follows_a_warped_surface_on_the_emulator() {
    // Tilted and warped: w·sin(2πx/λ)·sin(2πy/λ) with w = 0.15 mm, λ = 90 mm.
    let warped = |x: f64, y: f64| {
        0.1 + 0.004 * x + 0.003 * y + 0.15 * (TAU * x / 90.0).sin() * (TAU * y / 90.0).sin()
    };
    let (worst, cuts) = run_on(&warped);
    eprintln!("warped: worst {worst} over {cuts} cuts");
    assert!(cuts > 150, "{cuts} cut points");
    assert!(worst <= 0.02, "worst deviation {worst} mm");
}
