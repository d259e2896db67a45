//! The modal interpreter: evaluated blocks → canonical operations, in LinuxCNC's order of
//! execution (`overview.adoc`, "Order of Execution").
//!
//! Positions are kept in program coordinates (mm) as LinuxCNC does; every motion is emitted
//! in machine coordinates through the [`frame::Frame`] chain, and every change of an offset is
//! emitted too, so a printer can go back to program coordinates.

pub mod arcs;
pub mod comp;
pub mod cycles;
pub mod dialect;
pub mod frame;
mod simple;
pub mod state;
pub mod tool_table;
pub mod words;

use crate::block::{Block, Note};
use crate::diag::{Diagnostic, Span};
use crate::params::Params;
use crate::Dialect;
use arcs::{ArcError, ArcTolerance};
use frame::Frame;
use oficina_canon::{Canon, CanonOp, FeedMode, MotionMode, Plane, Pos, SpindleDir, Units};
use state::{Modal, Motion};
use tool_table::ToolTable;
use words::{g_group as G, m_group as M, Decoded};

/// What the caller should do after a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    Continue,
    /// M2 / M30: the program ended.
    End,
}

/// How a run starts.
#[derive(Clone, Debug)]
pub struct StartState {
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
pub const LEGACY_DEFAULT_FEED: f64 = 600.0;

/// Where the operations go.
pub type Sink<'a> = &'a mut dyn FnMut(Canon);

/// LinuxCNC's parameter numbers.
pub mod param {
    pub const G28_HOME: i64 = 5161;
    pub const G30_HOME: i64 = 5181;
    pub const G92_ENABLED: i64 = 5210;
    pub const G92_OFFSET: i64 = 5211;
    pub const COORD_SYSTEM: i64 = 5220;
    /// G54 X; system n (1-based) starts at `G5X_BASE + 20·(n−1)`, R (rotation) at +9.
    pub const G5X_BASE: i64 = 5221;
    pub const TOOL_NUMBER: i64 = 5400;
    pub const TOOL_OFFSET: i64 = 5401;
    pub const POSITION: i64 = 5420;
}

pub struct Interpreter {
    pub dialect: Dialect,
    pub modal: Modal,
    /// Current point in program coordinates, mm (A B C degrees).
    pub pos: [f64; 6],
    pub frame: Frame,
    pub tools: ToolTable,
    machine_units: Units,
    pub(crate) cycle: cycles::CycleMemory,
    pub(crate) comp: comp::CompState,
    line: u32,
    /// Scratch for the block being run (see [`Interpreter::execute`]).
    decoded: Option<Box<Decoded>>,
}

/// Axis letters in [`Pos::to_array`] order.
pub const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

impl Interpreter {
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
        Interpreter {
            dialect,
            modal,
            pos: [0.0; 6],
            frame: Frame::default(),
            tools,
            machine_units: start.machine_units,
            cycle: cycles::CycleMemory::default(),
            comp: comp::CompState::default(),
            line: 0,
            decoded: None,
        }
    }

    /// The operations that describe the start state (LinuxCNC's `rs274` prints them too).
    pub fn begin(&mut self, params: &mut Params, sink: Sink) {
        let line = 0;
        let emit = &mut |op| sink(Canon { line, op });
        emit(CanonOp::UseLengthUnits(self.modal.units));
        self.load_coord_system(params, self.modal.coord_system);
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
        sink(Canon {
            line: self.line,
            op,
        });
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
            Dialect::LinuxCnc => dialect::refuse_probe(d)?,
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
        let cycle = moving && matches!(motion, Motion::Cycle(_));
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
        let axis_users = matches!(non_modal, Some(100 | 280 | 300 | 520 | 920))
            || d.g_in(G::TOOL_LENGTH) == Some(431);
        if d.any_axis() && !axis_users {
            if motion == Motion::Off {
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
        }
        // The checks below are all about these letters, absent from nearly every block.
        const CHECKED: u32 = words::letter_mask(b"IJKRLPQDH");
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
        if !(arc || g10 || (cycle && motion == Motion::Cycle(870))) {
            // Static messages: this check runs on every block and must not allocate.
            unused(
                'I',
                "I word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it",
            )?;
            unused(
                'J',
                "J word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it",
            )?;
            if !cycle {
                unused(
                    'K',
                    "K word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it",
                )?;
            }
        }
        if !(arc || g10 || cycle) {
            unused('R', "R word with no g code that uses it")?;
            unused(
                'L',
                "L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code",
            )?;
        }
        let p_users = arc
            || matches!(non_modal, Some(40 | 100))
            || d.g_in(G::CONTROL) == Some(640)
            || matches!(d.m_in(M::OVERRIDE), Some(50..=53))
            || (cycle && matches!(motion, Motion::Cycle(820 | 860 | 880 | 890)));
        if !p_users {
            unused(
                'P',
                "P word with no G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it",
            )?;
        }
        let q_users = g10
            || d.g_in(G::CONTROL) == Some(640)
            || (cycle && matches!(motion, Motion::Cycle(730 | 830 | 870)));
        if !q_users {
            unused(
                'Q',
                "Q word with no G5, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it",
            )?;
        }
        if !matches!(d.g_in(G::CUTTER_COMP), Some(410 | 420 | 411 | 421)) {
            unused(
                'D',
                "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 or G96 to use it",
            )?;
        }
        if d.g_in(G::TOOL_LENGTH) != Some(430) {
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
            self.emit(sink, CanonOp::ChangeTool(self.modal.tool_selected));
        }
        // 7. Spindle.
        match d.m_in(M::SPINDLE) {
            Some(3) => self.spindle(sink, Some(SpindleDir::Clockwise)),
            Some(4) => self.spindle(sink, Some(SpindleDir::CounterClockwise)),
            Some(5) => self.spindle(sink, None),
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
                    self.emit(sink, CanonOp::EnableFeedOverride(m == 48));
                    self.emit(sink, CanonOp::EnableSpeedOverride(m == 48));
                }
                50 => {
                    self.modal.feed_override = on;
                    self.emit(sink, CanonOp::EnableFeedOverride(on))
                }
                51 => self.emit(sink, CanonOp::EnableSpeedOverride(on)),
                52 => self.emit(sink, CanonOp::EnableAdaptiveFeed(on)),
                _ => self.emit(sink, CanonOp::EnableFeedHold(on)),
            }
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
                610 => MotionMode::ExactPath,
                611 => MotionMode::ExactStop,
                _ => MotionMode::Continuous,
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
            self.modal.motion = Motion::from_tenths(t);
        }
        let needs_words = matches!(
            self.modal.motion,
            Motion::Rapid | Motion::Linear | Motion::Off
        );
        if !matches!(self.modal.motion, Motion::Cycle(_)) {
            self.cycle.reset();
        }
        if !motion_done && (d.any_axis() || (d.g[G::MOTION].is_some() && !needs_words)) {
            self.motion(d, sink)?;
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
        Ok(Flow::Continue)
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
                .with_help("add the tool to the tool table or correct the number"));
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
        let tol = if self.modal.control == MotionMode::Continuous {
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
        if self.modal.control == MotionMode::Continuous {
            self.emit(
                sink,
                CanonOp::SetNaivecamTolerance(self.modal.naive_tolerance),
            );
        }
    }

    /// The active work offset and rotation; `with_g92` as rs274 does on G54…G59.3 (it
    /// restates the G92 offset between the two).
    fn emit_coord_system(&self, sink: Sink, with_g92: bool) {
        self.emit(
            sink,
            CanonOp::SetG5xOffset {
                index: self.modal.coord_system,
                offset: Pos::from_array(self.frame.g5x),
            },
        );
        if with_g92 {
            self.emit(sink, CanonOp::SetG92Offset(Pos::from_array(self.frame.g92)));
        }
        self.emit(sink, CanonOp::SetXyRotation(self.frame.rotation));
    }

    /// Take the offset of system `index` from the parameters (LinuxCNC keeps them there, in
    /// program units).
    fn load_coord_system(&mut self, params: &Params, index: u8) {
        let base = param::G5X_BASE + 20 * (index as i64 - 1);
        let k = self.mk();
        let mut f = self.frame;
        for i in 0..6 {
            let v = params.get(base + i as i64).unwrap_or(0.0);
            f.g5x[i] = if i < 3 { v * k } else { v };
        }
        f.rotation = params.get(base + 9).unwrap_or(0.0);
        self.set_frame(f);
    }

    fn tool_length(&mut self, d: &Decoded, t: u16, sink: Sink) -> Result<(), Diagnostic> {
        let mut f = self.frame;
        match t {
            430 => {
                let n = match d.values[words::slot('H')] {
                    Some(h) => self.tool_number(h.v, h.span, "H")?,
                    None => self.modal.tool_in_spindle,
                };
                f.tool = match self.tools.get(n) {
                    Some(tool) => tool.offset,
                    None if n == 0 || self.tools.is_empty() => [0.0; 6],
                    None => {
                        return Err(self.fail(
                            d.span_of('H'),
                            format!("Requested tool {n} not found in the tool table"),
                            0,
                        ))
                    }
                };
            }
            431 => {
                f.tool = [0.0; 6];
                for (i, &l) in AXES.iter().enumerate() {
                    if let Some(v) = d.get(l) {
                        f.tool[i] = if i < 3 { v * self.k() } else { v };
                    }
                }
            }
            _ => f.tool = [0.0; 6],
        }
        self.modal.tool_length_on = t != 490;
        self.set_frame(f);
        self.emit(sink, CanonOp::UseToolLengthOffset(Pos::from_array(f.tool)));
        Ok(())
    }

    /// G4 (done earlier), G10, G28, G30, G52, G53 (only a flag), G92…: returns whether the
    /// block's axis words were used up (no motion follows).
    fn non_modal(
        &mut self,
        d: &Decoded,
        t: u16,
        params: &mut Params,
        sink: Sink,
    ) -> Result<bool, Diagnostic> {
        let k = self.k();
        let scale = |i: usize| if i < 3 { k } else { 1.0 };
        match t {
            100 => {
                self.g10(d, params, sink)?;
                Ok(true)
            }
            280 | 300 => {
                if self.modal.comp.is_some() {
                    return Err(self.fail(
                        d.g_span(G::NON_MODAL),
                        "Cannot use G28 or G30 with cutter radius compensation",
                        0,
                    ));
                }
                // Through the intermediate point (axis words), then home on those axes
                // (all axes when none is named).
                let mid = self.axis_target(d);
                let base = if t == 280 {
                    param::G28_HOME
                } else {
                    param::G30_HOME
                };
                // rs274 makes the intermediate move even when it goes nowhere.
                self.emit_straight(sink, false, mid);
                self.pos = mid;
                let mut home_m = self.frame.to_machine(self.pos);
                let mk = self.machine_units.mm();
                for i in 0..6 {
                    if !d.any_axis() || d.has(AXES[i]) {
                        let s = if i < 3 { mk } else { 1.0 };
                        home_m[i] = params.get(base + i as i64).unwrap_or(0.0) * s;
                    }
                }
                let home = self.frame.to_program(home_m);
                self.emit_straight(sink, false, home);
                self.pos = home;
                Ok(true)
            }
            281 | 301 => {
                let base = if t == 281 {
                    param::G28_HOME
                } else {
                    param::G30_HOME
                };
                let m = self.frame.to_machine(self.pos);
                let mk = self.machine_units.mm();
                for i in 0..6 {
                    let s = if i < 3 { mk } else { 1.0 };
                    let _ = params.set(base + i as i64, m[i] / s);
                }
                Ok(true)
            }
            520 | 920 => {
                if !d.any_axis() {
                    return Err(self.fail(
                        d.g_span(G::NON_MODAL),
                        "All axes missing with g52 or g92",
                        26,
                    ));
                }
                let mut f = self.frame;
                for i in 0..6 {
                    if let Some(v) = d.get(AXES[i]) {
                        f.g92[i] = if t == 920 {
                            self.pos[i] + self.frame.g92[i] - v * scale(i)
                        } else {
                            v * scale(i)
                        };
                    }
                }
                self.set_g92(f, params, sink);
                Ok(true)
            }
            921 | 922 => {
                let mut f = self.frame;
                f.g92 = [0.0; 6];
                if t == 921 {
                    for i in 0..6 {
                        let _ = params.set(param::G92_OFFSET + i as i64, 0.0);
                    }
                }
                self.set_frame(f);
                let _ = params.set(param::G92_ENABLED, 0.0);
                self.emit(sink, CanonOp::SetG92Offset(Pos::from_array(f.g92)));
                Ok(false)
            }
            923 => {
                let mut f = self.frame;
                for i in 0..6 {
                    let s = if i < 3 { self.mk() } else { 1.0 };
                    f.g92[i] = params.get(param::G92_OFFSET + i as i64).unwrap_or(0.0) * s;
                }
                self.set_g92(f, params, sink);
                Ok(false)
            }
            _ => Ok(false),
        }
    }

    fn set_g92(&mut self, f: Frame, params: &mut Params, sink: Sink) {
        let k = self.mk();
        for i in 0..6 {
            let s = if i < 3 { k } else { 1.0 };
            let _ = params.set(param::G92_OFFSET + i as i64, f.g92[i] / s);
        }
        let _ = params.set(param::G92_ENABLED, 1.0);
        self.set_frame(f);
        self.emit(sink, CanonOp::SetG92Offset(Pos::from_array(f.g92)));
    }

    fn g10(&mut self, d: &Decoded, params: &mut Params, sink: Sink) -> Result<(), Diagnostic> {
        let span = d.g_span(G::NON_MODAL);
        let l = d.values[words::slot('L')].ok_or_else(|| {
            self.fail(
                span,
                "Line with G10 does not have L0, L1, L10, L11, L2, or L20",
                28,
            )
        })?;
        let p = d.get('P');
        let k = self.k();
        match l.v as i64 {
            2 | 20 if l.v.fract() == 0.0 => {
                let pv = p.unwrap_or(-1.0);
                if !(0.0..=9.0).contains(&pv) || pv.fract() != 0.0 {
                    return Err(self.fail(
                        d.span_of('P'),
                        format!("P value out of range (0-9) with G10 L{}", l.v),
                        28,
                    ));
                }
                let index = if pv == 0.0 {
                    self.modal.coord_system
                } else {
                    pv as u8
                };
                let base = param::G5X_BASE + 20 * (index as i64 - 1);
                let mut off = [0.0; 6];
                for (i, o) in off.iter_mut().enumerate() {
                    *o = params.get(base + i as i64).unwrap_or(0.0);
                }
                let mut rot = params.get(base + 9).unwrap_or(0.0);
                if let Some(r) = d.get('R') {
                    rot = r;
                }
                let mk = self.mk();
                if l.v == 2.0 {
                    for (i, o) in off.iter_mut().enumerate() {
                        if let Some(v) = d.get(AXES[i]) {
                            *o = if i < 3 { v * k / mk } else { v };
                        }
                    }
                } else {
                    // L20: choose the offset that makes the current point read as the values.
                    let mut f = self.frame;
                    f.rotation = rot;
                    let m = self.frame.to_machine(self.pos);
                    let mut want = self.pos;
                    for (i, w) in want.iter_mut().enumerate() {
                        if let Some(v) = d.get(AXES[i]) {
                            *w = if i < 3 { v * k } else { v };
                        }
                    }
                    f.g5x = [0.0; 6];
                    let through = f.to_machine(want);
                    for i in 0..6 {
                        // X and Y are one rotated pair: rs274 keeps the reading of the
                        // one not named, which moves both offsets.
                        let xy = d.has('X') || d.has('Y') || d.has('R');
                        if d.has(AXES[i]) || (i < 2 && xy) {
                            let s = if i < 3 { mk } else { 1.0 };
                            off[i] = (m[i] - through[i]) / s;
                        }
                    }
                }
                for (i, o) in off.iter().enumerate() {
                    let _ = params.set(base + i as i64, *o);
                }
                let _ = params.set(base + 9, rot);
                if index == self.modal.coord_system {
                    self.load_coord_system(params, index);
                    self.emit_coord_system(sink, false);
                }
                Ok(())
            }
            1 | 10 if l.v.fract() == 0.0 => {
                let pv = p.unwrap_or(-1.0);
                if pv < 1.0 || pv.fract() != 0.0 || pv > u32::MAX as f64 {
                    return Err(self.fail(
                        d.span_of('P'),
                        format!("P value out of range with G10 L{}", l.v),
                        28,
                    ));
                }
                // Like T and H, a number missing from a loaded table is an error.
                let n = self.tool_number(pv, d.span_of('P'), "P")?;
                let mut tool = self.tools.get(n).cloned().unwrap_or(tool_table::Tool {
                    number: n,
                    pocket: n,
                    ..Default::default()
                });
                for (i, &axis) in AXES.iter().enumerate() {
                    if let Some(v) = d.get(axis) {
                        let s = if i < 3 { k } else { 1.0 };
                        tool.offset[i] = if l.v == 1.0 {
                            v * s
                        } else {
                            // L10: the offset that makes the current point read as the value.
                            let m = self.frame.to_machine(self.pos)[i] - self.frame.tool[i];
                            let mut f = self.frame;
                            f.tool = [0.0; 6];
                            let mut want = self.pos;
                            want[i] = v * s;
                            m - f.to_machine(want)[i]
                        };
                    }
                }
                if let Some(r) = d.get('R') {
                    tool.diameter = 2.0 * r * k;
                }
                self.tools.insert(tool);
                Ok(())
            }
            _ => Err(self.fail(
                l.span,
                "Line with G10 does not have L0, L1, L10, L11, L2, or L20",
                28,
            )),
        }
    }

    /// The end point of the axis words (incremental or absolute), in program coordinates.
    pub(crate) fn axis_target(&self, d: &Decoded) -> [f64; 6] {
        let mut end = self.pos;
        let k = self.k();
        for (i, &l) in AXES.iter().enumerate() {
            if let Some(v) = d.get(l) {
                let v = if i < 3 { v * k } else { v };
                end[i] = if self.modal.incremental {
                    self.pos[i] + v
                } else {
                    v
                };
            }
        }
        end
    }

    pub(crate) fn emit_straight(&self, sink: Sink, feed: bool, to: [f64; 6]) {
        let to = self.machine(to);
        let op = if feed {
            CanonOp::StraightFeed { to }
        } else {
            CanonOp::StraightTraverse { to }
        };
        self.emit(sink, op);
    }

    /// Feed checks common to every feed move of the block.
    pub(crate) fn check_feed(&self, d: &Decoded, what: &str, arc: bool) -> Result<(), Diagnostic> {
        match self.modal.feed_mode {
            FeedMode::InverseTime => {
                if !d.has('F') {
                    let msg = if arc {
                        "F word missing with inverse time arc move".to_string()
                    } else {
                        format!("F word missing with inverse time {what} move")
                    };
                    return Err(self.fail(d.g_span(G::MOTION), msg, 22));
                }
            }
            FeedMode::UnitsPerRev if self.modal.speed <= 0.0 => {
                return Err(self
                    .fail(
                        d.g_span(G::MOTION),
                        "Cannot feed with zero spindle speed in feed per rev mode",
                        0,
                    )
                    .with_help("set a spindle speed with an S word before feeding under G95"));
            }
            _ if self.modal.feed <= 0.0 => {
                let msg = if arc {
                    "Cannot make arc with zero feed rate".to_string()
                } else {
                    format!("Cannot do {what} with zero feed rate")
                };
                let help = if self.dialect == Dialect::Legacy2006 {
                    "the legacy dialect takes its feed from the machine configuration: set one"
                } else {
                    "program a feed with an F word before the first feed move"
                };
                return Err(self.fail(d.g_span(G::MOTION), msg, 22).with_help(help));
            }
            _ => {}
        }
        Ok(())
    }

    fn motion(&mut self, d: &Decoded, sink: Sink) -> Result<(), Diagnostic> {
        let g53 = d.g_in(G::NON_MODAL) == Some(530);
        if g53 && self.modal.incremental {
            return Err(self.fail(d.g_span(G::NON_MODAL), "Cannot use g53 incremental", 0));
        }
        if g53 && self.modal.comp.is_some() {
            return Err(self.fail(
                d.g_span(G::NON_MODAL),
                "Cannot use G53 with cutter radius compensation",
                0,
            ));
        }
        let end = if g53 {
            let mut m = self.frame.to_machine(self.pos);
            for (i, &l) in AXES.iter().enumerate() {
                if let Some(v) = d.get(l) {
                    m[i] = if i < 3 { v * self.k() } else { v };
                }
            }
            self.frame.to_program(m)
        } else {
            self.axis_target(d)
        };
        if self.modal.feed_mode == FeedMode::InverseTime
            && matches!(
                self.modal.motion,
                Motion::Linear | Motion::Clockwise | Motion::CounterClockwise
            )
        {
            if let Some(f) = d.get('F') {
                self.modal.feed = f;
            }
        }
        match self.modal.motion {
            Motion::Rapid => self.straight(d, sink, false, end),
            Motion::Linear => {
                self.check_feed(d, "g1", false)?;
                self.inverse_time_rate(d, sink);
                self.straight(d, sink, true, end)
            }
            Motion::Clockwise | Motion::CounterClockwise => {
                self.check_feed(d, "arc", true)?;
                self.inverse_time_rate(d, sink);
                self.arc(d, sink, end)
            }
            Motion::Cycle(code) => self.canned_cycle(d, code, sink),
            Motion::Off => Ok(()),
        }
    }

    fn inverse_time_rate(&self, d: &Decoded, sink: Sink) {
        if self.modal.feed_mode == FeedMode::InverseTime {
            if let Some(f) = d.get('F') {
                self.emit(sink, CanonOp::SetFeedRate(f));
            }
        }
    }

    fn straight(
        &mut self,
        d: &Decoded,
        sink: Sink,
        feed: bool,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        if self.modal.comp.is_some() {
            return self.comp_straight(d, sink, feed, end);
        }
        self.emit_straight(sink, feed, end);
        self.pos = end;
        Ok(())
    }

    /// Centre of the arc to `end` (program coordinates, mm) from the block's words.
    pub(crate) fn arc_center(
        &self,
        d: &Decoded,
        start: [f64; 2],
        end: [f64; 2],
    ) -> Result<[f64; 2], Diagnostic> {
        let plane = self.modal.plane;
        let (a0, a1, _) = plane.axes();
        let (l0, l1) = (AXES[a0], AXES[a1]);
        let (o0, o1, off_axis, pname) = match plane {
            Plane::XY => ('I', 'J', 'K', "xy"),
            Plane::XZ => ('K', 'I', 'J', "xz"),
            Plane::YZ => ('J', 'K', 'I', "yz"),
        };
        let clockwise = self.modal.motion == Motion::Clockwise;
        let k = self.k();
        let tol = ArcTolerance::for_units(self.modal.units);
        if let Some(r) = d.values[words::slot('R')] {
            if d.has(o0) || d.has(o1) {
                return Err(self.fail(r.span, "Mixed radius ijk format for arc", 0));
            }
            if !d.has(l0) && !d.has(l1) {
                let (n0, n1) = (l0.to_ascii_uppercase(), l1.to_ascii_lowercase());
                let (n0, n1) = if plane == Plane::XZ {
                    ('X', 'z')
                } else {
                    (n0, n1)
                };
                return Err(self.fail(
                    d.g_span(G::MOTION),
                    format!("{n0} and {n1} words missing for arc in {pname} plane"),
                    32,
                ));
            }
            return arcs::center_from_radius(start, end, r.v * k, clockwise, &tol)
                .map_err(|e| self.arc_error(e, r.span, start, end));
        }
        if d.has(off_axis) {
            return Err(self.fail(
                d.span_of(off_axis),
                format!(
                    "{} word given for arc in {pname} plane",
                    off_axis.to_ascii_uppercase()
                ),
                0,
            ));
        }
        if !d.has(o0) && !d.has(o1) {
            return Err(self
                .fail(d.g_span(G::MOTION), "R i j k words all missing for arc", 35)
                .with_help(format!(
                    "give the centre with {o0}/{o1} or the radius with R"
                )));
        }
        let (i, j) = (d.get(o0).unwrap_or(0.0) * k, d.get(o1).unwrap_or(0.0) * k);
        let center = if self.modal.arc_incremental {
            [start[0] + i, start[1] + j]
        } else {
            [i, j]
        };
        let span = d.values[words::slot(o0)]
            .or(d.values[words::slot(o1)])
            .map(|v| v.span);
        arcs::center_from_offsets(start, end, center, &tol)
            .map_err(|e| self.arc_error(e, span.unwrap_or(Span::line(d.line)), start, end))
    }

    fn arc_error(&self, e: ArcError, span: Span, start: [f64; 2], end: [f64; 2]) -> Diagnostic {
        let k = self.k();
        let u = if self.modal.units == Units::Mm {
            "mm"
        } else {
            "in"
        };
        let (a0, a1, _) = self.modal.plane.axes();
        let (l0, l1) = (AXES[a0], AXES[a1]);
        let pt = |p: [f64; 2]| format!("({l0}{:.4},{l1}{:.4})", p[0] / k, p[1] / k);
        match e {
            ArcError::ZeroRadius { r1, r2, center } => self.fail(
                span,
                format!(
                    "Zero-radius arc: start={} center={} end={} r1={:.4} r2={:.4}",
                    pt(start),
                    pt(center),
                    pt(end),
                    r1 / k,
                    r2 / k
                ),
                33,
            ),
            ArcError::RadiiDiffer { r1, r2, center } => self
                .fail(
                    span,
                    format!(
                        "Radius to end of arc differs from radius to start by {:.4} {u}: start={} center={} end={} r1={:.4} r2={:.4}",
                        (r1 - r2).abs() / k,
                        pt(start),
                        pt(center),
                        pt(end),
                        r1 / k,
                        r2 / k
                    ),
                    33,
                )
                .with_help("the end point must lie on the circle through the start point about the centre"),
            ArcError::SameEndPoint => {
                self.fail(span, "Current point same as end point of arc", 33)
                    .with_help("a full circle needs the centre form (I J K), not R")
            }
            ArcError::RadiusTooSmall { radius, half_chord } => self
                .fail(
                    span,
                    format!(
                        "Arc radius too small to reach end point: R{:.4} but half the chord is {:.4} {u}",
                        radius / k,
                        half_chord / k
                    ),
                    34,
                )
                .with_help("the radius must be at least half the distance from start to end"),
        }
    }

    /// Turns of an arc from the P word: ±P, sign by direction.
    pub(crate) fn arc_turns(&self, d: &Decoded) -> Result<i32, Diagnostic> {
        let p = match d.values[words::slot('P')] {
            None => 1,
            Some(p) => {
                if p.v.fract() != 0.0 {
                    return Err(self.fail(p.span, "P value not an integer with M19 G2 or G3", 23));
                }
                if p.v < 1.0 {
                    return Err(self.fail(
                        p.span,
                        "P value should be 1 or greater with G2 or G3",
                        0,
                    ));
                }
                if p.v > 10_000.0 {
                    return Err(self.fail(p.span, "P value of more than 10000 turns", 0));
                }
                p.v as i32
            }
        };
        Ok(if self.modal.motion == Motion::Clockwise {
            -p
        } else {
            p
        })
    }

    fn arc(&mut self, d: &Decoded, sink: Sink, end: [f64; 6]) -> Result<(), Diagnostic> {
        let (a0, a1, _) = self.modal.plane.axes();
        let start2 = [self.pos[a0], self.pos[a1]];
        let end2 = [end[a0], end[a1]];
        if self.modal.comp.is_some() {
            return self.comp_arc(d, sink, end);
        }
        let center = self.arc_center(d, start2, end2)?;
        let turns = self.arc_turns(d)?;
        self.emit_arc(sink, end, center, turns);
        self.pos = end;
        Ok(())
    }

    /// Emit an arc to `end` about `center` (program coordinates) in the current plane.
    pub(crate) fn emit_arc(&self, sink: Sink, end: [f64; 6], center: [f64; 2], turns: i32) {
        let plane = self.modal.plane;
        let (a0, a1, _) = plane.axes();
        let mut c = end;
        c[a0] = center[0];
        c[a1] = center[1];
        let cm = self.frame.to_machine(c);
        self.emit(
            sink,
            CanonOp::ArcFeed {
                plane,
                end: self.machine(end),
                center: [cm[a0], cm[a1]],
                turns,
            },
        );
    }

    /// M2 / M30: LinuxCNC's end-of-program resets, then the end itself.
    fn end_program(&mut self, params: &mut Params, sink: Sink) {
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
        let mut here = self.pos;
        for v in &mut here[..3] {
            *v /= k;
        }
        let _ = params.set_run(param::POSITION, &here);
        let _ = params.set(param::COORD_SYSTEM, self.modal.coord_system as f64);
        let _ = params.set(param::TOOL_NUMBER, self.modal.tool_in_spindle as f64);
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
        };
        params.set_system("_motion_mode", motion);
        params.set_system("_line", self.line as f64);
    }
}
