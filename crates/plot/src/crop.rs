//! Cropping strokes to a box: what lies outside is dropped, and a stroke that leaves and comes
//! back becomes two strokes, with the pen lifted between them.

use oficina_geom::Point;

use crate::clip::{cut, Area};
use crate::strokes::Plot;

/// Keeps the parts of every stroke inside `[x0, y0, x1, y1]` (edges included).
pub fn crop(plot: &mut Plot, b: [f64; 4]) -> Result<(), String> {
    if !(b.iter().all(|v| v.is_finite()) && b[2] > b[0] && b[3] > b[1]) {
        return Err(format!("crop box {b:?}: needs X0 < X1 and Y0 < Y1 (mm)"));
    }
    let area = Area::new(vec![vec![
        [b[0], b[1]],
        [b[2], b[1]],
        [b[2], b[3]],
        [b[0], b[3]],
    ]])
    .expect("a box has four corners");
    for pen in &mut plot.pens {
        pen.strokes = std::mem::take(&mut pen.strokes)
            .into_iter()
            .flat_map(|s| {
                // Wholly inside: kept as is (the common case, no cutting).
                if s.iter().all(|p| inside(*p, &b)) {
                    vec![s]
                } else {
                    cut(&s, &area, true, true)
                }
            })
            .collect();
    }
    Ok(())
}

fn inside(p: Point, b: &[f64; 4]) -> bool {
    p.x >= b[0] && p.x <= b[2] && p.y >= b[1] && p.y <= b[3]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strokes::Pen;

    #[test]
    fn a_zigzag_leaving_the_box_is_cut_into_pieces() {
        let z: Vec<Point> = [(0.0, 5.0), (20.0, 5.0), (20.0, 6.0), (0.0, 6.0)]
            .iter()
            .map(|&(x, y)| Point::new(x, y))
            .collect();
        let mut p = Plot {
            pens: vec![Pen {
                name: "p".into(),
                strokes: vec![z],
            }],
        };
        crop(&mut p, [0.0, 0.0, 10.0, 10.0]).unwrap();
        assert_eq!(p.pens[0].strokes.len(), 2);
        assert!((p.lengths().pen_down - 20.0).abs() < 1e-9);
        assert!((p.lengths().pen_up - 1.0).abs() < 1e-9);
        assert!(crop(&mut p, [0.0, 0.0, 0.0, 10.0]).is_err());
    }
}
