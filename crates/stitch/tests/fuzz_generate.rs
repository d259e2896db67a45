//! Random drawings: generation never panics, every point is finite, no sewn stitch is longer
//! than the machine's, and the file writers accept the result.

use oficina_geom::{Color, Drawing, Path, Point};
use oficina_stitch::{generate, generate_inkstitch, read_inkstitch, Format, Kind, Params};
use proptest::prelude::*;

fn drawing(shapes: &[(Vec<(i16, i16)>, bool, u8, u8)]) -> Drawing {
    let mut d = Drawing::new();
    for (i, (pts, closed, kind, width)) in shapes.iter().enumerate() {
        let pts: Vec<Point> = pts
            .iter()
            .map(|&(x, y)| Point::new(x as f64 / 50.0, y as f64 / 50.0))
            .collect();
        let mut p = Path::polyline(&pts, *closed);
        // Pairs share an element: two open strokes of one element are satin rails.
        p.source.element = format!("#p{}", i / 2);
        match kind % 3 {
            0 => {
                p.style.fill = Some(Color::rgb(200, 0, 0));
                p.style.stroke = None;
            }
            1 => p.style.stroke_width = *width as f64 / 20.0, // satin when ≥ 1 mm
            _ => p.style.stroke_width = 0.2,
        }
        d.push("0", p);
    }
    d
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]

    #[test]
    fn generation_is_total(
        shapes in proptest::collection::vec(
            (proptest::collection::vec((-2000i16..2000, -2000i16..2000), 1..8), any::<bool>(), any::<u8>(), 0u8..255),
            1..5),
        angle in -90.0f64..90.0,
        underlay: bool,
    ) {
        let d = drawing(&shapes);
        let p = Params { fill_angle_deg: angle, underlay, ..Params::default() };
        let Ok(g) = generate(&d, "fuzz", &p, &mut |_, _| {}) else { return Ok(()) };
        let mut prev = (0.0f64, 0.0f64);
        for (_, s) in g.plan.entries() {
            prop_assert!(s.x.is_finite() && s.y.is_finite(), "{s:?}");
            if s.kind == Kind::Stitch {
                let d = (s.x - prev.0).hypot(s.y - prev.1);
                prop_assert!(d <= p.max_stitch + 1e-6, "stitch of {d} mm");
            }
            prev = (s.x, s.y);
        }
        for f in Format::EVERY {
            prop_assert!(f.write(&g.plan).is_ok());
        }
    }
}

/// Ink/Stitch attributes for element `#p{i}` from random choices.
fn ink_attrs(i: usize, c: &[u8; 8], x: f64) -> String {
    let method = [
        "running_stitch",
        "manual_stitch",
        "zigzag_stitch",
        "ripple_stitch",
    ];
    let fill = ["auto_fill", "contour_fill", "legacy_fill"];
    let rails = ["automatic", "none", "first", "second", "both"];
    format!(
        r#"<path id="p{i}" inkstitch:satin_column="{}" inkstitch:stroke_method="{}"
             inkstitch:running_stitch_length_mm="{}" inkstitch:repeats="{}"
             inkstitch:bean_stitch_repeats="{}" inkstitch:zigzag_spacing_mm="{}"
             inkstitch:pull_compensation_mm="{}" inkstitch:e_stitch="{}"
             inkstitch:center_walk_underlay="{}" inkstitch:contour_underlay="{}"
             inkstitch:zigzag_underlay="{}" inkstitch:angle="{}" inkstitch:row_spacing_mm="{}"
             inkstitch:fill_method="{}" inkstitch:fill_underlay="{}"
             inkstitch:fill_underlay_angle="{} {}" inkstitch:fill_underlay_inset_mm="{}"
             inkstitch:trim_after="{}" inkstitch:stop_after="{}" inkstitch:ties="{}"
             inkstitch:min_stitch_length_mm="{}" inkstitch:reverse_rails="{}"
             inkstitch:max_stitch_length_mm="{}" inkstitch:expand_mm="{}"/>"#,
        c[0].is_multiple_of(2),
        method[c[1] as usize % 4],
        0.3 + x * 5.0,
        1 + c[2] % 4,
        c[3] % 3,
        0.2 + x,
        x - 0.3,
        c[4].is_multiple_of(3),
        c[4].is_multiple_of(2),
        c[5].is_multiple_of(2),
        c[6].is_multiple_of(2),
        x * 360.0 - 180.0,
        0.2 + x * 2.0,
        fill[c[7] as usize % 3],
        !c[0].is_multiple_of(3),
        x * 90.0,
        -x * 45.0,
        x - 0.2,
        c[1].is_multiple_of(5),
        c[2].is_multiple_of(7),
        c[3] % 4,
        x * 0.5,
        rails[c[5] as usize % 5],
        1.0 + x * 20.0,
        x * 2.0 - 1.0,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// The same with random Ink/Stitch parameters on every element: satin columns of any
    /// subpaths (rails and rungs), every stroke method, fill method and underlay.
    #[test]
    fn inkstitch_generation_is_total(
        shapes in proptest::collection::vec(
            (proptest::collection::vec((-2000i16..2000, -2000i16..2000), 1..8), any::<bool>(), any::<u8>(), 0u8..255),
            1..7),
        choices in proptest::collection::vec(any::<[u8; 8]>(), 4),
        x in 0.0f64..1.0,
    ) {
        let d = drawing(&shapes);
        let body: String = (0..4).map(|i| ink_attrs(i, &choices[i], x)).collect();
        let svg = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkstitch="{}">{body}</svg>"#,
            oficina_stitch::INKSTITCH_NAMESPACE
        );
        let ink = read_inkstitch(&svg, "fuzz.svg").unwrap();
        let p = Params::default();
        let Ok(g) = generate_inkstitch(&d, "fuzz", &p, &ink, &mut |_, _| {}) else { return Ok(()) };
        let mut prev = (0.0f64, 0.0f64);
        for (_, s) in g.plan.entries() {
            prop_assert!(s.x.is_finite() && s.y.is_finite(), "{s:?}");
            if s.kind == Kind::Stitch {
                let d = (s.x - prev.0).hypot(s.y - prev.1);
                prop_assert!(d <= p.max_stitch + 1e-6, "stitch of {d} mm");
            }
            prev = (s.x, s.y);
        }
        for f in Format::EVERY {
            prop_assert!(f.write(&g.plan).is_ok());
        }
    }
}
