//! The emulated firmware's state and behaviour, free of I/O: bytes go in through
//! [`Core::receive`], time advances through [`Core::tick`], replies come out of `out`.
//! The model follows grbl 1.1: real-time bytes act at once, other bytes wait in a 128-byte
//! RX ring (127 usable) and overflow is silently dropped as grbl's ISR does; a line is taken
//! out of the RX ring only when the previous one is fully in the planner (15 blocks), and
//! `ok` is sent once its blocks are queued.
//!
//! Timing model: the blocks in the planner buffer are planned by Oficina's own incremental
//! planner ([`Incremental`]) with the machine the `$` settings describe ($110… rates, $120…
//! accelerations, $11 junction deviation): as in grbl the plan always ends at rest after the
//! last buffered block, so a starved buffer slows the machine, and every new block re-plans
//! the rest from the current speed. Feed hold brakes and cycle start accelerates through the
//! same planner; overrides re-plan at once.
//!
//! Probing: a G38.x line waits for the planner to empty, is cut short where the probe input
//! changes (what [`ProbeModel`] says the tool touches), and is answered as grbl's
//! mc_probe_cycle answers once its move has run.

use super::flavor::Flavor;
use super::fluidnc;
use super::probe::{ProbeModel, Tool};
use oficina_grbl::GrblState;
use oficina_grbl::Realtime;
use oficina_grbl::SETTINGS;
use oficina_grbl::{Flow, Interp, ProbeKind, Rate, Segment};
use oficina_motion::MoveKind;
use oficina_motion::{Incremental, Push};
use std::collections::{BTreeMap, VecDeque};

mod homing;
mod rotary;
mod system;

use rotary::{Lane, Spin};

/// Knobs of the emulated board.
#[derive(Clone, Debug)]
pub struct Config {
    /// Serial line rate to emulate (bits/s, 10 bits a byte); `None` = as fast as the pipe.
    pub baud: Option<u32>,
    /// grbl's RX_BUFFER_SIZE (one byte of the ring stays unused).
    pub rx_buffer: usize,
    /// Planner blocks available (grbl's BLOCK_BUFFER_SIZE − 1).
    pub planner_blocks: usize,
    /// The version the board reports in its welcome and `$I` (e.g. "1.1h").
    pub version: String,
    /// Settings that differ from grbl's generic defaults.
    pub settings: Vec<(u16, f64)>,
    /// Keep the text of every G-code line whose motion completed (tests check that a job
    /// with stops and resumes ran every line exactly once).
    pub record_lines: bool,
    /// Which firmware to be: banner, `$I`, boot messages, what `Bf:` counts.
    pub flavor: Flavor,
    /// Ignore every n-th status query (0: answer all), as a harness that loses real-time
    /// flags does (grblHAL's Simulator) or a noisy link would.
    pub lose_status_every: u32,
    /// Keep every straight piece of motion the machine made (a block run to its end, or
    /// up to where a reset cut it): the witness for "every part of the path cut once".
    pub record_motion: bool,
    /// What the probe input touches (G38.x), and the tool in the spindle.
    pub probe: ProbeModel,
    /// Homing finds its switches; without them `$H` searches, then fails with `ALARM:9`.
    pub limit_switches: bool,
    /// The machine's clock runs this many times faster than the wall clock (1: real time),
    /// so a test can run a long real program to its end; the wire and the replies are
    /// unchanged, only motion and dwells are quicker.
    pub time_scale: f64,
}

impl Config {
    /// The defaults of `flavor`: its buffer sizes and version.
    pub fn flavored(flavor: Flavor) -> Config {
        let (planner_blocks, rx_buffer) = flavor.buffers();
        Config {
            flavor,
            planner_blocks,
            rx_buffer,
            version: flavor.version().into(),
            // grblHAL reports everything by default (`Bf:` included); grbl needs `$10=3`.
            settings: match flavor {
                Flavor::GrblHal => vec![(10, 511.0)],
                _ => Vec::new(),
            },
            ..Config::default()
        }
    }
}

impl Default for Config {
    fn default() -> Self {
        Config {
            baud: Some(115_200),
            rx_buffer: 128,
            planner_blocks: 15,
            version: "1.1h".into(),
            settings: Vec::new(),
            record_lines: false,
            flavor: Flavor::Grbl,
            lose_status_every: 0,
            record_motion: false,
            probe: ProbeModel::default(),
            limit_switches: true,
            time_scale: 1.0,
        }
    }
}

/// Counters a test or a benchmark reads.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Bytes read from the sender, real-time bytes included.
    pub bytes_received: u64,
    /// Bytes lost because the RX ring was full (a correct sender never causes one).
    pub rx_overflows: u64,
    /// G-code and `$` lines completed and answered.
    pub lines_executed: u64,
    /// `error:` replies sent.
    pub errors_sent: u64,
    /// Times the planner ran dry in a run and more motion arrived later.
    pub starvations: u64,
    /// Seconds the planner stood empty in those starvations.
    pub starved_seconds: f64,
    /// Starvations that began while the emulator's own reader was behind the wire schedule
    /// (its host was busy): the emulator's limit, not the sender's.
    pub starvations_host_late: u64,
    /// Seconds the machine was in motion.
    pub busy_seconds: f64,
    /// Most bytes ever waiting in the RX ring.
    pub max_rx_used: usize,
}

/// A line taken out of the RX ring whose work is not finished: it may wait for the
/// planner to drain (sync), dwell, then push its blocks as space frees.
struct Pending {
    sync: bool,
    dwell: f64,
    segments: VecDeque<Segment>,
    flow: Flow,
    probe: Option<ProbeEnd>,
    reply: String,
    line: Option<String>,
}

/// How a probing line ends once its (possibly shortened) move has run, as grbl's
/// mc_probe_cycle decides it.
#[derive(Clone, Copy, Debug)]
enum ProbeEnd {
    /// The probe changed state where the move now ends: `[PRB:…:1]`.
    Contact,
    /// The move ran to its end without the change: G38.3/5 report `[PRB:…:0]`, G38.2/4
    /// raise ALARM:5.
    Missed { no_error: bool },
    /// The probe was already as the move seeks it: ALARM:4, nothing moves.
    AlreadyTriggered,
}

/// The firmware model without I/O: bytes in, replies out, motion timed by the clock the
/// caller advances.
pub struct Core {
    /// The board's knobs.
    pub config: Config,
    /// The `$` settings in force, by number.
    pub settings: BTreeMap<u16, f64>,
    /// The G-code interpreter (modal state, work offsets).
    pub interp: Interp,
    /// The state `?` reports (Idle, Run, Hold...).
    pub state: GrblState,
    /// Machine position (mm).
    pub mpos: [f64; 3],
    /// Machine position of the 4th axis A (degrees), on a board with `$103`.
    pub mpos_a: f64,
    /// A at the end of the last block queued.
    a_tail: f64,
    /// How A turns along each block in the planner (front first).
    lanes: VecDeque<Lane>,
    /// A move of A alone, running (no other block moves meanwhile).
    spin: Option<Spin>,
    rx: VecDeque<u8>,
    line: Vec<u8>,
    line_overflow: bool,
    /// The planner buffer and the motion it plans.
    motion: Incremental,
    pending: Option<Pending>,
    /// A homing cycle under way (`$H`): no line is taken until it ends.
    homing: Option<homing::Homing>,
    /// Bytes to send to the host, oldest first.
    pub out: VecDeque<u8>,
    /// Counters for tests and benchmarks.
    pub stats: Stats,
    /// Lines whose motion completed, in order (with `record_lines`).
    pub executed: Vec<String>,
    /// Set by the server: the byte being received is late because the host was busy.
    pub host_late: bool,
    starving_host_late: bool,
    /// After a soft-limit alarm grbl takes no line until a reset.
    blocked: bool,
    /// Lines parsed but not finished: (text, sequence number of their last block).
    awaiting: VecDeque<(String, u64)>,
    blocks_pushed: u64,
    blocks_done: u64,
    /// (feed, rapid, spindle) overrides in percent.
    pub overrides: (u32, u32, u32),
    check_mode: bool,
    /// A jog cancel is braking; the jog blocks go once the machine is at rest.
    jog_cancelling: bool,
    resume_state: GrblState,
    starving: Option<f64>,
    clock: f64,
    report_counter: u32,
    /// The work offset the last `WCO:` field carried: grbl reports the next one at once
    /// when the offset changes (G10, G92, G54–G59, G43.1, M2's return to G54 all call
    /// `system_flag_wco_change`), or a sender's cached WCO goes stale.
    reported_wco: Option<[f64; 3]>,
    startup_lines: [String; 2],
    /// FluidNC's named settings (`$Config/Filename`, …).
    fluid: fluidnc::Named,
    jogging: bool,
    /// Where each block in the planner ends (front first), for grblHAL's `Bf:`.
    block_ends: VecDeque<[f64; 3]>,
    status_queries: u32,
    /// Pieces of motion made, (from, to) in machine mm (with `record_motion`).
    pub motion_record: Vec<([f64; 3], [f64; 3])>,
    /// Where the running block's motion began (it may have begun before a hold).
    piece_start: [f64; 3],
    /// grbl's sys_probe_position (machine mm), kept over a reset.
    probe_position: [f64; 3],
    /// grbl's sys.probe_succeeded, cleared by a reset.
    probe_succeeded: bool,
}

impl Core {
    /// A board just powered on with `config`.
    pub fn new(config: Config) -> Core {
        let mut settings: BTreeMap<u16, f64> =
            SETTINGS.iter().map(|s| (s.number, s.default)).collect();
        for (n, v) in &config.settings {
            settings.insert(*n, *v);
        }
        let motion = new_motion(&settings, [0.0; 3]);
        let mut core = Core {
            config,
            settings,
            interp: Interp::default(),
            state: GrblState::Idle,
            mpos: [0.0; 3],
            mpos_a: 0.0,
            a_tail: 0.0,
            lanes: VecDeque::new(),
            spin: None,
            rx: VecDeque::new(),
            line: Vec::new(),
            line_overflow: false,
            motion,
            pending: None,
            homing: None,
            out: VecDeque::new(),
            stats: Stats::default(),
            executed: Vec::new(),
            awaiting: VecDeque::new(),
            host_late: false,
            starving_host_late: false,
            blocked: false,
            blocks_pushed: 0,
            blocks_done: 0,
            overrides: (100, 100, 100),
            check_mode: false,
            jog_cancelling: false,
            resume_state: GrblState::Idle,
            starving: None,
            clock: 0.0,
            report_counter: 0,
            reported_wco: None,
            startup_lines: [String::new(), String::new()],
            fluid: fluidnc::Named::default(),
            jogging: false,
            block_ends: VecDeque::new(),
            status_queries: 0,
            motion_record: Vec::new(),
            piece_start: [0.0; 3],
            probe_position: [0.0; 3],
            probe_succeeded: false,
        };
        core.interp.arc_tolerance = core.setting(12);
        core.interp.a_axis = core.has_a();
        core.boot();
        core
    }

    /// Puts another tool in the spindle (what the probe touches with): a tool change
    /// without a firmware line, as an operator's hands do it.
    pub fn set_tool(&mut self, tool: Tool) {
        self.config.probe.tool = tool;
    }

    /// The last probe's machine position and whether it touched (what `$#` prints as PRB).
    pub fn last_probe(&self) -> ([f64; 3], bool) {
        (self.probe_position, self.probe_succeeded)
    }

    /// The board drives a 4th axis A (its `$103` is set).
    pub fn has_a(&self) -> bool {
        rotary::limits(&self.settings).is_some()
    }

    fn setting(&self, n: u16) -> f64 {
        self.settings.get(&n).copied().unwrap_or(0.0)
    }

    fn say(&mut self, s: &str) {
        self.out.extend(s.as_bytes());
        self.out.extend(b"\r\n");
    }

    /// A `[MSG:…]` line in the flavor's words.
    fn msg(&mut self, text: &str) {
        let m = self.config.flavor.message(text);
        self.say(&m);
    }

    fn banner(&mut self) {
        let banner = format!("\r\n{}", self.config.flavor.banner(&self.config.version));
        self.say(&banner);
        for m in self.config.flavor.boot_messages() {
            self.say(&m);
        }
    }

    fn boot(&mut self) {
        self.banner();
        if self.setting(22) != 0.0 {
            self.state = GrblState::Alarm;
            self.msg("'$H'|'$X' to unlock");
        }
    }

    /// Planner blocks free (what `Bf:` reports).
    pub fn planner_free(&self) -> usize {
        self.config.planner_blocks.saturating_sub(self.motion.len())
    }

    /// The planner's free blocks as `Bf:` reports them. grblHAL discards the running block
    /// once its steps are prepared, which happens up to [`Flavor::prepared_ahead`] seconds
    /// before it has run: from then on it no longer counts, although it still moves.
    pub fn reported_planner_free(&self) -> usize {
        let ahead = self.config.flavor.prepared_ahead();
        let prepared = match self.block_ends.front() {
            Some(end) if ahead > 0.0 && self.moving() => {
                let left = oficina_grbl::dist(&self.mpos, end);
                usize::from(left <= self.motion.speed() * ahead)
            }
            _ => 0,
        };
        (self.planner_free() + prepared).min(self.config.planner_blocks)
    }

    fn rx_capacity(&self) -> usize {
        self.config.rx_buffer - 1
    }

    /// One byte off the wire, as grbl's serial RX interrupt sees it.
    pub fn receive(&mut self, b: u8) {
        self.stats.bytes_received += 1;
        if Realtime::is_realtime_byte(b) {
            if let Some(r) = Realtime::from_byte(b) {
                self.realtime(r);
            }
            return;
        }
        if self.rx.len() >= self.rx_capacity() {
            self.stats.rx_overflows += 1;
            return;
        }
        self.rx.push_back(b);
        self.stats.max_rx_used = self.stats.max_rx_used.max(self.rx.len());
    }

    fn moving(&self) -> bool {
        (!self.motion.is_empty() || self.spin.is_some())
            && matches!(
                self.state,
                GrblState::Run | GrblState::Jog | GrblState::Hold(1) | GrblState::Door(2)
            )
    }

    /// Acts on a real-time byte (`?`, `!`, `~`, Ctrl-X, overrides, jog cancel).
    pub fn realtime(&mut self, r: Realtime) {
        let before = self.overrides;
        match r {
            Realtime::StatusQuery => {
                self.status_queries = self.status_queries.wrapping_add(1);
                let n = self.config.lose_status_every;
                if n > 0 && self.status_queries.is_multiple_of(n) {
                    return;
                }
                let s = self.status_report();
                self.say(&s);
            }
            Realtime::FeedHold => {
                if matches!(self.state, GrblState::Run) {
                    self.begin_decel(GrblState::Hold(1));
                } else if self.state == GrblState::Jog {
                    self.cancel_jog();
                }
            }
            Realtime::SafetyDoor => {
                if self.moving() {
                    self.begin_decel(GrblState::Door(2));
                } else if !matches!(self.state, GrblState::Alarm | GrblState::Sleep) {
                    self.resume_state = if self.motion.is_empty() {
                        GrblState::Idle
                    } else {
                        GrblState::Run
                    };
                    self.state = GrblState::Door(0);
                }
            }
            Realtime::CycleStart => match self.state {
                GrblState::Hold(0) | GrblState::Door(0) => {
                    self.motion.resume();
                    self.state = if self.motion.is_empty() && self.pending.is_none() {
                        GrblState::Idle
                    } else {
                        GrblState::Run
                    };
                }
                GrblState::Idle if !self.motion.is_empty() => {
                    self.motion.resume();
                    self.state = GrblState::Run;
                }
                _ => {}
            },
            Realtime::SoftReset => self.soft_reset(),
            Realtime::JogCancel => {
                if self.state == GrblState::Jog {
                    self.cancel_jog();
                }
            }
            Realtime::FeedOverrideReset => self.overrides.0 = 100,
            Realtime::FeedOverridePlus10 => nudge(&mut self.overrides.0, 10),
            Realtime::FeedOverrideMinus10 => nudge(&mut self.overrides.0, -10),
            Realtime::FeedOverridePlus1 => nudge(&mut self.overrides.0, 1),
            Realtime::FeedOverrideMinus1 => nudge(&mut self.overrides.0, -1),
            Realtime::RapidOverride100 => self.overrides.1 = 100,
            Realtime::RapidOverride50 => self.overrides.1 = 50,
            Realtime::RapidOverride25 => self.overrides.1 = 25,
            Realtime::SpindleOverrideReset => self.overrides.2 = 100,
            Realtime::SpindleOverridePlus10 => nudge(&mut self.overrides.2, 10),
            Realtime::SpindleOverrideMinus10 => nudge(&mut self.overrides.2, -10),
            Realtime::SpindleOverridePlus1 => nudge(&mut self.overrides.2, 1),
            Realtime::SpindleOverrideMinus1 => nudge(&mut self.overrides.2, -1),
            Realtime::SpindleStopToggle => {}
            Realtime::FloodToggle => self.interp.modal.flood = !self.interp.modal.flood,
            Realtime::MistToggle => self.interp.modal.mist = !self.interp.modal.mist,
        }
        // grbl (report.c): a changed override is shown in the very next report.
        if self.overrides != before && self.report_counter > 0 {
            self.report_counter = 6;
        }
        let (feed, rapid, _) = self.overrides;
        self.motion
            .set_overrides(feed as f64 / 100.0, rapid as f64 / 100.0);
    }

    /// The running block's motion so far ends at `to`.
    fn record_piece(&mut self, to: [f64; 3]) {
        if self.config.record_motion && oficina_grbl::dist(&self.piece_start, &to) > 1e-9 {
            self.motion_record.push((self.piece_start, to));
        }
        self.piece_start = to;
    }

    /// Moves finished lines from `awaiting` to `executed`.
    fn record_done(&mut self) {
        while self
            .awaiting
            .front()
            .is_some_and(|(_, seq)| *seq <= self.blocks_done)
        {
            let (l, _) = self.awaiting.pop_front().expect("front checked");
            self.executed.push(l);
        }
    }

    /// Drops every queued block; lines whose motion had not finished never ran.
    fn flush_planner(&mut self) {
        self.record_piece(self.motion.position());
        self.motion.clear();
        self.block_ends.clear();
        self.lanes.clear();
        self.spin = None;
        self.a_tail = self.mpos_a;
        self.mpos = self.motion.position();
        self.blocks_pushed = self.blocks_done;
        self.awaiting.clear();
    }

    /// grbl decelerates to a stop, then flushes every jog block.
    fn cancel_jog(&mut self) {
        // A jog line still waiting for planner room is dropped too, but it was received
        // and so is answered: every line gets exactly one reply.
        if let Some(p) = self.pending.take() {
            self.say(&p.reply);
        }
        self.motion.hold();
        self.jog_cancelling = true;
        if self.motion.held() || self.motion.is_empty() {
            self.end_jog_cancel();
        }
    }

    fn end_jog_cancel(&mut self) {
        self.flush_planner();
        self.jog_cancelling = false;
        self.jogging = false;
        self.state = GrblState::Idle;
        self.interp.pos = self.mpos;
        self.interp.a = self.mpos_a;
    }

    fn begin_decel(&mut self, into: GrblState) {
        self.motion.hold();
        self.state = into;
    }

    fn soft_reset(&mut self) {
        if self.homing.is_some() {
            // A reset during the cycle: grbl's EXEC_ALARM_HOMING_FAIL_RESET.
            return self.homing_failed(6);
        }
        // Only a reset while steps are being generated loses position; a completed hold
        // with blocks still queued is grbl's safe way to cancel a job.
        if self.moving() {
            // Stopping without deceleration loses steps on a real machine: grbl says so.
            self.state = GrblState::Alarm;
            self.say("ALARM:3");
        } else if self.state != GrblState::Alarm {
            self.state = GrblState::Idle;
        }
        self.flush_planner();
        self.pending = None;
        self.blocked = false;
        self.rx.clear();
        self.line.clear();
        self.line_overflow = false;
        self.jog_cancelling = false;
        self.jogging = false;
        self.check_mode = false;
        self.probe_succeeded = false;
        self.overrides = (100, 100, 100);
        self.motion.set_overrides(1.0, 1.0);
        let keep = (self.interp.wcs_offsets, self.interp.g28, self.interp.g30);
        self.interp = Interp {
            wcs_offsets: keep.0,
            g28: keep.1,
            g30: keep.2,
            pos: self.mpos,
            arc_tolerance: self.setting(12),
            a_axis: self.has_a(),
            a: self.mpos_a,
            ..Interp::default()
        };
        self.starving = None;
        self.banner();
        if self.state == GrblState::Alarm {
            self.msg("'$H'|'$X' to unlock");
        }
    }

    /// Advances the emulated firmware to time `now` (seconds since start).
    pub fn tick(&mut self, now: f64) {
        let dt = (now - self.clock).max(0.0);
        self.clock = now;
        // A tick far later than the 1 ms cadence means the host did not run us: motion
        // catches up in one step while bytes that were due wait in the reader.
        let was_late = self.host_late;
        if dt > 0.005 {
            self.host_late = true;
        }
        self.run_motion(dt);
        self.advance_homing(dt);
        self.host_late = was_late;
        if self.blocked || self.homing.is_some() {
            return;
        }
        // Take lines out of the RX ring while the previous one is fully planned.
        for _ in 0..64 {
            self.advance_pending();
            if self.pending.is_some() || self.blocked || self.homing.is_some() {
                break;
            }
            match self.next_line() {
                Some(line) => self.execute_line(&line),
                None => break,
            }
        }
        self.advance_pending();
    }

    fn next_line(&mut self) -> Option<String> {
        while let Some(b) = self.rx.pop_front() {
            if b == b'\n' || b == b'\r' {
                if self.line_overflow {
                    self.line_overflow = false;
                    self.line.clear();
                    return Some("\u{1}overflow".into());
                }
                let l = String::from_utf8_lossy(&self.line).into_owned();
                self.line.clear();
                return Some(l);
            }
            if self.line.len() >= 255 {
                self.line_overflow = true;
            } else {
                self.line.push(b);
            }
        }
        None
    }

    fn reply_error(&mut self, code: u8) {
        self.stats.errors_sent += 1;
        self.say(&format!("error:{code}"));
    }

    fn execute_line(&mut self, raw: &str) {
        if raw == "\u{1}overflow" {
            return self.reply_error(oficina_grbl::E_LINE_OVERFLOW);
        }
        let clean = match oficina_grbl::clean_line(raw) {
            Ok(c) => c,
            Err(e) => return self.reply_error(e),
        };
        if clean.is_empty() {
            // grbl answers an empty line with ok.
            return self.say("ok");
        }
        if let Some(cmd) = clean.strip_prefix('$') {
            return self.system_command(cmd, raw);
        }
        if matches!(
            self.state,
            GrblState::Alarm | GrblState::Jog | GrblState::Sleep
        ) {
            return self.reply_error(9);
        }
        let from = self.interp.pos;
        match self.interp.execute(&clean) {
            Err(e) => self.reply_error(e),
            Ok(mut effect) => {
                self.stats.lines_executed += 1;
                if self.check_mode {
                    return self.say("ok");
                }
                if self.beyond_soft_limits(&effect.segments) {
                    return self.alarm_soft_limit();
                }
                let probe = effect
                    .probe
                    .map(|kind| self.plan_probe(from, kind, &mut effect.segments));
                self.pending = Some(Pending {
                    // grbl's probe cycle starts only once the planner has emptied.
                    sync: effect.sync || effect.flow != Flow::Continue || probe.is_some(),
                    dwell: effect.dwell,
                    segments: effect.segments.into(),
                    flow: effect.flow,
                    probe,
                    reply: "ok".into(),
                    line: self.config.record_lines.then(|| clean.clone()),
                });
            }
        }
    }

    /// A probing move from `from`: cut short where the probe changes state, or dropped when
    /// it is already as the move seeks it (the parser then stays at `from`, as grbl's
    /// GC_UPDATE_POS_NONE). The move stops exactly at the contact: a real machine brakes
    /// past it and reports the contact, so the reported position is the same.
    fn plan_probe(&mut self, from: [f64; 3], kind: ProbeKind, segs: &mut Vec<Segment>) -> ProbeEnd {
        let model = &self.config.probe;
        if model.touching(from) != kind.away {
            segs.clear();
            self.interp.pos = from;
            return ProbeEnd::AlreadyTriggered;
        }
        let Some(last) = segs.last_mut() else {
            return ProbeEnd::Missed {
                no_error: kind.no_error,
            };
        };
        match model.first_change(from, last.to) {
            Some(at) => {
                last.to = at;
                self.interp.pos = at;
                ProbeEnd::Contact
            }
            None => ProbeEnd::Missed {
                no_error: kind.no_error,
            },
        }
    }

    /// The end of a probe cycle, once its motion is done: grbl's mc_probe_cycle reports
    /// the alarm first, then the probe position (MESSAGE_PROBE_COORDINATES), then `ok`.
    fn end_probe(&mut self, end: ProbeEnd) {
        let prb = |at: [f64; 3], ok: bool| {
            format!(
                "[PRB:{:.3},{:.3},{:.3}:{}]",
                at[0],
                at[1],
                at[2],
                u8::from(ok)
            )
        };
        match end {
            ProbeEnd::AlreadyTriggered => {
                self.probe_succeeded = false;
                self.state = GrblState::Alarm;
                self.say("ALARM:4");
            }
            ProbeEnd::Missed { no_error: false } => {
                // sys_probe_position keeps the last contact.
                self.probe_succeeded = false;
                self.state = GrblState::Alarm;
                self.say("ALARM:5");
                let l = prb(self.probe_position, false);
                self.say(&l);
            }
            ProbeEnd::Contact | ProbeEnd::Missed { no_error: true } => {
                self.probe_position = self.mpos;
                self.probe_succeeded = matches!(end, ProbeEnd::Contact);
                // The cycle waited for the machine to stop: it is idle when `ok` comes.
                if self.state == GrblState::Run {
                    self.state = GrblState::Idle;
                }
                let l = prb(self.probe_position, self.probe_succeeded);
                self.say(&l);
            }
        }
    }

    /// With `$20=1`, grbl's machine space is [-$13x, 0] on each axis.
    fn beyond_soft_limits(&self, segs: &[Segment]) -> bool {
        self.setting(20) != 0.0
            && segs
                .iter()
                .any(|s| (0..3).any(|i| s.to[i] > 0.0 || s.to[i] < -self.setting(130 + i as u16)))
    }

    /// grbl's limits_soft_check: the line is not run and gets no reply; the firmware raises
    /// ALARM:2 and answers nothing but status and reset until it is reset.
    fn alarm_soft_limit(&mut self) {
        self.flush_planner();
        self.pending = None;
        self.state = GrblState::Alarm;
        self.interp.pos = self.mpos;
        self.interp.a = self.mpos_a;
        self.say("ALARM:2");
        self.msg("Reset to continue");
        self.blocked = true;
    }

    fn advance_pending(&mut self) {
        let Some(p) = self.pending.as_mut() else {
            return;
        };
        if p.sync && (!self.motion.is_empty() || self.spin.is_some()) {
            return;
        }
        if p.sync && p.dwell > 0.0 {
            // A dwell holds the line until it has elapsed; time passes in run_motion.
            return;
        }
        let a_limits = rotary::limits(&self.settings);
        while let Some(p) = self.pending.as_mut() {
            if self.motion.len() >= self.config.planner_blocks || self.spin.is_some() {
                break;
            }
            let Some(&s) = p.segments.front() else { break };
            let tail = self.motion.tail();
            let length = oficina_grbl::dist(&tail, &s.to);
            let turn = s.a - self.a_tail;
            if let (Some(lim), true) = (a_limits, length < 1e-6 && turn.abs() > 1e-9) {
                // A alone: it waits for the blocks before it, then turns by itself.
                if !self.motion.is_empty() {
                    return;
                }
                p.segments.pop_front();
                self.spin = Some(Spin::new(self.a_tail, s.a, s.rate, lim));
                self.block_queued(s.to, s.a);
                break;
            }
            p.segments.pop_front();
            let (speed, kind) = match s.rate {
                Rate::Rapid => (f64::INFINITY, MoveKind::Rapid),
                // grbl's feeds are mm/min; the planner's mm/s.
                Rate::Feed(f) => (f / 60.0, MoveKind::Feed),
            };
            let speed = match a_limits {
                Some((rate, _)) => rotary::mixed_speed(speed, length, turn, rate),
                None => speed,
            };
            let push = Push {
                line: 0,
                end: s.to,
                speed,
                kind,
            };
            // A block without length queues nothing, as grbl drops blocks without steps;
            // the parser never lets a zero feed through, so no push fails.
            if !self.motion.push(push).unwrap_or(false) {
                continue;
            }
            self.lanes.push_back(Lane {
                start: tail,
                length,
                a0: self.a_tail,
                a1: s.a,
            });
            self.block_queued(s.to, s.a);
            if let Some(since) = self.starving.take() {
                self.stats.starvations += 1;
                if self.starving_host_late || self.host_late {
                    self.stats.starvations_host_late += 1;
                }
                self.stats.starved_seconds += self.clock - since;
            }
        }
        if self.pending.as_ref().is_some_and(|p| {
            // A probe line answers once its move has run.
            !p.segments.is_empty()
                || (p.probe.is_some() && (!self.motion.is_empty() || self.spin.is_some()))
        }) {
            return;
        }
        let p = self.pending.take().expect("pending checked above");
        // A line that waited for the machine to stop (G4) finds it idle: grbl's cycle stop
        // came before its `ok`, so a `$` command right after it is taken.
        if p.sync && self.state == GrblState::Run && self.motion.is_empty() && self.spin.is_none() {
            self.state = GrblState::Idle;
        }
        if let Some(l) = p.line {
            self.awaiting.push_back((l, self.blocks_pushed));
            self.record_done();
        }
        match p.flow {
            Flow::Pause => self.state = GrblState::Hold(0),
            Flow::End => self.state = GrblState::Idle,
            Flow::Continue => {}
        }
        if let Some(end) = p.probe {
            self.end_probe(end);
        }
        let reply = p.reply;
        self.say(&reply);
    }

    /// A block went to the planner (or to the rotary spin): the A tail moves on, the block
    /// is counted with where it ends, and an idle machine starts running (or jogging).
    fn block_queued(&mut self, to: [f64; 3], a: f64) {
        self.a_tail = a;
        self.blocks_pushed += 1;
        self.block_ends.push_back(to);
        if self.state == GrblState::Idle {
            self.state = if self.jogging {
                GrblState::Jog
            } else {
                GrblState::Run
            };
        }
    }

    fn run_motion(&mut self, dt: f64) {
        // Dwell of a waiting line.
        if let Some(p) = self.pending.as_mut() {
            if p.sync
                && p.dwell > 0.0
                && self.motion.is_empty()
                && self.spin.is_none()
                && !matches!(self.state, GrblState::Hold(_) | GrblState::Door(_))
            {
                let used = p.dwell.min(dt);
                p.dwell -= used;
                if p.dwell <= 1e-9 {
                    p.dwell = 0.0;
                }
            }
        }
        if let Some(spin) = self.spin.as_mut() {
            // A turn of A alone is short and runs to its end, a hold included; the hold
            // completes when it does.
            if !matches!(
                self.state,
                GrblState::Run | GrblState::Jog | GrblState::Hold(1) | GrblState::Door(2)
            ) {
                return;
            }
            let (a, done) = spin.advance(dt);
            self.mpos_a = a;
            self.stats.busy_seconds += dt - done.unwrap_or(0.0);
            let Some(rest) = done else { return };
            self.spin = None;
            self.blocks_done += 1;
            if let Some(end) = self.block_ends.pop_front() {
                self.record_piece(end);
            }
            self.record_done();
            // The time left after the turn goes to what follows.
            self.advance_pending();
            return self.run_motion(rest);
        }
        if self.motion.is_empty() {
            match self.state {
                GrblState::Run | GrblState::Jog if self.pending.is_none() => {
                    self.state = GrblState::Idle;
                    self.jogging = false;
                }
                GrblState::Hold(1) => self.state = GrblState::Hold(0),
                GrblState::Door(2) => self.state = GrblState::Door(0),
                _ => {}
            }
            return;
        }
        if !matches!(
            self.state,
            GrblState::Run | GrblState::Jog | GrblState::Hold(1) | GrblState::Door(2)
        ) {
            return;
        }
        let step = self.motion.advance(dt);
        self.stats.busy_seconds += dt - step.rest;
        self.mpos = self.motion.position();
        self.blocks_done += step.finished as u64;
        for _ in 0..step.finished {
            if let Some(end) = self.block_ends.pop_front() {
                self.record_piece(end);
            }
            if let Some(l) = self.lanes.pop_front() {
                self.mpos_a = l.a1;
            }
        }
        if let Some(l) = self.lanes.front() {
            self.mpos_a = l.a_at(self.mpos);
        }
        self.record_done();
        let at_rest = self.motion.held() || self.motion.is_empty();
        if self.jog_cancelling && at_rest {
            return self.end_jog_cancel();
        }
        match self.state {
            GrblState::Hold(1) if at_rest => self.state = GrblState::Hold(0),
            GrblState::Door(2) if at_rest => self.state = GrblState::Door(0),
            _ => {}
        }
        if !self.motion.is_empty() {
            return;
        }
        // The buffer ran dry: the machine stopped at the end of the last block.
        let more = !self.rx.is_empty() || self.pending.is_some();
        if self.state == GrblState::Run {
            self.starving = Some(self.clock - step.rest);
            self.starving_host_late = self.host_late;
            if !more {
                self.state = GrblState::Idle;
            }
        } else if self.state == GrblState::Jog && !more {
            self.state = GrblState::Idle;
            self.jogging = false;
        }
    }

    /// The `<…>` report, fields as grbl 1.1 prints them for the current `$10`.
    pub fn status_report(&mut self) -> String {
        let mask = self.setting(10) as u32;
        let wco = self.interp.wco();
        let inch = if self.setting(13) != 0.0 { 25.4 } else { 1.0 };
        // grblHAL prints as many axes as it drives: A (degrees, never scaled by $13) last.
        let a = self.has_a().then_some(self.mpos_a);
        let f = |p: [f64; 3], a: Option<f64>| {
            let xyz = format!("{:.3},{:.3},{:.3}", p[0] / inch, p[1] / inch, p[2] / inch);
            match a {
                Some(a) => format!("{xyz},{a:.3}"),
                None => xyz,
            }
        };
        let mut s = format!("<{}", self.state.name());
        if mask & 1 != 0 {
            s += &format!("|MPos:{}", f(self.mpos, a));
        } else {
            s += &format!(
                "|WPos:{}",
                f(
                    [
                        self.mpos[0] - wco[0],
                        self.mpos[1] - wco[1],
                        self.mpos[2] - wco[2]
                    ],
                    a
                )
            );
        }
        if mask & 2 != 0 {
            // grbl's serial_get_rx_buffer_available(): the full size when empty.
            let rx_free = self.config.rx_buffer - self.rx.len();
            // grblHAL reports one byte less: its ring keeps one slot unused.
            let rx_free = match self.config.flavor {
                Flavor::GrblHal => rx_free - 1,
                _ => rx_free,
            };
            s += &format!("|Bf:{},{}", self.reported_planner_free(), rx_free);
        }
        let spindle = if self.interp.modal.spindle == oficina_grbl::Spindle::Off {
            0.0
        } else {
            self.interp.spindle_speed
        };
        s += &format!("|FS:{:.0},{:.0}", self.speed() * 60.0 / inch, spindle);
        if self.config.probe.touching(self.mpos) {
            s += "|Pn:P";
        }
        if self.reported_wco != Some(wco) {
            self.report_counter = 0;
        }
        if self.report_counter == 0 {
            self.reported_wco = Some(wco);
            s += &format!("|WCO:{}", f(wco, a.map(|_| 0.0)));
            self.report_counter = if self.state == GrblState::Idle {
                10
            } else {
                30
            };
        } else {
            self.report_counter -= 1;
            if self.report_counter == 5 {
                let (a, b, c) = self.overrides;
                s += &format!("|Ov:{a},{b},{c}");
                let mut acc = String::new();
                match self.interp.modal.spindle {
                    oficina_grbl::Spindle::Cw => acc.push('S'),
                    oficina_grbl::Spindle::Ccw => acc.push('C'),
                    oficina_grbl::Spindle::Off => {}
                }
                if self.interp.modal.flood {
                    acc.push('F');
                }
                if self.interp.modal.mist {
                    acc.push('M');
                }
                if !acc.is_empty() {
                    s += &format!("|A:{acc}");
                }
            }
        }
        s.push('>');
        s
    }

    /// Current path speed, mm/s (°/s while A turns alone).
    fn speed(&self) -> f64 {
        match &self.spin {
            Some(s) => s.speed(),
            None => self.motion.speed(),
        }
    }

    /// Used RX bytes (what the sender's character count must never exceed).
    pub fn rx_used(&self) -> usize {
        self.rx.len()
    }
}

/// The planner for the machine the `$` settings describe, at rest at `at`.
fn new_motion(settings: &BTreeMap<u16, f64>, at: [f64; 3]) -> Incremental {
    Incremental::new(super::profile::motion_profile(settings), at)
        .expect("a Cartesian machine has linear kinematics")
}

fn format_setting(n: u16, v: f64) -> String {
    let unit = oficina_grbl::setting_info(n).map(|s| s.unit).unwrap_or("");
    if matches!(unit, "mask" | "boolean" | "microseconds" | "milliseconds") {
        format!("{}", v as i64)
    } else {
        format!("{v:.3}")
    }
}

/// A feed or spindle override step, kept within grbl's 10–200 % (config.h's
/// MIN/MAX_FEED_RATE_OVERRIDE and MIN/MAX_SPINDLE_SPEED_OVERRIDE).
fn nudge(percent: &mut u32, delta: i32) {
    *percent = (*percent as i32 + delta).clamp(10, 200) as u32;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feed(core: &mut Core, s: &str) {
        for b in s.bytes() {
            core.receive(b);
        }
    }

    fn take_out(core: &mut Core) -> String {
        let v: Vec<u8> = core.out.drain(..).collect();
        String::from_utf8(v).unwrap()
    }

    fn cfg() -> Config {
        Config {
            baud: None,
            settings: vec![(110, 6000.0), (111, 6000.0), (112, 6000.0)],
            ..Config::default()
        }
    }

    /// grbl reports `WCO:` every 10–30 reports, but at once after the offset changes
    /// (`system_flag_wco_change`): M2 going back to G54 included, or a sender's cached
    /// offset turns the end of a G55 program into a false position mismatch.
    #[test]
    fn a_changed_work_offset_is_reported_at_once() {
        let mut c = Core::new(cfg());
        let wco = |c: &mut Core| {
            let r = c.status_report();
            r.split("|WCO:")
                .nth(1)
                .map(|w| w.trim_end_matches('>').to_string())
        };
        assert_eq!(wco(&mut c).as_deref(), Some("0.000,0.000,0.000"));
        assert_eq!(wco(&mut c), None);
        for (line, expect) in [
            ("G10 L2 P2 Y-101.6\n", None),
            ("G55\n", Some("0.000,-101.600,0.000")),
            ("M2\n", Some("0.000,0.000,0.000")),
            ("G92 X1\n", Some("-1.000,0.000,0.000")),
        ] {
            take_out(&mut c);
            feed(&mut c, line);
            c.tick(0.0);
            assert!(take_out(&mut c).contains("ok"), "{line}");
            assert_eq!(wco(&mut c).as_deref(), expect, "{line}");
            assert_eq!(wco(&mut c), None, "{line}: once");
        }
    }

    #[test]
    fn boots_answers_and_moves_with_acceleration() {
        let mut c = Core::new(cfg());
        assert!(take_out(&mut c).contains("Grbl 1.1h ['$' for help]"));
        feed(&mut c, "G1 X10 F600\n");
        c.tick(0.0);
        assert_eq!(take_out(&mut c), "ok\r\n");
        assert_eq!(c.state, GrblState::Run);
        // 10 mm/s at grbl's default $120 = 10 mm/s²: 1 s and 5 mm up, 1 s and 5 mm down.
        c.tick(0.5);
        assert!((c.mpos[0] - 1.25).abs() < 1e-9, "{:?}", c.mpos);
        c.tick(1.0);
        assert!((c.mpos[0] - 5.0).abs() < 1e-9, "{:?}", c.mpos);
        assert!(c.status_report().contains("|FS:600,0"));
        c.tick(2.0001);
        assert_eq!(c.mpos, [10.0, 0.0, 0.0]);
        assert_eq!(c.state, GrblState::Idle);
        feed(&mut c, "G1 X10 Y\n$99=1\n$I\n");
        c.tick(1.1);
        assert_eq!(
            take_out(&mut c),
            "error:2\r\nerror:3\r\n[VER:1.1h.20190830:]\r\n[OPT:V,15,128]\r\nok\r\n"
        );
    }

    #[test]
    fn rx_ring_overflow_drops_bytes_like_grbl() {
        let mut c = Core::new(cfg());
        feed(&mut c, &"X".repeat(200));
        assert_eq!(c.rx_used(), 127);
        assert_eq!(c.stats.rx_overflows, 73);
    }

    #[test]
    fn planner_fills_to_fifteen_blocks_and_holds_the_ok() {
        let mut c = Core::new(cfg());
        take_out(&mut c);
        for i in 1..=20 {
            feed(&mut c, &format!("G1X{i}F60\n"));
            c.tick(0.0);
        }
        assert_eq!(c.stats.rx_overflows, 0);
        assert_eq!(c.planner_free(), 0);
        // The 16th line waits in the planner queue, so only 15 oks so far.
        assert_eq!(take_out(&mut c).matches("ok").count(), 15);
        // 0.1 s and 0.05 mm to reach 1 mm/s at 10 mm/s², then 0.95 s to the block's end.
        c.tick(1.04);
        assert_eq!(take_out(&mut c).matches("ok").count(), 0);
        c.tick(1.06);
        assert_eq!(take_out(&mut c).matches("ok").count(), 1);
    }

    #[test]
    fn hold_decelerates_resume_continues_reset_in_motion_alarms() {
        let mut c = Core::new(Config {
            settings: vec![(120, 100.0), (121, 100.0), (122, 100.0), (110, 6000.0)],
            ..cfg()
        });
        feed(&mut c, "G1X100F600\n");
        c.tick(0.0);
        c.tick(1.0);
        c.realtime(Realtime::FeedHold);
        assert_eq!(c.state, GrblState::Hold(1));
        // 0.1 s and 0.5 mm up to 10 mm/s, then 0.9 s cruising: at 9.5 mm. Braking at
        // 100 mm/s² takes 0.1 s over 0.5 mm.
        assert!((c.mpos[0] - 9.5).abs() < 1e-9, "{:?}", c.mpos);
        c.tick(1.05);
        assert_eq!(c.state, GrblState::Hold(1));
        assert!((c.mpos[0] - 9.875).abs() < 1e-9, "{:?}", c.mpos);
        c.tick(1.2);
        assert_eq!(c.state, GrblState::Hold(0));
        assert!((c.mpos[0] - 10.0).abs() < 1e-9, "{:?}", c.mpos);
        c.tick(5.0);
        assert!((c.mpos[0] - 10.0).abs() < 1e-9);
        c.realtime(Realtime::CycleStart);
        c.tick(6.0);
        assert!((c.mpos[0] - 19.5).abs() < 1e-9, "{:?}", c.mpos);
        take_out(&mut c);
        c.realtime(Realtime::SoftReset);
        assert_eq!(c.state, GrblState::Alarm);
        let out = take_out(&mut c);
        assert!(out.starts_with("ALARM:3\r\n"), "{out}");
        feed(&mut c, "G0X0\n$X\n");
        c.tick(6.1);
        assert_eq!(
            take_out(&mut c),
            "error:9\r\n[MSG:Caution: Unlocked]\r\nok\r\n"
        );
    }

    /// The emulator's job time against an independent sum of length / feed per move, with
    /// accelerations so high that the ramps take microseconds.
    #[test]
    fn job_time_is_length_over_feed() {
        let mut config = cfg();
        config.settings.extend([(120, 1e7), (121, 1e7), (122, 1e7)]);
        let mut c = Core::new(config);
        let moves = [
            (3.0, 4.0, 600.0),
            (3.0, 0.0, 1200.0),
            (0.0, 0.0, 300.0),
            (10.0, 10.0, 6000.0),
        ];
        let mut program = String::new();
        let (mut x, mut y, mut expected) = (0.0f64, 0.0f64, 0.0);
        for (tx, ty, f) in moves {
            program += &format!("G1X{tx}Y{ty}F{f}\n");
            expected += (tx - x).hypot(ty - y) / (f / 60.0);
            (x, y) = (tx, ty);
        }
        // Rapid back home: each axis at most $110/$111 = 6000 mm/min = 100 mm/s, so the
        // slowest axis sets the time.
        program += "G0X0Y0\n";
        expected += x.abs().max(y.abs()) / 100.0;
        let mut t = 0.0;
        let mut fed = false;
        while t < 60.0 {
            if !fed {
                feed(&mut c, &program);
                fed = true;
            }
            c.tick(t);
            if t > 0.0 && c.state == GrblState::Idle && c.rx_used() == 0 && c.planner_free() == 15 {
                break;
            }
            t += 0.001;
        }
        assert!(
            (t - expected).abs() <= 0.0015,
            "emulated {t:.4} s, expected {expected:.4} s"
        );
    }

    #[test]
    fn soft_limit_alarm_blocks_until_reset() {
        let mut c = Core::new(Config {
            settings: vec![(22, 1.0), (20, 1.0)],
            ..cfg()
        });
        feed(&mut c, "$X\nG0X-10\nG0X5\nG0X-1\n");
        c.tick(0.0);
        let out = take_out(&mut c);
        assert!(
            out.ends_with("ok\r\nok\r\nALARM:2\r\n[MSG:Reset to continue]\r\n"),
            "{out}"
        );
        c.tick(1.0);
        assert_eq!(take_out(&mut c), "", "no reply to anything before a reset");
        c.realtime(Realtime::SoftReset);
        assert_eq!(c.state, GrblState::Alarm);
        assert!(take_out(&mut c).contains("'$H'|'$X' to unlock"));
    }

    fn homing_core(limit_switches: bool) -> Core {
        let mut c = Core::new(Config {
            // Homing on, seek at 600 mm/min (10 mm/s), 10 mm of Z travel.
            settings: vec![(22, 1.0), (25, 600.0), (132, 10.0)],
            limit_switches,
            ..cfg()
        });
        take_out(&mut c);
        c
    }

    #[test]
    fn homing_takes_its_time_z_first_and_answers_when_home() {
        let mut c = homing_core(true);
        // The machine was moved away: 20 mm in Z, 40 mm in X.
        run_lines(&mut c, "$X\nG0 X-40 Y-10 Z-20\nG4 P0\n");
        let t0 = c.clock;
        feed(&mut c, "$H\nG0 X-1\n");
        c.tick(t0);
        c.tick(t0 + 1.0);
        assert_eq!(take_out(&mut c), "", "no answer while homing");
        assert_eq!(c.state, GrblState::Home);
        assert!(c.status_report().starts_with("<Home|"));
        // Z rises first (10 mm/s): half way after 1 s, X untouched.
        assert!((c.mpos[2] + 10.0).abs() < 1e-6, "{:?}", c.mpos);
        assert!((c.mpos[0] + 40.0).abs() < 1e-6, "{:?}", c.mpos);
        c.tick(t0 + 4.0);
        assert_eq!(c.state, GrblState::Home, "X and Y take 4 s more");
        assert!(
            c.mpos[2].abs() < 1e-9 && (c.mpos[0] + 20.0).abs() < 1e-6,
            "{:?}",
            c.mpos
        );
        c.tick(t0 + 6.01);
        // Home, answered; the line after it runs from there.
        assert!(take_out(&mut c).starts_with("ok\r\nok\r\n"));
        assert_eq!(c.mpos, [0.0; 3]);
        c.tick(t0 + 8.0);
        assert!((c.mpos[0] + 1.0).abs() < 1e-9, "{:?}", c.mpos);
    }

    #[test]
    fn homing_without_switches_or_reset_mid_cycle_alarms() {
        let mut c = homing_core(false);
        let out = run_lines(&mut c, "$X\n$H\n");
        // 15 mm searched at 10 mm/s.
        assert!((c.clock - 1.5).abs() < 0.05, "{}", c.clock);
        assert!(out.contains("ALARM:9\r\nok\r\n"), "{out}");
        assert!(
            out.contains("Grbl 1.1h ['$' for help]"),
            "reset after: {out}"
        );
        assert!(out.contains("'$H'|'$X' to unlock"), "{out}");
        assert_eq!(c.state, GrblState::Alarm);

        let mut c = homing_core(true);
        run_lines(&mut c, "$X\nG0 Z-30\nG4 P0\n");
        feed(&mut c, "$H\n");
        c.tick(c.clock);
        c.tick(c.clock + 1.0);
        assert_eq!(c.state, GrblState::Home);
        c.realtime(Realtime::SoftReset);
        let out = take_out(&mut c);
        assert!(out.starts_with("ALARM:6\r\nok\r\n"), "{out}");
        assert_eq!(c.state, GrblState::Alarm);
        assert!(
            (c.mpos[2] + 20.0).abs() < 1e-6,
            "stopped where it was: {:?}",
            c.mpos
        );
    }

    fn probe_core() -> Core {
        use super::super::probe::{Stock, TouchPlate};
        let mut config = cfg();
        config.settings.extend([(120, 1e5), (121, 1e5), (122, 1e5)]);
        config.probe = ProbeModel {
            stock: Some(Stock::flat([0.0, 0.0], [100.0, 50.0], -40.0)),
            plate: Some(TouchPlate {
                min: [10.0, 10.0],
                max: [30.0, 30.0],
                thickness: 5.0,
            }),
            ..ProbeModel::default()
        };
        let mut c = Core::new(config);
        take_out(&mut c);
        c
    }

    /// Feeds `lines` and runs the clock until every line is answered.
    fn run_lines(c: &mut Core, lines: &str) -> String {
        feed(c, lines);
        let want = lines.lines().count();
        let mut out = String::new();
        let mut t = c.clock;
        while out.matches("ok").count() + out.matches("error").count() < want && t < 600.0 {
            t += 0.01;
            c.tick(t);
            out += &take_out(c);
        }
        out
    }

    #[test]
    fn probe_stops_at_the_plate_and_reports_before_ok() {
        let mut c = probe_core();
        let out = run_lines(&mut c, "G0 X20 Y20 Z-10\nG38.2 Z-60 F300\n");
        assert_eq!(out, "ok\r\n[PRB:20.000,20.000,-35.000:1]\r\nok\r\n");
        assert_eq!(c.mpos, [20.0, 20.0, -35.0]);
        assert!(c.status_report().contains("|Pn:P"));
        // The parser continues from the contact, not from the programmed end.
        run_lines(&mut c, "G91 G0 Z2\nG4 P0\n");
        let out = run_lines(&mut c, "$#\n");
        assert!((c.interp.pos[2] + 33.0).abs() < 1e-9, "{:?}", c.interp.pos);
        assert!(
            out.contains("[TLO:0.000]\r\n[PRB:20.000,20.000,-35.000:1]\r\nok"),
            "{out}"
        );
        // Probing again from above touches again; probing away from it opens.
        let out = run_lines(&mut c, "G38.2 Z-10 F100\nG38.4 Z5\n");
        assert!(out.contains("[PRB:20.000,20.000,-35.000:1]"), "{out}");
        assert_eq!(c.state, GrblState::Idle);
    }

    #[test]
    fn probe_failures_as_grbl_reports_them() {
        let mut c = probe_core();
        // Beside the stock: G38.3 ends with :0 and no alarm.
        let out = run_lines(&mut c, "G0 X150 Y20 Z-10\nG38.3 Z-60 F600\n");
        assert_eq!(out, "ok\r\n[PRB:150.000,20.000,-60.000:0]\r\nok\r\n");
        assert_eq!(c.state, GrblState::Idle);
        // G38.2 alarms and keeps the last probe position.
        let out = run_lines(&mut c, "G0 Z-10\nG38.2 Z-60 F600\nG0 Z0\n");
        assert_eq!(
            out,
            "ok\r\nALARM:5\r\n[PRB:150.000,20.000,-60.000:0]\r\nok\r\nerror:9\r\n"
        );
        assert_eq!(c.state, GrblState::Alarm);
        // Already touching at the start: ALARM:4 and no motion.
        let out = run_lines(&mut c, "$X\nG0 X50 Y25 Z-40\nG38.2 Z-45 F100\n");
        assert!(out.ends_with("ok\r\nALARM:4\r\nok\r\n"), "{out}");
        assert_eq!(c.mpos, [50.0, 25.0, -40.0]);
        assert_eq!(c.interp.pos, [50.0, 25.0, -40.0]);
        // A reset forgets the success, not the position.
        c.realtime(Realtime::SoftReset);
        assert_eq!(c.last_probe(), ([150.0, 20.0, -60.0], false));
    }

    #[test]
    fn probing_away_seeks_the_opening() {
        let mut c = probe_core();
        // Not touching: G38.4 and G38.5 start with the probe open, ALARM:4 as grbl.
        let out = run_lines(&mut c, "G0 X20 Y20 Z-10\nG38.5 Z-20 F600\n");
        assert!(out.ends_with("ok\r\nALARM:4\r\nok\r\n"), "{out}");
        assert_eq!(c.mpos, [20.0, 20.0, -10.0]);
        // Resting on the plate (top −35), sliding along its top never opens: G38.5 ends
        // with :0 and no alarm, G38.4 raises ALARM:5.
        let out = run_lines(&mut c, "$X\nG0 Z-35\nG38.5 X25 F600\n");
        assert!(
            out.ends_with("[PRB:25.000,20.000,-35.000:0]\r\nok\r\n"),
            "{out}"
        );
        assert_eq!(c.state, GrblState::Idle);
        let out = run_lines(&mut c, "G38.4 X28 F600\n");
        assert!(out.starts_with("ALARM:5\r\n"), "{out}");
        // Sliding off the plate, a point tip opens just past its edge at X30.
        let out = run_lines(&mut c, "$X\nG38.4 X40 F600\n");
        assert!(out.contains("[PRB:30.000,20.000,-35.000:1]"), "{out}");
    }

    #[test]
    fn a_longer_tool_touches_higher() {
        let mut c = probe_core();
        c.set_tool(Tool {
            length: 12.5,
            diameter: 0.0,
        });
        let out = run_lines(&mut c, "G0 X60 Y20 Z0\nG38.2 Z-60 F600\n");
        assert!(out.contains("[PRB:60.000,20.000,-27.500:1]"), "{out}");
    }

    #[test]
    fn check_mode_validates_without_moving() {
        let mut c = Core::new(cfg());
        feed(&mut c, "$C\nG1X5F100\nG2X1\n$C\n");
        c.tick(0.0);
        let out = take_out(&mut c);
        assert!(
            out.contains("[MSG:Enabled]\r\nok\r\nok\r\nerror:35\r\n[MSG:Disabled]\r\nok\r\n"),
            "{out}"
        );
        assert_eq!(c.mpos, [0.0; 3]);
        assert_eq!(c.state, GrblState::Idle);
    }
}
