//! Levelling a program while it streams: the interpreter reads it (so G91, arcs in any
//! plane, units and modal words are resolved once, by the one interpreter), and every move
//! below the clearance leaves as short straight pieces whose end Z follows the height map.
//! The output is grbl G-code in G90 absolute coordinates and the program's units, each line
//! tagged with the source line it came from.

use super::map::HeightMap;
use super::source::{classify, LineInfo};
use crate::job::{StreamLine, StreamProgram};
use crate::toolchange::{m6_words, sender_view};
use crate::{ToolChange, ToolPolicy};
use oficina_canon::{Canon, CanonOp, FeedMode, SpindleDir, Units};
use oficina_gcode::{Dialect, RunOptions, Severity};
use oficina_geom::{chord_count, Helix};

/// Most pieces one programmed move may become: past it the move is refused (raise the
/// segment length) rather than flooding the link.
const MAX_PIECES_PER_MOVE: u64 = 10_000_000;

/// How a program is levelled.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelOptions {
    /// Longest piece a move is cut into, measured in XY, mm (default 1; at most half the
    /// grid spacing is sensible).
    pub max_segment: f64,
    /// Largest distance between an arc and the chords replacing it, mm (default 0.01).
    pub arc_tolerance: f64,
    /// Moves whose ends are both at or above this work Z (mm) are sent unchanged; below it
    /// every point is offset by the map. `None`: the map's probing clearance.
    pub clearance: Option<f64>,
    /// How far outside the map a point may lie and still take the height of the map's edge
    /// (with one warning), mm. `None`: half the smaller grid spacing. Further out is an error.
    pub outside_allowance: Option<f64>,
    /// The dialect the program is read in (grbl by default: the output goes to grbl).
    pub dialect: Dialect,
    /// How the sender that streams the output handles `M6` (`None`: the output is a file
    /// for another sender, or the firmware's own: `M6` is refused, see [`level_program`]).
    pub tool_change: Option<ToolChange>,
}

impl Default for LevelOptions {
    fn default() -> Self {
        LevelOptions {
            max_segment: 1.0,
            arc_tolerance: 0.01,
            clearance: None,
            outside_allowance: None,
            dialect: Dialect::Grbl,
            tool_change: None,
        }
    }
}

/// What levelling did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LevelReport {
    /// Lines written.
    pub lines: usize,
    /// Programmed moves that went below the clearance: cut into pieces, their ends offset.
    pub levelled_moves: usize,
    /// Smallest and largest Z offset applied, mm (0, 0 when none was).
    pub offset_range: (f64, f64),
    /// Things the operator should know (points beyond the map's edge).
    pub warnings: Vec<String>,
}

/// Levels `text` with `map`, writing each output line to `out` as it is made (constant
/// memory whatever the program's size). The first thing that cannot be levelled safely is
/// an error naming its source line; lines already written are then to be discarded.
pub fn level_program(
    text: &str,
    map: &HeightMap,
    opts: &LevelOptions,
    out: &mut dyn FnMut(StreamLine),
) -> Result<LevelReport, String> {
    if !(opts.max_segment.is_finite() && opts.max_segment >= 0.01) {
        return Err(format!(
            "segment length {}: must be at least 0.01 mm",
            opts.max_segment
        ));
    }
    if !(opts.arc_tolerance.is_finite() && opts.arc_tolerance >= 1e-4) {
        return Err(format!(
            "arc tolerance {}: must be at least 0.0001 mm",
            opts.arc_tolerance
        ));
    }
    map.check()?;
    // M6 passes through to the sender's tool-change policy, as in a plain job, where the
    // map stays valid after the change:
    // - `remeasure`: the new tool is measured on the setter against the first tool and the
    //   difference applied with G43.1, so the tip is where the first tool's was: the map,
    //   probed with the first tool, still describes the surface.
    // - `pause` / `park`: the operator changes the tool and zeroes Z again on the stock by
    //   hand. The map holds heights relative to the Z zero it was probed under, so it stays
    //   valid when Z is zeroed again at that same place (a warning says so).
    // - `ignore`: the tool is not changed, nor its length: the map holds (a warning says
    //   the job is cut with the first tool).
    // - `firmware`, or no sender (a file for another sender): what happens to the tool
    //   length at M6 is not ours to know, so M6 is refused.
    let passes = opts
        .tool_change
        .as_ref()
        .filter(|tc| tc.policy != ToolPolicy::Firmware);
    let viewed;
    let interpreted = match passes {
        Some(tc) => {
            tc.validate()?;
            // M6 (and T under `ignore`) blanked: the interpreter reads what grbl will
            // get; the transform writes the M6 back where it stood for the sender.
            viewed = String::from_utf8_lossy(&sender_view(text.as_bytes(), tc).0).into_owned();
            viewed.as_str()
        }
        None => {
            refuse_m6(text, opts.tool_change.as_ref())?;
            text
        }
    };
    let clearance = opts.clearance.unwrap_or(map.clearance);
    let (_, top) = map.z_range();
    if !(clearance.is_finite() && clearance > top) {
        return Err(format!(
            "clearance Z{clearance} is not above the highest probed point Z{top:.3}: moves at the clearance would hit the stock"
        ));
    }
    let allowance = opts
        .outside_allowance
        .unwrap_or(0.5 * map.spacing[0].min(map.spacing[1]));
    if !(allowance.is_finite() && allowance >= 0.0) {
        return Err(format!(
            "outside allowance {allowance}: must be 0 or more, mm"
        ));
    }
    let mut l = Leveller {
        map,
        clearance,
        allowance,
        max_segment: opts.max_segment,
        arc_tolerance: opts.arc_tolerance,
        out,
        src: text.lines(),
        src_line: 0,
        info: LineInfo::default(),
        incremental: false,
        at: [None; 3],
        k: 1.0,
        units: None,
        motion: None,
        pending_feed: None,
        coolant: (false, false),
        coolant_sent: (false, false),
        coolant_line: 0,
        levelled: false,
        tool_change: passes.map(|tc| tc.policy),
        m6_line: 0,
        error: None,
        report: LevelReport {
            offset_range: (f64::INFINITY, f64::NEG_INFINITY),
            ..LevelReport::default()
        },
    };
    let run = RunOptions {
        dialect: opts.dialect,
        ..RunOptions::default()
    };
    let diagnostics = oficina_gcode::run_text(interpreted, &run, &mut |c| l.take(c));
    if let Some(d) = diagnostics.iter().find(|d| d.severity == Severity::Error) {
        return Err(format!("line {}: {}", d.span.line, d.message));
    }
    if let Some(e) = l.error.take() {
        return Err(e);
    }
    l.flush_coolant();
    let mut report = l.report;
    if report.offset_range.0 > report.offset_range.1 {
        report.offset_range = (0.0, 0.0);
    }
    Ok(report)
}

/// [`level_program`] into a [`StreamProgram`] named `name`, ready for the sender: its lines
/// keep the source line numbers, so progress and resume name the user's lines.
///
/// ```
/// use oficina_grbl::{level_stream, HeightMap, LevelOptions};
///
/// // A plane rising 0.01 mm per mm of X, probed at X0 and X10 (Y0 and Y10).
/// let map = HeightMap::new([0.0, 0.0], [10.0, 10.0], 2, 2, vec![0.0, 0.1, 0.0, 0.1], 3.0).unwrap();
/// let text = "G21 G90\nG0 X0 Y5 Z5\nG1 Z-0.2 F300\nG1 X2\nG0 Z5\n";
/// let (program, report) = level_stream("cut.nc", text, &map, &LevelOptions::default()).unwrap();
/// let lines: Vec<_> = program.lines.iter().map(|l| (l.file_line, l.text.as_str())).collect();
/// assert_eq!(
///     lines,
///     [
///         (1, "G21"),
///         (1, "G90"),
///         (2, "G0X0Y5Z5"),
///         (3, "G1X0Y5Z-0.2F300"),
///         (4, "X1Y5Z-0.19"),
///         (4, "X2Y5Z-0.18"),
///         (5, "G0X2Y5Z5"),
///     ]
/// );
/// // The plunge, the cut and the retract went below the clearance.
/// assert_eq!(report.levelled_moves, 3);
/// ```
pub fn level_stream(
    name: &str,
    text: &str,
    map: &HeightMap,
    opts: &LevelOptions,
) -> Result<(StreamProgram, LevelReport), String> {
    let mut lines = Vec::new();
    let report = level_program(text, map, opts, &mut |l| lines.push(l))?;
    let mut program = StreamProgram {
        name: name.to_string(),
        lines,
        tool_change: ToolChange::as_written(),
        tool_stops: Vec::new(),
    };
    // The M6 lines the transform wrote back become the sender's tool stops, as in a plain
    // job (without a policy that passes them, the transform refused them).
    if let Some(tc) = opts
        .tool_change
        .as_ref()
        .filter(|tc| tc.policy != ToolPolicy::Firmware)
    {
        program.take_tool_changes(text, tc);
    }
    Ok((program, report))
}

/// The first `M6` of `text`, refused: no sender policy passes it through.
fn refuse_m6(text: &str, tc: Option<&ToolChange>) -> Result<(), String> {
    for (i, raw) in text.lines().enumerate() {
        let Ok(clean) = crate::gline::clean(raw) else {
            continue;
        };
        if m6_words(clean.as_bytes(), ToolPolicy::Pause).is_some() {
            let why = match tc {
                Some(_) => "with --tool-change firmware the firmware changes the tool, and what that does to the tool length the map was probed with is not known: levelling with tool changes needs the sender's remeasure (or pause) policy",
                None => "a levelled file for another sender cannot carry a tool change (the new tool's length is not the one the map was probed with): run it levelled with oficina's sender (`oficina run --level … --tool-change remeasure`), or level each tool's part on its own",
            };
            return Err(format!("line {}: M6: {why}", i + 1));
        }
    }
    Ok(())
}

/// [`level_program`] as the text of a G-code file (for any sender), opened by a comment
/// saying what it is.
pub fn level_text(
    text: &str,
    map: &HeightMap,
    opts: &LevelOptions,
    header: &str,
) -> Result<(String, LevelReport), String> {
    let mut s = String::new();
    for h in header.lines() {
        s.push_str(&format!("({})\n", h.replace(['(', ')'], "")));
    }
    let report = level_program(text, map, opts, &mut |l| {
        s.push_str(&l.text);
        s.push('\n');
    })?;
    Ok((s, report))
}

/// The transform's state between canonical operations.
struct Leveller<'a, 'o> {
    map: &'a HeightMap,
    clearance: f64,
    allowance: f64,
    max_segment: f64,
    arc_tolerance: f64,
    out: &'o mut dyn FnMut(StreamLine),
    /// The source lines, read in step with the operations (grbl's dialect never goes back).
    src: std::str::Lines<'a>,
    /// The source line `info` describes (0: none yet).
    src_line: u32,
    info: LineInfo,
    incremental: bool,
    /// Where the tool is in work coordinates (mm), per axis; `None` until the program names
    /// the axis (the interpreter's own start at 0 is a guess, never sent).
    at: [Option<f64>; 3],
    /// Millimetres per output unit (the program's units), and those units once written.
    k: f64,
    units: Option<Units>,
    /// The motion word last written (0 or 1), so repeated ones are left out.
    motion: Option<u8>,
    /// A feed (mm/min) to write with the next feed move.
    pending_feed: Option<f64>,
    /// Mist, flood: as the program wants them, as last written, and the line that asked.
    coolant: (bool, bool),
    coolant_sent: (bool, bool),
    coolant_line: u32,
    /// The move being written was cut into offset pieces.
    levelled: bool,
    /// The sender's policy for `M6`, when it passes through (`None`: refused before).
    tool_change: Option<ToolPolicy>,
    /// The last source line whose `M6` was written back (its `T` went with it).
    m6_line: u32,
    error: Option<String>,
    report: LevelReport,
}

impl Leveller<'_, '_> {
    fn take(&mut self, c: Canon) {
        if self.error.is_some() {
            return;
        }
        if let Err(e) = self.op(c) {
            self.error = Some(e);
        }
    }

    fn emit(&mut self, line: u32, text: String) {
        self.flush_coolant();
        self.report.lines += 1;
        (self.out)(StreamLine {
            file_line: line.max(1) as usize,
            text,
        });
    }

    /// Reads source lines up to `line` and classifies it.
    fn seek(&mut self, line: u32) -> Result<(), String> {
        if line < self.src_line {
            return Err(format!(
                "line {line}: the program goes back to an earlier line (subroutine or loop): not supported while levelling"
            ));
        }
        if self.src_line < line {
            // The coolant a finished line asked for goes out with its line number.
            self.flush_coolant();
        }
        while self.src_line < line {
            let text = self.src.next().unwrap_or("");
            self.src_line += 1;
            // Every line, those without operations too: G90 / G91 alone change the mode.
            self.info = classify(text, self.src_line, self.incremental)?;
            self.incremental = self.info.incremental;
            if let Some(policy) = self.tool_change {
                if let Some((tool, _)) = m6_words(self.info.clean.as_bytes(), policy) {
                    self.tool_change(self.src_line, policy, tool);
                }
            }
            if self.src_line == line && self.info.machine_move {
                // Sent as written: no motion word of ours is in force after it.
                self.motion = None;
                let t = self.info.clean.clone();
                self.emit(line, t);
            }
        }
        Ok(())
    }

    fn op(&mut self, c: Canon) -> Result<(), String> {
        let line = c.line;
        if line == 0 {
            return self.start_op(c.op);
        }
        self.seek(line)?;
        let at = |what: &str| format!("line {line}: {what}");
        if self.info.machine_move {
            // The line went out as written; what it moves is unknown from here.
            if c.op.is_motion() {
                for a in 0..3 {
                    if self.info.goes_home || self.info.names[a] {
                        self.at[a] = None;
                    }
                }
            }
            return Ok(());
        }
        if self.info.ends_program
            && matches!(
                c.op,
                CanonOp::SetG5xOffset { .. }
                    | CanonOp::StopSpindle
                    | CanonOp::MistOff
                    | CanonOp::FloodOff
            )
        {
            // Program end: grbl resets these itself.
            return Ok(());
        }
        match c.op {
            CanonOp::UseLengthUnits(u) => self.units(line, u),
            CanonOp::SetG5xOffset { index, offset } => {
                if offset.to_array().iter().any(|v| *v != 0.0) {
                    return Err(at("the work offset changes inside the program"));
                }
                let name = match index {
                    1..=6 => format!("G{}", 53 + index),
                    _ => return Err(at("G59.1 … G59.3 are not grbl's")),
                };
                if let Some(w) = &self.map.wcs {
                    if *w != name {
                        return Err(at(&format!(
                            "{name}: the height map was probed in {w}; probe in the coordinate system the program uses"
                        )));
                    }
                }
                self.emit(line, name);
            }
            CanonOp::SetG92Offset(p) if p.to_array().iter().any(|v| *v != 0.0) => {
                return Err(at("G92 offset in force: cannot level"))
            }
            CanonOp::SetXyRotation(r) if r != 0.0 => {
                return Err(at("rotated coordinates cannot be levelled"))
            }
            CanonOp::SetFeedMode(FeedMode::UnitsPerMinute) => {}
            CanonOp::SetFeedMode(_) => {
                return Err(at(
                    "inverse-time or per-revolution feed cannot be levelled: use G94",
                ))
            }
            CanonOp::SetFeedRate(f) => self.pending_feed = Some(f),
            CanonOp::StraightTraverse { to } => self.straight(line, 0, [to.x, to.y, to.z])?,
            CanonOp::StraightFeed { to } => self.straight(line, 1, [to.x, to.y, to.z])?,
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                if rotation != 0.0 {
                    return Err(at("an arc in a rotated plane cannot be levelled"));
                }
                let Some(from) = self.known() else {
                    return Err(at(
                        "an arc from an unknown position: move to a known X Y Z first",
                    ));
                };
                let to = [end.x, end.y, end.z];
                self.arc(line, from, Helix::new(plane, from, to, center, turns), to)?;
            }
            CanonOp::Dwell(s) => self.emit(line, format!("G4P{}", num(s, 3))),
            CanonOp::SetSpindleSpeed(s) => self.emit(line, format!("S{}", num(s, 1))),
            CanonOp::StartSpindle(SpindleDir::Clockwise) => self.emit(line, "M3".into()),
            CanonOp::StartSpindle(SpindleDir::CounterClockwise) => self.emit(line, "M4".into()),
            CanonOp::StopSpindle => self.emit(line, "M5".into()),
            CanonOp::MistOn => self.coolant_to(line, (true, self.coolant.1)),
            CanonOp::FloodOn => self.coolant_to(line, (self.coolant.0, true)),
            CanonOp::MistOff => self.coolant_to(line, (false, self.coolant.1)),
            CanonOp::FloodOff => self.coolant_to(line, (self.coolant.0, false)),
            // An M6 line's T went out with its M6.
            CanonOp::SelectTool(_) if line == self.m6_line => {}
            CanonOp::SelectTool(t) => self.emit(line, format!("T{t}")),
            CanonOp::ChangeTool(_) => {
                // The interpreter sees M6 only when no sender policy takes it (refused
                // before it runs): kept as a guard.
                return Err(at(
                    "M6: a new tool changes the tool length the map was probed with; run levelled with --tool-change remeasure, or level each tool's part on its own",
                ));
            }
            CanonOp::UseToolLengthOffset(p) if p.to_array().iter().any(|v| *v != 0.0) => {
                return Err(at("a tool length offset changes inside the program"))
            }
            CanonOp::ProgramStop => self.emit(line, "M0".into()),
            CanonOp::OptionalProgramStop => self.emit(line, "M1".into()),
            CanonOp::ProgramEnd => self.emit(line, "M2".into()),
            CanonOp::OrientSpindle { .. }
            | CanonOp::WaitOrientComplete(_)
            | CanonOp::StartSpeedFeedSync { .. }
            | CanonOp::StopSpeedFeedSync
            | CanonOp::RigidTap { .. } => {
                return Err(at(
                    "spindle-synchronised motion and orientation cannot be levelled",
                ))
            }
            // Plane (arcs go out as chords), path control, overrides, comments and
            // messages: nothing for grbl to do.
            _ => {}
        }
        Ok(())
    }

    /// An `M6` the sender handles, written back before the rest of its line (grbl's order:
    /// the change comes before the line's motion), with its `T` word.
    fn tool_change(&mut self, line: u32, policy: ToolPolicy, tool: Option<u32>) {
        let t = tool.map(|t| format!("T{t}")).unwrap_or_default();
        let name = if t.is_empty() {
            "M6".to_string()
        } else {
            format!("M6 {t}")
        };
        match policy {
            ToolPolicy::Ignore => self.report.warnings.push(format!(
                "line {line}: {name} dropped (--tool-change ignore): the whole job is cut with the tool the map was probed with"
            )),
            ToolPolicy::Pause | ToolPolicy::ParkPause => self.report.warnings.push(format!(
                "line {line}: {name} with --tool-change {}: zero Z again where it was zeroed before probing (the map's heights are relative to that zero), or use remeasure",
                policy.name()
            )),
            ToolPolicy::Remeasure | ToolPolicy::Firmware => {}
        }
        self.m6_line = line;
        self.emit(line, format!("{t}M6"));
    }

    /// The interpreter's opening state: the header of the output.
    fn start_op(&mut self, op: CanonOp) -> Result<(), String> {
        if let CanonOp::UseLengthUnits(u) = op {
            self.units(0, u);
            self.emit(0, "G90".into());
        }
        Ok(())
    }

    fn units(&mut self, line: u32, u: Units) {
        if self.units == Some(u) {
            return;
        }
        self.units = Some(u);
        self.k = u.mm();
        self.emit(
            line,
            match u {
                Units::Mm => "G21",
                Units::Inch => "G20",
            }
            .into(),
        );
    }

    /// Coolant goes out when something else does (or at the end), so the pair of
    /// operations M9 makes (mist off, flood off) becomes one M9: grbl's only off is M9
    /// (both), after which what stays on is turned back on.
    fn flush_coolant(&mut self) {
        let (was, want) = (self.coolant_sent, self.coolant);
        if want == was {
            return;
        }
        self.coolant_sent = want;
        let off = (was.0 && !want.0) || (was.1 && !want.1);
        let mut say = |s: &str| {
            self.report.lines += 1;
            (self.out)(StreamLine {
                file_line: self.coolant_line.max(1) as usize,
                text: s.into(),
            })
        };
        if off {
            say("M9");
        }
        if want.0 && (off || !was.0) {
            say("M7");
        }
        if want.1 && (off || !was.1) {
            say("M8");
        }
    }

    fn coolant_to(&mut self, line: u32, want: (bool, bool)) {
        if self.coolant == self.coolant_sent {
            self.coolant_line = line;
        }
        self.coolant = want;
    }

    /// The current position when every axis is known.
    fn known(&self) -> Option<[f64; 3]> {
        match self.at {
            [Some(x), Some(y), Some(z)] => Some([x, y, z]),
            _ => None,
        }
    }

    fn straight(&mut self, line: u32, motion: u8, to: [f64; 3]) -> Result<(), String> {
        if let Some(from) = self.known() {
            self.levelled = false;
            self.segment(line, motion, from, to)?;
            if self.levelled {
                self.report.levelled_moves += 1;
            }
            return Ok(());
        }
        // From an unknown position: send only the axes the program has given, as one move.
        let mut after = self.at;
        for a in 0..3 {
            if self.info.names[a] {
                if self.info.incremental && self.at[a].is_none() {
                    return Err(format!(
                        "line {line}: an incremental (G91) move from an unknown position: start with an absolute move"
                    ));
                }
                after[a] = Some(to[a]);
            }
        }
        if let [Some(x), Some(y), Some(z)] = after {
            self.at = after;
            let z = self.offset(line, [x, y, z])?;
            return self.write_move(line, motion, [Some(x), Some(y), Some(z)]);
        }
        if let Some(z) = after[2] {
            if z < self.clearance {
                return Err(format!(
                    "line {line}: a move below the clearance (Z{}) before X and Y are known: start with a move to X Y at a safe height",
                    num(z / self.k, 4)
                ));
            }
        }
        self.at = after;
        let send = [0, 1, 2].map(|a| if self.info.names[a] { after[a] } else { None });
        if send.iter().all(|v| v.is_none()) {
            return Ok(());
        }
        self.write_move(line, motion, send)
    }

    /// An arc as chords within the tolerance, each chord levelled as a straight move.
    fn arc(&mut self, line: u32, from: [f64; 3], helix: Helix, to: [f64; 3]) -> Result<(), String> {
        let n = chord_count(helix.arc.radius, helix.arc.sweep, self.arc_tolerance);
        let mut from = from;
        self.levelled = false;
        for k in 1..=n {
            let p = if k == n {
                to
            } else {
                helix.point_at(k as f64 / n as f64)
            };
            self.segment(line, 1, from, p)?;
            from = p;
        }
        if self.levelled {
            self.report.levelled_moves += 1;
        }
        Ok(())
    }

    /// A straight move between known points: whole when both ends are at or above the
    /// clearance, else in pieces of at most `max_segment` in XY, each end offset by the map.
    fn segment(&mut self, line: u32, motion: u8, a: [f64; 3], b: [f64; 3]) -> Result<(), String> {
        self.at = b.map(Some);
        if a[2] >= self.clearance && b[2] >= self.clearance {
            return self.write_move(line, motion, b.map(Some));
        }
        let xy = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = (xy / self.max_segment).ceil().max(1.0);
        if n > MAX_PIECES_PER_MOVE as f64 {
            return Err(format!(
                "line {line}: a {xy:.0} mm move would become {n:.0} pieces of {} mm: raise the segment length",
                self.max_segment
            ));
        }
        let n = n as u64;
        self.levelled = true;
        for k in 1..=n {
            // The last piece ends exactly on the programmed end point.
            let p = if k == n {
                b
            } else {
                let t = k as f64 / n as f64;
                [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
            };
            let z = self.offset(line, p)?;
            self.write_move(line, motion, [Some(p[0]), Some(p[1]), Some(z)])?;
        }
        Ok(())
    }

    /// The Z to send for work point `p`: below the clearance, `p.z` plus the surface height
    /// under it.
    fn offset(&mut self, line: u32, p: [f64; 3]) -> Result<f64, String> {
        if p[2] >= self.clearance {
            return Ok(p[2]);
        }
        let outside = self.map.outside_by(p[0], p[1]);
        if outside > self.allowance {
            let [x1, y1] = self.map.max_corner();
            return Err(format!(
                "line {line}: X{} Y{} is {outside:.3} mm outside the height map (X{:.3}…{x1:.3}, Y{:.3}…{y1:.3}): probe a grid that covers the program",
                num(p[0] / self.k, 4),
                num(p[1] / self.k, 4),
                self.map.origin[0],
                self.map.origin[1]
            ));
        }
        if outside > 1e-9 && self.report.warnings.is_empty() {
            self.report.warnings.push(format!(
                "line {line}: X{} Y{} is {outside:.3} mm outside the height map: the height at its edge is used (further points outside are not reported)",
                num(p[0] / self.k, 4),
                num(p[1] / self.k, 4)
            ));
        }
        let dz = self.map.height(p[0], p[1]);
        let r = &mut self.report.offset_range;
        *r = (r.0.min(dz), r.1.max(dz));
        Ok(p[2] + dz)
    }

    /// One move line: the motion word when it changes, the given axes in program units,
    /// and a pending feed on a feed move.
    fn write_move(&mut self, line: u32, motion: u8, p: [Option<f64>; 3]) -> Result<(), String> {
        let mut s = String::new();
        if self.motion != Some(motion) {
            s.push_str(if motion == 0 { "G0" } else { "G1" });
            self.motion = Some(motion);
        }
        let digits = if self.k == 1.0 { 4 } else { 5 };
        for (letter, v) in ['X', 'Y', 'Z'].into_iter().zip(p) {
            if let Some(v) = v {
                s.push(letter);
                s.push_str(&num(v / self.k, digits));
            }
        }
        if motion == 1 {
            if let Some(f) = self.pending_feed.take() {
                s.push('F');
                s.push_str(&num(f / self.k, 3));
            }
        }
        self.emit(line, s);
        Ok(())
    }
}

/// `v` with at most `digits` decimals, no trailing zeros, no `-0`.
fn num(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}
