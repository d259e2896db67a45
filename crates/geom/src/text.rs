//! Single-stroke text from the Hershey fonts (the `vector-text-hershey` crate's data, Paul
//! Bourke's compilation): each glyph is strokes, so a pen draws a letter once and a cutter
//! engraves it on its centre line. One font in one place: the plotter's and the mill's
//! `--text`, and the SVG and DXF importers' text, all draw with it.
//!
//! Hershey's Roman Simplex capitals run from y = −12 to the baseline at y = 9 (y down) in the
//! font's units; here a glyph is measured in cap heights (capitals are 1 tall), y up, its
//! baseline on y = 0 and its cell starting at x = 0.
//!
//! The font data's licence asks for this acknowledgement to go with it: the Hershey Fonts
//! were originally created by Dr. A. V. Hershey while working at the U. S. National Bureau
//! of Standards; the format of the font data in this distribution was originally created by
//! James Hurt, Cognition, Inc.

use crate::{Point, Vec2};
use std::sync::OnceLock;
use vector_text_core::Renderer;
use vector_text_hershey::{HersheyFont, HersheyRenderer};

/// Capital height of Roman Simplex, in the font's units.
const CAP_UNITS: f64 = 21.0;
/// Baseline of Roman Simplex, in the font's units (y down).
const BASELINE: f64 = 9.0;
/// Line pitch, in cap heights (32 font units).
pub const LINE_PITCH: f64 = 32.0 / CAP_UNITS;
/// Capital height per em (an SVG `font-size`). Roman Simplex has no em of its own; 0.7 is
/// the capital height of the sans faces a designer most often writes with (Helvetica and
/// Arial 0.716, DejaVu Sans 0.729; Times 0.662), so the strokes stand as tall as the
/// letters the designer saw.
pub const CAP_HEIGHT_PER_EM: f64 = 0.7;
/// Drawn in place of a character the font does not have.
pub const REPLACEMENT: char = '?';

/// One glyph: its strokes and how far it moves the pen, in cap heights.
#[derive(Clone, Debug)]
struct Glyph {
    advance: f64,
    strokes: Vec<Vec<Point>>,
}

/// Roman Simplex by Latin-1 code point (the font maps no other characters).
fn glyphs() -> &'static [Option<Glyph>] {
    static TABLE: OnceLock<Vec<Option<Glyph>>> = OnceLock::new();
    TABLE.get_or_init(|| {
        // The renderer gives no advance widths; a glyph's is where the next one starts: an
        // "I" after it starts `advance` further right than an "I" alone.
        let i_alone = HersheyRenderer::render_text("I", HersheyFont::Romans)
            .first()
            .map_or(0, |p| p.x);
        (0u8..=255)
            .map(|b| {
                let ch = char::from(b);
                let own = HersheyRenderer::render_text(&ch.to_string(), HersheyFont::Romans);
                let with_i = HersheyRenderer::render_text(&format!("{ch}I"), HersheyFont::Romans);
                let advance = with_i.get(own.len()).map_or(0, |p| p.x) - i_alone;
                if advance <= 0 {
                    return None;
                }
                let mut strokes: Vec<Vec<Point>> = Vec::new();
                let mut cur: Vec<Point> = Vec::new();
                for p in own {
                    let q = Point::new(p.x as f64 / CAP_UNITS, (BASELINE - p.y as f64) / CAP_UNITS);
                    if !p.pen && cur.len() > 1 {
                        strokes.push(std::mem::take(&mut cur));
                    }
                    if !p.pen {
                        cur.clear();
                    }
                    cur.push(q);
                }
                if cur.len() > 1 {
                    strokes.push(cur);
                }
                Some(Glyph {
                    advance: advance as f64 / CAP_UNITS,
                    strokes,
                })
            })
            .collect()
    })
}

fn glyph(ch: char) -> Option<&'static Glyph> {
    glyphs().get(ch as usize).and_then(Option::as_ref)
}

/// The font has a glyph for `ch` (a space is a glyph without strokes).
pub fn has_glyph(ch: char) -> bool {
    glyph(ch).is_some()
}

/// How far `ch` moves the pen, in cap heights; a character without a glyph is measured as
/// [`REPLACEMENT`].
pub fn glyph_advance(ch: char) -> f64 {
    glyph(ch)
        .or_else(|| glyph(REPLACEMENT))
        .map_or(0.0, |g| g.advance)
}

/// Strokes of `ch` with capitals `height` tall, its cell starting at `at` on the baseline,
/// the baseline along `dir` (a unit vector) and "up" along `up`. A character without a
/// glyph is drawn as [`REPLACEMENT`].
pub fn glyph_strokes(ch: char, at: Point, height: f64, dir: Vec2, up: Vec2) -> Vec<Vec<Point>> {
    let Some(g) = glyph(ch).or_else(|| glyph(REPLACEMENT)) else {
        return Vec::new();
    };
    g.strokes
        .iter()
        .map(|s| {
            s.iter()
                .map(|p| at + dir * (p.x * height) + up * (p.y * height))
                .collect()
        })
        .collect()
}

/// Width of one line of `text` with capitals `height` tall (the sum of its advances).
pub fn text_width(text: &str, height: f64) -> f64 {
    text.chars().map(glyph_advance).sum::<f64>() * height
}

/// Characters of `text` the font has no glyph for (drawn as [`REPLACEMENT`]), each once, in
/// order; line breaks are not counted.
pub fn missing_glyphs(text: &str) -> Vec<char> {
    let mut out: Vec<char> = Vec::new();
    for c in text.chars() {
        if c != '\n' && c != '\r' && !has_glyph(c) && !out.contains(&c) {
            out.push(c);
        }
    }
    out
}

/// Strokes of `text` with its first baseline starting at `at`, capitals `height` mm tall,
/// the baseline turned `angle` radians counter-clockwise. `\n` starts a new line below;
/// characters without a glyph are drawn as [`REPLACEMENT`].
pub fn text_strokes(text: &str, at: Point, height: f64, angle: f64) -> Vec<Vec<Point>> {
    let (dir, up) = (
        Vec2::from_angle(angle),
        Vec2::from_angle(angle + std::f64::consts::FRAC_PI_2),
    );
    let mut out: Vec<Vec<Point>> = Vec::new();
    for (row, line) in text.lines().enumerate() {
        let mut pen = at - up * (row as f64 * LINE_PITCH * height);
        for ch in line.chars() {
            out.extend(glyph_strokes(ch, pen, height, dir, up));
            pen += dir * (glyph_advance(ch) * height);
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

    #[test]
    fn laid_out_glyph_by_glyph_as_the_renderer_lays_out_a_string() {
        // The renderer's own layout of a whole string (y down, cells abutting) is the
        // reference for the advances measured one glyph at a time.
        let text = "Oficina 21, jig & fixture.";
        let theirs = HersheyRenderer::render_text(text, HersheyFont::Romans);
        let ours: Vec<Point> = text_strokes(text, Point::ORIGIN, CAP_UNITS, 0.0)
            .into_iter()
            .flatten()
            .collect();
        let (min_x, max_x) = theirs.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
            (a.min(p.x as f64), b.max(p.x as f64))
        });
        let (lo, hi) = ours
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.x), b.max(p.x)));
        assert!((lo - min_x).abs() < 1e-9 && (hi - max_x).abs() < 1e-9);
        // Every point of theirs is one of ours (y flipped about the baseline).
        for p in &theirs {
            let q = Point::new(p.x as f64, BASELINE - p.y as f64);
            assert!(ours.iter().any(|o| o.distance(q) < 1e-9), "{q:?}");
        }
    }

    #[test]
    fn unknown_characters_are_drawn_as_the_replacement_and_listed() {
        assert_eq!(missing_glyphs("a→b€→\n"), vec!['→', '€']);
        let q = text_strokes("?", Point::ORIGIN, 5.0, 0.0);
        assert!(!q.is_empty());
        assert_eq!(text_strokes("→", Point::ORIGIN, 5.0, 0.0), q);
        assert_eq!(glyph_advance('→'), glyph_advance('?'));
        // A space moves the pen and draws nothing.
        assert!(has_glyph(' ') && glyph_advance(' ') > 0.2);
        assert!(glyph_strokes(
            ' ',
            Point::ORIGIN,
            5.0,
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0)
        )
        .is_empty());
        assert!((text_width("HH", 2.0) - 2.0 * text_width("H", 2.0)).abs() < 1e-12);
    }
}
