//! The 4th axis: the emulator with a profile's `[joints.a]` (grblHAL's $103…$133) runs the
//! wrapped engraving sample to its end; its final A and its job time are checked against
//! Oficina's planner on the same program and profile (what `oficina plan` prints). The
//! firmware model runs in simulated time (1 ms ticks). The time agrees within 2 %, not yet
//! 1 %: see the note at the assertion.
//! The time agrees within 2 %, not yet 1 %: see the note at the assertion.

mod common;

use common::clocked::stream;
use oficina_gcode::{run, RunOptions};
use oficina_gcode::{Dialect, Severity};
use oficina_grbl::StatusReport;
use oficina_grbl_emu::grbl_settings;
use oficina_grbl_emu::{Config, Core, Flavor};
use oficina_motion::{estimate, Profile};
use std::io::Cursor;

fn root(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn router_4axis() -> Profile {
    Profile::load(&root("profiles/router-4axis.toml")).unwrap()
}

fn grblhal(p: &Profile) -> Core {
    let mut config = Config::flavored(Flavor::GrblHal);
    config.baud = None;
    config.settings.extend(grbl_settings(p).unwrap());
    Core::new(config)
}

/// `oficina plan`'s figure: the whole-job estimate with the profile's stored G54.
fn planned(text: &str, p: &Profile) -> f64 {
    let mut opts = RunOptions::check(Dialect::default());
    opts.initial_params = p.initial_params();
    let mut ops = Vec::new();
    let diags = run(Cursor::new(text.as_bytes().to_vec()), &opts, &mut |c| {
        ops.push(c)
    });
    assert!(
        diags.iter().all(|d| d.severity != Severity::Error),
        "{diags:?}"
    );
    estimate(ops.into_iter(), p).unwrap().seconds
}

#[test]
fn rotary_engraving_ends_at_its_a_and_takes_the_planned_time() {
    let p = router_4axis();
    let text = std::fs::read_to_string(root("samples/motion/rotary-engrave.ngc")).unwrap();
    let mut c = grblhal(&p);
    assert!(c.has_a());
    // The board holds the profile's G54, as `oficina emulate --machine` sets it up.
    let [x, y, z] = p.work_offset;
    let setup = format!("G10 L2 P1 X{x} Y{y} Z{z}");
    assert!(stream(&mut c, &[setup], |_| 0.0).seconds < 0.01);
    let lines: Vec<String> = text
        .lines()
        .map(|l| oficina_grbl::clean_line(l).unwrap())
        .filter(|l| !l.is_empty() && l != "%")
        .collect();
    let t0 = c.stats.busy_seconds;
    stream(&mut c, &lines, |_| 0.0);
    let emulated = c.stats.busy_seconds - t0;

    // The last A word of the program, and the report grblHAL prints with four axes.
    let last_a = text
        .lines()
        .rev()
        .filter_map(|l| l.split_whitespace().find_map(|w| w.strip_prefix('A')))
        .find_map(|a| a.parse::<f64>().ok())
        .unwrap();
    assert!(
        (c.mpos_a - last_a).abs() < 1e-9,
        "A {} vs {last_a}",
        c.mpos_a
    );
    let report = StatusReport::parse(&c.status_report()).unwrap();
    let mpos = report.mpos.expect("grblHAL reports MPos");
    assert_eq!(mpos.len(), 4, "{mpos:?}");
    assert!((mpos[3] - last_a).abs() < 1e-3);

    let plan = planned(&text, &p);
    let diff = (emulated - plan).abs() / plan;
    eprintln!(
        "emulated {emulated:.3} s, planned {plan:.3} s, {:.2} %",
        diff * 100.0
    );
    // Measured 1.3 %: the emulator's incremental planner (oficina-motion's `Incremental`)
    // takes X, Y, Z blocks only, so A's acceleration inside a mixed move and A's share of
    // the junction speeds are not seen there (A's rate is); the whole-job planner sees both.
    assert!(
        diff < 0.02,
        "emulated {emulated:.3} s vs planned {plan:.3} s"
    );
}

#[test]
fn a_words_are_refused_by_a_three_axis_grbl() {
    let p = Profile::load(&root("profiles/grbl-router.toml")).unwrap();
    let mut config = Config {
        baud: None,
        ..Config::default()
    };
    config.settings = grbl_settings(&p).unwrap();
    let mut c = Core::new(config);
    assert!(!c.has_a());
    for b in b"G0 A10\n" {
        c.receive(*b);
    }
    c.tick(0.001);
    let out: String = c.out.drain(..).map(char::from).collect();
    assert!(out.ends_with("error:20\r\n"), "{out:?}");
}
