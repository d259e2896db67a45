//! SVG → `Drawing` through usvg, which resolves transforms, units, the viewBox, groups,
//! `<use>`, CSS and turns every shape (rect, circle, ellipse, line, polyline, polygon) and
//! path command into moves, lines and curves. Coordinates come out in user-space px at
//! 96 px/in; here they become mm with y up (SVG's y runs down). Text is drawn with the
//! single-stroke font (`svg_text`), or counted as unsupported when
//! [`SvgOptions::draw_text`] is off; images and foreign objects are counted as unsupported.

use crate::import::{ImportError, Imported};
use oficina_geom::kurbo::{Affine, CubicBez, Point};
use oficina_geom::{Color, Path, Segment, SourceRef, Style};
use std::collections::HashMap;
use usvg::roxmltree;

/// CSS px per inch, as usvg converts mm, cm, in, pt.
const DPI: f64 = 96.0;

/// How to read an SVG document.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgOptions {
    /// Draw `<text>` with the single-stroke font (default); off, it is counted as skipped.
    pub draw_text: bool,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions { draw_text: true }
    }
}

/// Reads an SVG document into a drawing, in mm, text drawn with the single-stroke font.
pub fn svg_from_bytes(bytes: &[u8], file: &str) -> Result<Imported, ImportError> {
    read_svg(bytes, file, &SvgOptions::default())
}

/// Reads an SVG document into a drawing, in mm.
pub fn read_svg(bytes: &[u8], file: &str, opts: &SvgOptions) -> Result<Imported, ImportError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        ImportError::new(file, format!("byte {}", e.valid_up_to()), "not UTF-8 text")
    })?;
    let mut out = Imported::default();
    // What usvg drops or cannot make into outlines, counted from the source itself; and the
    // names of Inkscape layers by group id.
    let mut layer_names: HashMap<String, String> = HashMap::new();
    let doc = roxmltree::Document::parse_with_options(
        text,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .map_err(|e| ImportError::new(file, format!("{}", e.pos()), e.to_string()))?;
    for n in doc.descendants().filter(|n| n.is_element()) {
        let tag = n.tag_name().name();
        let where_ = || {
            let pos = doc.text_pos_at(n.range().start);
            n.attribute("id").map_or_else(
                || format!("line {}", pos.row),
                |id| format!("#{id} (line {})", pos.row),
            )
        };
        match tag {
            "text" if opts.draw_text => {}
            // (flowRoot: Inkscape 0.92's flowed text, not SVG; usvg drops it.)
            "text" | "image" | "foreignObject" | "video" | "audio" | "flowRoot" => {
                out.unsupported.add(&format!("<{tag}>"), where_())
            }
            "g" => {
                let inkscape = "http://www.inkscape.org/namespaces/inkscape";
                if n.attribute((inkscape, "groupmode")) == Some("layer") {
                    if let (Some(id), Some(label)) =
                        (n.attribute("id"), n.attribute((inkscape, "label")))
                    {
                        layer_names.insert(id.to_string(), label.to_string());
                    }
                }
            }
            _ => {}
        }
    }
    let with_text = if opts.draw_text {
        crate::svg_text::texts_to_paths(text, &doc, &mut out.unsupported)
    } else {
        None
    };
    let tree = usvg::Tree::from_str(
        with_text.as_deref().unwrap_or(text),
        &usvg::Options::default(),
    )
    .map_err(|e| ImportError::new(file, "SVG", e.to_string()))?;
    let k = 25.4 / DPI;
    let h = tree.size().height() as f64;
    // px, y down → mm, y up.
    let to_mm = Affine::new([k, 0.0, 0.0, -k, 0.0, h * k]);
    out.units = "mm (the SVG's width/height and viewBox, 96 px per inch)".into();
    let mut w = Walker {
        file,
        to_mm,
        out,
        layer_names,
        count: 0,
    };
    w.group(tree.root(), "svg");
    Ok(w.out)
}

struct Walker<'a> {
    file: &'a str,
    to_mm: Affine,
    out: Imported,
    layer_names: HashMap<String, String>,
    count: usize,
}

fn color(p: &usvg::Paint) -> Option<Color> {
    match p {
        usvg::Paint::Color(c) => Some(Color::rgb(c.red, c.green, c.blue)),
        _ => None,
    }
}

impl Walker<'_> {
    fn group(&mut self, g: &usvg::Group, layer: &str) {
        let layer = self
            .layer_names
            .get(g.id())
            .cloned()
            .unwrap_or_else(|| layer.to_string());
        for child in g.children() {
            match child {
                usvg::Node::Group(sub) => self.group(sub, &layer),
                usvg::Node::Path(p) => self.path(p, &layer),
                // Counted from the source already.
                usvg::Node::Image(_) | usvg::Node::Text(_) => {}
            }
        }
    }

    fn path(&mut self, p: &usvg::Path, layer: &str) {
        if !p.is_visible() {
            return;
        }
        self.count += 1;
        let t = p.abs_transform();
        let m = self.to_mm * Affine::new([t.sx, t.ky, t.kx, t.sy, t.tx, t.ty].map(f64::from));
        let det = m.determinant().abs().sqrt();
        let style = Style {
            stroke: p.stroke().and_then(|s| color(s.paint())),
            stroke_width: p.stroke().map_or(0.0, |s| s.width().get() as f64) * det,
            fill: p.fill().and_then(|f| color(f.paint())),
        };
        let id = if p.id().is_empty() {
            format!("path {}", self.count)
        } else {
            format!("#{}", p.id())
        };
        if p.fill().map(|f| f.rule()) == Some(usvg::FillRule::EvenOdd) {
            self.out.even_odd.insert(id.clone());
        }
        let pt = |q: usvg::tiny_skia_path::Point| Point::new(q.x as f64, q.y as f64);
        let mut segs: Vec<Segment> = Vec::new();
        let mut start = Point::ORIGIN;
        let mut cur = Point::ORIGIN;
        let flush = |segs: &mut Vec<Segment>, closed: bool, w: &mut Self| {
            if !segs.is_empty() {
                let mut path = Path::new(std::mem::take(segs), closed);
                path.close_gap();
                let path = path
                    .transform(m)
                    .with_style(style)
                    .with_source(SourceRef::new(w.file, id.clone()));
                w.out.drawing.push(layer, path);
            }
        };
        for s in p.data().segments() {
            use usvg::tiny_skia_path::PathSegment as S;
            match s {
                S::MoveTo(a) => {
                    flush(&mut segs, false, self);
                    start = pt(a);
                    cur = start;
                }
                S::LineTo(a) => {
                    if cur != pt(a) {
                        segs.push(Segment::line(cur, pt(a)));
                    }
                    cur = pt(a);
                }
                S::QuadTo(c, a) => {
                    // Degree elevation: the same curve as a cubic.
                    let (c, a) = (pt(c), pt(a));
                    segs.push(Segment::Cubic(CubicBez::new(
                        cur,
                        cur.lerp(c, 2.0 / 3.0),
                        a.lerp(c, 2.0 / 3.0),
                        a,
                    )));
                    cur = a;
                }
                S::CubicTo(c1, c2, a) => {
                    segs.push(Segment::Cubic(CubicBez::new(cur, pt(c1), pt(c2), pt(a))));
                    cur = pt(a);
                }
                S::Close => {
                    flush(&mut segs, true, self);
                    cur = start;
                }
            }
        }
        flush(&mut segs, false, self);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_viewbox_transforms_use_and_y_up() {
        // 100 mm × 50 mm page, viewBox in mm; a rect translated by a group, reused by <use>.
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
            width="100mm" height="50mm" viewBox="0 0 100 50">
          <g transform="translate(10,5)"><rect id="r" x="0" y="0" width="20" height="10" stroke="red" fill="none"/></g>
          <use xlink:href="#r" x="50" y="0"/>
          <circle id="c" cx="80" cy="40" r="5"/>
          <text x="1" y="1">hi</text>
        </svg>"##;
        // (Text left out here: svg_text's tests draw it.)
        let off = SvgOptions { draw_text: false };
        let imp = read_svg(svg.as_bytes(), "t.svg", &off).unwrap();
        let paths: Vec<&Path> = imp.drawing.paths().collect();
        assert_eq!(paths.len(), 3, "{paths:?}");
        let r = paths[0].bounding_box().unwrap();
        // SVG y 5..15 on a 50 mm page → y up 35..45.
        assert!(
            (r.x0 - 10.0).abs() < 1e-3 && (r.x1 - 30.0).abs() < 1e-3,
            "{r:?}"
        );
        assert!(
            (r.y0 - 35.0).abs() < 1e-3 && (r.y1 - 45.0).abs() < 1e-3,
            "{r:?}"
        );
        assert!(paths[0].closed);
        assert_eq!(paths[0].style.stroke, Some(Color::rgb(255, 0, 0)));
        let u = paths[1].bounding_box().unwrap();
        assert!((u.x0 - 50.0).abs() < 1e-3 && (u.y0 - 45.0).abs() < 1e-3 + 10.0);
        let c = paths[2];
        assert!(
            (c.area().abs() - std::f64::consts::PI * 25.0).abs() < 0.05,
            "{}",
            c.area()
        );
        assert_eq!(c.source.element, "#c");
        assert_eq!(imp.unsupported.total(), 1);
        assert!(imp.unsupported.to_string().contains("<text>"));
    }

    #[test]
    fn broken_svg_names_the_place() {
        let e = svg_from_bytes(
            b"<svg xmlns='http://www.w3.org/2000/svg'><rect></svg>",
            "b.svg",
        )
        .unwrap_err();
        assert!(e.to_string().starts_with("b.svg: 1:"), "{e}");
        assert!(svg_from_bytes(b"", "e.svg").is_err());
        assert!(svg_from_bytes(&[0xff, 0xfe], "x.svg").is_err());
    }
}
