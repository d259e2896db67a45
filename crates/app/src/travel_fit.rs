//! Where a CAM program sits in the machine's travel for its time estimate. A drawing's
//! origin is the program's work zero, and CAD programs put parts anywhere (below zero, at
//! −275 mm): the control's work offset places them on the stock. On a Cartesian machine the
//! planner's time does not depend on where the program runs, so a program that fits the travel
//! but lies outside it is timed moved in by the smallest shift, and the report says so; one
//! larger than the travel is not moved (the planner says why it cannot run).

use oficina_canon::{Canon, CanonOp, Pos};
use oficina_motion::{KinematicsKind, Profile};
use std::f64::consts::{FRAC_PI_2, TAU};

/// The XY shift that brings `canon` (machine coordinates) into `profile`'s travel; `Ok(None)`
/// when it is inside already or the machine is not Cartesian; an error saying how large the
/// program is beside the travel when it cannot fit.
pub(crate) fn shift_into_travel(
    canon: impl IntoIterator<Item = Canon>,
    profile: &Profile,
) -> Result<Option<[f64; 2]>, String> {
    if !matches!(profile.kinematics, KinematicsKind::Cartesian) {
        return Ok(None);
    }
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut grow = |axis: usize, v: f64| {
        lo[axis] = lo[axis].min(v);
        hi[axis] = hi[axis].max(v);
    };
    let mut prev: Option<[f64; 3]> = None;
    for c in canon {
        match &c.op {
            CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                grow(0, to.x);
                grow(1, to.y);
                prev = Some([to.x, to.y, to.z]);
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                if *rotation != 0.0 {
                    return Ok(None); // a rotated plane's centre is not in machine XY
                }
                let e = [end.x, end.y, end.z];
                grow(0, end.x);
                grow(1, end.y);
                // The arc's extremes along its in-plane axes: the quarter points it sweeps.
                let (a0, a1, _) = plane.axes();
                let s = prev.unwrap_or(e);
                let r = (e[a0] - center[0]).hypot(e[a1] - center[1]);
                let start = (s[a1] - center[1]).atan2(s[a0] - center[0]);
                let stop = (e[a1] - center[1]).atan2(e[a0] - center[0]);
                let ccw = *turns > 0;
                let part = if ccw { stop - start } else { start - stop }.rem_euclid(TAU);
                let full = turns.unsigned_abs() > 1 || part == 0.0;
                for q in 0..4 {
                    let theta = q as f64 * FRAC_PI_2;
                    let from_start =
                        if ccw { theta - start } else { start - theta }.rem_euclid(TAU);
                    if full || from_start <= part {
                        let p = [center[0] + r * theta.cos(), center[1] + r * theta.sin()];
                        for (i, axis) in [a0, a1].into_iter().enumerate() {
                            if axis < 2 {
                                grow(axis, p[i]);
                            }
                        }
                    }
                }
                prev = Some(e);
            }
            _ => {}
        }
    }
    if !(lo.iter().chain(&hi).all(|v| v.is_finite())) {
        return Ok(None);
    }
    let size = [hi[0] - lo[0], hi[1] - lo[1]];
    let travel = profile.travel.map(|[a, b]| b - a);
    if size[0] > travel[0] || size[1] > travel[1] {
        return Err(format!(
            "the program spans {:.1} × {:.1} mm, the machine's travel is {:.1} × {:.1} mm",
            size[0], size[1], travel[0], travel[1]
        ));
    }
    let mut shift = [0.0; 2];
    for axis in 0..2 {
        let [tmin, tmax] = profile.travel[axis];
        if lo[axis] < tmin {
            shift[axis] = tmin - lo[axis];
        } else if hi[axis] > tmax {
            shift[axis] = tmax - hi[axis];
        }
    }
    Ok((shift != [0.0, 0.0]).then_some(shift))
}

/// `c` moved by `d` in X and Y.
pub(crate) fn shifted(c: Canon, d: [f64; 2]) -> Canon {
    let mv = |mut p: Pos| {
        p.x += d[0];
        p.y += d[1];
        p
    };
    let op = match c.op {
        CanonOp::StraightTraverse { to } => CanonOp::StraightTraverse { to: mv(to) },
        CanonOp::StraightFeed { to } => CanonOp::StraightFeed { to: mv(to) },
        CanonOp::ArcFeed {
            plane,
            end,
            mut center,
            turns,
            rotation,
        } => {
            let (a0, a1, _) = plane.axes();
            for (i, axis) in [a0, a1].into_iter().enumerate() {
                if axis < 2 {
                    center[i] += d[axis];
                }
            }
            CanonOp::ArcFeed {
                plane,
                end: mv(end),
                center,
                turns,
                rotation,
            }
        }
        other => other,
    };
    Canon { line: c.line, op }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, y: f64) -> Canon {
        Canon {
            line: 1,
            op: CanonOp::StraightFeed {
                to: Pos {
                    x,
                    y,
                    ..Pos::default()
                },
            },
        }
    }

    #[test]
    fn a_program_below_zero_is_moved_in_and_one_too_large_is_not() {
        let p = oficina_motion::resolve("grbl-router").unwrap(); // 800 × 450 mm
        assert_eq!(
            shift_into_travel([at(5.0, 5.0), at(50.0, 40.0)], &p),
            Ok(None)
        );
        assert_eq!(
            shift_into_travel([at(-3.2, -280.0), at(100.0, -100.0)], &p),
            Ok(Some([3.2, 280.0]))
        );
        assert_eq!(
            shift_into_travel([at(700.0, 10.0), at(820.0, 20.0)], &p),
            Ok(Some([-20.0, 0.0]))
        );
        let e = shift_into_travel([at(0.0, 0.0), at(0.0, 500.0)], &p).unwrap_err();
        assert!(
            e.contains("0.0 × 500.0 mm") && e.contains("800.0 × 450.0 mm"),
            "{e}"
        );
        let moved = shifted(at(-3.2, -280.0), [3.2, 280.0]);
        let CanonOp::StraightFeed { to } = moved.op else {
            panic!()
        };
        assert!(to.x.abs() < 1e-12 && to.y.abs() < 1e-12);
    }
}
