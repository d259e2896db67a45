//! Single-stroke text from the Hershey fonts (the `vector-text-hershey` crate's data, Paul
//! Bourke's compilation): each glyph is strokes, so a pen draws a letter once.

use oficina_geom::{Point, Vec2};
use vector_text_core::Renderer;
use vector_text_hershey::{HersheyFont, HersheyRenderer};

use crate::strokes::Stroke;

/// Hershey's Roman Simplex capitals run from y = −12 to the baseline at y = 9 (y down).
const CAP_UNITS: f64 = 21.0;
const BASELINE: f64 = 9.0;
/// Line pitch, in the font's units.
const LINE_UNITS: f64 = 32.0;

/// Strokes of `text` with its first baseline starting at `at`, capitals `height` mm tall,
/// the baseline turned `angle` radians counter-clockwise. `\n` starts a new line below.
pub fn text_strokes(text: &str, at: Point, height: f64, angle: f64) -> Vec<Stroke> {
    let s = height / CAP_UNITS;
    let (u, v) = (
        Vec2::from_angle(angle),
        Vec2::from_angle(angle + std::f64::consts::FRAC_PI_2),
    );
    let mut out: Vec<Stroke> = Vec::new();
    for (row, line) in text.lines().enumerate() {
        let mut cur: Stroke = Vec::new();
        for p in HersheyRenderer::render_text(line, HersheyFont::Romans) {
            let x = p.x as f64 * s;
            let y = (BASELINE - p.y as f64 - row as f64 * LINE_UNITS) * s;
            let q = at + u * x + v * y;
            if !p.pen && cur.len() > 1 {
                out.push(std::mem::take(&mut cur));
            }
            if !p.pen {
                cur.clear();
            }
            cur.push(q);
        }
        if cur.len() > 1 {
            out.push(cur);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capitals_have_the_asked_height_and_letters_are_single_strokes() {
        let s = text_strokes("HI", Point::new(10.0, 20.0), 7.0, 0.0);
        // H is three strokes (two stems and the bar), I one.
        assert_eq!(s.len(), 4, "{s:?}");
        let ys: Vec<f64> = s.iter().flatten().map(|p| p.y).collect();
        let (lo, hi) = ys
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &y| (a.min(y), b.max(y)));
        assert!(
            (lo - 20.0).abs() < 1e-9 && (hi - 27.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        let turned = text_strokes("I", Point::ORIGIN, 21.0, std::f64::consts::FRAC_PI_2);
        // Turned a quarter turn, the stem (4 units into I's cell) lies along −X at y = 4.
        let p = turned[0][0];
        assert!(p.x < -20.0 && (p.y - 4.0).abs() < 1e-9, "{p:?}");
    }
}
