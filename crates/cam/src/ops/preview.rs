//! An SVG picture of a toolpath over its drawing: the drawing in black, cutting moves in
//! blue, rapids in dashed red, Y up as on the machine.

use crate::{Move, Toolpath};
use oficina_canon::{Canon, CanonOp};
use oficina_geom::Path;
use std::fmt::Write;

/// The SVG text (mm units) of the toolpath's own moves: the tool centre, except under
/// cutter compensation, where they are the outline (see [`preview_canon_svg`]).
pub fn preview_svg(drawing: &[Path], tp: &Toolpath) -> String {
    let (plain, _) = crate::toolpath::plain_moves(
        &tp.operations
            .iter()
            .flat_map(|o| o.moves.iter().cloned())
            .collect::<Vec<_>>(),
        [0.0, 0.0, tp.safe_z],
    );
    preview_moves(drawing, &plain, tp.safe_z)
}

/// The SVG text of a program as the interpreter read it back: for G41/G42 programs this is
/// the compensated tool-centre path the control will cut, not the programmed outline.
pub fn preview_canon_svg(drawing: &[Path], canon: &[Canon], safe_z: f64) -> String {
    let pos = |p: &oficina_canon::Pos| [p.x, p.y, p.z];
    let plain: Vec<Move> = canon
        .iter()
        .filter_map(|c| match &c.op {
            CanonOp::StraightTraverse { to } => Some(Move::Rapid { to: pos(to) }),
            CanonOp::StraightFeed { to } => Some(Move::Line {
                to: pos(to),
                feed: 0.0,
            }),
            CanonOp::ArcFeed {
                plane: oficina_canon::Plane::XY,
                end,
                center,
                turns,
                ..
            } => Some(Move::Arc {
                to: pos(end),
                center: *center,
                ccw: *turns > 0,
                feed: 0.0,
            }),
            _ => None,
        })
        .collect();
    preview_moves(drawing, &plain, safe_z)
}

fn preview_moves(drawing: &[Path], plain: &[Move], safe_z: f64) -> String {
    let mut pts: Vec<[f64; 2]> = drawing
        .iter()
        .flat_map(|p| p.flatten(0.05))
        .map(|p| [p.x, p.y])
        .collect();
    pts.extend(
        plain
            .iter()
            .filter_map(Move::end)
            .filter(|e| e[0].is_finite() && e[1].is_finite())
            .map(|e| [e[0], e[1]]),
    );
    let (x0, y0, x1, y1) = oficina_geom::bounds(pts.iter().copied())
        .map_or((0.0, 0.0, 1.0, 1.0), |b| (b.x0, b.y0, b.x1, b.y1));
    let m = 2.0;
    let (w, h) = (x1 - x0 + 2.0 * m, y1 - y0 + 2.0 * m);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.2}mm" height="{h:.2}mm" viewBox="{:.3} {:.3} {w:.3} {h:.3}">"#,
        x0 - m,
        -(y1 + m)
    );
    let _ = writeln!(s, r#"<g transform="scale(1,-1)" fill="none">"#);
    for p in drawing {
        let d = p.flatten(0.02);
        let _ = write!(s, r#"<polyline stroke="black" stroke-width="0.2" points=""#);
        for q in &d {
            let _ = write!(s, "{:.3},{:.3} ", q.x, q.y);
        }
        if p.closed {
            if let Some(q) = d.first() {
                let _ = write!(s, "{:.3},{:.3}", q.x, q.y);
            }
        }
        let _ = writeln!(s, r#""/>"#);
    }
    // Runs of cutting moves become one polyline; arcs are drawn as chords.
    let mut at = [f64::NAN, f64::NAN, safe_z];
    let mut run: Vec<[f64; 2]> = Vec::new();
    let flush = |s: &mut String, run: &mut Vec<[f64; 2]>| {
        if run.len() > 1 {
            let _ = write!(s, r#"<polyline stroke="blue" stroke-width="0.1" points=""#);
            for q in run.iter() {
                let _ = write!(s, "{:.3},{:.3} ", q[0], q[1]);
            }
            let _ = writeln!(s, r#""/>"#);
        }
        run.clear();
    };
    for m in plain {
        match *m {
            Move::Rapid { to } => {
                flush(&mut s, &mut run);
                if at[0].is_finite() && to[0].is_finite() && (at[0] != to[0] || at[1] != to[1]) {
                    let _ = writeln!(
                        s,
                        r#"<line stroke="red" stroke-width="0.1" stroke-dasharray="1,1" x1="{:.3}" y1="{:.3}" x2="{:.3}" y2="{:.3}"/>"#,
                        at[0], at[1], to[0], to[1]
                    );
                }
                at = to;
            }
            Move::Line { to, .. } => {
                if run.is_empty() {
                    run.push([at[0], at[1]]);
                }
                run.push([to[0], to[1]]);
                at = to;
            }
            Move::Arc {
                to, center, ccw, ..
            } => {
                if run.is_empty() {
                    run.push([at[0], at[1]]);
                }
                let arc = oficina_geom::Arc::from_center(
                    (at[0], at[1]).into(),
                    (to[0], to[1]).into(),
                    (center[0], center[1]).into(),
                    if ccw { 1 } else { -1 },
                );
                run.extend(arc.flatten(0.02).into_iter().skip(1).map(|p| [p.x, p.y]));
                at = to;
            }
            _ => {}
        }
    }
    flush(&mut s, &mut run);
    let _ = writeln!(s, "</g>\n</svg>");
    s
}
