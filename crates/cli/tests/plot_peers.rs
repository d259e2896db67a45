//! `oficina plot` against its peers on the real plotter files (`realworld/plot-svg`):
//! vpype's reading (every side drawn, curves within tolerance), vpype-occult's hidden-line
//! removal, vpype's multipass, and shapely's areas and clipping for fills and crops. The peer
//! side is `plot_peers.py`, which reads our G-code's pen-down moves.

mod common;
use common::{oficina, text};
use std::path::{Path, PathBuf};
use std::process::Command;

fn data() -> Vec<PathBuf> {
    let Some(dir) = oficina_testkit::realworld("plot-svg") else {
        return Vec::new();
    };
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .collect();
    v.sort();
    v
}

fn has_python(module: &str) -> bool {
    let ok = Command::new("python3")
        .args(["-c", &format!("import {module}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!(
            "python3 module '{module}' is not installed (pip install it): comparison not run"
        );
    }
    ok
}

/// A file name of its own (the tests run side by side in one process).
fn tmp(name: &str) -> String {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    std::env::temp_dir()
        .join(format!("oficina-peers-{}-{n}-{name}", std::process::id()))
        .display()
        .to_string()
}

/// Plots `file` on the A3 plotter, laid out on landscape A3 at its size (as the peer's
/// `layout --landscape a3`), one pen per layer (vpype's layers); returns the G-code's path.
fn plot(file: &Path, name: &str, extra: &[&str]) -> String {
    let out = tmp(name);
    let f = file.to_str().unwrap();
    let mut args = vec![
        "plot",
        f,
        "--layout",
        "a3",
        "--landscape",
        "--no-fit",
        "--pens",
        "layer",
        "-o",
        &out,
    ];
    args.extend_from_slice(extra);
    let o = oficina(&args);
    let (so, se) = text(&o);
    assert!(o.status.success(), "{f} {extra:?}\n{so}\n{se}");
    out
}

/// Runs the peer script; its JSON answer.
fn peer(args: &[&str]) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/plot_peers.py");
    let o = Command::new("python3")
        .arg(script)
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

fn num(v: &serde_json::Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("no {k} in {v}"))
}

/// Our drawing and vpype's after `pipeline`: pen-down lengths within `rel`, and every drawn
/// point within `dist` mm of the other's lines, both ways.
fn like_vpype(file: &Path, extra: &[&str], pipeline: &str, rel: f64, dist: f64) {
    let g = plot(file, "geom.nc", extra);
    let v = peer(&["geom", &g, file.to_str().unwrap(), pipeline]);
    let (ours, theirs) = (num(&v, "ours"), num(&v, "vpype"));
    eprintln!("{} {extra:?} / vpype {pipeline:?}: {v}", file.display());
    assert!(
        (ours / theirs - 1.0).abs() <= rel,
        "{} {extra:?}: pen-down {ours:.2} mm, vpype's {theirs:.2} mm",
        file.display()
    );
    for k in ["ours_to_vpype", "vpype_to_ours"] {
        assert!(num(&v, k) <= dist, "{} {extra:?}: {k} {v}", file.display());
    }
}

#[test]
fn every_side_drawn_and_curves_within_tolerance_as_vpype_reads_them() {
    if !has_python("vpype_cli") || !has_python("shapely") {
        return;
    }
    // Our chords (0.02 mm) and simplification (0.01 mm) against vpype's lines at 0.005 mm.
    for f in data() {
        like_vpype(&f, &[], "", 0.005, 0.05);
    }
}

#[test]
fn occult_hides_what_vpype_occult_hides() {
    if !has_python("vpype_cli") || !has_python("occult") {
        return;
    }
    for f in data() {
        // vpype keeps no elements: every closed subpath hides what came before it.
        like_vpype(&f, &["--filled", "loops", "--occult"], "occult", 0.01, 0.1);
        like_vpype(
            &f,
            &["--filled", "loops", "--occult-across"],
            "occult -i",
            0.01,
            0.1,
        );
    }
}

#[test]
fn multipass_draws_as_much_as_vpype_multipass_without_lifting() {
    if !has_python("vpype_cli") {
        return;
    }
    for f in data() {
        like_vpype(&f, &["--passes", "3"], "multipass -n 3", 0.005, 0.05);
        // No more pen lifts than with one pass.
        let one = peer(&["strokes", &plot(&f, "one.nc", &[])]);
        let three = peer(&["strokes", &plot(&f, "three.nc", &["--passes", "3"])]);
        assert_eq!(
            one["strokes"].as_array().unwrap().len(),
            three["strokes"].as_array().unwrap().len(),
            "{}",
            f.display()
        );
    }
}

#[test]
fn reloop_starts_each_closed_stroke_at_the_vertex_nearest_the_pen() {
    if !has_python("shapely") {
        return;
    }
    let Some(f) = data()
        .into_iter()
        .find(|f| f.ends_with("axidraw_Tests_for_Hatch_Fill.svg"))
    else {
        return;
    };
    let v = peer(&["strokes", &plot(&f, "reloop.nc", &["--reloop"])]);
    let strokes: Vec<Vec<(f64, f64)>> = serde_json::from_value(v["strokes"].clone()).unwrap();
    let d = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).hypot(a.1 - b.1);
    let mut closed = 0;
    for w in strokes.windows(2) {
        let (prev, s) = (*w[0].last().unwrap(), &w[1]);
        if s.len() > 3 && d(s[0], *s.last().unwrap()) < 1e-3 {
            closed += 1;
            let best = s.iter().map(|&p| d(p, prev)).fold(f64::MAX, f64::min);
            // G-code keeps 3 decimals.
            assert!(d(s[0], prev) <= best + 2e-3, "{s:?} after {prev:?}");
        }
    }
    assert!(closed > 10, "{closed} closed strokes");
}

#[test]
fn fill_hatches_the_area_of_each_shape_holes_left_empty() {
    if !has_python("svgelements") || !has_python("shapely") {
        return;
    }
    let Some(f) = data()
        .into_iter()
        .find(|f| f.ends_with("axidraw_Tests_for_Hatch_Fill.svg"))
    else {
        return;
    };
    let plain = plot(&f, "plain.nc", &[]);
    let s = "0.5";
    for (extra, sets) in [
        (vec!["--fill-angle", "30"], 1.0),
        (vec!["--fill-angle", "-15", "--fill-cross"], 2.0),
    ] {
        let mut a = vec!["--fill", "--filled", "closed", "--fill-spacing", s];
        a.extend(extra.iter().copied());
        let v = peer(&[
            "fill",
            &plot(&f, "fill.nc", &a),
            &plain,
            f.to_str().unwrap(),
        ]);
        // Hatch lines `s` apart cover the area: length ≈ area / s per set of lines.
        let want = num(&v, "area") / 0.5 * sets;
        let got = num(&v, "hatch");
        assert!((got / want - 1.0).abs() < 0.02, "{extra:?}: {v}");
    }
    let v = peer(&[
        "fill",
        &plot(
            &f,
            "conc.nc",
            &["--fill", "--filled", "closed", "--fill-concentric"],
        ),
        &plain,
        f.to_str().unwrap(),
    ]);
    assert!(num(&v, "hatch") > num(&v, "area") * 0.5, "{v}");
}

#[test]
fn fill_rule_of_the_svg_decides_the_holes() {
    // Two nested squares drawn the same way round: even-odd leaves the inner one empty
    // (area 40² − 20² = 1200 mm²), nonzero fills it all (1600 mm²).
    for (rule, area) in [("evenodd", 1200.0), ("nonzero", 1600.0)] {
        let svg = tmp(&format!("{rule}.svg"));
        std::fs::write(
            &svg,
            format!(
                r##"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">
<path fill="#000" fill-rule="{rule}" stroke="none" d="M10 10 H50 V50 H10 Z M20 20 H40 V40 H20 Z"/></svg>"##
            ),
        )
        .unwrap();
        let run = |extra: &[&str]| {
            let out = tmp("rule.nc");
            let mut a = vec!["plot", &svg, "-o", &out];
            a.extend_from_slice(extra);
            let o = oficina(&a);
            let (so, se) = text(&o);
            assert!(o.status.success(), "{so}{se}");
            let l = so.lines().find(|l| l.starts_with("pen-down")).unwrap();
            l.split_whitespace().nth(3).unwrap().parse::<f64>().unwrap()
        };
        let hatch = run(&["--fill", "--fill-spacing", "0.5", "--fill-angle", "0"]) - run(&[]);
        assert!((hatch * 0.5 / area - 1.0).abs() < 0.02, "{rule}: {hatch}");
    }
}

#[test]
fn crop_keeps_what_shapely_keeps_and_nothing_outside() {
    if !has_python("shapely") {
        return;
    }
    let Some(f) = data()
        .into_iter()
        .find(|f| f.ends_with("axidraw_Tests_for_Hatch_Fill.svg"))
    else {
        return;
    };
    let full = plot(&f, "full.nc", &["--no-optimise"]);
    let b = "100,60,260,200";
    let cropped = plot(&f, "crop.nc", &["--no-optimise", "--crop", b]);
    let v = peer(&["clip", &cropped, &full, b]);
    assert!(v["all_inside"].as_bool().unwrap(), "{v}");
    assert!(
        (num(&v, "ours") / num(&v, "shapely") - 1.0).abs() < 1e-3,
        "{v}"
    );
    // The paper: a sheet smaller than the drawing is refused, unless cropped to it.
    let on = |extra: &[&str]| {
        let out = tmp("paper.nc");
        let mut a = vec![
            "plot",
            f.to_str().unwrap(),
            "--paper",
            "100,80",
            "--at",
            "0,0",
        ];
        a.extend_from_slice(&["-o", &out]);
        a.extend_from_slice(extra);
        oficina(&a)
    };
    assert!(!on(&[]).status.success());
    let o = on(&["--crop", "paper"]);
    let (so, se) = text(&o);
    assert!(o.status.success(), "{so}{se}");
    let l = so.lines().find(|l| l.starts_with("drawing: ")).unwrap();
    let n: Vec<f64> = l
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter_map(|t| t.parse().ok())
        .collect();
    assert!(n[0] <= 100.0 + 1e-3 && n[1] <= 80.0 + 1e-3, "{l}");
}

#[test]
fn bad_settings_are_refused_with_a_reason() {
    let Some(f) = data().into_iter().next() else {
        return;
    };
    let f = f.to_str().unwrap();
    for (args, why) in [
        (vec!["--fill", "--fill-spacing", "1e-9"], "at least 0.01 mm"),
        (vec!["--fill", "--fill-spacing", "0"], "--fill-spacing 0"),
        (vec!["--fill", "--fill-angle", "NaN"], "degrees"),
        (vec!["--passes", "0"], "--passes 0"),
        (vec!["--passes", "100000"], "--passes 100000"),
        (vec!["--crop", "1,2,3"], "X0,Y0,X1,Y1"),
        (vec!["--crop", "5,5,1,1"], "X0 < X1"),
        (vec!["--crop", "paper"], "needs a sheet"),
        (vec!["--crop", "-50,-50,-40,-40"], "nothing of the drawing"),
    ] {
        let out = tmp("bad.nc");
        let mut a = vec!["plot", f, "-o", &out];
        a.extend(args.iter().copied());
        let o = oficina(&a);
        let (so, se) = text(&o);
        assert!(!o.status.success(), "{args:?}: {so}");
        assert!(se.contains(why), "{args:?}: {se}");
        assert!(!se.contains("panicked"), "{se}");
    }
}
