//! `oficina bench motion`: planner segments/s on a 1,000,000-segment relief-like program,
//! generated steps/s, and peak memory for two program lengths (flat when streaming works).

use crate::machine_profile;
use oficina_app::bench::motion::{plan_relief, step_relief};

#[derive(clap::Args)]
pub(crate) struct Args {
    /// Segments in the large program.
    #[arg(long, default_value_t = 1_000_000)]
    segments: u64,
    /// Machine profile.
    #[arg(long, default_value = machine_profile::DEFAULT)]
    machine: String,
}

pub(crate) fn run(args: Args) -> anyhow::Result<()> {
    let profile = machine_profile::resolve(&args.machine)?;
    println!("machine: {}", profile.name);
    for &n in &[args.segments / 10, args.segments] {
        let p = plan_relief(n, &profile)?;
        let dt = p.seconds;
        println!(
            "plan {n:>9} input segments: {} planned in {dt:.3} s = {:.0} segments/s (machine time {:.0} s); VmHWM {} kB",
            p.segments,
            p.segments as f64 / dt,
            p.machine_time,
            crate::peak_memory::vm_hwm_kb().map_or("?".into(), |v| v.to_string())
        );
    }
    // Steps: generate every step of the small program.
    let (steps, dt) = step_relief(args.segments / 10, &profile)?;
    println!(
        "steps: {steps} exact step times in {dt:.3} s = {:.0} steps/s",
        steps as f64 / dt
    );
    crate::peak_memory::print();
    Ok(())
}
