//! Lettering: text in an Ink/Stitch embroidery font, sewn as Ink/Stitch's lettering sews it.
//!
//! The bundled font is Ink/Stitch's Masego (`fonts/inkstitch_masego/`, SIL OFL 1.1, from
//! PyPI's `inkstitch-fonts` 0.1.0; see its `SOURCES.md`). A font is its `font.json`
//! (`horiz_adv_x`, `horiz_adv_x_default`, `horiz_adv_x_space`, `kerning_pairs`, `leading`, all
//! in font units = the SVG's user units, px; `size`, `min_scale`, `max_scale`,
//! `default_glyph`) and its `ltr.svg`, one glyph per layer `GlyphLayer-X`, each element a path
//! with its own `inkstitch:` parameters (satin columns with their rungs, running stitches,
//! fills, ties).
//!
//! Layout, as Ink/Stitch's lettering does it: lines split at `\n` or `|`, stripped; per line the
//! pen starts at 0; a space advances by `horiz_adv_x_space` and breaks kerning; a word's first
//! glyph has its left edge at the pen, a later one its origin at the pen less the pair's
//! kerning (pairs keyed `"A B"` or `"AB"`); the pen then goes to the glyph's origin plus its
//! `horiz_adv_x` (or the default, or the glyph's right edge). A line is centred or right
//! aligned by its drawn width. A character the font lacks is sewn as its `default_glyph`
//! (noted). Lines are `leading` apart. The baseline is the bottom of the font's `H`, the cap
//! height the height of `H`: the size asked for is the cap height in mm, held to the scales
//! the font allows (`min_scale`..`max_scale` of its glyphs at 96 px per inch, as Ink/Stitch's
//! lettering dialog holds them).
//!
//! Sewing (`sew`): the placed glyphs become an Ink/Stitch document, each glyph element
//! keeping its `inkstitch:` attributes (and `trim_after` where the trims asked for fall), read
//! back by [`crate::read_inkstitch`] and sewn by [`crate::generate_inkstitch`], the way any
//! Ink/Stitch SVG is sewn: a satin column's rungs pair its rails, its underlay, spacing and
//! ties are the font's.

mod sew;

use oficina_geom::Point;
use std::collections::HashMap;

pub use sew::{append, letter, Lettered, Trim};

/// Name of the bundled font.
pub const DEFAULT_FONT: &str = "masego";

const MASEGO_JSON: &str = include_str!("../fonts/inkstitch_masego/font.json");
const MASEGO_SVG: &str = include_str!("../fonts/inkstitch_masego/ltr.svg");

/// Names of the bundled fonts.
pub const FONTS: &[&str] = &[DEFAULT_FONT];

/// SVG user units (px) per mm: a font at scale 1 is sewn at this size (Ink/Stitch's
/// `PIXELS_PER_MM`).
pub const PX_PER_MM: f64 = 96.0 / 25.4;

/// A bad font, text or size.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct LetteringError(pub String);

/// One element of a glyph as the font draws it: a path, in font units (y down, the SVG's).
#[derive(Clone, Debug, PartialEq)]
pub struct GlyphElement {
    /// The path's id in the font.
    pub id: String,
    /// Its subpaths, flattened (a satin column: two rails and its rungs).
    pub subpaths: Vec<Vec<Point>>,
    /// Its `inkstitch:` attributes as written (name without prefix, value).
    pub params: Vec<(String, String)>,
    /// It is filled (its style's `fill` is a colour).
    pub filled: bool,
}

impl GlyphElement {
    /// `inkstitch:satin_column` is true.
    pub fn is_satin(&self) -> bool {
        self.params
            .iter()
            .any(|(k, v)| k == "satin_column" && v.eq_ignore_ascii_case("true"))
    }
}

/// A glyph: its elements and its extent.
#[derive(Clone, Debug, PartialEq)]
pub struct Glyph {
    /// Satins, running lines and fills in the font's sewing order.
    pub elements: Vec<GlyphElement>,
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
    /// Scales the font is made for (`min_scale`, `max_scale`; 1 = its px at 96 per inch).
    pub scales: (f64, f64),
    /// What a missing character is sewn as (`default_glyph`), if the font has it.
    pub default_glyph: Option<String>,
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
    /// Word number from 0, over the whole text.
    pub word: usize,
}

/// The text laid out, in font units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout {
    /// Glyphs in sewing order.
    pub glyphs: Vec<Placed>,
    /// Each line's drawn width (its glyphs' extent, by which it is aligned).
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
            let mut elements = Vec::new();
            for path in layer.descendants().filter(|n| n.has_tag_name("path")) {
                let Some(d) = path.attribute("d") else {
                    continue;
                };
                // Hidden paths are not sewn (the layer itself is hidden in the font file).
                let hidden = |n: &roxmltree::Node| {
                    n.attribute("style")
                        .is_some_and(|s| s.replace(' ', "").contains("display:none"))
                        || n.attribute("display") == Some("none")
                };
                if path
                    .ancestors()
                    .take_while(|a| *a != layer)
                    .any(|a| hidden(&a))
                {
                    continue;
                }
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
                let subpaths = subpaths(d, &m);
                if subpaths.is_empty() {
                    continue;
                }
                let style = path.attribute("style").unwrap_or("");
                let fill = style
                    .split(';')
                    .filter_map(|kv| kv.split_once(':'))
                    .find(|(k, _)| k.trim() == "fill")
                    .map(|(_, v)| v.trim().to_string())
                    .or_else(|| path.attribute("fill").map(str::to_string));
                elements.push(GlyphElement {
                    id: path.attribute("id").unwrap_or("path").to_string(),
                    subpaths,
                    params: path
                        .attributes()
                        .filter(|a| a.namespace() == Some(INKSTITCH))
                        .map(|a| (a.name().to_string(), a.value().to_string()))
                        .collect(),
                    filled: fill.is_some_and(|f| f != "none"),
                });
            }
            let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            for p in elements.iter().flat_map(|e| e.subpaths.iter().flatten()) {
                x0 = x0.min(p.x);
                x1 = x1.max(p.x);
                y0 = y0.min(p.y);
                y1 = y1.max(p.y);
            }
            if elements.is_empty() {
                (x0, x1, y0, y1) = (0.0, 0.0, 0.0, 0.0);
            }
            glyphs.insert(
                name.to_string(),
                Glyph {
                    elements,
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
        let names: Vec<String> = glyphs.keys().cloned().collect();
        let glyphs_has = |g: &str| names.iter().any(|n| n == g);
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
            scales: (
                get("min_scale").unwrap_or(1.0),
                get("max_scale").unwrap_or(1.0),
            ),
            default_glyph: meta
                .get("default_glyph")
                .and_then(|v| v.as_str())
                .filter(|g| glyphs_has(g))
                .map(str::to_string),
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

    /// Lays `text` out in font units: lines at `|` or newlines (stripped), aligned.
    pub fn layout(&self, text: &str, align: Align) -> Result<Layout, LetteringError> {
        let lines: Vec<&str> = text.split(['\n', '|']).map(str::trim).collect();
        if lines.iter().all(|l| l.is_empty()) {
            return Err(LetteringError(
                "the text is empty: give --text some letters".into(),
            ));
        }
        let mut out = Layout::default();
        let mut missing: Vec<char> = Vec::new();
        let mut word = 0;
        for (n, line) in lines.iter().enumerate() {
            let y = n as f64 * self.leading;
            let mut x = 0.0;
            let mut last: Option<String> = None;
            let first = out.glyphs.len();
            let (mut left, mut right) = (f64::INFINITY, f64::NEG_INFINITY);
            for c in line.chars() {
                let mut ch = c.to_string();
                if c == ' ' {
                    x += self.space;
                    if last.is_some() {
                        word += 1;
                    }
                    last = None;
                    continue;
                }
                if !self.glyphs.contains_key(&ch) {
                    if !missing.contains(&c) {
                        missing.push(c);
                    }
                    // Ink/Stitch sews the font's default glyph in its place.
                    match &self.default_glyph {
                        Some(d) => ch = d.clone(),
                        None => {
                            last = None;
                            continue;
                        }
                    }
                }
                let (x0, x1) = self.glyphs[&ch].x_range;
                // A word's first glyph has its left edge at the pen; the next ones their
                // origin, the pair's kerning back (Ink/Stitch's `_render_glyph`).
                let origin = match &last {
                    Some(l) => x - self.kern(l, &ch),
                    None => x - x0,
                };
                out.glyphs.push(Placed {
                    ch: ch.clone(),
                    x: origin,
                    y,
                    line: n,
                    word,
                });
                (left, right) = (left.min(origin + x0), right.max(origin + x1));
                x = origin + self.advance_of(&ch);
                last = Some(ch);
            }
            if last.is_some() {
                word += 1;
            }
            // Aligned by the line's drawn width, its left edge taken at 0 (as Ink/Stitch
            // shifts the line's group by its bounding box's width).
            let width = if right > left { right - left } else { 0.0 };
            let shift = match align {
                Align::Left => 0.0,
                Align::Center => -width / 2.0,
                Align::Right => -width,
            };
            for g in &mut out.glyphs[first..] {
                g.x += shift;
            }
            out.widths.push(width);
        }
        if !missing.is_empty() {
            let s: String = missing.iter().collect();
            out.notes.push(match &self.default_glyph {
                Some(d) => format!(
                    "font {}: no glyph for {s:?}: sewn as its default glyph {d:?}, as Ink/Stitch does",
                    self.name
                ),
                None => format!("font {}: no glyph for {s:?}: left out", self.name),
            });
        }
        if out.glyphs.is_empty() {
            return Err(LetteringError(format!(
                "font {} has none of the letters of {text:?}",
                self.name
            )));
        }
        Ok(out)
    }

    /// Cap heights (mm) the font may be sewn at: its `min_scale`..`max_scale`.
    pub fn sizes(&self) -> (f64, f64) {
        let mm = self.cap_height / PX_PER_MM;
        (self.scales.0 * mm, self.scales.1 * mm)
    }
}

/// What to letter.
#[derive(Clone, Debug, PartialEq)]
pub struct Text {
    /// The text; `|` or a newline starts a line.
    pub text: String,
    /// The bundled font's name.
    pub font: String,
    /// Cap height, mm (within the font's [`Font::sizes`]).
    pub size: f64,
    /// Alignment of the lines.
    pub align: Align,
    /// Where the first line's baseline starts (left) or is centred / ends, mm, y up.
    pub at: Point,
    /// Lettering added to a design: `at` is chosen under the design, half the cap height
    /// below its lowest point, centred on it (or at its left or right edge as aligned).
    pub under_design: bool,
    /// Thread colour.
    pub color: oficina_geom::Color,
    /// Where the thread is cut (Ink/Stitch's "Add trims").
    pub trim: Trim,
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
            color: oficina_geom::Color::BLACK,
            trim: Trim::Never,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Params;

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
            .flat_map(|g| &g.elements)
            .filter(|e| e.is_satin())
            .count();
        assert!(satins > 100, "{satins} satin columns");
        // font.json: size 14 mm at scale 1, scales 1.0..1.5.
        let (lo, hi) = f.sizes();
        assert!(
            (lo - 14.0).abs() < 0.2 && (hi - 21.0).abs() < 0.3,
            "{lo}..{hi}"
        );
    }

    #[test]
    fn advances_and_kerning_come_from_font_json_exactly() {
        let f = masego();
        let min_x = |c: &str| f.glyphs[c].x_range.0;
        let l = f.layout("Fo", Align::Left).unwrap();
        // The first glyph's left edge at 0.
        assert_eq!(l.glyphs[0].x, -min_x("F"));
        // 'o' after 'F': F's origin plus its advance, less the pair's kerning (5).
        assert_eq!(l.glyphs[1].x, -min_x("F") + f.advance_of("F") - 5.0);
        let l = f.layout("Fa o", Align::Left).unwrap();
        // A space breaks the pair: the next word's first glyph has its left edge at the pen.
        let pen = -min_x("F") + f.advance_of("F") + f.advance_of("a") + f.space;
        assert_eq!(l.glyphs[2].x, pen - min_x("o"), "a space breaks the pair");
        assert_eq!(l.widths[0], pen + f.glyphs["o"].x_range.1 - min_x("o"));
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
        // Each line's drawn extent centred on 0.
        for line in 0..2 {
            let g: Vec<&Placed> = l.glyphs.iter().filter(|g| g.line == line).collect();
            let lo = g[0].x + f.glyphs[&g[0].ch].x_range.0;
            let hi = g
                .iter()
                .map(|g| g.x + f.glyphs[&g.ch].x_range.1)
                .fold(f64::MIN, f64::max);
            assert!((lo + hi).abs() < 1e-9, "line {line}: {lo}..{hi}");
            assert!((hi - lo - l.widths[line]).abs() < 1e-9);
        }
        let r = f.layout("Ana|Maria", Align::Right).unwrap();
        let g = &r.glyphs[0];
        assert!((g.x + f.glyphs["A"].x_range.0 + r.widths[0]).abs() < 1e-9);
    }

    #[test]
    fn an_unknown_glyph_is_noted_and_empty_text_refused() {
        let f = masego();
        // Masego's default glyph is "o": "Zoë" is sewn "Zoo", with a note.
        let l = f.layout("Zoë", Align::Left).unwrap();
        assert_eq!(l.glyphs.len(), 3);
        assert_eq!(l.glyphs[2].ch, "o");
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
        let l = letter(&t).unwrap();
        assert!(l.notes.is_empty(), "{:?}", l.notes);
        assert!(l.ink.is_inkstitch);
        let g = l.sew(&p, &mut |_, _| {}).unwrap();
        assert!(g.satins > 10, "{} satins", g.satins);
        assert!(g.plan.counts().stitches > 1000);
        let b = g.plan.bounds().unwrap();
        // Height: the cap height (Masego has no pull compensation); the i's dot and the f's
        // top reach a little above the caps.
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

    #[test]
    fn bad_sizes_and_texts_get_clear_errors() {
        for size in [10.0, 25.0, f64::NAN] {
            let t = Text {
                text: "Ana".into(),
                size,
                ..Text::default()
            };
            let e = letter(&t).unwrap_err();
            assert!(e.0.contains("13.9 to 20.9"), "{e}");
        }
        let t = Text {
            text: "a".repeat(5000),
            ..Text::default()
        };
        assert!(letter(&t).unwrap_err().0.contains("at most"));
        // Characters XML cannot hold are letters the font lacks, not a broken document.
        let t = Text {
            text: "A\u{1}<&\"n".into(),
            ..Text::default()
        };
        let l = letter(&t).unwrap();
        assert!(l.ink.is_inkstitch && !l.notes.is_empty(), "{:?}", l.notes);
    }
}
