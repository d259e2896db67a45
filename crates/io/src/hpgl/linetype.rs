//! `LT`: dashed and dotted lines, as the plotter draws them (the pen lifts in the gaps).
//!
//! A pattern is a list of alternating pen-down and gap lengths in percent of the pattern
//! length, starting with pen-down; a pen-down element of 0 % is a dot. Fixed types (1…8) run
//! continuously along a pen-down path, restarting after each pen-up move; adaptive types
//! (−1…−8) fit a whole number of patterns into every line segment (the nearest number, at
//! least one, each stretched to fit), so corners are drawn. The tables are HP-GL/2's default
//! line types as hp2xx lists them (lindef.c). The pattern length is a percentage of the
//! diagonal P1–P2 (LT n,l or LT n,l,0), or millimetres (LT n,l,1); by default 4 % of it.

use oficina_geom::Point;

/// Pen-down / gap percentages of the fixed types 1…8.
const FIXED: [&[f64]; 8] = [
    &[0.0, 100.0],
    &[50.0, 50.0],
    &[70.0, 30.0],
    &[80.0, 10.0, 0.0, 10.0],
    &[70.0, 10.0, 10.0, 10.0],
    &[50.0, 10.0, 10.0, 10.0, 10.0, 10.0],
    &[70.0, 10.0, 0.0, 10.0, 0.0, 10.0],
    &[50.0, 10.0, 0.0, 10.0, 10.0, 10.0, 0.0, 10.0],
];

/// The adaptive types −1…−8: symmetric, so that a segment starts and ends with pen-down.
const ADAPTIVE: [&[f64]; 8] = [
    &[0.0, 100.0, 0.0],
    &[25.0, 50.0, 25.0],
    &[35.0, 30.0, 35.0],
    &[40.0, 10.0, 0.0, 10.0, 40.0],
    &[35.0, 10.0, 10.0, 10.0, 35.0],
    &[25.0, 10.0, 10.0, 10.0, 10.0, 10.0, 25.0],
    &[35.0, 10.0, 0.0, 10.0, 0.0, 10.0, 35.0],
    &[25.0, 10.0, 0.0, 10.0, 10.0, 10.0, 0.0, 10.0, 25.0],
];

/// A line type in force: its number (−8…−1, 1…8) and pattern length in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LineType {
    pub kind: i32,
    pub length: f64,
}

/// The pen-down pieces of the polyline `pts` drawn in line type `lt`, and how many dots the
/// pattern places (drawn by the plotter as a touch of the pen; counted, not drawn here).
pub(super) fn dash(pts: &[Point], lt: LineType) -> (Vec<Vec<Point>>, usize) {
    let mut pieces: Vec<Vec<Point>> = Vec::new();
    let mut dots = 0;
    let len = lt.length.max(1e-6);
    if lt.kind < 0 {
        let pat = ADAPTIVE[(-lt.kind - 1).clamp(0, 7) as usize];
        for w in pts.windows(2) {
            let seg = w[0].distance(w[1]);
            if seg < 1e-9 {
                continue;
            }
            let n = (seg / len).round().clamp(1.0, 100_000.0) as usize;
            let each = seg / n as f64;
            for k in 0..n {
                let a = w[0].lerp(w[1], k as f64 / n as f64);
                let b = w[0].lerp(w[1], (k + 1) as f64 / n as f64);
                walk(&[a, b], pat, each, &mut pieces, &mut dots);
            }
        }
    } else {
        let pat = FIXED[(lt.kind - 1).clamp(0, 7) as usize];
        walk(pts, pat, len, &mut pieces, &mut dots);
    }
    (pieces, dots)
}

/// Runs `pat` (percentages of `len`) along the polyline from the pattern's start,
/// collecting pen-down pieces and dots.
fn walk(pts: &[Point], pat: &[f64], len: f64, out: &mut Vec<Vec<Point>>, dots: &mut usize) {
    // Element boundaries in mm within one pattern.
    let mut ends = Vec::with_capacity(pat.len());
    let mut acc = 0.0;
    for p in pat {
        acc += p / 100.0 * len;
        ends.push(acc);
    }
    if acc <= 0.0 {
        return;
    }
    let mut pos = 0.0; // position within the pattern, mm
    let mut elem = 0;
    let mut cur: Option<Vec<Point>> = None;
    if elem % 2 == 0 {
        if pat[elem] == 0.0 {
            *dots += 1;
        } else {
            cur = Some(vec![pts[0]]);
        }
    }
    let mut budget = 0usize;
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let seg = a.distance(b);
        let mut done = 0.0;
        while seg - done > 1e-12 {
            budget += 1;
            if budget > 10_000_000 {
                return;
            }
            let left_in_elem = ends[elem] - pos;
            let step = left_in_elem.min(seg - done);
            done += step;
            pos += step;
            let p = a.lerp(b, done / seg);
            if let Some(c) = &mut cur {
                c.push(p);
            }
            if ends[elem] - pos <= 1e-12 {
                // The element ends here: the next begins (wrapping to the pattern's start).
                if let Some(c) = cur.take() {
                    out.push(c);
                }
                elem += 1;
                if elem == ends.len() {
                    elem = 0;
                    pos = 0.0;
                }
                if elem % 2 == 0 {
                    if pat[elem] == 0.0 {
                        *dots += 1;
                    } else {
                        cur = Some(vec![p]);
                    }
                }
            }
        }
    }
    if let Some(c) = cur {
        if c.len() >= 2 {
            out.push(c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(pieces: &[Vec<Point>]) -> f64 {
        pieces
            .iter()
            .flat_map(|p| p.windows(2))
            .map(|w| w[0].distance(w[1]))
            .sum()
    }

    #[test]
    fn fixed_dashes_run_across_corners() {
        // Type 2 (50 % down, 50 % up), 10 mm pattern, along 12 mm then 13 mm: down 0–5,
        // 10–15 (across the corner), 20–25.
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(12.0, 0.0),
            Point::new(12.0, 13.0),
        ];
        let (pieces, dots) = dash(
            &pts,
            LineType {
                kind: 2,
                length: 10.0,
            },
        );
        assert_eq!(dots, 0);
        assert_eq!(pieces.len(), 3);
        assert!((total(&pieces) - 15.0).abs() < 1e-9);
        assert_eq!(
            pieces[1],
            vec![
                Point::new(10.0, 0.0),
                Point::new(12.0, 0.0),
                Point::new(12.0, 3.0)
            ]
        );
    }

    #[test]
    fn adaptive_patterns_fit_each_segment() {
        // Type −2 (25/50/25) on a 25 mm segment with a 10 mm pattern: 2 patterns of 12.5 mm,
        // pen down half the time, ends drawn.
        let pts = [Point::new(0.0, 0.0), Point::new(25.0, 0.0)];
        let (pieces, _) = dash(
            &pts,
            LineType {
                kind: -2,
                length: 10.0,
            },
        );
        assert!((total(&pieces) - 12.5).abs() < 1e-9);
        assert_eq!(pieces[0][0], Point::new(0.0, 0.0));
        assert_eq!(
            *pieces.last().unwrap().last().unwrap(),
            Point::new(25.0, 0.0)
        );
        // Type 1: dots only.
        let (pieces, dots) = dash(
            &pts,
            LineType {
                kind: 1,
                length: 10.0,
            },
        );
        assert!(pieces.is_empty());
        assert_eq!(dots, 3);
    }
}
