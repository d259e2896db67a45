//! `oficina plot --layout`: vpype's `layout` as the oracle of where the drawing lands on the
//! page (within 0.1 mm, fitted and not), every real plotter file plotting on the A3 plotter
//! (with `--layout a3` where it is larger), and the travel's edge counted as inside.

mod common;
use common::{oficina, text};
use std::path::PathBuf;
use std::process::Command;

fn data() -> PathBuf {
    oficina_testkit::realworld("plot-svg").unwrap_or_default()
}

/// The shared folder's plot files and the HP-GL files kept beside the reader's tests.
fn files() -> Vec<PathBuf> {
    let kept = common::root().join("crates/io/tests/data/hpgl");
    let mut v: Vec<PathBuf> = [data(), kept]
        .iter()
        .filter_map(|d| std::fs::read_dir(d).ok())
        .flatten()
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| !p.extension().is_some_and(|e| e == "md" || e == "py"))
        .collect();
    v.sort();
    v
}

/// (x0, y0, x1, y1) of "drawing: W x H mm at (X, Y)".
fn drawn(out: &str) -> [f64; 4] {
    let l = out
        .lines()
        .find(|l| l.starts_with("drawing: "))
        .unwrap_or_else(|| panic!("{out}"));
    let nums: Vec<f64> = l
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|t| t.parse().ok())
        .collect();
    let [w, h, x, y] = nums[..] else {
        panic!("{l}")
    };
    [x, y, x + w, y + h]
}

fn out_nc() -> String {
    std::env::temp_dir()
        .join(format!("oficina-layout-{}.nc", std::process::id()))
        .display()
        .to_string()
}

#[test]
fn layout_puts_the_drawing_where_vpype_puts_it() {
    let probe = Command::new("python3")
        .args(["-c", "import vpype_cli"])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("vpype is not installed (pip install vpype): oracle comparison not run");
        return;
    }
    let svgs: Vec<PathBuf> = files()
        .into_iter()
        .filter(|f| f.extension().is_some_and(|e| e == "svg"))
        .collect();
    if svgs.is_empty() {
        eprintln!("{} is absent: oracle comparison not run", data().display());
        return;
    }
    for f in &svgs {
        for (ours, theirs) in [
            (vec!["--margin", "10"], "--fit-to-margins 10mm"),
            (vec!["--no-fit"], ""),
            (vec!["--margin", "25"], "--fit-to-margins 25mm"),
        ] {
            let file = f.display().to_string();
            let nc = out_nc();
            let mut args = vec![
                "plot",
                file.as_str(),
                "--layout",
                "a3",
                "--landscape",
                "-o",
                nc.as_str(),
            ];
            args.extend(ours.iter().copied());
            let o = oficina(&args);
            let (out, err) = text(&o);
            assert!(o.status.success(), "{file} {ours:?}: {err}");
            let b = drawn(&out);
            // vpype's page is y-down: its (y0, y1) are ours mirrored about the page's middle.
            let py = format!(
                "import vpype_cli\nd = vpype_cli.execute('read --no-crop \"{file}\" layout --landscape {theirs} a3')\nb = [v / 96 * 25.4 for v in d.bounds()]\nprint(b[0], 297 - b[3], b[2], 297 - b[1])"
            );
            let v = Command::new("python3").args(["-c", &py]).output().unwrap();
            let vs = String::from_utf8_lossy(&v.stdout);
            let pb: Vec<f64> = vs
                .split_whitespace()
                .filter_map(|t| t.parse().ok())
                .collect();
            assert_eq!(pb.len(), 4, "{}", String::from_utf8_lossy(&v.stderr));
            for k in 0..4 {
                assert!(
                    (b[k] - pb[k]).abs() <= 0.1,
                    "{file} {ours:?}: ours {b:?}, vpype {pb:?}"
                );
            }
        }
    }
}

#[test]
fn every_real_plotter_file_plots_on_the_a3_plotter() {
    let all = files();
    let nc = out_nc();
    let mut laid_out = Vec::new();
    for f in &all {
        let file = f.display().to_string();
        let o = oficina(&["plot", &file, "--machine", "pen-plotter", "-o", &nc]);
        if o.status.success() {
            continue;
        }
        let (_, err) = text(&o);
        assert!(
            err.contains("outside the machine travel") && err.contains("--layout a3"),
            "{file}: {err}"
        );
        let o = oficina(&[
            "plot",
            &file,
            "--machine",
            "pen-plotter",
            "--layout",
            "a3",
            "-o",
            &nc,
        ]);
        let (out, err) = text(&o);
        assert!(o.status.success(), "{file} --layout a3: {err}");
        assert!(err.contains("laid landscape"), "{err}");
        let b = drawn(&out);
        assert!(
            b[0] >= 10.0 - 0.01 && b[1] >= 10.0 - 0.01 && b[2] <= 410.01 && b[3] <= 287.01,
            "{file}: {b:?}"
        );
        laid_out.push(f.file_name().unwrap().to_string_lossy().to_string());
    }
    // Those larger than the plotter's travel or reaching below its edge.
    for name in [
        "hp2xx_arcs.hp",
        "vpype_multilayer_named_layers.svg",
        "ezdxf_hpgl2_ezdxf_forms.plt",
    ] {
        if all.iter().any(|f| f.ends_with(name)) {
            assert!(
                laid_out.iter().any(|n| n == name),
                "{name} plotted without a layout? {laid_out:?}"
            );
        }
    }
}

#[test]
fn a_point_on_the_travel_edge_is_inside_and_written_on_it() {
    // y = −0.016 plotter units = −0.0004 mm: below y = 0 only by rounding.
    let dir = std::env::temp_dir().join(format!("oficina-edge-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("edge.000");
    std::fs::write(&f, "IN;SP1;PU0,-0.016;PD4000,-0.016,4000,4000;PU;").unwrap();
    let nc = dir.join("edge.nc");
    let o = oficina(&[
        "plot",
        f.to_str().unwrap(),
        "--machine",
        "pen-plotter",
        "-o",
        nc.to_str().unwrap(),
    ]);
    let (_, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let prog = std::fs::read_to_string(&nc).unwrap();
    assert!(!prog.contains("Y-"), "{prog}");
    // A millimetre below is outside, and said so.
    std::fs::write(&f, "IN;SP1;PU0,-40;PD4000,-40;PU;").unwrap();
    let o = oficina(&[
        "plot",
        f.to_str().unwrap(),
        "--machine",
        "pen-plotter",
        "-o",
        nc.to_str().unwrap(),
    ]);
    let (_, err) = text(&o);
    assert!(
        !o.status.success() && err.contains("outside the machine travel y"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn layout_refuses_what_it_cannot_do_with_reasons() {
    let dir = std::env::temp_dir().join(format!("oficina-layout-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("big.plt");
    // 500 × 10 mm: larger than an A4 page at its size.
    std::fs::write(&f, "IN;SP1;PU0,0;PD20000,0,20000,400;").unwrap();
    let file = f.to_str().unwrap();
    let nc = dir.join("x.nc");
    let nc = nc.to_str().unwrap();
    for (args, want) in [
        (vec!["--layout", "a9"], "page 'a9'"),
        (vec!["--layout", "10x10furlong"], "unknown unit"),
        (
            vec!["--layout", "a4", "--no-fit"],
            "larger than the 210 × 297 mm page",
        ),
        (vec!["--layout", "a4", "--margin", "200"], "margin 200"),
    ] {
        let mut a = vec!["plot", file, "-o", nc];
        a.extend(args.iter().copied());
        let o = oficina(&a);
        let (_, err) = text(&o);
        assert!(!o.status.success() && err.contains(want), "{args:?}: {err}");
    }
    // Fitted, the same drawing fills the width of a portrait A4 page inside 10 mm margins.
    let o = oficina(&["plot", file, "-o", nc, "--layout", "a4"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    let b = drawn(&out);
    assert!(
        (b[0] - 10.0).abs() < 0.01 && (b[2] - 200.0).abs() < 0.01,
        "{b:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
