//! Entities placed in the drawing: block inserts composed as affine maps, each entity's own
//! coordinate system (OCS) projected onto XY, curves turned into the drawing's segments.
//!
//! The OCS of an entity with extrusion N (normalised) is DXF's "arbitrary axis" frame:
//! Ax = (0,1,0) × N when |Nx| and |Ny| are both below 1/64, else (0,0,1) × N; Ay = N × Ax.
//! A point (x, y, z) of the OCS is x·Ax + y·Ay + z·N in the world, so its projection on XY is
//! the 2-D affine map with columns (Ax.x, Ax.y), (Ay.x, Ay.y) and offset z·(N.x, N.y), z being
//! the entity's elevation. For N = +Z that is the identity; for N = −Z it mirrors x.

use super::entity::{Boundary, Edge, Ent, Geo, InsertData, SplineData, TextData, P3};
use super::spline::{through_fit_points, Nurbs};
use super::{Block, DxfText};
use crate::import::{ImportError, Imported};
use oficina_geom::kurbo::{Affine, CubicBez, Vec2};
use oficina_geom::{text, Arc, Color, Path, Point, Segment, SourceRef, Style};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::f64::consts::{FRAC_PI_2, TAU};

/// MTEXT's distance between baselines, in text heights (AutoCAD's at line spacing factor 1).
const MTEXT_LINE_PITCH: f64 = 5.0 / 3.0;

/// Deepest nesting of block inserts followed (a block that inserts itself stops here).
const MAX_DEPTH: usize = 16;
/// Most entities one file may expand to through inserts and arrays.
const MAX_EXPANDED: usize = 1_000_000;
/// Largest distance of a rational spline's Béziers from the spline, mm.
const SPLINE_TOL_MM: f64 = 0.001;

/// AutoCAD colour index 1–7 as RGB (7 is white on black, black on paper: black here).
fn aci(i: i64) -> Option<Color> {
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

fn xy(p: P3) -> Point {
    Point::new(p[0], p[1])
}

fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: P3) -> Option<P3> {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    (l > 1e-12 && l.is_finite()).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

/// The OCS of extrusion `n` at elevation `z`, projected onto XY (see the module notes). A
/// zero extrusion is taken as +Z.
fn ocs(n: P3, z: f64) -> Affine {
    let Some(n) = unit(n) else {
        return Affine::translate((0.0, 0.0));
    };
    let lim = 1.0 / 64.0;
    let w = if n[0].abs() < lim && n[1].abs() < lim {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let ax = unit(cross(w, n)).unwrap_or([1.0, 0.0, 0.0]);
    let ay = unit(cross(n, ax)).unwrap_or([0.0, 1.0, 0.0]);
    Affine::new([ax[0], ax[1], ay[0], ay[1], z * n[0], z * n[1]])
}

/// `m` keeps shapes (its columns are orthogonal and of one length).
fn similar(m: Affine) -> bool {
    let c = m.as_coeffs();
    let (a, b) = (Vec2::new(c[0], c[1]), Vec2::new(c[2], c[3]));
    let l = a.hypot().max(b.hypot());
    a.dot(b).abs() <= 1e-9 * l * l && (a.hypot() - b.hypot()).abs() <= 1e-9 * l
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

/// The sweep from `a0` to `a1` (radians) counter-clockwise, a full turn when they meet.
fn ccw_sweep(a0: f64, a1: f64) -> f64 {
    let s = (a1 - a0).rem_euclid(TAU);
    if s <= 1e-12 {
        TAU
    } else {
        s
    }
}

/// An elliptical arc c + cos t·M + sin t·m for t from `t0` over `sweep`, as a path of the
/// drawing (a circular arc of radius |M| mapped by the affine map with columns M/|M|, m/|M|).
fn ellipse_path(
    c: Point,
    major: Vec2,
    minor: Vec2,
    t0: f64,
    sweep: f64,
    m: Affine,
) -> Option<Path> {
    let r = major.hypot();
    if !(r > 0.0) || !(minor.hypot() > 0.0) {
        return None;
    }
    let e = Affine::new([major.x / r, major.y / r, minor.x / r, minor.y / r, c.x, c.y]);
    let arc = Arc::new(Point::ORIGIN, r, t0, sweep);
    let full = (sweep.abs() - TAU).abs() < 1e-9;
    Some(Path::new(vec![Segment::Arc(arc)], full).transform(m * e))
}

pub(super) struct Drawer<'b> {
    file: &'b str,
    /// Block definitions by name in capitals (DXF names ignore case).
    blocks: &'b HashMap<String, Block>,
    /// Layer colours by name in capitals.
    layers: &'b HashMap<String, i64>,
    /// Handles of every entity in the file (for associative hatch boundaries).
    handles: HashSet<&'b str>,
    scale: f64,
    out: Imported,
    counts: BTreeMap<String, usize>,
    texts: Vec<DxfText>,
    /// Draw text with the single-stroke font ([`super::DxfOptions::draw_text`]).
    pub(super) draw_text: bool,
    expanded: usize,
}

/// What an entity inside a block takes from the INSERT that placed it.
#[derive(Clone, Copy)]
struct Inherit<'s> {
    layer: &'s str,
    color: Option<Color>,
}

impl<'b> Drawer<'b> {
    pub(super) fn new(
        file: &'b str,
        blocks: &'b HashMap<String, Block>,
        layers: &'b HashMap<String, i64>,
        scale: f64,
    ) -> Drawer<'b> {
        Drawer {
            file,
            blocks,
            layers,
            handles: HashSet::new(),
            scale,
            out: Imported::default(),
            counts: BTreeMap::new(),
            texts: Vec::new(),
            draw_text: true,
            expanded: 0,
        }
    }

    pub(super) fn model(&mut self, model: &'b [Ent]) -> Result<(), ImportError> {
        self.handles = model
            .iter()
            .chain(self.blocks.values().flat_map(|b| b.ents.iter()))
            .map(|e| e.common.handle.as_str())
            .filter(|h| !h.is_empty())
            .collect();
        let m = Affine::scale(self.scale);
        for e in model {
            if e.common.paper {
                self.out
                    .unsupported
                    .add("paper-space entity", Self::element(e));
                continue;
            }
            self.entity(e, m, 0, None)?;
        }
        Ok(())
    }

    pub(super) fn finish(self) -> (Imported, BTreeMap<String, usize>, Vec<DxfText>) {
        (self.out, self.counts, self.texts)
    }

    fn element(e: &Ent) -> String {
        if e.common.handle.is_empty() {
            format!("{} at {}", e.kind, e.common.at)
        } else {
            format!("{} #{}", e.kind, e.common.handle)
        }
    }

    fn skip(&mut self, e: &Ent, why: &str) {
        let kind = if why.is_empty() {
            e.kind.clone()
        } else {
            format!("{} ({why})", e.kind)
        };
        self.out.unsupported.add(&kind, Self::element(e));
    }

    fn push(&mut self, e: &Ent, ctx: (&str, Option<Color>), mut path: Path) {
        if path.segments.is_empty() {
            return;
        }
        // A polyline whose last vertex is its first (R12 writers do that instead of setting the
        // closed flag) is closed by close_and_chain, the one closure rule of every importer.
        let mut src = SourceRef::new(self.file, Self::element(e));
        src.line = e.common.line;
        path = path.with_source(src);
        if let Some(c) = ctx.1 {
            path.style = Style {
                stroke: Some(c),
                ..Style::default()
            };
        }
        self.out.drawing.push(ctx.0, path);
    }

    fn entity(
        &mut self,
        e: &'b Ent,
        m: Affine,
        depth: usize,
        inherit: Option<Inherit>,
    ) -> Result<(), ImportError> {
        if depth > 0 && e.kind == "ATTDEF" {
            // An attribute's definition: what an INSERT's ATTRIB fills in, not drawn itself.
            return Ok(());
        }
        self.expanded += 1;
        if self.expanded > MAX_EXPANDED {
            return Err(ImportError::new(
                self.file,
                Self::element(e),
                format!("the drawing expands to more than {MAX_EXPANDED} entities through its block inserts"),
            ));
        }
        // Layer "0" inside a block is the layer of the insert; colour 0 is the insert's colour,
        // 256 (by layer) the layer's.
        let own = if e.common.layer.is_empty() {
            "0"
        } else {
            e.common.layer.as_str()
        };
        let layer: String = match inherit {
            Some(i) if own == "0" => i.layer.to_string(),
            _ => own.to_string(),
        };
        let color = match e.common.color {
            0 => inherit.and_then(|i| i.color),
            c @ 1..=255 => aci(c),
            _ => self
                .layers
                .get(&layer.to_uppercase())
                .and_then(|c| aci(c.abs())),
        };
        let ctx = (layer.as_str(), color);
        if !matches!(e.geo, Geo::Insert(_) | Geo::Dimension(_)) {
            // A circle or an arc placed with unequal scales is an ellipse (as ezdxf counts it).
            let kind = match e.geo {
                Geo::Circle { .. } | Geo::Arc { .. } if !similar(m) => "ELLIPSE",
                _ => e.kind.as_str(),
            };
            *self.counts.entry(kind.to_string()).or_default() += 1;
        }
        match &e.geo {
            Geo::Line(a, b) => {
                if xy(*a).distance(xy(*b)) > 0.0 {
                    let p = Path::new(vec![Segment::line(xy(*a), xy(*b))], false);
                    self.push(e, ctx, p.transform(m));
                }
            }
            Geo::Point(p) => self.out.points.push(m * xy(*p)),
            Geo::Circle { c, r, n } => {
                if *r > 0.0 {
                    let p = Path::new(vec![Segment::Arc(Arc::circle(xy(*c), *r))], true);
                    self.push(e, ctx, p.transform(m * ocs(*n, c[2])));
                } else {
                    self.skip(e, "radius not positive");
                }
            }
            Geo::Arc { c, r, a0, a1, n } => {
                if *r > 0.0 {
                    let (a0, a1) = (a0.to_radians(), a1.to_radians());
                    let arc = Arc::new(xy(*c), *r, a0, ccw_sweep(a0, a1));
                    let p = Path::new(vec![Segment::Arc(arc)], false);
                    self.push(e, ctx, p.transform(m * ocs(*n, c[2])));
                } else {
                    self.skip(e, "radius not positive");
                }
            }
            Geo::Ellipse {
                c,
                major,
                ratio,
                t0,
                t1,
                n,
            } => {
                // In WCS: the minor axis is ratio · (N × major).
                let minor = cross(unit(*n).unwrap_or([0.0, 0.0, 1.0]), *major);
                let minor = Vec2::new(minor[0] * ratio, minor[1] * ratio);
                let path = ellipse_path(
                    xy(*c),
                    Vec2::new(major[0], major[1]),
                    minor,
                    *t0,
                    ccw_sweep(*t0, *t1),
                    m,
                );
                match path {
                    Some(p) => self.push(e, ctx, p),
                    None => self.skip(e, "zero axis, or seen edge-on"),
                }
            }
            Geo::LwPolyline { v, closed, elev, n } => {
                let v: Vec<(Point, f64)> =
                    v.iter().map(|p| (Point::new(p[0], p[1]), p[2])).collect();
                let p = Path::new(bulged(&v, *closed), *closed);
                self.push(e, ctx, p.transform(m * ocs(*n, *elev)));
            }
            Geo::Polyline { flags, v, elev, n } => {
                let closed = flags & 1 != 0;
                if flags & (16 | 64) != 0 {
                    self.skip(e, "mesh");
                } else if flags & 8 != 0 {
                    let pts: Vec<Point> = v.iter().map(|(p, _)| xy(*p)).collect();
                    let v: Vec<(Point, f64)> = pts.iter().map(|p| (*p, 0.0)).collect();
                    self.push(e, ctx, Path::new(bulged(&v, closed), closed).transform(m));
                } else {
                    let v: Vec<(Point, f64)> = v.iter().map(|(p, b)| (xy(*p), *b)).collect();
                    let p = Path::new(bulged(&v, closed), closed);
                    self.push(e, ctx, p.transform(m * ocs(*n, *elev)));
                }
            }
            Geo::Spline(s) => match self.spline(s, m) {
                Ok(p) => self.push(e, ctx, p),
                Err(why) => self.skip(e, &why),
            },
            Geo::Solid { p, n } => {
                let mut q = vec![xy(p[0]), xy(p[1]), xy(p[3]), xy(p[2])];
                if p[3] == p[2] {
                    q.remove(2);
                }
                self.push(
                    e,
                    ctx,
                    Path::polyline(&q, true).transform(m * ocs(*n, p[0][2])),
                );
            }
            Geo::Face(p) => {
                let mut q: Vec<Point> = p.iter().map(|c| xy(*c)).collect();
                if p[3] == p[2] {
                    q.pop();
                }
                self.push(e, ctx, Path::polyline(&q, true).transform(m));
            }
            Geo::Hatch {
                paths,
                elev,
                n,
                associative,
            } => {
                let o = m * ocs(*n, *elev);
                for hp in paths {
                    if *associative
                        && !hp.sources.is_empty()
                        && hp.sources.iter().all(|h| self.handles.contains(h.as_str()))
                    {
                        self.skip(e, "boundary drawn by its source entities");
                        continue;
                    }
                    match self.boundary(&hp.boundary, o) {
                        Ok(ps) => {
                            for p in ps {
                                self.push(e, ctx, p);
                            }
                        }
                        Err(why) => self.skip(e, &format!("boundary: {why}")),
                    }
                }
            }
            Geo::Text(t) => {
                if t.hidden {
                    self.skip(e, "invisible attribute");
                } else {
                    self.text(e, t, m, Vec2::ZERO, ctx);
                    if !self.draw_text {
                        self.skip(e, "text is not drawn");
                    }
                }
            }
            Geo::Unreadable(why) => self.skip(e, why),
            Geo::Other => self.skip(e, ""),
            Geo::Insert(ins) => self.insert(e, ins, m, depth, ctx)?,
            Geo::Dimension(name) => match self.blocks.get(&name.to_uppercase()) {
                Some(_) if depth >= MAX_DEPTH => {
                    return Err(ImportError::new(
                        self.file,
                        Self::element(e),
                        format!(
                            "blocks nested deeper than {MAX_DEPTH} (a block inserting itself?)"
                        ),
                    ))
                }
                Some(b) => {
                    let place = m * Affine::translate((-b.base[0], -b.base[1]));
                    let inh = Inherit {
                        layer: ctx.0,
                        color: ctx.1,
                    };
                    for be in &b.ents {
                        self.entity(be, place, depth + 1, Some(inh))?;
                    }
                }
                None => self.skip(e, "its block is missing"),
            },
        }
        Ok(())
    }

    /// A string placed in mm: `shift` moves it first (in its own coordinates). Kept in
    /// `texts`, and drawn when text is drawn.
    fn text(&mut self, e: &Ent, t: &TextData, m: Affine, shift: Vec2, ctx: (&str, Option<Color>)) {
        let layer = ctx.0;
        let place = if t.mtext { m } else { m * ocs(t.n, t.at[2]) };
        let mut at = Point::new(t.at[0], t.at[1]) + shift;
        let (dir, up) = (
            Vec2::from_angle(t.angle),
            Vec2::from_angle(t.angle + FRAC_PI_2),
        );
        let mut anchor = at;
        if t.mtext {
            // The insertion point is the top, middle or bottom of the block of lines (the
            // first baseline a height under its top, the last on its bottom).
            let lines = t.text.split('\n').count().max(1) as f64;
            let below_first = (lines - 1.0) * MTEXT_LINE_PITCH * t.height;
            at -= up
                * match t.row {
                    0 => t.height,
                    1 => (t.height - below_first) / 2.0,
                    _ => -below_first,
                };
            anchor = at;
        } else if let Some(a) = t.anchor {
            anchor = Point::new(a[0], a[1]) + shift - up * (t.rise * t.height);
        }
        let c = place.as_coeffs();
        let lin = |v: Vec2| Vec2::new(c[0] * v.x + c[2] * v.y, c[1] * v.x + c[3] * v.y);
        let d = lin(dir);
        let scale = (c[0] * c[3] - c[1] * c[2]).abs().sqrt();
        let mut source = SourceRef::new(self.file, Self::element(e));
        source.line = e.common.line;
        let placed = DxfText {
            text: t.text.clone(),
            at: place * at,
            anchor: place * anchor,
            justify: t.justify,
            height: t.height * scale,
            angle: d.y.atan2(d.x),
            layer: layer.to_string(),
            source,
        };
        if self.draw_text {
            self.draw_string(e, ctx, &placed);
        }
        self.texts.push(placed);
    }

    /// A placed string drawn with the single-stroke font as open strokes on its layer: the
    /// capitals as tall as the text's height (CAD's text height is the capital height), each
    /// line justified on the anchor with the font's own widths (left text starts at its
    /// point; centred and right text is centred on or ends at its alignment point, as the
    /// CAD program draws it with its font), MTEXT's lines 5/3 of a height apart (AutoCAD's
    /// line spacing at factor 1).
    fn draw_string(&mut self, e: &Ent, ctx: (&str, Option<Color>), t: &DxfText) {
        if !(t.height.is_finite() && t.height > 0.0) {
            self.skip(e, "text of no height");
            return;
        }
        let missing = text::missing_glyphs(&t.text);
        if !missing.is_empty() {
            let chars: String = missing.iter().take(8).collect();
            self.out.unsupported.add(
                &format!("{} (characters without a glyph, drawn as '?')", e.kind),
                format!("{} {chars:?}", Self::element(e)),
            );
        }
        let (dir, up) = (
            Vec2::from_angle(t.angle),
            Vec2::from_angle(t.angle + FRAC_PI_2),
        );
        for (row, line) in t.text.split('\n').enumerate() {
            let mut pen = t.anchor
                - up * (row as f64 * MTEXT_LINE_PITCH * t.height)
                - dir * (t.justify * text::text_width(line, t.height));
            for ch in line.chars() {
                for s in text::glyph_strokes(ch, pen, t.height, dir, up) {
                    // Already in mm: pushed as they are.
                    self.push(e, ctx, Path::polyline(&s, false));
                }
                pen += dir * (text::glyph_advance(ch) * t.height);
            }
        }
    }

    fn insert(
        &mut self,
        e: &'b Ent,
        ins: &InsertData,
        m: Affine,
        depth: usize,
        ctx: (&str, Option<Color>),
    ) -> Result<(), ImportError> {
        if depth >= MAX_DEPTH {
            return Err(ImportError::new(
                self.file,
                Self::element(e),
                format!("blocks nested deeper than {MAX_DEPTH} (a block inserting itself?)"),
            ));
        }
        let Some(block) = self.blocks.get(&ins.name.to_uppercase()) else {
            return Err(ImportError::new(
                self.file,
                Self::element(e),
                format!("block '{}' is not defined", ins.name),
            ));
        };
        let sx = if ins.scale[0] == 0.0 {
            1.0
        } else {
            ins.scale[0]
        };
        let sy = if ins.scale[1] == 0.0 {
            1.0
        } else {
            ins.scale[1]
        };
        let (cols, rows) = (ins.cols.max(1) as u64, ins.rows.max(1) as u64);
        if cols.saturating_mul(rows) > MAX_EXPANDED as u64 {
            return Err(ImportError::new(
                self.file,
                Self::element(e),
                format!("an array of {cols} × {rows} inserts"),
            ));
        }
        let inh = Inherit {
            layer: ctx.0,
            color: ctx.1,
        };
        for r in 0..rows {
            for c in 0..cols {
                let cell = Vec2::new(c as f64 * ins.col_step, r as f64 * ins.row_step);
                let place = m
                    * ocs(ins.normal, ins.at[2])
                    * Affine::translate((ins.at[0], ins.at[1]))
                    * Affine::rotate(ins.rotation.to_radians())
                    * Affine::translate(cell)
                    * Affine::scale_non_uniform(sx, sy)
                    * Affine::translate((-block.base[0], -block.base[1]));
                for be in &block.ents {
                    self.entity(be, place, depth + 1, Some(inh))?;
                }
                if !ins.attribs.is_empty() {
                    *self.counts.entry("ATTRIB".into()).or_default() += ins.attribs.len();
                    // Attributes are written where the first cell puts them; the others move
                    // by the cell's offset along the turned axes.
                    let shift = Affine::rotate(ins.rotation.to_radians()) * cell.to_point();
                    for a in &ins.attribs {
                        if a.hidden {
                            self.out
                                .unsupported
                                .add("ATTRIB (invisible attribute)", Self::element(e));
                        } else {
                            self.text(e, a, m, shift.to_vec2(), ctx);
                            if !self.draw_text {
                                self.out
                                    .unsupported
                                    .add("ATTRIB (text is not drawn)", Self::element(e));
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// A SPLINE (in the coordinates `m` maps to mm) as Béziers in mm.
    fn spline(&self, s: &SplineData, m: Affine) -> Result<Path, String> {
        let segs = spline_cubics(s, m)?;
        if segs.is_empty() {
            return Err("no curve".into());
        }
        let (a, b) = (segs[0].p0, segs[segs.len() - 1].p3);
        let closed = a.distance(b) <= 1e-9 * (1.0 + a.to_vec2().hypot());
        Ok(Path::new(
            segs.into_iter().map(Segment::Cubic).collect(),
            closed,
        ))
    }

    /// One HATCH boundary path as paths of the drawing (edges that do not meet start anew).
    fn boundary(&self, b: &Boundary, m: Affine) -> Result<Vec<Path>, String> {
        match b {
            Boundary::Poly(v, closed) => {
                let v: Vec<(Point, f64)> =
                    v.iter().map(|p| (Point::new(p[0], p[1]), p[2])).collect();
                let segs = bulged(&v, *closed);
                Ok(vec![Path::new(segs, *closed).transform(m)])
            }
            Boundary::Edges(edges) => {
                let mut pieces: Vec<Vec<Segment>> = Vec::new();
                for edge in edges {
                    let segs: Vec<Segment> = match edge {
                        Edge::Line(a, b) => {
                            vec![Segment::line(
                                m * Point::new(a[0], a[1]),
                                m * Point::new(b[0], b[1]),
                            )]
                        }
                        Edge::Arc(c, r, s, t, ccw) => {
                            if !(*r > 0.0) {
                                continue;
                            }
                            let (s, t) = (s.to_radians(), t.to_radians());
                            // Clockwise arcs are stored with their angles mirrored (360° − a).
                            let arc = if *ccw {
                                Arc::new(Point::new(c[0], c[1]), *r, s, ccw_sweep(s, t))
                            } else {
                                Arc::new(Point::new(c[0], c[1]), *r, -s, -ccw_sweep(s, t))
                            };
                            Path::new(vec![Segment::Arc(arc)], false)
                                .transform(m)
                                .segments
                        }
                        Edge::Ellipse(c, a, ratio, s, t, ccw) => {
                            let (s, t) = (s.to_radians(), t.to_radians());
                            let major = Vec2::new(a[0], a[1]);
                            let minor = Vec2::new(-a[1], a[0]) * *ratio;
                            let (t0, sw) = if *ccw {
                                (s, ccw_sweep(s, t))
                            } else {
                                (-s, -ccw_sweep(s, t))
                            };
                            match ellipse_path(Point::new(c[0], c[1]), major, minor, t0, sw, m) {
                                Some(p) => p.segments,
                                None => continue,
                            }
                        }
                        Edge::Spline(s) => spline_cubics(s, m)?
                            .into_iter()
                            .map(Segment::Cubic)
                            .collect(),
                    };
                    if segs.is_empty() {
                        continue;
                    }
                    // Edges chain end to start; one written the other way round (as some
                    // writers do with clockwise arcs) is turned, as ezdxf does.
                    let meets =
                        |a: Point, b: Point| a.distance(b) <= 1e-6 * (1.0 + a.to_vec2().hypot());
                    let end = pieces.last().and_then(|l| l.last()).map(|l| l.end());
                    match end {
                        Some(e) if meets(e, segs[0].start()) => {
                            if let Some(l) = pieces.last_mut() {
                                l.extend(segs)
                            }
                        }
                        Some(e) if meets(e, segs[segs.len() - 1].end()) => {
                            let turned = segs.iter().rev().map(|s| s.reversed());
                            if let Some(l) = pieces.last_mut() {
                                l.extend(turned)
                            }
                        }
                        _ => pieces.push(segs),
                    }
                }
                Ok(pieces
                    .into_iter()
                    .map(|segs| {
                        let (a, b) = (segs[0].start(), segs[segs.len() - 1].end());
                        let closed = a.distance(b) <= 1e-6 * (1.0 + a.to_vec2().hypot());
                        Path::new(segs, closed)
                    })
                    .collect())
            }
        }
    }
}

/// Control points or fit points of a spline, mapped by `m`, as Béziers.
fn spline_cubics(s: &SplineData, m: Affine) -> Result<Vec<CubicBez>, String> {
    if !s.ctrl.is_empty() {
        let ctrl: Vec<Point> = s.ctrl.iter().map(|p| m * xy(*p)).collect();
        let weights: &[f64] = if s.weights.len() == ctrl.len() {
            &s.weights
        } else {
            &[]
        };
        let degree = usize::try_from(s.degree).map_err(|_| format!("degree {}", s.degree))?;
        return Nurbs {
            degree,
            ctrl: &ctrl,
            weights,
            knots: &s.knots,
        }
        .to_cubics(SPLINE_TOL_MM);
    }
    if s.fit.len() >= 2 {
        let fit: Vec<Point> = s.fit.iter().map(|p| m * xy(*p)).collect();
        let lin = |v: P3| {
            let c = m.as_coeffs();
            Vec2::new(c[0] * v[0] + c[2] * v[1], c[1] * v[0] + c[3] * v[1])
        };
        let tangents = s.tangents.map(|(a, b)| (lin(a), lin(b)));
        return Ok(through_fit_points(&fit, tangents));
    }
    Err("neither control points nor fit points".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ocs_of_minus_z_mirrors_x_and_tilted_planes_keep_lengths_in_plane() {
        let m = ocs([0.0, 0.0, -1.0], 5.0);
        assert!((m * Point::new(2.0, 3.0)).distance(Point::new(-2.0, 3.0)) < 1e-12);
        // A normal in the XZ plane tilted 60° from Z: OCS x stays in XY (Ax = Z × N),
        // OCS y is foreshortened by cos 60°.
        let a = 60f64.to_radians();
        let m = ocs([a.sin(), 0.0, a.cos()], 0.0);
        let x = m * Point::new(1.0, 0.0);
        let y = m * Point::new(0.0, 1.0);
        assert!((x.to_vec2().hypot() - 1.0).abs() < 1e-12, "{x:?}");
        assert!((y.to_vec2().hypot() - a.cos()).abs() < 1e-12, "{y:?}");
    }

    #[test]
    fn bulge_one_is_a_half_circle() {
        let s = bulged(
            &[(Point::new(0.0, 0.0), 1.0), (Point::new(10.0, 0.0), 0.0)],
            false,
        );
        assert_eq!(s.len(), 1);
        assert!((s[0].length() - 5.0 * std::f64::consts::PI).abs() < 1e-9);
    }
}
