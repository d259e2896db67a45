//! Entities from their group codes: what each kind's codes mean, kept as plain numbers
//! (drawing units, the entity's own coordinate system) for `draw` to place.

use super::tokens::Tag;

pub(super) type P3 = [f64; 3];

/// What every entity has.
#[derive(Clone, Debug, Default)]
pub(super) struct Common {
    pub(super) handle: String,
    pub(super) layer: String,
    /// ACI colour: 0 by block, 256 (or absent) by layer.
    pub(super) color: i64,
    pub(super) paper: bool,
    /// Where the entity starts ("line 12").
    pub(super) at: String,
    /// Its line, in an ASCII file.
    pub(super) line: Option<usize>,
}

/// One edge of a HATCH boundary path, in the hatch's coordinate system.
#[derive(Clone, Debug)]
pub(super) enum Edge {
    Line([f64; 2], [f64; 2]),
    /// Centre, radius, start and end angle (degrees), counter-clockwise.
    Arc([f64; 2], f64, f64, f64, bool),
    /// Centre, major axis end (relative), ratio, start and end parameter (degrees), ccw.
    Ellipse([f64; 2], [f64; 2], f64, f64, f64, bool),
    Spline(SplineData),
}

#[derive(Clone, Debug)]
pub(super) enum Boundary {
    /// Vertices (x, y, bulge), closed.
    Poly(Vec<[f64; 3]>, bool),
    Edges(Vec<Edge>),
}

#[derive(Clone, Debug)]
pub(super) struct HatchPath {
    pub(super) boundary: Boundary,
    /// Handles of the entities this boundary was made from (associative hatches).
    pub(super) sources: Vec<String>,
}

#[derive(Clone, Debug, Default)]
pub(super) struct SplineData {
    pub(super) degree: i64,
    pub(super) knots: Vec<f64>,
    pub(super) ctrl: Vec<P3>,
    pub(super) weights: Vec<f64>,
    pub(super) fit: Vec<P3>,
    pub(super) tangents: Option<(P3, P3)>,
}

#[derive(Clone, Debug)]
pub(super) struct InsertData {
    pub(super) name: String,
    pub(super) at: P3,
    pub(super) scale: P3,
    pub(super) rotation: f64,
    pub(super) cols: i64,
    pub(super) rows: i64,
    pub(super) col_step: f64,
    pub(super) row_step: f64,
    pub(super) normal: P3,
    /// ATTRIBs that follow it (text, not drawn).
    pub(super) attribs: Vec<TextData>,
}

/// A string with where and how large it is written.
#[derive(Clone, Debug)]
pub(super) struct TextData {
    pub(super) text: String,
    /// Start of the first baseline (TEXT, ATTRIB: in the OCS; MTEXT: in WCS, its insertion
    /// point).
    pub(super) at: P3,
    pub(super) height: f64,
    /// Direction of the baseline, radians (in the OCS for TEXT).
    pub(super) angle: f64,
    pub(super) n: P3,
    /// MTEXT: WCS, and the insertion point is where its attachment says.
    pub(super) mtext: bool,
    /// Justification: the fraction of each line's width left of the anchor (0 left,
    /// ½ centre, 1 right), and the anchor's height above the first baseline in text heights
    /// (0 baseline, −⅓ bottom of the descenders, ½ middle, 1 top). MTEXT's middle and bottom
    /// rows are counted from its last line in `draw`.
    pub(super) justify: f64,
    pub(super) rise: f64,
    /// MTEXT's attachment row: 0 top, 1 middle, 2 bottom.
    pub(super) row: u8,
    /// The point TEXT and ATTRIB are justified on (group 11, OCS) when not left on the
    /// baseline; the writer's group 10 assumed its own font's widths.
    pub(super) anchor: Option<P3>,
    /// An invisible attribute (flag 1).
    pub(super) hidden: bool,
}

#[derive(Clone, Debug)]
pub(super) enum Geo {
    Line(P3, P3),
    Point(P3),
    Circle {
        c: P3,
        r: f64,
        n: P3,
    },
    Arc {
        c: P3,
        r: f64,
        a0: f64,
        a1: f64,
        n: P3,
    },
    Ellipse {
        c: P3,
        major: P3,
        ratio: f64,
        t0: f64,
        t1: f64,
        n: P3,
    },
    /// Vertices (x, y, bulge) in the OCS at elevation `elev`.
    LwPolyline {
        v: Vec<[f64; 3]>,
        closed: bool,
        elev: f64,
        n: P3,
    },
    /// POLYLINE with its VERTEX entities: flags 1 closed, 8 3-D, 16/64 meshes.
    Polyline {
        flags: i64,
        v: Vec<(P3, f64)>,
        elev: f64,
        n: P3,
    },
    Spline(SplineData),
    Insert(InsertData),
    /// DIMENSION: its anonymous block, drawn as it is (in WCS).
    Dimension(String),
    Hatch {
        paths: Vec<HatchPath>,
        elev: f64,
        n: P3,
        associative: bool,
    },
    /// SOLID / TRACE corners in the OCS (drawn 1-2-4-3).
    Solid {
        p: [P3; 4],
        n: P3,
    },
    /// 3DFACE corners in WCS (drawn 1-2-3-4).
    Face([P3; 4]),
    /// TEXT, MTEXT, ATTRIB, ATTDEF: not drawn (no font), their strings kept.
    Text(TextData),
    /// Anything else (kept for the count of what was skipped).
    Other,
    /// A kind that is read, whose structure is broken (e.g. a HATCH boundary cut short).
    Unreadable(String),
}

#[derive(Clone, Debug)]
pub(super) struct Ent {
    pub(super) kind: String,
    pub(super) common: Common,
    pub(super) geo: Geo,
}

/// The tags of one entity with typed look-ups.
pub(super) struct Tags<'t, 'a>(pub &'t [Tag<'a>]);

impl<'a> Tags<'_, 'a> {
    fn first(&self, code: i32) -> Option<&Tag<'a>> {
        self.0.iter().find(|t| t.code == code)
    }
    pub(super) fn f(&self, code: i32, default: f64) -> Result<f64, String> {
        self.first(code).map_or(Ok(default), |t| t.f())
    }
    pub(super) fn i(&self, code: i32, default: i64) -> Result<i64, String> {
        self.first(code).map_or(Ok(default), |t| t.i())
    }
    pub(super) fn s(&self, code: i32) -> String {
        self.first(code)
            .map(|t| t.word().into_owned())
            .unwrap_or_default()
    }
    pub(super) fn p3(&self, code: i32) -> Result<P3, String> {
        Ok([
            self.f(code, 0.0)?,
            self.f(code + 10, 0.0)?,
            self.f(code + 20, 0.0)?,
        ])
    }
    fn normal(&self) -> Result<P3, String> {
        Ok([self.f(210, 0.0)?, self.f(220, 0.0)?, self.f(230, 1.0)?])
    }
}

/// Points of repeated x/y/z codes (`code`, `code`+10, `code`+20), in file order: each x
/// starts a point.
fn points(tags: &[Tag], code: i32) -> Result<Vec<P3>, String> {
    let mut v: Vec<P3> = Vec::new();
    for t in tags {
        if t.code == code {
            v.push([t.f()?, 0.0, 0.0]);
        } else if let Some(last) = v.last_mut() {
            if t.code == code + 10 {
                last[1] = t.f()?;
            } else if t.code == code + 20 {
                last[2] = t.f()?;
            }
        }
    }
    Ok(v)
}

fn all_f(tags: &[Tag], code: i32) -> Result<Vec<f64>, String> {
    tags.iter()
        .filter(|t| t.code == code)
        .map(|t| t.f())
        .collect()
}

pub(super) fn common(tags: &[Tag], at: String) -> Result<Common, String> {
    let t = Tags(tags);
    Ok(Common {
        line: at.strip_prefix("line ").and_then(|n| n.parse().ok()),
        handle: t.s(5),
        layer: t.s(8),
        color: t.i(62, 256)?,
        paper: t.i(67, 0)? == 1,
        at,
    })
}

/// Reads one entity (for POLYLINE, `vertices` are its VERTEX entities' tags).
pub(super) fn parse(
    kind: &str,
    tags: &[Tag],
    vertices: &[Vec<Tag>],
    at: String,
) -> Result<Ent, String> {
    let t = Tags(tags);
    let common = common(tags, at)?;
    let geo = match kind {
        "LINE" => Geo::Line(t.p3(10)?, t.p3(11)?),
        "POINT" => Geo::Point(t.p3(10)?),
        "CIRCLE" => Geo::Circle {
            c: t.p3(10)?,
            r: t.f(40, 0.0)?,
            n: t.normal()?,
        },
        "ARC" => Geo::Arc {
            c: t.p3(10)?,
            r: t.f(40, 0.0)?,
            a0: t.f(50, 0.0)?,
            a1: t.f(51, 360.0)?,
            n: t.normal()?,
        },
        "ELLIPSE" => Geo::Ellipse {
            c: t.p3(10)?,
            major: t.p3(11)?,
            ratio: t.f(40, 1.0)?,
            t0: t.f(41, 0.0)?,
            t1: t.f(42, std::f64::consts::TAU)?,
            n: t.normal()?,
        },
        "LWPOLYLINE" => {
            let mut v: Vec<[f64; 3]> = Vec::new();
            for g in tags {
                match g.code {
                    10 => v.push([g.f()?, 0.0, 0.0]),
                    20 => {
                        if let Some(l) = v.last_mut() {
                            l[1] = g.f()?
                        }
                    }
                    42 => {
                        if let Some(l) = v.last_mut() {
                            l[2] = g.f()?
                        }
                    }
                    _ => {}
                }
            }
            Geo::LwPolyline {
                v,
                closed: t.i(70, 0)? & 1 != 0,
                elev: t.f(38, 0.0)?,
                n: t.normal()?,
            }
        }
        "POLYLINE" => {
            let mut v = Vec::with_capacity(vertices.len());
            for vt in vertices {
                let vt = Tags(vt);
                // Spline frame control points (flag 16) are not part of the drawn line.
                if vt.i(70, 0)? & 16 != 0 {
                    continue;
                }
                v.push((vt.p3(10)?, vt.f(42, 0.0)?));
            }
            Geo::Polyline {
                flags: t.i(70, 0)?,
                v,
                elev: t.f(30, 0.0)?,
                n: t.normal()?,
            }
        }
        "SPLINE" => Geo::Spline(spline(tags)?),
        "INSERT" => Geo::Insert(InsertData {
            name: t.s(2),
            at: t.p3(10)?,
            scale: [t.f(41, 1.0)?, t.f(42, 1.0)?, t.f(43, 1.0)?],
            rotation: t.f(50, 0.0)?,
            cols: t.i(70, 1)?,
            rows: t.i(71, 1)?,
            col_step: t.f(44, 0.0)?,
            row_step: t.f(45, 0.0)?,
            normal: t.normal()?,
            attribs: vertices
                .iter()
                .map(|a| text("ATTRIB", a))
                .collect::<Result<_, _>>()?,
        }),
        "DIMENSION" | "ARC_DIMENSION" | "LARGE_RADIAL_DIMENSION" => Geo::Dimension(t.s(2)),
        "HATCH" => {
            let p = t.p3(10)?;
            // A boundary that does not follow the structure is skipped with its place; a
            // value that is not a number stays an error.
            let paths = match hatch_paths(tags) {
                Ok(p) => p,
                Err(m) if !m.contains("not a number") => {
                    return Ok(Ent {
                        kind: kind.to_string(),
                        common,
                        geo: Geo::Unreadable(m),
                    })
                }
                Err(m) => return Err(m),
            };
            Geo::Hatch {
                paths,
                elev: p[2],
                n: t.normal()?,
                associative: t.i(71, 0)? != 0,
            }
        }
        "SOLID" | "TRACE" => Geo::Solid {
            p: [t.p3(10)?, t.p3(11)?, t.p3(12)?, t.p3(13)?],
            n: t.normal()?,
        },
        "3DFACE" => Geo::Face([t.p3(10)?, t.p3(11)?, t.p3(12)?, t.p3(13)?]),
        "TEXT" | "MTEXT" | "ATTRIB" | "ATTDEF" => Geo::Text(text(kind, tags)?),
        _ => Geo::Other,
    };
    Ok(Ent {
        kind: kind.to_string(),
        common,
        geo,
    })
}

fn spline(tags: &[Tag]) -> Result<SplineData, String> {
    let t = Tags(tags);
    let tangent = |code: i32| -> Result<Option<P3>, String> {
        Ok(if t.first(code).is_some() {
            Some(t.p3(code)?)
        } else {
            None
        })
    };
    Ok(SplineData {
        degree: t.i(71, 3)?,
        knots: all_f(tags, 40)?,
        ctrl: points(tags, 10)?,
        weights: all_f(tags, 41)?,
        fit: points(tags, 11)?,
        tangents: tangent(12)?.zip(tangent(13)?),
    })
}

/// A cursor over a HATCH's tags: its boundary paths are a sequence, not a set of codes.
struct Cursor<'t, 'a> {
    tags: &'t [Tag<'a>],
    i: usize,
}

impl<'a> Cursor<'_, 'a> {
    fn peek(&self) -> Option<&Tag<'a>> {
        self.tags.get(self.i)
    }
    fn peek_code(&self, ahead: usize) -> Option<i32> {
        self.tags.get(self.i + ahead).map(|t| t.code)
    }
    fn want(&mut self, code: i32) -> Result<&Tag<'a>, String> {
        match self.tags.get(self.i) {
            Some(t) if t.code == code => {
                self.i += 1;
                Ok(t)
            }
            Some(t) => Err(format!(
                "{}: HATCH boundary: group {code} expected, {} found",
                t.place(),
                t.code
            )),
            None => Err(format!(
                "HATCH boundary: group {code} expected, the entity ends"
            )),
        }
    }
    fn f(&mut self, code: i32) -> Result<f64, String> {
        self.want(code)?.f()
    }
    fn i(&mut self, code: i32) -> Result<i64, String> {
        self.want(code)?.i()
    }
    fn xy(&mut self, code: i32) -> Result<[f64; 2], String> {
        Ok([self.f(code)?, self.f(code + 10)?])
    }
    fn opt(&mut self, code: i32) -> Option<&Tag<'a>> {
        if self.peek().is_some_and(|t| t.code == code) {
            self.i += 1;
            self.tags.get(self.i - 1)
        } else {
            None
        }
    }
}

/// A count read from the file, bounded by the tags left (each item takes at least one), so a
/// huge count is an error, not an allocation.
fn count(c: &mut Cursor, code: i32) -> Result<usize, String> {
    let t = *c.want(code)?;
    let n = t.i()?;
    let left = c.tags.len() - c.i;
    if n < 0 || n as u64 > left as u64 {
        return Err(format!(
            "{}: HATCH boundary: count {n} but {left} groups follow",
            t.place()
        ));
    }
    Ok(n as usize)
}

fn hatch_paths(tags: &[Tag]) -> Result<Vec<HatchPath>, String> {
    let Some(start) = tags.iter().position(|t| t.code == 91) else {
        return Ok(Vec::new());
    };
    let mut c = Cursor { tags, i: start };
    let n = count(&mut c, 91)?;
    let mut paths = Vec::new();
    for _ in 0..n {
        let flags = c.i(92)?;
        let boundary = if flags & 2 != 0 {
            let bulges = c.i(72)? != 0;
            let closed = c.i(73)? != 0;
            let nv = count(&mut c, 93)?;
            let mut v = Vec::new();
            for _ in 0..nv {
                let [x, y] = c.xy(10)?;
                let b = if bulges {
                    c.opt(42).map(|t| t.f()).transpose()?.unwrap_or(0.0)
                } else {
                    0.0
                };
                v.push([x, y, b]);
            }
            Boundary::Poly(v, closed)
        } else {
            let ne = count(&mut c, 93)?;
            let mut edges = Vec::new();
            for k in 0..ne {
                let last = k + 1 == ne;
                let kind = c.i(72)?;
                edges.push(match kind {
                    1 => Edge::Line(c.xy(10)?, c.xy(11)?),
                    2 => Edge::Arc(c.xy(10)?, c.f(40)?, c.f(50)?, c.f(51)?, c.i(73)? != 0),
                    3 => Edge::Ellipse(
                        c.xy(10)?,
                        c.xy(11)?,
                        c.f(40)?,
                        c.f(50)?,
                        c.f(51)?,
                        c.i(73)? != 0,
                    ),
                    4 => Edge::Spline(spline_edge(&mut c, last)?),
                    other => {
                        return Err(format!(
                            "{}: HATCH boundary: edge type {other} (1 to 4 exist)",
                            c.peek().map(|t| t.place()).unwrap_or_default()
                        ))
                    }
                });
            }
            Boundary::Edges(edges)
        };
        let mut sources = Vec::new();
        if c.peek_code(0) == Some(97) {
            let ns = count(&mut c, 97)?;
            for _ in 0..ns {
                match c.opt(330) {
                    Some(t) => sources.push(t.word().into_owned()),
                    None => break,
                }
            }
        }
        paths.push(HatchPath { boundary, sources });
    }
    Ok(paths)
}

fn spline_edge(c: &mut Cursor, last_edge: bool) -> Result<SplineData, String> {
    let degree = c.i(94)?;
    let rational = c.i(73)? != 0;
    let _periodic = c.i(74)?;
    let nk = count(c, 95)?;
    let nc = count(c, 96)?;
    let mut s = SplineData {
        degree,
        ..SplineData::default()
    };
    for _ in 0..nk {
        s.knots.push(c.f(40)?);
    }
    for _ in 0..nc {
        let [x, y] = c.xy(10)?;
        s.ctrl.push([x, y, 0.0]);
        if rational {
            if let Some(w) = c.opt(42) {
                s.weights.push(w.f()?);
            }
        }
    }
    // R2010+ adds fit points (97, then 11/21 each) and end tangents (12/22, 13/23). On the last
    // edge of a path, a 97 may instead be the count of source objects that follows the edges:
    // it is the fit count only if fit points or another 97 follow it.
    if c.peek_code(0) == Some(97) {
        let next = c.peek_code(1);
        if !last_edge || next == Some(11) || next == Some(97) {
            let nf = count(c, 97)?;
            for _ in 0..nf {
                let [x, y] = c.xy(11)?;
                s.fit.push([x, y, 0.0]);
            }
            if c.peek_code(0) == Some(12) {
                let a = c.xy(12)?;
                let b = if c.peek_code(0) == Some(13) {
                    c.xy(13)?
                } else {
                    a
                };
                s.tangents = Some(([a[0], a[1], 0.0], [b[0], b[1], 0.0]));
            }
        }
    }
    Ok(s)
}

fn text(kind: &str, tags: &[Tag]) -> Result<TextData, String> {
    let t = Tags(tags);
    let mtext = kind == "MTEXT";
    let raw: String = if mtext {
        // The string comes in chunks of 250: group 3 for all but the last, group 1 last.
        let mut s = String::new();
        for g in tags.iter().filter(|g| g.code == 3) {
            s.push_str(&g.text());
        }
        for g in tags.iter().filter(|g| g.code == 1) {
            s.push_str(&g.text());
        }
        s
    } else {
        t.s(1)
    };
    let angle = if mtext {
        // An x direction (11/21/31) overrides the rotation (group 50, radians in MTEXT).
        if tags.iter().any(|g| g.code == 11) {
            let d = t.p3(11)?;
            d[1].atan2(d[0])
        } else {
            t.f(50, 0.0)?
        }
    } else {
        t.f(50, 0.0)?.to_radians()
    };
    let (justify, rise, row, anchor) = if mtext {
        // Attachment 1–9: rows top, middle, bottom of left, centre, right.
        let a = t.i(71, 1)?.clamp(1, 9) - 1;
        ([0.0, 0.5, 1.0][(a % 3) as usize], 0.0, (a / 3) as u8, None)
    } else {
        // TEXT: 72 left, centre, right, aligned, middle, fit; vertical in 73 (ATTRIB and
        // ATTDEF: 74) baseline, bottom, middle, top. Aligned and fit stay on their start.
        let h = t.i(72, 0)?;
        let v = t.i(if kind == "TEXT" { 73 } else { 74 }, 0)?;
        let justify = match h {
            1 | 4 => 0.5,
            2 => 1.0,
            _ => 0.0,
        };
        let rise = match (h, v) {
            (4, 0) | (_, 2) => 0.5,
            (_, 1) => -1.0 / 3.0,
            (_, 3) => 1.0,
            _ => 0.0,
        };
        if !matches!(h, 3 | 5)
            && (justify != 0.0 || rise != 0.0)
            && tags.iter().any(|g| g.code == 11)
        {
            (justify, rise, 0, Some(t.p3(11)?))
        } else {
            (0.0, 0.0, 0, None)
        }
    };
    Ok(TextData {
        text: if mtext {
            plain_mtext(&raw)
        } else {
            plain_text(&raw)
        },
        at: t.p3(10)?,
        height: t.f(40, 1.0)?,
        angle,
        n: t.normal()?,
        mtext,
        justify,
        rise,
        row,
        anchor,
        hidden: matches!(kind, "ATTRIB" | "ATTDEF") && t.i(70, 0)? & 1 != 0,
    })
}

/// TEXT's control codes: %%d degree, %%p plus-minus, %%c diameter, %%u/%%o/%%k (underline,
/// overline, strike toggles) dropped.
pub(super) fn plain_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find("%%") {
        out.push_str(&rest[..i]);
        let code = rest[i + 2..].chars().next();
        match code.map(|c| c.to_ascii_lowercase()) {
            Some('d') => out.push('°'),
            Some('p') => out.push('±'),
            Some('c') => out.push('⌀'),
            Some('%') => out.push('%'),
            Some('u' | 'o' | 'k') => {}
            _ => {
                out.push_str("%%");
                rest = &rest[i + 2..];
                continue;
            }
        }
        rest = &rest[i + 2 + code.map_or(0, char::len_utf8)..];
    }
    out.push_str(rest);
    out
}

/// MTEXT's inline formatting removed: \P new line, \~ space, \\ \{ \} literal, braces
/// grouping, \X…; settings (font, height, width, colour, …) and \L \l \O \o \K \k toggles
/// dropped, \S stacked fractions as a/b.
pub(super) fn plain_mtext(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut it = s.chars().peekable();
    while let Some(c) = it.next() {
        match c {
            '{' | '}' => {}
            '\\' => match it.next() {
                Some('P') => out.push('\n'),
                Some('~') => out.push(' '),
                Some(c @ ('\\' | '{' | '}')) => out.push(c),
                Some('L' | 'l' | 'O' | 'o' | 'K' | 'k') | None => {}
                Some('S') => {
                    for c in it.by_ref() {
                        match c {
                            ';' => break,
                            '^' | '#' => out.push('/'),
                            c => out.push(c),
                        }
                    }
                }
                Some(_) => {
                    for c in it.by_ref() {
                        if c == ';' {
                            break;
                        }
                    }
                }
            },
            c => out.push(c),
        }
    }
    plain_text(&out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_codes_become_plain_strings() {
        assert_eq!(
            plain_text("%%c10 %%p0.1 45%%d %%uA%%u 5%%%"),
            "⌀10 ±0.1 45° A 5%"
        );
        assert_eq!(plain_text("100%% sure"), "100%% sure");
        assert_eq!(
            plain_mtext(r"{\fArial|b1;Oficina}\PA\~B \H2.5x;big\S1^2; \\x\{"),
            "Oficina\nA B big1/2 \\x{"
        );
    }
}
