//! DXF import: a hand-written R12-style file (as a user's CAD would write it) and files made
//! with the dxf crate's writer, checked against geometry computed by hand.

use oficina_geom::{Path, Segment};
use oficina_io::dxf_from_bytes;

fn pairs(p: &[(&str, &str)]) -> String {
    p.iter().map(|(c, v)| format!("{c}\n{v}\n")).collect()
}

/// Header with $INSUNITS, a block "B" (a 10 mm line from its base point), entities.
fn hand_written(units: &str) -> String {
    let mut s = pairs(&[
        ("0", "SECTION"),
        ("2", "HEADER"),
        ("9", "$INSUNITS"),
        ("70", units),
        ("0", "ENDSEC"),
    ]);
    s += &pairs(&[
        ("0", "SECTION"),
        ("2", "BLOCKS"),
        ("0", "BLOCK"),
        ("8", "0"),
        ("2", "B"),
        ("70", "0"),
        ("10", "1.0"),
        ("20", "0.0"),
        ("30", "0.0"),
        ("0", "LINE"),
        ("8", "0"),
        ("10", "1.0"),
        ("20", "0.0"),
        ("30", "0.0"),
        ("11", "11.0"),
        ("21", "0.0"),
        ("31", "0.0"),
        ("0", "ENDBLK"),
        ("0", "ENDSEC"),
    ]);
    s += &pairs(&[
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "LINE"),
        ("5", "A1"),
        ("8", "cut"),
        ("62", "1"),
        ("10", "0.0"),
        ("20", "0.0"),
        ("30", "0.0"),
        ("11", "10.0"),
        ("21", "0.0"),
        ("31", "0.0"),
        ("0", "ARC"),
        ("5", "A2"),
        ("8", "cut"),
        ("10", "0.0"),
        ("20", "0.0"),
        ("30", "0.0"),
        ("40", "5.0"),
        ("50", "0.0"),
        ("51", "90.0"),
        ("0", "CIRCLE"),
        ("5", "A3"),
        ("8", "holes"),
        ("10", "20.0"),
        ("20", "20.0"),
        ("30", "0.0"),
        ("40", "2.0"),
        // A closed 10×10 square whose top edge bulges out in a half circle (bulge 1).
        ("0", "LWPOLYLINE"),
        ("5", "A4"),
        ("8", "cut"),
        ("90", "4"),
        ("70", "1"),
        ("10", "0.0"),
        ("20", "0.0"),
        ("10", "10.0"),
        ("20", "0.0"),
        ("10", "10.0"),
        ("20", "10.0"),
        ("42", "1.0"),
        ("10", "0.0"),
        ("20", "10.0"),
        ("0", "INSERT"),
        ("5", "A5"),
        ("8", "0"),
        ("2", "B"),
        ("10", "100.0"),
        ("20", "0.0"),
        ("30", "0.0"),
        ("41", "2.0"),
        ("42", "2.0"),
        ("50", "90.0"),
        ("0", "TEXT"),
        ("5", "A6"),
        ("8", "0"),
        ("10", "0.0"),
        ("20", "0.0"),
        ("30", "0.0"),
        ("40", "2.5"),
        ("1", "hello"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ]);
    s
}

fn find<'a>(paths: &'a [&'a Path], element: &str) -> &'a Path {
    paths
        .iter()
        .find(|p| p.source.element.contains(element))
        .unwrap_or_else(|| panic!("{element} missing: {paths:?}"))
}

#[test]
fn hand_written_file_in_mm_with_bulge_insert_and_text() {
    let imp = dxf_from_bytes(hand_written("4").as_bytes(), "h.dxf").unwrap();
    // The TEXT is drawn in single strokes ("hello": h 2, e 1, l 1, l 1, o 1), on its layer.
    let (text, paths): (Vec<&Path>, Vec<&Path>) = imp
        .drawing
        .paths()
        .partition(|p| p.source.element == "TEXT #A6");
    assert_eq!(text.len(), 6, "{text:?}");
    assert_eq!(paths.len(), 5, "{paths:?}");
    let line = find(&paths, "LINE #A1");
    assert!((line.length() - 10.0).abs() < 1e-12);
    assert_eq!(
        line.style.stroke,
        Some(oficina_geom::Color::rgb(255, 0, 0)),
        "ACI 1 is red"
    );
    let Segment::Arc(a) = find(&paths, "ARC #A2").segments[0] else {
        panic!()
    };
    assert!(
        (a.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12 && (a.radius - 5.0).abs() < 1e-12
    );
    let sq = find(&paths, "LWPOLYLINE #A4");
    assert!(sq.closed);
    assert_eq!(sq.counts(), (3, 1, 0));
    // 100 mm² plus a half disc of radius 5 bulging outwards (bulge 1 from (10,10) to (0,10)).
    let want = 100.0 + std::f64::consts::PI * 25.0 / 2.0;
    assert!((sq.area() - want).abs() < 0.05, "{}", sq.area());
    // The block's line from its base (1,0) is 10 long, scaled 2 and turned 90°: (100,0)→(100,20).
    let inserted = paths
        .iter()
        .find(|p| p.start().is_some_and(|s| (s.x - 100.0).abs() < 1e-9))
        .expect("inserted line");
    assert!(
        inserted
            .end()
            .unwrap()
            .distance(oficina_geom::Point::new(100.0, 20.0))
            < 1e-9
    );
    assert!(imp.unsupported.is_empty(), "{}", imp.unsupported);
    assert_eq!(
        imp.drawing
            .layers
            .iter()
            .map(|l| l.name.as_str())
            .collect::<Vec<_>>(),
        ["cut", "holes", "0"]
    );
}

#[test]
fn insunits_inches_scale_to_mm() {
    let imp = dxf_from_bytes(hand_written("1").as_bytes(), "in.dxf").unwrap();
    let paths: Vec<&Path> = imp.drawing.paths().collect();
    assert!((find(&paths, "LINE #A1").length() - 254.0).abs() < 1e-9);
    let Segment::Arc(c) = find(&paths, "CIRCLE #A3").segments[0] else {
        panic!()
    };
    assert!((c.radius - 50.8).abs() < 1e-9);
}

#[test]
fn spline_and_ellipse_written_by_the_dxf_crate() {
    use dxf::entities::{Ellipse, Entity, EntityType, Spline};
    let mut d = dxf::Drawing::new();
    d.header.default_drawing_units = dxf::enums::Units::Millimeters;
    d.header.version = dxf::enums::AcadVersion::R2000;
    let mut s = Spline::default();
    s.degree_of_curve = 3;
    s.knot_values = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    s.control_points = vec![
        dxf::Point::new(0.0, 0.0, 0.0),
        dxf::Point::new(0.0, 10.0, 0.0),
        dxf::Point::new(10.0, 10.0, 0.0),
        dxf::Point::new(10.0, 0.0, 0.0),
    ];
    d.add_entity(Entity::new(EntityType::Spline(s)));
    let mut e = Ellipse::default();
    e.center = dxf::Point::new(50.0, 0.0, 0.0);
    e.major_axis = dxf::Vector::new(20.0, 0.0, 0.0);
    e.minor_axis_ratio = 0.5;
    e.start_parameter = 0.0;
    e.end_parameter = std::f64::consts::TAU;
    d.add_entity(Entity::new(EntityType::Ellipse(e)));
    let mut buf = Vec::new();
    d.save(&mut buf).unwrap();
    let imp = dxf_from_bytes(&buf, "w.dxf").unwrap();
    let paths: Vec<&Path> = imp.drawing.paths().collect();
    assert_eq!(paths.len(), 2);
    // The Bézier-equivalent spline's midpoint: (0+3·0+3·10+10)/8, (0+30+30+0)/8 = (5, 7.5).
    let sp = paths[0];
    assert!(sp.distance(oficina_geom::Point::new(5.0, 7.5)) < 1e-3);
    let el = paths[1];
    assert!(el.closed);
    // Within what flattening to 1 µm loses.
    assert!(
        (el.area().abs() - std::f64::consts::PI * 20.0 * 10.0).abs() < 0.1,
        "{}",
        el.area()
    );
}

#[test]
fn broken_files_are_errors_that_say_where() {
    let e = dxf_from_bytes(b"0\nSECTION\n2\nENTITIES\n0\nLINE\n10\nabc\n", "bad.dxf").unwrap_err();
    // The value "abc" of group 10 is on line 8 (its group code on line 7).
    assert_eq!(
        (e.file.as_str(), e.location.as_str()),
        ("bad.dxf", "line 7"),
        "{e}"
    );
    assert!(e.message.contains("'abc' is not a number"), "{e}");
    let undefined = hand_written("4").replace("2\nB\n10\n100.0", "2\nNOPE\n10\n100.0");
    let e = dxf_from_bytes(undefined.as_bytes(), "u.dxf").unwrap_err();
    assert!(e.to_string().contains("block 'NOPE' is not defined"), "{e}");
    assert!(e.location.contains("A5"), "{e}");
}
