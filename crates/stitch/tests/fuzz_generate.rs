//! Random drawings: generation never panics, every point is finite, no sewn stitch is longer
//! than the machine's, and the file writers accept the result.

use oficina_geom::{Color, Drawing, Path, Point};
use oficina_stitch::{generate, Format, Kind, Params};
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
