//! The straight-move criterion of relief finishing, on designs where joining raw drop-cutter
//! samples with straight lines gouges: a needle field and a steep ramp. The exact bound at
//! 4 points per pixel must stay gouge-free and leave less than the one-pixel widening it
//! replaced (`samples_per_pixel = 1` is that widening: the max of a sample and its two
//! neighbours is the exact sup of the tip surface over the pixel either side).

mod common;

use common::replay_on_fresh_stock;
use oficina_cam::apply_moves;
use oficina_cam::relief::{plan, Cutter, Direction, Pass, ReliefJob};
use oficina_cam::Feeds;
use oficina_cam::{surface_rows, Kernel};
use oficina_cam::{Move, Tool};
use oficina_io::Heightmap;
use oficina_sim::{compare, ideal_surface, Report};

const PIXEL: f64 = 0.1;

fn ball() -> Tool {
    "ball:2".parse().unwrap()
}

/// Needles one pixel wide, 2 mm tall, on a flat floor 3 mm down.
fn needles() -> Heightmap {
    Heightmap::from_fn(90, 40, PIXEL, |x, y| {
        let (ix, iy) = ((x / PIXEL).round() as i64, (y / PIXEL).round() as i64);
        if ix % 23 == 11 && iy % 9 == 4 {
            -1.0
        } else {
            -3.0
        }
    })
}

/// A ramp rising 3 mm per mm along X between two flats.
fn ramp() -> Heightmap {
    Heightmap::from_fn(90, 30, PIXEL, |x, _| {
        (-4.0 + 3.0 * (x - 3.0)).clamp(-4.0, -0.5)
    })
}

fn job(samples_per_pixel: usize) -> ReliefJob {
    ReliefJob {
        safe_z: 5.0,
        clearance: 1.0,
        tolerance: 0.002,
        samples_per_pixel,
        passes: vec![Pass {
            name: "finish".into(),
            cutter: Cutter {
                number: 1,
                tool: ball(),
                feeds: Feeds {
                    cut: 30.0,
                    plunge: 10.0,
                    rapid: 80.0,
                },
                spindle_rpm: 18000.0,
            },
            stepover: 0.3,
            stepdown: 100.0,
            allowance: 0.0,
            direction: Direction::X,
            zigzag: true,
            rest_only: false,
            min_cut: 0.001,
        }],
        simulate_last: false,
    }
}

/// The program replayed through canonical operations on fresh stock, judged on the rows
/// the raster visits (between rows a ball leaves scallops whatever the criterion).
fn carve(design: &Heightmap, samples_per_pixel: usize) -> Report {
    let planned = plan(design, &job(samples_per_pixel), &|_, _| {}).unwrap();
    let stock = replay_on_fresh_stock(design, &planned);
    compare(&stock, design, &ideal_surface(design, &ball()))
}

/// Straight feeds through the raw tip heights of every pixel of one row, as image-to-gcode
/// does: the deepest cut below the design.
fn naive_gouge(design: &Heightmap, iy: usize) -> f64 {
    let tips = &surface_rows(design, &Kernel::new(&ball(), PIXEL, 0.0, 0.0), &[iy])[0];
    let y = iy as f64 * PIXEL;
    let start = [0.0, y, tips[0] as f64];
    let moves: Vec<Move> = tips
        .iter()
        .enumerate()
        .map(|(ix, &z)| Move::Line {
            to: [ix as f64 * PIXEL, y, z as f64],
            feed: 30.0,
        })
        .collect();
    let mut stock = Heightmap::flat(design.width, design.height, PIXEL, 0.0);
    apply_moves(&mut stock, &ball(), start, &moves);
    compare(&stock, design, design).max_gouge
}

fn check(name: &str, design: &Heightmap, naive_row: usize) {
    let naive = naive_gouge(design, naive_row);
    assert!(
        naive > 1e-3,
        "{name}: raw samples should gouge here, got {naive}"
    );
    let old = carve(design, 1);
    let exact = carve(design, 4);
    for (label, r) in [("widening", &old), ("exact", &exact)] {
        // 4-decimal G-code can round a point 0.05 µm down; nothing else may go below.
        assert!(
            r.max_gouge < 1e-4,
            "{name} {label}: gouge {} at {:?}",
            r.max_gouge,
            r.gouge_at
        );
    }
    assert!(
        exact.leftover_mean < old.leftover_mean && exact.scallop_mean < old.scallop_mean,
        "{name}: exact left {} / scallop {}, widening left {} / scallop {}",
        exact.leftover_mean,
        exact.scallop_mean,
        old.leftover_mean,
        old.scallop_mean
    );
}

#[test]
fn needles_are_never_gouged_and_less_is_left() {
    // Row 4 runs through a needle: a straight move between raw samples clips it.
    check("needles", &needles(), 4);
}

#[test]
fn steep_ramp_is_never_gouged_and_less_is_left() {
    check("ramp", &ramp(), 15);
}
