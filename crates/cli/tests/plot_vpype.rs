//! vpype as the oracle of path optimisation: on the same generated SVG, `oficina bench plot`
//! must leave no more pen-up travel and no more strokes than vpype's `linemerge linesort`,
//! with the same pen-down length (both outputs measured by the same SVG reader).

use std::process::Command;

fn field(text: &str, row: &str, key: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.starts_with(row))
        .unwrap_or_else(|| panic!("no row '{row}' in\n{text}"));
    let i = line.find(key).unwrap() + key.len();
    line[i..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn pen_up_travel_is_no_worse_than_vpype() {
    if Command::new("vpype").arg("--version").output().is_err() {
        eprintln!("vpype is not installed (pip install vpype): oracle comparison not run");
        return;
    }
    let o = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["bench", "plot", "--paths", "3000"])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{}\n{out}",
        String::from_utf8_lossy(&o.stderr)
    );
    let ours = "oficina optimise";
    let peer = "vpype read linemerge linesort";
    assert!(
        field(&out, ours, "pen-up") <= field(&out, peer, "pen-up"),
        "{out}"
    );
    assert!(
        field(&out, ours, "strokes") <= field(&out, peer, "strokes"),
        "{out}"
    );
    let (a, b) = (field(&out, ours, "pen-down"), field(&out, peer, "pen-down"));
    assert!((a - b).abs() / b < 0.01, "{out}");
    // And far less than the unsorted input.
    assert!(field(&out, ours, "pen-up") < field(&out, "input (as read)", "pen-up") / 10.0);
}
