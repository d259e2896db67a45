//! Seed 000's own files end to end: a CADTEC `.PUB` stitched, written as `.BOR` and read back
//! the same; shifted and linked programs against figures computed by hand.

use oficina_stitch::{
    alter, generate, link, read_bor, write_bor, Alteration, Format, Kind, Params, SeedHeader,
};

const PUB: &str = "$ EMPRESA ITAUTEC INFORMATICA\n$ TIPOARQ ARQUIVO PUBLICO\n$ UNI 1.0 MM\n\
P 1 2 3 1 0 5\n0.0 0.0 30.0 0.0 30.0 20.0 0.0 20.0 0.0 0.0\n\
A 1 4 1 1 0 15.0 10.0 8.0 0.0 180.0\n\
P 1 1 1 1 23 2\n-80.0 0.0 80.0 0.0\n";

#[test]
fn a_pub_design_goes_to_bor_and_back_unchanged() {
    let imp = oficina_io::pub_from_str(PUB, "emc.pub").unwrap();
    let g = generate(&imp.drawing, "emc", &Params::default(), &mut |_, _| {}).unwrap();
    assert_eq!(
        (g.runnings, g.satins),
        (1, 1),
        "style 3 running, the arc satin"
    );
    let bor = Format::Bor.write(&g.plan).unwrap();
    let back = Format::Bor.read(&bor, "emc").unwrap();
    // The plan on the 0.2 mm grid, trims left out (the seed has none): the same entries.
    let grid = |v: f64| (v / 0.2).round() as i64;
    let want: Vec<_> = g
        .plan
        .entries()
        .filter(|(_, s)| s.kind != Kind::Trim)
        .map(|(b, s)| (b, grid(s.x), grid(s.y), s.kind))
        .collect();
    let got: Vec<_> = back
        .entries()
        .map(|(b, s)| (b, grid(s.x), grid(s.y), s.kind))
        .collect();
    // Sewn stitches longer than 12.4 mm would be split; the generator makes none.
    assert_eq!(got, want);
    // Written again, the same text.
    assert_eq!(Format::Bor.write(&back).unwrap(), bor);
}

#[test]
fn shifted_and_linked_programs_keep_their_points() {
    let imp = oficina_io::pub_from_str(PUB, "emc.pub").unwrap();
    let p = Params {
        center: false,
        ..Params::default()
    };
    let g = generate(&imp.drawing, "emc", &p, &mut |_, _| {}).unwrap();
    // EMC1: EMC shifted +30 X, −30 Y (L1887-1889).
    let emc1 = alter(
        &g.plan,
        &Alteration {
            shift: [30.0, -30.0],
            ..Alteration::default()
        },
    );
    let a: Vec<_> = g.plan.entries().map(|(_, s)| (s.x, s.y)).collect();
    let b: Vec<_> = emc1.entries().map(|(_, s)| (s.x, s.y)).collect();
    for (p, q) in a.iter().zip(&b) {
        assert!((q.0 - p.0 - 30.0).abs() < 1e-9 && (q.1 - p.1 + 30.0).abs() < 1e-9);
    }
    // SOMA = EMC + EMC written with its Zero-Peça 100 mm to the right.
    let h = SeedHeader {
        program: 2,
        start: [100.0, 0.0],
        hoop: None,
    };
    let (second, h2) = read_bor(&write_bor(&g.plan, &h).unwrap()).unwrap();
    assert_eq!(h2.start, [100.0, 0.0]);
    let soma = link(&[(g.plan.clone(), [0.0, 0.0]), (second, h2.start)]);
    let n = g.plan.counts();
    let s = soma.counts();
    // One joining point: a jump (the last point is far from (100, 0)).
    assert_eq!(s.stitches, 2 * n.stitches);
    assert_eq!(s.jumps, 2 * n.jumps + 1);
    let last = soma.blocks.last().unwrap().stitches.last().unwrap();
    let orig = g.plan.blocks.last().unwrap().stitches.last().unwrap();
    assert!((last.x - orig.x - 100.0).abs() < 0.11 && (last.y - orig.y).abs() < 0.11);
}
