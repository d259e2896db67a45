//! Rest machining: what a smaller tool must still cut after a larger one (seed 001 §7: the
//! 6 mm mill for "all offsets except the last", the 1 mm bit for the finishing offsets).
//!
//! A tool of radius r kept inside the region R can sweep exactly the opening of R by r,
//! open(R, r) = dilate(erode(R, r), r): the union of the discs of radius r inside R. It
//! leaves rest(R, r) = R − open(R, r): corners tighter than r, features narrower than 2r.
//! The next tool (radius r₂) pockets Q = R ∩ dilate(rest, 2·r₂): a disc of radius r₂ inside
//! R that touches the rest lies within 2·r₂ of it, hence inside Q, so pocketing Q reaches
//! all of the rest that r₂ can reach, and Q ⊂ R keeps every cut inside the region.

use super::pocket::{pocket, PocketParams, Strategy};
use super::profile::OFFSET_TOL;
use super::{Cut, OpError};
use crate::Operation;
use oficina_geom::{boolean, offset_areas, Area, BoolOp, Fill, Path, Point, Region, Ring};

/// Rest thinner than twice this (mm) is dropped: the offsets' own tolerance leaves slivers
/// of a few µm along every wall, and no tool is worth sending for less.
pub(super) const SLIVER: f64 = 0.02;

fn geo(e: oficina_geom::PolygonError) -> OpError {
    OpError::Geometry(e.to_string())
}

fn rings(areas: &[Area]) -> Vec<Ring> {
    areas
        .iter()
        .flat_map(|a| {
            let r = a.to_region(OFFSET_TOL / 2.0);
            std::iter::once(r.outer).chain(r.holes)
        })
        .collect()
}

fn areas_of(regions: &[Region]) -> Vec<Area> {
    let paths: Vec<Path> = regions
        .iter()
        .flat_map(|r| std::iter::once(&r.outer).chain(&r.holes))
        .filter(|ring| ring.len() >= 3)
        .map(|ring| {
            let pts: Vec<Point> = ring.iter().map(|p| Point::new(p[0], p[1])).collect();
            Path::polyline(&pts, true)
        })
        .collect();
    Area::from_paths(&paths)
}

/// The part of `region` a tool of radius `r` cannot reach: rest(R, r) above, less slivers.
pub fn rest(region: &[Area], r: f64) -> Result<Vec<Area>, OpError> {
    let eroded = offset_areas(region, -r, OFFSET_TOL).map_err(geo)?;
    let opened = offset_areas(&eroded, r, OFFSET_TOL).map_err(geo)?;
    let left = boolean(
        &rings(region),
        &rings(&opened),
        BoolOp::Difference,
        Fill::NonZero,
    )
    .map_err(geo)?;
    let left = areas_of(&left);
    // Open the rest by SLIVER: the wall slivers vanish, real corners keep their body.
    let thin = offset_areas(&left, -SLIVER, OFFSET_TOL).map_err(geo)?;
    offset_areas(&thin, SLIVER, OFFSET_TOL).map_err(geo)
}

/// The pocket the next tool clears: Q = R ∩ dilate(rest, 2·r₂) (empty when nothing is left).
pub fn rest_pocket(region: &[Area], prev_r: f64, next_r: f64) -> Result<Vec<Area>, OpError> {
    let left = rest(region, prev_r)?;
    if left.is_empty() {
        return Ok(vec![]);
    }
    let grown = offset_areas(&left, 2.0 * next_r, OFFSET_TOL).map_err(geo)?;
    let q = boolean(
        &rings(region),
        &rings(&grown),
        BoolOp::Intersection,
        Fill::NonZero,
    )
    .map_err(geo)?;
    Ok(areas_of(&q))
}

/// Rest machining as one operation: `cut`'s tool pockets what a tool of radius `prev_r`
/// left in `region`, contour-parallel, 0.6·D apart, to size. `None` when nothing is left
/// or nothing left is wide enough for this tool.
pub fn rest_machining(
    name: &str,
    region: &[Area],
    prev_r: f64,
    cut: &Cut,
) -> Result<Option<Operation>, OpError> {
    if !(prev_r.is_finite() && prev_r > cut.radius()) {
        return Err(OpError::Invalid(format!(
            "rest machining needs a tool smaller than the previous one ({} mm ≥ {} mm)",
            cut.tool.diameter,
            2.0 * prev_r
        )));
    }
    let q = rest_pocket(region, prev_r, cut.radius())?;
    if q.is_empty() {
        return Ok(None);
    }
    let paths: Vec<Path> = q.iter().flat_map(|a| a.paths().cloned()).collect();
    let params = PocketParams {
        strategy: Strategy::Offset,
        stepover: 0.6 * cut.tool.diameter,
        allowance: 0.0,
    };
    match pocket(name, &paths, cut, &params) {
        Ok(op) => Ok(Some(op)),
        Err(OpError::Empty(_)) => Ok(None),
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Total area of `areas`, mm².
    fn area_of(areas: &[Area]) -> f64 {
        areas.iter().map(Area::area).sum()
    }

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Path {
        Path::polyline(
            &[
                Point::new(x0, y0),
                Point::new(x1, y0),
                Point::new(x1, y1),
                Point::new(x0, y1),
            ],
            true,
        )
    }

    #[test]
    fn square_corners_leave_r2_times_4_minus_pi() {
        // A 40 mm square opened by r loses (4 − π)·r² at its four corners.
        let r = 3.0;
        let sq = Area::from_paths(&[rect(0.0, 0.0, 40.0, 40.0)]);
        let left = rest(&sq, r).unwrap();
        assert_eq!(left.len(), 4);
        let want = (4.0 - std::f64::consts::PI) * r * r;
        // The opening by SLIVER trims each corner's tip by a hair.
        let got = area_of(&left);
        assert!((got - want).abs() < 0.02 * want, "{got} vs {want}");
    }

    #[test]
    fn a_round_pocket_leaves_nothing() {
        let c = Path::new(
            vec![oficina_geom::Segment::Arc(oficina_geom::Arc::new(
                Point::new(0.0, 0.0),
                20.0,
                0.0,
                std::f64::consts::TAU,
            ))],
            true,
        );
        assert!(rest(&Area::from_paths(&[c]), 8.0).unwrap().is_empty());
    }

    #[test]
    fn a_slot_narrower_than_the_tool_is_all_rest() {
        let slot = Area::from_paths(&[rect(0.0, 0.0, 30.0, 5.0)]);
        let left = rest(&slot, 3.0).unwrap();
        assert!((area_of(&left) - 150.0).abs() < 0.5, "{}", area_of(&left));
        let q = rest_pocket(&slot, 3.0, 1.0).unwrap();
        assert!((area_of(&q) - 150.0).abs() < 0.5);
    }
}
