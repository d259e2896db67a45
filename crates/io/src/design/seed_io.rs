//! A design as seed 001's graphic file and back (`crate::seed001`). The file has no layers,
//! ids or colours: entities are read onto layer `0`, numbered in file order. Numbers are
//! written in Rust's shortest exact form, so coordinates read back bit for bit (arc angles
//! are recomputed from the end points, within 1e-12°).
//!
//! Design → file: a point goes to the point list; a circle is a code 19 chain of two half
//! circles; every other entity is its paths as `seed001::path_entities` writes them (a line
//! or a straight polyline code 4, an arc code 1, a closed all-arc polyline code 19, a
//! polyline mixing lines and arcs piece by piece, splines and text flattened to 0.01 mm).
//! File → design: a two-point code 4 is a line, a lone arc an arc, a closed chain of two
//! arcs about one centre a circle, every other entity a polyline with bulges.

use super::model::{Design, Entity, Shape};
use super::to_drawing::{entity_paths, path_to_polyline};
use crate::import::ImportError;
use crate::seed001::{parse_seed001, path_entities, SeedEntity, SeedFile};
use oficina_geom::{Point, Segment};
use std::f64::consts::TAU;

/// The design as a seed 001 graphic file's text.
pub fn design_to_seed001(design: &Design) -> String {
    let mut f = SeedFile::default();
    for e in &design.entities {
        match &e.shape {
            Shape::Point { at } => f.points.push(Point::new(at[0], at[1])),
            Shape::Circle { center, radius } => {
                let c = Point::new(center[0], center[1]);
                let (east, west) = (Point::new(c.x + radius, c.y), Point::new(c.x - radius, c.y));
                let arcs = vec![(east, c, *radius, 1.0), (west, c, *radius, 1.0)];
                f.entities
                    .push((SeedEntity::ArcChain { arcs, close: east }, 0));
            }
            shape => f.entities.extend(
                entity_paths(shape)
                    .iter()
                    .flat_map(path_entities)
                    .map(|s| (s, 0)),
            ),
        }
    }
    f.to_text()
}

/// A seed 001 graphic file as a design (layer `0`, ids in file order).
pub fn design_from_seed001(text: &str, file: &str) -> Result<Design, ImportError> {
    let f = parse_seed001(text, file)?;
    if let Some((code, line)) = f.unknown.first() {
        return Err(ImportError::new(
            file,
            format!("line {line}"),
            format!(
                "entity code {code} is not one this reader knows ({} such)",
                f.unknown.len()
            ),
        ));
    }
    let mut d = Design::new();
    let mut id = 0;
    let mut push = |d: &mut Design, shape: Shape| {
        id += 1;
        d.entities.push(Entity {
            id,
            layer: "0".into(),
            shape,
        });
    };
    for (e, line) in &f.entities {
        let path = e
            .to_path()
            .map_err(|m| ImportError::new(file, format!("line {line}"), m))?;
        push(
            &mut d,
            shape_of(e, &path)
                .ok_or_else(|| ImportError::new(file, format!("line {line}"), "an empty entity"))?,
        );
    }
    for p in &f.points {
        push(&mut d, Shape::Point { at: [p.x, p.y] });
    }
    d.check(file)?;
    Ok(d)
}

/// The design shape of one file entity whose path is `path`.
fn shape_of(e: &SeedEntity, path: &oficina_geom::Path) -> Option<Shape> {
    let segs = &path.segments;
    match (e, segs.as_slice()) {
        (SeedEntity::Polyline(v), [Segment::Line(l)]) if v.len() == 2 => Some(Shape::Line {
            a: [l.p0.x, l.p0.y],
            b: [l.p1.x, l.p1.y],
        }),
        (SeedEntity::Arc { .. }, [Segment::Arc(a)]) if !path.closed => Some(Shape::Arc {
            center: [a.center.x, a.center.y],
            radius: a.radius,
            start: a.start_angle.to_degrees(),
            sweep: a.sweep.to_degrees(),
        }),
        // Two arcs about one centre closing a whole turn: a circle.
        (SeedEntity::ArcChain { .. }, [Segment::Arc(a), Segment::Arc(b)])
            if a.center == b.center
                && (a.radius - b.radius).abs() <= 1e-9 * a.radius
                && ((a.sweep + b.sweep).abs() - TAU).abs() < 1e-9 =>
        {
            Some(Shape::Circle {
                center: [a.center.x, a.center.y],
                radius: a.radius,
            })
        }
        _ => path_to_polyline(path),
    }
}
