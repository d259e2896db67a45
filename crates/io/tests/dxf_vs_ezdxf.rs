//! The DXF reader against ezdxf on real files (`tests/data/dxf/`, SOURCES.md there, and
//! `../shared/data/realworld/mill-dxf-svg/` when present): entity counts per kind, total length
//! of the curves, extents and closed curves, from `scripts/ezdxf_figures.py`. Skips with a note
//! when python3 or ezdxf is missing.

use oficina_io::{read_dxf, DxfOptions, DxfRead};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Kinds both readers count the same way (exploded inserts included).
const COUNTED: &[&str] = &[
    "LINE",
    "ARC",
    "CIRCLE",
    "ELLIPSE",
    "LWPOLYLINE",
    "POLYLINE",
    "SPLINE",
    "HATCH",
    "SOLID",
    "TRACE",
    "3DFACE",
    "POINT",
    "TEXT",
    "MTEXT",
    "ATTRIB",
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn files() -> Vec<PathBuf> {
    let mut dirs = vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dxf")];
    dirs.extend(oficina_testkit::realworld("mill-dxf-svg"));
    let mut out = Vec::new();
    for d in dirs {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("dxf")) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn peer(files: &[PathBuf]) -> Option<Vec<Value>> {
    peer_with(&[], files)
}

fn peer_with(flags: &[&str], files: &[PathBuf]) -> Option<Vec<Value>> {
    let script = root().join("scripts/ezdxf_figures.py");
    let out = Command::new("python3")
        .arg(&script)
        .args(flags)
        .args(files)
        .output();
    match out {
        Ok(o) if o.status.success() => Some(
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .map(|l| serde_json::from_str(l).expect("the script prints JSON lines"))
                .collect(),
        ),
        Ok(o) => {
            eprintln!(
                "note: skipped, ezdxf is not usable: {}",
                String::from_utf8_lossy(&o.stderr)
                    .lines()
                    .last()
                    .unwrap_or("")
            );
            None
        }
        Err(e) => {
            eprintln!("note: skipped, python3 cannot be run: {e}");
            None
        }
    }
}

struct Ours {
    length: f64,
    extents: Option<[f64; 4]>,
    closed: usize,
}

fn ours(r: &DxfRead) -> Ours {
    let paths: Vec<_> = r.imported.drawing.paths().collect();
    let closed = paths
        .iter()
        .filter(|p| {
            p.closed
                || match (p.start(), p.end()) {
                    (Some(a), Some(b)) => a.distance(b) <= 1e-9 * a.to_vec2().hypot().max(1.0),
                    _ => false,
                }
        })
        .count();
    Ours {
        length: paths.iter().map(|p| p.length()).sum(),
        extents: r
            .imported
            .drawing
            .bounding_box()
            .map(|b| [b.x0, b.y0, b.x1, b.y1]),
        closed,
    }
}

#[test]
fn real_files_read_as_ezdxf_reads_them() {
    let files = files();
    assert!(files.len() >= 12, "{files:?}");
    let Some(peer) = peer(&files) else { return };
    let mut bad = Vec::new();
    eprintln!(
        "{:<40} {:>12} {:>12} {:>8} {:>9} {:>11}  kinds",
        "file", "length mm", "ezdxf", "Δ %", "extents Δ", "closed/ez"
    );
    for (path, fig) in files.iter().zip(&peer) {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if let Some(e) = fig.get("error") {
            bad.push(format!("{name}: ezdxf failed: {e}"));
            continue;
        }
        let bytes = std::fs::read(path).unwrap();
        // ezdxf's figures are of the curves: text is not drawn here (its placement is
        // compared below, and its strokes in dxf_text.rs).
        let opts = DxfOptions {
            max_size_mm: f64::INFINITY,
            draw_text: false,
            ..DxfOptions::default()
        };
        let r = match read_dxf(&bytes, &name, &opts) {
            Ok(r) => r,
            Err(e) => {
                bad.push(format!("{name}: {e}"));
                continue;
            }
        };
        let o = ours(&r);
        let f = |k: &str| fig[k].as_f64().unwrap_or(0.0);
        let want_len = f("length") - f("hatch_dup");
        let want_closed = fig["closed"].as_u64().unwrap() as usize
            - fig["hatch_dup_closed"].as_u64().unwrap() as usize;
        let rel = if want_len > 0.0 {
            (o.length - want_len) / want_len * 100.0
        } else {
            o.length
        };
        let ext = match (o.extents, fig["extents"].as_array()) {
            (Some(a), Some(b)) => a
                .iter()
                .zip(b)
                .map(|(x, y)| (x - y.as_f64().unwrap()).abs())
                .fold(0.0, f64::max),
            (None, None) => 0.0,
            _ => f64::INFINITY,
        };
        let mut kinds = Vec::new();
        let counts = fig["counts"].as_object().unwrap();
        for (k, n) in counts {
            let n = n.as_u64().unwrap() as usize;
            let got = r.entities.get(k).copied().unwrap_or(0);
            kinds.push(format!("{k} {got}/{n}"));
            if COUNTED.contains(&k.as_str()) && got != n {
                bad.push(format!("{name}: {k}: {got} read, ezdxf {n}"));
            }
        }
        for (k, got) in &r.entities {
            if !counts.contains_key(k) {
                bad.push(format!("{name}: {k}: {got} read, none in ezdxf"));
            }
        }
        eprintln!(
            "{:<40} {:>12.3} {:>12.3} {:>8.4} {:>9.5} {:>5}/{:<5}  {}",
            name,
            o.length,
            want_len,
            rel,
            ext,
            o.closed,
            want_closed,
            kinds.join(", ")
        );
        if rel.abs() > 0.5 {
            bad.push(format!(
                "{name}: length {:.3} mm, ezdxf {want_len:.3} mm",
                o.length
            ));
        }
        if ext > 0.05 {
            bad.push(format!(
                "{name}: extents {:?}, ezdxf {}",
                o.extents, fig["extents"]
            ));
        }
        if o.closed != want_closed {
            bad.push(format!(
                "{name}: {} closed curves, ezdxf {want_closed}",
                o.closed
            ));
        }
        // Strings of TEXT and ATTRIB where ezdxf places them (MTEXT's attachment is ours).
        let mut texts: Vec<(String, f64, f64, f64)> = r
            .texts
            .iter()
            .filter(|t| !t.source.element.starts_with("MTEXT"))
            .map(|t| (t.text.clone(), t.at.x, t.at.y, t.height))
            .collect();
        texts.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let want: Vec<(String, f64, f64, f64)> = fig["texts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| {
                let f = |i: usize| t[i].as_f64().unwrap();
                (t[0].as_str().unwrap().to_string(), f(1), f(2), f(3))
            })
            .collect();
        let placed = texts.len() == want.len()
            && texts.iter().zip(&want).all(|(a, b)| {
                (a.1 - b.1).abs() < 0.05 && (a.2 - b.2).abs() < 0.05 && (a.3 - b.3).abs() < 0.05
            });
        if !placed {
            bad.push(format!(
                "{name}: texts {:?}…, ezdxf {:?}…",
                &texts[..texts.len().min(3)],
                &want[..want.len().min(3)]
            ));
        }
        // Units as ezdxf reads the header.
        let scale = fig["units"]["mm_per_unit"].as_f64().unwrap();
        if (r.mm_per_unit - scale).abs() > 1e-9 * scale {
            bad.push(format!(
                "{name}: {} mm per unit, ezdxf {scale}",
                r.mm_per_unit
            ));
        }
    }
    assert!(
        bad.is_empty(),
        "{} differences:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

/// Every SPLINE and ELLIPSE within 1 µm of the curve as ezdxf evaluates it (NURBS with its
/// weights, fit points interpolated as CAD programs do, ellipses by their parameters).
#[test]
fn splines_and_ellipses_lie_within_a_micrometre_of_ezdxfs_curves() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dxf");
    let names = [
        "made_by_ezdxf.dxf",
        "camotics_camotics.dxf",
        "camotics_stretching_cat.dxf",
        "ezdxf_no_layouts.dxf",
        "ezdxf_hatches_2.dxf",
        "dxfparser_ellipse.dxf",
    ];
    let files: Vec<PathBuf> = names.iter().map(|n| dir.join(n)).collect();
    let Some(peer) = peer_with(&["--curves"], &files) else {
        return;
    };
    let mut worst_all = 0.0f64;
    let mut checked = 0;
    let mut bad = Vec::new();
    for (path, fig) in files.iter().zip(&peer) {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let r = read_dxf(&std::fs::read(path).unwrap(), &name, &DxfOptions::default()).unwrap();
        let curves = fig["curves"].as_object().expect("curves");
        for (handle, pts) in curves {
            let ours: Vec<_> = r
                .imported
                .drawing
                .paths()
                .filter(|p| {
                    p.source.element == format!("SPLINE #{handle}")
                        || p.source.element == format!("ELLIPSE #{handle}")
                })
                .collect();
            if ours.is_empty() {
                bad.push(format!("{name}: curve #{handle} not read"));
                continue;
            }
            let worst = pts
                .as_array()
                .unwrap()
                .iter()
                .map(|q| {
                    let q =
                        oficina_geom::Point::new(q[0].as_f64().unwrap(), q[1].as_f64().unwrap());
                    ours.iter()
                        .map(|p| p.distance(q))
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0f64, f64::max);
            if worst > 1e-6 {
                eprintln!("{name} #{handle}: {worst:.2e} mm");
            }
            worst_all = worst_all.max(worst);
            checked += 1;
            if worst > 1e-3 {
                bad.push(format!(
                    "{name}: #{handle} is {worst:.6} mm from ezdxf's curve"
                ));
            }
        }
    }
    eprintln!("{checked} splines and ellipses, at most {worst_all:.2e} mm from ezdxf's curves");
    assert!(checked > 300, "{checked}");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
