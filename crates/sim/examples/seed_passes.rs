//! Leftover after every pass of seed 004's hemisphere plans, as measured on the simulated
//! stock: shows where each plan's time goes and what each pass leaves.
//! `cargo run --release -p oficina-sim --example seed_passes -- [PIXEL_MM]`

use oficina_cam::relief::{plan, ReliefJob};
use oficina_cam::seed004;
use oficina_sim::{compare, feed_only_estimate, ideal_surface};

fn show(name: &str, job: &ReliefJob, pixel: f64) {
    let design = seed004::hemisphere(150.0, 25.0, pixel);
    for k in 1..=job.passes.len() {
        let partial = ReliefJob {
            passes: job.passes[..k].to_vec(),
            simulate_last: true,
            ..job.clone()
        };
        let planned = plan(&design, &partial, &|_, _| {}).expect("built-in job");
        let stock = planned.stock.expect("simulated");
        let tool = &job.passes[k - 1].cutter.tool;
        let r = compare(&stock, &design, &ideal_surface(&design, tool));
        let t = feed_only_estimate(&planned.toolpath.canon(), [0.0, 0.0, job.safe_z], 6000.0);
        println!(
            "{name:<5} after {:<48} feed-only {:>6.0} s  gouge {:.4}  left max {:.3} mean {:.4}",
            job.passes[k - 1].name,
            t,
            r.max_gouge,
            r.leftover_max,
            r.leftover_mean
        );
    }
}

fn main() {
    let pixel: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    show("seed", &seed004::seed_two_tools(), pixel);
    show("ours", &seed004::improved(), pixel);
}
