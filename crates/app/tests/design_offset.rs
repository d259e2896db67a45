//! The design editor's offset: a filleted plate offset inwards and outwards, against the
//! areas and the corner radius derived by hand.

use oficina_app::design::{offset, parse_design, Shape};
use oficina_io::entity_paths;
use oficina_io::geom::{Path, Segment};
use std::f64::consts::PI;

/// A 60 × 40 plate whose top-right corner is filleted with radius 5 (bulge tan(90°/4)).
const PLATE: &str = r##"{"format": "oficina-design", "version": 1,
  "layers": [{"name": "0", "color": "#000000"}],
  "entities": [{"id": 7, "layer": "0", "type": "polyline", "closed": true,
    "vertices": [[0, 0], [60, 0], [60, 35, 0.41421356237309503], [55, 40], [0, 40]]},
    {"id": 8, "layer": "0", "type": "line", "a": [0, 0], "b": [1, 1]}]}"##;

fn the_path(s: &Shape) -> Path {
    entity_paths(s).remove(0)
}

#[test]
fn inwards_the_fillet_shrinks_and_the_corners_stay_sharp() {
    let d = parse_design(PLATE, "plate").unwrap();
    let out = offset(&d, &[7], -3.0).unwrap();
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].id, 9, "after the largest id");
    let p = the_path(&out[0].shape);
    // Inwards by 3: a 54 × 34 box whose fillet (radius 5 − 3 = 2 about the same centre)
    // takes the corner square 2 × 2 less its quarter disc.
    let area = 54.0 * 34.0 - (4.0 - PI * 4.0 / 4.0);
    assert!(
        (p.area().abs() - area).abs() < 1e-2,
        "{} vs {area}",
        p.area()
    );
    let arcs: Vec<_> = p
        .segments
        .iter()
        .filter_map(|s| match s {
            Segment::Arc(a) => Some(*a),
            _ => None,
        })
        .collect();
    assert_eq!(arcs.len(), 1, "{:?}", p.segments);
    assert!((arcs[0].radius - 2.0).abs() < 1e-6, "{:?}", arcs[0]);
    assert!(
        arcs[0].center.distance((55.0, 35.0).into()) < 1e-6,
        "{:?}",
        arcs[0]
    );
}

#[test]
fn outwards_every_corner_rounds() {
    let d = parse_design(PLATE, "plate").unwrap();
    let p = the_path(&offset(&d, &[7], 2.0).unwrap()[0].shape);
    // Outwards by 2 (Minkowski sum with a disc): the plate's area, its perimeter × 2, and a
    // whole disc of radius 2 from the turning corners. Perimeter: 60 + 35 + 55 + 40 + the
    // quarter arc 2π·5/4.
    let perimeter = 60.0 + 35.0 + 55.0 + 40.0 + 2.0 * PI * 5.0 / 4.0;
    let plate = 60.0 * 40.0 - (25.0 - PI * 25.0 / 4.0);
    let area = plate + perimeter * 2.0 + PI * 4.0;
    assert!(
        (p.area().abs() - area).abs() < 2e-2,
        "{} vs {area}",
        p.area()
    );
}

#[test]
fn open_and_missing_entities_are_named() {
    let d = parse_design(PLATE, "plate").unwrap();
    let e = offset(&d, &[8], 1.0).unwrap_err().0;
    assert!(e.contains("entity 8 (line) is open"), "{e}");
    let e = offset(&d, &[42], 1.0).unwrap_err().0;
    assert!(e.contains("no entity 42"), "{e}");
    let e = offset(&d, &[7], f64::NAN).unwrap_err().0;
    assert!(e.contains("distance"), "{e}");
}
