//! A milling job (`oficina mill --job job.toml`): one drawing, the stock, a tool library
//! and operations in order, each on the shapes it selects → one program with its tool
//! changes (grouped to save changes, never across a cut-out) or one program per tool, each
//! judged as `oficina mill` judges one operation. The format: `docs/cam-jobs.md`.

mod build;
mod model;
mod order;
mod select;

use crate::judge::{judge, Judged};
use crate::{Error, Feedback, PostParams};
use build::{build, Built, Frame};
use model::{line_of, parse_job, JobOp, JobShape, OpKind, Order, Origin, ToolRef};
use oficina_cam::ops::preview_svg;
use oficina_cam::{Library, Tool, ToolFeeds, Toolpath};
use oficina_geom::{Arc, Path, Point, Segment};
use oficina_sim::Design;
use select::{number_shapes, select, Shape};
use std::path::Path as FsPath;

/// Feeds when neither the job nor the library gives them (`oficina mill`'s defaults).
const DEFAULT_FEED: f64 = 800.0;
/// Spindle speed when neither gives it, rev/min.
const DEFAULT_RPM: f64 = 12000.0;

/// How the job's programs are written.
#[derive(Clone, Debug, Default)]
pub struct JobOptions {
    /// Post-processor and format.
    pub post: PostParams,
    /// One program per tool instead of one with tool changes.
    pub per_tool: bool,
}

/// One operation as it will run.
#[derive(Clone, Debug)]
pub struct JobOpReport {
    /// Its number in the job file (from 1).
    pub index: usize,
    /// Its name in the program's comments.
    pub name: String,
    /// Tool number.
    pub tool_number: u32,
    /// Tool spec.
    pub tool: String,
    /// Ids of its shapes.
    pub shapes: Vec<usize>,
    /// Moves.
    pub moves: usize,
    /// Depth, mm.
    pub depth: f64,
    /// Feed, mm/min, spindle rpm, and where they came from.
    pub feeds: ToolFeeds,
    /// The tool centre's feed moves, polylines of X, Y, Z (for drawing the toolpath).
    pub path: Vec<Vec<[f64; 3]>>,
}

/// One program of the job.
pub struct JobProgram {
    /// The tool, when written one file per tool.
    pub tool: Option<u32>,
    /// The program and what it was judged to be.
    pub judged: Judged,
}

/// What a job made.
pub struct JobResult {
    /// Things the user should know (drawing content left out, checks not made).
    pub warnings: Vec<String>,
    /// The import summary.
    pub imported: Vec<String>,
    /// Every shape with its id, as selections name them.
    pub shapes: Vec<String>,
    /// The operations in cutting order.
    pub ops: Vec<JobOpReport>,
    /// Tool loads in the cutting order (the first counts).
    pub tool_loads: usize,
    /// The programs: one, or one per tool.
    pub programs: Vec<JobProgram>,
    /// SVG preview of every toolpath over the drawing.
    pub preview_svg: String,
    /// The stock in program coordinates.
    pub stock: JobStock,
}

/// The job's stock where the program sees it.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct JobStock {
    /// Lower-left X, Y in program coordinates, mm (top at Z 0).
    pub corner: [f64; 2],
    /// Width and height, mm, when the job gives them.
    pub size: Option<[f64; 2]>,
    /// Thickness, mm.
    pub thickness: f64,
}

/// Most shapes the import report of `oficina mill` lists one by one.
const LISTED: usize = 50;

/// The import report's shape lines (`#3 HOLES #000000 closed circle Ø3.60 at …`): the ids
/// a job's selections name; beyond [`LISTED`] shapes a count of the rest.
pub(crate) fn shape_lines(drawing: &oficina_geom::Drawing) -> Vec<String> {
    let layers: Vec<(String, Path)> = drawing
        .layers
        .iter()
        .flat_map(|l| l.paths.iter().map(|p| (l.name.clone(), p.clone())))
        .collect();
    let n = layers.len();
    let mut lines: Vec<String> = number_shapes(layers, LISTED)
        .iter()
        .take(LISTED)
        .map(Shape::describe)
        .collect();
    if n > LISTED {
        lines.push(format!(
            "… and {} more (#{} to #{n})",
            n - LISTED,
            LISTED + 1
        ));
    }
    lines
}

/// A rectangle `[x0, y0, x1, y1]` with corners rounded to `r`, counter-clockwise.
fn rect_path(s: &JobShape) -> Result<Path, String> {
    let [x0, y0, x1, y1] = s.rect;
    let r = s.corner_radius;
    let (w, h) = (x1 - x0, y1 - y0);
    if !(s.rect.iter().all(|v| v.is_finite()) && w > 0.0 && h > 0.0) {
        return Err("rect = [x0, y0, x1, y1] needs x1 > x0 and y1 > y0".into());
    }
    if !(r.is_finite() && r >= 0.0 && 2.0 * r <= w.min(h)) {
        return Err(format!(
            "corner_radius = {r}: 0 up to half the shorter side"
        ));
    }
    if r == 0.0 {
        let pts = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)].map(|(x, y)| Point::new(x, y));
        return Ok(Path::polyline(&pts, true));
    }
    use std::f64::consts::FRAC_PI_2;
    let corners = [
        (x1 - r, y0 + r, -FRAC_PI_2),
        (x1 - r, y1 - r, 0.0),
        (x0 + r, y1 - r, FRAC_PI_2),
        (x0 + r, y0 + r, 2.0 * FRAC_PI_2),
    ];
    let mut segs = Vec::new();
    for (k, &(cx, cy, a0)) in corners.iter().enumerate() {
        let arc = Arc::new(Point::new(cx, cy), r, a0, FRAC_PI_2);
        let end = Segment::Arc(arc).end();
        segs.push(Segment::Arc(arc));
        let (nx, ny, na) = corners[(k + 1) % 4];
        let next = Point::new(nx + r * na.cos(), ny + r * na.sin());
        segs.push(Segment::line(end, next));
    }
    Ok(Path::new(segs, true))
}

/// A name safe inside a G-code comment.
fn comment_safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_alphanumeric() || " -_.:/#".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The tool of `op`: by library number or spec; the T number and the feeds.
fn resolve_tool(
    op: &JobOp,
    lib: Option<(&str, &Library)>,
    material: Option<&str>,
    next_free: &mut u32,
    specs: &mut Vec<(String, u32)>,
) -> Result<(u32, Tool, ToolFeeds), String> {
    let (number, tool, from_lib) = match &op.tool {
        ToolRef::Number(n) => {
            let Some((lib_name, lib)) = lib else {
                return Err(format!(
                    "tool = {n}: a tool number needs a library (library = \"tools.toml\"), or give a spec such as tool = \"flat:3\""
                ));
            };
            let t = lib.get(*n).ok_or_else(|| {
                let have: Vec<String> = lib.tools.iter().map(|t| t.number.to_string()).collect();
                format!(
                    "tool = {n}: not in the library {lib_name} (it has {})",
                    if have.is_empty() {
                        "no tools".into()
                    } else {
                        have.join(", ")
                    }
                )
            })?;
            (
                *n,
                t.tool().map_err(|e| format!("tool = {n}: {e}"))?,
                Some(t),
            )
        }
        ToolRef::Spec(s) => {
            let tool: Tool = s.parse().map_err(|e| format!("tool = {s:?}: {e}"))?;
            let number = match (op.tool_number, specs.iter().find(|(k, _)| k == s)) {
                (Some(n), _) => n,
                (None, Some(&(_, n))) => n,
                (None, None) => {
                    let n = *next_free;
                    *next_free += 1;
                    n
                }
            };
            specs.push((s.clone(), number));
            (number, tool, None)
        }
    };
    let base = from_lib.and_then(|t| t.feeds(material));
    let rpm = op
        .rpm
        .or(base.as_ref().map(|f| f.rpm))
        .unwrap_or(DEFAULT_RPM);
    let feeds = match (op.feed, base) {
        (Some(feed), _) => ToolFeeds {
            rpm,
            feed,
            plunge_feed: op.plunge_feed.unwrap_or(feed / 3.0),
            source: "the job's feed".into(),
        },
        (None, Some(f)) => ToolFeeds {
            rpm,
            plunge_feed: op.plunge_feed.unwrap_or(f.plunge_feed),
            ..f
        },
        (None, None) => ToolFeeds {
            rpm,
            feed: DEFAULT_FEED,
            plunge_feed: op.plunge_feed.unwrap_or(DEFAULT_FEED / 3.0),
            source: "default (no feed in the job or the library)".into(),
        },
    };
    for (what, v) in [("feed", feeds.feed), ("plunge_feed", feeds.plunge_feed)] {
        if !(v.is_finite() && v > 1e-3 && v <= 1e6) {
            return Err(format!("{what} = {v}: use 0.001 to 1000000 mm/min"));
        }
    }
    if !(feeds.rpm.is_finite() && (0.0..=1e6).contains(&feeds.rpm)) {
        return Err(format!("rpm = {}: use 0 to 1000000", feeds.rpm));
    }
    Ok((number, tool, feeds))
}

/// Runs the job in `job_file`; `profile` times each program.
pub fn mill_job(
    job_file: &FsPath,
    opts: &JobOptions,
    profile: &Result<oficina_motion::Profile, String>,
    fb: Feedback,
) -> Result<JobResult, Error> {
    mill_job_upto(job_file, opts, profile, None, fb)
}

/// The job stopped after the first `upto` operations of its cutting order (all when
/// `None`): the program as far as that operation, judged as the whole job is (the stock
/// after each operation, its gouge against those operations' designs).
pub fn mill_job_upto(
    job_file: &FsPath,
    opts: &JobOptions,
    profile: &Result<oficina_motion::Profile, String>,
    upto: Option<usize>,
    fb: Feedback,
) -> Result<JobResult, Error> {
    let name = job_file.display().to_string();
    fb.stage("reading the job")?;
    let text = std::fs::read_to_string(job_file).map_err(|e| Error(format!("{name}: {e}")))?;
    let job = parse_job(&name, &text)?;
    let base = job_file.parent().unwrap_or(FsPath::new("."));
    let mut warnings = Vec::new();
    let lib = match &job.library {
        Some(l) => {
            let path = base.join(l);
            let lib = Library::load(&path).map_err(|e| Error(format!("{name}: library: {e}")))?;
            Some((path.display().to_string(), lib))
        }
        None => None,
    };
    fb.stage("reading the drawing")?;
    let (drawing, imported, shapes, shift) = load_shapes(&name, &text, &job, base, &mut warnings)?;
    let clear_z = job.clear_z.unwrap_or(5.0);
    let safe_z = job.safe_z.unwrap_or(20.0);
    if !(clear_z > 0.0 && safe_z >= clear_z && safe_z.is_finite()) {
        return Err(Error(format!(
            "{name}: safe_z = {safe_z} must be at or above clear_z = {clear_z}, which must be above 0"
        )));
    }
    let frame = Frame {
        clear_z,
        thickness: job.stock.thickness,
    };
    let mut next_free = lib
        .as_ref()
        .and_then(|(_, l)| l.tools.iter().map(|t| t.number).max())
        .unwrap_or(0)
        .max(
            job.op
                .iter()
                .filter_map(|o| o.get_ref().tool_number)
                .max()
                .unwrap_or(0),
        )
        + 1;
    let mut specs = Vec::new();
    let mut built: Vec<(Built, JobOpReport, bool)> = Vec::new();
    for (k, spanned) in job.op.iter().enumerate() {
        let op = spanned.get_ref();
        let line = line_of(&text, spanned.span().start);
        let label = match &op.name {
            Some(n) => format!("op {} ({n})", k + 1),
            None => format!("op {}", k + 1),
        };
        let err = |e: String| Error(format!("{name}: line {line}: {label}: {e}"));
        fb.stage(&format!("{label}: {:?}", op.kind))?;
        let (number, tool, feeds) = resolve_tool(
            op,
            lib.as_ref().map(|(n, l)| (n.as_str(), l)),
            job.material.as_deref(),
            &mut next_free,
            &mut specs,
        )
        .map_err(err)?;
        let picked = select(&shapes, &op.select).map_err(err)?;
        if picked.is_empty() {
            return Err(err(format!(
                "select = {}: matches none of the {} shapes (listed with their ids in the import report)",
                describe_select(&op.select),
                shapes.len()
            )));
        }
        let op_name = comment_safe(&format!(
            "op {} {}",
            k + 1,
            op.name
                .clone()
                .unwrap_or_else(|| format!("{:?}", op.kind).to_lowercase())
        ));
        let b = build(&op_name, op, &picked, number, &tool, &feeds, &frame).map_err(err)?;
        let cut_out = op.kind == OpKind::ProfileOut && b.depth >= job.stock.thickness - 1e-9;
        let report = JobOpReport {
            index: k + 1,
            name: op_name,
            tool_number: number,
            tool: tool.spec(),
            shapes: picked.iter().map(|s| s.id).collect(),
            moves: b
                .operation
                .moves
                .iter()
                .filter(|m| m.end().is_some())
                .count(),
            depth: b.depth,
            feeds,
            path: feed_polylines(&b.operation),
        };
        built.push((b, report, cut_out));
    }
    // Two tools under one number would load the wrong cutter.
    for (a, ra, _) in &built {
        for (b, rb, _) in &built {
            if ra.tool_number == rb.tool_number && a.operation.tool != b.operation.tool {
                return Err(Error(format!(
                    "{name}: {} and {} use T{} for two different tools ({} and {}): give tool_number",
                    ra.name, rb.name, ra.tool_number, ra.tool, rb.tool
                )));
            }
        }
    }
    let keys: Vec<(u32, bool)> = built.iter().map(|(_, r, c)| (r.tool_number, *c)).collect();
    let order: Vec<usize> = match job.order {
        Order::ByTool => order::order_by_tool(&keys),
        Order::AsWritten => (0..keys.len()).collect(),
    };
    let order = match upto {
        Some(n) if n == 0 || n > order.len() => {
            return Err(Error(format!(
                "{name}: up to operation {n}: the job has operations 1 to {}",
                order.len()
            )))
        }
        Some(n) => order[..n].to_vec(),
        None => order,
    };
    let tool_loads = order::changes(&keys, &order);
    let checked = built.iter().all(|(b, _, _)| b.designs.is_some());
    if !checked {
        warnings.push(
            "a V-carving of open strokes is its own design: the stock was not checked".into(),
        );
    }
    // The programs: all operations, or each tool's.
    let groups: Vec<(Option<u32>, Vec<usize>)> = if opts.per_tool {
        let mut g: Vec<(Option<u32>, Vec<usize>)> = Vec::new();
        for &k in &order {
            let t = keys[k].0;
            match g.iter_mut().find(|(n, _)| *n == Some(t)) {
                Some((_, v)) => v.push(k),
                None => g.push((Some(t), vec![k])),
            }
        }
        g
    } else {
        vec![(None, order.clone())]
    };
    let all_paths: Vec<Path> = shapes.iter().map(|s| s.path.clone()).collect();
    let mut programs = Vec::new();
    let mut whole = Toolpath {
        safe_z,
        operations: vec![],
    };
    for (tool, ks) in &groups {
        let tp = Toolpath {
            safe_z,
            operations: ks.iter().map(|&k| built[k].0.operation.clone()).collect(),
        };
        whole.operations.extend(tp.operations.iter().cloned());
        let designs: Option<Vec<Design>> = checked.then(|| {
            ks.iter()
                .flat_map(|&k| built[k].0.designs.clone().unwrap_or_default())
                .collect()
        });
        let settings = vec![
            ("job".into(), name.clone()),
            ("drawing".into(), drawing.display().to_string()),
            (
                "operations".into(),
                ks.iter()
                    .map(|&k| built[k].1.name.clone())
                    .collect::<Vec<_>>()
                    .join(", "),
            ),
        ];
        let (post, format) = opts.post.options("Oficina 2.5D milling job", settings)?;
        let judged = judge(
            &tp,
            &post,
            &format,
            designs,
            job.check_pixel.unwrap_or(0.2),
            profile,
            fb,
        )?;
        programs.push(JobProgram {
            tool: *tool,
            judged,
        });
    }
    if let Some([w, h]) = job.stock.size {
        let [cx, cy] = [
            job.stock.corner[0] - shift[0],
            job.stock.corner[1] - shift[1],
        ];
        if let Some(b) = toolpath_box(&whole) {
            if b[0] < cx - 1e-6 || b[1] < cy - 1e-6 || b[2] > cx + w + 1e-6 || b[3] > cy + h + 1e-6
            {
                warnings.push(format!(
                    "the tool centre reaches ({:.2}, {:.2})–({:.2}, {:.2}), beyond the stock ({cx}, {cy})–({}, {})",
                    b[0], b[1], b[2], b[3], cx + w, cy + h
                ));
            }
        }
    }
    let summary = imported.summary();
    let stock = JobStock {
        corner: [
            job.stock.corner[0] - shift[0],
            job.stock.corner[1] - shift[1],
        ],
        size: job.stock.size,
        thickness: job.stock.thickness,
    };
    Ok(JobResult {
        stock,
        warnings,
        imported: summary,
        shapes: shapes.iter().map(Shape::describe).collect(),
        ops: order.iter().map(|&k| built[k].1.clone()).collect(),
        tool_loads,
        preview_svg: preview_svg(&all_paths, &whole),
        programs,
    })
}

/// The drawing's path, its import, the numbered shapes and the shift to the program origin.
type Loaded = (
    std::path::PathBuf,
    oficina_io::Imported,
    Vec<Shape>,
    [f64; 2],
);

/// The job's drawing with its own shapes added, moved to the program's origin and numbered
/// as selections name them: (the drawing's path, the import, the shapes, the shift).
fn load_shapes(
    name: &str,
    text: &str,
    job: &model::Job,
    base: &FsPath,
    warnings: &mut Vec<String>,
) -> Result<Loaded, Error> {
    let drawing = base.join(&job.drawing);
    let join_tol = job.join_tol.unwrap_or(oficina_io::JOIN_TOL);
    let imported = oficina_io::load_drawing_with(&drawing, join_tol)
        .map_err(|e| Error(format!("{name}: drawing: {}", Error::chain(&e).0)))?;
    if !imported.unsupported.is_empty() {
        warnings.push(format!("{}: {}", drawing.display(), imported.unsupported));
    }
    let mut layers: Vec<(String, Path)> = imported
        .drawing
        .layers
        .iter()
        .flat_map(|l| l.paths.iter().map(|p| (l.name.clone(), p.clone())))
        .collect();
    for s in &job.shape {
        let line = line_of(text, s.span().start);
        let path = rect_path(s.get_ref())
            .map_err(|e| Error(format!("{name}: line {line}: [[shape]]: {e}")))?;
        layers.push((s.get_ref().layer.clone(), path));
    }
    // Program zero at the stock's corner: every shape moves by −corner (the stock too).
    let shift = match job.stock.origin {
        Origin::Drawing => [0.0, 0.0],
        Origin::StockCorner => job.stock.corner,
    };
    if shift != [0.0, 0.0] {
        let m = oficina_geom::kurbo::Affine::translate((-shift[0], -shift[1]));
        for (_, p) in layers.iter_mut() {
            *p = p.transform(m);
        }
    }
    let shapes = number_shapes(layers, usize::MAX);
    if shapes.is_empty() {
        return Err(Error(format!(
            "{name}: the drawing {} has no paths",
            drawing.display()
        )));
    }
    Ok((drawing, imported, shapes, shift))
}

/// One shape of a job as the workbench draws it: its id (the import report's), layer,
/// report line, and its outline flattened to 0.02 mm.
#[derive(Clone, Debug, serde::Serialize)]
pub struct JobShapeView {
    /// The id selections name.
    pub id: usize,
    /// Its layer.
    pub layer: String,
    /// The stroke colour, `#rrggbb`, when the drawing gives one.
    pub color: Option<String>,
    /// Closed.
    pub closed: bool,
    /// A circle's diameter, mm.
    pub circle: Option<f64>,
    /// Inside an odd number of closed shapes.
    pub hole: bool,
    /// The import report's line (`#3 HOLES closed circle Ø3.60 at …`).
    pub describe: String,
    /// The outline, X Y in program coordinates.
    pub points: Vec<[f64; 2]>,
}

/// The shapes of the job in `job_file` (its drawing and `[[shape]]`s, its operations not
/// built): what the workbench draws and selects from.
pub fn job_shapes(job_file: &FsPath) -> Result<(Vec<JobShapeView>, Vec<String>), Error> {
    let name = job_file.display().to_string();
    let text = std::fs::read_to_string(job_file).map_err(|e| Error(format!("{name}: {e}")))?;
    let job = model::parse_job_shapes(&name, &text)?;
    let base = job_file.parent().unwrap_or(FsPath::new("."));
    let mut warnings = Vec::new();
    let (_, _, shapes, _) = load_shapes(&name, &text, &job, base, &mut warnings)?;
    let views = shapes
        .iter()
        .map(|s| JobShapeView {
            id: s.id,
            layer: s.layer.clone(),
            color: s
                .path
                .style
                .stroke
                .map(|c| format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)),
            closed: s.path.closed,
            circle: s.circle,
            hole: s.path.closed && s.depth % 2 == 1,
            describe: s.describe(),
            points: s.path.flatten(0.02).iter().map(|p| [p.x, p.y]).collect(),
        })
        .collect();
    Ok((views, warnings))
}

/// The tool centre's feed moves as polylines (X, Y, Z), arcs flattened to about 0.05 mm;
/// a rapid or a drilled hole starts a new one (a hole is its own two-point line).
fn feed_polylines(o: &oficina_cam::Operation) -> Vec<Vec<[f64; 3]>> {
    use oficina_cam::Move;
    let mut out: Vec<Vec<[f64; 3]>> = Vec::new();
    let mut cur: Vec<[f64; 3]> = Vec::new();
    let mut at: Option<[f64; 3]> = None;
    for m in &o.moves {
        match m {
            Move::Rapid { to } => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
                at = Some(*to);
            }
            Move::Line { to, .. } => {
                if cur.is_empty() {
                    cur.extend(at);
                }
                cur.push(*to);
                at = Some(*to);
            }
            Move::Arc {
                to, center, ccw, ..
            } => {
                let from = at.unwrap_or(*to);
                if cur.is_empty() {
                    cur.push(from);
                }
                let r = (from[0] - center[0]).hypot(from[1] - center[1]);
                let a0 = (from[1] - center[1]).atan2(from[0] - center[0]);
                let a1 = (to[1] - center[1]).atan2(to[0] - center[0]);
                let tau = std::f64::consts::TAU;
                let mut sweep = if *ccw { a1 - a0 } else { a0 - a1 };
                sweep = sweep.rem_euclid(tau);
                if sweep < 1e-9 {
                    sweep = tau;
                }
                let step = if r > 0.05 {
                    2.0 * (1.0 - 0.05 / r).acos()
                } else {
                    tau
                };
                let n = ((sweep / step.max(1e-3)).ceil() as usize).clamp(1, 720);
                for i in 1..=n {
                    let f = i as f64 / n as f64;
                    let a = if *ccw { a0 + sweep * f } else { a0 - sweep * f };
                    cur.push([
                        center[0] + r * a.cos(),
                        center[1] + r * a.sin(),
                        from[2] + (to[2] - from[2]) * f,
                    ]);
                }
                at = Some(*to);
            }
            Move::Drill(d) => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
                let [x, y] = d.at;
                out.push(vec![[x, y, d.r], [x, y, d.bottom]]);
            }
            _ => {}
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

/// Box of the tool centre's cutting moves [x0, y0, x1, y1] (rapids at clearance left out).
fn toolpath_box(tp: &Toolpath) -> Option<[f64; 4]> {
    let pts = tp.operations.iter().flat_map(|o| {
        o.moves.iter().filter_map(|m| match m {
            oficina_cam::Move::Line { to, .. } | oficina_cam::Move::Arc { to, .. } => {
                Some([to[0], to[1]])
            }
            _ => None,
        })
    });
    oficina_geom::bounds(pts).map(|b| [b.x0, b.y0, b.x1, b.y1])
}

/// A selection as the job wrote it, for messages.
fn describe_select(s: &model::Select) -> String {
    let mut parts = Vec::new();
    if let Some(l) = &s.layer {
        parts.push(format!("layer = {:?}", l.names()));
    }
    if let Some(c) = &s.color {
        parts.push(format!("color = {c:?}"));
    }
    if let Some(ids) = &s.ids {
        parts.push(format!("ids = {ids:?}"));
    }
    if let Some(d) = s.diameter_under {
        parts.push(format!("diameter_under = {d}"));
    }
    if let Some(d) = s.diameter_over {
        parts.push(format!("diameter_over = {d}"));
    }
    if let Some(c) = s.closed {
        parts.push(format!("closed = {c}"));
    }
    if let Some(c) = s.circle {
        parts.push(format!("circle = {c}"));
    }
    format!("{{ {} }}", parts.join(", "))
}
