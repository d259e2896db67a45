//! Seed 003's experiment: squares, triangles and hexagons drawn at five places on the board,
//! timed by our planner, beside the times the seed measured (its Table 1).
//!
//! The seed gives only times and mean speeds; t × v fixes the path of each set: ≈ 240 cm of
//! squares, ≈ 205 cm of triangles and ≈ 90 cm of hexagons. We draw 4 squares of 150 mm
//! (2400 mm), 4 equilateral triangles of 171 mm (2052 mm) and 3 hexagons of 50 mm sides
//! (900 mm). The seed names no place for the pedestal. Near the pivot a millimetre of pen
//! travel turns the arm by more (dθ ≈ ds / R), and the seed's host stopped the arm at every
//! sub-segment, so its slowest place is the one nearest the pivot: its lower-left. We put
//! the pivot at the lower-left corner of a 1200 × 850 mm board and give, beside our planner
//! (look-ahead over the joint limits, no stops), that stop-at-every-piece model.

use oficina_geom::Point;
use oficina_motion::estimate_with;
use oficina_motion::{PlanOptions, Profile};

use crate::canon::to_canon;
use crate::machine::{PenMachine, PlotError};
use crate::strokes::{Pen, Plot, Stroke};

/// The seed's places, with the centre of each group of figures relative to the pivot, mm.
pub const PLACES: [(&str, [f64; 2]); 5] = [
    ("lower right", [900.0, 200.0]),
    ("upper right", [900.0, 650.0]),
    ("centre", [600.0, 425.0]),
    ("upper left", [250.0, 650.0]),
    ("lower left", [250.0, 200.0]),
];

/// Seed Table 1: seconds for squares, triangles, hexagons at each place (same order).
pub const SEED_SECONDS: [[f64; 3]; 5] = [
    [64.0, 67.0, 35.0],
    [89.0, 70.0, 33.0],
    [111.0, 80.0, 40.0],
    [115.0, 90.0, 51.0],
    [202.0, 120.0, 53.0],
];

/// The stop-start model's sub-segment, mm (the seed leaves it to the user).
pub const STOP_PIECE: f64 = 5.0;

/// The seed's three figure sets, in table order.
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
            // Side by side, 1.15 × the figure's width apart.
            let dx = (k as f64 - (count - 1) as f64 / 2.0) * side * 1.15;
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
    /// Where on the sheet.
    pub place: &'static str,
    /// Distance of the place from the pivot, mm.
    pub radius: f64,
    /// Our planned seconds for each figure set.
    pub planned: [f64; 3],
    /// The seed's seconds for each figure set.
    pub seed: [f64; 3],
    /// Pen-down length of each set, mm.
    pub drawn: [f64; 3],
    /// Seconds when the host stops at the end of every `piece` mm (the seed's method).
    pub stop_start: [f64; 3],
}

/// Rest-to-rest time of one joint over `d` with rate `v` and acceleration `a`: a triangle
/// 2√(d/a) when d < v²/a, else a trapezoid d/v + v/a.
fn rest_to_rest(d: f64, v: f64, a: f64) -> f64 {
    let d = d.abs();
    if d < v * v / a {
        2.0 * (d / a).sqrt()
    } else {
        d / v + v / a
    }
}

/// The seed's host: each line cut into `piece` mm sub-segments, each one a rest-to-rest move
/// of both joints (the slower sets the time), no faster than `feed` mm/min.
pub fn stop_start_seconds(plot: &Plot, profile: &Profile, feed: f64, piece: f64) -> f64 {
    use oficina_motion::{for_profile, Kinematics};
    let k = for_profile(profile);
    let mut t = 0.0;
    for s in plot.strokes() {
        for w in s.windows(2) {
            let n = (w[0].distance(w[1]) / piece).ceil().max(1.0) as usize;
            let mut q0 = k.joints([w[0].x, w[0].y, 0.0]).unwrap_or([0.0; 3]);
            for i in 1..=n {
                let p = w[0].lerp(w[1], i as f64 / n as f64);
                let q1 = k.joints_near([p.x, p.y, 0.0], q0).unwrap_or(q0);
                let mut dt = w[0].distance(w[1]) / n as f64 / (feed / 60.0);
                for j in 0..2 {
                    if let Some(jt) = &profile.joints[j] {
                        dt = dt.max(rest_to_rest(q1[j] - q0[j], jt.max_rate, jt.acceleration));
                    }
                }
                t += dt;
                q0 = q1;
            }
        }
    }
    t
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
            stop_start: [0.0; 3],
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
            row.stop_start[fig] = stop_start_seconds(&plot, profile, m.draw_feed, STOP_PIECE);
        }
        rows.push(row);
    }
    Ok(rows)
}
