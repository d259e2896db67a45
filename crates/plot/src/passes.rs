//! After ordering: closed strokes begin where the pen is (reloop), and every stroke is drawn
//! several times (multipass) for pens that need more than one pass.

use oficina_geom::Point;

use crate::optimise::Optimise;
use crate::order::{apply, nearest_neighbour, two_opt};
use crate::strokes::{Plot, Stroke};

/// Orders each pen's strokes again (after an even number of passes an open stroke ends
/// where it began, so the order made for its old end no longer holds).
pub(crate) fn reorder(plot: &mut Plot, o: &Optimise, home: Point) {
    let mut at = home;
    for pen in &mut plot.pens {
        if !pen.strokes.is_empty() {
            let mut tour = nearest_neighbour(&pen.strokes, at);
            if o.two_opt_window > 0 {
                two_opt(
                    &pen.strokes,
                    &mut tour,
                    at,
                    o.two_opt_window,
                    o.two_opt_passes,
                );
            }
            pen.strokes = apply(std::mem::take(&mut pen.strokes), &tour);
        }
        if let Some(&p) = pen.strokes.last().and_then(|s| s.last()) {
            at = p;
        }
    }
}

/// More passes than this are refused.
pub const MAX_PASSES: usize = 100;

fn is_closed(s: &Stroke) -> bool {
    s.len() > 2 && s[0].distance(*s.last().unwrap()) < 1e-9
}

/// Rotates each closed stroke to start at its vertex nearest the pen's position before it
/// (the previous stroke's end, `home` for the first). Open strokes are left as they are.
pub fn reloop(plot: &mut Plot, home: Point) {
    let mut at = home;
    for pen in &mut plot.pens {
        for s in &mut pen.strokes {
            if is_closed(s) {
                let n = s.len() - 1; // the last point repeats the first
                let k = (0..n)
                    .min_by(|&a, &b| s[a].distance(at).total_cmp(&s[b].distance(at)))
                    .unwrap_or(0);
                if k > 0 {
                    s.pop();
                    s.rotate_left(k);
                    s.push(s[0]);
                }
            }
            if let Some(&p) = s.last() {
                at = p;
            }
        }
    }
}

/// Draws every stroke `n` times without lifting the pen: a closed stroke goes round `n`
/// times, an open one back and forth (as vpype's `multipass`).
pub fn multipass(plot: &mut Plot, n: usize) -> Result<(), String> {
    if !(1..=MAX_PASSES).contains(&n) {
        return Err(format!("--passes {n}: use 1 to {MAX_PASSES}"));
    }
    for pen in &mut plot.pens {
        for s in &mut pen.strokes {
            let one = s.clone();
            let closed = is_closed(&one);
            for k in 1..n {
                if closed || k % 2 == 0 {
                    s.extend_from_slice(&one[1..]);
                } else {
                    s.extend(one.iter().rev().skip(1));
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strokes::Pen;

    fn plot(strokes: Vec<Stroke>) -> Plot {
        Plot {
            pens: vec![Pen {
                name: "p".into(),
                strokes,
            }],
        }
    }

    #[test]
    fn reloop_starts_at_the_nearest_vertex_and_keeps_the_loop() {
        let sq: Stroke = [
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (0.0, 10.0),
            (0.0, 0.0),
        ]
        .iter()
        .map(|&(x, y)| Point::new(x, y))
        .collect();
        let mut p = plot(vec![sq.clone()]);
        reloop(&mut p, Point::new(11.0, 9.0));
        let s = &p.pens[0].strokes[0];
        assert_eq!(s[0], Point::new(10.0, 10.0));
        assert_eq!(s.last(), Some(&Point::new(10.0, 10.0)));
        assert_eq!(s.len(), 5);
        assert!((crate::polyline_length(s) - 40.0).abs() < 1e-12);
        let mut p = plot(vec![sq, vec![Point::new(0.0, 0.0), Point::new(5.0, 0.0)]]);
        multipass(&mut p, 3).unwrap();
        assert!((crate::polyline_length(&p.pens[0].strokes[0]) - 120.0).abs() < 1e-12);
        let open = &p.pens[0].strokes[1];
        assert!((crate::polyline_length(open) - 15.0).abs() < 1e-12);
        assert_eq!(open.last(), Some(&Point::new(5.0, 0.0)));
        assert!(multipass(&mut p, 0).is_err());
        assert!(multipass(&mut p, 1000).is_err());
    }
}
