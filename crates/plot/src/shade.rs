//! A drawing's filled shapes: hatched (`fill`) and hiding what was drawn before them
//! (`occult`, as vpype-occult does it). An SVG element's subpaths come in as consecutive paths
//! with one source, so they are gathered back into one shape: its holes are its other rings.

use oficina_geom::{simplify, Drawing, Fill, Path, Region, Ring};
use rstar::{RTree, RTreeObject, AABB};

use crate::clip::{cut, Area};
use crate::fill::{fill_regions, FillStyle, MAX_FILL_LINES};
use crate::strokes::{color_name, PenBy, Plot, Stroke};

/// What counts as a filled (opaque) shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filled {
    /// Shapes with a fill colour (the SVG's own rule).
    Svg,
    /// Every closed outline, filled or not (as AxiDraw's Hatch Fill takes them: plotter SVGs
    /// rarely set a fill); an element's closed subpaths make one shape, holes by its rule.
    Closed,
    /// Every closed subpath is a shape of its own, drawn in turn: a later loop hides what is
    /// inside it even within one element (vpype-occult's rule: vpype keeps no elements).
    Loops,
}

/// Which shapes hide which.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Occult {
    /// Nothing is hidden.
    Off,
    /// A filled shape hides what its own pen drew before it (vpype `occult`).
    PerPen,
    /// A filled shape hides what any pen drew before it (vpype `occult -i`).
    Across,
}

/// How the filled shapes of a drawing are drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Shading {
    /// Hatch the filled shapes; `None` draws outlines only.
    pub fill: Option<FillStyle>,
    /// What counts as filled.
    pub filled: Filled,
    /// Hidden-line removal.
    pub occult: Occult,
    /// Drawing units per mm on paper (the hatch spacing is on paper; the drawing is scaled
    /// after): 1 / the plot's scale.
    pub units_per_mm: f64,
}

impl Default for Shading {
    fn default() -> Self {
        Shading {
            fill: None,
            filled: Filled::Svg,
            occult: Occult::Off,
            units_per_mm: 1.0,
        }
    }
}

/// One SVG element (or DXF/HPGL entity): its pens' strokes and the area it fills.
struct Item {
    strokes: Vec<(usize, Stroke)>,
    area: Option<Area>,
    pen: usize,
}

struct Boxed(usize, [f64; 4]);

impl RTreeObject for Boxed {
    type Envelope = AABB<[f64; 2]>;
    fn envelope(&self) -> Self::Envelope {
        AABB::from_corners([self.1[0], self.1[1]], [self.1[2], self.1[3]])
    }
}

/// The element's rings as it fills them: every subpath, closed or not (SVG closes them).
fn rings(paths: &[&Path], tol: f64, filled: Filled) -> Vec<Ring> {
    paths
        .iter()
        .filter(|p| filled == Filled::Svg || p.closed)
        .map(|p| oficina_geom::to_ring(&p.flatten(tol)))
        .filter(|r| r.len() >= 3)
        .collect()
}

/// Pens of strokes for `d` with its filled shapes hatched and/or hiding earlier strokes.
/// `even_odd` says whether an element is filled with the even-odd rule (else nonzero).
pub fn shade(
    d: &Drawing,
    by: PenBy,
    tol: f64,
    s: &Shading,
    even_odd: &dyn Fn(&Path) -> bool,
) -> Result<Plot, String> {
    if let Some(f) = &s.fill {
        f.check()?;
    }
    if !(s.units_per_mm.is_finite() && s.units_per_mm > 0.0) {
        return Err(format!("scale of 1/{}: must be > 0", s.units_per_mm));
    }
    let mut plot = Plot::default();
    let mut items: Vec<Item> = Vec::new();
    let mut budget = MAX_FILL_LINES;
    for layer in &d.layers {
        let mut i = 0;
        while i < layer.paths.len() {
            // Consecutive subpaths of one element share its source.
            let src = &layer.paths[i].source;
            let mut j = i + 1;
            while s.filled != Filled::Loops
                && !src.element.is_empty()
                && j < layer.paths.len()
                && layer.paths[j].source == *src
            {
                j += 1;
            }
            let group: Vec<&Path> = layer.paths[i..j].iter().collect();
            i = j;
            let first = group[0];
            let pen_name = match by {
                PenBy::Layer => layer.name.clone(),
                PenBy::Color => color_name(first.style.stroke.or(first.style.fill)),
            };
            let pen = plot.pen_index(&pen_name);
            let mut item = Item {
                strokes: Vec::new(),
                area: None,
                pen,
            };
            for p in &group {
                if let Some(st) = crate::strokes::path_stroke(p, tol) {
                    item.strokes.push((pen, st));
                }
            }
            let is_filled = match s.filled {
                Filled::Svg => first.style.fill.is_some(),
                Filled::Closed | Filled::Loops => group.iter().any(|p| p.closed),
            };
            if is_filled && (s.fill.is_some() || s.occult != Occult::Off) {
                let rule = if even_odd(first) {
                    Fill::EvenOdd
                } else {
                    Fill::NonZero
                };
                let regions: Vec<Region> =
                    simplify(&rings(&group, tol, s.filled), rule).map_err(|e| e.to_string())?;
                if let Some(f) = &s.fill {
                    let on_paper = FillStyle {
                        spacing: f.spacing * s.units_per_mm,
                        ..*f
                    };
                    let hatch_pen = match (by, first.style.fill) {
                        (PenBy::Color, Some(c)) => plot.pen_index(&color_name(Some(c))),
                        _ => pen,
                    };
                    for h in fill_regions(&regions, &on_paper, tol, &mut budget)? {
                        item.strokes.push((hatch_pen, h));
                    }
                }
                item.area = Area::new(
                    regions
                        .into_iter()
                        .flat_map(|r| std::iter::once(r.outer).chain(r.holes))
                        .collect(),
                );
            }
            items.push(item);
        }
    }
    if s.occult != Occult::Off {
        occult(&mut items, s.occult == Occult::Across);
    }
    for it in items {
        for (pen, st) in it.strokes {
            plot.pens[pen].strokes.push(st);
        }
    }
    plot.pens.retain(|p| !p.strokes.is_empty());
    Ok(plot)
}

/// Each filled item hides the parts of earlier items' strokes inside it (of its own pen, or
/// of any with `across`), as vpype-occult does: later shapes lie on top.
fn occult(items: &mut [Item], across: bool) {
    let tree = RTree::bulk_load(
        items
            .iter()
            .enumerate()
            .filter_map(|(k, it)| it.area.as_ref().map(|a| Boxed(k, a.bbox)))
            .collect(),
    );
    for j in 0..items.len() {
        let mut strokes = std::mem::take(&mut items[j].strokes);
        let b = strokes
            .iter()
            .flat_map(|(_, s)| s.iter())
            .fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, p| {
                [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)]
            });
        if b[0] > b[2] {
            continue;
        }
        let mut later: Vec<usize> = tree
            .locate_in_envelope_intersecting(&AABB::from_corners([b[0], b[1]], [b[2], b[3]]))
            .map(|o| o.0)
            .filter(|&k| k > j && (across || items[k].pen == items[j].pen))
            .collect();
        later.sort_unstable();
        for k in later {
            let area = items[k].area.as_ref().expect("indexed items have areas");
            strokes = strokes
                .into_iter()
                .flat_map(|(pen, s)| {
                    cut(&s, area, false, true)
                        .into_iter()
                        .map(move |piece| (pen, piece))
                })
                .collect();
        }
        items[j].strokes = strokes;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use oficina_geom::{Color, Point, Style};

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64, fill: bool, id: &str) -> Path {
        let pts = [
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ];
        Path::polyline(&pts, true)
            .with_style(Style {
                fill: fill.then_some(Color::BLACK),
                ..Style::default()
            })
            .with_source(oficina_geom::SourceRef::new("t", id))
    }

    #[test]
    fn a_later_filled_square_hides_the_earlier_one_and_holes_show_through() {
        let mut d = Drawing::new();
        d.push("a", rect(0.0, 0.0, 10.0, 10.0, false, "a"));
        d.push("a", rect(5.0, 5.0, 15.0, 15.0, true, "b"));
        let s = Shading {
            occult: Occult::PerPen,
            ..Shading::default()
        };
        let p = shade(&d, PenBy::Layer, 0.01, &s, &|_| false).unwrap();
        // The first square loses its 5 + 5 mm inside the second.
        let l = p.lengths().pen_down;
        assert!((l - (30.0 + 40.0)).abs() < 1e-6, "{l}");
        // With a hole (even-odd) where the first square's corner is, it shows through.
        let mut d2 = d.clone();
        d2.push("a", rect(4.0, 4.0, 11.0, 11.0, true, "c"));
        d2.push("a", rect(6.0, 6.0, 12.0, 12.0, true, "c"));
        let p = shade(&d2, PenBy::Layer, 0.01, &s, &|_| true).unwrap();
        for st in p.strokes() {
            for w in st.windows(2) {
                let m = w[0].midpoint(w[1]);
                let on_c = [4.0, 11.0, 6.0, 12.0]
                    .iter()
                    .any(|&v| (m.x - v).abs() < 1e-9 || (m.y - v).abs() < 1e-9);
                let in_ring = !on_c
                    && m.x > 4.0
                    && m.x < 11.0
                    && m.y > 4.0
                    && m.y < 11.0
                    && !(m.x > 6.0 && m.x < 12.0 && m.y > 6.0 && m.y < 12.0);
                assert!(!in_ring, "{m:?} drawn under the later ring");
            }
        }
    }
}
