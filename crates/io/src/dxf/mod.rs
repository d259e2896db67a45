//! DXF → `Drawing`, read as ezdxf reads it: ASCII (any release from AutoCAD 2 to 2018, with
//! or without a HEADER, trash after EOF ignored) and binary DXF; model space with every INSERT
//! exploded (nested, scaled, rotated, MINSERT arrays) and DIMENSION blocks drawn; LINE, ARC,
//! CIRCLE, ELLIPSE, LWPOLYLINE and POLYLINE (2-D with bulges, 3-D; centre lines, widths not
//! drawn), SPLINE (control points with knots and weights, or fit points), HATCH boundary
//! paths, SOLID, TRACE and 3DFACE outlines, POINT; entities in any plane (their OCS) projected
//! onto XY. Text (TEXT, MTEXT, visible ATTRIBs) is drawn with the single-stroke Hershey font
//! (`oficina_geom::text`) as open strokes on its layer, or, with [`DxfOptions::draw_text`]
//! off, counted in `Unsupported` as every other kind not read; either way its strings are
//! placed in [`DxfRead::texts`]. Units come from `$INSUNITS`, else `$MEASUREMENT` (0: inches), else mm;
//! a drawing larger than [`DxfOptions::max_size_mm`] is refused with a hint, as its units are
//! then almost surely wrong.
//!
//! The reader is its own: a group-code tokenizer (`tokens`) that keeps values as slices of the
//! file, entities read from their codes (`entity`), placed and converted (`draw`, with NURBS →
//! cubic Béziers in `spline`). Bounded: the file is at most `MAX_DRAWING_BYTES` (the loader's
//! cap), the tokenizer allocates nothing per pair, one entity holds at most `MAX_GROUPS`
//! groups and a file `MAX_ENTITIES` entities, counts in the file (hatch paths, edges, knots)
//! are checked against what follows them, and inserts expand to at most 10⁶ entities.

mod draw;
mod entity;
mod spline;
pub(crate) use spline::through_fit_points;
mod tokens;

use crate::import::{ImportError, Imported};
use entity::{Ent, P3};
use std::collections::{BTreeMap, HashMap};
use tokens::{Tag, Tokens};

/// Most groups one entity may have (a polyline of a million vertices has about three million):
/// the groups of the entity being read are held until it ends, 40 bytes each.
const MAX_GROUPS: usize = 8_000_000;
/// Most entities a file may hold (model space and blocks).
const MAX_ENTITIES: usize = 4_000_000;

/// How to read a DXF file.
#[derive(Clone, Debug, PartialEq)]
pub struct DxfOptions {
    /// Millimetres per drawing unit, overriding the header's units.
    pub mm_per_unit: Option<f64>,
    /// Largest width or height in mm accepted (beyond it the units are taken to be wrong).
    pub max_size_mm: f64,
    /// Draw TEXT, MTEXT and visible ATTRIBs with the single-stroke font as open strokes on
    /// their layer (default); off, they are counted as skipped. Either way they are placed
    /// in [`DxfRead::texts`].
    pub draw_text: bool,
}

impl Default for DxfOptions {
    fn default() -> Self {
        DxfOptions {
            mm_per_unit: None,
            max_size_mm: 10_000.0,
            draw_text: true,
        }
    }
}

/// A string of the drawing, placed: MTEXT formatting removed, TEXT's %% codes as characters.
#[derive(Clone, Debug, PartialEq)]
pub struct DxfText {
    /// The string; `\n` between lines.
    pub text: String,
    /// Start of the first baseline, mm: TEXT's first point (where the writer's font put
    /// it), MTEXT's insertion point moved to its first baseline by its attachment row.
    pub at: oficina_geom::Point,
    /// The point on the first baseline each line is justified on, mm: `at` for left text,
    /// TEXT's alignment point (group 11) moved to the baseline for centred, right, middle or
    /// top text.
    pub anchor: oficina_geom::Point,
    /// Fraction of each line's width left of `anchor`: 0 left, ½ centred, 1 right.
    pub justify: f64,
    /// Height of capitals, mm.
    pub height: f64,
    /// Direction of the baseline, radians counter-clockwise from +X.
    pub angle: f64,
    /// Layer it is on.
    pub layer: String,
    /// Entity and line.
    pub source: oficina_geom::SourceRef,
}

/// A DXF file read: the drawing and what was found in it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DxfRead {
    /// The drawing in mm, what was skipped, loose points.
    pub imported: Imported,
    /// Entities met in model space by kind, INSERTs and DIMENSIONs exploded (they are not
    /// counted themselves; what their blocks hold is).
    pub entities: BTreeMap<String, usize>,
    /// The strings of TEXT, MTEXT and visible ATTRIBs, placed in mm (drawn in the drawing
    /// too unless [`DxfOptions::draw_text`] is off).
    pub texts: Vec<DxfText>,
    /// Millimetres per drawing unit used.
    pub mm_per_unit: f64,
    /// Where the units came from, e.g. "inches ($INSUNITS 1)".
    pub units: String,
    /// `$ACADVER` (empty when the file has no header).
    pub version: String,
    /// The file was binary DXF.
    pub binary: bool,
}

/// Reads a DXF file's model space into a drawing, in mm, with the default options.
pub fn dxf_from_bytes(bytes: &[u8], file: &str) -> Result<Imported, ImportError> {
    read_dxf(bytes, file, &DxfOptions::default()).map(|r| r.imported)
}

/// Reads a DXF file's model space into a drawing, in mm, with what was found in it.
pub fn read_dxf(bytes: &[u8], file: &str, opts: &DxfOptions) -> Result<DxfRead, ImportError> {
    let f = structure(bytes, file)?;
    let (scale, units) = match opts.mm_per_unit {
        Some(s) if s.is_finite() && s > 0.0 => (s, format!("{s} mm per unit (given)")),
        Some(s) => {
            return Err(ImportError::new(
                file,
                "units",
                format!("{s} mm per unit: give a positive number"),
            ))
        }
        None => header_units(&f.header, file)?,
    };
    let mut d = draw::Drawer::new(file, &f.blocks, &f.layers, scale);
    d.draw_text = opts.draw_text;
    d.model(&f.model)?;
    let (mut imported, entities, texts) = d.finish();
    imported.set_units(units.clone(), scale);
    if let Some(b) = bounds(&imported) {
        let (w, h) = (b.width(), b.height());
        // (A bounding box hides NaN: min and max pass over it. Every coordinate is checked.)
        if !(w.is_finite() && h.is_finite() && finite(&imported)) {
            return Err(ImportError::new(
                file,
                "extents",
                "coordinates too large to draw (they overflow once in mm)",
            ));
        }
        if w.max(h) > opts.max_size_mm {
            return Err(ImportError::new(
                file,
                "units",
                format!(
                    "the drawing is {:.1} m × {:.1} m read in {units}: larger than {} m, so the \
                     units are probably not the ones it was drawn in. Save it with $INSUNITS set \
                     to its units (4 = mm, 1 = inch), or scale it in the CAD program",
                    w / 1000.0,
                    h / 1000.0,
                    opts.max_size_mm / 1000.0
                ),
            ));
        }
    }
    Ok(DxfRead {
        imported,
        entities,
        texts,
        mm_per_unit: scale,
        units,
        version: f.header.version,
        binary: f.binary,
    })
}

fn finite(i: &Imported) -> bool {
    use oficina_geom::Segment;
    let ok = |p: &oficina_geom::Point| p.x.is_finite() && p.y.is_finite();
    i.points.iter().all(ok)
        && i.drawing.paths().all(|p| {
            p.segments.iter().all(|s| match s {
                Segment::Line(l) => ok(&l.p0) && ok(&l.p1),
                Segment::Arc(a) => {
                    ok(&a.center)
                        && a.radius.is_finite()
                        && a.start_angle.is_finite()
                        && a.sweep.is_finite()
                }
                Segment::Cubic(c) => [c.p0, c.p1, c.p2, c.p3].iter().all(ok),
            })
        })
}

fn bounds(i: &Imported) -> Option<oficina_geom::kurbo::Rect> {
    let mut b = i.drawing.bounding_box();
    for p in &i.points {
        let r = oficina_geom::kurbo::Rect::from_points(*p, *p);
        b = Some(b.map_or(r, |b| b.union(r)));
    }
    b
}

/// Millimetres per unit of `$INSUNITS` codes 1–24 (0 is "unitless").
fn insunits_mm(code: i64) -> Option<(f64, &'static str)> {
    Some(match code {
        1 => (25.4, "inches"),
        2 => (304.8, "feet"),
        3 => (1_609_344.0, "miles"),
        4 => (1.0, "millimetres"),
        5 => (10.0, "centimetres"),
        6 => (1000.0, "metres"),
        7 => (1e6, "kilometres"),
        8 => (2.54e-5, "microinches"),
        9 => (0.0254, "mils"),
        10 => (914.4, "yards"),
        11 => (1e-7, "ångströms"),
        12 => (1e-6, "nanometres"),
        13 => (1e-3, "microns"),
        14 => (100.0, "decimetres"),
        15 => (1e4, "decametres"),
        16 => (1e5, "hectometres"),
        17 => (1e12, "gigametres"),
        18 => (1.495_978_707e14, "astronomical units"),
        19 => (9.460_730_472_580_8e18, "light years"),
        20 => (3.085_677_581_491_367e19, "parsecs"),
        21 => (304.800_609_6, "US survey feet"),
        22 => (25.400_050_8, "US survey inches"),
        23 => (914.401_828_8, "US survey yards"),
        24 => (1_609_347.218_694_4, "US survey miles"),
        _ => return None,
    })
}

fn header_units(h: &Header, file: &str) -> Result<(f64, String), ImportError> {
    match h.insunits {
        Some(0) | None => Ok(match h.measurement {
            Some(0) => (
                25.4,
                "inches ($INSUNITS unset, $MEASUREMENT 0: imperial)".into(),
            ),
            Some(_) => (
                1.0,
                "millimetres ($INSUNITS unset, $MEASUREMENT 1: metric)".into(),
            ),
            None => (1.0, "millimetres (no units in the header)".into()),
        }),
        Some(c) => match insunits_mm(c) {
            Some((s, name)) => Ok((s, format!("{name} ($INSUNITS {c})"))),
            None => Err(ImportError::new(
                file,
                "$INSUNITS",
                format!("units code {c} is not one of DXF's (0 to 24)"),
            )),
        },
    }
}

#[derive(Debug, Default)]
struct Header {
    insunits: Option<i64>,
    measurement: Option<i64>,
    version: String,
}

/// A block definition: base point and entities.
#[derive(Debug, Default)]
struct Block {
    base: P3,
    ents: Vec<Ent>,
}

struct FileData {
    header: Header,
    layers: HashMap<String, i64>,
    blocks: HashMap<String, Block>,
    model: Vec<Ent>,
    binary: bool,
}

/// A tokenizer or entity message "line 12: what" as an error naming the file and the line.
fn located(file: &str, msg: String) -> ImportError {
    match msg.split_once(": ") {
        Some((at, rest)) if at.starts_with("line ") || at.starts_with("byte ") => {
            ImportError::new(file, at, rest)
        }
        _ => ImportError::new(file, "DXF", msg),
    }
}

/// An entity whose sub-entities follow it until SEQEND: POLYLINE (VERTEX) and INSERT with
/// attributes (ATTRIB).
struct Pending<'a> {
    kind: String,
    tags: Vec<Tag<'a>>,
    at: String,
    subs: Vec<Vec<Tag<'a>>>,
}

struct Sections<'a> {
    file: &'a str,
    data: FileData,
    section: Option<String>,
    block: Option<(String, Block)>,
    pending: Option<Pending<'a>>,
    stored: usize,
}

impl<'a> Sections<'a> {
    fn store(&mut self, e: Ent) -> Result<(), ImportError> {
        self.stored += 1;
        if self.stored > MAX_ENTITIES {
            return Err(ImportError::new(
                self.file,
                e.common.at,
                format!("more than {MAX_ENTITIES} entities: too many to read"),
            ));
        }
        match (&mut self.block, self.section.as_deref()) {
            (Some((_, b)), _) => b.ents.push(e),
            (None, Some("ENTITIES") | None) => self.data.model.push(e),
            _ => {}
        }
        Ok(())
    }

    fn entity(
        &mut self,
        kind: &str,
        tags: &[Tag<'a>],
        subs: &[Vec<Tag<'a>>],
        at: String,
    ) -> Result<(), ImportError> {
        let e = entity::parse(kind, tags, subs, at).map_err(|m| located(self.file, m))?;
        self.store(e)
    }

    fn flush_pending(&mut self) -> Result<(), ImportError> {
        if let Some(p) = self.pending.take() {
            self.entity(&p.kind, &p.tags, &p.subs, p.at)?;
        }
        Ok(())
    }

    /// One record: a group-code 0 and the groups up to the next.
    fn record(&mut self, kind: &str, tags: Vec<Tag<'a>>, at: String) -> Result<(), ImportError> {
        let t = entity::Tags(&tags);
        if let Some(p) = &mut self.pending {
            let belongs = match p.kind.as_str() {
                "POLYLINE" => kind == "VERTEX",
                _ => kind == "ATTRIB",
            };
            if belongs {
                if p.subs.len() >= MAX_GROUPS / 4 {
                    return Err(ImportError::new(
                        self.file,
                        p.at.clone(),
                        format!(
                            "a {} of more than {} parts: too large to read",
                            p.kind,
                            MAX_GROUPS / 4
                        ),
                    ));
                }
                p.subs.push(tags);
                return Ok(());
            }
            self.flush_pending()?;
            if kind == "SEQEND" {
                return Ok(());
            }
        }
        match kind {
            "SECTION" => {
                let name = t.s(2);
                if name == "HEADER" {
                    self.header(&tags).map_err(|m| located(self.file, m))?;
                }
                self.section = Some(name);
            }
            "ENDSEC" => {
                self.section = None;
                if let Some((name, b)) = self.block.take() {
                    self.data.blocks.insert(name, b);
                }
            }
            _ => match self.section.as_deref() {
                Some("TABLES") if kind == "LAYER" => {
                    let c = t.i(62, 7).map_err(|m| located(self.file, m))?;
                    self.data.layers.insert(t.s(2).to_uppercase(), c);
                }
                Some("BLOCKS") if kind == "BLOCK" => {
                    if let Some((name, b)) = self.block.take() {
                        self.data.blocks.insert(name, b);
                    }
                    let base = t.p3(10).map_err(|m| located(self.file, m))?;
                    self.block = Some((
                        t.s(2).to_uppercase(),
                        Block {
                            base,
                            ents: Vec::new(),
                        },
                    ));
                }
                Some("BLOCKS") if kind == "ENDBLK" => {
                    if let Some((name, b)) = self.block.take() {
                        self.data.blocks.insert(name, b);
                    }
                }
                Some("BLOCKS") | Some("ENTITIES") | None => {
                    let attribs =
                        kind == "INSERT" && t.i(66, 0).map_err(|m| located(self.file, m))? == 1;
                    if kind == "POLYLINE" || attribs {
                        self.pending = Some(Pending {
                            kind: kind.to_string(),
                            tags,
                            at,
                            subs: Vec::new(),
                        });
                    } else if kind != "SEQEND" && kind != "VERTEX" {
                        self.entity(kind, &tags, &[], at)?;
                    }
                }
                _ => {}
            },
        }
        Ok(())
    }

    fn header(&mut self, tags: &[Tag]) -> Result<(), String> {
        let mut var = String::new();
        for t in tags {
            if t.code == 9 {
                var = t.word().into_owned();
                continue;
            }
            match (var.as_str(), t.code) {
                ("$INSUNITS", 70) => self.data.header.insunits = Some(t.i()?),
                ("$MEASUREMENT", 70) => self.data.header.measurement = Some(t.i()?),
                ("$ACADVER", 1) => self.data.header.version = t.word().into_owned(),
                _ => {}
            }
        }
        Ok(())
    }
}

fn structure(bytes: &[u8], file: &str) -> Result<FileData, ImportError> {
    let mut toks = Tokens::new(bytes);
    let binary = toks.is_binary();
    let mut s = Sections {
        file,
        data: FileData {
            header: Header::default(),
            layers: HashMap::new(),
            blocks: HashMap::new(),
            model: Vec::new(),
            binary,
        },
        section: None,
        block: None,
        pending: None,
        stored: 0,
    };
    let mut current: Option<(String, String)> = None;
    let mut tags: Vec<Tag> = Vec::new();
    let mut any = false;
    loop {
        let next = match toks.next() {
            // 999: a comment, anywhere (CAD programs write their name before the first 0).
            Some(Ok(t)) if t.code == 999 => continue,
            Some(Ok(t)) => Some(t),
            Some(Err(m)) => return Err(located(file, m)),
            None => None,
        };
        any |= next.is_some();
        let starts = next.as_ref().is_none_or(|t| t.code == 0);
        if !starts {
            if let Some(t) = next {
                if current.is_none() {
                    return Err(ImportError::new(
                        file,
                        t.place(),
                        format!(
                            "group {} before any group 0: this is not a DXF file",
                            t.code
                        ),
                    ));
                }
                if tags.len() >= MAX_GROUPS {
                    let at = current.as_ref().map(|c| c.1.clone()).unwrap_or_default();
                    return Err(ImportError::new(
                        file,
                        at,
                        format!("one entity of more than {MAX_GROUPS} groups: too large to read"),
                    ));
                }
                tags.push(t);
            }
            continue;
        }
        if let Some((kind, at)) = current.take() {
            s.record(&kind, std::mem::take(&mut tags), at)?;
        }
        match next {
            Some(t) => {
                let kind = t.word().into_owned();
                if kind == "EOF" {
                    break;
                }
                current = Some((kind, t.place()));
            }
            None => break,
        }
    }
    if !any {
        return Err(ImportError::new(file, "file", "the file is empty"));
    }
    s.flush_pending()?;
    if let Some((name, b)) = s.block.take() {
        s.data.blocks.insert(name, b);
    }
    Ok(s.data)
}
