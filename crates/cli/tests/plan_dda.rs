//! `oficina plan --interpolator dda`: seed 002's programs stepped by the seed's own
//! interpolators, checked against the seed's tables and against the exact step generator.

mod common;

use common::oficina;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn sample(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../samples/legacy-2006")
        .join(name)
        .display()
        .to_string()
}

/// Runs `plan` on a legacy-2006 program and returns the rows of its step file.
fn steps(program: &str, machine: &str, extra: &[&str], dir: &Path) -> Vec<(String, f64, i64)> {
    let out: PathBuf = dir.join(format!("steps{}.csv", extra.len()));
    let path = out.display().to_string();
    let mut args = vec![
        "plan",
        program,
        "--machine",
        machine,
        "--dialect",
        "legacy-2006",
        "--steps",
        &path,
    ];
    args.extend_from_slice(extra);
    let o = oficina(&args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    text.lines()
        .skip(1)
        .map(|row| {
            let f: Vec<&str> = row.split(',').collect();
            let dir = if f[2] == "+" { 1 } else { -1 };
            (f[0].to_string(), f[1].parse().unwrap(), dir)
        })
        .collect()
}

/// Per motor: (steps taken, net displacement in steps).
fn tally(rows: &[(String, f64, i64)]) -> BTreeMap<String, (i64, i64)> {
    let mut t = BTreeMap::new();
    for (motor, _, dir) in rows {
        let e = t.entry(motor.clone()).or_insert((0, 0));
        e.0 += 1;
        e.1 += dir;
    }
    t
}

#[test]
fn test1_program1_steps_every_motor_exactly_its_travel() {
    let dir = tempfile::tempdir().unwrap();
    let program = sample("table15-test1-program1.nc");
    let dda = tally(&steps(
        &program,
        "hotwire-xy",
        &["--interpolator", "dda"],
        dir.path(),
    ));
    let exact = tally(&steps(&program, "hotwire-xy", &[], dir.path()));

    // Independent reading of Table 15's program 1: its vertices in mm. Every piece (line or
    // quarter arc between two axes) moves each coordinate one way only, so a motor takes
    // |Δ| × 100 steps per piece, plus hotwire-xy's backlash (0.1 mm = 10 steps) per reversal.
    let vertices = [
        (0, 0),
        (0, -80),
        (-80, 0),
        (-160, 0),
        (0, 160),
        (0, 80),
        (80, 0),
        (160, 0),
        (0, -160),
        (0, -80),
    ];
    for (axis, name) in ["x", "y"].iter().enumerate() {
        let deltas: Vec<i64> = vertices
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                if axis == 0 {
                    b.0 - a.0
                } else {
                    b.1 - a.1
                }
            })
            .filter(|&d| d != 0)
            .collect();
        let reversals = deltas
            .windows(2)
            .filter(|w| w[0].signum() != w[1].signum())
            .count() as i64;
        let travel: i64 = deltas.iter().map(|d| d.abs() * 100).sum();
        let expected = travel + 10 * reversals;
        assert_eq!(dda[*name].0, expected, "{name}: DDA steps");
        assert_eq!(exact[*name].0, expected, "{name}: exact steps");
        assert_eq!(dda[*name].1, exact[*name].1, "{name}: net displacement");
    }
}

/// Seed 002's resolution (1 mm per pulse) and one feed for G0 and G90 moves, so every DDA
/// iteration is one second and a step's time names its iteration.
const ONE_MM_PER_PULSE: &str = r#"
name = "seed 002 worked examples, 1 mm/pulse"
[kinematics]
type = "cartesian"
[travel]
x = [0.0, 50.0]
y = [0.0, 50.0]
start = [0.0, 0.0, 0.0]
[planner]
junction_deviation = 0.02
arc_tolerance = 0.005
velocity_profile = "trapezoid"
horizon = 2.0
max_step_rate = 1000
default_feed = 60
[joints.x]
steps_per_unit = 1.0
max_rate = 60.0
acceleration = 50.0
[joints.y]
steps_per_unit = 1.0
max_rate = 60.0
acceleration = 50.0
"#;

/// The iterations (1-based, within one move) at which `motor` steps, for the move whose
/// first iteration is slot `first` and which lasts `count` slots.
fn iterations(rows: &[(String, f64, i64)], motor: &str, first: i64, count: i64) -> Vec<(i64, i64)> {
    rows.iter()
        .filter(|(m, _, _)| m == motor)
        .map(|(_, t, dir)| (t.round() as i64 - first + 1, *dir))
        .filter(|&(i, _)| (1..=count).contains(&i))
        .collect()
}

#[test]
fn table7_triangle_steps_in_the_order_of_tables_8_and_9() {
    let dir = tempfile::tempdir().unwrap();
    let profile = dir.path().join("seed002.toml");
    std::fs::write(&profile, ONE_MM_PER_PULSE).unwrap();
    let profile = profile.display().to_string();
    let dda = ["--interpolator", "dda"];
    for name in [
        "table7-triangle-absolute.nc",
        "table7-triangle-incremental.nc",
    ] {
        let rows = steps(&sample(name), &profile, &dda, dir.path());
        // Every step starts an iteration of one second: times are whole seconds.
        assert!(rows.iter().all(|(_, t, _)| (t - t.round()).abs() < 1e-9));
        // G0 to X15 Y10: ⌊√(15² + 10²)⌋ = 18 iterations (slots 0–17).
        assert_eq!(iterations(&rows, "x", 0, 18).len(), 15, "{name}");
        assert_eq!(iterations(&rows, "y", 0, 18).len(), 10, "{name}");
        // Table 8, X15 Y10 → X35: 20 iterations, X steps in every one, Y never.
        let x: Vec<i64> = iterations(&rows, "x", 18, 20).iter().map(|s| s.0).collect();
        assert_eq!(x, (1..=20).collect::<Vec<_>>(), "{name}: table 8");
        assert!(iterations(&rows, "y", 18, 20).is_empty(), "{name}: table 8");
        // Table 9, X35 Y10 → X25 Y17: limit 12; X (−) at 1–4, 6–10, 12; Y (+) at 1, 3, 5, 6, 8,
        // 10, 12. The way back to X15 Y10 is the same pattern with Y negative.
        let table9_x = [1, 2, 3, 4, 6, 7, 8, 9, 10, 12];
        let table9_y = [1, 3, 5, 6, 8, 10, 12];
        for (first, y_dir) in [(38, 1), (50, -1)] {
            let x = iterations(&rows, "x", first, 12);
            let y = iterations(&rows, "y", first, 12);
            assert_eq!(x, table9_x.map(|i| (i, -1)).to_vec(), "{name}: table 9 X");
            assert_eq!(
                y,
                table9_y.map(|i| (i, y_dir)).to_vec(),
                "{name}: table 9 Y"
            );
        }
        assert_eq!(
            rows.len(),
            15 + 10 + 20 + 2 * (10 + 7),
            "{name}: no other steps"
        );
    }
}

#[test]
fn dda_refuses_what_it_cannot_interpolate() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("z.nc");
    std::fs::write(&program, "G21 G90\nG1 X10 Y10 F300\nG1 Z-1\n").unwrap();
    let program = program.display().to_string();
    // A polar machine: its motors are not X and Y.
    let o = oficina(&[
        "plan",
        &program,
        "--machine",
        "polar-plotter",
        "--interpolator",
        "dda",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("cartesian") && err.contains("polar"), "{err}");
    // The hot-wire table has no Z: line 3 is refused by name.
    let o = oficina(&[
        "plan",
        &program,
        "--machine",
        "hotwire-xy",
        "--interpolator",
        "dda",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("line 3") && err.contains('Z'), "{err}");
    // A helix on a 3-axis router: the circular DDA is planar.
    let helix = dir.path().join("helix.nc");
    std::fs::write(
        &helix,
        "G21 G90\nG0 X20 Y20 Z-10\nG2 X30 Y20 Z-12 I5 J0 F300\n",
    )
    .unwrap();
    let o = oficina(&[
        "plan",
        &helix.display().to_string(),
        "--interpolator",
        "dda",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("line 3") && err.contains("helix"), "{err}");
}
