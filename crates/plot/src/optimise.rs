//! The optimisation pipeline, pen by pen: drop duplicates, merge networks, simplify, order.

use oficina_geom::Point;

use crate::clean::{dedupe, simplify};
use crate::merge::merge;
use crate::order::{apply, nearest_neighbour, two_opt};
use crate::strokes::{Lengths, Plot};

/// How strokes are merged, simplified, de-duplicated and reordered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Optimise {
    /// Ends closer than this (mm) are joined; 0 turns merging off. vpype's default is 0.05.
    pub merge_tol: f64,
    /// Ramer–Douglas–Peucker tolerance, mm; 0 keeps every point.
    pub simplify_tol: f64,
    /// Strokes equal within this (mm) are drawn once; 0 keeps duplicates.
    pub dedupe_tol: f64,
    /// Reorder and reverse strokes (nearest neighbour, then 2-opt).
    pub reorder: bool,
    /// 2-opt looks this many strokes ahead; 0 skips 2-opt.
    pub two_opt_window: usize,
    /// 2-opt passes at most.
    pub two_opt_passes: usize,
}

impl Default for Optimise {
    fn default() -> Self {
        Optimise {
            merge_tol: 0.05,
            simplify_tol: 0.01,
            dedupe_tol: 0.01,
            reorder: true,
            two_opt_window: 40,
            two_opt_passes: 4,
        }
    }
}

/// What the optimisation changed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Report {
    /// Lengths before.
    pub before: Lengths,
    /// Lengths after.
    pub after: Lengths,
    /// Duplicate strokes removed.
    pub duplicates: usize,
    /// Points before and after simplification.
    pub points_before: usize,
    /// Points after simplification.
    pub points_after: usize,
}

/// Optimises every pen of `plot` in place; the first pen starts from `home`, each next pen
/// from where the previous one ended.
pub fn optimise(plot: &mut Plot, opts: &Optimise, home: Point) -> Report {
    let mut r = Report {
        before: plot.lengths(),
        points_before: plot.strokes().map(Vec::len).sum(),
        ..Report::default()
    };
    let mut at = home;
    for pen in &mut plot.pens {
        let mut strokes = std::mem::take(&mut pen.strokes);
        strokes.retain(|s| s.len() >= 2 && s.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
        if opts.dedupe_tol > 0.0 {
            r.duplicates += dedupe(&mut strokes, opts.dedupe_tol);
        }
        if opts.merge_tol > 0.0 {
            strokes = merge(strokes, opts.merge_tol);
        }
        if opts.simplify_tol > 0.0 {
            for s in &mut strokes {
                *s = simplify(s, opts.simplify_tol);
            }
        }
        if opts.reorder && !strokes.is_empty() {
            let mut tour = nearest_neighbour(&strokes, at);
            if opts.two_opt_window > 0 {
                two_opt(
                    &strokes,
                    &mut tour,
                    at,
                    opts.two_opt_window,
                    opts.two_opt_passes,
                );
            }
            strokes = apply(strokes, &tour);
        }
        if let Some(p) = strokes.last().and_then(|s| s.last()) {
            at = *p;
        }
        pen.strokes = strokes;
    }
    r.after = plot.lengths();
    r.points_after = plot.strokes().map(Vec::len).sum();
    r
}
