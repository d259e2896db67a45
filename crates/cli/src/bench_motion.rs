//! `oficina bench motion`: planner segments/s on a 1,000,000-segment relief-like program,
//! generated steps/s, and peak memory for two program lengths (flat when streaming works).

use crate::machine_profile;
use oficina_canon::{Canon, CanonOp, Pos};
use oficina_motion::Kinematics;
use oficina_motion::{plan, PlanOptions};
use oficina_motion::{StepCount, StepGenerator};
use std::time::Instant;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Segments in the large program.
    #[arg(long, default_value_t = 1_000_000)]
    segments: u64,
    /// Machine profile.
    #[arg(long, default_value = machine_profile::DEFAULT)]
    machine: String,
}

/// A raster over a bumpy relief, 0.1 mm per segment, like a finishing pass of seed 004.
fn relief(n: u64) -> impl Iterator<Item = Canon> {
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

pub(crate) fn run(args: Args) -> anyhow::Result<()> {
    let profile = machine_profile::resolve(&args.machine)?;
    println!("machine: {}", profile.name);
    for &n in &[args.segments / 10, args.segments] {
        let t = Instant::now();
        let mut segs = 0u64;
        let mut machine_time = 0.0;
        for s in
            plan(relief(n), &profile, PlanOptions::default()).map_err(|e| anyhow::anyhow!("{e}"))?
        {
            let s = s.map_err(|e| anyhow::anyhow!("{e}"))?;
            segs += 1;
            machine_time += s.duration();
        }
        let dt = t.elapsed().as_secs_f64();
        println!(
            "plan {n:>9} input segments: {segs} planned in {dt:.3} s = {:.0} segments/s (machine time {machine_time:.0} s); VmHWM {} kB",
            segs as f64 / dt,
            crate::peak_memory::vm_hwm_kb().map_or("?".into(), |v| v.to_string())
        );
    }
    // Steps: generate every step of the small program.
    let n = args.segments / 10;
    let segs: Vec<_> = plan(relief(n), &profile, PlanOptions::default())
        .map_err(|e| anyhow::anyhow!("{e}"))?
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let q = oficina_motion::for_profile(&profile)
        .joints(profile.start)
        .map_err(|e| anyhow::anyhow!(e))?;
    let mut gen = StepGenerator::new(&profile, q);
    let mut sink = StepCount::default();
    let t = Instant::now();
    for s in &segs {
        gen.segment(s, &mut sink)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "steps: {} exact step times in {dt:.3} s = {:.0} steps/s",
        sink.steps,
        sink.steps as f64 / dt
    );
    crate::peak_memory::print();
    Ok(())
}
