//! Drawings cut by the tests of more than one crate (CAM, post, CLI).

use oficina_geom::{Path, Point};

/// The closed polyline through `pts`.
pub fn poly(pts: &[(f64, f64)]) -> Path {
    let p: Vec<Point> = pts.iter().map(|&(x, y)| Point::new(x, y)).collect();
    Path::polyline(&p, true)
}

/// Two 25 × 25 rooms joined by a 10 mm long, 7 mm wide corridor: concave corners on both
/// sides, and with a 6 mm tool the offsets split in two.
pub fn dumbbell() -> Vec<Path> {
    vec![poly(&[
        (0.0, 0.0),
        (25.0, 0.0),
        (25.0, 9.0),
        (35.0, 9.0),
        (35.0, 0.0),
        (60.0, 0.0),
        (60.0, 25.0),
        (35.0, 25.0),
        (35.0, 16.0),
        (25.0, 16.0),
        (25.0, 25.0),
        (0.0, 25.0),
    ])]
}
