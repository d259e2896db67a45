//! `oficina run` executes every bundled motion sample on the virtual machine, and
//! `oficina plan --trace` writes one row per millisecond of the total time it prints.

mod common;

use common::root;

use std::process::Command;

const SAMPLES: [(&str, &str); 5] = [
    ("router-square", "grbl-router"),
    ("hotwire-pinwheel", "hotwire-xy"),
    ("polar-shapes", "polar-plotter"),
    ("embroidery-stitches", "embroidery-xy"),
    ("polargraph-star", "polargraph-wall"),
];

#[test]
fn run_executes_every_sample_on_its_machine() {
    for (file, machine) in SAMPLES {
        let path = root().join(format!("samples/motion/{file}.nc"));
        let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
            .args([
                "run",
                path.to_str().unwrap(),
                "--machine",
                machine,
                "--instant",
            ])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && text.contains("done"),
            "{file}: {text} {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn run_refuses_a_job_beyond_the_soft_limits() {
    let dir = oficina_testkit::scratch_dir("motion-run");
    let f = dir.join("far.nc");
    std::fs::write(&f, "G90 G1 X100 F1000\nG1 X900\nM2\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["run", f.to_str().unwrap(), "--instant"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("line 2")
            && err.contains("travel limits")
            && err.contains("nothing was moved"),
        "{err}"
    );
    // The operator reads the program: its own X900 is quoted first, the machine's X (the
    // work offset added: 900 + 100 = 1000) beside it.
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["run", f.to_str().unwrap(), "--instant"])
        .args(["--work-offset", "100,20,-30"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("line 2: X900.0000 of the program is X = 1000.0000 mm on the machine"),
        "{err}"
    );
}

#[test]
fn plan_trace_has_one_row_per_millisecond() {
    let dir = oficina_testkit::scratch_dir("motion-plan");
    let trace = dir.join("t.csv");
    let path = root().join("samples/motion/router-square.nc");
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args([
            "plan",
            path.to_str().unwrap(),
            "--trace",
            trace.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    oficina_testkit::assert_success(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    let total: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("total time: "))
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let csv = std::fs::read_to_string(&trace).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len() as f64, (total * 1000.0).floor() + 1.0);
    let last: Vec<f64> = rows
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!((last[0] - (rows.len() - 1) as f64 / 1000.0).abs() < 1e-9);
}
