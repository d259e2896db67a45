//! grbl's arcs over Oficina's one arc module (`oficina_geom`'s arcs): the geometry (plane
//! axes, centre from IJK or R, sweep, points on the helix) is geom's; what stays here is what
//! grbl decides itself: its error numbers, its tolerance on the end radius (gcode.c), and how
//! many chords mc_arc cuts an arc into (so the emulator's planner holds as many blocks as the
//! firmware's would).

use super::{E_ARC_RADIUS, E_INVALID_TARGET, E_NO_OFFSETS_IN_PLANE};
use oficina_geom::{
    center_from_offsets, center_from_radius, ArcError, ArcTolerance, Helix, Plane, Point,
};

/// gcode.c's checks: a centre's end radius may differ from its start radius by 0.005 mm, or
/// up to 0.5 mm and 0.1 % of the start radius ([`ArcTolerance::GRBL`]). grbl has no
/// zero-radius check and no slack on R (`4r² − d² < 0` is error 33), hence `radius: 0`.
const TOLERANCE: ArcTolerance = ArcTolerance {
    radius: 0.0,
    ..ArcTolerance::GRBL
};

/// G17 / G18 / G19 from grbl's plane number (0, 1, 2).
pub(super) fn plane(n: u8) -> Plane {
    match n {
        1 => Plane::XZ,
        2 => Plane::YZ,
        _ => Plane::XY,
    }
}

/// Arc centre (in-plane coordinates) from R or IJK (offsets from the start), with grbl's
/// error numbers.
pub(super) fn center(
    from: [f64; 3],
    to: [f64; 3],
    plane: Plane,
    cw: bool,
    r: Option<f64>,
    ijk: [Option<f64>; 3],
) -> Result<[f64; 2], u8> {
    let (a0, a1, _) = plane.axes();
    let (start, end) = (plane.project(from), plane.project(to));
    let c = match r {
        Some(r) => center_from_radius(start, end, r, cw, &TOLERANCE).map_err(|e| match e {
            ArcError::RadiusTooSmall { .. } => E_ARC_RADIUS,
            _ => E_INVALID_TARGET,
        })?,
        None => {
            if ijk[a0].is_none() && ijk[a1].is_none() {
                return Err(E_NO_OFFSETS_IN_PLANE);
            }
            let off = Point::new(ijk[a0].unwrap_or(0.0), ijk[a1].unwrap_or(0.0));
            center_from_offsets(start, end, start + off.to_vec2(), &TOLERANCE)
                .map_err(|_| E_INVALID_TARGET)?
        }
    };
    Ok([c.x, c.y])
}

/// Chord end points of an arc (the end included), as many as grbl's mc_arc cuts: chords of
/// length `√(tol·(2r − tol))` (a chord whose sagitta is the $12 tolerance), i.e.
/// `⌊½·|sweep|·r / chord⌋` segments.
pub(super) fn chords(
    from: [f64; 3],
    to: [f64; 3],
    center: [f64; 2],
    plane: Plane,
    cw: bool,
    tolerance: f64,
) -> Vec<[f64; 3]> {
    let helix = Helix::new(plane, from, to, center, if cw { -1 } else { 1 });
    let (radius, sweep) = (helix.arc.radius, helix.arc.sweep);
    let tol = tolerance.max(1e-6);
    let chord = (tol * (2.0 * radius - tol)).max(1e-12).sqrt();
    let segments = ((0.5 * sweep * radius).abs() / chord)
        .floor()
        .min(100_000.0) as usize;
    let mut pts: Vec<[f64; 3]> = (1..segments)
        .map(|k| helix.point_at(k as f64 / segments as f64))
        .collect();
    pts.push(to);
    pts
}
