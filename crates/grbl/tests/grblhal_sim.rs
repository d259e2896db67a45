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
use oficina_grbl::job::Job;
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

#[test]
fn sim_done_means_at_rest_when_status_queries_are_lost() {
    let Some(sim) = grblhal_sim::start("done", None) else {
        return;
    };
    let flag = sim.drop_queries.clone();
    scenarios::done_means_at_rest(&sim.endpoint, &move |on| flag.store(on, Ordering::Relaxed));
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
/// witness. `OFICINA_RANDOM_STOPS` sets how many (default 4).
#[test]
fn sim_random_stops_on_a_relief_leave_no_gap_and_no_double_cut() {
    if std::env::var_os("OFICINA_GRBLHAL_SIM").is_none() {
        grblhal_sim::start("random-stops", None);
        return;
    }
    let job = Job::from_text("relief.nc", &coverage::relief_program(6, 30, 0.5, 1500.0)).unwrap();
    let run = |stop: Duration| {
        let sim: Sim = grblhal_sim::start("random-stops", Some(0.005)).unwrap();
        let mut s = scenarios::connect(&sim.endpoint);
        scenarios::configure(&mut s);
        let (c, report) =
            scenarios::stop_and_resume(&mut s, &job, stop, &|| sim.pieces(STEPS_PER_MM));
        (c, report, sim.samples())
    };
    let (full, _, samples) = run(Duration::from_secs(3600));
    assert!(
        full.worst_gap <= 0.01 && full.worst_double <= 0.01,
        "{full:?}"
    );
    let total = samples.last().unwrap().0 - samples.first().unwrap().0;
    let trials: u64 = std::env::var("OFICINA_RANDOM_STOPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(4);
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut worst = (0.0f64, 0.0f64);
    for k in 0..trials {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let f = 0.1 + 0.8 * (seed >> 11) as f64 / (1u64 << 53) as f64;
        let stop = Duration::from_secs_f64(total * f);
        let (c, report, _) = run(stop);
        eprintln!(
            "sim stop {k}: after {:.2} s of {total:.2} s, resumed at {:?}: worst gap {:.4} mm, worst double cut {:.4} mm",
            stop.as_secs_f64(),
            report.resume.as_ref().map(|r| (r.index, r.entry)),
            c.worst_gap,
            c.worst_double
        );
        worst = (worst.0.max(c.worst_gap), worst.1.max(c.worst_double));
        assert!(
            c.worst_gap <= 0.01 && c.worst_double <= 0.01,
            "stop {k} at {stop:?}: {c:?} {report:?}"
        );
    }
    eprintln!(
        "sim random stops: {trials} trials, worst gap {:.4} mm, worst double cut {:.4} mm",
        worst.0, worst.1
    );
}
