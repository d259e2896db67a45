//! One operation on a drawing, and the region it is allowed to cut (for verification).

use super::drill::hole_centres;
use super::profile::OFFSET_TOL;
use super::{
    drill, pocket, profile, vcarve, Cut, DrillParams, OpError, PocketParams, ProfileParams, Side,
    VCarveParams,
};
use crate::{Operation, Toolpath};
use oficina_geom::{offset_areas, to_ring, Area, Path};

/// One 2.5D operation with its own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MillOp {
    /// Clear the inside of closed shapes.
    Pocket(PocketParams),
    /// Cut along the shapes' outlines.
    Profile(ProfileParams),
    /// Drill the circles' centres.
    Drill(DrillParams),
    /// V-carve the shapes.
    VCarve(VCarveParams),
}

impl MillOp {
    /// The operation's name for comments and reports.
    pub fn name(&self) -> &'static str {
        match self {
            MillOp::Pocket(_) => "pocket",
            MillOp::Profile(p) => match p.side {
                Side::Inside => "profile inside",
                Side::Outside => "profile outside",
                Side::On => "engrave on the line",
            },
            MillOp::Drill(_) => "drill",
            MillOp::VCarve(_) => "V-carve",
        }
    }
}

/// The operation's moves for `paths`.
pub fn operation(paths: &[Path], cut: &Cut, op: &MillOp) -> Result<Operation, OpError> {
    let name = op.name();
    match op {
        MillOp::Pocket(p) => pocket(name, paths, cut, p),
        MillOp::Profile(p) => profile(name, paths, cut, p),
        MillOp::Drill(p) => drill(name, paths, cut, p),
        MillOp::VCarve(p) => vcarve(name, paths, cut, p),
    }
}

/// A toolpath of one operation with `safe_z` for tool changes.
pub fn toolpath(paths: &[Path], cut: &Cut, op: &MillOp, safe_z: f64) -> Result<Toolpath, OpError> {
    Ok(Toolpath {
        safe_z,
        operations: vec![operation(paths, cut, op)?],
    })
}

/// Within this (mm) of the drawn wall a cut does not count as a gouge: offsets are exact
/// to [`OFFSET_TOL`], arcs are flattened for the check to a tenth of it.
pub const GOUGE_TOL: f64 = 0.005;

/// Rings of the region `op` may cut and whether that is their inside (pocket, hole, drill)
/// or outside (a part cut out), [`GOUGE_TOL`] generous. `None` for cuts on the line, whose
/// drawing is the tool-centre path itself.
pub fn allowed_region(
    paths: &[Path],
    op: &MillOp,
) -> Result<Option<(Vec<Vec<[f64; 2]>>, bool)>, OpError> {
    let geo = |e: oficina_geom::PolygonError| OpError::Geometry(e.to_string());
    let rings_of = |areas: &[Area]| -> Vec<Vec<[f64; 2]>> {
        areas
            .iter()
            .flat_map(|a| {
                a.paths()
                    .map(|p| to_ring(&p.flatten(OFFSET_TOL / 10.0)))
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let areas = Area::from_paths(paths);
    match op {
        MillOp::Pocket(_)
        | MillOp::Profile(ProfileParams {
            side: Side::Inside, ..
        }) => {
            let grown = offset_areas(&areas, GOUGE_TOL, OFFSET_TOL).map_err(geo)?;
            Ok(Some((rings_of(&grown), true)))
        }
        MillOp::Profile(ProfileParams {
            side: Side::Outside,
            ..
        }) => {
            let shrunk = offset_areas(&areas, -GOUGE_TOL, OFFSET_TOL).map_err(geo)?;
            Ok(Some((rings_of(&shrunk), false)))
        }
        MillOp::Profile(_) => Ok(None),
        // The closed shapes, carved with sloping walls (the caller knows the slope); a
        // drawing with open strokes is its own design, like a cut on the line.
        MillOp::VCarve(_) => {
            if paths.iter().any(|p| !p.closed) {
                return Ok(None);
            }
            Ok(Some((rings_of(&areas), true)))
        }
        MillOp::Drill(_) => {
            let holes: Vec<Path> = paths
                .iter()
                .filter(|p| !hole_centres(std::slice::from_ref(*p)).is_empty())
                .cloned()
                .collect();
            let grown =
                offset_areas(&Area::from_paths(&holes), GOUGE_TOL, OFFSET_TOL).map_err(geo)?;
            Ok(Some((rings_of(&grown), true)))
        }
    }
}
