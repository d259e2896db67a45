//! Simulating any program (ours or another CAM's): read as `check` reads it, its tools given
//! shapes, replayed on a box of stock with `oficina_sim::stock_box`, the stock rendered and
//! the moves to look at listed. Two passes over the text keep memory bounded whatever the
//! program's length: the first finds extents, tools and time, the second removes material.

use crate::check::Diag;
use crate::Error;
use oficina_cam::{CutterShape, Library, Tool};
use oficina_canon::{Canon, CanonOp, Pos, Summarizer, Summary};
use oficina_gcode::{CanonStream, Dialect, RunOptions, Severity, ToolTable};
use oficina_io::Heightmap;
use oficina_motion::Profile;
use oficina_sim::stock_box::{self, Finding, Grid, StockBox, Workload};
use serde::Serialize;
use std::collections::{BTreeSet, HashMap};
use std::io::Cursor;
use std::path::PathBuf;
use std::sync::Arc;

/// Default memory budget for the stock grid, MB.
pub const DEFAULT_SIM_MEMORY_MB: u64 = 256;

/// Where each tool's shape comes from, first match wins: `by_number`, the `library`, the
/// interpreter's tool table (diameter; shape from its comment), then `default`.
#[derive(Clone, Debug, Default)]
pub struct ToolChoice {
    /// `--tool N=SPEC`.
    pub by_number: Vec<(u32, Tool)>,
    /// A tool library (TOML).
    pub library: Option<Library>,
    /// `--tool SPEC`: every tool not known otherwise.
    pub default: Option<Tool>,
}

/// The stock's size: given, or the program's cutting extents plus a margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StockSize {
    /// Width, height, thickness, mm.
    Given([f64; 3]),
    /// The extents of the moves below Z 0 (or the stock top), grown by the margin (mm).
    Auto {
        /// Margin around the cuts, mm.
        margin: f64,
    },
}

/// A design to compare the stock with: a grayscale image, white the stock top, black
/// `depth` mm below it, spread over the stock's width.
#[derive(Clone, Debug)]
pub struct DesignImage {
    /// The image.
    pub path: PathBuf,
    /// Depth of black, mm.
    pub depth: f64,
}

/// What to simulate and how.
pub struct SimulateRequest {
    /// The program's text.
    pub text: Arc<String>,
    /// The interpreter's options (dialect, tool table); work offsets are zeroed here so
    /// the stock sits in the program's own coordinates.
    pub run: RunOptions,
    /// The machine whose planner times the program.
    pub profile: Profile,
    /// Tool shapes.
    pub tools: ToolChoice,
    /// Stock size.
    pub stock: StockSize,
    /// Lower-left X, Y and top Z of the stock; default: the cuts' lower-left, top Z 0.
    pub stock_origin: Option<[f64; 3]>,
    /// Grid cell, mm; default: chosen from the budget.
    pub resolution: Option<f64>,
    /// Memory budget for the grids, MB.
    pub memory_mb: u64,
    /// A design to compare with.
    pub design: Option<DesignImage>,
}

/// A tool as simulated and where its shape came from.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ToolUse {
    /// Tool number.
    pub number: u32,
    /// `shape:diameter…`.
    pub spec: String,
    /// Where the shape came from.
    pub from: String,
}

/// Gouge and leftover against the design.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DesignComparison {
    /// Deepest cut below the design, mm, and where (program X, Y).
    pub max_gouge: f64,
    /// Where the deepest gouge is.
    pub gouge_at: [f64; 2],
    /// Most material left above the design, mm.
    pub leftover_max: f64,
    /// Mean material left, mm.
    pub leftover_mean: f64,
}

/// What a simulation found, in numbers (what `oficina simulate` prints and the page shows).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SimulationReport {
    /// Stock lower-left X, Y (program mm).
    pub stock_origin: [f64; 2],
    /// Stock top, program Z.
    pub stock_top: f64,
    /// Width, height, thickness, mm.
    pub stock_size: [f64; 3],
    /// Grid cell, mm, and cells along X and Y.
    pub pixel: f64,
    /// Cells along X.
    pub grid_width: usize,
    /// Cells along Y.
    pub grid_height: usize,
    /// How the cell size was chosen.
    pub resolution_note: String,
    /// Material removed, mm³.
    pub removed_mm3: f64,
    /// Lowest stock surface after the program, program Z.
    pub lowest_z: f64,
    /// Highest.
    pub highest_z: f64,
    /// Area cut through the bottom, mm².
    pub through_mm2: f64,
    /// The program's lowest tip Z (feed moves), as its extents give it.
    pub program_lowest_z: Option<f64>,
    /// Feed length, mm.
    pub feed_length: f64,
    /// The planner's machine time, s, or why there is none.
    pub machine_seconds: Result<f64, String>,
    /// Rapids through material: line and depth (mm), the first few.
    pub rapids_into_material: Vec<(u32, f64)>,
    /// Moves below the stock's bottom: line and tip Z, the first few.
    pub below_bottom: Vec<(u32, f64)>,
    /// Cutting moves ending off the stock: line and X, Y, the first few.
    pub off_stock: Vec<(u32, [f64; 2])>,
    /// How many of each: rapids into material, below bottom, off the stock.
    pub counts: [usize; 3],
    /// The tools simulated.
    pub tools: Vec<ToolUse>,
    /// What was assumed, in words.
    pub notes: Vec<String>,
    /// The interpreter's errors (the simulation goes on past them).
    pub errors: Vec<Diag>,
    /// Against the design, when one was given.
    pub design: Option<DesignComparison>,
}

/// The report and the stock's height field (program Z on the grid).
pub struct Simulation {
    /// The numbers.
    pub report: SimulationReport,
    /// The stock surface; cell (0, 0)'s centre at `stock_origin` + half a pixel.
    pub stock: Heightmap,
}

/// The program's text shared by both passes (no copy of a large program per pass).
struct Shared(Arc<String>);

impl AsRef<[u8]> for Shared {
    fn as_ref(&self) -> &[u8] {
        self.0.as_bytes()
    }
}

/// First pass: extents, tools, time, errors.
struct Survey {
    summary: Summary,
    tool_numbers: Vec<u32>,
    seconds: Result<f64, String>,
    diagnostics: Vec<oficina_gcode::Diagnostic>,
}

/// Simulates the program of `req`.
pub fn simulate(req: &SimulateRequest) -> Result<Simulation, Error> {
    let mut notes = Vec::new();
    let text = sender_text(&req.text, req.run.dialect, &mut notes);
    let mut run = req.run.clone();
    let mut profile = req.profile.clone();
    profile.work_offset = [0.0; 3];
    // Program coordinates are not the machine's: the planner's time does not depend on where
    // the work sits, its travel limits would (they are `check`'s business).
    profile.travel = [[-1e7, 1e7]; 3];
    for j in profile.joints.iter_mut().flatten() {
        j.limits = None;
    }
    run.initial_params = crate::run_options::initial_params_for(&profile, run.dialect);
    if run.tool_table.is_empty() || run.tool_table.is_rs274_default() {
        run.tool_table = open_table(&req.tools);
    }
    let survey = survey(&text, &run, &profile);
    let s = &survey.summary;
    if s.feed_extents.is_empty() && s.rapid_extents.is_empty() {
        return Err(Error(
            "the program makes no move: nothing to simulate".into(),
        ));
    }
    let (tools, uses) = tool_shapes(
        &survey.tool_numbers,
        &req.tools,
        &run.tool_table,
        &mut notes,
    );
    let stock = stock_box(req, s, &uses, &tools, &mut notes)?;
    stock.validate().map_err(Error)?;
    let budget = req.memory_mb.saturating_mul(1_000_000);
    let work = Workload {
        path_mm: s.feed_length,
        tool_radius: tools.values().map(|t| t.reach_radius()).fold(0.0, f64::max),
    };
    let grid = stock_box::choose_grid(
        &stock,
        req.resolution,
        budget,
        stock_box::bytes_per_cell(req.design.is_some()),
        work,
    )
    .map_err(Error)?;
    let smallest = tools
        .values()
        .map(|t| t.diameter)
        .fold(f64::INFINITY, f64::min);
    if grid.pixel > smallest / 2.0 {
        notes.push(format!(
            "the {} mm cell is coarser than half the smallest tool ({smallest} mm): the stock is rough",
            grid.pixel
        ));
    }
    // Before any tool change the operator has the program's first tool in the spindle.
    let first = survey.tool_numbers.first().copied().unwrap_or(0);
    let preload = Canon {
        line: 0,
        op: CanonOp::ChangeTool(first),
    };
    let mut stream = CanonStream::spawn(Cursor::new(Shared(text.clone())), run);
    // The tool starts over the program's origin, above the stock and every move.
    let high = s.rapid_extents.max[2]
        .max(s.feed_extents.max[2])
        .max(stock.top);
    let sim = stock_box::simulate(
        std::iter::once(preload).chain(stream.by_ref()),
        &tools,
        &stock,
        &grid,
        [0.0, 0.0, if high.is_finite() { high } else { stock.top }],
    )
    .map_err(Error::from_display)?;
    drop(stream.finish());
    let design = match &req.design {
        Some(d) => Some(compare_design(d, &stock, &sim, &tools, &survey, budget)?),
        None => None,
    };
    Ok(Simulation {
        report: report(&stock, &grid, &sim, &survey, uses, notes, design),
        stock: sim.stock,
    })
}

/// For grbl: the program as Oficina's sender sends it (M6 a pause), as `check` reads it.
fn sender_text(text: &Arc<String>, dialect: Dialect, notes: &mut Vec<String>) -> Arc<String> {
    if dialect != Dialect::Grbl {
        return text.clone();
    }
    let (view, sent) =
        oficina_grbl::sender_view(text.as_bytes(), &oficina_grbl::ToolChange::default());
    if !sent.is_empty() {
        notes.push(format!(
            "{} line(s) read as the sender sends them to grbl (M6 a pause, % marks dropped)",
            sent.len()
        ));
    }
    String::from_utf8(view).map_or_else(|_| text.clone(), Arc::new)
}

fn survey(text: &Arc<String>, run: &RunOptions, profile: &Profile) -> Survey {
    let [x, y, z] = profile.start;
    let mut summarizer = Summarizer::with_bound(
        Pos::xyz(x, y, z),
        Box::new(oficina_motion::JointBound::new(profile)),
    );
    let mut tools = BTreeSet::new();
    let mut order = Vec::new();
    let mut note_tool = |n: u32| {
        if tools.insert(n) {
            order.push(n);
        }
    };
    let mut stream = CanonStream::spawn(Cursor::new(Shared(text.clone())), run.clone());
    let mut see = |c: &Canon| {
        summarizer.add(&c.op);
        if let CanonOp::ChangeTool(n) | CanonOp::SelectTool(n) = c.op {
            note_tool(n);
        }
    };
    let planned = oficina_motion::estimate(stream.by_ref().inspect(&mut see), profile);
    // The planner may stop early (an unreachable point); the survey still covers it all.
    for c in stream.by_ref() {
        see(&c);
    }
    Survey {
        summary: summarizer.finish(),
        tool_numbers: order,
        seconds: planned.map(|e| e.seconds).map_err(|e| e.to_string()),
        diagnostics: stream.finish(),
    }
}

/// The comment of every tool of [`open_table`].
const OPEN_TABLE: &str = "simulate: no tool table given";

/// Without a tool table every tool number 0–999 is accepted, as a sender passes any `T` to
/// the operator (LinuxCNC refuses a `T` its table lacks): each with the diameter the choice
/// gives it, for G41/G42.
fn open_table(choice: &ToolChoice) -> ToolTable {
    let mut table = ToolTable::new();
    for n in 0..1000u32 {
        let diameter = choice
            .by_number
            .iter()
            .find(|(k, _)| *k == n)
            .map(|(_, t)| t.diameter)
            .or_else(|| choice.library.as_ref()?.get(n).map(|t| t.diameter))
            .or(choice.default.as_ref().map(|t| t.diameter))
            .unwrap_or(3.0);
        table.insert(oficina_gcode::Tool {
            number: n,
            pocket: n,
            diameter,
            comment: OPEN_TABLE.into(),
            ..Default::default()
        });
    }
    table
}

/// A shape for every tool number the program names (and for "no tool", 0).
fn tool_shapes(
    numbers: &[u32],
    choice: &ToolChoice,
    table: &ToolTable,
    notes: &mut Vec<String>,
) -> (HashMap<u32, Tool>, Vec<ToolUse>) {
    // The table made up by `open_table` holds nothing of the shop's tools.
    let table = table
        .iter()
        .all(|t| t.comment != OPEN_TABLE)
        .then_some(table);
    let fallback = choice
        .default
        .clone()
        .unwrap_or_else(|| Tool::new(CutterShape::Flat, 3.0).expect("a 3 mm flat is a tool"));
    let mut map = HashMap::new();
    let mut uses = Vec::new();
    let wanted = if numbers.is_empty() {
        vec![0]
    } else {
        numbers.to_vec()
    };
    for n in wanted {
        let (tool, from) = if let Some((_, t)) = choice.by_number.iter().find(|(k, _)| *k == n) {
            (t.clone(), format!("--tool {n}=…"))
        } else if let Some(t) = choice.library.as_ref().and_then(|l| l.get(n)) {
            match t.tool() {
                Ok(tool) => (tool, "tool library".to_string()),
                Err(e) => (fallback.clone(), format!("default ({e} in the library)")),
            }
        } else if let Some(t) = table.and_then(|t| t.get(n)).filter(|t| t.diameter > 0.0) {
            from_table(t)
        } else {
            let why = if choice.default.is_some() {
                "--tool".to_string()
            } else {
                "assumed (no --tool)".to_string()
            };
            if n != 0 {
                notes.push(format!(
                    "T{n} is not in the tool table or library: simulated as {} ({why})",
                    fallback.spec()
                ));
            } else if choice.default.is_none() {
                notes.push(format!(
                    "the program names no tool: simulated with {} (--tool sets it)",
                    fallback.spec()
                ));
            }
            (fallback.clone(), why)
        };
        uses.push(ToolUse {
            number: n,
            spec: tool.spec(),
            from,
        });
        map.insert(n, tool);
    }
    // Motion before the first change uses the first tool (see `simulate`).
    if !map.contains_key(&0) {
        let first = map[&uses[0].number].clone();
        map.insert(0, first);
    }
    (map, uses)
}

/// A tool table row: its diameter; the shape from its comment (`ball`, `v 60`, a spec such
/// as `ball:6`), else a flat end mill.
fn from_table(t: &oficina_gcode::Tool) -> (Tool, String) {
    let c = t.comment.to_ascii_lowercase();
    let spec = c.split_whitespace().find_map(|w| w.parse::<Tool>().ok());
    if let Some(tool) = spec {
        return (tool, "tool table comment".into());
    }
    let angle = c
        .split(|ch: char| !(ch.is_ascii_digit() || ch == '.'))
        .filter_map(|w| w.parse::<f64>().ok())
        .find(|a| (10.0..=150.0).contains(a));
    let words: Vec<&str> = c
        .split(|ch: char| !ch.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .collect();
    let has = |w: &str| words.contains(&w);
    let shape = if has("ball") || has("ballnose") {
        CutterShape::Ball
    } else if has("v") || has("vbit") || has("vee") || c.contains("v-bit") || has("engraving") {
        CutterShape::V {
            angle: angle.unwrap_or(60.0),
        }
    } else {
        CutterShape::Flat
    };
    match Tool::new(shape, t.diameter) {
        Ok(tool) => (
            tool,
            "tool table (shape from its comment, else flat)".into(),
        ),
        Err(_) => (
            Tool::new(CutterShape::Flat, t.diameter).unwrap_or_else(|_| {
                Tool::new(CutterShape::Flat, 3.0).expect("a 3 mm flat is a tool")
            }),
            "tool table (flat)".into(),
        ),
    }
}

/// The stock box: its size given or from the cuts, its origin given or at the cuts'
/// lower-left with the top at Z 0 (as most CAM posts zero the work).
fn stock_box(
    req: &SimulateRequest,
    s: &Summary,
    uses: &[ToolUse],
    tools: &HashMap<u32, Tool>,
    notes: &mut Vec<String>,
) -> Result<StockBox, Error> {
    let top = req.stock_origin.map_or(0.0, |o| o[2]);
    let e = if s.feed_extents.is_empty() {
        &s.rapid_extents
    } else {
        &s.feed_extents
    };
    let ([x0, y0], [x1, y1]) = ([e.min[0], e.min[1]], [e.max[0], e.max[1]]);
    match req.stock {
        StockSize::Given(size) => {
            let origin = match req.stock_origin {
                Some(o) => [o[0], o[1]],
                None => {
                    notes.push(format!(
                        "stock lower-left at the cuts' lower-left X{x0:.3} Y{y0:.3}, top at Z{top} \
                         (--stock-origin X,Y,Z moves it)"
                    ));
                    [x0, y0]
                }
            };
            Ok(StockBox { origin, top, size })
        }
        StockSize::Auto { margin } => {
            let reach = uses
                .iter()
                .filter_map(|u| tools.get(&u.number))
                .map(|t| t.cutting_radius())
                .fold(0.0, f64::max);
            let m = margin.max(0.0) + reach;
            let depth = (top - e.min[2]).max(0.0);
            let size = [
                x1 - x0 + 2.0 * m,
                y1 - y0 + 2.0 * m,
                depth + margin.max(1.0),
            ];
            notes.push(format!(
                "stock auto: the cuts' extents plus {m:.3} mm (margin + tool radius), {:.3} mm \
                 thick (the deepest cut + {:.3} mm)",
                size[2],
                margin.max(1.0)
            ));
            Ok(StockBox {
                origin: [x0 - m, y0 - m],
                top,
                size,
            })
        }
    }
}

fn compare_design(
    d: &DesignImage,
    stock: &StockBox,
    sim: &stock_box::Simulated,
    tools: &HashMap<u32, Tool>,
    survey: &Survey,
    budget: u64,
) -> Result<DesignComparison, Error> {
    let image = oficina_io::load_image(
        &d.path,
        oficina_io::Scale::Width(stock.size[0]),
        oficina_io::DepthMapping::new(d.depth),
        budget,
    )
    .map_err(|e| Error::chain(&e))?;
    // The design resampled (nearest) on the stock's cells, lifted to the stock top.
    let g = &sim.stock;
    let design = Heightmap::from_fn(g.width, g.height, g.pixel, |x, y| {
        let ix = ((x + g.pixel / 2.0) / image.pixel).floor() as usize;
        let iy = ((y + g.pixel / 2.0) / image.pixel).floor() as usize;
        if ix < image.width && iy < image.height {
            stock.top + image.at(ix, iy) as f64
        } else {
            stock.top
        }
    });
    let last = survey.tool_numbers.last().copied().unwrap_or(0);
    let ideal = oficina_sim::ideal_surface(&design, &tools[&last]);
    let r = oficina_sim::compare(g, &design, &ideal);
    Ok(DesignComparison {
        max_gouge: r.max_gouge,
        gouge_at: [
            r.gouge_at[0] + sim.cell_origin[0],
            r.gouge_at[1] + sim.cell_origin[1],
        ],
        leftover_max: r.leftover_max,
        leftover_mean: r.leftover_mean,
    })
}

fn report(
    stock: &StockBox,
    grid: &Grid,
    sim: &stock_box::Simulated,
    survey: &Survey,
    tools: Vec<ToolUse>,
    notes: Vec<String>,
    design: Option<DesignComparison>,
) -> SimulationReport {
    let mut r = SimulationReport {
        stock_origin: stock.origin,
        stock_top: stock.top,
        stock_size: stock.size,
        pixel: grid.pixel,
        grid_width: grid.width,
        grid_height: grid.height,
        resolution_note: grid.why.clone(),
        removed_mm3: sim.removed_mm3,
        lowest_z: sim.depth_range.0,
        highest_z: sim.depth_range.1,
        through_mm2: sim.through_mm2,
        program_lowest_z: (!survey.summary.feed_extents.is_empty())
            .then_some(survey.summary.feed_extents.min[2]),
        feed_length: survey.summary.feed_length,
        machine_seconds: survey.seconds.clone(),
        rapids_into_material: Vec::new(),
        below_bottom: Vec::new(),
        off_stock: Vec::new(),
        counts: sim.counts,
        tools,
        notes,
        errors: survey
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(Diag::from)
            .collect(),
        design,
    };
    for f in &sim.findings {
        match *f {
            Finding::RapidIntoMaterial { line, depth } => {
                r.rapids_into_material.push((line, depth))
            }
            Finding::BelowBottom { line, z } => r.below_bottom.push((line, z)),
            Finding::OffStock { line, at } => r.off_stock.push((line, at)),
        }
    }
    r
}
