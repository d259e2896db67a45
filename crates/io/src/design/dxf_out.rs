//! A design as DXF (R12 tags, as ezdxf and the DXF importer read them): a LAYER table with
//! the layers (colour: the nearest of the seven basic ACI colours, the ones the importer
//! names), then LINE, ARC, CIRCLE, POLYLINE with bulges, SPLINE by its fit points (the
//! importer builds the same interpolating cubic the design means), and text as one
//! POLYLINE per stroke. Numbers are written in Rust's shortest exact form, so they read
//! back bit for bit.

use super::model::{parse_color, Design, Shape};
use super::to_drawing::entity_paths;
use oficina_geom::Color;
use std::fmt::Write;

/// The DXF text.
pub fn design_to_dxf(design: &Design) -> String {
    let mut s = String::new();
    let mut tag = |code: i32, v: &dyn std::fmt::Display| {
        let _ = write!(s, "{code}\n{v}\n");
    };
    tag(0, &"SECTION");
    tag(2, &"HEADER");
    tag(9, &"$ACADVER");
    tag(1, &"AC1009");
    tag(9, &"$INSUNITS");
    tag(70, &4); // millimetres
    tag(0, &"ENDSEC");
    tag(0, &"SECTION");
    tag(2, &"TABLES");
    tag(0, &"TABLE");
    tag(2, &"LAYER");
    tag(70, &design.layers.len());
    for l in &design.layers {
        tag(0, &"LAYER");
        tag(2, &l.name);
        tag(70, &0);
        tag(
            62,
            &nearest_aci(parse_color(&l.color).unwrap_or(Color::BLACK)),
        );
        tag(6, &"CONTINUOUS");
    }
    tag(0, &"ENDTAB");
    tag(0, &"ENDSEC");
    tag(0, &"SECTION");
    tag(2, &"ENTITIES");
    for e in &design.entities {
        let head = |tag: &mut dyn FnMut(i32, &dyn std::fmt::Display), kind: &str| {
            tag(0, &kind);
            tag(8, &e.layer);
            tag(62, &256); // by layer
        };
        match &e.shape {
            Shape::Line { a, b } => {
                head(&mut tag, "LINE");
                for (k, p) in [a, b].into_iter().enumerate() {
                    tag(10 + k as i32, &p[0]);
                    tag(20 + k as i32, &p[1]);
                }
            }
            Shape::Arc {
                center,
                radius,
                start,
                sweep,
            } => {
                // DXF arcs run counter-clockwise: a clockwise one from its end.
                let (a0, a1) = if *sweep > 0.0 {
                    (*start, start + sweep)
                } else {
                    (start + sweep, *start)
                };
                head(&mut tag, "ARC");
                tag(10, &center[0]);
                tag(20, &center[1]);
                tag(40, radius);
                tag(50, &a0);
                tag(51, &a1);
            }
            Shape::Point { at } => {
                head(&mut tag, "POINT");
                tag(10, &at[0]);
                tag(20, &at[1]);
            }
            Shape::Circle { center, radius } => {
                head(&mut tag, "CIRCLE");
                tag(10, &center[0]);
                tag(20, &center[1]);
                tag(40, radius);
            }
            Shape::Polyline { vertices, closed } => {
                head(&mut tag, "POLYLINE");
                tag(66, &1);
                tag(70, &i32::from(*closed));
                for v in vertices {
                    tag(0, &"VERTEX");
                    tag(8, &e.layer);
                    tag(10, &v[0]);
                    tag(20, &v[1]);
                    if let Some(b) = v.get(2).filter(|b| **b != 0.0) {
                        tag(42, b);
                    }
                }
                tag(0, &"SEQEND");
            }
            Shape::Spline { points } => {
                // SPLINE is not an R12 entity: ezdxf reads it only with its subclass markers.
                tag(0, &"SPLINE");
                tag(100, &"AcDbEntity");
                tag(8, &e.layer);
                tag(62, &256);
                tag(100, &"AcDbSpline");
                tag(70, &8); // planar
                tag(71, &3);
                tag(72, &0);
                tag(73, &0);
                tag(74, &points.len());
                for p in points {
                    tag(11, &p[0]);
                    tag(21, &p[1]);
                }
            }
            Shape::Text { .. } => {
                for p in entity_paths(&e.shape) {
                    head(&mut tag, "POLYLINE");
                    tag(66, &1);
                    tag(70, &0);
                    for q in p.flatten(1.0) {
                        tag(0, &"VERTEX");
                        tag(8, &e.layer);
                        tag(10, &q.x);
                        tag(20, &q.y);
                    }
                    tag(0, &"SEQEND");
                }
            }
        }
    }
    tag(0, &"ENDSEC");
    tag(0, &"EOF");
    s
}

/// The nearest (in RGB) of ACI 1–7: red, yellow, green, cyan, blue, magenta, white/black.
fn nearest_aci(c: Color) -> u8 {
    const BASIC: [(u8, [u8; 3]); 7] = [
        (1, [255, 0, 0]),
        (2, [255, 255, 0]),
        (3, [0, 255, 0]),
        (4, [0, 255, 255]),
        (5, [0, 0, 255]),
        (6, [255, 0, 255]),
        (7, [0, 0, 0]),
    ];
    let d = |q: [u8; 3]| {
        [c.r, c.g, c.b]
            .iter()
            .zip(q)
            .map(|(a, b)| (i32::from(*a) - i32::from(b)).pow(2))
            .sum::<i32>()
    };
    BASIC
        .iter()
        .min_by_key(|(_, q)| d(*q))
        .map_or(7, |(n, _)| *n)
}
