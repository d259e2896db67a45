//! Steps replayed through forward kinematics stay on the planned path, and their
//! compressed queue_step form keeps every step within 25 µs.

mod common;
use common::{profile, program};
use oficina_motion::{self, Kinematics};
use oficina_motion::{decompress, Compressor};
use oficina_motion::{plan, PlanOptions, Profile, Segment};
use oficina_motion::{StepGenerator, StepLog};

fn planned(p: &Profile, kind: &str, c: [f64; 3], size: f64) -> Vec<Segment> {
    let prog = program(kind, 3, c, size);
    plan(prog.ops.into_iter(), p, PlanOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap()
}

/// Replays the steps with a backlash dead band and returns the worst distance between the
/// replayed Cartesian point and the planned one at each step, beyond the quantisation bound.
fn replay(p: &Profile, segs: &[Segment]) -> (f64, usize) {
    let kin = oficina_motion::for_profile(p);
    let q_start = kin.joints(p.start).unwrap();
    let mut gen = StepGenerator::new(p, q_start);
    let mut log = StepLog::default();
    for s in segs {
        gen.segment(s, &mut log).unwrap();
    }
    let mut events: Vec<(f64, usize, bool)> = Vec::new();
    for (m, steps) in log.motors.iter().enumerate() {
        events.extend(steps.iter().map(|&(t, d)| (t, m, d)));
    }
    events.sort_by(|a, b| a.0.total_cmp(&b.0));
    let spu: [f64; 3] = std::array::from_fn(|i| p.joints[i].map_or(1.0, |j| j.steps_per_unit));
    let play: [i64; 3] = std::array::from_fn(|i| {
        p.joints[i].map_or(0, |j| (j.backlash * j.steps_per_unit).round() as i64)
    });
    let mut count: [i64; 3] = std::array::from_fn(|i| (q_start[i] * spu[i]).round() as i64);
    let mut dir: [Option<bool>; 3] = [None; 3];
    let mut skip = [0i64; 3];
    let (mut seg_i, mut seg_t0) = (0usize, 0.0);
    let mut worst: f64 = 0.0;
    for &(t, m, fwd) in &events {
        if dir[m].is_some_and(|d| d != fwd) {
            skip[m] = play[m]; // these steps only take up the play
        }
        dir[m] = Some(fwd);
        if skip[m] > 0 {
            skip[m] -= 1;
        } else {
            count[m] += if fwd { 1 } else { -1 };
        }
        while seg_i + 1 < segs.len() && t > seg_t0 + segs[seg_i].duration() {
            seg_t0 += segs[seg_i].duration();
            seg_i += 1;
        }
        let (want, _, _) = segs[seg_i].sample(t - seg_t0);
        let q: [f64; 3] = std::array::from_fn(|i| count[i] as f64 / spu[i]);
        let got = kin.forward(q);
        // Half a step on each joint, mapped to Cartesian by finite differences.
        let mut quant = 0.0;
        for j in 0..3 {
            let mut qj = q;
            qj[j] += 0.5 / spu[j];
            let pj = kin.forward(qj);
            quant +=
                ((pj[0] - got[0]).powi(2) + (pj[1] - got[1]).powi(2) + (pj[2] - got[2]).powi(2))
                    .sqrt();
        }
        let d =
            ((want[0] - got[0]).powi(2) + (want[1] - got[1]).powi(2) + (want[2] - got[2]).powi(2))
                .sqrt();
        worst = worst.max(d - quant);
    }
    // Every motor ends where the last segment ends.
    let end = segs.last().unwrap().q1;
    for j in 0..3 {
        if p.joints[j].is_some() {
            assert_eq!(
                count[j],
                (end[j] * spu[j]).round() as i64,
                "motor {j} lost steps"
            );
        }
    }
    (worst, events.len())
}

#[test]
fn replay_stays_on_the_planned_path_on_every_kinematics() {
    let cases: [(&str, [f64; 3], f64); 4] = [
        ("grbl-router.toml", [400.0, 225.0, -10.0], 40.0),
        ("hotwire-xy.toml", [0.0, 0.0, 0.0], 40.0),
        ("embroidery-xy.toml", [0.0, 0.0, 0.0], 100.0),
        ("polar-plotter.toml", [600.0, 300.0, 2.0], 100.0),
    ];
    for (file, c, size) in cases {
        let p = profile(file);
        for kind in ["spiral", "reversals", "full-circles", "zigzag"] {
            let c = if kind == "full-circles" && p.joints[2].is_none() {
                [c[0], c[1], 0.0]
            } else {
                c
            };
            if kind == "full-circles" && p.joints[2].is_none() {
                continue; // the helix needs a Z axis
            }
            let segs = planned(&p, kind, c, size);
            let (worst, steps) = replay(&p, &segs);
            eprintln!("{file} {kind}: {steps} steps, worst excess {worst:.2e} mm");
            // Joint-linear motion between piece ends may leave the chord by the path tolerance.
            assert!(
                worst <= p.path_tolerance,
                "{file} {kind}: replay strays {worst} mm beyond quantisation"
            );
        }
    }
}

#[test]
fn compressed_steps_are_within_25_microseconds() {
    let p = profile("grbl-router.toml");
    let segs = planned(&p, "spiral", [400.0, 225.0, -10.0], 40.0);
    let kin = oficina_motion::for_profile(&p);
    let mut gen = StepGenerator::new(&p, kin.joints(p.start).unwrap());
    let mut log = StepLog::default();
    for s in &segs {
        gen.segment(s, &mut log).unwrap();
    }
    for steps in &log.motors {
        if steps.is_empty() {
            continue;
        }
        let mut c = Compressor::new(16e6, 25e-6);
        for &(t, d) in steps {
            c.push(t, d);
        }
        c.flush();
        let back = decompress(&c.out);
        assert_eq!(back.len(), steps.len());
        let worst = back
            .iter()
            .zip(steps)
            .map(|(b, s)| (b.0 as f64 / 16e6 - s.0).abs())
            .fold(0.0, f64::max);
        assert!(worst <= 25e-6, "worst {worst}");
        assert!(
            back.iter().zip(steps).all(|(b, s)| b.1 == s.1),
            "direction changed"
        );
        eprintln!(
            "{} steps → {} queue_step runs, worst error {:.1} µs",
            steps.len(),
            c.out.len(),
            worst * 1e6
        );
    }
}

#[test]
fn polar_planner_slows_near_the_pivot() {
    let p = profile("polar-plotter.toml");
    let mut prog = common::Prog::new(6000.0);
    prog.g1(600.0, 100.0, 5.0);
    prog.g1(-600.0, 100.0, 5.0); // passes 100 mm from the pivot (h = 40 mm)
    let segs: Vec<Segment> = plan(prog.ops.into_iter(), &p, PlanOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let speed_at = |x: f64| {
        segs.iter()
            .filter(|s| (s.start[0] - x).abs() < 5.0 && s.start[1] > 99.0)
            .map(|s| s.motion.v_start())
            .fold(0.0, f64::max)
    };
    // Far away the arm turns slowly per mm; near the pivot θ races, so the path must slow.
    assert!(
        speed_at(0.0) < 0.5 * speed_at(-400.0),
        "{} vs {}",
        speed_at(0.0),
        speed_at(-400.0)
    );
    let mut bad = common::Prog::new(6000.0);
    bad.g1(600.0, 10.0, 5.0);
    bad.g1(-600.0, 10.0, 5.0);
    let e = plan(bad.ops.into_iter(), &p, PlanOptions::default())
        .unwrap()
        .find_map(|r| r.err())
        .unwrap();
    assert!(e.to_string().contains("pen offset"), "{e}");
}
