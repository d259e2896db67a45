//! `oficina fit` on the shipped size-34 sole contour: one row per method, tangent circles
//! and biarcs as arcs only, the polyline methods as lines; bad input named.

use std::process::Command;

fn oficina(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn fit_prints_blocks_and_deviation_per_method() {
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/sole/size34.csv");
    let (ok, out, err) = oficina(&["fit", sample, "--tol", "0.1"]);
    assert!(ok, "{out}{err}");
    assert!(out.starts_with("80 points"), "{out}");
    let row = |name: &str| -> Vec<f64> {
        let line = out
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("{name}: {out}"));
        line[name.len()..]
            .split_whitespace()
            .filter_map(|w| w.parse().ok())
            .collect()
    };
    // control, blocks, arcs, lines, deviation
    let tc = row("tangent circles");
    assert_eq!(tc[1], tc[2], "tangent circles: all arcs");
    assert!(tc[4] < 1.0);
    let bi = row("biarc");
    assert!(bi[4] <= 0.1 && bi[1] == bi[2]);
    let interp = row("interpolation");
    assert_eq!(interp[1], interp[3], "interpolation: all lines");
    assert!(tc[1] < interp[1] && bi[1] < interp[1]);
}

#[test]
fn fit_names_the_bad_line() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bad.csv");
    std::fs::write(&f, "x,y\n1,2\n3,oops\n").unwrap();
    let (ok, _, err) = oficina(&["fit", f.to_str().unwrap()]);
    assert!(!ok);
    assert!(
        err.contains("line 3") && err.contains("'oops' is not a number"),
        "{err}"
    );
}
