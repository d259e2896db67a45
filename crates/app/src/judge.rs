//! Judging a milling program the way the control will see it: post it, read it back with
//! the interpreter, simulate the stock against the design, and time it.

use crate::{Error, Feedback};
use oficina_cam::{Tool, Toolpath};
use oficina_post::{post_for, read_back_with_tools, write_program_with, Format, PostOptions};
use oficina_sim::{check_mill, feed_only_estimate, Design};
use serde::Serialize;
use std::collections::HashMap;

/// Rapid rate for the feed-only estimate, mm/min (the planner's estimate uses the profile).
const FEED_ONLY_RAPID: f64 = 6000.0;
/// Gouges deeper than this are reported as cuts outside the drawing, mm.
pub const GOUGE_REPORTED: f64 = 1e-3;

/// What a milling program was judged to be.
#[derive(Serialize)]
pub struct Judged {
    #[serde(skip)]
    /// The program text.
    pub program: String,
    /// The program as the interpreter read it back (what the control will do).
    #[serde(skip)]
    pub canon: Vec<oficina_canon::Canon>,
    /// Deepest cut outside the design and where, when the design was checked.
    pub gouge: Option<(f64, [f64; 2])>,
    /// Mean material left above the design, mm, when checked.
    pub leftover_mean: Option<f64>,
    /// Time at the programmed feeds alone, s.
    pub feed_only_s: f64,
    /// The planner's time on the machine profile, s.
    pub planner_s: Option<f64>,
    /// The planner's time for each tool in the order the program loads them: (tool number,
    /// tool, seconds), from the same planning run as `planner_s`.
    pub per_tool: Vec<(u32, String, f64)>,
    /// Why there is no planner time.
    pub planner_error: Option<String>,
    /// The XY shift, mm, that placed a program lying outside the machine's travel inside it
    /// for the planner's time (the time does not depend on the place on a Cartesian machine).
    pub planner_shift: Option<[f64; 2]>,
    #[serde(skip)]
    /// The simulated stock, when the design was checked.
    pub stock: Option<oficina_io::Heightmap>,
}

impl Judged {
    /// True when the program cuts deeper than the design by more than [`GOUGE_REPORTED`].
    pub fn gouged(&self) -> bool {
        self.gouge.is_some_and(|(g, _)| g > GOUGE_REPORTED)
    }

    /// The report, a line each: gouge, leftover, time.
    pub fn summary_lines(&self) -> Vec<String> {
        let hms = |s| oficina_motion::format_hms(s, 0);
        let mut lines = vec![match self.gouge {
            Some((g, at)) if g > GOUGE_REPORTED => format!(
                "gouge:    {g:.3} mm at ({:.2}, {:.2})  ← cut outside the drawing",
                at[0], at[1]
            ),
            Some(_) => "gouge:    none (within 0.001 mm)".into(),
            None => "gouge:    not checked (a cut on the line is its own design)".into(),
        }];
        if let Some(l) = self.leftover_mean {
            lines.push(format!(
                "leftover: {l:.4} mm mean over the checked area, above what the last tool can reach"
            ));
        }
        lines.push(match (self.planner_s, &self.planner_error) {
            (Some(s), _) => format!(
                "time:     {} (planner{}), {} at programmed feeds",
                hms(s),
                self.planner_shift.map_or(String::new(), |[x, y]| format!(
                    ", the program moved by ({x:+.2}, {y:+.2}) mm into the machine's travel"
                )),
                hms(self.feed_only_s)
            ),
            (None, Some(e)) => format!(
                "time:     {} at programmed feeds (planner: {e})",
                hms(self.feed_only_s)
            ),
            _ => format!("time:     {} at programmed feeds", hms(self.feed_only_s)),
        });
        for (n, spec, s) in &self.per_tool {
            lines.push(format!("  T{n} {spec}: {} (planner)", hms(*s)));
        }
        lines
    }
}

/// Posts, reads back as the interpreter does, simulates against `design`, times on
/// `profile` (its load error is reported, not fatal: the program is still good).
pub(crate) fn judge(
    tp: &Toolpath,
    post: &PostOptions,
    format: &Format,
    designs: Option<Vec<Design>>,
    check_pixel: f64,
    profile: &Result<oficina_motion::Profile, String>,
    fb: Feedback,
) -> Result<Judged, Error> {
    fb.stage("writing the program")?;
    let mut buf = Vec::new();
    write_program_with(tp, post, format, post_for(post.dialect).as_ref(), &mut buf)
        .map_err(|e| Error::chain(&e))?;
    let program = String::from_utf8(buf).map_err(|e| Error::chain(&e))?;
    fb.stage("reading it back as the control will")?;
    // The tool table the control holds: G41/G42 take the radius from it.
    let table: Vec<(u32, f64)> = tp
        .operations
        .iter()
        .map(|o| (o.tool_number, o.tool.diameter))
        .collect();
    let canon = read_back_with_tools(&program, post, &table)
        .map_err(|e| Error(format!("internal error, please report: {e}")))?;
    let tools = tp.tools();
    let (mut gouge, mut leftover_mean, mut stock) = (None, None, None);
    if let Some(designs) = designs {
        fb.stage("simulating the stock")?;
        // The tool in the spindle when the program starts: the legacy control has no tool
        // words, and the Sinumerik program moves to its change position before T01 M06.
        // Nothing after the last motion cuts (the Sinumerik end loads the empty T99).
        let end = canon
            .iter()
            .rposition(|c| c.op.is_motion())
            .map_or(0, |k| k + 1);
        let mut ops = canon[..end].to_vec();
        if let Some(first) = tp.operations.first() {
            ops.insert(
                0,
                oficina_canon::Canon {
                    line: 0,
                    op: oficina_canon::CanonOp::SelectTool(first.tool_number),
                },
            );
            let check = check_mill(
                &ops,
                &tools,
                &designs,
                check_pixel,
                2.0 * first.tool.diameter + 2.0,
                tp.safe_z,
                &tp.operations.last().expect("one").tool,
            )
            .map_err(|e| Error::chain(&e))?;
            gouge = Some((check.report.max_gouge, check.report.gouge_at));
            leftover_mean = Some(check.report.scallop_mean);
            stock = Some(check.stock);
        }
    }
    fb.stage("estimating time")?;
    let feed_only_s = feed_only_estimate(&canon, [0.0, 0.0, tp.safe_z], FEED_ONLY_RAPID);
    let mut planner_shift = None;
    let mut too_large = None;
    let (planner_s, per_tool, planner_error) = match profile {
        Ok(p) => match oficina_motion::estimate_with(
            {
                // Two passes over the read-back program (no copy of it is kept).
                let lifted = || oficina_sim::to_machine(&canon, tp.safe_z + 1.0);
                match crate::travel_fit::shift_into_travel(lifted(), p) {
                    Ok(d) => planner_shift = d,
                    Err(e) => too_large = Some(e),
                }
                let d = planner_shift.unwrap_or([0.0, 0.0]);
                lifted().map(move |c| crate::travel_fit::shifted(c, d))
            },
            p,
            oficina_motion::PlanOptions::default(),
            true,
        ) {
            Ok(e) => {
                let per_tool = per_tool_times(&canon, &e.per_line, &tools);
                (Some(e.seconds), per_tool, None)
            }
            Err(e) => {
                let why = too_large.map_or(String::new(), |t| format!("; {t}"));
                (None, vec![], Some(format!("{e}{why}")))
            }
        },
        Err(e) => (None, vec![], Some(e.clone())),
    };
    Ok(Judged {
        program,
        canon,
        gouge,
        leftover_mean,
        feed_only_s,
        planner_s,
        per_tool,
        planner_error,
        planner_shift,
        stock,
    })
}

/// The planner's per-line seconds summed by the tool loaded at each line (a tool change,
/// or the first tool selected before any change).
fn per_tool_times(
    canon: &[oficina_canon::Canon],
    per_line: &[(u32, f64)],
    tools: &HashMap<u32, Tool>,
) -> Vec<(u32, String, f64)> {
    use oficina_canon::CanonOp;
    // Line where each tool takes over, in program order.
    let mut starts: Vec<(u32, u32)> = Vec::new();
    for c in canon {
        match c.op {
            CanonOp::ChangeTool(n) => starts.push((c.line, n)),
            CanonOp::SelectTool(n) if starts.is_empty() => starts.push((c.line, n)),
            _ => {}
        }
    }
    let mut out: Vec<(u32, String, f64)> = Vec::new();
    for &(line, s) in per_line {
        let Some(&(_, n)) = starts
            .iter()
            .rev()
            .find(|(l, _)| *l <= line)
            .or(starts.first())
        else {
            continue;
        };
        // Unknown numbers (Sinumerik's empty T99) take no time worth a line.
        let Some(tool) = tools.get(&n) else { continue };
        match out.iter_mut().find(|(m, _, _)| *m == n) {
            Some(t) => t.2 += s,
            None => out.push((n, tool.spec(), s)),
        }
    }
    out
}
