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
    let h = parse("IN;VS10;FT3;SP1;PD10,10;");
    assert_eq!(h.imported.unsupported.counts.get("VS"), Some(&1));
    assert_eq!(h.imported.unsupported.counts.get("FT"), Some(&1));
}

#[test]
fn filled_rectangles_are_edged_by_ep_and_their_fill_noted() {
    // hp2xx's ft.hp: RR then EP draws the rectangle's outline; the fill is not drawn.
    let h = parse("IN;SP1;PA2000,2000;FT;RR2500,300;EP;PR0,300;RR2500,300;");
    let d = &h.imported.drawing;
    assert_eq!(d.path_count(), 1);
    let r = d.layers[0].paths[0].bounding_box().unwrap();
    assert_eq!((r.x0, r.y0, r.x1, r.y1), (50.0, 50.0, 112.5, 57.5));
    assert_eq!(
        h.imported
            .unsupported
            .counts
            .get("RR fill (its outline is drawn by EP)"),
        Some(&2)
    );
}

#[test]
fn line_types_are_drawn_as_the_pen_draws_them() {
    // LT2 with a 10 mm pattern (mode 1: mm) on a 25 mm line: down 0–5, 10–15, 20–25.
    let h = parse("IN;SP1;LT2,10,1;PU0,0;PD1000,0;LT;PU0,400;PD1000,400;");
    let d = &h.imported.drawing;
    assert_eq!(d.path_count(), 4, "three dashes and the solid line");
    let total: f64 = d.paths().map(|p| p.length()).sum();
    assert!((total - (15.0 + 25.0)).abs() < 1e-9, "{total}");
    // Relative pattern length: 4 % of P1–P2's diagonal (5000 units = 125 mm → 5 mm).
    let h = parse("IN;IP0,0,3000,4000;SP1;LT2,4;PU0,0;PD400,0;");
    let d = &h.imported.drawing;
    assert_eq!(d.path_count(), 2);
    assert!((d.layers[0].paths[1].start().unwrap().x - 5.0).abs() < 1e-9);
    // A pattern of a micron along 25 km is not dashed into billions of pieces.
    let h = parse("IN;SP1;LT2,0.001,1;PU0,0;PD999999999,0;");
    assert_eq!(h.imported.drawing.path_count(), 1);
    assert!(h
        .imported
        .unsupported
        .counts
        .keys()
        .any(|k| k.contains("drawn solid")));
    let e = hpgl_from_bytes(b"IN;LT2,-1;", "x.plt").unwrap_err();
    assert!(e.message.contains("pattern length"), "{e}");
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
    let e = hpgl_from_bytes(b"\n\n%%garbage;IN;", "x.plt").unwrap_err();
    assert_eq!(e.location, "line 3, column 1");
    // Inside a plot, text that is not HP-GL is skipped to the next ';' and counted…
    let h = hpgl_from_bytes(b"IN;SP1;\nX0=0;Y0=0;\nPD10,10;", "x.plt").unwrap();
    let (k, n) = h.imported.unsupported.counts.iter().next().unwrap();
    assert!(k.contains("not HP-GL") && *n == 2, "{k}: {n}");
    // …but a file that is mostly such text is refused.
    let e = hpgl_from_bytes(
        b"IN;\n%%%% this is a letter, not a plot; it goes on and on",
        "x.plt",
    )
    .unwrap_err();
    assert!(e.message.contains("mostly not HP-GL"), "{e}");
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

/// `PE` digits of `v` (base 64, 8-bit): the sign in the low bit, least significant first.
fn pe(v: i64) -> Vec<u8> {
    let mut u = if v < 0 {
        (v.unsigned_abs() << 1) | 1
    } else {
        (v as u64) << 1
    };
    let mut out = Vec::new();
    loop {
        let d = (u & 63) as u8;
        u >>= 6;
        if u == 0 {
            out.push(191 + d);
            return out;
        }
        out.push(63 + d);
    }
}

#[test]
fn values_round_trip_through_the_encoding() {
    // `>f` fractional bits, then a relative pen-down move of (v, 0) from (0, 0), in plotter
    // units (40 a millimetre); the value read is v rounded to 2^-f units.
    for f in [0, 1, 5] {
        for v in [0.0, 1.0, -1.0, 31.0, 32.0, -1000.5, 123456.25, 8.0e8] {
            let scaled = |v: f64| (v * f64::powi(2.0, f)).round() as i64;
            let mut b = b"IN;SP1;PA0,0;PE>".to_vec();
            b.extend(pe(f.into()));
            b.extend(pe(scaled(v)));
            b.extend(pe(0));
            b.extend(b";");
            let h = hpgl_from_bytes(&b, "t.plt").unwrap_or_else(|e| panic!("{e}"));
            let want = scaled(v) as f64 / f64::powi(2.0, f) / 40.0;
            let layers = &h.imported.drawing.layers;
            let end = layers.first().and_then(|l| l.paths.last()?.end());
            if v == 0.0 {
                assert!(end.is_none_or(|e| e.x == 0.0), "{end:?}");
                continue;
            }
            let e = end.unwrap_or_else(|| panic!("{v} with {f} bits: no path"));
            assert!(
                (e.x - want).abs() < 1e-9 && e.y == 0.0,
                "{v} with {f} bits: {e:?}"
            );
        }
    }
}

#[test]
fn polyline_encoded_moves_decode_as_the_hpgl2_reference_encodes_them() {
    // A 100 × 50 mm rectangle: pen-up absolute move to (400, 400), then relative pen-down sides.
    let mut b = b"IN;SP1;PE<=".to_vec();
    for v in [400, 400] {
        b.extend(pe(v));
    }
    for (x, y) in [(4000, 0), (0, 2000), (-4000, 0), (0, -2000)] {
        b.extend(pe(x));
        b.extend(pe(y));
    }
    b.extend(b";PU;");
    let h = hpgl_from_bytes(&b, "pe.plt").unwrap_or_else(|e| panic!("{e}"));
    let d = &h.imported.drawing;
    assert_eq!(d.path_count(), 1);
    let p = &d.layers[0].paths[0];
    assert_eq!(p.start().unwrap(), oficina_geom::Point::new(10.0, 10.0));
    assert!((p.length() - 300.0).abs() < 1e-9, "{}", p.length());
    // Fractional bits: >k then values × 2^k; `:2` selects pen 2. 7-bit mode: base 32.
    let mut b = b"IN;PE:".to_vec();
    b.extend(pe(2));
    b.extend(b">");
    b.extend(pe(3));
    b.extend(pe(8 * 40)); // 40.0 units = 1 mm
    b.extend(pe(-4)); // -0.5 units
    b.extend(b";");
    let h = hpgl_from_bytes(&b, "frac.plt").unwrap();
    let p = &h.imported.drawing.layers[0];
    assert_eq!(p.name, "pen 2");
    let e = p.paths[0].end().unwrap();
    assert!(
        (e.x - 1.0).abs() < 1e-12 && (e.y + 0.5 / 40.0).abs() < 1e-12,
        "{e:?}"
    );
    // 7-bit: 10 → 20 → one terminating digit 95 + 20.
    let h = hpgl_from_bytes(
        &[b"IN;PE7".as_slice(), &[95 + 20, 95], b";"].concat(),
        "7.plt",
    )
    .unwrap();
    let e = h.imported.drawing.layers[0].paths[0].end().unwrap();
    assert!((e.x - 0.25).abs() < 1e-12 && e.y == 0.0, "{e:?}");
}

#[test]
fn truncated_and_broken_pe_is_refused_with_its_place() {
    let e = hpgl_from_bytes(b"IN;SP1;\nPE<=\x40\x41", "cut.plt").unwrap_err();
    assert!(e.message.contains("truncated PE"), "{e}");
    assert!(
        e.location.starts_with("line 2, column 7, PE"),
        "{}",
        e.location
    );
    let e = hpgl_from_bytes(b"IN;PE\x40;", "x.plt").unwrap_err();
    assert!(e.message.contains("cut short"), "{e}");
    let e = hpgl_from_bytes(b"IN;PE\x01;", "x.plt").unwrap_err();
    assert!(e.message.contains("neither a PE flag"), "{e}");
    // 11 digits of 6 bits: more than 60 bits.
    let mut b = b"IN;PE".to_vec();
    b.extend([100u8; 11]);
    b.push(200);
    let e = hpgl_from_bytes(&b, "x.plt").unwrap_err();
    assert!(e.message.contains("60 bits"), "{e}");
}

#[test]
fn scaling_maps_user_units_onto_p1_p2() {
    // IP 0,0,4000,4000 (100 mm square), SC 0,10,0,10: one user unit = 10 mm.
    let h = parse("IN;IP0,0,4000,4000;SC0,10,0,10;SP1;PU1,1;PD9,1;PR0,2;PU;");
    let p = &h.imported.drawing.layers[0].paths[0];
    assert_eq!(p.start().unwrap(), oficina_geom::Point::new(10.0, 10.0));
    assert_eq!(p.end().unwrap(), oficina_geom::Point::new(90.0, 30.0));
    // Isotropic SC (type 1) on a 200 × 100 mm P1–P2: 10 mm per unit, centred in x.
    let h = parse("IN;IP0,0,8000,4000;SC0,10,0,10,1;SP1;PU0,0;PD10,10;");
    let p = &h.imported.drawing.layers[0].paths[0];
    assert_eq!(p.start().unwrap(), oficina_geom::Point::new(50.0, 0.0));
    assert_eq!(p.end().unwrap(), oficina_geom::Point::new(150.0, 100.0));
    // Isotropic circles stay circular arcs: CI 1 unit = 10 mm radius.
    let h = parse("IN;IP0,0,4000,4000;SC0,10,0,10;SP1;PA5,5;CI1;");
    let c = &h.imported.drawing.layers[0].paths[0];
    assert!((c.length() - 20.0 * std::f64::consts::PI).abs() < 1e-9);
    // IR: P1, P2 at 0 % and 50 % of the hard-clip limits (0…33600, 0…47520 units).
    let h = parse("IN;IR0,0,50,50;SC0,10,0,10;SP1;PU0,0;PD10,10;");
    let e = h.imported.drawing.layers[0].paths[0].end().unwrap();
    assert!(
        (e.x - 420.0).abs() < 1e-9 && (e.y - 594.0).abs() < 1e-9,
        "{e:?}"
    );
    let e = hpgl_from_bytes(b"IN;SC0,0,0,10;", "x.plt").unwrap_err();
    assert!(e.message.contains("min and max must differ"), "{e}");
}

#[test]
fn hpgl2_inside_pcl_and_device_control_escapes_are_read() {
    // PCL reset, UEL with PJL, PCL raster data (with bytes that look like HP-GL), then HP-GL/2
    // between ESC%1B and ESC%0A.
    let mut b =
        b"\x1bE\x1b%-12345X@PJL JOB\r\n@PJL ENTER LANGUAGE=PCL\r\n\x1b*r1A\x1b*b4W".to_vec();
    b.extend(b"PD99");
    b.extend(b"\x1b*rB\x1b%1BIN;SP1;PU0,0;PD400,0;PU;\x1b%0A\x1bE\x1b%-12345X");
    let h = hpgl_from_bytes(&b, "job.prn").unwrap_or_else(|e| panic!("{e}"));
    let d = &h.imported.drawing;
    assert_eq!(d.path_count(), 1);
    assert!((d.layers[0].paths[0].length() - 10.0).abs() < 1e-9);
    assert!(h
        .imported
        .unsupported
        .counts
        .keys()
        .any(|k| k.contains("PCL")));
    // A raster print job (PCL alone) is not a plot.
    let e = hpgl_from_bytes(b"\x1bE\x1b*r1A\x1b*b2WPD\x1b*rB\x0c\x1bE", "page.prn").unwrap_err();
    assert!(e.message.contains("PCL without HP-GL/2"), "{e}");
    // Device control, no newlines, lower case, trailing commas, no separators.
    let h = parse(
        "\x1b.(;\x1b.I81;;17:\x1b.N;19:in;sp1;pu0,0,;pd400,0,400,400,;pu;PA800,800PD1200,800PU",
    );
    assert_eq!(h.imported.drawing.path_count(), 2);
}

#[test]
fn absurd_numbers_are_refused_with_the_instruction() {
    for (src, what) in [
        (&b"IN;PA1e12,0;"[..], "PA"),
        (b"IN;IP0,0,1,1;SC0,1e-300,0,1;PD1,1;", "PD"),
        (b"IN;SC0,1,0,1;PA9e8,0;", "PA"),
        (b"IN;SP300;", "SP"),
        // 2^48 units: beyond the ±1e9 limit.
        (b"IN;PE~~~~~~~~\xc0;", "PE"),
    ] {
        let e = hpgl_from_bytes(src, "x.plt").unwrap_err();
        assert!(
            e.location.contains(what),
            "{}: {e}",
            String::from_utf8_lossy(src)
        );
    }
}

#[test]
fn drawings_are_hpgl_by_content_whatever_the_extension() {
    let dir = std::env::temp_dir().join(format!("oficina-sniff-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["a.hp", "b.000", "c.prn", "d.txt", "e"] {
        let f = dir.join(name);
        std::fs::write(&f, "IN;SP1;PU0,0;PD400,0;").unwrap();
        let i = oficina_io::load_drawing(&f).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(i.drawing.path_count(), 1, "{name}");
    }
    let f = dir.join("x.hpgl");
    std::fs::write(&f, "").unwrap();
    let e = oficina_io::load_drawing(&f).unwrap_err();
    assert!(
        e.to_string().contains("x.hpgl") && e.message.contains("0 bytes"),
        "{e}"
    );
    let f = dir.join("notes.foo");
    std::fs::write(&f, "Dear plotter").unwrap();
    let e = oficina_io::load_drawing(&f).unwrap_err();
    assert!(e.message.contains("not HP-GL by its content"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn three_point_arcs_and_the_pen_after_a_label() {
    // AT from (10, 0) mm through (0, 10) to (-10, 0): a half circle of radius 10 mm about the
    // origin; RT the same relative; collinear points draw straight lines.
    let h = parse("IN;SP1;PU400,0;PD;AT0,400,-400,0;PU;PA400,4000;PD;RT-400,400,-800,0;PU;PA0,0;PD;AT100,0,200,0;");
    let p = &h.imported.drawing.layers[0].paths;
    assert_eq!(p.len(), 3);
    for k in 0..2 {
        assert!(
            (p[k].length() - std::f64::consts::PI * 10.0).abs() < 1e-9,
            "{}",
            p[k].length()
        );
    }
    assert!((p[1].end().unwrap().x + 10.0).abs() < 1e-9);
    assert!((p[2].length() - 5.0).abs() < 1e-9);
    let e = hpgl_from_bytes(b"IN;AT1,2;", "x.plt").unwrap_err();
    assert!(e.location.contains("AT"), "{e}");
    // After "AB" (two cells of 1.5 × 2.85 mm) the pen is 8.55 mm further on; PR goes from there.
    let h = parse("IN;SP1;PA0,0;LBAB\x03PD;PR400,0;");
    let s = h.imported.drawing.layers[0].paths[0].start().unwrap();
    assert!((s.x - 8.55).abs() < 1e-9 && s.y.abs() < 1e-9, "{s:?}");
}
