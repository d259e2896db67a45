//! The laid-out text as an Ink/Stitch document, sewn the way any Ink/Stitch SVG is sewn.
//!
//! Ink/Stitch's lettering copies each glyph's layer into the document at the pen, scaled,
//! keeping every element's `inkstitch:` attributes, and adds `trim_after` to the last element
//! of a letter, word or line as the "Add trims" option asks (an element without its own
//! minimum jump then takes the document's: Ink/Stitch's default, 3 mm). The same happens
//! here: the document's attributes are read by [`read_inkstitch`] and its paths (the same
//! points, in mm, y up) sewn by [`generate_inkstitch`], so a glyph's satin column is paired by
//! its own rungs, with its own underlay, spacing and lock stitches, exactly as a satin column
//! of an Ink/Stitch design.

use super::{Font, LetteringError, Text, INKSCAPE, INKSTITCH, PX_PER_MM};
use crate::inkstitch::{read_inkstitch, Inkstitch};
use crate::plan::{Kind, Stitch, StitchPlan};
use crate::{generate_inkstitch, Generated, Params};
use oficina_geom::{Drawing, Path, Point, SourceRef, Style};
use std::fmt::Write;

/// Where the thread is cut between glyphs (Ink/Stitch's "Add trims": never, after each
/// line, word or letter).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Trim {
    /// No trims added (the font's own jumps and ties only).
    #[default]
    Never,
    /// After the last letter of each line but the last.
    Line,
    /// After the last letter of each word but the last.
    Word,
    /// After every letter.
    Letter,
}

impl Trim {
    /// `never`, `line`, `word`, `letter`.
    pub fn from_id(s: &str) -> Option<Trim> {
        match s.to_ascii_lowercase().as_str() {
            "never" | "none" | "" => Some(Trim::Never),
            "line" => Some(Trim::Line),
            "word" => Some(Trim::Word),
            "letter" => Some(Trim::Letter),
            _ => None,
        }
    }
}

/// Lettering ready to sew.
#[derive(Clone, Debug)]
pub struct Lettered {
    /// The glyphs' paths in mm, y up; an element's subpaths (a satin's rails and rungs) share
    /// its source element `#id`.
    pub drawing: Drawing,
    /// The elements' Ink/Stitch parameters, read from `svg`.
    pub ink: Inkstitch,
    /// The Ink/Stitch document of the lettering (mm, y down), as Ink/Stitch would hold it.
    pub svg: String,
    /// What was sewn otherwise than asked (characters the font lacks).
    pub notes: Vec<String>,
}

/// Ink/Stitch's document-wide minimum jump (`collapse_len_mm`, 3 mm unless the document
/// says otherwise): a shorter move to an element without its own is sewn, not jumped.
const MIN_JUMP: f64 = 3.0;

/// The longest text lettered: thousands of glyphs would only come from a pasted file.
pub(super) const MAX_CHARS: usize = 2000;

/// `s` as XML attribute text (control characters, which XML cannot hold, left out).
fn esc(s: &str) -> String {
    let s: String = s.chars().filter(|c| !c.is_control()).collect();
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `t` laid out in its font and placed in mm, as an Ink/Stitch document and a drawing.
pub fn letter(t: &Text) -> Result<Lettered, LetteringError> {
    let n = t.text.chars().count();
    if n > MAX_CHARS {
        return Err(LetteringError(format!(
            "--text of {n} characters: at most {MAX_CHARS} are lettered (a name, a line or two)"
        )));
    }
    let font = Font::bundled(&t.font)?;
    let (lo, hi) = font.sizes();
    // Half a percent of slack: the font's own 14 mm is 13.92 mm of its H.
    if !(t.size.is_finite() && t.size >= lo * 0.995 && t.size <= hi * 1.005) {
        return Err(LetteringError(format!(
            "--text-size {}: {} is made to be sewn with capitals {lo:.1} to {hi:.1} mm high \
             (its font.json scales {}..{}, as Ink/Stitch's lettering allows)",
            t.size, font.name, font.scales.0, font.scales.1
        )));
    }
    let layout = font.layout(&t.text, t.align)?;
    let s = t.size / font.cap_height;
    let hex = format!("#{:02x}{:02x}{:02x}", t.color.r, t.color.g, t.color.b);
    let mut d = Drawing::new();
    let layer = d.layer_mut("lettering");
    let mut body = String::new();
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for (gi, g) in layout.glyphs.iter().enumerate() {
        let glyph = &font.glyphs[&g.ch];
        let to_mm = |q: &Point| {
            Point::new(
                t.at.x + (g.x + q.x) * s,
                t.at.y - (g.y + q.y - font.baseline) * s,
            )
        };
        let next = layout.glyphs.get(gi + 1);
        let trim = match t.trim {
            Trim::Never => false,
            Trim::Letter => true,
            Trim::Word => next.is_some_and(|n| n.word != g.word),
            Trim::Line => next.is_some_and(|n| n.line != g.line),
        };
        let _ = write!(
            body,
            "<g id=\"glyph-{gi}\" inkscape:label=\"{}\">",
            esc(&g.ch)
        );
        let last = glyph.elements.len().saturating_sub(1);
        for (k, el) in glyph.elements.iter().enumerate() {
            let id = format!("g{gi}-{}", el.id);
            let src = SourceRef::new("lettering", format!("#{id}"));
            let style = Style {
                stroke: Some(t.color),
                stroke_width: 1.0 / PX_PER_MM,
                fill: el.filled.then_some(t.color),
            };
            let mut dattr = String::new();
            for sub in &el.subpaths {
                let mut pts: Vec<Point> = sub.iter().map(to_mm).collect();
                for (n, q) in pts.iter().enumerate() {
                    let _ = write!(
                        dattr,
                        "{}{:.4},{:.4} ",
                        if n == 0 { "M" } else { "L" },
                        q.x,
                        -q.y
                    );
                    (x0, x1, y0, y1) = (x0.min(q.x), x1.max(q.x), y0.min(q.y), y1.max(q.y));
                }
                // A filled element's rings are closed shapes.
                let closed =
                    el.filled && pts.len() > 3 && pts[0].distance(pts[pts.len() - 1]) < 1e-6;
                if closed {
                    pts.pop();
                    dattr.push_str("Z ");
                }
                let mut path = Path::polyline(&pts, closed).with_source(src.clone());
                path.style = style;
                layer.paths.push(path);
            }
            let mut attrs = String::new();
            let mut min_jump = false;
            for (name, value) in &el.params {
                if (k == last && trim && name == "trim_after") || value.trim().is_empty() {
                    continue;
                }
                min_jump |= name == "min_jump_stitch_length_mm";
                let _ = write!(attrs, " inkstitch:{name}=\"{}\"", esc(value));
            }
            if !min_jump {
                // What Ink/Stitch uses for an element without its own: the document's.
                let _ = write!(attrs, " inkstitch:min_jump_stitch_length_mm=\"{MIN_JUMP}\"");
            }
            if k == last && trim {
                attrs.push_str(" inkstitch:trim_after=\"true\"");
            }
            let fill = if el.filled { hex.as_str() } else { "none" };
            let _ = write!(
                body,
                "<path id=\"{id}\" style=\"fill:{fill};stroke:{hex};stroke-width:{:.4}\" d=\"{}\"{attrs}/>",
                1.0 / PX_PER_MM,
                dattr.trim_end()
            );
        }
        body.push_str("</g>");
    }
    let (w, h) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
    let svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:inkstitch=\"{INKSTITCH}\" \
         xmlns:inkscape=\"{INKSCAPE}\" width=\"{w:.3}mm\" height=\"{h:.3}mm\" \
         viewBox=\"{x0:.3} {:.3} {w:.3} {h:.3}\"><g inkscape:label=\"{}\">{body}</g></svg>\n",
        -y1,
        esc(&t.text)
    );
    let ink = read_inkstitch(&svg, "lettering").map_err(|e| LetteringError(e.0))?;
    Ok(Lettered {
        drawing: d,
        ink,
        svg,
        notes: layout.notes,
    })
}

impl Lettered {
    /// The stitches, each element with its own parameters in the font's order.
    pub fn sew(
        &self,
        p: &Params,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Generated, LetteringError> {
        generate_inkstitch(&self.drawing, "lettering", p, &self.ink, progress)
            .map_err(|e| LetteringError(e.0))
    }
}

/// `other` sewn after `plan`: a colour change where the threads differ, else the thread is
/// cut (a trim where `plan` ends) and `other`'s first block goes on in the same colour.
pub fn append(plan: &mut StitchPlan, other: StitchPlan) {
    let mut blocks = other.blocks.into_iter();
    if let (Some(last), Some(first)) = (plan.blocks.last_mut(), blocks.next()) {
        if last.thread.rgb == first.thread.rgb {
            if let Some(end) = last.stitches.last().copied() {
                last.stitches.push(Stitch::new(end.x, end.y, Kind::Trim));
            }
            last.stitches.extend(first.stitches);
        } else {
            plan.blocks.push(first);
        }
    }
    plan.blocks.extend(blocks);
}
