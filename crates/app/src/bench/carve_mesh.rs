//! `bench carve --mesh`'s workload: our drop-cutter beside OpenCAMLib's `BatchDropCutter`
//! on the same mesh, tool and points (a square grid over the model's box grown by the tool
//! radius), with the largest difference between the two sets of tip heights.

use super::{failed, measure, BenchError, Cost};
use oficina_cam::mesh::DropCutter;
use oficina_cam::{CutterShape, Tool};
use oficina_io::Mesh;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Most grid points the bench drops at (16 bytes each here, more in the peer's Python).
pub const MAX_POINTS: usize = 20_000_000;

/// The points of a square grid `step` mm apart over the model's box grown by `reach`,
/// half a step in from its corner: a point exactly `reach` from a face of the box (a ball
/// tangent to a vertical wall all the way up) has any height between the wall's foot and
/// top within rounding, for both programs alike.
pub fn grid_points(mesh: &Mesh, reach: f64, step: f64) -> Result<Vec<[f64; 2]>, BenchError> {
    if !(step.is_finite() && step > 0.0) {
        return Err(failed(format!("--grid-step {step}: must be above 0 mm")));
    }
    let [lo, hi] = mesh.bounds();
    let n = |k: usize| ((hi[k] - lo[k] + 2.0 * reach) / step).floor() as usize;
    let (nx, ny) = (n(0), n(1));
    if nx.saturating_mul(ny) > MAX_POINTS {
        return Err(BenchError::OverMemory(format!(
            "a {nx} x {ny} grid of points (at most {MAX_POINTS})"
        )));
    }
    Ok((0..ny)
        .flat_map(|iy| {
            (0..nx).map(move |ix| {
                [
                    lo[0] - reach + (ix as f64 + 0.5) * step,
                    lo[1] - reach + (iy as f64 + 0.5) * step,
                ]
            })
        })
        .collect())
}

/// The peer script's name for `tool` and its two numbers (see `ocl_drop.py`); OpenCAMLib's
/// tapered ball ends in a cone of its own, so that shape has no peer here.
pub fn peer_cutter(tool: &Tool) -> Result<(&'static str, f64, f64), BenchError> {
    let d = tool.diameter;
    Ok(match tool.shape {
        CutterShape::Ball => ("ball", d, 0.0),
        CutterShape::Flat => ("flat", d, 0.0),
        CutterShape::Bull { corner_radius } => ("bull", d, corner_radius),
        CutterShape::V { angle } => ("v", d, angle),
        CutterShape::Taper { .. } => {
            return Err(failed(
                "the tapered ball has no OpenCAMLib twin in the bench (the test compares it)",
            ))
        }
    })
}

/// The driver script: `given`, else the repository's `crates/cam/tests/peer/ocl_drop.py`.
pub fn peer_script(given: Option<&Path>) -> PathBuf {
    super::repo_file(given, "crates/cam/tests/peer/ocl_drop.py")
}

/// Our drop: the buckets and every point, on all cores.
pub struct OursDrop {
    /// Building the buckets and dropping.
    pub cost: Cost,
    /// Tip heights, `None` out of reach.
    pub z: Vec<Option<f64>>,
}

/// Drops `tool` on `mesh` at every point, timing the buckets and the drops together.
pub fn drop_ours(mesh: &Mesh, tool: &Tool, points: &[[f64; 2]]) -> OursDrop {
    let (z, cost) = measure(|| DropCutter::new(mesh, tool).drop_all(points));
    OursDrop { cost, z }
}

/// OpenCAMLib's run, as its script reports it.
pub struct PeerDrop {
    /// Building its kd-tree and dropping.
    pub cost: Cost,
    /// Its process's peak resident memory, kB.
    pub peak_kb: u64,
    /// Its peak before reading the mesh (Python and OpenCAMLib loaded), kB.
    pub base_kb: u64,
    /// Tip heights, `None` out of reach.
    pub z: Vec<Option<f64>>,
}

/// Runs OpenCAMLib through `python` and `script` on the mesh file at `path`.
pub fn drop_peer(
    python: &Path,
    script: &Path,
    path: &Path,
    cutter: (&str, f64, f64),
    points: &[[f64; 2]],
) -> Result<PeerDrop, BenchError> {
    let mut child = Command::new(python)
        .arg(script)
        .arg(path)
        .args([
            cutter.0.to_string(),
            cutter.1.to_string(),
            cutter.2.to_string(),
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| super::cannot_run(python, script, e))?;
    let mut input = String::with_capacity(points.len() * 24);
    for p in points {
        input.push_str(&format!("{:?} {:?}\n", p[0], p[1]));
    }
    // Written from a thread: the peer answers only after reading every point, and its
    // answer would fill the pipe while we still wrote.
    let mut stdin = child.stdin.take().ok_or_else(|| failed("no stdin"))?;
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().map_err(failed)?;
    let written = writer
        .join()
        .map_err(|_| failed("the writer thread panicked"))?;
    let err = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(failed(format!("OpenCAMLib failed: {err}")));
    }
    written.map_err(|e| failed(format!("writing points to OpenCAMLib: {e}")))?;
    let last = err.lines().last().unwrap_or("");
    let field = |key: &str| -> Result<f64, BenchError> {
        let mut words = last.split_whitespace();
        words
            .position(|w| w == key)
            .and_then(|_| words.next())
            .and_then(|v| v.parse().ok())
            .ok_or_else(|| failed(format!("OpenCAMLib's script printed no {key}: {err}")))
    };
    let z: Vec<Option<f64>> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.trim().parse().ok())
        .collect();
    if z.len() != points.len() {
        return Err(failed(format!(
            "OpenCAMLib gave {} heights for {} points",
            z.len(),
            points.len()
        )));
    }
    Ok(PeerDrop {
        cost: Cost {
            wall: field("seconds")?,
            cpu: field("cpu")?,
        },
        peak_kb: field("peak_kb")? as u64,
        base_kb: field("base_kb")? as u64,
        z,
    })
}

/// How two sets of tip heights differ.
#[derive(Debug, Default)]
pub struct Agreement {
    /// Largest |Δz| where both touch, mm.
    pub max_dz: f64,
    /// Where it is.
    pub at: [f64; 2],
    /// Points where both touch.
    pub both: usize,
    /// Points where one touches and the other does not (the rim of the reach).
    pub one_only: usize,
    /// Points with |Δz| above 0.001 mm.
    pub over_micron: usize,
}

/// Compares `ours` and `peer` at `points`.
pub fn agreement(points: &[[f64; 2]], ours: &[Option<f64>], peer: &[Option<f64>]) -> Agreement {
    let mut a = Agreement::default();
    for ((p, o), q) in points.iter().zip(ours).zip(peer) {
        match (o, q) {
            (Some(o), Some(q)) => {
                a.both += 1;
                let d = (o - q).abs();
                if d > 1e-3 {
                    a.over_micron += 1;
                }
                if d > a.max_dz {
                    a.max_dz = d;
                    a.at = *p;
                }
            }
            (None, None) => {}
            _ => a.one_only += 1,
        }
    }
    a
}
