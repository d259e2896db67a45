//! The stress corpus: generated programs that push the planner where it is weakest.
#![allow(dead_code)]

use oficina_canon::{Canon, CanonOp, PathControlMode, Plane, Pos};
use oficina_motion::Profile;

pub(crate) fn profile(name: &str) -> Profile {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../profiles")
        .join(name);
    Profile::load(&path).unwrap()
}

/// A tiny deterministic generator (no dependency, reproducible corpus).
pub(crate) struct Lcg(u64);
impl Lcg {
    pub(crate) fn new(seed: u64) -> Lcg {
        Lcg(seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407))
    }
    pub(crate) fn f(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
}

pub(crate) struct Prog {
    pub(crate) ops: Vec<Canon>,
    line: u32,
}

impl Prog {
    pub(crate) fn new(feed_mm_min: f64) -> Prog {
        let mut p = Prog {
            ops: Vec::new(),
            line: 0,
        };
        p.op(CanonOp::SetFeedRate(feed_mm_min));
        p
    }
    pub(crate) fn op(&mut self, op: CanonOp) {
        self.line += 1;
        self.ops.push(Canon {
            line: self.line,
            op,
        });
    }
    pub(crate) fn g0(&mut self, x: f64, y: f64, z: f64) {
        self.op(CanonOp::StraightTraverse {
            to: Pos::xyz(x, y, z),
        });
    }
    pub(crate) fn g1(&mut self, x: f64, y: f64, z: f64) {
        self.op(CanonOp::StraightFeed {
            to: Pos::xyz(x, y, z),
        });
    }
    pub(crate) fn arc(&mut self, x: f64, y: f64, z: f64, cx: f64, cy: f64, turns: i32) {
        self.op(CanonOp::ArcFeed {
            plane: Plane::XY,
            end: Pos::xyz(x, y, z),
            center: [cx, cy],
            turns,
            rotation: 0.0,
        });
    }
}

/// Program kinds of the corpus, each drawn around centre (cx, cy) at height z, scaled by `size`.
pub(crate) const KINDS: [&str; 10] = [
    "tiny-segments",
    "spiral",
    "tangent-arcs",
    "zigzag",
    "micron-segments",
    "full-circles",
    "reversals",
    "modes",
    "inverse-time",
    "mixed-rapids",
];

pub(crate) fn program(kind: &str, seed: u64, c: [f64; 3], size: f64) -> Prog {
    let mut r = Lcg::new(seed);
    let mut p = Prog::new(r.range(300.0, 6000.0));
    let [cx, cy, z] = c;
    p.g0(cx, cy, z);
    match kind {
        "tiny-segments" => {
            let n = 400;
            for i in 0..n {
                let t = i as f64 / n as f64;
                let w = r.range(-0.005, 0.005);
                p.g1(cx + t * size, cy + (t * 40.0).sin() * 0.05 * size + w, z);
            }
        }
        "spiral" => {
            let n = 600;
            for i in 1..=n {
                let a = i as f64 * r.range(0.05, 0.15);
                let rad = size * 0.5 * i as f64 / n as f64;
                p.g1(cx + rad * a.cos(), cy + rad * a.sin(), z);
            }
        }
        "tangent-arcs" => {
            // S-bends: alternating half circles tangent at their joints.
            let rad = size * r.range(0.02, 0.1);
            let mut x = cx - size * 0.5;
            p.g1(x, cy, z);
            for i in 0..8 {
                let turns = if i % 2 == 0 { -1 } else { 1 };
                p.arc(x + 2.0 * rad, cy, z, x + rad, cy, turns);
                x += 2.0 * rad;
            }
        }
        "zigzag" => {
            for i in 0..200 {
                let x = cx - size * 0.5 + size * i as f64 / 200.0;
                let y = cy + if i % 2 == 0 { 1.0 } else { -1.0 } * r.range(0.0, size * 0.3);
                p.g1(x, y, z);
            }
        }
        "micron-segments" => {
            let mut x = cx;
            let mut y = cy;
            for i in 0..1500 {
                let a = (i as f64 * 0.01).sin() * r.range(0.5, 1.5);
                x += 0.001 * a.cos();
                y += 0.001 * a.sin();
                p.g1(x, y, z);
            }
        }
        "full-circles" => {
            let rad = size * r.range(0.05, 0.4);
            p.g1(cx + rad, cy, z);
            p.arc(cx + rad, cy, z, cx, cy, 1);
            p.arc(cx + rad, cy, z - 2.0, cx, cy, -3); // a helix down, 3 turns
            p.arc(cx + rad, cy, z - 2.0, cx, cy, 2);
        }
        "reversals" => {
            for i in 0..60 {
                let d = r.range(0.01, size * 0.4);
                let s = if i % 2 == 0 { 1.0 } else { -1.0 };
                p.g1(cx + s * d, cy, z);
                p.g1(cx, cy, z);
            }
        }
        "modes" => {
            for i in 0..40 {
                let mode = match i % 3 {
                    0 => PathControlMode::ExactStop,
                    1 => PathControlMode::Continuous,
                    _ => PathControlMode::ExactPath,
                };
                p.op(CanonOp::SetMotionControlMode {
                    mode,
                    tolerance: r.range(0.0, 0.05),
                });
                p.g1(
                    cx + r.range(-0.4, 0.4) * size,
                    cy + r.range(-0.4, 0.4) * size,
                    z,
                );
                if i % 10 == 9 {
                    p.op(CanonOp::Dwell(0.1));
                }
            }
        }
        "inverse-time" => {
            p.op(CanonOp::SetFeedMode(oficina_canon::FeedMode::InverseTime));
            for _ in 0..30 {
                p.op(CanonOp::SetFeedRate(r.range(20.0, 2000.0)));
                p.g1(
                    cx + r.range(-0.4, 0.4) * size,
                    cy + r.range(-0.4, 0.4) * size,
                    z,
                );
            }
            p.op(CanonOp::SetFeedMode(
                oficina_canon::FeedMode::UnitsPerMinute,
            ));
        }
        _ => {
            for i in 0..50 {
                let (x, y) = (
                    cx + r.range(-0.45, 0.45) * size,
                    cy + r.range(-0.45, 0.45) * size,
                );
                if i % 4 == 0 {
                    p.g0(x, y, z);
                } else {
                    p.g1(x, y, z - r.range(0.0, 1.0));
                }
            }
        }
    }
    p.op(CanonOp::ProgramEnd);
    p
}

/// `ops` numbered as the lines 1, 2, … of a program.
pub(crate) fn numbered(ops: impl IntoIterator<Item = CanonOp>) -> Vec<Canon> {
    ops.into_iter()
        .enumerate()
        .map(|(i, op)| Canon {
            line: i as u32 + 1,
            op,
        })
        .collect()
}
