//! Seed 004's experiment, reproduced: a 150 × 150 mm hemisphere 25 mm deep, its two-tool
//! method (12 mm flat, 5 mm step, levels of 5 mm; then the 3 mm flat on the regions the big
//! one missed, level by level; then the 3 mm flat column by column at full depth) against
//! the 3 mm tool alone, and a better plan of ours.

use crate::raster::Feeds;
use crate::relief::{Cutter, Direction, Pass, ReliefJob};
use oficina_io::Heightmap;

/// The seed's hard-coded feed, F2000 mm/min; its plunge is the same diagonal G1.
pub const SEED_FEED_MM_MIN: f64 = 2000.0;

/// The hemisphere z-buffer: a half sphere of radius 75 mm squashed to `depth`, carved as a
/// bowl (black centre = deepest), sampled every `pixel` mm.
pub fn hemisphere(size: f64, depth: f64, pixel: f64) -> Heightmap {
    let n = (size / pixel).round() as usize;
    let (c, r) = (size / 2.0, size / 2.0);
    Heightmap::from_fn(n, n, pixel, |x, y| {
        let d2 = (x + pixel / 2.0 - c).powi(2) + (y + pixel / 2.0 - c).powi(2);
        -depth * (1.0 - d2 / (r * r)).max(0.0).sqrt()
    })
}

fn cutter(number: u32, spec: &str, feed_mm_min: f64, plunge_mm_min: f64) -> Cutter {
    Cutter {
        number,
        tool: spec.parse().expect("built-in tool spec"),
        feeds: Feeds {
            cut: feed_mm_min / 60.0,
            plunge: plunge_mm_min / 60.0,
            rapid: 6000.0 / 60.0,
        },
        spindle_rpm: 15000.0,
    }
}

fn pass(
    name: &str,
    c: Cutter,
    stepover: f64,
    stepdown: f64,
    direction: Direction,
    rest_only: bool,
) -> Pass {
    Pass {
        name: name.into(),
        cutter: c,
        stepover,
        stepdown,
        allowance: 0.0,
        direction,
        zigzag: true,
        rest_only,
        min_cut: 0.01,
    }
}

fn job(passes: Vec<Pass>) -> ReliefJob {
    ReliefJob {
        safe_z: 2.0,
        clearance: 1.0,
        tolerance: 0.01,
        samples_per_pixel: crate::relief::SAMPLES_PER_PIXEL,
        passes,
        simulate_last: true,
    }
}

/// The seed's last pass, in both its methods: the 3 mm flat (tool `number`) column by
/// column at full depth.
fn seed_final_pass(number: u32) -> Pass {
    let f = SEED_FEED_MM_MIN;
    pass(
        "seed: 3 mm flat, final pass by columns",
        cutter(number, "flat:3", f, f),
        1.0,
        1000.0,
        Direction::Y,
        false,
    )
}

/// The seed's two-tool method.
pub fn seed_two_tools() -> ReliefJob {
    let f = SEED_FEED_MM_MIN;
    job(vec![
        pass(
            "seed: 12 mm flat, 5 mm step, levels",
            cutter(1, "flat:12", f, f),
            5.0,
            5.0,
            Direction::X,
            false,
        ),
        pass(
            "seed: 3 mm flat on the missed regions, levels",
            cutter(2, "flat:3", f, f),
            1.0,
            5.0,
            Direction::X,
            true,
        ),
        seed_final_pass(2),
    ])
}

/// The 3 mm tool alone, as the seed's single-tool program: levels, then the final pass.
pub fn seed_one_tool() -> ReliefJob {
    let f = SEED_FEED_MM_MIN;
    job(vec![
        pass(
            "seed: 3 mm flat, 1 mm step, levels",
            cutter(1, "flat:3", f, f),
            1.0,
            5.0,
            Direction::X,
            false,
        ),
        seed_final_pass(1),
    ])
}

/// Ours, measured on the simulator to beat the seed's two-tool plan on time *and* on
/// leftover (max and mean) at 1 and 0.5 mm pixels. The 12 mm flat roughs at 50 % step-over
/// by levels that skip finished ground; a 3 mm ball clears, level by level, only the regions
/// where more than 2 mm stands above its own surface; the same ball finishes by columns at
/// 1 mm and then, by rows, only where the columns left more than 0.02 mm (rest machining for
/// the finishing tool: steep walls across the columns). The seed's leftover comes mostly
/// from its flat finisher's steps on the slopes; the ball follows them.
pub fn improved() -> ReliefJob {
    let f = SEED_FEED_MM_MIN;
    let ball = || cutter(2, "ball:3", f, f / 2.0);
    job(vec![
        pass(
            "ours: 12 mm flat, 6 mm step, levels",
            cutter(1, "flat:12", f, f / 2.0),
            6.0,
            5.0,
            Direction::X,
            false,
        ),
        Pass {
            min_cut: 2.0,
            ..pass(
                "ours: 3 mm ball rest, regions",
                ball(),
                1.5,
                5.0,
                Direction::X,
                true,
            )
        },
        pass(
            "ours: 3 mm ball finish by columns",
            ball(),
            1.0,
            1000.0,
            Direction::Y,
            false,
        ),
        Pass {
            min_cut: 0.02,
            ..pass(
                "ours: 3 mm ball, rows where columns left 0.02",
                ball(),
                1.0,
                1000.0,
                Direction::X,
                true,
            )
        },
    ])
}
