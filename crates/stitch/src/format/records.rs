//! The record stream both formats share: increments in 0.1 mm and a command per record.

use super::{Format, FormatError};
use crate::plan::{ColorBlock, Kind, Stitch, StitchPlan, Thread};

/// What a record does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// A sewn stitch.
    Stitch,
    /// A move with the needle up.
    Jump,
    /// Cut the thread.
    Trim,
    /// Change to the next colour.
    ColorChange,
    /// Stop for the operator.
    Stop,
    /// End of the design.
    End,
}

/// One record: an increment in 0.1 mm (y up) and its command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rec {
    /// X increment, 0.1 mm.
    pub dx: i32,
    /// Y increment, 0.1 mm (y up).
    pub dy: i32,
    /// The command.
    pub op: Op,
}

impl Rec {
    /// A record of `op` moving (`dx`, `dy`) in 0.1 mm.
    pub fn new(dx: i32, dy: i32, op: Op) -> Rec {
        Rec { dx, dy, op }
    }
}

/// Coordinates beyond ±10 m are refused: no hoop is that large and i32 sums stay exact.
const MAX_UNITS: f64 = 100_000.0;

/// The records of a plan, moves split so that no axis exceeds `max` units per record.
pub(super) fn to_records(
    plan: &StitchPlan,
    max: i32,
    format: Format,
) -> Result<Vec<Rec>, FormatError> {
    let mut out = Vec::new();
    let mut cur = (0i32, 0i32);
    for (b, block) in plan.blocks.iter().enumerate() {
        if b > 0 {
            out.push(Rec::new(0, 0, Op::ColorChange));
        }
        for (i, s) in block.stitches.iter().enumerate() {
            let (ux, uy) = (s.x * 10.0, s.y * 10.0);
            if !(ux.abs() <= MAX_UNITS && uy.abs() <= MAX_UNITS) {
                return Err(FormatError::new(
                    format,
                    out.len(),
                    format!(
                        "block {} entry {i}: point ({}, {}) mm is not finite or beyond ±10 m",
                        b + 1,
                        s.x,
                        s.y
                    ),
                ));
            }
            let target = (ux.round() as i32, uy.round() as i32);
            match s.kind {
                Kind::Stitch => split(&mut out, cur, target, max, Op::Stitch, true),
                Kind::Jump => split(&mut out, cur, target, max, Op::Jump, false),
                Kind::Trim => out.push(Rec::new(0, 0, Op::Trim)),
                Kind::Stop => out.push(Rec::new(0, 0, Op::Stop)),
            }
            if matches!(s.kind, Kind::Stitch | Kind::Jump) {
                cur = target;
            }
        }
    }
    out.push(Rec::new(0, 0, Op::End));
    Ok(out)
}

/// n = ceil(max(|dx|, |dy|) / max) equal records; the intermediate points are rounded on
/// absolute positions so they sum exactly to the move.
fn split(out: &mut Vec<Rec>, from: (i32, i32), to: (i32, i32), max: i32, op: Op, keep_zero: bool) {
    let (dx, dy) = (to.0 - from.0, to.1 - from.1);
    let n = (dx.abs().max(dy.abs()) + max - 1) / max;
    if n == 0 {
        if keep_zero {
            out.push(Rec::new(0, 0, op));
        }
        return;
    }
    let mut prev = from;
    for k in 1..=n {
        let t = k as f64 / n as f64;
        let p = (
            from.0 + (dx as f64 * t).round() as i32,
            from.1 + (dy as f64 * t).round() as i32,
        );
        out.push(Rec::new(p.0 - prev.0, p.1 - prev.1, op));
        prev = p;
    }
}

/// Thread colours for files that carry none: distinct, in the order machines often load.
pub(super) const PALETTE: [[u8; 3]; 8] = [
    [0, 0, 0],
    [200, 30, 30],
    [30, 90, 200],
    [30, 150, 60],
    [240, 200, 20],
    [140, 60, 170],
    [240, 130, 20],
    [120, 120, 120],
];

/// When a run of jumps also cuts the thread, for formats that have no trim command of their
/// own (as pyembroidery reads them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum TrimRule {
    /// Only explicit trim records cut.
    Explicit,
    /// A run of this many jumps or more cuts (DST: three).
    Jumps(usize),
    /// A run that goes further than this many units on either axis cuts (JEF: 30, 3 mm).
    Distance(i64),
}

/// A plan from records. A run of consecutive jumps becomes one jump to its end; under
/// `rule`, a run is also a trim where it starts, unless the thread is already cut (no stitch
/// since the start, a trim or a colour change). A run that ends where it began moves
/// nothing and leaves no jump. A colour change's own displacement, if any, is a jump at the
/// start of the next block.
pub(super) fn to_plan(recs: &[Rec], rule: TrimRule) -> StitchPlan {
    let new_block = |n: usize| {
        let [r, g, b] = PALETTE[n % PALETTE.len()];
        ColorBlock {
            thread: Thread::rgb(r, g, b),
            stitches: Vec::new(),
        }
    };
    let mut blocks = vec![new_block(0)];
    let (mut x, mut y) = (0i64, 0i64);
    let mm = |v: i64| v as f64 / 10.0;
    // The jump run in progress: its record count, where it started and how far it went.
    let mut run = 0usize;
    let mut run_far = 0i64;
    let mut run_from = (0i64, 0i64);
    let mut trimmed = true;
    let flush = |blocks: &mut Vec<ColorBlock>,
                 trimmed: &mut bool,
                 run: usize,
                 far: i64,
                 from: (i64, i64),
                 to: (i64, i64)| {
        let Some(block) = blocks.last_mut() else {
            return;
        };
        let cuts = match rule {
            TrimRule::Explicit => false,
            TrimRule::Jumps(n) => run >= n,
            TrimRule::Distance(d) => far > d,
        };
        if run > 0 && cuts && !*trimmed {
            *trimmed = true;
            block
                .stitches
                .push(Stitch::new(mm(from.0), mm(from.1), Kind::Trim));
        }
        if run > 0 && to != from {
            block
                .stitches
                .push(Stitch::new(mm(to.0), mm(to.1), Kind::Jump));
        }
    };
    for r in recs {
        if r.op == Op::Jump {
            if run == 0 {
                run_from = (x, y);
                run_far = 0;
            }
            run += 1;
            x += r.dx as i64;
            y += r.dy as i64;
            run_far = run_far.max((x - run_from.0).abs().max((y - run_from.1).abs()));
            continue;
        }
        flush(&mut blocks, &mut trimmed, run, run_far, run_from, (x, y));
        run = 0;
        x += r.dx as i64;
        y += r.dy as i64;
        let Some(block) = blocks.last_mut() else {
            break;
        };
        let at = |kind| Stitch::new(mm(x), mm(y), kind);
        trimmed = match r.op {
            Op::Stitch => false,
            Op::Trim | Op::ColorChange => true,
            _ => trimmed,
        };
        match r.op {
            Op::Stitch => block.stitches.push(at(Kind::Stitch)),
            Op::Trim => block.stitches.push(at(Kind::Trim)),
            Op::Stop => block.stitches.push(at(Kind::Stop)),
            Op::ColorChange => {
                let n = blocks.len();
                blocks.push(new_block(n));
                if r.dx != 0 || r.dy != 0 {
                    if let Some(b) = blocks.last_mut() {
                        b.stitches.push(at(Kind::Jump));
                    }
                }
            }
            // Jumps were taken above.
            Op::Jump => {}
            Op::End => break,
        }
    }
    flush(&mut blocks, &mut trimmed, run, run_far, run_from, (x, y));
    if blocks.len() > 1 && blocks.last().is_some_and(|b| b.stitches.is_empty()) {
        blocks.pop();
    }
    StitchPlan {
        name: String::new(),
        blocks,
    }
}

/// Gives the blocks the file's threads in order; blocks beyond the list keep their default.
pub(super) fn set_threads(plan: &mut StitchPlan, threads: &[Thread]) {
    for (b, t) in plan.blocks.iter_mut().zip(threads) {
        b.thread = t.clone();
    }
}

/// Formats whose only pause is a colour change write a stop as a change to the same thread
/// again; read back, a change between two equal threads is a stop (as pyembroidery reads
/// PES, PEC and JEF). `threads` holds one thread per block the changes separate.
pub(super) fn duplicates_as_stops(recs: &mut [Rec], threads: &mut Vec<Thread>) {
    let mut kept: Vec<Thread> = threads.iter().take(1).cloned().collect();
    let mut k = 0;
    for r in recs.iter_mut().filter(|r| r.op == Op::ColorChange) {
        k += 1;
        let Some(next) = threads.get(k) else { break };
        if kept.last() == Some(next) {
            r.op = Op::Stop;
        } else {
            kept.push(next.clone());
        }
    }
    kept.extend(threads.iter().skip(k + 1).cloned());
    *threads = kept;
}

/// The threads a plan's blocks and stops ask for, one per colour change or stop plus the
/// first: a stop repeats the thread before it.
pub(super) fn thread_sequence(recs: &[Rec], plan: &StitchPlan) -> Vec<Thread> {
    let mut blocks = plan.blocks.iter().map(|b| b.thread.clone());
    let mut cur = blocks
        .next()
        .unwrap_or_else(|| Thread::rgb(PALETTE[0][0], PALETTE[0][1], PALETTE[0][2]));
    let mut out = vec![cur.clone()];
    for r in recs {
        match r.op {
            Op::ColorChange => {
                if let Some(t) = blocks.next() {
                    cur = t;
                }
                out.push(cur.clone());
            }
            Op::Stop => out.push(cur.clone()),
            _ => {}
        }
    }
    out
}

/// The bounds of the records' points in units: [min x, min y, max x, max y] (0s when empty),
/// and the last point.
pub(super) fn extents(recs: &[Rec]) -> ([i64; 4], (i64, i64)) {
    let (mut x, mut y) = (0i64, 0i64);
    let mut b: Option<[i64; 4]> = None;
    for r in recs {
        x += r.dx as i64;
        y += r.dy as i64;
        if matches!(r.op, Op::Stitch | Op::Jump) {
            b = Some(match b {
                None => [x, y, x, y],
                Some([a, c, d, e]) => [a.min(x), c.min(y), d.max(x), e.max(y)],
            });
        }
    }
    (b.unwrap_or([0; 4]), (x, y))
}
