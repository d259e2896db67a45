//! A design as SVG: one Inkscape layer per design layer (the SVG importer names layers by
//! their labels), one `<path>` per entity path stroked in its layer's colour, in mm.

use super::model::Design;
use super::to_drawing::entity_paths;
use oficina_geom::{Path, Segment};
use std::fmt::Write;

/// The SVG text. Its canvas runs from 0 to the drawing's right and top edges (at least
/// 1 mm); the importer takes y up from the canvas height, so y is written as `H − y` and
/// reads back as y (what lies left of or below 0 is kept, outside the canvas).
pub fn design_to_svg(design: &Design) -> String {
    let drawing = design.to_drawing("");
    let bb = drawing.bounding_box();
    let w = bb.map_or(1.0, |b| b.x1.max(1.0));
    let h = bb.map_or(1.0, |b| b.y1.max(1.0));
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="{w}mm" height="{h}mm" viewBox="0 0 {w} {h}">"#
    );
    for (li, layer) in design.layers.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"<g id="layer{li}" inkscape:groupmode="layer" inkscape:label="{}" fill="none" stroke="{}" stroke-width="0.1">"#,
            xml_escape(&layer.name),
            layer.color
        );
        for e in design.entities.iter().filter(|e| e.layer == layer.name) {
            for (k, p) in entity_paths(&e.shape).iter().enumerate() {
                if p.is_empty() {
                    continue;
                }
                let id = if k == 0 {
                    format!("e{}", e.id)
                } else {
                    format!("e{}-{k}", e.id)
                };
                let _ = writeln!(s, r#"<path id="{id}" d="{}"/>"#, path_data(p, h));
            }
        }
        s.push_str("</g>\n");
    }
    s.push_str("</svg>\n");
    s
}

/// SVG path data with y flipped about the canvas height `h`. Flipping y turns a
/// counter-clockwise arc clockwise on the page: SVG's sweep flag 1 is the page's positive
/// angle direction, so a design arc with sweep > 0 is written with flag 0. A whole circle
/// (one arc of 360°) is written as two halves: an SVG arc cannot end where it starts.
fn path_data(p: &Path, h: f64) -> String {
    let xy = |q: oficina_geom::Point| format!("{} {}", q.x, h - q.y);
    let mut d = String::new();
    if let Some(a) = p.start() {
        let _ = write!(d, "M{}", xy(a));
    }
    for seg in &p.segments {
        match seg {
            Segment::Line(l) => {
                let _ = write!(d, " L{}", xy(l.p1));
            }
            Segment::Arc(a) => {
                let halves = if a.sweep.abs() > std::f64::consts::PI {
                    2
                } else {
                    1
                };
                let part = a.sweep / halves as f64;
                for k in 1..=halves {
                    let end = oficina_geom::Arc::new(
                        a.center,
                        a.radius,
                        a.start_angle + part * (k - 1) as f64,
                        part,
                    )
                    .end();
                    let flag = if part > 0.0 { 0 } else { 1 };
                    let _ = write!(d, " A{r} {r} 0 0 {flag} {}", xy(end), r = a.radius);
                }
            }
            Segment::Cubic(c) => {
                let _ = write!(d, " C{} {} {}", xy(c.p1), xy(c.p2), xy(c.p3));
            }
        }
    }
    if p.closed {
        d.push_str(" Z");
    }
    d
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
