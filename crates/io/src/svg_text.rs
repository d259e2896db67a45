//! SVG `<text>` drawn with the single-stroke Hershey font (`oficina_geom::text`).
//!
//! usvg (built without its text feature, so without fonts or shaping) drops `<text>`. Before
//! usvg reads the document, each `<text>` element of the source is replaced by a `<path>` of
//! its strokes in the text's own user space, carrying the text's attributes (id, class,
//! transform, style, visibility…) but not filled and stroked in the text's fill colour; usvg
//! then places it as any path (transforms, `<use>`, viewBox, units).
//!
//! Why single-stroke and not the glyph outlines: what comes out of Oficina is cut, engraved,
//! plotted or stitched, and there text is wanted as one pass of the pen or the cutter per
//! stroke (engraving, pen plotting); outlines of a filled font would be cut around, twice
//! per stroke, and need a font file per face. The cost is that the letters are Roman Simplex,
//! not the designer's face: sized so that capitals stand as tall as a common sans face's
//! ([`text::CAP_HEIGHT_PER_EM`] of the font-size). A designer who wants the exact outlines
//! converts text to paths in the drawing program (Inkscape: Path → Object to Path).
//!
//! Laid out as SVG lays out text: x, y, dx, dy and rotate lists on `<text>` and `<tspan>`
//! (the innermost element that gives a value for a character wins), a new chunk at each
//! absolute x or y, `text-anchor` start / middle / end per chunk, `font-size` inherited with
//! its units (px, pt, pc, mm, cm, in, em, ex, %, keywords), white space collapsed unless
//! `xml:space="preserve"`. Read from attributes and `style`, not from `<style>` sheets.
//! Not followed: `<textPath>` (drawn on a straight baseline, noted), `textLength`,
//! letter-spacing, vertical writing.

use crate::import::Unsupported;
use oficina_geom::text;
use oficina_geom::{Point, Vec2};
use std::collections::HashMap;
use std::fmt::Write as _;
use usvg::roxmltree::{Document, Node, NodeId};

/// CSS's `medium` font size, px.
const MEDIUM: f64 = 16.0;
/// Largest font-size drawn, in px or user units (a 100 m letter is a mistake, and the
/// strokes must stay within usvg's f32).
pub(crate) const MAX_FONT_SIZE: f64 = 1.0e6;
/// Most characters drawn for one document (each becomes some 300 bytes of path data).
const MAX_CHARS: usize = 100_000;

/// `source` with every `<text>` replaced by the `<path>` of its strokes, and what could not
/// be drawn noted in `notes`. `None` when the document has no `<text>`.
pub(crate) fn texts_to_paths(
    source: &str,
    doc: &Document,
    notes: &mut Unsupported,
) -> Option<String> {
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    let mut budget = MAX_CHARS;
    for n in doc.descendants().filter(|n| is_svg(n, "text")) {
        let place = where_(doc, &n);
        let mut t = TextLayout {
            notes,
            place: &place,
            chars: Vec::new(),
        };
        let path = t.draw(&n, &mut budget);
        // As many lines as the text took, so that later lines keep their numbers.
        let lines = source.get(n.range()).map_or(0, |s| s.matches('\n').count());
        edits.push((n.range(), element(&n, path.as_deref(), lines)));
    }
    if edits.is_empty() {
        return None;
    }
    let mut out = String::with_capacity(source.len());
    let mut at = 0;
    for (r, s) in edits {
        if r.start < at || r.end > source.len() {
            // (Entities of a DTD can put a node's range outside the text; left as it is.)
            continue;
        }
        out.push_str(&source[at..r.start]);
        out.push_str(&s);
        at = r.end;
    }
    out.push_str(&source[at..]);
    Some(out)
}

fn is_svg(n: &Node, tag: &str) -> bool {
    n.is_element()
        && n.tag_name().name() == tag
        && n.tag_name().namespace() == Some("http://www.w3.org/2000/svg")
}

/// The element's id and line, for notes.
pub(crate) fn where_(doc: &Document, n: &Node) -> String {
    let pos = doc.text_pos_at(n.range().start);
    n.attribute("id").map_or_else(
        || format!("line {}", pos.row),
        |id| format!("#{id} (line {})", pos.row),
    )
}

/// A property from the `style` attribute, else the presentation attribute.
fn property<'a>(n: &Node<'a, '_>, name: &str) -> Option<&'a str> {
    if let Some(style) = n.attribute("style") {
        for decl in style.split(';') {
            if let Some((k, v)) = decl.split_once(':') {
                if k.trim() == name {
                    return Some(v.trim().trim_end_matches("!important").trim());
                }
            }
        }
    }
    n.attribute(name).map(str::trim)
}

/// An inherited property: the element's or its nearest ancestor's.
fn inherited<'a>(n: &Node<'a, '_>, name: &str) -> Option<&'a str> {
    n.ancestors()
        .filter(|a| a.is_element())
        .find_map(|a| property(&a, name).filter(|v| *v != "inherit"))
}

/// A CSS length in px (user units) with `em` and `%` relative to `font`.
fn length(s: &str, font: f64) -> Option<f64> {
    let s = s.trim();
    let split = s
        .find(|c: char| c.is_ascii_alphabetic() || c == '%')
        .unwrap_or(s.len());
    let v: f64 = s[..split].trim().parse().ok()?;
    let k = match s[split..].trim() {
        "" | "px" => 1.0,
        "pt" => 4.0 / 3.0,
        "pc" => 16.0,
        "mm" => 96.0 / 25.4,
        "cm" => 96.0 / 2.54,
        "in" => 96.0,
        "em" => font,
        "ex" => font / 2.0,
        "%" => font / 100.0,
        _ => return None,
    };
    Some(v * k).filter(|v| v.is_finite())
}

/// The font size of `n` in user units, from the root down.
fn font_size(n: &Node) -> f64 {
    let mut chain: Vec<Node> = n.ancestors().filter(|a| a.is_element()).collect();
    chain.reverse();
    let mut size = MEDIUM;
    for a in chain {
        // font-size, else the size in the `font` shorthand ("bold 12px/1.2 sans-serif").
        let shorthand = || {
            property(&a, "font")?
                .split_whitespace()
                .map(|w| w.split('/').next().unwrap_or(""))
                .find(|w| w.starts_with(|c: char| c.is_ascii_digit() || c == '.'))
        };
        let Some(v) = property(&a, "font-size").or_else(shorthand) else {
            continue;
        };
        size = match v {
            "xx-small" => 9.0,
            "x-small" => 10.0,
            "small" => 13.0,
            "medium" => MEDIUM,
            "large" => 18.0,
            "x-large" => 24.0,
            "xx-large" => 32.0,
            "larger" => size * 1.2,
            "smaller" => size / 1.2,
            "inherit" => size,
            v => length(v, size).unwrap_or(size),
        };
    }
    size
}

/// A list of lengths (`x="10 20,30"`).
fn lengths(n: &Node, name: &str, font: f64) -> Vec<f64> {
    n.attribute(name).map_or_else(Vec::new, |s| {
        s.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|v| !v.is_empty())
            .map(|v| length(v, font).unwrap_or(0.0))
            .collect()
    })
}

/// An element's positioning lists (x, y, dx, dy), rotations and font size, user units.
struct Pos {
    lists: [Vec<f64>; 4],
    rotate: Vec<f64>,
    size: f64,
}

/// One character to draw, with the positioning of the elements it is in.
struct Char<'a, 'i> {
    ch: char,
    /// Innermost first: the `<tspan>`s it is in, then the `<text>`, with the index of the
    /// character within each.
    chain: Vec<(Node<'a, 'i>, usize)>,
}

struct TextLayout<'n, 'a, 'i> {
    notes: &'n mut Unsupported,
    place: &'n str,
    chars: Vec<Char<'a, 'i>>,
}

impl<'a, 'i> TextLayout<'_, 'a, 'i> {
    /// Collects the characters of `n` (and its tspans) with white space handled.
    fn collect(&mut self, n: Node<'a, 'i>, chain: &mut Vec<(Node<'a, 'i>, usize)>) {
        chain.insert(0, (n, 0));
        for c in n.children() {
            if c.is_text() {
                for ch in c.text().unwrap_or("").chars() {
                    self.chars.push(Char {
                        ch,
                        // (Indices within each element are counted after collapsing.)
                        chain: chain.iter().map(|(e, _)| (*e, 0)).collect(),
                    });
                }
            } else if is_svg(&c, "tspan") || is_svg(&c, "a") || is_svg(&c, "textPath") {
                if is_svg(&c, "textPath") {
                    self.notes.add(
                        "<textPath> (drawn on a straight baseline)",
                        self.place.to_string(),
                    );
                }
                self.collect(c, chain);
            }
            // <title>, <desc> and others hold no drawn text.
        }
        chain.remove(0);
    }

    /// White space as SVG 1.1 handles it: by default newlines removed, tabs made spaces,
    /// leading, trailing and repeated spaces dropped; with `xml:space="preserve"` newlines
    /// and tabs are spaces and all are kept.
    fn collapse(&mut self, preserve: bool) {
        let chars = std::mem::take(&mut self.chars);
        for mut c in chars {
            match c.ch {
                '\n' | '\r' if !preserve => continue,
                '\n' | '\r' | '\t' => c.ch = ' ',
                _ => {}
            }
            if !preserve && c.ch == ' ' && self.chars.last().is_none_or(|p| p.ch == ' ') {
                continue;
            }
            self.chars.push(c);
        }
        if !preserve {
            while self.chars.last().is_some_and(|c| c.ch == ' ') {
                self.chars.pop();
            }
        }
        // Index of each character within each element, counted after collapsing.
        let mut firsts: HashMap<NodeId, usize> = HashMap::new();
        for (i, c) in self.chars.iter_mut().enumerate() {
            for (e, k) in c.chain.iter_mut() {
                *k = i - *firsts.entry(e.id()).or_insert(i);
            }
        }
    }

    /// The path data of `n`'s strokes in its user space, or `None` when nothing is drawn.
    fn draw(&mut self, n: &Node<'a, 'i>, budget: &mut usize) -> Option<String> {
        self.collect(*n, &mut Vec::new());
        let preserve =
            n.attribute(("http://www.w3.org/XML/1998/namespace", "space")) == Some("preserve");
        self.collapse(preserve);
        if self.chars.is_empty() {
            return None;
        }
        if self.chars.len() > *budget {
            self.notes.add(
                "<text> (over 100,000 characters in the document: not drawn)",
                self.place.to_string(),
            );
            return None;
        }
        *budget -= self.chars.len();
        let missing: String = self
            .chars
            .iter()
            .map(|c| c.ch)
            .filter(|&c| !text::has_glyph(c))
            .fold(String::new(), |mut s, c| {
                if !s.contains(c) {
                    s.push(c);
                }
                s
            });
        if !missing.is_empty() {
            self.notes.add(
                "<text> (characters without a glyph, drawn as '?')",
                format!("{} {missing:?}", self.place),
            );
        }
        // Each element's lists and font size, read once.
        let mut pos: HashMap<NodeId, Pos> = HashMap::new();
        for e in n.descendants().filter(Node::is_element) {
            let size = font_size(&e);
            pos.insert(
                e.id(),
                Pos {
                    lists: ["x", "y", "dx", "dy"].map(|name| lengths(&e, name, size)),
                    rotate: lengths(&e, "rotate", 1.0),
                    size,
                },
            );
        }
        let at = |e: &Node| &pos[&e.id()];
        // Pen positions: per character, from the innermost element giving a value.
        let pick = |c: &Char, list: usize| -> Option<f64> {
            c.chain
                .iter()
                .find_map(|(e, k)| at(e).lists[list].get(*k).copied())
        };
        let mut d = String::new();
        let (mut pen_x, mut pen_y) = (0.0f64, 0.0f64);
        // Characters of the current chunk: (index, x, y, size, rotation) before anchoring.
        let mut chunk: Vec<(usize, f64, f64, f64, f64)> = Vec::new();
        let mut anchor = "start";
        let mut rotation = 0.0;
        let mut too_large = false;
        for (i, c) in self.chars.iter().enumerate() {
            let x = pick(c, 0);
            let y = pick(c, 1);
            if (x.is_some() || y.is_some()) && !chunk.is_empty() {
                self.flush(&mut d, &chunk, anchor, pen_x);
                chunk.clear();
            }
            if chunk.is_empty() {
                anchor = inherited(&c.chain[0].0, "text-anchor").unwrap_or("start");
            }
            pen_x = x.unwrap_or(pen_x) + pick(c, 2).unwrap_or(0.0);
            pen_y = y.unwrap_or(pen_y) + pick(c, 3).unwrap_or(0.0);
            // rotate: the innermost element with a list; its last value goes on.
            if let Some((e, k)) = c.chain.iter().find(|(e, _)| !at(e).rotate.is_empty()) {
                let r = &at(e).rotate;
                if let Some(v) = r.get(*k).or(r.last()) {
                    rotation = *v;
                }
            }
            let size = at(&c.chain[0].0).size;
            if !(size.is_finite() && size > 0.0 && size <= MAX_FONT_SIZE) {
                too_large = true;
                continue;
            }
            chunk.push((i, pen_x, pen_y, size, rotation));
            pen_x += text::glyph_advance(c.ch) * size * text::CAP_HEIGHT_PER_EM;
        }
        self.flush(&mut d, &chunk, anchor, pen_x);
        if too_large {
            self.notes.add(
                &format!("<text> (font-size not above 0 and at most {MAX_FONT_SIZE}: not drawn)"),
                self.place.to_string(),
            );
        }
        (!d.is_empty()).then_some(d)
    }

    /// Draws one chunk, moved by its anchor (`end` is where the pen stopped).
    fn flush(&self, d: &mut String, chunk: &[(usize, f64, f64, f64, f64)], anchor: &str, end: f64) {
        let Some(&(_, start, ..)) = chunk.first() else {
            return;
        };
        let shift = match anchor {
            "middle" => -(end - start) / 2.0,
            "end" => -(end - start),
            _ => 0.0,
        };
        for &(i, x, y, size, rot) in chunk {
            // SVG's y runs down: "up" is −y, and a positive rotate turns clockwise on screen.
            let a = rot.to_radians();
            let dir = Vec2::new(a.cos(), a.sin());
            let up = Vec2::new(a.sin(), -a.cos());
            let cap = size * text::CAP_HEIGHT_PER_EM;
            for s in text::glyph_strokes(self.chars[i].ch, Point::new(x + shift, y), cap, dir, up) {
                for (k, p) in s.iter().enumerate() {
                    let _ = write!(d, "{}{} {} ", if k == 0 { 'M' } else { 'L' }, p.x, p.y);
                }
            }
        }
    }
}

/// XML attribute value escaping.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The element standing in for `n`: a `<path>` with `d`, or an empty group with its id.
fn element(n: &Node, d: Option<&str>, lines: usize) -> String {
    // The pen's colour is the text's fill (its stroke when it is not filled).
    let paint = |name: &str| inherited(n, name).filter(|v| *v != "none" && !v.starts_with("url("));
    let colour = paint("fill").or_else(|| paint("stroke")).unwrap_or("black");
    let mut out = String::from(if d.is_some() { "<path" } else { "<g" });
    out.push_str(&"\n".repeat(lines));
    let skip = [
        "x",
        "y",
        "dx",
        "dy",
        "rotate",
        "textLength",
        "lengthAdjust",
        "d",
        "fill",
        "stroke",
        "style",
    ];
    for a in n.attributes() {
        if a.namespace().is_some() || skip.contains(&a.name()) {
            continue;
        }
        let _ = write!(out, " {}=\"{}\"", a.name(), escape(a.value()));
    }
    // The style without its paint, then the strokes' paint (inline style wins over classes).
    let mut style: String = n
        .attribute("style")
        .unwrap_or("")
        .split(';')
        .filter(|decl| {
            let k = decl.split_once(':').map_or("", |(k, _)| k.trim());
            !k.is_empty() && k != "fill" && k != "stroke"
        })
        .map(|decl| format!("{};", decl.trim()))
        .collect();
    if d.is_some() {
        let _ = write!(style, "fill:none;stroke:{colour}");
    }
    let _ = write!(out, " style=\"{}\"", escape(&style));
    match d {
        Some(d) => {
            let _ = write!(out, " d=\"{}\"/>", d.trim_end());
        }
        None => out.push_str("/>"),
    }
    out
}
