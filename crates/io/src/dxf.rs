//! DXF → `Drawing` through the `dxf` crate: LINE, ARC, CIRCLE, LWPOLYLINE and POLYLINE (with
//! bulges), SPLINE, ELLIPSE, INSERT of blocks (scale, rotation, arrays, nesting) and POINT,
//! in mm from `$INSUNITS`. Anything else is counted and listed in `Unsupported`.

use crate::import::{ImportError, Imported};
use dxf::entities::{Entity, EntityType};
use dxf::enums::Units;
use oficina_geom::kurbo::{self, Affine};
use oficina_geom::{Arc, Color, Path, Point, Segment, SourceRef, Style};
use std::collections::HashMap;

/// Deepest nesting of block inserts followed (a block that inserts itself stops here).
const MAX_DEPTH: usize = 16;
/// Most entities one file may expand to through inserts and arrays (a bound on the
/// drawing's size however the arrays nest).
const MAX_EXPANDED: usize = 1_000_000;

/// Millimetres per drawing unit of `$INSUNITS`; unitless drawings are taken as mm.
fn mm_per_unit(u: Units) -> Option<f64> {
    Some(match u {
        Units::Unitless | Units::Millimeters => 1.0,
        Units::Inches => 25.4,
        Units::Feet => 304.8,
        Units::Yards => 914.4,
        Units::Centimeters => 10.0,
        Units::Decimeters => 100.0,
        Units::Meters => 1000.0,
        Units::Microns => 1e-3,
        Units::Mils => 0.0254,
        Units::Microinches => 2.54e-5,
        Units::USSurveyInch => 25.400_050_8,
        Units::USSurveyFeet => 304.800_609_6,
        _ => return None,
    })
}

/// AutoCAD colour index 1–7 as RGB (7 is white on black, black on paper: black here).
fn aci(i: u8) -> Option<Color> {
    Some(match i {
        1 => Color::rgb(255, 0, 0),
        2 => Color::rgb(255, 255, 0),
        3 => Color::rgb(0, 255, 0),
        4 => Color::rgb(0, 255, 255),
        5 => Color::rgb(0, 0, 255),
        6 => Color::rgb(255, 0, 255),
        7 => Color::BLACK,
        _ => return None,
    })
}

struct Reader<'a> {
    file: &'a str,
    blocks: HashMap<String, &'a dxf::Block>,
    out: Imported,
    expanded: usize,
}

fn kind(e: &EntityType) -> String {
    let s = format!("{e:?}");
    s.split(['(', ' ', '{'])
        .next()
        .unwrap_or("?")
        .to_ascii_uppercase()
}

/// Segments of a polyline with bulges (bulge = tan(sweep/4) on the vertex starting a span).
fn bulged(v: &[(Point, f64)], closed: bool) -> Vec<Segment> {
    let n = v.len();
    let spans = if closed { n } else { n.saturating_sub(1) };
    (0..spans)
        .filter_map(|i| {
            let (a, bulge) = v[i];
            let b = v[(i + 1) % n].0;
            if a.distance(b) < 1e-12 {
                return None;
            }
            Some(match Arc::from_bulge(a, b, bulge) {
                Some(arc) => Segment::Arc(arc),
                None => Segment::line(a, b),
            })
        })
        .collect()
}

/// Points of a (possibly rational) B-spline of any degree, by de Boor, `per` per knot span.
fn spline_points(s: &dxf::entities::Spline) -> Option<Vec<Point>> {
    let p = s.degree_of_curve.max(1) as usize;
    let ctrl: Vec<Point> = s
        .control_points
        .iter()
        .map(|c| Point::new(c.x, c.y))
        .collect();
    let k = &s.knot_values;
    if ctrl.len() <= p || k.len() != ctrl.len() + p + 1 || p > 10 {
        return None;
    }
    let w: Vec<f64> = if s.weight_values.len() == ctrl.len() {
        s.weight_values.clone()
    } else {
        vec![1.0; ctrl.len()]
    };
    let (u0, u1) = (k[p], k[ctrl.len()]);
    if !(u1 > u0) || k.windows(2).any(|x| !(x[1] >= x[0])) {
        return None;
    }
    let per = 24;
    let spans = ctrl.len() - p;
    let eval = |u: f64| -> Point {
        let mut s = p;
        while s < ctrl.len() - 1 && u >= k[s + 1] {
            s += 1;
        }
        // Homogeneous de Boor.
        let mut d: Vec<(f64, f64, f64)> = (0..=p)
            .map(|j| {
                let c = ctrl[s - p + j];
                let wj = w[s - p + j];
                (c.x * wj, c.y * wj, wj)
            })
            .collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let i = s - p + j;
                let den = k[i + p + 1 - r] - k[i];
                let a = if den > 0.0 { (u - k[i]) / den } else { 0.0 };
                d[j] = (
                    (1.0 - a) * d[j - 1].0 + a * d[j].0,
                    (1.0 - a) * d[j - 1].1 + a * d[j].1,
                    (1.0 - a) * d[j - 1].2 + a * d[j].2,
                );
            }
        }
        let (x, y, ww) = d[p];
        Point::new(x / ww, y / ww)
    };
    let n = spans * per;
    let pts: Vec<Point> = (0..=n)
        .map(|i| eval(u0 + (u1 - u0) * i as f64 / n as f64))
        .collect();
    pts.iter().all(|p| p.is_finite()).then_some(pts)
}

impl<'a> Reader<'a> {
    fn push(&mut self, layer: &str, e: &Entity, path: Path, m: Affine, what: &str) {
        let color = e.common.color.index().and_then(aci);
        let mut p = path.transform(m).with_source(SourceRef::new(
            self.file,
            format!("{what} #{}", e.common.handle.as_string()),
        ));
        if let Some(c) = color {
            p.style = Style {
                stroke: Some(c),
                ..Style::default()
            };
        }
        self.out.drawing.push(layer, p);
    }

    fn entity(&mut self, e: &'a Entity, m: Affine, depth: usize) -> Result<(), ImportError> {
        self.expanded += 1;
        if self.expanded > MAX_EXPANDED {
            return Err(ImportError::new(
                self.file,
                "INSERT",
                format!("expands to more than {MAX_EXPANDED} entities"),
            ));
        }
        let layer = if e.common.layer.is_empty() {
            "0"
        } else {
            e.common.layer.as_str()
        };
        let handle = || format!("#{}", e.common.handle.as_string());
        let pt = |p: &dxf::Point| Point::new(p.x, p.y);
        // Entities drawn in a plane other than XY (seen from below, normal −Z, is X mirrored).
        let ocs = |n: &dxf::Vector| -> Option<Affine> {
            if n.x.abs() < 1e-9 && n.y.abs() < 1e-9 {
                Some(if n.z < 0.0 {
                    Affine::new([-1.0, 0.0, 0.0, 1.0, 0.0, 0.0])
                } else {
                    Affine::IDENTITY
                })
            } else {
                None
            }
        };
        match &e.specific {
            EntityType::Line(l) => {
                if pt(&l.p1).distance(pt(&l.p2)) > 0.0 {
                    self.push(
                        layer,
                        e,
                        Path::new(vec![Segment::line(pt(&l.p1), pt(&l.p2))], false),
                        m,
                        "LINE",
                    );
                }
            }
            EntityType::Arc(a) => {
                let Some(o) = ocs(&a.normal) else {
                    self.out
                        .unsupported
                        .add("ARC (not in the XY plane)", handle());
                    return Ok(());
                };
                let a0 = a.start_angle.to_radians();
                let mut sweep = (a.end_angle - a.start_angle).rem_euclid(360.0).to_radians();
                if sweep <= 1e-12 {
                    sweep = std::f64::consts::TAU;
                }
                let arc = Arc::new(pt(&a.center), a.radius, a0, sweep);
                self.push(
                    layer,
                    e,
                    Path::new(vec![Segment::Arc(arc)], false),
                    m * o,
                    "ARC",
                );
            }
            EntityType::Circle(c) => {
                let Some(o) = ocs(&c.normal) else {
                    self.out
                        .unsupported
                        .add("CIRCLE (not in the XY plane)", handle());
                    return Ok(());
                };
                let arc = Arc::circle(pt(&c.center), c.radius);
                self.push(
                    layer,
                    e,
                    Path::new(vec![Segment::Arc(arc)], true),
                    m * o,
                    "CIRCLE",
                );
            }
            EntityType::LwPolyline(p) => {
                let Some(o) = ocs(&p.extrusion_direction) else {
                    self.out
                        .unsupported
                        .add("LWPOLYLINE (not in the XY plane)", handle());
                    return Ok(());
                };
                let v: Vec<(Point, f64)> = p
                    .vertices
                    .iter()
                    .map(|v| (Point::new(v.x, v.y), v.bulge))
                    .collect();
                let segs = bulged(&v, p.is_closed());
                if !segs.is_empty() {
                    self.push(
                        layer,
                        e,
                        Path::new(segs, p.is_closed()),
                        m * o,
                        "LWPOLYLINE",
                    );
                }
            }
            EntityType::Polyline(p) => {
                // 16: polygon mesh, 64: polyface mesh: surfaces, not outlines.
                if p.flags & (16 | 64) != 0 {
                    self.out.unsupported.add("POLYLINE (mesh)", handle());
                    return Ok(());
                }
                let v: Vec<(Point, f64)> =
                    p.vertices().map(|v| (pt(&v.location), v.bulge)).collect();
                let segs = bulged(&v, p.is_closed());
                if !segs.is_empty() {
                    self.push(layer, e, Path::new(segs, p.is_closed()), m, "POLYLINE");
                }
            }
            EntityType::Spline(s) => {
                let pts = spline_points(s).or_else(|| {
                    // Fit points only: a curve through them.
                    let f: Vec<Point> = s.fit_points.iter().map(pt).collect();
                    (f.len() >= 2).then_some(f)
                });
                match pts {
                    Some(pts) => {
                        let closed = s.flags & 1 != 0;
                        let flat = oficina_geom::fit::simplify_open(&pts, 1e-4);
                        self.push(layer, e, Path::polyline(&flat, closed), m, "SPLINE");
                    }
                    None => self
                        .out
                        .unsupported
                        .add("SPLINE (bad knots or control points)", handle()),
                }
            }
            EntityType::Ellipse(el) => {
                let Some(o) = ocs(&el.normal) else {
                    self.out
                        .unsupported
                        .add("ELLIPSE (not in the XY plane)", handle());
                    return Ok(());
                };
                let major = kurbo::Vec2::new(el.major_axis.x, el.major_axis.y);
                let rx = major.hypot();
                let ry = rx * el.minor_axis_ratio;
                let mut sweep =
                    (el.end_parameter - el.start_parameter).rem_euclid(std::f64::consts::TAU);
                if sweep <= 1e-12 {
                    sweep = std::f64::consts::TAU;
                }
                if !(rx > 0.0 && ry > 0.0) {
                    self.out.unsupported.add("ELLIPSE (zero axis)", handle());
                    return Ok(());
                }
                let k = kurbo::Arc::new(
                    pt(&el.center),
                    (rx, ry),
                    el.start_parameter,
                    sweep,
                    major.atan2(),
                );
                let mut segs = Vec::new();
                let mut from = Affine::translate(k.center.to_vec2())
                    * Affine::rotate(major.atan2())
                    * Point::new(rx * el.start_parameter.cos(), ry * el.start_parameter.sin());
                k.to_cubic_beziers(1e-6, |p1, p2, p3| {
                    segs.push(Segment::Cubic(kurbo::CubicBez::new(from, p1, p2, p3)));
                    from = p3;
                });
                let closed = (sweep - std::f64::consts::TAU).abs() < 1e-9;
                self.push(layer, e, Path::new(segs, closed), m * o, "ELLIPSE");
            }
            EntityType::Insert(ins) => {
                if depth >= MAX_DEPTH {
                    return Err(ImportError::new(
                        self.file,
                        format!("INSERT {}", handle()),
                        format!(
                            "blocks nested deeper than {MAX_DEPTH} (a block inserting itself?)"
                        ),
                    ));
                }
                let Some(block) = self.blocks.get(&ins.name).copied() else {
                    return Err(ImportError::new(
                        self.file,
                        format!("INSERT {}", handle()),
                        format!("block '{}' is not defined", ins.name),
                    ));
                };
                let (sx, sy) = (
                    if ins.x_scale_factor == 0.0 {
                        1.0
                    } else {
                        ins.x_scale_factor
                    },
                    if ins.y_scale_factor == 0.0 {
                        1.0
                    } else {
                        ins.y_scale_factor
                    },
                );
                let rot = ins.rotation.to_radians();
                let (cols, rows) = (
                    ins.column_count.max(1) as usize,
                    ins.row_count.max(1) as usize,
                );
                if cols * rows > 100_000 {
                    return Err(ImportError::new(
                        self.file,
                        format!("INSERT {}", handle()),
                        format!("array of {cols}×{rows}"),
                    ));
                }
                for r in 0..rows {
                    for c in 0..cols {
                        let cell = kurbo::Vec2::new(
                            c as f64 * ins.column_spacing,
                            r as f64 * ins.row_spacing,
                        );
                        let place = m
                            * Affine::translate((ins.location.x, ins.location.y))
                            * Affine::rotate(rot)
                            * Affine::translate(cell)
                            * Affine::scale_non_uniform(sx, sy)
                            * Affine::translate((-block.base_point.x, -block.base_point.y));
                        for be in &block.entities {
                            self.entity(be, place, depth + 1)?;
                        }
                    }
                }
            }
            EntityType::ModelPoint(p) => self.out.points.push(m * pt(&p.location)),
            other => self.out.unsupported.add(&kind(other), handle()),
        }
        Ok(())
    }
}

/// Reads a DXF file's model space into a drawing, in mm.
pub fn dxf_from_bytes(bytes: &[u8], file: &str) -> Result<Imported, ImportError> {
    let mut cursor = std::io::Cursor::new(bytes);
    // The dxf crate is defensive but not fuzzed by its authors: a panic in it becomes an error.
    let loaded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        dxf::Drawing::load(&mut cursor)
    }));
    let d = match loaded {
        Ok(Ok(d)) => d,
        Ok(Err(e)) => return Err(ImportError::new(file, "DXF", e.to_string())),
        Err(_) => {
            return Err(ImportError::new(
                file,
                "DXF",
                "the DXF reader failed on this file (malformed)",
            ))
        }
    };
    let units = d.header.default_drawing_units;
    let scale = mm_per_unit(units).ok_or_else(|| {
        ImportError::new(
            file,
            "$INSUNITS",
            format!("units {units:?} are not supported"),
        )
    })?;
    let blocks: HashMap<String, &dxf::Block> = d.blocks().map(|b| (b.name.clone(), b)).collect();
    let mut r = Reader {
        file,
        blocks,
        out: Imported::default(),
        expanded: 0,
    };
    r.out.set_units(format!("{units:?} ($INSUNITS)"), scale);
    let m = Affine::scale(scale);
    for e in d.entities() {
        if e.common.is_in_paper_space {
            r.out.unsupported.add(
                "paper-space entity",
                format!("#{}", e.common.handle.as_string()),
            );
            continue;
        }
        r.entity(e, m, 0)?;
    }
    Ok(r.out)
}
