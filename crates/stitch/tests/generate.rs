//! Stitches from real SVG designs (through Oficina's importer): every kind present, every
//! stitch within the machine's limit, fills with holes left open, colours from the SVG.

mod common;

use common::{sample, sunflower};
use oficina_stitch::{generate, Format, Kind, Params, StitchPlan};

#[test]
fn the_sample_has_fill_satin_and_running_in_three_threads() {
    let g = sunflower("sunflower", &Params::default());
    assert_eq!((g.fills, g.satins, g.runnings), (1, 2, 2));
    let plan = g.plan;
    let hexes: Vec<String> = plan.blocks.iter().map(|b| b.thread.hex()).collect();
    assert_eq!(hexes, ["#2e8b3a", "#f2c014", "#6b3e1e"]);
    let c = plan.counts();
    assert!(c.stitches > 1000 && c.stitches < 12000, "{c:?}");
    // Centred on the hoop: the design is 70 × 80 at most.
    let b = plan.bounds().unwrap();
    assert!(
        (b[0] + b[2]).abs() < 1e-6 && (b[1] + b[3]).abs() < 1e-6,
        "{b:?}"
    );
    assert!(b[2] - b[0] < 50.0 && b[3] - b[1] < 75.0, "{b:?}");
    // No sewn stitch beyond the machine's longest.
    let mut prev = (0.0, 0.0);
    for (_, s) in plan.entries() {
        if s.kind == Kind::Stitch {
            let d = (s.x - prev.0).hypot(s.y - prev.1);
            assert!(d <= 12.1 + 1e-9, "{d} at {s:?}");
        }
        prev = (s.x, s.y);
    }
    // The ring's hole (the flower's centre, Ø 20 mm at (35, 52) mm y up) has no yellow
    // stitch within 9 mm of its centre.
    let raw = sunflower(
        "s",
        &Params {
            center: false,
            ..Params::default()
        },
    )
    .plan;
    let yellow = &raw.blocks[1];
    let near = |s: &&oficina_stitch::Stitch| (s.x - 35.0).hypot(s.y - 52.0) < 9.0;
    assert_eq!(
        yellow
            .stitches
            .iter()
            .filter(|s| s.kind == Kind::Stitch)
            .filter(near)
            .count(),
        0
    );
    assert!(
        yellow
            .stitches
            .iter()
            .filter(|s| (s.x - 35.0).hypot(s.y - 52.0) < 12.0)
            .count()
            > 50
    );
    // Every kind of file holds it.
    for f in Format::ALL {
        let back = f.read(&f.write(&plan).unwrap(), "s").unwrap();
        assert_eq!(back.counts().stitches, c.stitches, "{f}");
    }
    // The seed's program: every sewn point on the 0.2 mm step grid, within 0.1 mm per axis
    // (no stitch of the sample is over 12.4 mm, so none becomes a long point).
    let ram = Format::SeedRam
        .read(&Format::SeedRam.write(&plan).unwrap(), "s")
        .unwrap();
    let sewn = |p: &StitchPlan| -> Vec<(f64, f64)> {
        p.entries()
            .filter(|e| e.1.kind == Kind::Stitch)
            .map(|e| (e.1.x, e.1.y))
            .collect()
    };
    let (a, b) = (sewn(&plan), sewn(&ram));
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(&b) {
        assert!(
            (p.0 - q.0).abs() <= 0.1 + 1e-9 && (p.1 - q.1).abs() <= 0.1 + 1e-9,
            "{p:?} {q:?}"
        );
    }
    assert_eq!(ram.blocks.len(), plan.blocks.len());
}

#[test]
fn the_thread_is_locked_wherever_it_is_cut() {
    let plan = sample();
    let near =
        |a: &oficina_stitch::Stitch, b: &oficina_stitch::Stitch| (a.x - b.x).hypot(a.y - b.y);
    let mut trims = 0;
    for block in &plan.blocks {
        let s = &block.stitches;
        // Tie-in: jump, anchor, 0.5 mm out, back.
        assert_eq!(s[0].kind, Kind::Jump);
        assert!(
            (near(&s[1], &s[2]) - oficina_stitch::TIE).abs() < 1e-9 && near(&s[1], &s[3]) < 1e-9
        );
        // Tie-off before every trim and at the block's end.
        let n = s.len();
        assert!(
            near(&s[n - 1], &s[n - 3]) < 1e-9
                && near(&s[n - 1], &s[n - 2]) <= oficina_stitch::TIE + 1e-9
        );
        for i in 3..n {
            if s[i].kind == Kind::Trim {
                trims += 1;
                assert!(
                    near(&s[i - 1], &s[i - 3]) < 1e-9 && near(&s[i - 1], &s[i]) < 1e-9,
                    "{:?}",
                    &s[i - 3..=i]
                );
            }
        }
    }
    assert!(trims > 0);
    let loose = sunflower(
        "s",
        &Params {
            ties: false,
            ..Params::default()
        },
    )
    .plan;
    assert_eq!(
        plan.counts().stitches,
        loose.counts().stitches + 4 * trims + 4 * plan.blocks.len()
    );
}

fn from_svg(svg: &str, params: &Params) -> oficina_stitch::Generated {
    let imported = oficina_io::svg_from_bytes(svg.as_bytes(), "t.svg").unwrap();
    generate(&imported.drawing, "t", params, &mut |_, _| {}).unwrap()
}

#[test]
fn two_open_subpaths_are_the_rails_of_a_satin() {
    // Rails 6 mm apart at the left, 2 mm at the right, drawn in opposite directions.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="40mm" height="20mm" viewBox="0 0 40 20">
      <path d="M 5 7 L 35 9 M 35 11 L 5 13" fill="none" stroke="#123456" stroke-width="1"/></svg>"##;
    let p = Params {
        underlay: false,
        pull_compensation: 0.0,
        ties: false,
        center: false,
        ..Params::default()
    };
    let g = from_svg(svg, &p);
    assert_eq!((g.fills, g.satins, g.runnings), (0, 1, 0));
    let pts: Vec<(f64, f64)> = g
        .plan
        .entries()
        .filter(|e| e.1.kind == Kind::Stitch)
        .map(|e| (e.1.x, e.1.y))
        .collect();
    // y up: the rails are y = 13 − ... in mm; every needle point lies on one of the two rails.
    let on_rail = |x: f64, y: f64| {
        let t = (x - 5.0) / 30.0;
        let (r1, r2) = (20.0 - (7.0 + 2.0 * t), 20.0 - (13.0 - 2.0 * t));
        (y - r1).abs() < 1e-6 || (y - r2).abs() < 1e-6
    };
    assert!(
        pts.iter().all(|&(x, y)| on_rail(x, y)),
        "{:?}",
        pts.iter().find(|&&(x, y)| !on_rail(x, y))
    );
    // Zigs alternate rails and advance 0.4 mm at most along X.
    assert!(pts.len() > 2 * 70, "{}", pts.len());
    assert_eq!(g.plan.blocks[0].thread.hex(), "#123456");
}

#[test]
fn closed_dxf_outlines_fill_when_asked() {
    // A DXF square (no fill colour in DXF): running stitch by default, tatami with fill_closed.
    let dxf = "0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n0\n90\n4\n70\n1\n10\n0\n20\n0\n10\n20\n20\n0\n10\n20\n20\n20\n10\n0\n20\n20\n0\nENDSEC\n0\nEOF\n";
    let path = std::env::temp_dir().join(format!("oficina-stitch-sq-{}.dxf", std::process::id()));
    std::fs::write(&path, dxf).unwrap();
    let drawing = oficina_io::load_drawing(&path).unwrap().drawing;
    let run = generate(&drawing, "sq", &Params::default(), &mut |_, _| {}).unwrap();
    assert_eq!((run.fills, run.runnings), (0, 1));
    let filled = generate(
        &drawing,
        "sq",
        &Params {
            fill_closed: true,
            ..Params::default()
        },
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!((filled.fills, filled.runnings), (1, 0));
    // 20 × 20 mm at 0.4 mm rows and 3 mm stitches: ≥ 50 rows × 7 stitches.
    assert!(
        filled.plan.counts().stitches > 350,
        "{}",
        filled.plan.counts().stitches
    );
}

#[test]
fn the_seeds_speed_example_in_its_program() {
    // §8: two filled polylines of width 8.0 and 5.0 mm → speed level 6 at the start of the
    // program and level 11 at the start of the second polyline.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="80mm" height="40mm" viewBox="0 0 80 40">
      <path d="M 10 10 L 70 10" fill="none" stroke="#000" stroke-width="8"/>
      <path d="M 10 30 L 70 30" fill="none" stroke="#000" stroke-width="5"/></svg>"##;
    let p = Params {
        pull_compensation: 0.0,
        underlay: false,
        ties: false,
        ..Params::default()
    };
    let plan = from_svg(svg, &p).plan;
    let ram = Format::SeedRam.write(&plan).unwrap();
    let speeds: Vec<u8> = ram[9..]
        .windows(2)
        .filter(|w| w[0] == 0xFE)
        .map(|w| w[1])
        .collect();
    assert_eq!(speeds, [6, 11]);
}

#[test]
fn an_absurd_design_is_refused_before_any_stitch_is_made() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="20000mm" height="20000mm" viewBox="0 0 20000 20000">
      <rect x="0" y="0" width="20000" height="20000" fill="#000"/></svg>"##;
    let imported = oficina_io::svg_from_bytes(svg.as_bytes(), "huge.svg").unwrap();
    let e = generate(
        &imported.drawing,
        "huge",
        &Params::default(),
        &mut |_, _| {},
    )
    .unwrap_err();
    assert!(e.to_string().contains("more than the 2000000"), "{e}");
}
