//! A 2.5D milling job: one operation (pocket, profile, drill) on an SVG/DXF drawing →
//! program, SVG preview, stock check, time. `oficina mill` and the workbench both run it.

use crate::judge::{judge, Judged};
use crate::{Error, Feedback, PostParams};
use oficina_cam::ops::{
    adaptive, allowed_region, half_tan, preview_canon_svg, preview_svg, toolpath, AdaptiveParams,
    Cut, DrillParams, Entry, MillOp, PocketParams, ProfileParams, Side, Strategy, Tabs,
    VCarveParams,
};
use oficina_cam::Tool;
use oficina_sim::Design;
use serde::Deserialize;
use std::path::Path;

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
/// The milling operation.
pub enum MillOpKind {
    /// Clear the inside of each closed shape.
    Pocket,
    /// Clear the inside of each closed shape at a bounded engagement angle
    /// (--max-engagement, --stepover caps the radial depth).
    Adaptive,
    /// Cut along each contour, inside it.
    ProfileIn,
    /// Cut along each contour, outside it.
    ProfileOut,
    /// Cut on each contour line.
    ProfileOn,
    /// Drill the circles' centres.
    Drill,
    /// V-carve with a V bit: closed shapes to the depth their width allows (capped at
    /// --depth), open strokes along the line.
    Vcarve,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
/// How the tool enters the material.
pub enum EntryKind {
    /// Along the path, at the ramp angle.
    Ramp,
    /// Down a helix.
    Helix,
    /// Straight down.
    Plunge,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "kebab-case")]
/// How a pocket is cleared.
pub enum PocketStrategy {
    /// Offsets of the contour, inwards.
    Offset,
    /// Parallel rows.
    Zigzag,
}

/// The form of a milling job; lengths in mm, feeds in mm/min, angles in degrees. The
/// defaults are the CLI's.
#[derive(Clone, Debug, Deserialize)]
#[serde(default)]
pub struct MillParams {
    /// The operation.
    pub op: MillOpKind,
    /// flat:D, ball:D, v:D:ANGLE … [,flute=L,shank=D].
    pub tool: String,
    /// The tool's number in the program.
    pub tool_number: u32,
    /// Depth below the stock top.
    pub depth: f64,
    /// Largest depth per pass (default: half the tool diameter).
    pub stepdown: Option<f64>,
    /// Pocket step-over (default 0.6 × tool diameter).
    pub stepover: Option<f64>,
    /// Pocket strategy.
    pub strategy: PocketStrategy,
    /// Stock left by the depth passes for one finishing pass at full depth.
    pub allowance: f64,
    /// Adaptive clearing: largest engagement angle, degrees.
    #[serde(default = "default_max_engagement")]
    pub max_engagement: f64,
    /// Adaptive clearing: stock left on the walls, mm.
    #[serde(default)]
    pub stock_to_leave: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Ramp, helix and plunge feed (default: a third of the feed).
    pub plunge_feed: Option<f64>,
    /// Spindle speed, rev/min.
    pub rpm: f64,
    /// How the tool enters.
    pub entry: EntryKind,
    /// Ramp angle.
    pub ramp_angle: f64,
    /// Helix radius (default: a third of the tool diameter).
    pub helix_radius: Option<f64>,
    /// Tabs per contour for profiles (0 = none).
    pub tabs: usize,
    /// Tab width.
    pub tab_width: f64,
    /// Tab height.
    pub tab_height: f64,
    /// Tangent lead-out arc radius after a profile.
    pub lead_out: f64,
    /// Tangent lead-in arc radius onto a profile (default: the tool radius; 0: none).
    #[serde(default)]
    pub lead_in: Option<f64>,
    /// Profiles on the outline with G41 + D: the control offsets by the tool radius.
    #[serde(default)]
    pub comp: bool,
    /// Drill peck depth (G83).
    pub peck: Option<f64>,
    /// Drill dwell at the bottom, s (G82).
    pub dwell: f64,
    /// Retraction plane above the stock top.
    pub clear_z: f64,
    /// Safe Z for tool changes and the end.
    pub safe_z: f64,
    /// Grid of the stock simulation.
    pub check_pixel: f64,
    /// V-carving: largest height of material left at the medial axis and on capped floors.
    pub leftover: f64,
    /// A smaller tool (tool number + 1) for what the tool could not reach (pocket,
    /// profile-in): corners tighter than its radius, features narrower than it.
    pub rest_tool: Option<String>,
    /// Carve this text (Hershey Roman Simplex, single strokes) instead of a drawing.
    pub text: Option<String>,
    /// Capital height of `text`, mm.
    pub text_height: f64,
    /// Ends of a drawing's paths that meet within this distance are joined (closed as
    /// drawn, open pieces chained into loops), mm.
    pub join_tol: f64,
    #[serde(flatten)]
    /// The post-processor and format.
    pub post: PostParams,
}

impl Default for MillParams {
    fn default() -> Self {
        MillParams {
            op: MillOpKind::Pocket,
            tool: "flat:6".into(),
            tool_number: 1,
            depth: 3.0,
            stepdown: None,
            stepover: None,
            strategy: PocketStrategy::Offset,
            allowance: 0.2,
            max_engagement: default_max_engagement(),
            stock_to_leave: 0.0,
            feed: 800.0,
            plunge_feed: None,
            rpm: 12000.0,
            entry: EntryKind::Ramp,
            ramp_angle: 3.0,
            helix_radius: None,
            tabs: 0,
            tab_width: 5.0,
            tab_height: 1.0,
            lead_out: 0.0,
            lead_in: None,
            comp: false,
            peck: None,
            dwell: 0.0,
            clear_z: 5.0,
            safe_z: 20.0,
            check_pixel: 0.2,
            leftover: 0.05,
            rest_tool: None,
            text: None,
            text_height: 10.0,
            join_tol: oficina_io::JOIN_TOL,
            post: PostParams::default(),
        }
    }
}

fn default_max_engagement() -> f64 {
    90.0
}

/// A milling job's output.
pub struct MillResult {
    /// What the drawing held that was left out, if anything.
    pub warning: Option<String>,
    /// What was imported: paths, layers, units, loops and what stayed open (empty for
    /// `--text`).
    pub imported: Vec<String>,
    /// The drawing's shapes with the ids a job's selections name them by (empty for
    /// `--text`).
    pub shapes: Vec<String>,
    /// The operation's name.
    pub op_name: &'static str,
    /// Moves in the toolpath.
    pub moves: usize,
    /// The SVG preview.
    pub preview_svg: String,
    /// The program and what it was judged to be.
    pub judged: Judged,
}

/// A number in a form: finite and within `lo..=hi`.
fn within(flag: &str, v: f64, lo: f64, hi: f64) -> Result<(), Error> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(Error(format!("--{flag} {v}: use {lo} to {hi}")))
    }
}

/// Mills `input` (SVG or DXF) as `p` says; `profile` times it (its load error is reported).
pub fn mill(
    input: &Path,
    p: &MillParams,
    profile: &Result<oficina_motion::Profile, String>,
    fb: Feedback,
) -> Result<MillResult, Error> {
    within("feed", p.feed, 1e-3, 1e6)?;
    within("rpm", p.rpm, 0.0, 1e6)?;
    within("check-pixel", p.check_pixel, 0.01, 10.0)?;
    within("join-tol", p.join_tol, 0.0, oficina_io::MAX_JOIN_TOL)?;
    fb.stage("reading the drawing")?;
    let (paths, warning, summary, closure, shapes) = match &p.text {
        Some(text) => (text_paths(text, p.text_height)?, None, vec![], None, vec![]),
        None => {
            let imported =
                oficina_io::load_drawing_with(input, p.join_tol).map_err(|e| Error::chain(&e))?;
            let warning = (!imported.unsupported.is_empty())
                .then(|| format!("{}: {}", input.display(), imported.unsupported));
            let paths: Vec<oficina_geom::Path> = imported.drawing.paths().cloned().collect();
            let summary = imported.summary();
            let shapes = crate::mill_job::shape_lines(&imported.drawing);
            (paths, warning, summary, Some(imported.closure), shapes)
        }
    };
    if paths.is_empty() {
        return Err(Error(format!(
            "{}: the drawing has no paths",
            input.display()
        )));
    }
    let tool: Tool = p
        .tool
        .parse()
        .map_err(|e| Error(format!("--tool {}: {e}", p.tool)))?;
    let d = tool.diameter;
    let entry = match p.entry {
        EntryKind::Plunge => Entry::Plunge,
        EntryKind::Ramp => Entry::Ramp {
            angle: p.ramp_angle,
        },
        EntryKind::Helix => Entry::Helix {
            radius: p.helix_radius.unwrap_or(d / 3.0),
            angle: p.ramp_angle,
        },
    };
    let cut = Cut {
        tool_number: p.tool_number,
        tool,
        spindle_rpm: p.rpm,
        feed: p.feed / 60.0,
        plunge_feed: p.plunge_feed.unwrap_or(p.feed / 3.0) / 60.0,
        top: 0.0,
        depth: p.depth,
        stepdown: p.stepdown.unwrap_or((d / 2.0).min(p.depth)),
        clear_z: p.clear_z,
        entry,
    };
    let profile_op = |side| {
        MillOp::Profile(ProfileParams {
            side,
            allowance: if matches!(side, Side::On) {
                0.0
            } else {
                p.allowance
            },
            tabs: (p.tabs > 0).then_some(Tabs {
                count: p.tabs,
                width: p.tab_width,
                height: p.tab_height,
            }),
            lead_out: p.lead_out,
            lead_in: p
                .lead_in
                .unwrap_or(d / 2.0 * oficina_cam::ops::DEFAULT_LEAD_IN),
            comp: if p.comp {
                oficina_cam::ops::Comp::Control
            } else {
                oficina_cam::ops::Comp::Computer
            },
        })
    };
    let op = match p.op {
        // Adaptive clearing may cut what an offset pocket may: it is judged as one.
        MillOpKind::Pocket | MillOpKind::Adaptive => MillOp::Pocket(PocketParams {
            strategy: match p.strategy {
                PocketStrategy::Zigzag => Strategy::ZigZag,
                PocketStrategy::Offset => Strategy::Offset,
            },
            stepover: p.stepover.unwrap_or(0.6 * d),
            allowance: p.allowance,
        }),
        MillOpKind::ProfileIn => profile_op(Side::Inside),
        MillOpKind::ProfileOut => profile_op(Side::Outside),
        MillOpKind::ProfileOn => profile_op(Side::On),
        MillOpKind::Drill => MillOp::Drill(DrillParams {
            peck: p.peck,
            dwell: p.dwell,
        }),
        MillOpKind::Vcarve => MillOp::VCarve(VCarveParams {
            leftover: p.leftover,
        }),
    };
    if p.safe_z < p.clear_z {
        return Err(Error(format!(
            "--safe-z {} must be at or above --clear-z {}",
            p.safe_z, p.clear_z
        )));
    }
    let op_name = match p.op {
        MillOpKind::Adaptive => "adaptive",
        _ => op.name(),
    };
    fb.stage(&format!("{op_name} with {}", cut.tool.spec()))?;
    let made = match p.op {
        MillOpKind::Adaptive => {
            let params = AdaptiveParams {
                max_engagement: p.max_engagement,
                // No step-over given: the engagement alone bounds the cut.
                stepover: p.stepover.unwrap_or(d),
                stock_to_leave: p.stock_to_leave,
            };
            adaptive(op_name, &paths, &cut, &params).map(|o| oficina_cam::Toolpath {
                safe_z: p.safe_z,
                operations: vec![o],
            })
        }
        _ => toolpath(&paths, &cut, &op, p.safe_z),
    };
    let mut tp = made.map_err(|e| {
        // Nothing closed to cut is often an outline whose ends miss by more than the join
        // tolerance: say what stayed open and what tolerance would join it.
        let mut err = Error::chain(&e);
        if let Some(hint) = closure.as_ref().and_then(|c| c.open_hint()) {
            err.0.push('\n');
            err.0.push_str(&hint);
        }
        err
    })?;
    let mut warning = warning;
    if let Some(spec) = &p.rest_tool {
        match rest_operation(&paths, &cut, &op, spec)? {
            Some(rest) => tp.operations.push(rest),
            None => {
                warning = Some(format!(
                    "--rest-tool {spec}: nothing left that it can reach, no rest pass"
                ))
            }
        }
    }
    let settings = vec![
        ("input".into(), input.display().to_string()),
        ("operation".into(), op_name.into()),
        (
            "tool".into(),
            format!("T{} {}", cut.tool_number, cut.tool.spec()),
        ),
        (
            "depth".into(),
            format!("{} mm in passes of at most {} mm", cut.depth, cut.stepdown),
        ),
    ];
    let (post, format) = p.post.options("Oficina 2.5D milling", settings)?;
    // A V-carving's walls slope at the bit's flank: 1 / tan(half angle) mm down per mm in.
    let slope = match op {
        MillOp::VCarve(_) => 1.0 / half_tan(&cut).map_err(|e| Error::chain(&e))?,
        _ => 0.0,
    };
    let design = allowed_region(&paths, &op)
        .map_err(|e| Error::chain(&e))?
        .map(|(rings, cut_inside)| {
            vec![Design {
                rings,
                cut_inside,
                top: cut.top,
                floor: cut.bottom(),
                slope,
            }]
        });
    let judged = judge(&tp, &post, &format, design, p.check_pixel, profile, fb)?;
    Ok(MillResult {
        warning,
        imported: summary,
        shapes,
        op_name,
        moves: tp.move_count(),
        // Under G41/G42 the moves are the outline: show the compensated path the
        // interpreter read back instead, the tool centre as the control will move it.
        preview_svg: if p.comp {
            preview_canon_svg(&paths, &judged.canon, p.safe_z)
        } else {
            preview_svg(&paths, &tp)
        },
        judged,
    })
}

/// The rest pass of `spec` (tool number + 1) after `op` with `cut`'s tool.
fn rest_operation(
    paths: &[oficina_geom::Path],
    cut: &Cut,
    op: &MillOp,
    spec: &str,
) -> Result<Option<oficina_cam::Operation>, Error> {
    let tool: Tool = spec
        .parse()
        .map_err(|e| Error(format!("--rest-tool {spec}: {e}")))?;
    let inside = matches!(
        op,
        MillOp::Pocket(_)
            | MillOp::Profile(ProfileParams {
                side: Side::Inside,
                ..
            })
    );
    if !inside {
        return Err(Error(
            "--rest-tool works after --op pocket or profile-in".into(),
        ));
    }
    let d = tool.diameter;
    let rest_cut = Cut {
        tool_number: cut.tool_number + 1,
        stepdown: (d / 2.0).min(cut.depth),
        tool,
        ..cut.clone()
    };
    let region = oficina_geom::Area::from_paths(paths);
    oficina_cam::ops::rest_machining(
        &format!("rest ({spec} after {})", cut.tool.spec()),
        &region,
        cut.radius(),
        &rest_cut,
    )
    .map_err(|e| Error(format!("--rest-tool {spec}: {e}")))
}

/// Single-stroke paths of `text` (Hershey Roman Simplex), capitals `height` mm tall, the
/// first baseline on y = 0.
fn text_paths(text: &str, height: f64) -> Result<Vec<oficina_geom::Path>, Error> {
    within("text-height", height, 0.1, 10_000.0)?;
    if text.chars().count() > 100_000 {
        return Err(Error("--text: at most 100,000 characters".into()));
    }
    let strokes = oficina_plot::text_strokes(text, oficina_geom::Point::ZERO, height, 0.0);
    if strokes.is_empty() {
        return Err(Error(format!("--text {text:?}: no strokes to carve")));
    }
    Ok(strokes
        .iter()
        .map(|s| oficina_geom::Path::polyline(s, false))
        .collect())
}
