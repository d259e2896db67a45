//! Seed 003's experiment: squares, triangles and hexagons drawn at five places on the board,
//! timed by our planner, beside the times the seed measured (its Table 1).
//!
//! The seed gives only times and mean speeds; t × v fixes the path of each set: ≈ 240 cm of
//! squares, ≈ 205 cm of triangles and ≈ 90 cm of hexagons. We draw 4 squares of 150 mm
//! (2400 mm), 4 equilateral triangles of 171 mm (2052 mm) and 3 hexagons of 50 mm sides
//! (900 mm). The seed names no place for the pedestal; its lower-right figures were the
//! fastest, so we put the pivot at the lower-right corner of a 1100 × 800 mm board.

use oficina_geom::Point;
use oficina_motion::estimate::estimate_with;
use oficina_motion::{PlanOptions, Profile};

use crate::canon::to_canon;
use crate::machine::{PenMachine, PlotError};
use crate::strokes::{Pen, Plot, Stroke};

/// The seed's places, with the centre of each group of figures relative to the pivot, mm.
pub const PLACES: [(&str, [f64; 2]); 5] = [
    ("lower right", [-250.0, 200.0]),
    ("upper right", [-250.0, 650.0]),
    ("centre", [-600.0, 425.0]),
    ("upper left", [-950.0, 650.0]),
    ("lower left", [-950.0, 200.0]),
];

/// Seed Table 1: seconds for squares, triangles, hexagons at each place (same order).
pub const SEED_SECONDS: [[f64; 3]; 5] = [
    [64.0, 67.0, 35.0],
    [89.0, 70.0, 33.0],
    [111.0, 80.0, 40.0],
    [115.0, 90.0, 51.0],
    [202.0, 120.0, 53.0],
];

pub const FIGURES: [&str; 3] = ["squares", "triangles", "hexagons"];

fn polygon(c: Point, sides: usize, side: f64, turn: f64) -> Stroke {
    // Circumradius of a regular n-gon of side a: a / (2 sin(π/n)).
    let r = side / (2.0 * (std::f64::consts::PI / sides as f64).sin());
    (0..=sides)
        .map(|i| {
            let a = turn + i as f64 * std::f64::consts::TAU / sides as f64;
            Point::new(c.x + r * a.cos(), c.y + r * a.sin())
        })
        .collect()
}

/// The figure set `fig` (0 squares, 1 triangles, 2 hexagons) centred on `c`.
pub fn figures(fig: usize, c: Point) -> Plot {
    let (sides, side, count) = [(4, 150.0, 4), (3, 171.0, 4), (6, 50.0, 3)][fig];
    let strokes = (0..count)
        .map(|k| {
            // Side by side, 1.2 × the figure's width apart.
            let dx = (k as f64 - (count - 1) as f64 / 2.0) * side * 1.4;
            polygon(
                Point::new(c.x + dx, c.y),
                sides,
                side,
                std::f64::consts::FRAC_PI_4 * (fig == 0) as u8 as f64,
            )
        })
        .collect();
    Plot {
        pens: vec![Pen {
            name: FIGURES[fig].into(),
            strokes,
        }],
    }
}

/// One row of the table: our planned seconds and the seed's for each figure set.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub place: &'static str,
    /// Distance of the place from the pivot, mm.
    pub radius: f64,
    pub planned: [f64; 3],
    pub seed: [f64; 3],
    /// Pen-down length of each set, mm.
    pub drawn: [f64; 3],
}

/// Plans every set at every place on `profile` (which must be the polar plotter, its pivot
/// at the origin), starting and ending each job at the place itself so that only drawing and
/// the pen-up moves between figures count, as in the seed's timing.
pub fn seed_check(profile: &Profile, m: &PenMachine) -> Result<Vec<Row>, PlotError> {
    let mut rows = Vec::new();
    for (pi, (place, c)) in PLACES.iter().enumerate() {
        let centre = Point::new(c[0], c[1]);
        let mut row = Row {
            place,
            radius: centre.to_vec2().hypot(),
            planned: [0.0; 3],
            seed: SEED_SECONDS[pi],
            drawn: [0.0; 3],
        };
        for fig in 0..3 {
            let plot = figures(fig, centre);
            crate::machine::check_reach(&plot, profile, 2.0)?;
            let mut local = profile.clone();
            let first = plot.pens[0].strokes[0][0];
            local.start = [
                first.x + profile.work_offset[0],
                first.y + profile.work_offset[1],
                profile.travel[2][1],
            ];
            let mut mm = m.clone();
            mm.home = first;
            let ops = to_canon(&plot, &mm, &local);
            let e = estimate_with(ops.into_iter(), &local, PlanOptions::default(), false).map_err(
                |e| PlotError::OutOfReach {
                    pen: FIGURES[fig].into(),
                    stroke: 0,
                    x: centre.x,
                    y: centre.y,
                    why: e.to_string(),
                },
            )?;
            row.planned[fig] = e.seconds;
            row.drawn[fig] = plot.lengths().pen_down;
        }
        rows.push(row);
    }
    Ok(rows)
}
