//! `oficina plan --steps / --steps-compressed`: the step files against closed forms and
//! against each other.

use std::process::Command;

#[test]
fn step_files_match_the_closed_form_and_each_other() {
    let dir = oficina_testkit::scratch_dir("steps");
    let prog = dir.join("x10.nc");
    // 10 mm along X at 600 mm/min, then back 4 mm: 2000 + 800 steps at 200 steps/mm.
    std::fs::write(&prog, "G21 G90\nG1 X10 F600\nG1 X6\nM2\n").unwrap();
    let (csv, runs) = (dir.join("steps.csv"), dir.join("steps.txt"));
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["plan", prog.to_str().unwrap(), "--machine", "grbl-router"])
        // Machine coordinates: no stored work offset, so G1 X10 is 2000 steps from home.
        .args(["--work-offset", "0,0,0"])
        .args(["--steps", csv.to_str().unwrap()])
        .args(["--steps-compressed", runs.to_str().unwrap()])
        .output()
        .unwrap();
    oficina_testkit::assert_success(&out);
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<(String, f64, bool)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].to_string(), f[1].parse().unwrap(), f[2] == "+")
        })
        .collect();
    let fwd = rows.iter().filter(|r| r.0 == "x" && r.2).count();
    let back = rows.iter().filter(|r| r.0 == "x" && !r.2).count();
    // The reversal adds the backlash (0.05 mm = 10 steps) to the return.
    assert_eq!((fwd, back), (2000, 800 + 10), "{fwd} {back}");
    assert!(rows.iter().all(|r| r.0 == "x"));
    // First step at half a step (0.0025 mm) from rest at 300 mm/s²: t = √(2d/a).
    let want = (2.0 * 0.0025 / 300.0_f64).sqrt();
    assert!((rows[0].1 - want).abs() < 1e-9, "{} vs {want}", rows[0].1);
    // Decoding the queue_step runs gives every step within 25 µs of the CSV time.
    let runs = std::fs::read_to_string(&runs).unwrap();
    let (mut tick, mut decoded) = (0i64, Vec::new());
    for l in runs.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let (mut interval, count, add): (i64, i64, i64) = (
            f[1].parse().unwrap(),
            f[2].parse().unwrap(),
            f[3].parse().unwrap(),
        );
        for _ in 0..count {
            tick += interval;
            decoded.push((tick as f64 / 16e6, f[4] == "+"));
            interval += add;
        }
    }
    assert_eq!(decoded.len(), rows.len());
    for (d, r) in decoded.iter().zip(&rows) {
        assert!(
            (d.0 - r.1).abs() <= 25e-6 + 1e-9 && d.1 == r.2,
            "{d:?} vs {r:?}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
