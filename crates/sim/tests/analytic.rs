//! Plans real jobs on analytic surfaces and checks the simulated result: never a gouge,
//! and scallops as the closed forms predict.

mod common;

use common::replay_on_fresh_stock;
use oficina_cam::relief::{plan, Cutter, Direction, Pass, Planned, ReliefJob};
use oficina_cam::Feeds;
use oficina_io::Heightmap;
use oficina_sim::{compare, feed_only_estimate, ideal_surface};

const FEEDS: Feeds = Feeds {
    cut: 2000.0 / 60.0,
    plunge: 500.0 / 60.0,
    rapid: 5000.0 / 60.0,
};

fn cutter(number: u32, spec: &str) -> Cutter {
    Cutter {
        number,
        tool: spec.parse().unwrap(),
        feeds: FEEDS,
        spindle_rpm: 18000.0,
    }
}

// Kept here on purpose: `Pass` is plain data with no public builder (cam's seed004 has its
// own private one with other defaults), and each test states every field it relies on.
fn pass(
    name: &str,
    c: Cutter,
    stepover: f64,
    stepdown: f64,
    allowance: f64,
    direction: Direction,
    rest_only: bool,
) -> Pass {
    Pass {
        name: name.into(),
        cutter: c,
        stepover,
        stepdown,
        allowance,
        direction,
        zigzag: true,
        rest_only,
        min_cut: 0.001,
    }
}

fn job(passes: Vec<Pass>) -> ReliefJob {
    ReliefJob {
        safe_z: 5.0,
        clearance: 1.0,
        tolerance: 0.005,
        samples_per_pixel: oficina_cam::relief::SAMPLES_PER_PIXEL,
        passes,
        simulate_last: true,
    }
}

/// A single finishing pass of tool 1 (`spec`) along X over `design`, planned.
fn finish_plan(design: &Heightmap, spec: &str, stepover: f64, stepdown: f64) -> Planned {
    plan(
        design,
        &job(vec![pass(
            "finish",
            cutter(1, spec),
            stepover,
            stepdown,
            0.0,
            Direction::X,
            false,
        )]),
        &|_, _| {},
    )
    .unwrap()
}

fn hemisphere(size_mm: f64, depth: f64, pixel: f64) -> Heightmap {
    let n = (size_mm / pixel).round() as usize + 1;
    let (c, r) = (size_mm / 2.0, size_mm / 2.0 * 0.8);
    // A bowl (cavity) of radius r, `depth` deep, scaled into a sphere cap.
    Heightmap::from_fn(n, n, pixel, |x, y| {
        let d2 = (x - c).powi(2) + (y - c).powi(2);
        if d2 < r * r {
            -depth * (1.0 - d2 / (r * r)).sqrt()
        } else {
            0.0
        }
    })
}

#[test]
fn ball_on_a_plane_leaves_the_closed_form_scallop() {
    // A floor 2 mm deep; rows 2 mm apart with a 6 mm ball: h = r − sqrt(r² − (s/2)²).
    let design = Heightmap::flat(81, 81, 0.25, -2.0);
    let planned = finish_plan(&design, "ball:6", 2.0, 5.0);
    let stock = replay_on_fresh_stock(&design, &planned);
    let ideal = ideal_surface(&design, &planned.toolpath.operations[0].tool);
    let report = compare(&stock, &design, &ideal);
    let exact = 3.0 - (9.0f64 - 1.0).sqrt();
    assert!(report.max_gouge < 1e-3 * 1e-3 + 1e-6, "{report:?}");
    assert!(
        (report.scallop_max - exact).abs() < 0.01,
        "scallop {} vs {exact}",
        report.scallop_max
    );
}

#[test]
fn no_gouge_on_hemisphere_cone_ramp_and_step_with_every_tool() {
    let pixel = 0.5;
    let surfaces: Vec<(&str, Heightmap)> = vec![
        ("hemisphere", hemisphere(40.0, 10.0, pixel)),
        (
            "cone",
            Heightmap::from_fn(81, 81, pixel, |x, y| {
                -(8.0 - 0.5 * ((x - 20.0).powi(2) + (y - 20.0).powi(2)).sqrt()).max(0.0)
            }),
        ),
        ("ramp", Heightmap::from_fn(81, 61, pixel, |x, _| -0.2 * x)),
        (
            "step",
            Heightmap::from_fn(61, 61, pixel, |x, y| {
                if x > 15.0 && y > 10.0 {
                    -6.0
                } else {
                    -1.0
                }
            }),
        ),
    ];
    for (name, design) in &surfaces {
        for spec in ["ball:3", "flat:4", "v:6:90", "bull:6:1", "taper:1:8"] {
            let planned = plan(
                design,
                &job(vec![
                    pass(
                        "rough",
                        cutter(1, "flat:8"),
                        6.0,
                        5.0,
                        0.5,
                        Direction::X,
                        false,
                    ),
                    pass(
                        "finish",
                        cutter(2, spec),
                        0.7,
                        5.0,
                        0.0,
                        Direction::Both,
                        false,
                    ),
                ]),
                &|_, _| {},
            )
            .unwrap();
            let stock = replay_on_fresh_stock(design, &planned);
            let ideal = ideal_surface(design, &planned.toolpath.operations[1].tool);
            let report = compare(&stock, design, &ideal);
            assert!(
                report.max_gouge <= 1e-6,
                "{name} with {spec}: gouge {} at {:?}",
                report.max_gouge,
                report.gouge_at
            );
            // The CAM's own stock model agrees with the replay of canonical operations.
            let own = planned.stock.as_ref().unwrap();
            let diff = own
                .z
                .iter()
                .zip(&stock.z)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f32, f32::max);
            assert!(
                diff < 1e-4,
                "{name}/{spec}: CAM stock differs from replay by {diff}"
            );
        }
    }
}

#[test]
fn feed_only_estimate_matches_move_by_move_sum() {
    let design = hemisphere(30.0, 8.0, 0.5);
    let planned = finish_plan(&design, "ball:3", 1.0, 4.0);
    let rapid = 5000.0;
    let est = feed_only_estimate(&planned.toolpath.canon(), [0.0, 0.0, 5.0], rapid);
    // Independent: walk the toolpath moves.
    let mut pos = [0.0, 0.0, 5.0];
    let mut t = 0.0;
    for op in &planned.toolpath.operations {
        for m in &op.moves {
            if let Some(to) = m.end() {
                let len = ((to[0] - pos[0]).powi(2)
                    + (to[1] - pos[1]).powi(2)
                    + (to[2] - pos[2]).powi(2))
                .sqrt();
                // A rapid takes as long as its slowest axis: each axis at the rapid rate.
                let axis_max = (0..3).map(|i| (to[i] - pos[i]).abs()).fold(0.0, f64::max);
                t += match m {
                    oficina_cam::Move::Line { feed, .. } => len / feed,
                    _ => axis_max / (rapid / 60.0),
                };
                pos = to;
            }
        }
    }
    assert!(t > 10.0);
    assert!((est - t).abs() < 1e-6 * t, "{est} vs {t}");
}

#[test]
fn a_move_below_the_design_is_reported_as_a_gouge() {
    let design = Heightmap::flat(41, 41, 0.5, -2.0);
    let mut planned = finish_plan(&design, "ball:3", 1.0, 4.0);
    planned.toolpath.operations[0]
        .moves
        .push(oficina_cam::Move::Line {
            to: [10.0, 10.0, -2.3],
            feed: 10.0,
        });
    let stock = replay_on_fresh_stock(&design, &planned);
    let ideal = ideal_surface(&design, &planned.toolpath.operations[0].tool);
    let report = compare(&stock, &design, &ideal);
    assert!((report.max_gouge - 0.3).abs() < 1e-5, "{report:?}");
    assert_eq!(report.gouge_at, [10.0, 10.0]);
}
