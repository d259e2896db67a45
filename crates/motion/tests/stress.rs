//! The invariant checker over the stress corpus: 10 kinds × 6 seeds = 60 programs on the
//! Cartesian router in both velocity shapes, and a share of them on the non-linear machines.

mod common;
use common::{profile, program, KINDS};
use oficina_motion::check;
use oficina_motion::VelocityProfile;
use oficina_motion::{plan, PlanOptions, Profile, Segment};

fn run(p: &Profile, shape: VelocityProfile, centre: [f64; 3], size: f64, seeds: u64) -> usize {
    let mut n = 0;
    let mut worst: f64 = 0.0;
    for kind in KINDS {
        for seed in 0..seeds {
            let prog = program(kind, seed, centre, size);
            let opts = PlanOptions {
                shape: Some(shape),
                ..PlanOptions::default()
            };
            let segs: Vec<Segment> = plan(prog.ops.iter().cloned(), p, opts)
                .unwrap()
                .collect::<Result<_, _>>()
                .unwrap_or_else(|e| panic!("{kind}/{seed}: {e}"));
            match check(&prog.ops, &segs, p, shape, 1.0) {
                Ok(r) => worst = worst.max(r.max_path_deviation),
                Err(v) => panic!(
                    "{} {kind}/{seed} {shape:?}: {} violations:\n{}",
                    p.name,
                    v.len(),
                    v.join("\n")
                ),
            }
            n += 1;
        }
    }
    eprintln!(
        "{} {shape:?}: {n} programs, worst path deviation {worst:.6} mm",
        p.name
    );
    n
}

#[test]
fn router_trapezoid_and_scurve_over_the_corpus() {
    let p = profile("grbl-router.toml");
    let n = run(
        &p,
        VelocityProfile::Trapezoid,
        [400.0, 225.0, -10.0],
        300.0,
        6,
    );
    assert!(n >= 50);
    run(&p, VelocityProfile::SCurve, [400.0, 225.0, -10.0], 300.0, 6);
}

#[test]
fn polar_plotter_over_the_corpus() {
    let mut p = profile("polar-plotter.toml");
    p.travel[2] = [-10.0, 5.0];
    run(
        &p,
        VelocityProfile::Trapezoid,
        [600.0, 300.0, 0.0],
        200.0,
        2,
    );
    run(&p, VelocityProfile::SCurve, [-500.0, -200.0, 0.0], 200.0, 1);
}

#[test]
fn polargraph_and_corexy_over_the_corpus() {
    let mut p = profile("polargraph-wall.toml");
    p.travel[2] = [-10.0, 5.0];
    run(
        &p,
        VelocityProfile::Trapezoid,
        [500.0, -500.0, 0.0],
        300.0,
        2,
    );
    let mut c = profile("grbl-router.toml");
    c.kinematics = oficina_motion::KinematicsKind::CoreXy;
    c.joints[0].as_mut().unwrap().name = "a";
    c.joints[1].as_mut().unwrap().name = "b";
    run(&c, VelocityProfile::SCurve, [400.0, 225.0, -10.0], 300.0, 1);
}
