//! SVG preview: pen-down strokes in each pen's colour, pen-up moves dashed.

use oficina_geom::Point;
use std::fmt::Write;

use crate::strokes::Plot;

/// An SVG of the plot in mm, Y up (flipped for SVG), with the pen-up travel from `home`
/// through every stroke and back drawn as thin dashed red lines.
pub fn svg(plot: &Plot, home: Point) -> String {
    let b = plot.bounds().unwrap_or([0.0, 0.0, 1.0, 1.0]);
    let b = [
        b[0].min(home.x),
        b[1].min(home.y),
        b[2].max(home.x),
        b[3].max(home.y),
    ];
    let m = 5.0;
    let (w, h) = (b[2] - b[0] + 2.0 * m, b[3] - b[1] + 2.0 * m);
    let tx = |p: Point| (p.x - b[0] + m, b[3] - p.y + m);
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.2}mm" height="{h:.2}mm" viewBox="0 0 {w:.3} {h:.3}">"#
    );
    let mut up = String::new();
    let mut at = home;
    for pen in &plot.pens {
        let color = if pen.name.starts_with('#') {
            pen.name.as_str()
        } else {
            "black"
        };
        let _ = writeln!(
            out,
            r#"<g id="pen-{}" fill="none" stroke="{color}" stroke-width="0.3" stroke-linecap="round" stroke-linejoin="round">"#,
            xml_escape(&pen.name)
        );
        for s in &pen.strokes {
            let (x0, y0) = tx(at);
            let (x1, y1) = tx(s[0]);
            let _ = write!(up, "M{x0:.3},{y0:.3}L{x1:.3},{y1:.3}");
            out.push_str("<path d=\"");
            for (i, p) in s.iter().enumerate() {
                let (x, y) = tx(*p);
                let _ = write!(out, "{}{x:.3},{y:.3}", if i == 0 { "M" } else { "L" });
            }
            out.push_str("\"/>\n");
            at = *s.last().unwrap();
        }
        out.push_str("</g>\n");
    }
    let (x0, y0) = tx(at);
    let (x1, y1) = tx(home);
    let _ = write!(up, "M{x0:.3},{y0:.3}L{x1:.3},{y1:.3}");
    let _ = writeln!(
        out,
        r#"<path id="pen-up" d="{up}" fill="none" stroke="red" stroke-width="0.15" stroke-dasharray="1,1"/>"#
    );
    out.push_str("</svg>\n");
    out
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('"', "&quot;")
}
