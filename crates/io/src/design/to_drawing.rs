//! Design entities as the drawing every command works on, and back: a path of lines and
//! arcs (an offset's result) as a polyline with bulges.

use super::model::{Design, Entity, Shape};
use oficina_geom::{text_strokes, Arc, Drawing, Path, Point, Segment, SourceRef, Style};

fn pt(p: [f64; 2]) -> Point {
    Point::new(p[0], p[1])
}

/// The paths of one entity (a text is one path per stroke).
pub fn entity_paths(shape: &Shape) -> Vec<Path> {
    match shape {
        Shape::Line { a, b } => vec![Path::new(vec![Segment::line(pt(*a), pt(*b))], false)],
        Shape::Arc {
            center,
            radius,
            start,
            sweep,
        } => {
            let arc = Arc::new(pt(*center), *radius, start.to_radians(), sweep.to_radians());
            vec![Path::new(vec![Segment::Arc(arc)], false)]
        }
        Shape::Circle { center, radius } => {
            vec![Path::new(
                vec![Segment::Arc(Arc::circle(pt(*center), *radius))],
                true,
            )]
        }
        Shape::Polyline { vertices, closed } => {
            let n = vertices.len();
            let pieces = if *closed { n } else { n - 1 };
            let segments = (0..pieces)
                .filter_map(|k| {
                    let (v, w) = (&vertices[k], &vertices[(k + 1) % n]);
                    let (a, b) = (Point::new(v[0], v[1]), Point::new(w[0], w[1]));
                    if a == b {
                        return None;
                    }
                    let bulge = v.get(2).copied().unwrap_or(0.0);
                    Some(Arc::from_bulge(a, b, bulge).map_or(Segment::line(a, b), Segment::Arc))
                })
                .collect();
            vec![Path::new(segments, *closed)]
        }
        // A mark, not a stroke: nothing to cut, plot or sew.
        Shape::Point { .. } => vec![],
        Shape::Spline { points } => {
            let pts: Vec<Point> = points.iter().map(|p| pt(*p)).collect();
            let cubics = crate::dxf::through_fit_points(&pts, None);
            vec![Path::new(
                cubics.into_iter().map(Segment::Cubic).collect(),
                false,
            )]
        }
        Shape::Text {
            at,
            height,
            angle,
            text,
        } => text_strokes(text, pt(*at), *height, angle.to_radians())
            .iter()
            .filter(|s| s.len() > 1)
            .map(|s| Path::polyline(s, false))
            .collect(),
    }
}

impl Design {
    /// The drawing: a layer per design layer (in order, empty ones too), every entity's paths
    /// stroked in its layer's colour, each path naming its entity (`entity ID`).
    pub fn to_drawing(&self, file: &str) -> Drawing {
        let mut d = Drawing::new();
        for l in &self.layers {
            d.layer_mut(&l.name);
        }
        for e in &self.entities {
            let style = Style {
                stroke: Some(self.layer_color(&e.layer)),
                ..Style::default()
            };
            for p in entity_paths(&e.shape) {
                if p.is_empty() {
                    continue;
                }
                let src = SourceRef::new(file, format!("entity {}", e.id));
                d.push(&e.layer, p.with_style(style).with_source(src));
            }
        }
        d
    }
}

/// A path of lines and arcs as polyline vertices with bulges (tan(sweep/4)); `None` when
/// it holds a Bézier, which a bulge cannot say.
pub fn path_to_polyline(p: &Path) -> Option<Shape> {
    let mut vertices: Vec<Vec<f64>> = Vec::with_capacity(p.segments.len() + 1);
    let mut vertex = |a: Point, bulge: f64| {
        vertices.push(if bulge == 0.0 {
            vec![a.x, a.y]
        } else {
            vec![a.x, a.y, bulge]
        })
    };
    for s in &p.segments {
        match s {
            Segment::Line(l) => vertex(l.p0, 0.0),
            // A bulge grows without bound towards a whole turn: an arc of more than half a
            // turn (a circle) is written as its two halves.
            Segment::Arc(arc) if arc.sweep.abs() > std::f64::consts::PI => {
                let h = arc.sweep / 2.0;
                let second = Arc::new(arc.center, arc.radius, arc.start_angle + h, h);
                vertex(arc.start(), (h / 4.0).tan());
                vertex(second.start(), (h / 4.0).tan());
            }
            Segment::Arc(arc) => vertex(arc.start(), (arc.sweep / 4.0).tan()),
            Segment::Cubic(_) => return None,
        }
    }
    let end = p.end()?;
    if !p.closed {
        vertices.push(vec![end.x, end.y]);
    }
    Some(Shape::Polyline {
        vertices,
        closed: p.closed,
    })
}

/// New entities on `layer` for `paths`, ids from `first_id` on: a path of lines and arcs
/// becomes a polyline; one holding Béziers, the spline of its segment ends is not the same
/// curve, so it is refused by name.
pub fn design_from_paths(
    paths: &[Path],
    layer: &str,
    first_id: u64,
) -> Result<Vec<Entity>, String> {
    paths
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let shape = path_to_polyline(p).ok_or_else(|| {
                format!("path {k} has Bézier pieces, which a polyline cannot hold")
            })?;
            Ok(Entity {
                id: first_id + k as u64,
                layer: layer.to_string(),
                shape,
            })
        })
        .collect()
}
