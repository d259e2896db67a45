//! Chamfering (deburring) the top edge of contours with a V bit: the tip runs along the
//! edge, moved `tip_offset` into the waste (a V bit's tip does not cut, it rubs), as deep as
//! makes a chamfer `width` wide on the part: (width + tip_offset) / tan(half angle).
//! Outlines of parts are chamfered from outside, holes from inside; the caller says which
//! is which (it knows the whole drawing's nesting, the selection alone does not).

use super::mill::GOUGE_TOL;
use super::profile::OFFSET_TOL;
use super::{half_tan, profile, Comp, Cut, OpError, ProfileParams, Side};
use crate::Operation;
use oficina_geom::{offset_areas, oriented, to_ring, Area, Path};

/// Chamfer parameters besides the cut (whose depth this op sets).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChamferParams {
    /// Width of the chamfer on the part's top face, mm (> 0).
    pub width: f64,
    /// The tip runs this far into the waste, mm (≥ 0).
    pub tip_offset: f64,
}

impl ChamferParams {
    /// Depth of the tip below the top for `cut`'s V bit, mm.
    pub fn depth(&self, cut: &Cut) -> Result<f64, OpError> {
        let t = half_tan(cut)?;
        let valid = self.width.is_finite()
            && self.width > 0.0
            && self.tip_offset.is_finite()
            && self.tip_offset >= 0.0;
        if !valid {
            return Err(OpError::Invalid(format!(
                "chamfer width must be above 0 and tip offset 0 or more (got {} and {})",
                self.width, self.tip_offset
            )));
        }
        let reach = self.width + self.tip_offset;
        if reach > cut.radius() + 1e-9 {
            return Err(OpError::Invalid(format!(
                "chamfer width {} mm + tip offset {} mm is more than the radius of {}",
                self.width,
                self.tip_offset,
                cut.tool.spec()
            )));
        }
        Ok(reach / t)
    }
}

/// `path` (closed) moved by `d` mm outwards (negative: inwards), as lone loops.
fn moved(path: &Path, d: f64) -> Result<Vec<Path>, OpError> {
    if d == 0.0 {
        return Ok(vec![path.clone()]);
    }
    let area = Area {
        outer: oriented(path, true),
        holes: vec![],
    };
    Ok(offset_areas(&[area], d, OFFSET_TOL)
        .map_err(|e| OpError::Geometry(e.to_string()))?
        .into_iter()
        .map(|a| a.outer)
        .collect())
}

/// Chamfers the outside of closed `parts` and the inside of closed `holes` with `cut`'s
/// V bit, in one pass per step-down to the depth [`ChamferParams::depth`] gives.
pub fn chamfer(
    name: &str,
    parts: &[Path],
    holes: &[Path],
    cut: &Cut,
    p: &ChamferParams,
) -> Result<Operation, OpError> {
    let depth = p.depth(cut)?;
    let mut tips = Vec::new();
    // Climb milling: clockwise round a part, counter-clockwise inside a hole.
    for part in parts.iter().filter(|q| q.closed) {
        tips.extend(
            moved(part, p.tip_offset)?
                .iter()
                .map(|q| oriented(q, false)),
        );
    }
    for hole in holes.iter().filter(|q| q.closed) {
        tips.extend(
            moved(hole, -p.tip_offset)?
                .iter()
                .map(|q| oriented(q, true)),
        );
    }
    if tips.is_empty() {
        return Err(OpError::Empty(
            "no closed edge to chamfer (or every hole is narrower than the tip offset)".into(),
        ));
    }
    let cut = Cut {
        depth,
        stepdown: cut.stepdown.min(depth),
        ..cut.clone()
    };
    let on = ProfileParams {
        side: Side::On,
        allowance: 0.0,
        tabs: None,
        lead_out: 0.0,
        lead_in: 0.0,
        comp: Comp::Computer,
    };
    profile(name, &tips, &cut, &on)
}

/// The regions a chamfer may cut, for the stock check: (rings, cut inside) for the parts
/// and for the holes, each the edge moved `width` (+ [`GOUGE_TOL`]) into the material, from
/// which the design slopes down at the bit's flank.
pub fn chamfer_regions(
    parts: &[Path],
    holes: &[Path],
    p: &ChamferParams,
) -> Result<Vec<(Vec<Vec<[f64; 2]>>, bool)>, OpError> {
    let rings = |paths: &[Path], d: f64| -> Result<Vec<Vec<[f64; 2]>>, OpError> {
        let mut out = Vec::new();
        for q in paths.iter().filter(|q| q.closed) {
            for m in moved(q, d)? {
                out.push(to_ring(&m.flatten(OFFSET_TOL / 10.0)));
            }
        }
        Ok(out)
    };
    let mut out = Vec::new();
    let shrunk = rings(parts, -(p.width + GOUGE_TOL))?;
    if !shrunk.is_empty() {
        out.push((shrunk, false));
    }
    let grown = rings(holes, p.width + GOUGE_TOL)?;
    if !grown.is_empty() {
        out.push((grown, true));
    }
    Ok(out)
}
