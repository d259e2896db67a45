//! Lettering: text in an Ink/Stitch embroidery font becomes a `Drawing` the generator sews.
//!
//! The bundled font is Ink/Stitch's Masego (`fonts/inkstitch_masego/`, SIL OFL 1.1, from
//! PyPI's `inkstitch-fonts` 0.1.0; see its `SOURCES.md`). A font is its `font.json`
//! (`horiz_adv_x`, `horiz_adv_x_default`, `horiz_adv_x_space`, `kerning_pairs`, `leading`, all
//! in font units = the SVG's user units) and its `ltr.svg`, one glyph per layer
//! `GlyphLayer-X`; a path with `inkstitch:satin_column="True"` is a satin column (two rails,
//! any other subpaths rungs), every other path a running stitch.
//!
//! Layout, as Ink/Stitch's lettering does it: lines split at `\n` or `|`; per line the pen
//! starts at 0; a space advances by `horiz_adv_x_space` and breaks kerning; before a glyph
//! the pair's kerning is subtracted (SVG `hkern` convention, pairs keyed `"AB"` or `"A B"`);
//! the glyph sits at the pen in its own layer coordinates; the pen then advances by the
//! glyph's `horiz_adv_x` (or the default, or the glyph's width). Lines are `leading` apart.
//! The baseline is the bottom of the font's `H`, the cap height the height of `H`: the size
//! asked for is the cap height in mm.
//!
//! Satin columns go to the current generator as Ink/Stitch's two-rail element (two open
//! subpaths, stroked ≥ `satin_min_width`): the rungs are not passed on, so the rails are paired
//! by arc length along their whole length (the rungs' finer pairing waits for the rail-satin
//! generator with rungs).

use crate::generate::Params;
use oficina_geom::{Color, Drawing, Path, Point, SourceRef, Style};
use std::collections::HashMap;

/// Name of the bundled font.
pub const DEFAULT_FONT: &str = "masego";

const MASEGO_JSON: &str = include_str!("../fonts/inkstitch_masego/font.json");
const MASEGO_SVG: &str = include_str!("../fonts/inkstitch_masego/ltr.svg");

/// Names of the bundled fonts.
pub const FONTS: &[&str] = &[DEFAULT_FONT];

/// Stroke width given to satin rails so the generator sews them as a satin (mm).
const RAIL_WIDTH: f64 = 1.0;

/// A bad font, text or size.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct LetteringError(pub String);

/// One stitched part of a glyph, in font units, y down (the SVG's).
#[derive(Clone, Debug, PartialEq)]
pub enum GlyphPart {
    /// A satin column between two rails.
    Satin([Vec<Point>; 2]),
    /// A running stitch line.
    Running(Vec<Point>),
}

/// A glyph: its parts and its horizontal extent.
#[derive(Clone, Debug, PartialEq)]
pub struct Glyph {
    /// Satins and running lines in the font's sewing order.
    pub parts: Vec<GlyphPart>,
    /// Leftmost and rightmost x, font units.
    pub x_range: (f64, f64),
    /// Topmost and bottommost y, font units (y down).
    pub y_range: (f64, f64),
}

/// An embroidery font.
#[derive(Clone, Debug)]
pub struct Font {
    /// Its name in `font.json`.
    pub name: String,
    /// Distance between lines, font units.
    pub leading: f64,
    /// Advance of a space, font units.
    pub space: f64,
    /// Advance of a glyph without its own, if the font gives one.
    pub default_advance: Option<f64>,
    /// Advances per glyph.
    pub advance: HashMap<String, f64>,
    /// Kerning per pair (`"AB"` or `"A B"`), subtracted from the pen.
    pub kerning: HashMap<String, f64>,
    /// The glyphs by their character(s).
    pub glyphs: HashMap<String, Glyph>,
    /// Baseline y, font units (the bottom of `H`).
    pub baseline: f64,
    /// Cap height, font units (the height of `H`).
    pub cap_height: f64,
}

/// Horizontal alignment of the lines.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Align {
    /// Lines start at x = 0.
    #[default]
    Left,
    /// Lines are centred on x = 0.
    Center,
    /// Lines end at x = 0.
    Right,
}

impl Align {
    /// `left`, `center`/`centre`, `right`.
    pub fn from_id(s: &str) -> Option<Align> {
        match s.to_ascii_lowercase().as_str() {
            "left" => Some(Align::Left),
            "center" | "centre" => Some(Align::Center),
            "right" => Some(Align::Right),
            _ => None,
        }
    }
}

/// A glyph placed by the layout: pen position in font units (y down, line 0's baseline at 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// The character.
    pub ch: String,
    /// Pen x where the glyph's origin goes.
    pub x: f64,
    /// The line's baseline y.
    pub y: f64,
    /// Line number from 0.
    pub line: usize,
}

/// The text laid out, in font units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    /// Glyphs in sewing order.
    pub glyphs: Vec<Placed>,
    /// Each line's advance width (before alignment).
    pub widths: Vec<f64>,
    /// What could not be set (characters the font lacks).
    pub notes: Vec<String>,
}

fn num(v: &serde_json::Value) -> Option<f64> {
    v.as_f64()
        .or_else(|| v.as_str().and_then(|s| s.trim().parse().ok()))
}

/// A map from font.json: an object, or (as some fonts store it) its Python `repr` string.
fn map(v: Option<&serde_json::Value>) -> HashMap<String, f64> {
    let mut out = HashMap::new();
    match v {
        Some(serde_json::Value::Object(o)) => {
            for (k, v) in o {
                if let Some(x) = num(v) {
                    out.insert(k.clone(), x);
                }
            }
        }
        Some(serde_json::Value::String(s)) => {
            // {'A': 47, "'": 20, ...}: quoted keys, numeric values.
            let c: Vec<char> = s.chars().collect();
            let mut i = 0;
            while i < c.len() {
                if c[i] == '\'' || c[i] == '"' {
                    let q = c[i];
                    let mut j = i + 1;
                    let mut key = String::new();
                    while j < c.len() && c[j] != q {
                        if c[j] == '\\' && j + 1 < c.len() {
                            j += 1;
                        }
                        key.push(c[j]);
                        j += 1;
                    }
                    let mut k = j + 1;
                    while k < c.len() && (c[k] == ':' || c[k] == ' ') {
                        k += 1;
                    }
                    let start = k;
                    while k < c.len() && (c[k].is_ascii_digit() || "+-.eE".contains(c[k])) {
                        k += 1;
                    }
                    let v: String = c[start..k].iter().collect();
                    if let Ok(x) = v.parse() {
                        out.insert(key, x);
                    }
                    i = k;
                } else {
                    i += 1;
                }
            }
        }
        _ => {}
    }
    out
}

type Affine = [f64; 6];

fn mul(m: &Affine, n: &Affine) -> Affine {
    [
        m[0] * n[0] + m[2] * n[1],
        m[1] * n[0] + m[3] * n[1],
        m[0] * n[2] + m[2] * n[3],
        m[1] * n[2] + m[3] * n[3],
        m[0] * n[4] + m[2] * n[5] + m[4],
        m[1] * n[4] + m[3] * n[5] + m[5],
    ]
}

fn apply(m: &Affine, x: f64, y: f64) -> Point {
    Point::new(m[0] * x + m[2] * y + m[4], m[1] * x + m[3] * y + m[5])
}

fn transform_of(node: roxmltree::Node) -> Affine {
    node.attribute("transform")
        .and_then(|t| t.parse::<svgtypes::Transform>().ok())
        .map_or([1.0, 0.0, 0.0, 1.0, 0.0, 0.0], |t| {
            [t.a, t.b, t.c, t.d, t.e, t.f]
        })
}

/// Subpaths of a path's `d`, flattened, transformed by `m`.
fn subpaths(d: &str, m: &Affine) -> Vec<Vec<Point>> {
    let mut out: Vec<Vec<Point>> = Vec::new();
    let mut cur: Vec<Point> = Vec::new();
    let (mut at, mut start) = ((0.0, 0.0), (0.0, 0.0));
    let flush = |cur: &mut Vec<Point>, out: &mut Vec<Vec<Point>>| {
        if cur.len() >= 2 {
            out.push(std::mem::take(cur));
        } else {
            cur.clear();
        }
    };
    for seg in svgtypes::SimplifyingPathParser::from(d).flatten() {
        use svgtypes::SimplePathSegment as S;
        match seg {
            S::MoveTo { x, y } => {
                flush(&mut cur, &mut out);
                cur.push(apply(m, x, y));
                at = (x, y);
                start = at;
            }
            S::LineTo { x, y } => {
                cur.push(apply(m, x, y));
                at = (x, y);
            }
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => {
                const N: usize = 16;
                for i in 1..=N {
                    let t = i as f64 / N as f64;
                    let u = 1.0 - t;
                    let (b0, b1, b2, b3) = (u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t);
                    cur.push(apply(
                        m,
                        b0 * at.0 + b1 * x1 + b2 * x2 + b3 * x,
                        b0 * at.1 + b1 * y1 + b2 * y2 + b3 * y,
                    ));
                }
                at = (x, y);
            }
            S::Quadratic { x1, y1, x, y } => {
                const N: usize = 12;
                for i in 1..=N {
                    let t = i as f64 / N as f64;
                    let u = 1.0 - t;
                    cur.push(apply(
                        m,
                        u * u * at.0 + 2.0 * u * t * x1 + t * t * x,
                        u * u * at.1 + 2.0 * u * t * y1 + t * t * y,
                    ));
                }
                at = (x, y);
            }
            S::ClosePath => {
                if let Some(&f) = cur.first() {
                    cur.push(f);
                }
                flush(&mut cur, &mut out);
                at = start;
                cur.push(apply(m, at.0, at.1));
            }
        }
    }
    flush(&mut cur, &mut out);
    out
}

fn cross(a: Point, b: Point, c: Point) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

fn seg_hit(p: Point, q: Point, r: Point, s: Point) -> bool {
    let d1 = cross(r, s, p);
    let d2 = cross(r, s, q);
    let d3 = cross(p, q, r);
    let d4 = cross(p, q, s);
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0 && (d1 != 0.0 || d2 != 0.0)
}

fn hits(a: &[Point], b: &[Point]) -> bool {
    a.windows(2)
        .any(|u| b.windows(2).any(|v| seg_hit(u[0], u[1], v[0], v[1])))
}

fn length(l: &[Point]) -> f64 {
    l.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// The two rails of a satin column: with two subpaths both; with more, the pair that does
/// not cross itself and that most other subpaths (rungs) cross both of, the longer pair on a
/// tie.
fn rails(subs: &[Vec<Point>]) -> Option<[Vec<Point>; 2]> {
    match subs.len() {
        0 | 1 => None,
        2 => Some([subs[0].clone(), subs[1].clone()]),
        n => {
            let crossings: Vec<Vec<bool>> = (0..n)
                .map(|i| (0..n).map(|j| i != j && hits(&subs[i], &subs[j])).collect())
                .collect();
            let mut best: Option<(usize, f64, usize, usize)> = None;
            for i in 0..n {
                for j in i + 1..n {
                    if crossings[i][j] {
                        continue;
                    }
                    let rungs = (0..n)
                        .filter(|&k| crossings[k][i] && crossings[k][j])
                        .count();
                    let len = length(&subs[i]) + length(&subs[j]);
                    if best.is_none_or(|b| (rungs, len) > (b.0, b.1)) {
                        best = Some((rungs, len, i, j));
                    }
                }
            }
            best.map(|(_, _, i, j)| [subs[i].clone(), subs[j].clone()])
        }
    }
}

const INKSTITCH: &str = "http://inkstitch.org/namespace";
const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";

impl Font {
    /// A bundled font by name (`masego`; also its folder or display name).
    pub fn bundled(name: &str) -> Result<Font, LetteringError> {
        let n = name.to_ascii_lowercase().replace([' ', '/', '-'], "_");
        match n.as_str() {
            "masego" | "inkstitch_masego" | "ink_stitch_masego" => {
                Font::parse(MASEGO_JSON, MASEGO_SVG)
            }
            _ => Err(LetteringError(format!(
                "no font {name:?}: the bundled fonts are {}",
                FONTS.join(", ")
            ))),
        }
    }

    /// A font from its `font.json` and glyph SVG.
    pub fn parse(json: &str, svg: &str) -> Result<Font, LetteringError> {
        let meta: serde_json::Value =
            serde_json::from_str(json).map_err(|e| LetteringError(format!("font.json: {e}")))?;
        let doc = roxmltree::Document::parse_with_options(
            svg,
            roxmltree::ParsingOptions {
                allow_dtd: true,
                ..Default::default()
            },
        )
        .map_err(|e| LetteringError(format!("font SVG: {e}")))?;
        let mut glyphs = HashMap::new();
        for layer in doc.descendants().filter(|n| n.has_tag_name("g")) {
            let Some(name) = layer
                .attribute((INKSCAPE, "label"))
                .and_then(|l| l.strip_prefix("GlyphLayer-"))
            else {
                continue;
            };
            let mut parts = Vec::new();
            for path in layer.descendants().filter(|n| n.has_tag_name("path")) {
                let Some(d) = path.attribute("d") else {
                    continue;
                };
                // Transforms from the layer down to the path.
                let mut m = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
                let chain: Vec<roxmltree::Node> = path
                    .ancestors()
                    .take_while(|a| *a != layer)
                    .chain(std::iter::once(layer))
                    .collect();
                for a in chain.iter().rev() {
                    m = mul(&m, &transform_of(*a));
                }
                let subs = subpaths(d, &m);
                let satin = path
                    .attribute((INKSTITCH, "satin_column"))
                    .is_some_and(|v| v.eq_ignore_ascii_case("true"));
                if satin {
                    if let Some(r) = rails(&subs) {
                        parts.push(GlyphPart::Satin(r));
                        continue;
                    }
                }
                parts.extend(subs.into_iter().map(GlyphPart::Running));
            }
            let pts = || {
                parts.iter().flat_map(|p| match p {
                    GlyphPart::Satin([a, b]) => a.iter().chain(b.iter()),
                    GlyphPart::Running(l) => l.iter().chain([].iter()),
                })
            };
            let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            for p in pts() {
                x0 = x0.min(p.x);
                x1 = x1.max(p.x);
                y0 = y0.min(p.y);
                y1 = y1.max(p.y);
            }
            if parts.is_empty() {
                (x0, x1, y0, y1) = (0.0, 0.0, 0.0, 0.0);
            }
            glyphs.insert(
                name.to_string(),
                Glyph {
                    parts,
                    x_range: (x0, x1),
                    y_range: (y0, y1),
                },
            );
        }
        let h = glyphs
            .get("H")
            .or_else(|| glyphs.get("I"))
            .ok_or_else(|| LetteringError("font has no H or I to measure".into()))?;
        let (baseline, cap_height) = (h.y_range.1, h.y_range.1 - h.y_range.0);
        let get = |k: &str| meta.get(k).and_then(num);
        Ok(Font {
            name: meta
                .get("name")
                .and_then(|v| v.as_str())
                .unwrap_or("font")
                .to_string(),
            leading: get("leading").unwrap_or(cap_height * 1.5),
            space: get("horiz_adv_x_space").unwrap_or(cap_height / 2.0),
            default_advance: get("horiz_adv_x_default"),
            advance: map(meta.get("horiz_adv_x")),
            kerning: map(meta.get("kerning_pairs")),
            glyphs,
            baseline,
            cap_height,
        })
    }

    /// The pen's advance after `ch`, font units.
    pub fn advance_of(&self, ch: &str) -> f64 {
        self.advance
            .get(ch)
            .copied()
            .or(self.default_advance)
            .or_else(|| self.glyphs.get(ch).map(|g| g.x_range.1.max(0.0)))
            .unwrap_or(self.space)
    }

    /// Kerning between `a` and `b`, font units (subtracted from the pen).
    pub fn kern(&self, a: &str, b: &str) -> f64 {
        self.kerning
            .get(&format!("{a} {b}"))
            .or_else(|| self.kerning.get(&format!("{a}{b}")))
            .copied()
            .unwrap_or(0.0)
    }

    /// Lays `text` out in font units: lines at `|` or newlines, aligned.
    pub fn layout(&self, text: &str, align: Align) -> Result<Layout, LetteringError> {
        let lines: Vec<&str> = text
            .split(['\n', '|'])
            .map(|l| l.trim_end_matches('\r'))
            .collect();
        if lines.iter().all(|l| l.trim().is_empty()) {
            return Err(LetteringError(
                "the text is empty: give --text some letters".into(),
            ));
        }
        let mut out = Layout::default();
        let mut missing: Vec<char> = Vec::new();
        for (n, line) in lines.iter().enumerate() {
            let y = n as f64 * self.leading;
            let mut x = 0.0;
            let mut last: Option<String> = None;
            let first = out.glyphs.len();
            for c in line.chars() {
                let ch = c.to_string();
                if c == ' ' {
                    x += self.space;
                    last = None;
                    continue;
                }
                if !self.glyphs.contains_key(&ch) {
                    if !missing.contains(&c) {
                        missing.push(c);
                    }
                    last = None;
                    continue;
                }
                if let Some(l) = &last {
                    x -= self.kern(l, &ch);
                }
                out.glyphs.push(Placed {
                    ch: ch.clone(),
                    x,
                    y,
                    line: n,
                });
                x += self.advance_of(&ch);
                last = Some(ch);
            }
            let shift = match align {
                Align::Left => 0.0,
                Align::Center => -x / 2.0,
                Align::Right => -x,
            };
            for g in &mut out.glyphs[first..] {
                g.x += shift;
            }
            out.widths.push(x);
        }
        if !missing.is_empty() {
            let s: String = missing.iter().collect();
            out.notes
                .push(format!("font {}: no glyph for {s:?}: left out", self.name));
        }
        if out.glyphs.is_empty() {
            return Err(LetteringError(format!(
                "font {} has none of the letters of {text:?}",
                self.name
            )));
        }
        Ok(out)
    }
}

/// What to letter.
#[derive(Clone, Debug, PartialEq)]
pub struct Text {
    /// The text; `|` or a newline starts a line.
    pub text: String,
    /// The bundled font's name.
    pub font: String,
    /// Cap height, mm.
    pub size: f64,
    /// Alignment of the lines.
    pub align: Align,
    /// Where the first line's baseline starts (left) or is centred / ends, mm, y up.
    pub at: Point,
    /// Lettering added to a design: `at` is chosen under the design, half the cap height
    /// below its lowest point, centred on it (or at its left or right edge as aligned).
    pub under_design: bool,
    /// Thread colour.
    pub color: Color,
}

impl Default for Text {
    fn default() -> Text {
        Text {
            text: String::new(),
            font: DEFAULT_FONT.into(),
            size: 15.0,
            align: Align::Center,
            at: Point::ZERO,
            under_design: false,
            color: Color::BLACK,
        }
    }
}

/// The text as a drawing in mm, y up, and notes on what was left out. Satin columns are
/// two-rail elements stroked wide enough for `p.satin_min_width`; the rest thin strokes.
pub fn letter(t: &Text, p: &Params) -> Result<(Drawing, Vec<String>), LetteringError> {
    if !(t.size.is_finite() && t.size > 0.5 && t.size <= 500.0) {
        return Err(LetteringError(format!(
            "text size {} mm is outside 0.5..500",
            t.size
        )));
    }
    let font = Font::bundled(&t.font)?;
    let layout = font.layout(&t.text, t.align)?;
    let s = t.size / font.cap_height;
    let mut d = Drawing::new();
    let layer = d.layer_mut("lettering");
    let mut id = 0usize;
    for g in &layout.glyphs {
        let glyph = &font.glyphs[&g.ch];
        let to_mm = |q: &Point| {
            Point::new(
                t.at.x + (g.x + q.x) * s,
                t.at.y - (g.y + q.y - font.baseline) * s,
            )
        };
        for part in &glyph.parts {
            id += 1;
            let src = SourceRef::new("lettering", format!("{}-{id}", g.ch));
            match part {
                GlyphPart::Satin(r) => {
                    for rail in r {
                        let pts: Vec<Point> = rail.iter().map(to_mm).collect();
                        let mut path = Path::polyline(&pts, false).with_source(src.clone());
                        path.style = Style {
                            stroke: Some(t.color),
                            stroke_width: RAIL_WIDTH.max(p.satin_min_width),
                            fill: None,
                        };
                        layer.paths.push(path);
                    }
                }
                GlyphPart::Running(l) => {
                    let pts: Vec<Point> = l.iter().map(to_mm).collect();
                    let mut path = Path::polyline(&pts, false).with_source(src);
                    path.style = Style {
                        stroke: Some(t.color),
                        stroke_width: 0.0,
                        fill: None,
                    };
                    layer.paths.push(path);
                }
            }
        }
    }
    Ok((d, layout.notes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::generate;

    fn masego() -> Font {
        Font::bundled("masego").unwrap()
    }

    #[test]
    fn the_bundled_font_loads_with_its_metrics() {
        let f = masego();
        assert_eq!(f.name, "Ink/Stitch Masego");
        assert!(f.glyphs.len() >= 70, "{} glyphs", f.glyphs.len());
        assert_eq!(f.leading, 100.0);
        assert_eq!(f.space, 30.0);
        assert_eq!(f.advance_of("M"), 78.0);
        assert_eq!(f.kern("F", "o"), 5.0);
        // Cap height ≈ the font's "caps" guide: 83.6 − 69.64 below the top, bottom 66.55.
        assert!((f.cap_height - 52.6).abs() < 1.5, "cap {}", f.cap_height);
        let satins = f
            .glyphs
            .values()
            .flat_map(|g| &g.parts)
            .filter(|p| matches!(p, GlyphPart::Satin(_)))
            .count();
        assert!(satins > 100, "{satins} satin columns");
    }

    #[test]
    fn advances_and_kerning_come_from_font_json_exactly() {
        let f = masego();
        let l = f.layout("Fo", Align::Left).unwrap();
        assert_eq!(l.glyphs[0].x, 0.0);
        // 'o' after 'F': F's advance minus the pair's kerning.
        assert_eq!(l.glyphs[1].x, f.advance_of("F") - 5.0);
        let l = f.layout("Fa o", Align::Left).unwrap();
        let x_o = f.advance_of("F") + f.advance_of("a") + f.space;
        assert_eq!(l.glyphs[2].x, x_o, "a space breaks the pair");
        assert_eq!(l.widths[0], x_o + f.advance_of("o"));
    }

    #[test]
    fn lines_are_leading_apart_and_centred() {
        let f = masego();
        let l = f.layout("Ana|Maria", Align::Center).unwrap();
        let l2 = f.layout("Ana\nMaria", Align::Center).unwrap();
        assert_eq!(l, l2);
        assert_eq!(l.widths.len(), 2);
        let a = &l.glyphs[0];
        let m = l.glyphs.iter().find(|g| g.ch == "M").unwrap();
        assert_eq!((a.line, m.line), (0, 1));
        assert_eq!(m.y - a.y, f.leading);
        assert!((a.x + l.widths[0] / 2.0).abs() < 1e-12);
        assert!((m.x + l.widths[1] / 2.0).abs() < 1e-12);
        let r = f.layout("Ana|Maria", Align::Right).unwrap();
        assert!((r.glyphs[0].x + r.widths[0]).abs() < 1e-12);
    }

    #[test]
    fn an_unknown_glyph_is_noted_and_empty_text_refused() {
        let f = masego();
        let l = f.layout("Zoë", Align::Left).unwrap();
        assert_eq!(l.glyphs.len(), 2);
        assert!(l.notes[0].contains('ë'), "{:?}", l.notes);
        let e = f.layout(" | ", Align::Left).unwrap_err();
        assert!(e.0.contains("empty"), "{e}");
        assert!(Font::bundled("comic").is_err());
    }

    #[test]
    fn oficina_sews_at_its_size() {
        let p = Params {
            center: false,
            ..Params::default()
        };
        let t = Text {
            text: "Oficina".into(),
            size: 15.0,
            align: Align::Left,
            ..Text::default()
        };
        let (d, notes) = letter(&t, &p).unwrap();
        assert!(notes.is_empty(), "{notes:?}");
        let g = generate(&d, "Oficina", &p, &mut |_, _| {}).unwrap();
        assert!(g.satins > 10, "{} satins", g.satins);
        assert!(g.plan.counts().stitches > 1000);
        let b = g.plan.bounds().unwrap();
        // Height: the cap height plus the satin's pull compensation (no descenders in
        // "Oficina"; the i's dot and f's top reach a little above the caps).
        let h = b[3] - b[1];
        assert!((h - 15.0).abs() < 1.5, "height {h}");
        // Baseline at y = 0: nothing sews much below it.
        assert!(b[1] > -0.5, "bottom {}", b[1]);
        let f = masego();
        let w = f.layout("Oficina", Align::Left).unwrap().widths[0] * 15.0 / f.cap_height;
        let sewn = b[2] - b[0];
        assert!(
            sewn < w + 1.0 && sewn > w * 0.85,
            "width {sewn} vs advance {w}"
        );
    }
}
