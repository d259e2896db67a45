//! Offsets against the peers: shapely (GEOS) and pyclipper (Clipper 1) offset the same rings
//! with round joins, and the areas must agree within 0.1 %, for single offsets (in and out,
//! with a hole) and for chained insets (each made from the last, as pockets are).
//! Skipped with a note when python3 lacks shapely or pyclipper (scripts/install-deps installs
//! them); OFICINA_REQUIRE_PEERS=1 makes that a failure.

use oficina_geom::{offset_regions, offset_steps, Join, Region};
use std::f64::consts::TAU;
use std::process::Command;

const PEER: &str = r#"
import sys, json, math
from shapely.geometry import Polygon
import pyclipper
cases = json.load(open(sys.argv[1]))
out = []
for c in cases:
    outer, holes, d, n, tol = c["outer"], c["holes"], c["distance"], c["count"], c["tolerance"]
    # Segments per quarter circle so chords stay within tol of the arc of radius |d|.
    q = max(1, math.ceil((math.pi / 2) / math.sqrt(8 * tol / abs(d))))
    poly = Polygon(outer, holes)
    s = 1e3
    sol = [[(round(x * s), round(y * s)) for x, y in r] for r in [outer] + holes]
    sh, pc = [], []
    for k in range(n):
        poly = poly.buffer(d, quad_segs=q)
        sh.append(poly.area)
        o = pyclipper.PyclipperOffset(2.0, tol * s)
        o.AddPaths(sol, pyclipper.JT_ROUND, pyclipper.ET_CLOSEDPOLYGON)
        sol = o.Execute(d * s)
        pc.append(sum(pyclipper.Area(p) for p in sol) / (s * s))
    out.append({"shapely": sh, "pyclipper": pc})
print(json.dumps(out))
"#;

struct Case {
    name: &'static str,
    region: Region,
    distance: f64,
    count: usize,
    /// Chord tolerance of the round joins, mm (all three libraries).
    tolerance: f64,
}

fn wavy(n: usize, r0: f64, waves: &[(f64, f64)]) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let t = TAU * i as f64 / n as f64;
            let r = r0 + waves.iter().map(|(a, k)| a * (k * t).sin()).sum::<f64>();
            [r * t.cos(), r * t.sin()]
        })
        .collect()
}

fn cases() -> Vec<Case> {
    let bumpy = wavy(4000, 100.0, &[(8.0, 7.0), (3.0, 31.0)]);
    // A star: sharp convex and reflex corners.
    let star: Vec<[f64; 2]> = (0..10)
        .map(|i| {
            let t = TAU * i as f64 / 10.0;
            let r = if i % 2 == 0 { 50.0 } else { 22.0 };
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    // A notched plate (outer counter-clockwise) with a square hole (clockwise).
    let plate = Region {
        outer: vec![
            [0.0, 0.0],
            [80.0, 0.0],
            [80.0, 50.0],
            [45.0, 50.0],
            [45.0, 30.0],
            [35.0, 30.0],
            [35.0, 50.0],
            [0.0, 50.0],
        ],
        holes: vec![vec![[10.0, 10.0], [10.0, 25.0], [25.0, 25.0], [25.0, 10.0]]],
    };
    let region = |outer: &Vec<[f64; 2]>| Region {
        outer: outer.clone(),
        holes: vec![],
    };
    vec![
        Case {
            name: "bumpy inset 1.5 × 40 (chained)",
            region: region(&bumpy),
            distance: -1.5,
            count: 40,
            // The bench's tolerance: coarse chords are where a bias in the chained insets
            // shows (plain Douglas–Peucker thinning: +0.3 % by the 40th).
            tolerance: 0.01,
        },
        Case {
            name: "bumpy outset 4",
            region: region(&bumpy),
            distance: 4.0,
            count: 1,
            tolerance: 0.001,
        },
        Case {
            name: "star inset 2 × 6 (chained)",
            region: region(&star),
            distance: -2.0,
            count: 6,
            tolerance: 0.001,
        },
        Case {
            name: "star outset 5",
            region: region(&star),
            distance: 5.0,
            count: 1,
            tolerance: 0.001,
        },
        Case {
            name: "plate with hole inset 1 × 4 (chained)",
            region: plate.clone(),
            distance: -1.0,
            count: 4,
            tolerance: 0.001,
        },
        Case {
            name: "plate with hole outset 2",
            region: plate,
            distance: 2.0,
            count: 1,
            tolerance: 0.001,
        },
    ]
}

fn ring_json(r: &[[f64; 2]]) -> String {
    let pts: Vec<String> = r.iter().map(|p| format!("[{},{}]", p[0], p[1])).collect();
    format!("[{}]", pts.join(","))
}

/// The peers' areas per case and step, or None when they are not installed.
fn peer_areas(cases: &[Case]) -> Option<Vec<(Vec<f64>, Vec<f64>)>> {
    let ok = Command::new("python3")
        .args(["-c", "import shapely, pyclipper"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !ok {
        assert!(
            std::env::var_os("OFICINA_REQUIRE_PEERS").is_none(),
            "python3 with shapely and pyclipper is required"
        );
        eprintln!("skipped: python3 -c 'import shapely, pyclipper' failed (scripts/install-deps)");
        return None;
    }
    let json: Vec<String> = cases
        .iter()
        .map(|c| {
            let holes: Vec<String> = c.region.holes.iter().map(|h| ring_json(h)).collect();
            format!(
                "{{\"outer\":{},\"holes\":[{}],\"distance\":{},\"count\":{},\"tolerance\":{}}}",
                ring_json(&c.region.outer),
                holes.join(","),
                c.distance,
                c.count,
                c.tolerance
            )
        })
        .collect();
    let file =
        std::env::temp_dir().join(format!("oficina-offset-peers-{}.json", std::process::id()));
    std::fs::write(&file, format!("[{}]", json.join(","))).unwrap();
    let out = Command::new("python3")
        .arg("-c")
        .arg(PEER)
        .arg(&file)
        .output()
        .unwrap();
    std::fs::remove_file(&file).ok();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Parse [{"shapely": [..], "pyclipper": [..]}, ...] by its lists of numbers.
    let text = String::from_utf8(out.stdout).unwrap();
    let lists: Vec<Vec<f64>> = text
        .split('[')
        .filter_map(|s| s.split(']').next())
        .filter(|s| !s.trim().is_empty() && !s.contains('{'))
        .map(|s| s.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect();
    assert_eq!(lists.len(), 2 * cases.len(), "{text}");
    Some(
        lists
            .chunks(2)
            .map(|p| (p[0].clone(), p[1].clone()))
            .collect(),
    )
}

fn area(regions: &[Region]) -> f64 {
    regions.iter().map(Region::area).sum()
}

#[test]
fn offset_areas_agree_with_shapely_and_pyclipper_within_a_thousandth() {
    let cases = cases();
    let Some(peers) = peer_areas(&cases) else {
        return;
    };
    for (c, (shapely, pyclipper)) in cases.iter().zip(&peers) {
        let ours: Vec<f64> = if c.count == 1 {
            vec![area(
                &offset_regions(
                    std::slice::from_ref(&c.region),
                    c.distance,
                    Join::Round {
                        tolerance: c.tolerance,
                    },
                )
                .unwrap(),
            )]
        } else {
            offset_steps(
                std::slice::from_ref(&c.region),
                c.distance,
                c.distance,
                c.count,
                c.tolerance,
            )
            .unwrap()
            .iter()
            .map(|s| area(s))
            .collect()
        };
        assert_eq!(ours.len(), c.count, "{}: steps", c.name);
        for (k, a) in ours.iter().enumerate() {
            for (peer, b) in [("shapely", shapely[k]), ("pyclipper", pyclipper[k])] {
                let diff = (a - b).abs() / b;
                assert!(
                    diff <= 1e-3,
                    "{} step {}: ours {a:.4} mm², {peer} {b:.4} mm² ({:.4} %)",
                    c.name,
                    k + 1,
                    diff * 100.0
                );
            }
        }
    }
}
