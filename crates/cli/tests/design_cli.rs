//! `oficina design` and the design file as a drawing: a filleted plate offset inwards by
//! the CLI, then pocketed by `oficina mill` reading the design file; LinuxCNC's rs274 reads
//! the program and its cuts stay where the hand-derived ring between wall and island puts
//! the cutter. A bad file is a message naming the place.

use oficina_testkit::{assert_success, rs274, scratch_dir};
use std::process::Command;

const PLATE: &str = r##"{"format": "oficina-design", "version": 1,
  "layers": [{"name": "0", "color": "#000000"}],
  "entities": [{"id": 1, "layer": "0", "type": "polyline", "closed": true,
    "vertices": [[0, 0], [60, 0], [60, 35, 0.41421356237309503], [55, 40], [0, 40]]}]}"##;

/// `oficina ARGS` (split at spaces) in `dir`.
fn oficina(dir: &std::path::Path, args: &str) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(args.split_whitespace())
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn offset_then_pocket_the_design_file() {
    let dir = scratch_dir("design-cli");
    std::fs::write(dir.join("plate.oficina.json"), PLATE).unwrap();
    let said = assert_success(&oficina(
        &dir,
        "design offset plate.oficina.json --ids 1 --distance -3 -o ring.oficina.json",
    ));
    assert!(said.contains("entity 2 on layer 0"), "{said}");
    assert_success(&oficina(
        &dir,
        "mill ring.oficina.json --op pocket --tool flat:3 --depth 1 -o ring.ngc",
    ));
    let canon = rs274::accepts_file(&dir.join("ring.ngc"), None);
    // The pocket is the ring between the wall and the island 3 mm inside it; a 3 mm cutter
    // fills its width in one lap on its middle line, 1.5 mm from each: the cutter's centre
    // spans x 1.5 … 58.5 and y 1.5 … 38.5.
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for l in canon
        .lines()
        .filter(|l| l.contains("STRAIGHT_FEED(") || l.contains("ARC_FEED("))
    {
        let args: Vec<f64> = l
            .split_once('(')
            .unwrap()
            .1
            .trim_end_matches(')')
            .split(',')
            .map(|v| v.trim().parse().unwrap())
            .collect();
        for i in 0..2 {
            lo[i] = lo[i].min(args[i]);
            hi[i] = hi[i].max(args[i]);
        }
    }
    let want = ([1.5, 1.5], [58.5, 38.5]);
    for i in 0..2 {
        assert!(
            (lo[i] - want.0[i]).abs() < 1e-3 && (hi[i] - want.1[i]).abs() < 1e-3,
            "{lo:?} {hi:?}"
        );
    }
    // Exported as DXF, the CLI's own DXF reader mills the same program.
    assert_success(&oficina(
        &dir,
        "design export ring.oficina.json --dxf ring.dxf",
    ));
    assert_success(&oficina(
        &dir,
        "mill ring.dxf --op pocket --tool flat:3 --depth 1 -o ring-dxf.ngc",
    ));
    let moves = |f: &str| {
        std::fs::read_to_string(dir.join(f))
            .unwrap()
            .lines()
            .filter(|l| l.starts_with("G1") || l.starts_with("G2") || l.starts_with("G3"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(moves("ring.ngc"), moves("ring-dxf.ngc"));
}

#[test]
fn a_bad_design_names_the_place() {
    let dir = scratch_dir("design-cli-bad");
    std::fs::write(
        dir.join("bad.oficina.json"),
        PLATE.replace("\"closed\": true", "\"closed\": 3"),
    )
    .unwrap();
    let out = oficina(
        &dir,
        "mill bad.oficina.json --op pocket --tool flat:3 --depth 1 -o x.ngc",
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.oficina.json") && err.contains("line 4 column"),
        "{err}"
    );
    let out = oficina(&dir, "design offset bad.oficina.json --ids 1 --distance 1");
    assert!(!out.status.success());
}

#[test]
fn design_fit_adds_the_contour_oficina_fit_reports() {
    let dir = scratch_dir("design-cli-fit");
    // 24 points of the ellipse of radii 60 × 40 about (150, 85).
    let pts: String = (0..24)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 24.0;
            format!("{},{}\n", 150.0 + 60.0 * t.cos(), 85.0 + 40.0 * t.sin())
        })
        .collect();
    std::fs::write(dir.join("e.csv"), pts).unwrap();
    let said = assert_success(&oficina(
        &dir,
        "design fit e.csv --tol 0.1 -o e.oficina.json",
    ));
    // `oficina fit`'s biarc row: the same blocks and deviation.
    let table = assert_success(&oficina(&dir, "fit e.csv --tol 0.1"));
    let row: Vec<&str> = table
        .lines()
        .find(|l| l.starts_with("biarc"))
        .unwrap()
        .split_whitespace()
        .collect();
    assert!(
        said.contains(&format!(
            "{} blocks, largest deviation {} mm",
            row[2], row[5]
        )),
        "{said}\n{table}"
    );
    // The contour, read as a drawing, encloses the ellipse's area πab within 0.5 %.
    let d = oficina_io::load_drawing(&dir.join("e.oficina.json")).unwrap();
    let area = d.drawing.paths().next().unwrap().area().abs();
    let want = std::f64::consts::PI * 60.0 * 40.0;
    assert!((area - want).abs() < 0.005 * want, "{area} vs {want}");
}

#[test]
fn design_grade_gives_oficina_soles_contours() {
    let dir = scratch_dir("design-cli-grade");
    let pts =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/sole/size34.csv");
    let pts = pts.display();
    let said = assert_success(&oficina(
        &dir,
        &format!("design grade {pts} --from-size 34 --to-size 36,40 -o g.oficina.json"),
    ));
    assert!(said.contains("size 40:"), "{said}");
    for size in [36, 40] {
        assert_success(&oficina(
            &dir,
            &format!(
                "sole {pts} --from-size 34 --to-size {size} --contours s.oficina.json -o out{size}"
            ),
        ));
    }
    let read = |f: &str| {
        oficina_io::parse_design(&std::fs::read_to_string(dir.join(f)).unwrap(), f).unwrap()
    };
    let (mine, theirs) = (read("g.oficina.json"), read("s.oficina.json"));
    let graded: Vec<_> = mine.entities.iter().map(|e| (&e.layer, &e.shape)).collect();
    let peer: Vec<_> = theirs
        .entities
        .iter()
        .map(|e| (&e.layer, &e.shape))
        .collect();
    assert_eq!(graded.len(), 4);
    assert_eq!(graded, peer);
    // By hand: size 34 → 40 in the Brazilian system is 6 · 6.66 mm longer, and the 2 %
    // shrinkage scales the length too: L·1.02 + 39.96 (vertices within the 0.3 mm fit).
    let ys = |s: &oficina_io::Shape| match s {
        oficina_io::Shape::Polyline { vertices, .. } => {
            let y = vertices.iter().map(|v| v[1]);
            y.clone().fold(f64::MIN, f64::max) - y.fold(f64::MAX, f64::min)
        }
        _ => panic!("a polyline"),
    };
    let base = oficina_io::load_points(std::path::Path::new(&pts.to_string())).unwrap();
    let l = base.iter().map(|p| p.y).fold(f64::MIN, f64::max)
        - base.iter().map(|p| p.y).fold(f64::MAX, f64::min);
    let len = ys(graded[2].1);
    assert!(
        (len - (l * 1.02 + 6.0 * 6.66)).abs() < 0.6,
        "{len} vs {}",
        l * 1.02 + 39.96
    );
}
