//! The sender against real grblHAL firmware: grblHAL's own Simulator (grblHAL/Simulator with
//! its grblHAL/core submodule), whose binary the tester provides in `OFICINA_GRBLHAL_SIM`
//! (never vendored: GPL-3). Unset, each test prints SKIPPED and passes without running.
//!
//! Each of the four failures seen on this firmware is a test here that failed before its
//! fix; the emulator runs the same scenarios in CI (`firmware_flavors.rs`).

mod common;

use common::coverage;
use common::grblhal_sim::{self, Sim};
use common::scenarios;
use oficina_grbl::StreamProgram;
use std::sync::atomic::Ordering;
use std::time::Duration;

/// grblHAL's default `$100…$102`.
const STEPS_PER_MM: f64 = 250.0;

#[test]
fn sim_reset_banner_is_recognised() {
    let Some(sim) = grblhal_sim::start("banner", None) else {
        return;
    };
    let s = scenarios::reset_is_recognised(&sim.endpoint);
    assert!(s.firmware.starts_with("1.1f"), "{}", s.firmware);
}

/// The error table ([`oficina_gcode::grbl_errors`]) against the firmware's own words: grblHAL
/// lists its errors with `$EE`; codes 20 to 37 (the G-code errors) read exactly as grbl's.
#[test]
fn sim_error_texts_are_the_firmwares() {
    let Some(sim) = grblhal_sim::start("errors", None) else {
        return;
    };
    let mut s = scenarios::connect(&sim.endpoint);
    let reply = s.command("$EE").expect("$EE");
    assert_eq!(reply.error, None);
    // `[ERRORCODE:24||More than one g-code command that requires axis words found in block.]`
    let listed: std::collections::BTreeMap<u16, String> = reply
        .lines
        .iter()
        .filter_map(|l| {
            let (code, text) = l
                .strip_prefix("[ERRORCODE:")?
                .strip_suffix(']')?
                .split_once("||")?;
            Some((code.parse().ok()?, text.to_string()))
        })
        .collect();
    for code in 20..=37u16 {
        let ours = oficina_gcode::grbl_errors::error_text(code).map(|t| t.1);
        assert_eq!(ours, listed.get(&code).map(|t| t.as_str()), "error:{code}");
    }
    // The decoder's conflicts, numbered by their kind, as the firmware numbers them. gcode.c
    // meets a second axis command before it checks modal groups (`G0 G1` is 24, `G17 G18`
    // 21). A reset before each line: the Simulator answered every line after its first
    // error with that same error.
    for line in [
        "G0 G1 X1",
        "G2 G38.2 X1",
        "G28 G30 X1",
        "G28 G1 X1",
        "G4 G28 P1",
        "G17 G18",
        "M3 M4",
        "G1 X1 X2",
        "G1 X1 F100 F200",
        "G15 X1",
    ] {
        s.reset().expect("reset");
        let firmware = s.command(line).expect("reply").error.map(u16::from);
        assert!(firmware.is_some(), "`{line}` accepted by the firmware");
        let diags = oficina_gcode::run_text(
            &format!("{line}\n"),
            &oficina_gcode::RunOptions::check(oficina_gcode::Dialect::Grbl),
            &mut |_| {},
        );
        let ours = diags.first().and_then(|d| d.code);
        assert_eq!(ours, firmware, "`{line}`: {diags:?}");
    }
}

#[test]
fn sim_done_means_at_rest_when_status_queries_are_lost() {
    let Some(sim) = grblhal_sim::start("done", None) else {
        return;
    };
    let flag = sim.drop_queries.clone();
    scenarios::done_means_at_rest(&sim.endpoint, &move |on| flag.store(on, Ordering::Relaxed));
}

#[test]
fn sim_wco_is_reported_when_it_changes() {
    let Some(sim) = grblhal_sim::start("wco", None) else {
        return;
    };
    scenarios::wco_reported_when_it_changes(&sim.endpoint);
}

#[test]
fn sim_hold_resume_override_stop_work_until_idle() {
    let Some(sim) = grblhal_sim::start("controls", None) else {
        return;
    };
    scenarios::controls_work_until_idle(&sim.endpoint);
}

#[test]
fn sim_resume_comes_from_the_reported_position() {
    let Some(sim) = grblhal_sim::start("resume", Some(0.005)) else {
        return;
    };
    // The record holds everything since start: the job starts at the origin, at rest, so
    // motion before it is none (the settings move nothing).
    scenarios::resume_from_the_position(&sim.endpoint, &|| {}, &|| sim.pieces(STEPS_PER_MM));
}

/// Random stops on a relief raster, each in a fresh simulator, its position record the
/// witness. `OFICINA_RANDOM_STOPS` sets how many (default 4). Under host load grblHAL's
/// harness sometimes stops sampling while the machine moves; a trial whose record has such
/// a hole is reported and not counted as a witness.
#[test]
fn sim_random_stops_on_a_relief_leave_no_gap_and_no_double_cut() {
    if std::env::var_os("OFICINA_GRBLHAL_SIM").is_none() {
        grblhal_sim::start("random-stops", None);
        return;
    }
    let job = StreamProgram::from_text("relief.nc", &coverage::relief_program(6, 30, 0.5, 1500.0))
        .unwrap();
    let run = |stop: Duration| {
        let sim: Sim = grblhal_sim::start("random-stops", Some(0.005)).unwrap();
        let mut s = scenarios::connect(&sim.endpoint);
        scenarios::configure(&mut s);
        let (c, report) =
            scenarios::stop_and_resume(&mut s, &job, stop, &|| sim.pieces(STEPS_PER_MM));
        // Samples every 5 ms at F1500 (25 mm/s) are 0.125 mm apart.
        let hole = coverage::record_hole(
            &coverage::program_cuts(&job),
            &sim.pieces(STEPS_PER_MM),
            0.01,
            2.0 * 25.0 * 0.005 + 0.02,
        );
        (c, report, sim.samples(), hole)
    };
    let trials: u64 = std::env::var("OFICINA_RANDOM_STOPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(4);
    let mut total = 0.0;
    let mut random = oficina_testkit::random::Xorshift::new(0x2545_f491_4f6c_dd1d);
    let (mut worst_gap, mut worst_double, mut witnessed) = (0.0f64, 0.0f64, 0);
    // Trial 0 runs the job without a stop (and measures its length).
    for k in 0..=trials {
        let f = 0.1 + 0.8 * random.unit();
        let stop = if k == 0 {
            Duration::from_secs(3600)
        } else {
            Duration::from_secs_f64(total * f)
        };
        let (c, report, samples, hole) = run(stop);
        if k == 0 {
            total = samples.last().unwrap().0 - samples.first().unwrap().0;
        }
        eprintln!(
            "sim stop {k}: after {:.2} s of {total:.2} s, resumed at {:?}: worst gap {:.4} mm, worst double cut {:.4} mm{}",
            if k == 0 { total } else { stop.as_secs_f64() },
            report.resume.as_ref().map(|r| (r.index, r.entry)),
            c.worst_gap,
            c.worst_double,
            if hole > 0.0 { format!(" (the record jumps {hole:.2} mm along the path: not a witness)") } else { String::new() }
        );
        if hole > 0.0 {
            continue;
        }
        witnessed += 1;
        worst_gap = worst_gap.max(c.worst_gap);
        worst_double = worst_double.max(c.worst_double);
        assert!(
            c.worst_gap <= 0.01 && c.worst_double <= 0.01,
            "stop {k} at {stop:?}: {c:?} {report:?}"
        );
    }
    eprintln!(
        "sim random stops: {} runs, {witnessed} with a complete record: worst gap {worst_gap:.4} mm, worst double cut {worst_double:.4} mm",
        trials + 1
    );
    assert!(witnessed > 0, "no run had a complete position record");
}

/// Oficina's time estimate (its planner, with the `$` settings the firmware reports)
/// against the firmware's own run time (the simulated time of its position record, first
/// to last motion, and the part of it spent moving) on a zig-zag, arcs and a relief
/// raster. Printed as a table; the estimate must be within 5 % of the moving time.
#[test]
fn sim_time_estimates_match_the_firmware() {
    use oficina_gcode::{run as gcode_run, RunOptions};
    use oficina_grbl_emu::motion_profile;
    let mut zigzag = String::from("G21G90G94\nG0X0Y0\nG1F3000\n");
    for i in 0..20 {
        zigzag += &format!("X{}Y{}\n", if i % 2 == 0 { 30 } else { 0 }, i + 1);
    }
    let mut arcs = String::from("G21G90G94\nG0X10Y0\nG1F2000\n");
    for i in 0..6 {
        let r = 10.0 + i as f64;
        arcs += &format!("G1X{r}Y0\nG3X{r}Y0I{}J0\n", -r);
    }
    let relief = coverage::relief_program(6, 30, 0.5, 1500.0);
    let mut rows = Vec::new();
    for (name, text) in [
        ("zig-zag", zigzag),
        ("arcs", arcs),
        ("relief raster", relief),
    ] {
        let Some(sim) = grblhal_sim::start("estimates", Some(0.005)) else {
            return;
        };
        let mut s = scenarios::connect(&sim.endpoint);
        scenarios::configure(&mut s);
        let job = StreamProgram::from_text(name, &text).unwrap();
        let report = s.stream(&job, 0, None, None, &mut |_| {});
        assert_eq!(report.end, oficina_grbl::StreamEnd::Completed);
        sim.finish();
        let samples = sim.samples();
        let firmware = samples.last().unwrap().0 - samples.first().unwrap().0;
        // The harness samples every 5 ms while a block runs; longer gaps are time with an
        // empty planner (its serial reader fell behind: a starved machine, not motion).
        let moving: f64 = samples
            .windows(2)
            .map(|w| w[1].0 - w[0].0)
            .filter(|dt| *dt <= 0.0051)
            .sum();
        let mut ops = Vec::new();
        gcode_run(
            std::io::Cursor::new((text.clone() + "M2\n").into_bytes()),
            &RunOptions::check(oficina_gcode::Dialect::Grbl),
            &mut |c| ops.push(c),
        );
        let mut profile = motion_profile(&s.settings);
        // grblHAL's soft limits are off by default ($20=0): no travel bound.
        profile.travel = [[-1e4, 1e4]; 3];
        let estimate = oficina_motion::estimate(ops.into_iter(), &profile)
            .unwrap()
            .seconds;
        rows.push((name, estimate, firmware, moving));
    }
    eprintln!("| program | Oficina estimate (s) | grblHAL first to last motion (s) | of which moving (s) | estimate vs moving |");
    eprintln!("|---|---|---|---|---|");
    for (name, e, f, m) in &rows {
        eprintln!(
            "| {name} | {e:.3} | {f:.3} | {m:.3} | {:+.2} % |",
            (e - m) / m * 100.0
        );
    }
    // A run whose record shows the machine waiting (the harness's reader fell behind the
    // wire under host load) is reported, not compared: its motion was starved.
    let mut compared = 0;
    for (name, e, f, m) in &rows {
        if f - m > 0.02 * f {
            eprintln!("{name}: starved for {:.3} s, not compared", f - m);
            continue;
        }
        compared += 1;
        assert!(
            (e - m).abs() / m < 0.05,
            "{name}: estimate {e:.3} s, firmware moving {m:.3} s"
        );
    }
    assert!(compared > 0, "every run was starved");
}
