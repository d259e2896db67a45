//! "The union of the motion made is the program path, with no gap and no double cut": each
//! cutting move of the program is an interval [0, L] along its line; every recorded piece of
//! motion that lies on it (both ends within `tol`) covers its projection. Uncovered stretches
//! are gaps; length covered more than once is double cut.

use oficina_grbl::StreamProgram;
use oficina_grbl::{Interp, Rate};

pub(crate) type Piece = ([f64; 3], [f64; 3]);

/// The program's moves in machine mm, each with whether it cuts (a feed move).
pub(crate) fn program_cuts(job: &StreamProgram) -> Vec<(Piece, bool)> {
    let mut it = Interp::default();
    let mut out = Vec::new();
    for l in &job.lines {
        let mut from = it.pos;
        if let Ok(e) = it.execute(&l.text) {
            for s in e.segments {
                out.push(((from, s.to), matches!(s.rate, Rate::Feed(_))));
                from = s.to;
            }
        }
    }
    out
}

#[derive(Debug, Default)]
pub(crate) struct Coverage {
    /// Longest uncovered stretch of any cutting move (mm).
    pub(crate) worst_gap: f64,
    /// Largest length of one move covered more than once (mm).
    pub(crate) worst_double: f64,
    pub(crate) where_gap: Option<usize>,
    pub(crate) where_double: Option<usize>,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Distance of `p` from segment `a`–`b` and its position along it (clamped to [0, len]).
fn project(p: [f64; 3], a: [f64; 3], u: [f64; 3], len: f64) -> (f64, f64) {
    let t = dot(sub(p, a), u).clamp(0.0, len);
    let q = [a[0] + u[0] * t, a[1] + u[1] * t, a[2] + u[2] * t];
    (dot(sub(p, q), sub(p, q)).sqrt(), t)
}

/// Distance of `p` from program segment `seg`.
fn off(p: [f64; 3], seg: &Piece) -> f64 {
    let d = sub(seg.1, seg.0);
    let len = dot(d, d).sqrt();
    if len < 1e-12 {
        return dot(sub(p, seg.0), sub(p, seg.0)).sqrt();
    }
    project(p, seg.0, [d[0] / len, d[1] / len, d[2] / len], len).0
}

/// A sampled record (grblHAL's, every few ms) has pieces that cross a vertex of the path:
/// the machine went through the vertex (grbl's planner never cuts a corner, it slows), so
/// such a piece is split there. Pieces on one segment, or off the path, are kept as they are.
fn through_vertices(program: &[Piece], made: &[Piece], tol: f64) -> Vec<Piece> {
    let mut out = Vec::with_capacity(made.len());
    for &(p, q) in made {
        if program.iter().any(|s| off(p, s) <= tol && off(q, s) <= tol) {
            out.push((p, q));
            continue;
        }
        let split = program.iter().enumerate().find_map(|(i, s)| {
            if off(p, s) > tol {
                return None;
            }
            (i + 1..program.len().min(i + 4))
                .find(|&j| off(q, &program[j]) <= tol)
                .map(|j| (i, j))
        });
        match split {
            Some((i, j)) => {
                out.push((p, program[i].1));
                out.extend(program[i + 1..j].iter().copied());
                out.push((program[j].0, q));
            }
            None => out.push((p, q)),
        }
    }
    out
}

/// The longest jump between consecutive samples of a sampled record (`made`, as its
/// pieces) that both lie on a cutting move, when longer than `max_step` (the most the
/// machine moves between two samples at the job's feed): the record has a hole there, it
/// missed motion. 0 when there is none.
pub(crate) fn record_hole(
    program: &[(Piece, bool)],
    made: &[Piece],
    tol: f64,
    max_step: f64,
) -> f64 {
    let cuts: Vec<Piece> = program
        .iter()
        .filter(|(_, c)| *c)
        .map(|(p, _)| *p)
        .collect();
    let on_path = |p: [f64; 3]| cuts.iter().any(|s| off(p, s) <= tol);
    made.iter()
        .map(|&(p, q)| dot(sub(q, p), sub(q, p)).sqrt())
        .zip(made)
        .filter(|(d, (p, q))| *d > max_step && on_path(*p) && on_path(*q))
        .map(|(d, _)| d)
        .fold(0.0, f64::max)
}

/// How the cutting moves of `program` are covered by the motion `made`.
pub(crate) fn check(program: &[(Piece, bool)], made: &[Piece], tol: f64) -> Coverage {
    let path: Vec<Piece> = program.iter().map(|(p, _)| *p).collect();
    let made = &through_vertices(&path, made, tol);
    let mut c = Coverage::default();
    for (i, &((a, b), cuts)) in program.iter().enumerate() {
        if !cuts {
            continue;
        }
        let d = sub(b, a);
        let len = dot(d, d).sqrt();
        if len < 1e-9 {
            continue;
        }
        let u = [d[0] / len, d[1] / len, d[2] / len];
        let mut spans: Vec<(f64, f64)> = made
            .iter()
            .filter_map(|&(p, q)| {
                let (dp, tp) = project(p, a, u, len);
                let (dq, tq) = project(q, a, u, len);
                (dp <= tol && dq <= tol && (tp - tq).abs() > 1e-9).then(|| (tp.min(tq), tp.max(tq)))
            })
            .collect();
        spans.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut reach = 0.0f64;
        let mut double = 0.0f64;
        let mut gap = 0.0f64;
        for (s, e) in spans {
            if s > reach {
                gap = gap.max(s - reach);
            } else {
                double += e.min(reach) - s;
            }
            reach = reach.max(e);
        }
        gap = gap.max(len - reach);
        if gap > c.worst_gap {
            c.worst_gap = gap;
            c.where_gap = Some(i);
        }
        if double > c.worst_double {
            c.worst_double = double;
            c.where_double = Some(i);
        }
    }
    c
}

/// A relief carved by a zig-zag raster: one continuous path (no point passed twice), every
/// row's depth following a dome-and-ripple surface, `rows` rows of `cols` moves. It starts
/// at X1 Y1, away from the origin, so the first rapids (from wherever the machine rests)
/// do not run along its plunge.
pub(crate) fn relief_program(rows: usize, cols: usize, step: f64, feed: f64) -> String {
    let (w, h) = (cols as f64 * step, rows as f64 * step);
    let depth = |x: f64, y: f64| {
        let r2 = ((x - w / 2.0).powi(2) + (y - h / 2.0).powi(2)) / (w * w / 4.0 + h * h / 4.0);
        -0.5 - 2.0 * (1.0 - r2).max(0.0) - 0.3 * (x * 0.7).sin() * (y * 0.5).cos()
    };
    let point = |x: f64, y: f64| format!("X{:.3}Y{:.3}Z{:.3}", x + 1.0, y + 1.0, depth(x, y));
    let mut s = format!(
        "G21G90G94\nG0Z2\nG0X1Y1\nG1Z{:.3}F{feed}\n",
        depth(0.0, 0.0)
    );
    for r in 0..rows {
        let y = r as f64 * step;
        if r > 0 {
            let x = if r % 2 == 1 { w } else { 0.0 };
            s += &format!("G1{}\n", point(x, y));
        }
        for k in 1..=cols {
            let x = if r % 2 == 0 { k } else { cols - k } as f64 * step;
            s += &format!("G1{}\n", point(x, y));
        }
    }
    s += "G0Z2\n";
    s
}
