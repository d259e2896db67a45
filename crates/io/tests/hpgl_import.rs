//! HPGL import: instructions as HP's HP-GL reference describes them (40 units per mm).

use oficina_io::hpgl_from_bytes;

fn parse(s: &str) -> oficina_io::Hpgl {
    hpgl_from_bytes(s.as_bytes(), "t.plt").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_square_in_absolute_then_relative_moves() {
    let h = parse("IN;SP1;PU0,0;PD4000,0,4000,4000,0,4000,0,0;PU;\nPR;PU8000,0;PD400,0 0,400;PU;");
    let d = &h.imported.drawing;
    assert_eq!(d.path_count(), 2);
    let sq = &d.layers[0].paths[0];
    assert!((sq.length() - 400.0).abs() < 1e-9, "{}", sq.length());
    let rel = &d.layers[0].paths[1];
    assert_eq!(rel.start().unwrap(), oficina_geom::Point::new(200.0, 0.0));
    assert_eq!(rel.end().unwrap(), oficina_geom::Point::new(210.0, 10.0));
    assert_eq!(d.layers[0].name, "pen 1");
}

#[test]
fn circles_and_arcs_stay_arcs_with_their_lengths() {
    // CI 400 units = 10 mm radius about (50, 50) mm; AA: quarter arc about (100, 50) mm
    // starting 10 mm to its right, counter-clockwise.
    let h = parse("IN;SP2;PA2000,2000;CI400;PU4400,2000;PD;AA4000,2000,90;PU;");
    let d = &h.imported.drawing;
    assert_eq!(d.layers[0].name, "pen 2");
    let circle = &d.layers[0].paths[0];
    assert!((circle.length() - 2.0 * std::f64::consts::PI * 10.0).abs() < 1e-9);
    let arc = &d.layers[0].paths[1];
    assert!((arc.length() - std::f64::consts::PI * 5.0).abs() < 1e-9);
    let e = arc.end().unwrap();
    assert!(
        (e.x - 100.0).abs() < 1e-9 && (e.y - 60.0).abs() < 1e-9,
        "{e:?}"
    );
}

#[test]
fn pens_become_layers_and_labels_are_kept() {
    let h = parse("IN;SP1;PD100,0;PU;SP3;PU0,0;PD0,100;PU400,400;SI0.5,0.7;LBHello\x03;");
    let names: Vec<&str> = h
        .imported
        .drawing
        .layers
        .iter()
        .map(|l| l.name.as_str())
        .collect();
    assert_eq!(names, ["pen 1", "pen 3"]);
    assert_eq!(h.labels.len(), 1);
    let l = &h.labels[0];
    assert_eq!(l.text, "Hello");
    assert_eq!((l.width, l.height), (5.0, 7.0));
    assert_eq!(l.at, oficina_geom::Point::new(10.0, 10.0));
}

#[test]
fn unknown_settings_are_counted_not_dropped_silently() {
    let h = parse("IN;VS10;LT2;SP1;PD10,10;");
    assert_eq!(h.imported.unsupported.counts.get("VS"), Some(&1));
    assert_eq!(h.imported.unsupported.counts.get("LT"), Some(&1));
}

#[test]
fn errors_name_the_line_and_the_instruction() {
    let e = hpgl_from_bytes(b"IN;\nSP1;\nPD10,20,30;", "x.plt").unwrap_err();
    assert_eq!(e.location, "line 3, column 11, PD");
    assert!(e.message.contains("pairs"), "{e}");
    let e = hpgl_from_bytes(b"IN;CI;", "x.plt").unwrap_err();
    assert!(
        e.to_string().contains("CI") && e.message.contains("radius"),
        "{e}"
    );
    let e = hpgl_from_bytes(b"IN;PA1e300,0;", "x.plt").unwrap_err();
    assert!(e.to_string().contains("PA"), "{e}");
    let e = hpgl_from_bytes(b"IN;\n\n%%garbage", "x.plt").unwrap_err();
    assert_eq!(e.location, "line 3, column 1");
    let e = hpgl_from_bytes(b"IN;AA10,10;", "x.plt").unwrap_err();
    assert!(e.to_string().contains("AA"), "{e}");
}

#[test]
fn an_empty_file_is_refused_by_name_and_a_file_of_settings_is_an_empty_drawing() {
    let e = hpgl_from_bytes(b"", "empty.plt").unwrap_err();
    assert_eq!(e.file, "empty.plt");
    assert!(e.message.contains("empty (0 bytes)"), "{e}");
    let e = hpgl_from_bytes(b" \r\n\0", "blank.plt").unwrap_err();
    assert!(e.message.contains("blanks"), "{e}");
    assert_eq!(parse("IN;SP1;").imported.drawing.path_count(), 0);
}
