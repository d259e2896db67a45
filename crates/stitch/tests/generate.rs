//! Stitches from real SVG designs (through Oficina's importer): every kind present, every
//! stitch within the machine's limit, fills with holes left open, colours from the SVG.

use oficina_stitch::{generate, Format, Kind, Params, StitchPlan};
use std::path::Path;

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

pub fn sample() -> StitchPlan {
    let imported =
        oficina_io::load_drawing(&root().join("samples/embroidery/sunflower.svg")).unwrap();
    generate(
        &imported.drawing,
        "sunflower",
        &Params::default(),
        &mut |_, _| {},
    )
    .unwrap()
    .plan
}

#[test]
fn the_sample_has_fill_satin_and_running_in_three_threads() {
    let imported =
        oficina_io::load_drawing(&root().join("samples/embroidery/sunflower.svg")).unwrap();
    let g = generate(
        &imported.drawing,
        "sunflower",
        &Params::default(),
        &mut |_, _| {},
    )
    .unwrap();
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
    let raw = generate(
        &imported.drawing,
        "s",
        &Params {
            center: false,
            ..Params::default()
        },
        &mut |_, _| {},
    )
    .unwrap()
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
    let loose = generate(
        &oficina_io::load_drawing(&root().join("samples/embroidery/sunflower.svg"))
            .unwrap()
            .drawing,
        "s",
        &Params {
            ties: false,
            ..Params::default()
        },
        &mut |_, _| {},
    )
    .unwrap()
    .plan;
    assert_eq!(
        plan.counts().stitches,
        loose.counts().stitches + 4 * trims + 4 * plan.blocks.len()
    );
}
