//! `oficina bench cam`: (1) 59 successive inward offsets of 1.5 mm (each from the last, as
//! pocket rings are made) of a 10,000-vertex contour,
//! beside shapely (GEOS) and pyclipper (Clipper1) doing the same offsets in the same run, with
//! the areas compared; (2) pocket toolpaths for a DXF of 1,000 shapes. Wall and CPU seconds,
//! peak memory (max RSS) of each process.

use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use oficina_cam::ops::{pocket, Cut, Entry, PocketParams, Strategy};
use oficina_geom::{offset_steps, Region};
use std::f64::consts::TAU;
use std::io::Write;
use std::process::Command;
use std::time::Instant;

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Vertices of the contour.
    #[arg(long, default_value_t = 10_000)]
    pub vertices: usize,
    /// Number of successive offsets.
    #[arg(long, default_value_t = 59)]
    pub offsets: usize,
    #[arg(long, default_value_t = 1.5)]
    pub step: f64,
    /// Shapes in the pocketing DXF.
    #[arg(long, default_value_t = 1000)]
    pub shapes: usize,
    /// Chord tolerance of round joins, mm (all three libraries).
    #[arg(long, default_value_t = 0.01)]
    pub tolerance: f64,
    /// Skip the python peers.
    #[arg(long)]
    pub no_peers: bool,
}

/// A wavy closed contour of radius about 100 mm: r(θ) = 100 + 8 sin 7θ + 3 sin 31θ, which has
/// concave stretches (round joins) and, deep inside, splits into several regions.
fn contour(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let t = TAU * i as f64 / n as f64;
            let r = 100.0 + 8.0 * (7.0 * t).sin() + 3.0 * (31.0 * t).sin();
            [r * t.cos(), r * t.sin()]
        })
        .collect()
}

fn cpu_and_rss() -> (f64, f64) {
    use nix::sys::resource::{getrusage, UsageWho};
    getrusage(UsageWho::RUSAGE_SELF).map_or((0.0, 0.0), |u| {
        let t = |v: nix::sys::time::TimeVal| v.tv_sec() as f64 + v.tv_usec() as f64 * 1e-6;
        (
            t(u.user_time()) + t(u.system_time()),
            u.max_rss() as f64 / 1024.0,
        )
    })
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

struct Peer {
    wall: f64,
    cpu: f64,
    rss_mb: f64,
    areas: Vec<f64>,
}

fn run_peer(which: &str, file: &std::path::Path, args: &Args) -> Result<Peer> {
    let out = Command::new("python3")
        .arg("-c")
        .arg(PEER)
        .arg(file)
        .arg(which)
        .arg(args.offsets.to_string())
        .arg(args.step.to_string())
        .arg(args.tolerance.to_string())
        .output()
        .context("python3")?;
    if !out.status.success() {
        bail!(
            "{which}: {} (pip install shapely pyclipper)",
            String::from_utf8_lossy(&out.stderr).trim()
        );
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
fn shapes_dxf(n: usize) -> String {
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

pub fn run(args: Args) -> Result<()> {
    if args.vertices < 3 || args.vertices > 10_000_000 || args.offsets == 0 || args.offsets > 10_000
    {
        bail!("--vertices 3..=10000000 and --offsets 1..=10000");
    }
    let pts = contour(args.vertices);
    let dir = tempfile::tempdir()?;
    let file = dir.path().join("contour.txt");
    let mut f = std::fs::File::create(&file)?;
    for p in &pts {
        writeln!(f, "{} {}", p[0], p[1])?;
    }
    drop(f);
    println!(
        "1. {} offsets at {} mm steps of a {}-vertex contour, round joins within {} mm; the same \
         operation in each library: every inset made from the last, round joins, chords within \
         the tolerance",
        args.offsets, args.step, args.vertices, args.tolerance
    );
    // Peers first: a child inherits the parent's peak RSS at fork (Linux signal->maxrss), so
    // they run while this process is still small.
    let peers: Vec<(&str, Result<Peer>)> = if args.no_peers {
        vec![]
    } else {
        ["shapely", "pyclipper"]
            .into_iter()
            .map(|w| (w, run_peer(w, &file, &args)))
            .collect()
    };
    let region = Region {
        outer: pts.clone(),
        holes: vec![],
    };
    let (c0, _) = cpu_and_rss();
    let t0 = Instant::now();
    // Each inset made from the one before (`offset_steps`), as the peers do below.
    let steps = offset_steps(
        std::slice::from_ref(&region),
        -args.step,
        -args.step,
        args.offsets,
        args.tolerance,
    )?;
    let regions_total: usize = steps.iter().map(Vec::len).sum();
    let mut ours: Vec<f64> = steps
        .iter()
        .map(|r| r.iter().map(Region::area).sum::<f64>())
        .collect();
    // Offsets past the last non-empty one have no area (the peers report 0 there too).
    ours.resize(args.offsets, 0.0);
    let wall = t0.elapsed().as_secs_f64();
    let (c1, rss) = cpu_and_rss();
    println!(
        "   {:<28} {:>9} {:>9} {:>10} {:>11} {:>11}",
        "library", "wall s", "cpu s", "peak MB", "max diff %", "all diff %"
    );
    println!(
        "   {:<28} {wall:>9.3} {:>9.3} {rss:>10.1} {:>11} {:>11}",
        "oficina (i_overlay)",
        c1 - c0,
        "—",
        "—"
    );
    let ok: Vec<(&str, Peer)> = peers
        .into_iter()
        .filter_map(|(which, peer)| match peer {
            Ok(p) => Some((which, p)),
            Err(e) => {
                println!("   {which}: not run: {e}");
                None
            }
        })
        .collect();
    // Relative area difference per step, |ours − peer| / peer, and over all steps together
    // (the summed areas, i.e. the material the rings enclose in all).
    let rel = |a: f64, b: f64| if b > 0.0 { (a - b) / b } else { f64::NAN };
    let total: f64 = ours.iter().sum();
    for (which, p) in &ok {
        let max = ours
            .iter()
            .zip(&p.areas)
            .map(|(a, b)| rel(*a, *b).abs())
            .fold(0.0f64, f64::max);
        let name = if *which == "shapely" {
            "shapely (GEOS)"
        } else {
            "pyclipper (Clipper 1)"
        };
        println!(
            "   {:<28} {:>9.3} {:>9.3} {:>10.1} {:>11.4} {:>+11.4}",
            name,
            p.wall,
            p.cpu,
            p.rss_mb,
            max * 100.0,
            rel(total, p.areas.iter().sum()) * 100.0
        );
    }
    println!("     ({regions_total} regions in all)");
    if let [(_, a), (_, b)] = &ok[..] {
        // The peers' own disagreement: on the last, tiny insets the chords alone make a few %.
        let max = a
            .areas
            .iter()
            .zip(&b.areas)
            .map(|(x, y)| rel(*x, *y).abs())
            .fold(0.0f64, f64::max);
        println!(
            "     (shapely against pyclipper: max diff {:.4} %, all {:+.4} %)",
            max * 100.0,
            rel(a.areas.iter().sum(), b.areas.iter().sum()) * 100.0
        );
    }
    if !ok.is_empty() {
        print!("   {:>4} {:>12}", "step", "oficina mm²");
        for (which, _) in &ok {
            print!(" {which:>12} {:>9}", "diff %");
        }
        println!();
        for (k, a) in ours.iter().enumerate() {
            print!("   {:>4} {a:>12.3}", k + 1);
            for (_, p) in &ok {
                let b = p.areas.get(k).copied().unwrap_or(f64::NAN);
                print!(" {b:>12.3} {:>+9.4}", rel(*a, b) * 100.0);
            }
            println!();
        }
    }
    println!("2. pocket toolpaths for a DXF of {} shapes (flat:3, 3 mm deep in one pass, offsets from the centre out)", args.shapes);
    let dxf = dir.path().join("shapes.dxf");
    std::fs::write(&dxf, shapes_dxf(args.shapes))?;
    let (c0, _) = cpu_and_rss();
    let t0 = Instant::now();
    let imported = oficina_io::load_drawing(&dxf)?;
    let paths: Vec<oficina_geom::Path> = imported.drawing.paths().cloned().collect();
    let t_import = t0.elapsed().as_secs_f64();
    let cut = Cut {
        tool_number: 1,
        tool: "flat:3".parse()?,
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
    )?;
    let wall = t0.elapsed().as_secs_f64();
    let (c1, rss) = cpu_and_rss();
    println!(
        "   {} paths imported in {t_import:.3} s; {} moves; {wall:.3} s wall, {:.3} s CPU in all; peak {rss:.1} MB",
        paths.len(),
        op.moves.len(),
        c1 - c0
    );
    Ok(())
}
