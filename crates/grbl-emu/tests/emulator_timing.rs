//! The emulator's motion timing against independent figures: Oficina's whole-job estimate
//! (the planner over the whole program, read by Oficina's own G-code interpreter), the
//! closed-form trapezoid, and a starved stream. The firmware model runs in simulated time
//! (1 ms ticks), so nothing depends on the host's clock.

mod common;

use common::clocked::{stream, TICK};
use oficina_gcode::Dialect;
use oficina_gcode::{run, RunOptions};
use oficina_grbl_emu::grbl_settings;
use oficina_grbl_emu::{Config, Core};
use oficina_motion::{estimate, Profile};
use std::io::Cursor;

fn router() -> Profile {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../profiles/grbl-router.toml"
    );
    Profile::load(std::path::Path::new(path)).unwrap()
}

fn core(p: &Profile, extra: &[(u16, f64)]) -> Core {
    let mut settings = grbl_settings(p).unwrap();
    settings.extend_from_slice(extra);
    Core::new(Config {
        baud: None,
        settings,
        ..Config::default()
    })
}

/// A closed tour of long random segments in XY with small Z changes, feeds varying.
fn program(n: usize) -> Vec<String> {
    let mut random = oficina_testkit::random::Xorshift::new(0x2545_f491_4f6c_dd1d);
    let mut r = move || random.unit();
    let mut lines = vec!["G21 G90 G94".to_string()];
    for i in 0..n {
        let (x, y, z) = (20.0 + 300.0 * r(), 20.0 + 300.0 * r(), -5.0 * r());
        if i % 10 == 9 {
            lines.push(format!("G0 X{x:.3} Y{y:.3} Z{z:.3}"));
        } else {
            let f = 1000.0 + 5000.0 * r();
            lines.push(format!("G1 X{x:.3} Y{y:.3} Z{z:.3} F{f:.0}"));
        }
    }
    lines.push("G0 X0 Y0 Z0".into());
    lines
}

/// The whole-job estimate of `lines` for profile `p` (no stored work offset: the emulator
/// starts with G54 = 0).
fn estimated(lines: &[String], p: &Profile) -> f64 {
    let text = lines.join("\n") + "\nM2\n";
    let mut ops = Vec::new();
    let diags = run(
        Cursor::new(text.into_bytes()),
        &RunOptions::check(Dialect::Grbl),
        &mut |c| ops.push(c),
    );
    assert!(
        diags
            .iter()
            .all(|d| d.severity != oficina_gcode::Severity::Error),
        "{diags:?}"
    );
    estimate(ops.into_iter(), p).unwrap().seconds
}

#[test]
fn a_full_buffer_takes_the_whole_job_estimate() {
    let p = router();
    let lines = program(150);
    let want = estimated(&lines, &p);
    let mut c = core(&p, &[]);
    c.out.clear();
    let got = stream(&mut c, &lines, |_| 0.0);
    assert_eq!(c.planner_free(), 15);
    assert!(
        (got.seconds - want).abs() <= 0.01 * want,
        "emulated {:.3} s, estimate {want:.3} s",
        got.seconds
    );
    assert_eq!(got.starvations, 0);
}

#[test]
fn a_starved_stream_takes_longer_and_is_reported() {
    let p = router();
    let lines = program(150);
    let want = estimated(&lines, &p);
    let mut c = core(&p, &[]);
    c.out.clear();
    // The sender stalls for ten minutes before every 40th line, longer than the 15 buffered
    // blocks last: the buffer drains and the machine stops.
    let got = stream(&mut c, &lines, |i| {
        if i > 0 && i % 40 == 0 {
            600.0
        } else {
            0.0
        }
    });
    assert_eq!(c.planner_free(), 15);
    assert_eq!(got.starvations, 3);
    assert!(
        got.starved_seconds > 1.0,
        "{} s starved",
        got.starved_seconds
    );
    // Stopped time, plus the ramps down and up around each stop.
    assert!(
        got.seconds > want + got.starved_seconds,
        "{} s vs {want} s + {} s starved",
        got.seconds,
        got.starved_seconds
    );
}

/// StatusReport positions during a long G1 follow the trapezoid: ¼ a t² at ramp start, and `Bf:`
/// counts the block being executed.
#[test]
fn status_positions_follow_the_trapezoid() {
    let p = router();
    let a = p.joints[0].unwrap().acceleration;
    let mut c = core(&p, &[(10, 3.0)]);
    for b in b"G1 X200 F6000\n" {
        c.receive(*b);
    }
    // 100 mm/s at 300 mm/s²: 1/3 s ramping up.
    for k in 0..=250u32 {
        c.tick(k as f64 * TICK);
    }
    c.out.clear();
    let s = c.status_report();
    let want_x = 0.5 * a * 0.25 * 0.25;
    let mpos = s
        .split('|')
        .find_map(|f| f.strip_prefix("MPos:"))
        .unwrap_or_else(|| panic!("{s}"));
    let x: f64 = mpos.split(',').next().unwrap().parse().unwrap();
    assert!((x - want_x).abs() < 0.0015, "{s}: want X {want_x:.4}");
    let feed = 0.25 * a * 60.0;
    assert!(s.contains(&format!("|FS:{feed:.0},")), "{s}");
    assert!(s.starts_with("<Run|") && s.contains("|Bf:14,128"), "{s}");
    // After the ramp and 1.5 s of cruise: one third of a second of ramp is 16.667 mm.
    for k in 251..=1833u32 {
        c.tick(k as f64 * TICK);
    }
    let s = c.status_report();
    assert!(s.contains("MPos:166.6"), "{s}");
}
