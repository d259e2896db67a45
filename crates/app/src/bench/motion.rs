//! `bench motion`'s workload: a raster over a bumpy relief of 0.1 mm segments, planned on a
//! profile (segments/s) and stepped (exact step times/s).

use super::{failed, BenchError};
use oficina_canon::{Canon, CanonOp, Pos};
use oficina_motion::Kinematics;
use oficina_motion::{plan, PlanOptions, Profile};
use oficina_motion::{StepCount, StepGenerator};
use std::time::Instant;

/// A raster over a bumpy relief, 0.1 mm per segment, like a finishing pass of seed 004.
pub fn relief(n: u64) -> impl Iterator<Item = Canon> {
    let per_row = 2000u64; // 200 mm rows
    let head = [
        CanonOp::SetFeedRate(3000.0),
        CanonOp::StraightTraverse {
            to: Pos::xyz(100.0, 100.0, -1.0),
        },
    ];
    head.into_iter()
        .chain((0..n).map(move |i| {
            let row = i / per_row;
            let k = i % per_row;
            let k = if row.is_multiple_of(2) {
                k
            } else {
                per_row - 1 - k
            };
            let x = 100.0 + k as f64 * 0.1;
            let y = 100.0 + (row % 1500) as f64 * 0.2;
            let z = -3.0 + 1.5 * (x * 0.13).sin() * (y * 0.07).cos();
            CanonOp::StraightFeed {
                to: Pos::xyz(x, y, z),
            }
        }))
        .enumerate()
        .map(|(i, op)| Canon {
            line: i as u32 + 1,
            op,
        })
}

/// The planner's run over [`relief`]`(n)`.
pub struct Planned {
    /// Segments planned.
    pub segments: u64,
    /// Wall seconds.
    pub seconds: f64,
    /// Machine time of the plan, s.
    pub machine_time: f64,
}

/// Plan [`relief`]`(n)` on `profile`, streaming, timed.
pub fn plan_relief(n: u64, profile: &Profile) -> Result<Planned, BenchError> {
    let t = Instant::now();
    let (mut segments, mut machine_time) = (0u64, 0.0);
    for s in plan(relief(n), profile, PlanOptions::default()).map_err(failed)? {
        machine_time += s.map_err(failed)?.duration();
        segments += 1;
    }
    Ok(Planned {
        segments,
        seconds: t.elapsed().as_secs_f64(),
        machine_time,
    })
}

/// Every exact step time of [`relief`]`(n)` on `profile`: the steps, and the wall seconds
/// of generating them (the planning before is not counted).
pub fn step_relief(n: u64, profile: &Profile) -> Result<(u64, f64), BenchError> {
    let segs: Vec<_> = plan(relief(n), profile, PlanOptions::default())
        .map_err(failed)?
        .collect::<Result<_, _>>()
        .map_err(failed)?;
    let q = oficina_motion::for_profile(profile)
        .joints(profile.start)
        .map_err(failed)?;
    let mut gen = StepGenerator::new(profile, q);
    let mut sink = StepCount::default();
    let t = Instant::now();
    for s in &segs {
        gen.segment(s, &mut sink).map_err(failed)?;
    }
    Ok((sink.steps, t.elapsed().as_secs_f64()))
}
