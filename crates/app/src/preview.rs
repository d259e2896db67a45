//! Straight pieces of a program's path for a preview, in machine coordinates, each tagged
//! with its source line and whether it is a rapid, a feed or a plunge. The interpreter reads
//! the program (no second G-code reader in the page); arcs become chords.

use crate::check::Diag;
use crate::text::reader;
use oficina_canon::{from_arc_frame, to_arc_frame, CanonOp, Pos};
use oficina_gcode::CanonStream;
use oficina_gcode::Dialect;
use oficina_gcode::RunOptions;
use oficina_geom::{sweep_between, Helix, Point};
use oficina_motion::Profile;
use std::sync::Arc;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
/// The kind of a preview segment.
pub enum PathKind {
    /// A rapid.
    Rapid = 0,
    /// A feed move.
    Feed = 1,
    /// A feed move straight down (Z falls, X and Y stay).
    Plunge = 2,
}

#[derive(Clone, Copy, Debug, PartialEq)]
/// One straight piece of the toolpath preview.
pub struct PreviewSegment {
    /// Its kind.
    pub kind: PathKind,
    /// The source line it comes from.
    pub line: u32,
    /// Start, machine mm.
    pub from: [f64; 3],
    /// End, machine mm.
    pub to: [f64; 3],
}

/// Chord height allowed on arcs in the preview, mm: invisible at any zoom a workbench shows.
const CHORD_TOLERANCE: f64 = 0.01;
/// At most this many chords per full turn, so a 1 km radius arc stays a few hundred pieces.
const MAX_CHORDS_PER_TURN: f64 = 720.0;

/// Call `emit` for every straight piece of the path of `text`; returns the diagnostics.
pub fn for_each_segment(
    text: &Arc<String>,
    profile: &Profile,
    dialect: Dialect,
    mut emit: impl FnMut(PreviewSegment),
) -> Vec<Diag> {
    let mut run = RunOptions::check(dialect);
    run.initial_params = crate::run_options::initial_params_for(profile, dialect);
    let mut stream = CanonStream::spawn(reader(text), run);
    let [x, y, z] = profile.start;
    let mut at = Pos::xyz(x, y, z);
    for c in stream.by_ref() {
        let line = c.line;
        match c.op {
            CanonOp::StraightTraverse { to } => {
                emit(straight(PathKind::Rapid, line, &at, &to));
                at = to;
            }
            CanonOp::StraightFeed { to } => {
                emit(straight(PathKind::Feed, line, &at, &to));
                at = to;
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let axes = plane.axes();
                // In the arc's own frame (turned about Z under G10 L2 R), drawn in the machine's.
                let (s, e) = (
                    to_arc_frame(xyz(&at), rotation),
                    to_arc_frame(xyz(&end), rotation),
                );
                let (sx, sy) = (s[axes.0] - center[0], s[axes.1] - center[1]);
                let (ex, ey) = (e[axes.0] - center[0], e[axes.1] - center[1]);
                let (r0, r1) = (sx.hypot(sy), ex.hypot(ey));
                let (a0, a1) = (sy.atan2(sx), ey.atan2(ex));
                let sweep = sweep_between(a0, a1, turns);
                let helix = Helix {
                    plane,
                    arc: oficina_geom::Arc::new(Point::new(center[0], center[1]), r0, a0, sweep),
                    axial: (s[axes.2], e[axes.2]),
                };
                let n = chords(r0.max(r1), sweep);
                let mut prev = xyz(&at);
                for k in 1..=n {
                    let p = if k == n {
                        xyz(&end)
                    } else {
                        let f = k as f64 / n as f64;
                        from_arc_frame(helix.spiral_point_at(f, r1), rotation)
                    };
                    emit(PreviewSegment {
                        kind: PathKind::Feed,
                        line,
                        from: prev,
                        to: p,
                    });
                    prev = p;
                }
                at = end;
            }
            _ => {}
        }
    }
    stream.finish().iter().map(Diag::from).collect()
}

/// Chords for an arc of radius `r` sweeping `sweep` radians: the chord of angle θ stands
/// r(1 − cos θ/2) off the arc, so θ = 2 acos(1 − tol/r) keeps it within the tolerance.
fn chords(r: f64, sweep: f64) -> usize {
    let step = if r > CHORD_TOLERANCE {
        (2.0 * (1.0 - CHORD_TOLERANCE / r).acos()).max(std::f64::consts::TAU / MAX_CHORDS_PER_TURN)
    } else {
        std::f64::consts::PI
    };
    ((sweep.abs() / step).ceil() as usize).max(1)
}

fn xyz(p: &Pos) -> [f64; 3] {
    [p.x, p.y, p.z]
}

fn straight(kind: PathKind, line: u32, from: &Pos, to: &Pos) -> PreviewSegment {
    let plunge = kind == PathKind::Feed
        && to.z < from.z
        && (to.x - from.x).abs() < 1e-9
        && (to.y - from.y).abs() < 1e-9;
    PreviewSegment {
        kind: if plunge { PathKind::Plunge } else { kind },
        line,
        from: xyz(from),
        to: xyz(to),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segments(text: &str) -> Vec<PreviewSegment> {
        let profile = crate::profile::resolve("grbl-router").unwrap();
        let mut out = Vec::new();
        let diags = for_each_segment(&Arc::new(text.into()), &profile, Dialect::LinuxCnc, |s| {
            out.push(s)
        });
        assert!(diags.is_empty(), "{diags:?}");
        out
    }

    #[test]
    fn kinds_and_lines_follow_the_program() {
        let s = segments("G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG0 Z5\nM2\n");
        let kinds: Vec<_> = s.iter().map(|s| (s.kind, s.line)).collect();
        assert_eq!(
            kinds,
            [
                (PathKind::Rapid, 1),
                (PathKind::Plunge, 2),
                (PathKind::Feed, 3),
                (PathKind::Rapid, 4)
            ]
        );
        // Each piece starts where the one before ended.
        for w in s.windows(2) {
            assert_eq!(w[0].to, w[1].from);
        }
    }

    /// A Makelangelo-style Marlin program: G0 travel with the pen up is a rapid, G1 with the
    /// pen down a feed; the servo lines, the message and the homing read without a diagnostic
    /// worse than a note.
    #[test]
    fn a_marlin_plot_previews_with_its_travel_as_rapids() {
        let profile = crate::profile::resolve("grbl-router").unwrap();
        let text = "G28 X Y\nM280 P0 S90 T250\nM0 Ready for pen change\nG0 X10 Y10 F3000.0\nM280 P0 S25 T250\nG1 X20 Y10 F3000.0\nM280 P0 S90 T250\n";
        let mut out = Vec::new();
        let diags = for_each_segment(&Arc::new(text.into()), &profile, Dialect::Marlin, |s| {
            out.push(s)
        });
        assert!(diags.iter().all(|d| d.severity == "note"), "{diags:?}");
        let kinds: Vec<_> = out.iter().map(|s| (s.kind, s.line)).collect();
        assert!(kinds.contains(&(PathKind::Rapid, 4)), "{kinds:?}");
        assert!(kinds.contains(&(PathKind::Feed, 6)), "{kinds:?}");
    }

    #[test]
    fn a_full_circle_stays_on_its_radius() {
        let s = segments("G0 X10 Y0 Z0\nG2 X10 Y0 I-10 J0 F100\nM2\n");
        let arc: Vec<_> = s.iter().filter(|s| s.line == 2).collect();
        assert!(arc.len() > 50, "{}", arc.len());
        let c = arc[0].from;
        let centre = [c[0] - 10.0, c[1]];
        for p in &arc {
            let r = (p.to[0] - centre[0]).hypot(p.to[1] - centre[1]);
            assert!((r - 10.0).abs() < 1e-9, "{r}");
            // The chord's midpoint is inside the tolerance of the arc.
            let m = [(p.from[0] + p.to[0]) / 2.0, (p.from[1] + p.to[1]) / 2.0];
            let rm = (m[0] - centre[0]).hypot(m[1] - centre[1]);
            assert!(10.0 - rm <= CHORD_TOLERANCE + 1e-12, "{rm}");
        }
        assert_eq!(arc.last().unwrap().to, c);
    }
}
