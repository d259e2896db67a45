//! The modal interpreter: evaluated blocks → canonical operations, in LinuxCNC's order of
//! execution (`overview.adoc`, "Order of Execution").
//!
//! Positions are kept in program coordinates (mm) as LinuxCNC does; every motion is emitted
//! in machine coordinates through the [`frame::Frame`] chain, and every change of an offset is
//! emitted too, so a printer can go back to program coordinates.

pub(crate) mod arcs;
pub(crate) mod comp;
mod context;
pub(crate) mod cycles;
pub(crate) mod dialect;
pub(crate) mod frame;
mod inputs;
mod lathe_cycle;
mod motion;
mod offsets;
mod probe;
mod simple;
mod spindle_mode;
pub(crate) mod splines;
pub(crate) mod state;
mod threading;
pub(crate) mod tool_table;
pub(crate) mod words;

use crate::block::{Block, Note};
use crate::diag::{Diagnostic, Span};
use crate::params::Params;
use crate::Dialect;
use frame::Frame;
use oficina_canon::{
    Canon, CanonOp, FeedMode, PathControlMode, Plane, Pos, SpindleDir, SpindleMode, Units,
};
use state::{Modal, Motion, Side};
use tool_table::ToolTable;
use words::{g_group as G, m_group as M, Decoded};

/// What the caller should do after a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on with the next block.
    Continue,
    /// M2 / M30: the program ended.
    End,
    /// A G70–G72 lathe cycle: the caller reads the profile subroutine
    /// ([`Interpreter::lathe_profile_call`]) into [`Interpreter::profile_block`], then
    /// calls [`Interpreter::finish_lathe_cycle`].
    ReadProfile,
}

/// How a run starts.
#[derive(Clone, Debug)]
pub struct StartState {
    /// Length units before the program sets them (G20/G21).
    pub units: Units,
    /// Feed (mm/min) before the program sets one; the legacy dialect takes its feed from
    /// the machine configuration, never from F words.
    pub feed: f64,
    /// Units of the G28/G30 home parameters (#5161…, #5181…): LinuxCNC keeps them in
    /// machine units; the standalone `rs274` uses inches.
    pub machine_units: Units,
}

impl Default for StartState {
    fn default() -> Self {
        StartState {
            units: Units::Mm,
            feed: 0.0,
            machine_units: Units::Mm,
        }
    }
}

/// Feed of the legacy dialect when the run gives none (mm/min): the seed takes its feed
/// from the machine configuration, never from the program.
pub(crate) const LEGACY_DEFAULT_FEED: f64 = 600.0;

/// Where the operations go.
pub(crate) type Sink<'a> = &'a mut dyn FnMut(Canon);

/// LinuxCNC's parameter numbers.
pub(crate) mod param {
    pub(crate) const G28_HOME: i64 = 5161;
    pub(crate) const G30_HOME: i64 = 5181;
    pub(crate) const G92_ENABLED: i64 = 5210;
    pub(crate) const G92_OFFSET: i64 = 5211;
    pub(crate) const COORD_SYSTEM: i64 = 5220;
    /// G54 X; system n (1-based) starts at `G5X_BASE + 20·(n−1)`, R (rotation) at +9.
    pub(crate) const G5X_BASE: i64 = 5221;
    pub(crate) const TOOL_NUMBER: i64 = 5400;
    pub(crate) const POSITION: i64 = 5420;
    /// #5061–#5069: the last probed point (X … W), #5070: whether the probe tripped.
    pub(crate) const PROBE_POSITION: i64 = 5061;
}

/// The modal interpreter: turns blocks into canonical operations, keeping the modal state
/// between them.
pub struct Interpreter {
    /// The dialect blocks are interpreted in.
    pub dialect: Dialect,
    /// The modal state (motion mode, plane, units, feed, …).
    pub modal: Modal,
    /// Current point in program coordinates, mm (A B C degrees).
    pub pos: [f64; 6],
    /// The offsets between program and machine coordinates.
    pub frame: Frame,
    /// The tools the machine knows.
    pub tools: ToolTable,
    /// Degrees added to every M19 angle (LinuxCNC's `[RS274NGC]ORIENT_OFFSET`).
    pub orient_offset: f64,
    /// Emit each spline whole, as one [`CanonOp::Spline`], instead of traced into feeds
    /// (see `splines.rs`); off by default.
    pub whole_splines: bool,
    machine_units: Units,
    pub(crate) cycle: cycles::CycleMemory,
    pub(crate) comp: comp::CompState,
    pub(crate) spline: splines::SplineMemory,
    contexts: context::Contexts,
    /// The target of a probing move of this block, for #5061… (set after the block).
    probed: Option<[f64; 6]>,
    line: u32,
    /// Scratch for the block being run (see [`Interpreter::execute`]).
    decoded: Option<Box<Decoded>>,
    /// The G7x cycle whose profile is being read.
    lathe: Option<Box<lathe_cycle::Pending>>,
}

/// Marlin's feed at power-up, mm/min.
const MARLIN_DEFAULT_FEED: f64 = 1500.0;

/// Axis letters in [`Pos::to_array`] order.
pub(crate) const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

impl Interpreter {
    /// An interpreter in `dialect`, starting from `start`, with `tools`.
    pub fn new(dialect: Dialect, start: &StartState, tools: ToolTable) -> Interpreter {
        let mut modal = Modal::new(start.units);
        modal.feed = start.feed;
        if dialect == Dialect::Grbl {
            // grbl's gc_init zeroes its state: the motion mode at power-up is G0.
            modal.motion = Motion::Rapid;
        }
        if dialect == Dialect::Legacy2006 {
            // Seed 002: I and J are absolute centres; the feed is the machine's.
            modal.arc_incremental = false;
            if modal.feed <= 0.0 {
                modal.feed = LEGACY_DEFAULT_FEED;
            }
        }
        if dialect == Dialect::Marlin && modal.feed <= 0.0 {
            // Marlin starts with a feed (motion.cpp: `feedrate_mm_s = MMM_TO_MMS(1500)`).
            modal.feed = MARLIN_DEFAULT_FEED;
        }
        Interpreter {
            dialect,
            modal,
            pos: [0.0; 6],
            frame: Frame::default(),
            tools,
            orient_offset: 0.0,
            whole_splines: false,
            machine_units: start.machine_units,
            cycle: cycles::CycleMemory::default(),
            comp: comp::CompState::default(),
            spline: splines::SplineMemory::default(),
            contexts: context::Contexts::default(),
            probed: None,
            line: 0,
            decoded: None,
            lathe: None,
        }
    }

    /// The operations that describe the start state (LinuxCNC's `rs274` prints them too).
    pub fn begin(&mut self, params: &mut Params, sink: Sink) {
        let line = 0;
        let emit = &mut |op| sink(Canon { line, op });
        emit(CanonOp::UseLengthUnits(self.modal.units));
        self.load_coord_system(params, self.modal.coord_system);
        // A G92 offset in force when the parameters were saved (#5210 set) is in force again
        // (rs274ngc_pre.cc init; DISABLE_G92_PERSISTENCE has zeroed #5210–#5219 before).
        if params.get(param::G92_ENABLED).unwrap_or(0.0) != 0.0 {
            for i in 0..6 {
                let s = if i < 3 { self.mk() } else { 1.0 };
                self.frame.g92[i] = params.get(param::G92_OFFSET + i as i64).unwrap_or(0.0) * s;
            }
        }
        emit(CanonOp::SetG5xOffset {
            index: 1,
            offset: Pos::from_array(self.frame.g5x),
        });
        emit(CanonOp::SetG92Offset(Pos::from_array(self.frame.g92)));
        emit(CanonOp::SetXyRotation(self.frame.rotation));
        if self.modal.feed > 0.0 {
            emit(CanonOp::SetFeedRate(self.modal.feed));
        }
        self.update_params(params);
    }

    /// End of input without M2/M30: emit what cutter compensation still holds.
    pub fn finish(&mut self, sink: Sink) {
        self.comp_flush(sink);
    }

    /// Millimetres per program unit.
    fn k(&self) -> f64 {
        self.modal.units.mm()
    }

    /// Millimetres per machine unit: the unit of every offset parameter (#5161…, #5211…,
    /// #5221…), as LinuxCNC stores them.
    fn mk(&self) -> f64 {
        self.machine_units.mm()
    }

    pub(crate) fn emit(&self, sink: Sink, op: CanonOp) {
        let op = Canon {
            line: self.line,
            op,
        };
        // Usually nothing is held (no cutter compensation): straight to the sink, without
        // the tail's borrow and the operation's moves in and out of `hold`.
        if !self.comp.is_holding() {
            sink(op);
        } else if let Some(op) = self.comp.hold(op) {
            sink(op);
        }
    }

    /// An error at `span`; in the grbl dialect it carries grbl's error number.
    pub(crate) fn fail(&self, span: Span, message: impl Into<String>, grbl: u16) -> Diagnostic {
        let d = Diagnostic::error(span, message);
        if self.dialect == Dialect::Grbl && grbl != 0 {
            dialect::grbl_error(d, grbl)
        } else {
            d
        }
    }

    pub(crate) fn machine(&self, p: [f64; 6]) -> Pos {
        Pos::from_array(self.frame.to_machine(p))
    }

    /// Replace the offset chain and keep the machine where it is: the program position moves.
    pub(crate) fn set_frame(&mut self, f: Frame) {
        let m = self.frame.to_machine(self.pos);
        self.frame = f;
        self.pos = self.frame.to_program(m);
    }

    /// Run one block.
    pub fn execute(
        &mut self,
        block: &Block,
        params: &mut Params,
        sink: Sink,
    ) -> Result<Flow, Diagnostic> {
        match self.simple_move(block, params, sink) {
            Some(flow) => Ok(flow),
            None => self.execute_full(block, params, sink),
        }
    }

    /// [`Interpreter::execute`] without the short way for simple moves.
    ///
    /// Never inlined: inside `execute` its large frame was set up for every block, the
    /// short way's too.
    #[inline(never)]
    fn execute_full(
        &mut self,
        block: &Block,
        params: &mut Params,
        sink: Sink,
    ) -> Result<Flow, Diagnostic> {
        self.line = block.line;
        // The decoded block lives in a reused box: taken out for the block, put back after.
        let mut d = self
            .decoded
            .take()
            .unwrap_or_else(|| Box::new(Decoded::empty()));
        let result = self.execute_decoded(&mut d, block, params, sink);
        self.decoded = Some(d);
        result
    }

    fn execute_decoded(
        &mut self,
        d: &mut Decoded,
        block: &Block,
        params: &mut Params,
        sink: Sink,
    ) -> Result<Flow, Diagnostic> {
        d.fill(block).map_err(|e| match self.dialect {
            Dialect::Grbl => dialect::grbl_code_for_decode(e),
            _ => e.diag,
        })?;
        match self.dialect {
            Dialect::Grbl => dialect::check_grbl(self, d)?,
            Dialect::Legacy2006 => {
                dialect::refuse_probe(d)?;
                dialect::translate_legacy(d)
            }
            Dialect::Marlin => dialect::refuse_probe(d)?,
            Dialect::LinuxCnc => {}
        }
        self.check_words(d)?;
        let flow = self.run_block(d, block, params, sink)?;
        self.update_params(params);
        Ok(flow)
    }

    /// Words that nothing in the block would use, and pairs that cannot go together.
    fn check_words(&self, d: &Decoded) -> Result<(), Diagnostic> {
        let motion = d
            .g_in(G::MOTION)
            .map(Motion::from_tenths)
            .unwrap_or(self.modal.motion);
        let non_modal = d.g_in(G::NON_MODAL);
        let moving = d.g[G::MOTION].is_some() || d.any_axis();
        let arc = moving && matches!(motion, Motion::Clockwise | Motion::CounterClockwise);
        let lathe = d.g[G::MOTION].is_some()
            && matches!(motion, Motion::Cycle(c) if lathe_cycle::is_lathe_cycle(c));
        let cycle = moving && !lathe && matches!(motion, Motion::Cycle(_));
        let spline =
            |codes: &[u16]| moving && matches!(motion, Motion::Spline(t) if codes.contains(&t));
        let g10 = non_modal == Some(100);
        if let Some(code) = non_modal {
            let uses_axes = matches!(code, 100 | 280 | 300 | 520 | 920);
            if uses_axes && d.g[G::MOTION].is_some() && d.any_axis() {
                return Err(self.fail(
                    d.g_span(G::NON_MODAL),
                    "Cannot use two g codes that both use axis values",
                    24,
                ));
            }
            if code == 530 && !matches!(motion, Motion::Rapid | Motion::Linear) {
                return Err(self
                    .fail(d.g_span(G::NON_MODAL), "Must use g0 or g1 with g53", 30)
                    .with_help("G53 moves in machine coordinates with G0 or G1 only"));
            }
        }
        if d.has('@') || d.has('^') {
            for l in ['X', 'Y'] {
                if d.has(l) {
                    return Err(self.fail(
                        d.span_of(l),
                        format!("Cannot specify both polar coordinate and {l} word"),
                        0,
                    ));
                }
            }
        }
        let axis_users = matches!(non_modal, Some(100 | 280 | 300 | 520 | 920))
            || d.g_in(G::TOOL_LENGTH) == Some(431);
        if d.any_axis() && !axis_users && motion == Motion::Off {
            let msg = if d.g_in(G::MOTION) == Some(800)
                || self.modal.motion == Motion::Off && d.g[G::MOTION].is_some()
            {
                "Cannot use axis values with g80"
            } else {
                "Cannot use axis values without a g code that uses them"
            };
            return Err(self
                .fail(d.axis_span(), msg, 31)
                .with_help("give a motion code (G0, G1, G2, G3, or a canned cycle) first"));
        }
        // The checks below are all about these letters, absent from nearly every block.
        const CHECKED: u32 = words::letter_mask(b"IJKRLPQDHE");
        if !d.has_any_of(CHECKED) {
            return Ok(());
        }
        let unused = |letter: char, msg: &str| -> Result<(), Diagnostic> {
            if d.has(letter) {
                Err(self.fail(d.span_of(letter), msg.to_string(), 36))
            } else {
                Ok(())
            }
        };
        let sync = moving && motion == Motion::SpindleSync;
        let tap = moving && motion == Motion::RigidTap;
        let thread = moving && motion == Motion::Threading;
        let orient = d.m_in(M::SPINDLE) == Some(19);
        let arcs_and_g10 = arc || g10 || (cycle && motion == Motion::Cycle(870));
        // Static messages: this check runs on every block and must not allocate.
        let g70 = lathe && motion == Motion::Cycle(700);
        let roughing = lathe && !g70;
        if !(arcs_and_g10 || tap || thread || spline(&[50, 51]) || roughing) {
            unused(
                'I',
                "I word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it",
            )?;
        }
        if !(arcs_and_g10 || thread || spline(&[50, 51])) {
            unused(
                'J',
                "J word with no G2, G3, G5, G5.1, G10, G76 or G87 to use it",
            )?;
        }
        if !(arcs_and_g10 || cycle || sync || tap || thread) {
            unused(
                'K',
                "K word with no G2, G3, G33, G33.1, G76, or G87 to use it",
            )?;
        }
        if !(arc || g10 || cycle || thread || orient || roughing) {
            unused('R', "R word with no g code that uses it")?;
        }
        if !(arc || g10 || cycle || thread || spline(&[52]) || d.m_in(M::IO) == Some(66)) {
            unused(
                'L',
                "L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code",
            )?;
        }
        let input = d.m_in(M::IO) == Some(66);
        if !(thread || input || g70) {
            unused('E', "E word with no G70, G76, M66, M67 or M68 to use it")?;
        }
        let p_users = arc
            || spline(&[50, 52])
            || thread
            || orient
            || matches!(non_modal, Some(40 | 100))
            || d.g_in(G::CONTROL) == Some(640)
            || matches!(d.m_in(M::OVERRIDE), Some(50..=53))
            || input
            || g70
            || (cycle && matches!(motion, Motion::Cycle(740 | 820 | 840 | 860 | 880 | 890)));
        if !p_users {
            unused(
                'P',
                "P word with no G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it",
            )?;
        }
        let q_users = g10
            || spline(&[50])
            || thread
            || orient
            || input
            || lathe
            || d.g_in(G::CONTROL) == Some(640)
            || (cycle && matches!(motion, Motion::Cycle(730 | 830 | 870)));
        if !q_users {
            unused(
                'Q',
                "Q word with no G5, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it",
            )?;
        }
        if !matches!(d.g_in(G::CUTTER_COMP), Some(410 | 420 | 411 | 421))
            && d.g_in(G::SPINDLE_MODE) != Some(960)
            && !lathe
        {
            unused(
                'D',
                "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 or G96 to use it",
            )?;
        }
        if d.g_in(G::TOOL_LENGTH) != Some(430) && !thread {
            unused('H', "H word with no G43 or G76 to use it")?;
        }
        Ok(())
    }

    fn run_block(
        &mut self,
        d: &Decoded,
        block: &Block,
        params: &mut Params,
        sink: Sink,
    ) -> Result<Flow, Diagnostic> {
        // 1. Comments and messages.
        for note in &block.notes {
            match note {
                Note::Message(m) => self.emit(sink, CanonOp::Message(m.clone())),
                Note::Comment(c) => self.emit(sink, CanonOp::Comment(c.clone())),
                // rs274 shows (DEBUG,…) to the operator like (MSG,…).
                Note::Debug(m) => self.emit(sink, CanonOp::Message(m.clone())),
            }
        }
        // 1b. Spindle mode (rs274 sets it before the feed mode).
        if let Some(t) = d.g_in(G::SPINDLE_MODE) {
            self.set_spindle_mode(d, t, sink)?;
        }
        // 2. Feed rate mode.
        if let Some(t) = d.g_in(G::FEED_MODE) {
            self.modal.feed_mode = match t {
                930 => FeedMode::InverseTime,
                950 => FeedMode::UnitsPerRev,
                _ => FeedMode::UnitsPerMinute,
            };
            self.emit(sink, CanonOp::SetFeedMode(self.modal.feed_mode));
            // rs274 forgets the feed on every G93/G94/G95: a new mode needs a new F.
            self.modal.feed = 0.0;
            if self.modal.feed_mode != FeedMode::InverseTime {
                self.emit(sink, CanonOp::SetFeedRate(0.0));
            }
        }
        // 3. Feed rate.
        if let Some(f) = d.values[words::slot('F')] {
            if f.v < 0.0 {
                return Err(self.fail(f.span, "Negative f word used", 0));
            }
            if self.dialect != Dialect::Legacy2006 {
                self.modal.feed = match self.modal.feed_mode {
                    FeedMode::InverseTime => f.v,
                    _ => f.v * self.k(),
                };
                if self.modal.feed_mode != FeedMode::InverseTime {
                    self.emit(sink, CanonOp::SetFeedRate(self.modal.feed));
                }
            }
        }
        // 4. Spindle speed.
        if let Some(s) = d.values[words::slot('S')] {
            if s.v < 0.0 {
                return Err(self.fail(s.span, "Negative spindle speed used", 0));
            }
            self.modal.speed = s.v;
            self.emit(sink, CanonOp::SetSpindleSpeed(s.v));
        }
        // 5. Tool selection.
        if let Some(t) = d.values[words::slot('T')] {
            let n = self.tool_number(t.v, t.span, "T")?;
            self.modal.tool_selected = n;
            self.emit(sink, CanonOp::SelectTool(n));
        }
        // 6. Tool change.
        if d.m_in(M::TOOL_CHANGE).is_some() {
            if self.modal.comp.is_some() {
                return Err(self
                    .fail(
                        d.m_span(M::TOOL_CHANGE),
                        "Cannot change tools with cutter radius compensation on",
                        0,
                    )
                    .with_help("turn compensation off with G40 before M6"));
            }
            self.emit(sink, CanonOp::StopSpindle);
            self.modal.spindle = None;
            self.modal.tool_in_spindle = self.modal.tool_selected;
            self.set_tool_params(params);
            self.emit(sink, CanonOp::ChangeTool(self.modal.tool_selected));
        }
        // 7. Spindle.
        match d.m_in(M::SPINDLE) {
            Some(3) => self.spindle(sink, Some(SpindleDir::Clockwise)),
            Some(4) => self.spindle(sink, Some(SpindleDir::CounterClockwise)),
            Some(5) => self.spindle(sink, None),
            Some(19) => self.orient_spindle(d, sink)?,
            // M70–M73 share rs274's modal group 7 with the spindle codes.
            Some(70) => self.save_context(params, false),
            Some(71) => self.invalidate_context(params),
            Some(72) => self.restore_context(params, d.m_span(M::SPINDLE), sink)?,
            Some(73) => self.save_context(params, true),
            _ => {}
        }
        // 8. Coolant.
        match d.m_in(M::COOLANT) {
            Some(7) => {
                self.modal.mist = true;
                self.emit(sink, CanonOp::MistOn);
            }
            Some(8) => {
                self.modal.flood = true;
                self.emit(sink, CanonOp::FloodOn);
            }
            Some(9) => {
                self.modal.mist = false;
                self.modal.flood = false;
                self.emit(sink, CanonOp::MistOff);
                self.emit(sink, CanonOp::FloodOff);
            }
            _ => {}
        }
        // 9. Overrides.
        if let Some(m) = d.m_in(M::OVERRIDE) {
            let on = d.get('P').map(|p| p != 0.0).unwrap_or(true);
            match m {
                48 | 49 => {
                    self.modal.feed_override = m == 48;
                    self.modal.speed_override = m == 48;
                    self.emit(sink, CanonOp::EnableFeedOverride(m == 48));
                    self.emit(sink, CanonOp::EnableSpeedOverride(m == 48));
                }
                50 => {
                    self.modal.feed_override = on;
                    self.emit(sink, CanonOp::EnableFeedOverride(on))
                }
                51 => {
                    self.modal.speed_override = on;
                    self.emit(sink, CanonOp::EnableSpeedOverride(on))
                }
                52 => {
                    self.modal.adaptive_feed = on;
                    self.emit(sink, CanonOp::EnableAdaptiveFeed(on))
                }
                _ => {
                    self.modal.feed_hold = on;
                    self.emit(sink, CanonOp::EnableFeedHold(on))
                }
            }
        }
        // 9b. Waiting on an input.
        if d.m_in(M::IO) == Some(66) {
            self.wait_input(d, params)?;
        }
        // 10. Dwell.
        if d.g_in(G::NON_MODAL) == Some(40) {
            let p = d.values[words::slot('P')].ok_or_else(|| {
                self.fail(d.g_span(G::NON_MODAL), "Dwell time missing with g4", 28)
            })?;
            if p.v < 0.0 || !p.v.is_finite() {
                return Err(self.fail(p.span, format!("Dwell time must be ≥ 0, not {}", p.v), 0));
            }
            self.emit(sink, CanonOp::Dwell(p.v));
        }
        // 11. Plane.
        if let Some(t) = d.g_in(G::PLANE) {
            let plane = match t {
                180 => Plane::XZ,
                190 => Plane::YZ,
                _ => Plane::XY,
            };
            if self.modal.comp.is_some() && plane != Plane::XY {
                return Err(self.fail(
                    d.g_span(G::PLANE),
                    "Cannot change plane with cutter radius compensation on",
                    0,
                ));
            }
            self.modal.plane = plane;
            self.emit(sink, CanonOp::SelectPlane(plane));
        }
        // 11b. Lathe diameter (G7) or radius (G8) mode.
        if let Some(t) = d.g_in(G::LATHE_DIAMETER) {
            self.modal.diameter_mode = t == 70;
        }
        // 12. Units.
        if let Some(t) = d.g_in(G::UNITS) {
            if self.modal.comp.is_some() {
                return Err(self.fail(
                    d.g_span(G::UNITS),
                    "Cannot change units with cutter radius compensation",
                    0,
                ));
            }
            self.modal.units = if t == 200 { Units::Inch } else { Units::Mm };
            self.emit(sink, CanonOp::UseLengthUnits(self.modal.units));
        }
        // 13. Cutter radius compensation.
        if let Some(t) = d.g_in(G::CUTTER_COMP) {
            self.set_cutter_comp(d, t, sink)?;
        }
        // 14. Tool length offset.
        if let Some(t) = d.g_in(G::TOOL_LENGTH) {
            self.tool_length(d, t, sink)?;
        }
        // 15. Coordinate system.
        if let Some(t) = d.g_in(G::COORD_SYSTEM) {
            if self.modal.comp.is_some() {
                return Err(self.fail(
                    d.g_span(G::COORD_SYSTEM),
                    "Cannot change coordinate systems with cutter radius compensation on",
                    0,
                ));
            }
            let index = match t {
                591 => 7,
                592 => 8,
                593 => 9,
                _ => ((t - 540) / 10 + 1) as u8,
            };
            // rs274 re-selecting the active system changes nothing and says nothing.
            if index != self.modal.coord_system {
                self.modal.coord_system = index;
                self.load_coord_system(params, index);
                self.emit_coord_system(sink, true);
            }
        }
        // 16. Path control.
        if let Some(t) = d.g_in(G::CONTROL) {
            self.modal.control = match t {
                610 => PathControlMode::ExactPath,
                611 => PathControlMode::ExactStop,
                _ => PathControlMode::Continuous,
            };
            if t == 640 {
                let p = d.get('P').unwrap_or(0.0).max(0.0) * self.k();
                let q = d.get('Q').map(|q| q.max(0.0) * self.k()).unwrap_or(p);
                self.modal.blend_tolerance = p;
                self.modal.naive_tolerance = q;
            }
            self.emit_control_mode(sink);
        }
        // 17. Distance modes; 18. retract mode.
        match d.g_in(G::DISTANCE) {
            Some(900) => self.modal.incremental = false,
            Some(910) => self.modal.incremental = true,
            _ => {}
        }
        match d.g_in(G::ARC_DISTANCE) {
            Some(901) => self.modal.arc_incremental = false,
            Some(911) => self.modal.arc_incremental = true,
            _ => {}
        }
        match d.g_in(G::RETRACT) {
            Some(980) => self.modal.retract_to_old_z = true,
            Some(990) => self.modal.retract_to_old_z = false,
            _ => {}
        }
        // 19. Home, G10, G92 family.
        // G43.1 uses the axis words as offsets.
        let mut motion_done = d.g_in(G::TOOL_LENGTH) == Some(431);
        if let Some(t) = d.g_in(G::NON_MODAL) {
            motion_done = self.non_modal(d, t, params, sink)?;
        }
        // 20. Motion.
        if let Some(t) = d.g_in(G::MOTION) {
            // rs274 runs G5 and G5.1 in their block and keeps the motion mode as it was.
            if !matches!(t, 50 | 51) {
                self.modal.motion = Motion::from_tenths(t);
            }
            if !matches!(t, 52 | 53) {
                self.spline.continuing = false;
            }
        }
        // rs274 moves on a G0 or G1 without axis words (to where it is: a move of length
        // zero); grbl and the legacy dialect only set the motion mode.
        let needs_words = match self.block_motion(d) {
            Motion::Off => true,
            Motion::Rapid | Motion::Linear => self.dialect != Dialect::LinuxCnc,
            _ => false,
        };
        if !matches!(self.modal.motion, Motion::Cycle(_)) {
            self.cycle.reset();
        }
        if !motion_done && (d.any_axis() || (d.g[G::MOTION].is_some() && !needs_words)) {
            self.motion(d, sink)?;
            self.set_probe_params(params);
        }
        // 21. Stop.
        match d.m_in(M::STOP) {
            Some(0) | Some(60) => self.emit(sink, CanonOp::ProgramStop),
            Some(1) => self.emit(sink, CanonOp::OptionalProgramStop),
            Some(2) | Some(30) => {
                self.end_program(params, sink);
                return Ok(Flow::End);
            }
            _ => {}
        }
        Ok(if self.lathe.is_some() {
            Flow::ReadProfile
        } else {
            Flow::Continue
        })
    }

    /// The motion of this block: G5 / G5.1 when it names one (they are not modal), else the
    /// motion mode.
    pub(crate) fn block_motion(&self, d: &Decoded) -> Motion {
        match d.g_in(G::MOTION) {
            Some(t @ (50 | 51)) => Motion::Spline(t),
            _ => self.modal.motion,
        }
    }

    fn tool_number(&self, v: f64, span: Span, letter: &str) -> Result<u32, Diagnostic> {
        if v < 0.0 {
            return Err(self.fail(span, "Negative tool id (tool not found)", 0));
        }
        if v.fract() != 0.0 || v > u32::MAX as f64 {
            return Err(self.fail(span, format!("{letter} word must be a whole number"), 23));
        }
        let n = v as u32;
        if n != 0 && !self.tools.is_empty() && self.tools.get(n).is_none() {
            return Err(self
                .fail(
                    span,
                    format!("Requested tool {n} not found in the tool table"),
                    0,
                )
                .with_help(if self.tools.is_rs274_default() {
                    "no tool table was given, so this is rs274's standalone default (tools \
                     1, 2 and 3): give the machine's table with --tool-table"
                } else {
                    "add the tool to the tool table or correct the number"
                }));
        }
        Ok(n)
    }

    fn spindle(&mut self, sink: Sink, dir: Option<SpindleDir>) {
        self.modal.spindle = dir;
        match dir {
            Some(d) => self.emit(sink, CanonOp::StartSpindle(d)),
            None => self.emit(sink, CanonOp::StopSpindle),
        }
    }

    pub(crate) fn emit_control_mode(&self, sink: Sink) {
        let tol = if self.modal.control == PathControlMode::Continuous {
            self.modal.blend_tolerance
        } else {
            0.0
        };
        self.emit(
            sink,
            CanonOp::SetMotionControlMode {
                mode: self.modal.control,
                tolerance: tol,
            },
        );
        if self.modal.control == PathControlMode::Continuous {
            self.emit(
                sink,
                CanonOp::SetNaivecamTolerance(self.modal.naive_tolerance),
            );
        }
    }

    /// M2 / M30: LinuxCNC's end-of-program resets, then the end itself.
    fn end_program(&mut self, params: &mut Params, sink: Sink) {
        // rs274 issues what cutter compensation holds before it resets anything.
        self.comp_flush(sink);
        self.modal.coord_system = 1;
        self.load_coord_system(params, 1);
        self.emit_coord_system(sink, false);
        if self.modal.plane != Plane::XY {
            self.modal.plane = Plane::XY;
            self.emit(sink, CanonOp::SelectPlane(Plane::XY));
        }
        self.modal.incremental = false;
        self.modal.feed_mode = FeedMode::UnitsPerMinute;
        self.emit(sink, CanonOp::SetFeedMode(FeedMode::UnitsPerMinute));
        if self.dialect != Dialect::Legacy2006 {
            self.modal.feed = 0.0;
            self.emit(sink, CanonOp::SetFeedRate(0.0));
        }
        // rs274 switches the feed override back on (only that one) when it was off.
        if !self.modal.feed_override {
            self.modal.feed_override = true;
            self.emit(sink, CanonOp::EnableFeedOverride(true));
        }
        self.modal.comp = None;
        self.comp = comp::CompState::default();
        self.modal.spindle = None;
        self.emit(sink, CanonOp::StopSpindle);
        if self.modal.spindle_mode != SpindleMode::Rpm {
            self.modal.spindle_mode = SpindleMode::Rpm;
            self.emit(sink, CanonOp::SetSpindleMode(SpindleMode::Rpm));
        }
        self.modal.motion = Motion::Linear;
        // rs274 turns off only what is on.
        if self.modal.mist {
            self.modal.mist = false;
            self.emit(sink, CanonOp::MistOff);
        }
        if self.modal.flood {
            self.modal.flood = false;
            self.emit(sink, CanonOp::FloodOff);
        }
        self.emit(sink, CanonOp::ProgramEnd);
    }

    /// `#5420…` current position, `#5400` tool, and the cheap named `#<_…>` values.
    fn update_params(&self, params: &mut Params) {
        let k = self.k();
        // In mm (k = 1) the division changes nothing: skipped, as it runs after every block.
        // Two real branches, not one copy with a select: the select divides every time, and
        // its 16-byte reads across `self.pos`'s 16-byte stores miss store forwarding, while
        // the plain copy reads the position with the same widths it was just written with.
        if k == 1.0 {
            let _ = params.set_run(param::POSITION, &self.pos);
        } else {
            let p = self.pos;
            let here = [p[0] / k, p[1] / k, p[2] / k, p[3], p[4], p[5]];
            let _ = params.set_run(param::POSITION, &here);
        }
        let _ = params.set(param::COORD_SYSTEM, self.modal.coord_system as f64);
        let _ = params.set(param::TOOL_NUMBER, self.modal.tool_in_spindle as f64);
    }

    /// The rest of rs274 2.9's read-only named parameters (interp_namedparams.cc): modes as
    /// 0/1 flags or G-code numbers ×10, and the version of the LinuxCNC Oficina follows
    /// (`_vmajor` 2.9, `_vminor` 0, as rs274 2.9.0 reads its own version).
    fn update_mode_params(&self, params: &mut Params) {
        let b = |v: bool| if v { 1.0 } else { 0.0 };
        let ccomp = match self.modal.comp {
            Some(Side::Left) => 410.0,
            Some(Side::Right) => 420.0,
            None => 400.0,
        };
        let m = &self.modal;
        for (name, value) in [
            ("_vmajor", 2.9),
            ("_vminor", 0.0),
            ("_ccomp", ccomp),
            ("_inverse_time", b(m.feed_mode == FeedMode::InverseTime)),
            (
                "_units_per_minute",
                b(m.feed_mode == FeedMode::UnitsPerMinute),
            ),
            ("_units_per_rev", b(m.feed_mode == FeedMode::UnitsPerRev)),
            ("_tool_offset", b(self.frame.tool.iter().any(|&t| t != 0.0))),
            ("_retract_r_plane", b(!m.retract_to_old_z)),
            ("_retract_old_z", b(m.retract_to_old_z)),
            ("_spindle_rpm_mode", b(m.spindle_mode == SpindleMode::Rpm)),
            ("_spindle_css_mode", b(m.spindle_mode != SpindleMode::Rpm)),
            ("_ijk_absolute_mode", b(!m.arc_incremental)),
            ("_lathe_diameter_mode", b(m.diameter_mode)),
            ("_lathe_radius_mode", b(!m.diameter_mode)),
            ("_spindle_on", b(m.spindle.is_some())),
            ("_spindle_cw", b(m.spindle == Some(SpindleDir::Clockwise))),
            ("_mist", b(m.mist)),
            ("_flood", b(m.flood)),
            ("_speed_override", b(m.speed_override)),
            ("_feed_override", b(m.feed_override)),
            ("_adaptive_feed", b(m.adaptive_feed)),
            ("_feed_hold", b(m.feed_hold)),
            ("_u", 0.0),
            ("_v", 0.0),
            ("_w", 0.0),
        ] {
            params.set_system(name, value);
        }
    }

    /// `#5401`…`#5413`: the loaded tool's table entry (X Y Z A B C U V W offsets, diameter,
    /// front and back angle, orientation) in machine units, zero without a tool. rs274 sets
    /// them (set_tool_parameters) on a tool change and when G10 L1/L10/L11 changes a tool.
    pub(crate) fn set_tool_params(&self, params: &mut Params) {
        let mk = self.mk();
        let mut v = [0.0; 13];
        let loaded = self.modal.tool_in_spindle;
        if let Some(t) = self.tools.get(loaded).filter(|_| loaded > 0) {
            for (i, o) in t.offset.iter().enumerate() {
                v[i] = if i < 3 { o / mk } else { *o };
            }
            v[9] = t.diameter / mk;
        }
        let _ = params.set_run(param::TOOL_NUMBER + 1, &v);
    }

    /// Named parameters (`#<_x>`, `#<_metric>` …) as LinuxCNC defines them. They cost a
    /// map update each, so the driver refreshes them only for programs that read them.
    pub fn update_named_params(&self, params: &mut Params) {
        const HERE: [&str; 6] = ["_x", "_y", "_z", "_a", "_b", "_c"];
        const ABS: [&str; 6] = ["_abs_x", "_abs_y", "_abs_z", "_abs_a", "_abs_b", "_abs_c"];
        let k = self.k();
        // G53 coordinates: the offsets without the tool length.
        let mut no_tool = self.frame;
        no_tool.tool = [0.0; 6];
        let m = no_tool.to_machine(self.pos);
        for i in 0..6 {
            let s = if i < 3 { k } else { 1.0 };
            params.set_system(HERE[i], self.pos[i] / s);
            params.set_system(ABS[i], m[i] / s);
        }
        let b = |v: bool| if v { 1.0 } else { 0.0 };
        params.set_system("_metric", b(self.modal.units == Units::Mm));
        params.set_system("_imperial", b(self.modal.units == Units::Inch));
        params.set_system("_absolute", b(!self.modal.incremental));
        params.set_system("_incremental", b(self.modal.incremental));
        params.set_system("_feed", self.modal.feed / k);
        params.set_system("_rpm", self.modal.speed);
        params.set_system("_current_tool", self.modal.tool_in_spindle as f64);
        params.set_system("_selected_tool", self.modal.tool_selected as f64);
        let coord = match self.modal.coord_system {
            n @ 1..=6 => 530.0 + 10.0 * n as f64,
            n => 590.0 + (n - 6) as f64,
        };
        params.set_system("_coord_system", coord);
        let plane = match self.modal.plane {
            Plane::XY => 170.0,
            Plane::XZ => 180.0,
            Plane::YZ => 190.0,
        };
        params.set_system("_plane", plane);
        let motion = match self.modal.motion {
            Motion::Rapid => 0.0,
            Motion::Linear => 10.0,
            Motion::Clockwise => 20.0,
            Motion::CounterClockwise => 30.0,
            Motion::Cycle(c) => c as f64,
            Motion::Off => 800.0,
            Motion::SpindleSync => 330.0,
            Motion::RigidTap => 331.0,
            Motion::Threading => 760.0,
            Motion::Spline(t) => t as f64,
            Motion::Probe(t) => t as f64,
        };
        params.set_system("_motion_mode", motion);
        self.update_mode_params(params);
        params.set_system("_line", self.line as f64);
    }
}
