//! The shipped size-34 sole contour through the geometry pipeline: fitting (blocks and
//! deviation per method), offsets against GEOS, grading 33–44, mirroring.

use oficina_geom::fit::{fit_all, Method};
use oficina_geom::{
    mirror_path, offset_areas, Area, Grading, MirrorAxis, Path, Point, Reference, Segment,
    SizeSystem,
};

// Read by hand on purpose: the point-list reader lives in oficina_io, which depends on this
// crate (the shipped file is plain `x,y` lines).
fn sample() -> Vec<Point> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/sole/size34.csv");
    std::fs::read_to_string(p)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_digit() || c == '-'))
        .map(|l| {
            let (x, y) = l.split_once(',').unwrap();
            Point::new(x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

#[test]
fn polygon_offsets_match_geos_areas_and_splits() {
    // shapely 2.2.0 (GEOS) on the same 80-point polygon: Polygon(pts).buffer(d, quad_segs=512),
    // area and number of polygons. At −26 mm the waist pinches the pocket in two.
    let geos = [
        (-2.0, 12280.1755, 1),
        (-8.0, 9264.8054, 1),
        (-20.0, 3915.0203, 1),
        (-26.0, 1665.7424, 2),
        (-29.0, 976.4286, 1),
        (-32.0, 569.8975, 1),
        (3.0, 14966.275, 1),
        (8.0, 17809.4908, 1),
    ];
    let contour = Area::from_paths(&[Path::polyline(&sample(), true)]);
    for (d, area, count) in geos {
        let out = offset_areas(&contour, d, 0.001).unwrap();
        assert_eq!(out.len(), count, "d={d}");
        let a: f64 = out.iter().map(Area::area).sum();
        assert!((a - area).abs() / area < 2e-4, "d={d}: {a} vs GEOS {area}");
        if d > 0.0 {
            // Growing a polygon rounds its convex corners: arcs of radius d.
            let arcs = out[0].outer.counts().1;
            assert!(arcs > 10, "d={d}: {arcs} arcs");
        }
    }
}

#[test]
fn fitting_report_on_the_sample() {
    let pts = sample();
    let all = fit_all(&pts, 0.1);
    for (m, r) in &all {
        let f = r.as_ref().unwrap_or_else(|e| panic!("{m}: {e}"));
        eprintln!(
            "{:<28} control {:>3} blocks {:>4} max dev {:.3} mm",
            m.name(),
            f.control_points,
            f.blocks,
            f.max_deviation
        );
    }
    let get = |m| {
        all.iter()
            .find(|(x, _)| *x == m)
            .unwrap()
            .1
            .as_ref()
            .unwrap()
    };
    let tc = get(Method::TangentCircles);
    assert_eq!(
        tc.path.counts(),
        (0, tc.blocks, 0),
        "tangent circles: only arcs"
    );
    assert!(tc.max_deviation < 1.0, "{}", tc.max_deviation);
    let biarc = get(Method::Biarc);
    assert!(biarc.max_deviation <= 0.1 + 1e-9);
    let interp = get(Method::Interpolation);
    assert!(tc.blocks < interp.blocks && biarc.blocks < interp.blocks);
}

#[test]
fn fitted_arcs_offset_as_arcs_and_grade_and_mirror() {
    let pts = sample();
    let all = fit_all(&pts, 0.1);
    let tc = &all
        .iter()
        .find(|(m, _)| *m == Method::TangentCircles)
        .unwrap()
        .1
        .as_ref()
        .unwrap()
        .path;
    // Finishing offset of the cavity for a 16 mm cutter: 8 mm in. Arcs keep their centres.
    let inset = offset_areas(&Area::from_paths(std::slice::from_ref(tc)), -8.0, 0.001).unwrap();
    assert_eq!(inset.len(), 1);
    let centres: Vec<Point> = tc
        .segments
        .iter()
        .filter_map(|s| {
            if let Segment::Arc(a) = s {
                Some(a.center)
            } else {
                None
            }
        })
        .collect();
    let arcs: Vec<_> = inset[0]
        .outer
        .segments
        .iter()
        .filter_map(|s| {
            if let Segment::Arc(a) = s {
                Some(*a)
            } else {
                None
            }
        })
        .collect();
    // A simple closed G1 poly-arc turns once: its sweeps add up to 2π.
    let turning: f64 = tc
        .segments
        .iter()
        .map(|s| {
            if let Segment::Arc(a) = s {
                a.sweep
            } else {
                0.0
            }
        })
        .sum();
    assert!((turning - std::f64::consts::TAU).abs() < 1e-6, "{turning}");
    assert_eq!(
        inset[0].outer.counts(),
        (0, centres.len(), 0),
        "every arc kept as an arc"
    );
    assert!(
        arcs.len() * 2 >= centres.len(),
        "{} arcs of {}",
        arcs.len(),
        centres.len()
    );
    assert!(arcs
        .iter()
        .all(|a| centres.iter().any(|c| c.distance(a.center) < 1e-9)
            || (a.radius - 8.0).abs() < 1e-9));

    // Grading 33–44 from 34 in one call; mirrored about x = 100 for the right foot.
    let g = Grading::for_points(&pts, SizeSystem::BRAZILIAN, 34.0, 0.0, Reference::Heel).unwrap();
    let sizes: Vec<f64> = (33..=44).map(f64::from).collect();
    let run = g.run(&pts, &sizes).unwrap();
    let len = |q: &[Point]| {
        q.iter().map(|p| p.y).fold(f64::MIN, f64::max)
            - q.iter().map(|p| p.y).fold(f64::MAX, f64::min)
    };
    for (s, q) in &run {
        assert!((len(q) - (len(&pts) + (s - 34.0) * 6.66)).abs() < 1e-9);
    }
    let right = mirror_path(tc, MirrorAxis::X(100.0));
    assert!((right.area() + tc.area()).abs() < 1e-6 * tc.area().abs());
}
