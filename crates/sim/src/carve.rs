//! A relief carving job from its settings to its figures: the settings become a CAM job
//! (with the carving policy: roughing allowance, rest machining, thinnest cut), the job is
//! planned, posted, read back by the interpreter, simulated on the stock and timed, all
//! inside one memory budget estimated before each stage allocates.
//!
//! The CLI's `carve` and `bench carve` parse options into [`Settings`] and print an
//! [`Evaluation`]; they hold no policy of their own.

use crate::{compare, feed_only_estimate, ideal_surface, replay, Report, SimError};
use oficina_cam::memory::{self, Budget, Lever, OverBudget};
use oficina_cam::relief::{plan_within, Cutter, Direction, Pass, Planned, ReliefError, ReliefJob};
use oficina_cam::Feeds;
use oficina_cam::{Move, ToolError};
use oficina_canon::Canon;
use oficina_io::Heightmap;
use oficina_post::{program_text, PostDialect, PostOptions};

/// The carving settings a user chooses (feeds in mm/min, lengths in mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Finishing tool, e.g. `ball:6` (see [`Tool`]'s syntax).
    pub tool: String,
    /// Roughing tool; enables roughing by levels and rest machining.
    pub rough_tool: Option<String>,
    /// Target scallop height of the finish (sets the step-over unless `stepover` is given).
    pub scallop: f64,
    /// Finishing step-over, mm (overrides `scallop`).
    pub stepover: Option<f64>,
    /// Roughing step-over as a fraction of the roughing tool's diameter.
    pub rough_stepover: f64,
    /// Roughing depth per level, mm.
    pub stepdown: f64,
    /// Material the roughing leaves for the finishing tool.
    pub allowance: f64,
    /// Direction of the finishing raster.
    pub direction: Direction,
    /// Cut in one direction only (climb or conventional throughout) instead of zig-zag.
    pub one_way: bool,
    /// Skip rest machining after roughing.
    pub no_rest: bool,
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    pub rpm: f64,
    /// Height for rapids above the stock, mm.
    pub safe_z: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            tool: "ball:6".into(),
            rough_tool: None,
            scallop: 0.02,
            stepover: None,
            rough_stepover: 0.8,
            stepdown: 5.0,
            allowance: 0.5,
            direction: Direction::X,
            one_way: false,
            no_rest: false,
            feed: 2000.0,
            plunge_feed: 500.0,
            rpm: 18000.0,
            safe_z: 5.0,
        }
    }
}

/// What a rapid is assumed to achieve when the CAM weighs lifting against feeding, mm/min.
const RAPID_MM_MIN: f64 = 5000.0;
/// Thinnest layer worth a visit, mm.
const MIN_CUT: f64 = 0.01;
/// Rest machining leaves at most this much for the finish, mm, and visits only where the
/// roughing left more than its allowance plus this margin.
const REST_ALLOWANCE: f64 = 0.2;
const REST_MARGIN: f64 = 0.3;
/// Rest machining's step-over, as a fraction of the finishing tool's diameter.
const REST_STEPOVER: f64 = 0.5;

/// A setting outside what any machine or part could mean.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SettingsError {
    /// The tool spec does not parse.
    #[error(transparent)]
    Tool(#[from] ToolError),
    /// A number outside `min..=max`.
    #[error("{what} must be a number from {min} to {max}{unit}, got {value}")]
    Range {
        /// The setting's name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// Smallest value allowed.
        min: f64,
        /// Largest value allowed.
        max: f64,
        /// Unit of the setting (" mm", "").
        unit: &'static str,
    },
    /// A number that must be above 0 and at most `max`.
    #[error("{what} must be a number above 0 and at most {max}{unit}, got {value}")]
    Positive {
        /// The setting's name.
        what: &'static str,
        /// The value given.
        value: f64,
        /// Largest value allowed.
        max: f64,
        /// Unit of the setting (" mm", "").
        unit: &'static str,
    },
}

/// Largest length a setting may have, mm: no part or machine is larger (see the planner's
/// own limit on the part).
const MAX_LENGTH_MM: f64 = oficina_cam::relief::MAX_EXTENT_MM;

impl Settings {
    /// Every number finite and within what a machine could do.
    fn check(&self) -> Result<(), SettingsError> {
        let positive = |what, value: f64, max, unit| {
            if value.is_finite() && value > 0.0 && value <= max {
                Ok(())
            } else {
                Err(SettingsError::Positive {
                    what,
                    value,
                    max,
                    unit,
                })
            }
        };
        positive("scallop", self.scallop, MAX_LENGTH_MM, " mm")?;
        if let Some(s) = self.stepover {
            positive("step-over", s, MAX_LENGTH_MM, " mm")?;
        }
        positive(
            "roughing step-over",
            self.rough_stepover,
            100.0,
            " diameters",
        )?;
        positive("step-down", self.stepdown, MAX_LENGTH_MM, " mm")?;
        // Feeds as the post writes them (4 decimals) must not read as F0.
        for (what, value, min, max, unit) in [
            ("feed", self.feed, 0.01, 1.0e6, " mm/min"),
            ("plunge feed", self.plunge_feed, 0.01, 1.0e6, " mm/min"),
            ("allowance", self.allowance, 0.0, MAX_LENGTH_MM, " mm"),
            ("safe Z", self.safe_z, 0.0, MAX_LENGTH_MM, " mm"),
            ("spindle speed", self.rpm, 0.0, 1.0e6, " rpm"),
        ] {
            if !(value.is_finite() && (min..=max).contains(&value)) {
                return Err(SettingsError::Range {
                    what,
                    value,
                    min,
                    max,
                    unit,
                });
            }
        }
        Ok(())
    }

    fn cutter(&self, number: u32, spec: &str) -> Result<Cutter, ToolError> {
        Ok(Cutter {
            number,
            tool: spec.parse()?,
            feeds: Feeds {
                cut: self.feed / 60.0,
                plunge: self.plunge_feed / 60.0,
                rapid: RAPID_MM_MIN / 60.0,
            },
            spindle_rpm: self.rpm,
        })
    }

    /// The CAM job: roughing and rest machining when a roughing tool is given, then the
    /// finish.
    pub fn job(&self) -> Result<ReliefJob, SettingsError> {
        self.check()?;
        let finish = self.cutter(2, &self.tool)?;
        let stepover = self
            .stepover
            .unwrap_or_else(|| finish.tool.stepover_for_scallop(self.scallop));
        let base = |name: &str, c: Cutter, stepover: f64| Pass {
            name: name.into(),
            cutter: c,
            stepover,
            stepdown: self.stepdown,
            allowance: 0.0,
            direction: Direction::X,
            zigzag: !self.one_way,
            rest_only: false,
            min_cut: MIN_CUT,
        };
        let mut passes = Vec::new();
        if let Some(spec) = &self.rough_tool {
            let rough = self.cutter(1, spec)?;
            let so = rough.tool.diameter * self.rough_stepover;
            passes.push(Pass {
                allowance: self.allowance,
                ..base("roughing", rough, so)
            });
            if !self.no_rest {
                // The finishing tool clears, level by level, what the big tool could not reach.
                let so = finish.tool.diameter * REST_STEPOVER;
                passes.push(Pass {
                    allowance: self.allowance.min(REST_ALLOWANCE),
                    rest_only: true,
                    min_cut: self.allowance + REST_MARGIN,
                    ..base("rest machining", finish.clone(), so)
                });
            }
        }
        passes.push(Pass {
            direction: self.direction,
            ..base("finishing", finish, stepover)
        });
        Ok(ReliefJob {
            safe_z: self.safe_z,
            clearance: 1.0,
            tolerance: 0.005,
            samples_per_pixel: oficina_cam::relief::SAMPLES_PER_PIXEL,
            passes,
            simulate_last: false,
        })
    }

    /// The settings as `name = value` pairs for a program's header.
    pub fn describe(&self) -> Vec<(String, String)> {
        let mut out = vec![("tool".to_string(), self.tool.clone())];
        let mut put = |k: &str, v: String| out.push((k.to_string(), v));
        match &self.rough_tool {
            Some(t) => {
                put("rough tool", t.clone());
                put(
                    "rough step-over",
                    format!("{} x diameter", self.rough_stepover),
                );
                put("allowance", format!("{} mm", self.allowance));
                put("rest machining", (!self.no_rest).to_string());
            }
            None => put("rough tool", "none".into()),
        }
        put(
            "step-over",
            match self.stepover {
                Some(s) => format!("{s} mm"),
                None => format!("for a {} mm scallop", self.scallop),
            },
        );
        put("step-down", format!("{} mm", self.stepdown));
        put(
            "direction",
            match self.direction {
                Direction::X => "x",
                Direction::Y => "y",
                Direction::Both => "both",
            }
            .into(),
        );
        put("zig-zag", (!self.one_way).to_string());
        put(
            "feed",
            format!("{} mm/min, plunge {} mm/min", self.feed, self.plunge_feed),
        );
        put("spindle", format!("{} rpm", self.rpm));
        put("safe Z", format!("{} mm", self.safe_z));
        out
    }
}

/// What one planned job gives: the program, the simulated stock, its quality and times.
pub struct Evaluation {
    /// The relief plan (passes and toolpath).
    pub planned: Planned,
    /// The G-code program.
    pub program: String,
    /// The stock after simulating the program.
    pub stock: Heightmap,
    /// How the stock compares with the design.
    pub report: Report,
    /// Time at the programmed feeds, rapids at 6000 mm/min, no acceleration: seconds.
    pub feed_only_s: f64,
    /// The motion planner's estimate on the machine profile, or why there is none.
    pub planner: Result<f64, String>,
}

/// Why a relief job could not be planned, simulated or written.
#[derive(Debug, thiserror::Error)]
pub enum CarveError {
    /// The relief planner refused the job.
    #[error(transparent)]
    Plan(#[from] ReliefError),
    /// The job would need more memory than allowed.
    #[error(transparent)]
    Memory(#[from] OverBudget),
    /// The simulator could not replay the program.
    #[error(transparent)]
    Simulation(#[from] SimError),
    /// Oficina's interpreter rejects the program Oficina wrote: a bug to report.
    #[error("internal error: the interpreter rejects the generated program ({count} diagnostics); please report it:\n{first}")]
    Interpreter {
        /// How many diagnostics.
        count: usize,
        /// The first one, as text.
        first: String,
    },
    /// The job has no passes to cut.
    #[error("the job has no passes")]
    NoPasses,
    /// The post-processor refused the toolpath.
    #[error("the post-processor refused the toolpath: {0}")]
    Post(#[from] std::io::Error),
}

impl CarveError {
    /// The memory refusal, if this is one (so a caller can name its own option).
    pub fn over_budget(&self) -> Option<&OverBudget> {
        match self {
            CarveError::Memory(e) | CarveError::Plan(ReliefError::Memory(e)) => Some(e),
            _ => None,
        }
    }
}

/// Bytes of G-code text per move, an upper bound: `G1 X-1234.5678 Y-1234.5678 Z-123.4567
/// F12345` and its newline.
const TEXT_PER_MOVE: u64 = 48;

/// Grids the stages after planning hold at once: the design, the simulated stock, the ideal
/// surface (a dilation and an erosion, each through a padded copy, rows and their join, and
/// the negated field) and the preview's pixels.
const GRIDS_AFTER_PLANNING: u64 = 12;

/// What every move costs from planning to simulation: the move, its line of text and its
/// canonical operation.
pub fn bytes_per_move() -> u64 {
    (std::mem::size_of::<Move>() + std::mem::size_of::<Canon>()) as u64 + TEXT_PER_MOVE
}

/// Progress: stage name and fraction done.
pub type Progress<'a> = oficina_cam::relief::Progress<'a>;

/// Plans, posts, reads back, simulates and times `job` on `design` within `budget_bytes`.
/// `profile` gives the planner's time estimate (`None`: feed-only time only).
pub fn evaluate(
    design: &Heightmap,
    job: &ReliefJob,
    profile: Option<&oficina_motion::Profile>,
    post: &PostOptions,
    budget_bytes: u64,
    progress: Progress,
) -> Result<Evaluation, CarveError> {
    let last_tool = job
        .passes
        .last()
        .map(|p| p.cutter.tool.clone())
        .ok_or(CarveError::NoPasses)?;
    let grid = memory::grid_bytes(design.width, design.height);
    let reach = (last_tool.reach_radius() / design.pixel).ceil().min(1e9) as usize;
    let fixed = grid
        .saturating_mul(GRIDS_AFTER_PLANNING)
        .saturating_add(memory::kernel_bytes(reach));
    memory::check(
        || {
            format!(
                "simulating the {} x {} stock and its preview",
                design.width, design.height
            )
        },
        fixed,
        budget_bytes,
        Lever::PixelSize,
    )?;
    let budget = Budget {
        bytes: budget_bytes,
        reserved: fixed,
        per_move: bytes_per_move(),
    };
    let planned = plan_within(design, job, budget, progress)?;
    progress("writing G-code", 0.0);
    let program = program_text(&planned.toolpath, post)?;
    // Everything downstream judges the program as a machine would read it: the written
    // text through the interpreter, never the CAM's own idea of the moves.
    progress("interpreting the program", 0.0);
    let canon = interpret(&program, post)?;
    progress("simulating the stock", 0.0);
    let tools = planned.toolpath.tools();
    let mut stock = Heightmap::flat(design.width, design.height, design.pixel, 0.0);
    let start = [0.0, 0.0, job.safe_z];
    replay(&canon, &tools, &mut stock, start)?;
    let report = compare(&stock, design, &ideal_surface(design, &last_tool));
    progress("estimating time", 0.0);
    let feed_only_s = feed_only_estimate(&canon, start, 6000.0);
    let planner = match profile {
        Some(p) => oficina_motion::estimate(to_machine(&canon, job.safe_z + 1.0), p)
            .map(|e| e.seconds)
            .map_err(|e| e.to_string()),
        None => Err("no machine profile".into()),
    };
    Ok(Evaluation {
        planned,
        program,
        stock,
        report,
        feed_only_s,
        planner,
    })
}

/// The canonical operations of our own program. Any diagnostic means the post wrote
/// something the control would reject or misread: a bug, reported with its line.
pub fn interpret(program: &str, post: &PostOptions) -> Result<Vec<Canon>, CarveError> {
    use oficina_gcode::{run_text, RunOptions};
    // M6-capable grbl forks read tool changes as LinuxCNC does.
    let dialect = match post.dialect {
        PostDialect::Grbl if !post.allow_m6 => oficina_gcode::Dialect::Grbl,
        _ => oficina_gcode::Dialect::LinuxCnc,
    };
    let opts = RunOptions {
        dialect,
        ..RunOptions::default()
    };
    let mut canon = Vec::new();
    let diagnostics = run_text(program, &opts, &mut |c| canon.push(c));
    if let Some(d) = diagnostics.first() {
        let line = program.lines().nth(d.span.line.saturating_sub(1) as usize);
        return Err(CarveError::Interpreter {
            count: diagnostics.len(),
            first: d.render("<generated program>", line),
        });
    }
    Ok(canon)
}

/// The program placed in machine coordinates with the work zero `drop` mm below the
/// top of Z travel (the usual Z-zero-at-top router), so the planner's travel check passes;
/// times do not depend on where the work zero is. (The planner takes the F0 that G94 sets
/// before any F word as legal, as it is; feed moves check their own feed.)
pub fn to_machine(canon: &[Canon], drop: f64) -> impl Iterator<Item = Canon> + '_ {
    canon.iter().map(move |c| c.translated([0.0, 0.0, -drop]))
}
