//! `bench cam`'s workload: successive inward offsets of a generated wavy contour (Oficina
//! and, through python3, shapely and pyclipper on the same contour), and pocket toolpaths for
//! a generated DXF of many shapes.

use super::{failed, BenchError};
use oficina_cam::ops::{pocket, Cut, Entry, PocketParams, Strategy};
use oficina_geom::{offset_steps, Region};
use std::f64::consts::TAU;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// A wavy closed contour of radius about 100 mm: r(θ) = 100 + 8 sin 7θ + 3 sin 31θ, which has
/// concave stretches (round joins) and, deep inside, splits into several regions.
pub fn contour(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let t = TAU * i as f64 / n as f64;
            let r = 100.0 + 8.0 * (7.0 * t).sin() + 3.0 * (31.0 * t).sin();
            [r * t.cos(), r * t.sin()]
        })
        .collect()
}

const PEER: &str = r#"
import sys, time, resource, json
pts = [tuple(map(float, l.split())) for l in open(sys.argv[1])]
which, n, step, tol = sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
t0, c0 = time.perf_counter(), time.process_time()
areas = []
if which == "shapely":
    from shapely.geometry import Polygon
    import math
    poly = Polygon(pts)
    # Segments per quarter circle so chords stay within tol on the step's radius.
    q = max(1, math.ceil((math.pi / 2) / math.sqrt(8 * tol / step)))
    for k in range(1, n + 1):
        poly = poly.buffer(-step, quad_segs=q)
        areas.append(poly.area)
else:
    import pyclipper
    s = 1000.0
    sol = [[(int(round(x * s)), int(round(y * s))) for x, y in pts]]
    for k in range(1, n + 1):
        o = pyclipper.PyclipperOffset(2.0, tol * s)
        o.AddPaths(sol, pyclipper.JT_ROUND, pyclipper.ET_CLOSEDPOLYGON)
        sol = o.Execute(-step * s)
        areas.append(sum(pyclipper.Area(p) for p in sol) / (s * s))
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
print(json.dumps({"wall": wall, "cpu": cpu, "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, "areas": areas}))
"#;

/// A peer's run: its own wall and CPU seconds, peak memory and the area of every inset.
pub struct Peer {
    /// Wall seconds.
    pub wall: f64,
    /// CPU seconds.
    pub cpu: f64,
    /// Peak resident memory, MB.
    pub rss_mb: f64,
    /// The area of every inset, mm².
    pub areas: Vec<f64>,
}

/// Runs `which` ("shapely" or "pyclipper") through python3 on the contour in `file` (one
/// `x y` a line): `offsets` insets of `step` mm, each from the last, chords within `tolerance`.
pub fn run_peer(
    which: &str,
    file: &Path,
    offsets: usize,
    step: f64,
    tolerance: f64,
) -> Result<Peer, BenchError> {
    let out = Command::new("python3")
        .arg("-c")
        .arg(PEER)
        .arg(file)
        .arg(which)
        .arg(offsets.to_string())
        .arg(step.to_string())
        .arg(tolerance.to_string())
        .output()
        .map_err(|e| failed(format!("python3: {e}")))?;
    if !out.status.success() {
        return Err(failed(format!(
            "{which}: {} (pip install shapely pyclipper)",
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // A tiny reader for the one JSON object the script prints.
    let field = |name: &str| -> Option<&str> {
        let k = text.find(&format!("\"{name}\": "))? + name.len() + 4;
        Some(&text[k..])
    };
    let num = |name: &str| -> f64 {
        field(name)
            .and_then(|s| s.split([',', '}']).next())
            .and_then(|s| s.trim().parse().ok())
            .unwrap_or(f64::NAN)
    };
    let areas = field("areas")
        .and_then(|s| s.strip_prefix('['))
        .and_then(|s| s.split(']').next())
        .map(|s| s.split(',').filter_map(|v| v.trim().parse().ok()).collect())
        .unwrap_or_default();
    Ok(Peer {
        wall: num("wall"),
        cpu: num("cpu"),
        rss_mb: num("rss_mb"),
        areas,
    })
}

/// A DXF of `n` shapes on a grid: circles and rounded-corner-free rectangles, alternating.
pub fn shapes_dxf(n: usize) -> String {
    let mut s = String::from(
        "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n",
    );
    let cols = (n as f64).sqrt().ceil() as usize;
    for i in 0..n {
        let (cx, cy) = ((i % cols) as f64 * 25.0, (i / cols) as f64 * 25.0);
        if i % 2 == 0 {
            s.push_str(&format!(
                "0\nCIRCLE\n8\n0\n10\n{cx}\n20\n{cy}\n30\n0\n40\n{}\n",
                6.0 + (i % 5) as f64
            ));
        } else {
            let (w, h) = (12.0 + (i % 7) as f64, 10.0 + (i % 3) as f64 * 2.0);
            s.push_str("0\nLWPOLYLINE\n8\n0\n90\n4\n70\n1\n");
            for (x, y) in [
                (cx - w / 2.0, cy - h / 2.0),
                (cx + w / 2.0, cy - h / 2.0),
                (cx + w / 2.0, cy + h / 2.0),
                (cx - w / 2.0, cy + h / 2.0),
            ] {
                s.push_str(&format!("10\n{x}\n20\n{y}\n"));
            }
        }
    }
    s.push_str("0\nENDSEC\n0\nEOF\n");
    s
}

/// Oficina's insets: each made from the one before (`offset_steps`), as the peers do. The
/// area of each of `offsets` steps (0 past the last non-empty one, as the peers report) and
/// the number of regions in all.
pub fn our_offsets(
    pts: &[[f64; 2]],
    offsets: usize,
    step: f64,
    tolerance: f64,
) -> Result<(Vec<f64>, usize), BenchError> {
    let region = Region {
        outer: pts.to_vec(),
        holes: vec![],
    };
    let steps = offset_steps(
        std::slice::from_ref(&region),
        -step,
        -step,
        offsets,
        tolerance,
    )
    .map_err(failed)?;
    let regions = steps.iter().map(Vec::len).sum();
    let mut areas: Vec<f64> = steps
        .iter()
        .map(|r| r.iter().map(Region::area).sum::<f64>())
        .collect();
    areas.resize(offsets, 0.0);
    Ok((areas, regions))
}

/// Relative difference (a − b) / b; NaN where b is not positive.
pub fn relative_diff(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        (a - b) / b
    } else {
        f64::NAN
    }
}

/// The pocketing run: paths imported, moves made, and the import's wall seconds.
pub struct Pocketed {
    /// Paths imported.
    pub paths: usize,
    /// Moves made.
    pub moves: usize,
    /// Wall seconds of the import.
    pub import_seconds: f64,
}

/// Imports the DXF at `dxf` and pockets every shape with a 3 mm flat end mill, 3 mm deep in
/// one pass, offsets from the centre out.
pub fn pocket_shapes(dxf: &Path) -> Result<Pocketed, BenchError> {
    let t0 = Instant::now();
    let imported = oficina_io::load_drawing(dxf).map_err(failed)?;
    let paths: Vec<oficina_geom::Path> = imported.drawing.paths().cloned().collect();
    let import_seconds = t0.elapsed().as_secs_f64();
    let cut = Cut {
        tool_number: 1,
        tool: "flat:3".parse().map_err(failed)?,
        spindle_rpm: 12000.0,
        feed: 10.0,
        plunge_feed: 5.0,
        top: 0.0,
        depth: 3.0,
        stepdown: 3.0,
        clear_z: 3.0,
        entry: Entry::Ramp { angle: 3.0 },
    };
    let op = pocket(
        "bench",
        &paths,
        &cut,
        &PocketParams::for_tool(Strategy::Offset, 3.0),
    )
    .map_err(failed)?;
    Ok(Pocketed {
        paths: paths.len(),
        moves: op.moves.len(),
        import_seconds,
    })
}
