//! Degenerate relief jobs: every small grid from 1 × 1 up, tools far larger than the part,
//! step-overs and step-downs larger than the part, absurd pixel sizes and depths. Each
//! either plans (finite moves, never below the design's lowest point) or is refused with a
//! named error; none panics, and an absurd one is refused by its estimate, not by the
//! kernel's OOM killer.
//!
//! The property over random jobs runs `PROPTEST_CASES` cases (default 256); a long run:
//! `PROPTEST_CASES=20000 cargo test --release -p oficina-cam --test degenerate`.

use oficina_cam::memory::{Budget, Lever};
use oficina_cam::relief::{plan, plan_within, Cutter, Direction, Pass, ReliefError, ReliefJob};
use oficina_cam::Feeds;
use oficina_cam::Toolpath;
use oficina_io::Heightmap;
use proptest::prelude::*;

fn cutter(number: u32, spec: &str) -> Cutter {
    Cutter {
        number,
        tool: spec.parse().unwrap(),
        feeds: Feeds {
            cut: 2000.0 / 60.0,
            plunge: 500.0 / 60.0,
            rapid: 5000.0 / 60.0,
        },
        spindle_rpm: 18000.0,
    }
}

// Kept here on purpose: `Pass` is plain data with no public builder (cam's seed004 has its
// own private one with other defaults), and each test states every field it relies on.
fn pass(name: &str, c: Cutter, stepover: f64, stepdown: f64, direction: Direction) -> Pass {
    Pass {
        name: name.into(),
        cutter: c,
        stepover,
        stepdown,
        allowance: 0.0,
        direction,
        zigzag: true,
        rest_only: false,
        min_cut: 0.01,
    }
}

/// Roughing, rest machining and finishing in both directions: every code path of `plan`.
fn full_job(rough: &str, finish: &str, stepover: f64, stepdown: f64) -> ReliefJob {
    let mut rough = pass(
        "roughing",
        cutter(1, rough),
        stepover,
        stepdown,
        Direction::X,
    );
    rough.allowance = 0.5;
    let mut rest = pass("rest", cutter(2, finish), stepover, stepdown, Direction::Y);
    rest.rest_only = true;
    rest.allowance = 0.2;
    rest.min_cut = 0.8;
    ReliefJob {
        safe_z: 5.0,
        clearance: 1.0,
        tolerance: 0.005,
        samples_per_pixel: 4,
        passes: vec![
            rough,
            rest,
            pass(
                "finishing",
                cutter(2, finish),
                stepover,
                stepdown,
                Direction::Both,
            ),
        ],
        simulate_last: true,
    }
}

/// A bowl with ripples: deepest in the middle.
fn design(w: usize, h: usize, pixel: f64, depth: f64) -> Heightmap {
    Heightmap::from_fn(w, h, pixel, |x, y| {
        let (cx, cy) = ((w - 1) as f64 * pixel / 2.0, (h - 1) as f64 * pixel / 2.0);
        let r = ((x - cx).powi(2) + (y - cy).powi(2)).sqrt() / (cx.max(cy).max(pixel));
        -depth * (1.0 - r.min(1.0)) - 0.1 * (1.0 + (x * 7.0 + y * 3.0).sin())
    })
}

/// Every move's end is finite and its tool touches no design sample from below (no gouge
/// at the ends of moves, with the tool's own profile).
fn sane(path: &Toolpath, design: &Heightmap) {
    for op in &path.operations {
        for m in &op.moves {
            let Some(p) = m.end() else { continue };
            assert!(p.iter().all(|v| v.is_finite()), "{}: {m:?}", op.name);
            for iy in 0..design.height {
                for ix in 0..design.width {
                    let d = (design.x(ix) - p[0]).hypot(design.y(iy) - p[1]);
                    if let Some(lift) = op.tool.profile(d) {
                        let gouge = design.at(ix, iy) as f64 - (p[2] + lift);
                        assert!(
                            gouge <= 1e-3 * p[2].abs().max(1.0),
                            "{}: {m:?} cuts {gouge} mm into sample {ix},{iy}",
                            op.name
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn every_small_grid_plans_with_tools_larger_than_the_part() {
    for w in 1..=7 {
        for h in 1..=7 {
            let d = design(w, h, 0.5, 3.0);
            for (rough, finish) in [("flat:6", "ball:3"), ("flat:100", "v:60:90")] {
                for (so, sd) in [(0.3, 1.0), (1000.0, 1000.0)] {
                    let planned = plan(&d, &full_job(rough, finish, so, sd), &|_, _| {})
                        .unwrap_or_else(|e| panic!("{w} x {h}, {rough} {finish} {so} {sd}: {e}"));
                    sane(&planned.toolpath, &d);
                    assert_eq!(planned.toolpath.operations.len(), 3);
                }
            }
        }
    }
    // Single rows and columns of some length.
    for (w, h) in [(1, 40), (40, 1), (2, 33), (33, 2)] {
        let d = design(w, h, 0.5, 3.0);
        let planned = plan(&d, &full_job("flat:6", "ball:3", 0.5, 1.0), &|_, _| {}).unwrap();
        sane(&planned.toolpath, &d);
        assert!(
            planned.toolpath.move_count() > 0,
            "{w} x {h} cuts something"
        );
    }
}

#[test]
fn a_tool_narrower_than_a_pixel_plans_finite_moves() {
    // 10 m pixels: between grid points no sample lies under a 3 mm ball.
    let d = design(5, 4, 1.0e4, 10.0);
    let planned = plan(&d, &full_job("flat:6", "ball:3", 1.0, 5.0), &|_, _| {}).unwrap();
    sane(&planned.toolpath, &d);
}

#[test]
fn absurd_depths_and_grids_are_refused_by_their_estimate() {
    let budget = Budget {
        bytes: 256 << 20,
        reserved: 0,
        per_move: 200,
    };
    // 100 m deep in 0.5 mm levels: 200000 levels of every row.
    let d = design(20, 20, 0.5, 0.99e5);
    let job = full_job("flat:6", "ball:3", 0.5, 0.5);
    match plan_within(&d, &job, budget, &|_, _| {}) {
        Err(ReliefError::Memory(e)) => {
            assert_eq!(e.lever, Lever::Levels, "{e}");
            assert!(e.to_string().contains("step-down"), "{e}");
            assert!(e.needed > e.budget);
        }
        other => panic!(
            "expected a memory refusal, got {:?}",
            other.map(|p| p.toolpath.move_count())
        ),
    }
    // A 20000 x 20000 grid: refused before any grid is allocated (the stand-in claims the
    // size and holds no samples: it must never be read).
    let big = Heightmap {
        width: 20_000,
        height: 20_000,
        pixel: 0.1,
        z: Vec::new(),
    };
    match plan_within(&big, &job, budget, &|_, _| {}) {
        Err(ReliefError::Memory(e)) => {
            assert_eq!(e.lever, Lever::PixelSize);
            assert!(e.to_string().contains("pixel size"), "{e}");
        }
        other => panic!("expected a memory refusal, got ok = {:?}", other.is_ok()),
    }
    // Beyond any machine: a kilometre of part or of depth.
    for d in [design(20, 20, 1.0e6, 10.0), design(20, 20, 0.5, 1.0e6)] {
        let e = plan_within(&d, &job, budget, &|_, _| {}).err();
        assert!(matches!(e, Some(ReliefError::TooLarge { .. })), "{e:?}");
    }
}

fn tool_spec() -> impl Strategy<Value = String> {
    prop_oneof![
        (0.01f64..300.0).prop_map(|d| format!("ball:{d}")),
        (0.01f64..300.0).prop_map(|d| format!("flat:{d}")),
        (0.01f64..300.0, 1.0f64..179.0).prop_map(|(d, a)| format!("v:{d}:{a}")),
        (0.01f64..300.0, 0.01f64..1.0).prop_map(|(d, c)| format!("bull:{d}:{}", d * c / 2.0)),
        (0.01f64..5.0, 0.5f64..59.0).prop_map(|(d, a)| format!("taper:{d}:{a}")),
    ]
}

/// Log-uniform over many decades, plus edge values.
fn scale(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (lo.ln()..hi.ln()).prop_map(f64::exp),
        1 => prop::sample::select(vec![
            0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            lo,
            hi,
            f64::MAX,
            f64::MIN_POSITIVE
        ]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { max_shrink_iters: 200, ..ProptestConfig::default() })]

    #[test]
    fn random_jobs_plan_or_are_refused(
        w in 1usize..14, h in 1usize..14,
        z in prop::collection::vec(-50.0f32..0.0, 1..200),
        pixel in scale(1e-3, 1e7),
        rough in tool_spec(), finish in tool_spec(),
        stepover in scale(1e-4, 1e6), stepdown in scale(1e-4, 1e7),
        allowance in scale(1e-3, 1e3), tol in scale(1e-6, 1e2),
        sub in 0usize..20, safe_z in scale(1e-3, 1e6),
    ) {
        let d = Heightmap {
            width: w,
            height: h,
            pixel,
            z: (0..w * h).map(|i| z[i % z.len()]).collect(),
        };
        if rough.parse::<oficina_cam::Tool>().is_err() || finish.parse::<oficina_cam::Tool>().is_err() {
            return Ok(());
        }
        let mut job = full_job(&rough, &finish, stepover, stepdown);
        job.passes[0].allowance = allowance;
        job.tolerance = tol;
        job.samples_per_pixel = sub;
        job.safe_z = safe_z;
        let budget = Budget { bytes: 64 << 20, reserved: 0, per_move: 200 };
        let t = std::time::Instant::now();
        let result = plan_within(&d, &job, budget, &|stage, f| {
            if t.elapsed().as_secs_f64() > 1.0 {
                eprintln!("slow case: {:.1} s at {stage} {f}", t.elapsed().as_secs_f64());
            }
        });
        if t.elapsed().as_secs_f64() > 1.0 {
            eprintln!(
                "slow case: {:.1} s, {w} x {h} px of {pixel} mm, {rough} {finish} stepover {stepover} stepdown {stepdown} allowance {allowance} tol {tol} sub {sub}",
                t.elapsed().as_secs_f64()
            );
        }
        if let Ok(planned) = result {
            sane(&planned.toolpath, &d);
        }
    }
}
