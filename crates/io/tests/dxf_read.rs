//! The DXF reader's rules checked by hand: units from the header, the refusal of absurd sizes,
//! files cut short or with trash after EOF, binary and ASCII giving the same drawing, layer
//! and block colours, what is skipped and why.

use oficina_geom::{Color, Path as GPath};
use oficina_io::{dxf_from_bytes, read_dxf, DxfOptions};
use std::path::Path;

fn pairs(p: &[(&str, &str)]) -> String {
    p.iter().map(|(c, v)| format!("{c}\n{v}\n")).collect()
}

fn data(name: &str) -> Vec<u8> {
    std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/dxf")
            .join(name),
    )
    .unwrap()
}

/// A header with the given variables (name, code, value) and one 10-unit LINE.
fn with_header(vars: &[(&str, &str, &str)]) -> String {
    let mut s = pairs(&[("0", "SECTION"), ("2", "HEADER")]);
    for (n, c, v) in vars {
        s += &pairs(&[("9", n), (c, v)]);
    }
    s += &pairs(&[("0", "ENDSEC"), ("0", "SECTION"), ("2", "ENTITIES")]);
    s += &pairs(&[
        ("0", "LINE"),
        ("8", "0"),
        ("10", "0"),
        ("20", "0"),
        ("11", "10"),
        ("21", "0"),
    ]);
    s += &pairs(&[("0", "ENDSEC"), ("0", "EOF")]);
    s
}

fn length(bytes: &[u8]) -> f64 {
    dxf_from_bytes(bytes, "u.dxf")
        .unwrap()
        .drawing
        .paths()
        .map(GPath::length)
        .sum()
}

#[test]
fn units_come_from_insunits_then_measurement_then_mm() {
    let cases = [
        (
            vec![("$INSUNITS", "70", "4"), ("$MEASUREMENT", "70", "0")],
            10.0,
        ),
        (vec![("$INSUNITS", "70", "5")], 100.0),
        (
            vec![("$INSUNITS", "70", "0"), ("$MEASUREMENT", "70", "0")],
            254.0,
        ),
        (vec![("$MEASUREMENT", "70", "1")], 10.0),
        (vec![("$ACADVER", "1", "AC1009")], 10.0),
    ];
    for (vars, want) in cases {
        let got = length(with_header(&vars).as_bytes());
        assert!((got - want).abs() < 1e-9, "{vars:?}: {got}");
    }
    let r = read_dxf(
        with_header(&[("$MEASUREMENT", "70", "0")]).as_bytes(),
        "m.dxf",
        &DxfOptions::default(),
    )
    .unwrap();
    assert!(r.units.contains("$MEASUREMENT 0"), "{}", r.units);
    let e = dxf_from_bytes(
        with_header(&[("$INSUNITS", "70", "99")]).as_bytes(),
        "x.dxf",
    )
    .unwrap_err();
    assert_eq!(e.location, "$INSUNITS", "{e}");
}

#[test]
fn an_absurd_size_is_refused_with_a_hint_and_read_when_the_units_are_given() {
    // A hatch drawn in metres on a 56 m × 70 m site.
    let bytes = data("ezdxf_clockwise_arcs_hatch.dxf");
    let e = dxf_from_bytes(&bytes, "site.dxf").unwrap_err();
    assert_eq!(e.location, "units");
    assert!(
        e.message.contains("56.0 m × 70.0 m")
            && e.message.contains("$INSUNITS 6")
            && e.message.contains("4 = mm"),
        "{e}"
    );
    let opts = DxfOptions {
        mm_per_unit: Some(1.0),
        ..DxfOptions::default()
    };
    let r = read_dxf(&bytes, "site.dxf", &opts).unwrap();
    let b = r.imported.drawing.bounding_box().unwrap();
    assert!(
        (b.width() - 56.0).abs() < 0.01 && (b.height() - 70.0).abs() < 0.01,
        "{b:?}"
    );
}

#[test]
fn trash_after_eof_is_ignored_and_a_file_cut_short_names_its_line() {
    let mut s = with_header(&[]);
    s += "this is not DXF\n12\n";
    assert!((length(s.as_bytes()) - 10.0).abs() < 1e-12);
    // Entities with no SECTION around them at all, as some generators write.
    let bare = "0\nLINE\n10\n0\n20\n0\n11\n3\n21\n4\n0\nEOF\n";
    assert!((length(bare.as_bytes()) - 5.0).abs() < 1e-12);
    let cut = "0\nSECTION\n2\nENTITIES\n0\nLINE\n10\n1\n20";
    let e = dxf_from_bytes(cut.as_bytes(), "cut.dxf").unwrap_err();
    assert_eq!(e.location, "line 9", "{e}");
    assert!(e.message.contains("no value"), "{e}");
    let svg = b"<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n";
    let e = dxf_from_bytes(svg, "a.dxf").unwrap_err();
    assert_eq!(e.location, "line 1", "{e}");
    assert!(dxf_from_bytes(b"", "empty.dxf")
        .unwrap_err()
        .message
        .contains("empty"));
    // A binary file cut in a double names its byte.
    let bin = data("ezdxf_bin_dxf_r13.dxf");
    let e = dxf_from_bytes(&bin[..505], "b.dxf").unwrap_err(); // inside "$CELTYPE"
    assert!(e.location.starts_with("byte "), "{e}");
}

#[test]
fn binary_and_ascii_files_of_one_drawing_read_the_same() {
    let a = read_dxf(&data("made_by_ezdxf.dxf"), "a.dxf", &DxfOptions::default()).unwrap();
    let b = read_dxf(
        &data("made_by_ezdxf_binary.dxf"),
        "b.dxf",
        &DxfOptions::default(),
    )
    .unwrap();
    assert!(b.binary && !a.binary);
    assert_eq!(a.entities, b.entities);
    let la: Vec<f64> = a.imported.drawing.paths().map(GPath::length).collect();
    let lb: Vec<f64> = b.imported.drawing.paths().map(GPath::length).collect();
    assert_eq!(la.len(), lb.len());
    for (x, y) in la.iter().zip(&lb) {
        assert!((x - y).abs() < 1e-9, "{x} {y}");
    }
    assert_eq!(a.imported.points, b.imported.points);
    assert_eq!(a.version, "AC1032");
}

#[test]
fn colours_by_layer_and_by_block_and_layer_zero_inside_blocks() {
    let mut s = pairs(&[
        ("0", "SECTION"),
        ("2", "TABLES"),
        ("0", "TABLE"),
        ("2", "LAYER"),
        ("0", "LAYER"),
        ("2", "blue"),
        ("70", "0"),
        ("62", "5"),
        ("0", "LAYER"),
        ("2", "off-red"),
        ("70", "0"),
        ("62", "-1"),
        ("0", "ENDTAB"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "BLOCKS"),
        ("0", "BLOCK"),
        ("2", "B"),
        ("10", "0"),
        ("20", "0"),
        // On layer 0 by block: takes the insert's layer and colour.
        ("0", "LINE"),
        ("8", "0"),
        ("62", "0"),
        ("10", "0"),
        ("20", "0"),
        ("11", "1"),
        ("21", "0"),
        // Its own layer and colour.
        ("0", "LINE"),
        ("8", "blue"),
        ("62", "2"),
        ("10", "0"),
        ("20", "1"),
        ("11", "1"),
        ("21", "1"),
        ("0", "ENDBLK"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "ENTITIES"),
    ]);
    s += &pairs(&[
        ("0", "LINE"),
        ("8", "blue"),
        ("10", "0"),
        ("20", "5"),
        ("11", "1"),
        ("21", "5"),
    ]);
    s += &pairs(&[
        ("0", "LINE"),
        ("8", "off-red"),
        ("10", "0"),
        ("20", "6"),
        ("11", "1"),
        ("21", "6"),
    ]);
    s += &pairs(&[
        ("0", "INSERT"),
        ("8", "off-red"),
        ("62", "3"),
        ("2", "B"),
        ("10", "10"),
        ("20", "0"),
    ]);
    s += &pairs(&[("0", "ENDSEC"), ("0", "EOF")]);
    let i = dxf_from_bytes(s.as_bytes(), "c.dxf").unwrap();
    let got: Vec<(String, Option<Color>)> = i
        .drawing
        .layers
        .iter()
        .flat_map(|l| {
            l.paths
                .iter()
                .map(move |p| (l.name.clone(), p.style.stroke))
        })
        .collect();
    let blue = Some(Color::rgb(0, 0, 255));
    let red = Some(Color::rgb(255, 0, 0));
    let green = Some(Color::rgb(0, 255, 0));
    let yellow = Some(Color::rgb(255, 255, 0));
    let want = [
        ("blue".to_string(), blue),
        ("blue".to_string(), yellow),
        ("off-red".to_string(), red),
        ("off-red".to_string(), green),
    ];
    let mut got = got;
    got.sort_by_key(|(l, c)| (l.clone(), format!("{c:?}")));
    let mut want = want.to_vec();
    want.sort_by_key(|(l, c)| (l.clone(), format!("{c:?}")));
    assert_eq!(got, want);
}

#[test]
fn what_is_skipped_is_counted_with_its_reason() {
    // Text is drawn unless asked not to; asked not to, it is counted with its reason.
    let no_text = DxfOptions {
        draw_text: false,
        ..DxfOptions::default()
    };
    let r = read_dxf(&data("ezdxf_hatches_2.dxf"), "h.dxf", &no_text).unwrap();
    let u = &r.imported.unsupported;
    assert_eq!(u.counts.get("MTEXT (text is not drawn)"), Some(&2), "{u}");
    assert_eq!(
        u.counts
            .get("HATCH (boundary drawn by its source entities)"),
        Some(&2),
        "{u}"
    );
    assert_eq!(r.units, "inches ($INSUNITS 1)");
    // A closed 3-D polyline written without the closed flag, its last vertex on its first.
    let s = pairs(&[
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "POLYLINE"),
        ("66", "1"),
        ("70", "8"),
        ("0", "VERTEX"),
        ("10", "0"),
        ("20", "0"),
        ("70", "32"),
        ("0", "VERTEX"),
        ("10", "4"),
        ("20", "0"),
        ("70", "32"),
        ("0", "VERTEX"),
        ("10", "4"),
        ("20", "3"),
        ("70", "32"),
        ("0", "VERTEX"),
        ("10", "0"),
        ("20", "0"),
        ("70", "32"),
        ("0", "SEQEND"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ]);
    let mut i = dxf_from_bytes(s.as_bytes(), "r12.dxf").unwrap();
    // The reader keeps it as drawn; the one closure rule of every importer closes it.
    assert!(!i.drawing.paths().next().unwrap().closed);
    i.close(oficina_io::JOIN_TOL);
    assert_eq!(i.closure.loops(), 1);
    let p = i.drawing.paths().next().unwrap();
    // Paper space (group 67 = 1) is the sheet, not the part.
    let paper = s.replace("0\nPOLYLINE\n66\n1\n", "0\nPOLYLINE\n5\nA0\n67\n1\n66\n1\n");
    let ip = dxf_from_bytes(paper.as_bytes(), "p.dxf").unwrap();
    assert_eq!(ip.drawing.path_count(), 0);
    assert_eq!(
        ip.unsupported.examples["paper-space entity"],
        ["POLYLINE #A0"]
    );
    assert!(p.closed && (p.length() - 12.0).abs() < 1e-12 && (p.area().abs() - 6.0).abs() < 1e-12);
}

#[test]
fn texts_are_placed_for_a_caller_with_a_font() {
    let r = read_dxf(&data("made_by_ezdxf.dxf"), "t.dxf", &DxfOptions::default()).unwrap();
    assert_eq!(r.texts.len(), 1);
    let t = &r.texts[0];
    assert_eq!(t.text, "Oficina");
    assert!(
        t.at.distance(oficina_geom::Point::new(500.0, 10.0)) < 1e-9
            && (t.height - 5.0).abs() < 1e-12
    );
    // A TEXT in a block inserted at (10, 0), turned 90° and scaled 2: the baseline turns, the
    // height doubles; MTEXT codes are removed.
    let s = pairs(&[
        ("0", "SECTION"),
        ("2", "BLOCKS"),
        ("0", "BLOCK"),
        ("2", "T"),
        ("10", "0"),
        ("20", "0"),
        ("0", "TEXT"),
        ("8", "0"),
        ("10", "1"),
        ("20", "0"),
        ("40", "2.5"),
        ("1", "%%c6 H7"),
        ("0", "ENDBLK"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "INSERT"),
        ("8", "marks"),
        ("2", "T"),
        ("10", "10"),
        ("20", "0"),
        ("41", "2"),
        ("42", "2"),
        ("50", "90"),
        ("0", "MTEXT"),
        ("8", "notes"),
        ("10", "0"),
        ("20", "50"),
        ("40", "3"),
        ("71", "1"),
        ("1", r"{\fArial;Part\P}rev \H2x;B"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ]);
    let no_text = DxfOptions {
        draw_text: false,
        ..DxfOptions::default()
    };
    let r = read_dxf(s.as_bytes(), "t.dxf", &no_text).unwrap();
    let t = &r.texts[0];
    assert_eq!((t.text.as_str(), t.layer.as_str()), ("⌀6 H7", "marks"));
    assert!(
        t.at.distance(oficina_geom::Point::new(10.0, 2.0)) < 1e-9,
        "{:?}",
        t.at
    );
    assert!(
        (t.height - 5.0).abs() < 1e-12 && (t.angle - std::f64::consts::FRAC_PI_2).abs() < 1e-12
    );
    let m = &r.texts[1];
    assert_eq!(m.text, "Part\nrev B");
    assert!(
        m.at.distance(oficina_geom::Point::new(0.0, 47.0)) < 1e-9,
        "{:?}",
        m.at
    );
    assert_eq!(
        r.imported.unsupported.total(),
        2,
        "{}",
        r.imported.unsupported
    );
    // Attributes of a 5 × 5 array: one string per cell and attribute.
    let opts = DxfOptions {
        max_size_mm: f64::INFINITY,
        ..DxfOptions::default()
    };
    let r = read_dxf(&data("ezdxf_multi_insert_with_attribs.dxf"), "m.dxf", &opts).unwrap();
    assert_eq!(r.texts.len(), 75);
}

#[test]
fn block_and_layer_names_ignore_case() {
    let s = pairs(&[
        ("0", "SECTION"),
        ("2", "TABLES"),
        ("0", "TABLE"),
        ("2", "LAYER"),
        ("0", "LAYER"),
        ("2", "Cut"),
        ("62", "1"),
        ("0", "ENDTAB"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "BLOCKS"),
        ("0", "BLOCK"),
        ("2", "Part"),
        ("10", "0"),
        ("20", "0"),
        ("0", "CIRCLE"),
        ("8", "0"),
        ("10", "0"),
        ("20", "0"),
        ("40", "3"),
        ("0", "ENDBLK"),
        ("0", "ENDSEC"),
        ("0", "SECTION"),
        ("2", "ENTITIES"),
        ("0", "INSERT"),
        ("8", "CUT"),
        ("2", "PART"),
        ("10", "5"),
        ("20", "5"),
        ("0", "ENDSEC"),
        ("0", "EOF"),
    ]);
    let i = dxf_from_bytes(s.as_bytes(), "case.dxf").unwrap();
    let p = i.drawing.paths().next().unwrap();
    assert_eq!(p.style.stroke, Some(Color::rgb(255, 0, 0)));
    assert!((p.length() - 6.0 * std::f64::consts::PI).abs() < 1e-9);
}
