//! The machine panel's controls on a [`Session`], the same on real firmware and on the
//! virtual machine: typed lines (MDI), home, unlock, soft reset, the work coordinate systems
//! (zero some axes, choose G54…G59, go to the work zero, read the table) and macros.
//!
//! Real firmware gets its own lines (`$H`, `G10 L20 P2 X0`, `G55`, `$#`). The virtual
//! machine has no firmware language: a typed G-code line runs there as a one-line job (in
//! the system chosen, no modal state kept between lines), `$` lines are refused, and the
//! work offsets are the session's (G54 is the profile's).

use crate::macros::{expand, MacroValues};
use crate::offsets::SYSTEMS;
use crate::session::{state_name, JobView};
use crate::{Error, Probing, Session};
use oficina_grbl::GrblDevice;
use oficina_machine::{Command, Job, MachineError, Pace, State};
use serde::Serialize;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Longest typed line, bytes (grblHAL's line buffer; grbl's own is 80 after cleaning).
const MAX_TYPED: usize = 256;
/// Longest wait for the virtual machine to run a typed line.
const VIRTUAL_LINE_WAIT: Duration = Duration::from_secs(30);
/// Homing speed of the virtual machine, mm/min.
const HOME_FEED: f64 = 3000.0;
/// Where firmware's Z goes before moving to the work zero: 1 mm under machine zero, the top
/// of travel once homed (grbl's convention), machine mm. Never lower than Z is already.
const FIRMWARE_CLEAR_Z: f64 = -1.0;

/// A typed `G10 L2 P…` (origin given) or `G10 L20 P…` (the current point named).
#[derive(Debug, PartialEq)]
struct TypedG10 {
    /// 0 = G54 … 5 = G59; `None` for P0, the active one.
    system: Option<usize>,
    /// L20: the values are the current point's new work coordinates.
    relative_to_here: bool,
    /// X, Y, Z as given, in mm (a G20 in the line converts).
    values: [Option<f64>; 3],
}

/// The G10 origin setting of a cleaned line the interpreter accepted, if it is one.
fn typed_g10(clean: &str) -> Option<TypedG10> {
    let words = oficina_grbl::line_words(clean).ok()?;
    let has = |l: char, v: f64| words.iter().any(|&(c, x)| c == l && x == v);
    let l20 = has('L', 20.0);
    if !has('G', 10.0) || !(has('L', 2.0) || l20) {
        return None;
    }
    let unit = if has('G', 20.0) { 25.4 } else { 1.0 };
    let p = words.iter().find(|w| w.0 == 'P').map_or(0.0, |w| w.1);
    let mut values = [None; 3];
    for &(c, v) in &words {
        if let Some(i) = "XYZ".find(c) {
            values[i] = Some(v * unit);
        }
    }
    Some(TypedG10 {
        system: (p >= 1.0).then(|| p as usize - 1),
        relative_to_here: l20,
        values,
    })
}

/// What a typed line got: the firmware's lines before its acknowledgement and the error it
/// gave instead of `ok`, explained.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MdiReply {
    /// The line as sent.
    pub line: String,
    /// The lines before the acknowledgement (`$$` settings, `[G54:…]`, messages).
    pub lines: Vec<String>,
    /// The error instead of `ok`, in words.
    pub error: Option<String>,
}

impl MdiReply {
    /// The console's lines: `> line`, the reply, then `ok` or the error.
    pub fn console_lines(&self) -> Vec<String> {
        let mut out = vec![format!("> {}", self.line)];
        out.extend(self.lines.iter().cloned());
        out.push(self.error.clone().unwrap_or_else(|| "ok".into()));
        out
    }
}

/// What homing answers `error:5` means, in words.
const HOMING_DISABLED: &str = "homing is not enabled on this machine ($22=0): if it has limit switches, enable it with `$22=1` (typed below) and home again; otherwise jog to the work zero and set it by hand";

/// How long a homing cycle may take before the firmware is given up on: grbl searches up
/// to 1.5 × each axis's travel at the seek rate, one axis after another.
const HOMING_PATIENCE: Duration = Duration::from_secs(300);

/// What the firmware's answer to `$H` means: homed, refused (homing disabled, not idle), or
/// an alarm raised during the cycle (grbl answers `ok` after `ALARM:9` and resets).
fn homing_outcome(lines: &[String], error: Option<String>) -> Result<(), String> {
    if let Some(alarm) = lines.iter().find(|l| l.starts_with("ALARM:")) {
        return Err(format!(
            "homing failed: {}",
            crate::session::alarm_meaning(alarm)
        ));
    }
    match error {
        Some(e) if e.starts_with("error:5 ") => Err(format!("{HOMING_DISABLED} ({e})")),
        Some(e) => Err(format!("homing refused: {e}")),
        None => Ok(()),
    }
}

impl Session {
    /// Why the machine takes no typed line now (a job streams, it jogs), if it does not.
    fn busy(&self, what: &str) -> Result<(), Error> {
        let running = self.job.as_ref().is_some_and(|j| j.completed.is_none());
        let state = self.machine.status().state;
        match state {
            State::Idle | State::Alarm(_) if !running => Ok(()),
            State::Jog => Err(Error(format!(
                "{what}: the machine is jogging; wait until it stops"
            ))),
            s if running => Err(Error(format!(
                "{what}: a job is running ({}): wait until it ends; Hold, Stop and Reset still work",
                state_name(&s)
            ))),
            // Firmware still moving after a typed line: it queues the next one itself.
            State::Run if self.profile().is_none() => Ok(()),
            s => Err(Error(format!(
                "{what}: the machine is not idle ({})",
                state_name(&s)
            ))),
        }
    }

    /// Sends one typed line (G-code or a `$` command) and waits for its acknowledgement.
    /// Refused while a job runs; on the virtual machine a G-code line runs as a one-line
    /// job and `$` lines are refused.
    pub fn mdi(&mut self, line: &str) -> Result<MdiReply, Error> {
        let line = line.trim();
        if line.is_empty() {
            return Err(Error("type a G-code line or a $ command".into()));
        }
        if line.len() > MAX_TYPED || line.chars().any(char::is_control) {
            return Err(Error(format!(
                "one line of at most {MAX_TYPED} printable characters (real-time keys are buttons)"
            )));
        }
        self.busy(&format!("`{line}`"))?;
        if self.profile().is_some() {
            return self.virtual_line(line);
        }
        let reply = self.machine.raw_line(line).map_err(busy_error)?;
        self.offsets.read_reply(&reply.lines);
        let reply = MdiReply {
            line: line.to_string(),
            lines: reply.lines,
            error: reply.error,
        };
        // A line that changed the offsets: the table is read again (`$#` answers when idle).
        let upper = line.to_ascii_uppercase();
        if reply.error.is_none()
            && !line.starts_with('$')
            && ["G10", "G5", "G92"].iter().any(|g| upper.contains(g))
        {
            let _ = self.read_offsets();
        }
        Ok(reply)
    }

    /// A typed G-code line on the virtual machine: a one-line job in the system chosen, run
    /// at once; nothing moves when it is refused (the machine checks a whole job first).
    fn virtual_line(&mut self, line: &str) -> Result<MdiReply, Error> {
        if line.starts_with('$') {
            return Err(Error(format!(
                "`{line}`: the virtual machine has no firmware $ commands (its profile says how it moves); Home, Unlock and the offsets table work without them"
            )));
        }
        let clean = oficina_grbl::clean_line(line).unwrap_or_default();
        if clean.contains("G92") {
            return Err(Error(format!(
                "`{line}`: on the virtual machine a typed line is a job of its own, so a G92 offset would end with it; set the work zero with Zero or G10 L20 instead"
            )));
        }
        let text = format!("{}{line}\nM2\n", self.virtual_preamble());
        let error = self.run_virtual(line, text, Pace::Instant)?;
        if error.is_none() {
            // The job's interpreter ends with the line: its G10 goes to the session's table.
            if let Some(set) = typed_g10(&clean) {
                self.set_virtual_origin(set)?;
            }
        }
        Ok(MdiReply {
            line: line.to_string(),
            lines: Vec::new(),
            error,
        })
    }

    /// What a job of typed lines starts with on the virtual machine (it ends with M2, the
    /// program end the machine asks for): the system chosen, and a move of no length to
    /// where the machine stands, so the interpreter starts there (axes a line leaves out
    /// stay where they are, G91 counts from there).
    fn virtual_preamble(&self) -> String {
        let [x, y, z] = self.machine.status().machine_pos;
        format!(
            "{}\nG90 G53 G0 X{x:.6} Y{y:.6} Z{z:.6}\n",
            SYSTEMS[self.offsets.active]
        )
    }

    /// Runs `text` as a job named after `line` on the virtual machine; with `Pace::Instant`
    /// waits for its end and gives its refusal (the machine is unlocked again: nothing moved).
    fn run_virtual(
        &mut self,
        line: &str,
        text: String,
        pace: Pace,
    ) -> Result<Option<String>, Error> {
        let lines = text.lines().count();
        let instant = pace == Pace::Instant;
        self.machine
            .start(Job {
                name: format!("typed: {line}"),
                text: Arc::new(text),
                start_line: None,
                pace,
            })
            .map_err(Error::from_display)?;
        self.job = Some(JobView {
            name: format!("typed: {line}"),
            lines,
            from_line: None,
            speed: None,
            completed: None,
        });
        if !instant {
            return Ok(None);
        }
        let t0 = Instant::now();
        loop {
            let state = self.machine.status().state;
            if let (State::Idle | State::Alarm(_), Some(j)) = (&state, &mut self.job) {
                // Ended (the events say so too, later): the next line may follow at once.
                j.completed = Some(state == State::Idle);
            }
            match state {
                State::Idle => return Ok(None),
                State::Alarm(why) => {
                    // The whole line was refused before any motion.
                    let _ = self.machine.command(Command::Unlock);
                    return Ok(Some(why));
                }
                _ if t0.elapsed() > VIRTUAL_LINE_WAIT => {
                    return Err(Error(format!("`{line}` is still running")))
                }
                _ => std::thread::sleep(Duration::from_millis(2)),
            }
        }
    }

    /// Reads the work offsets again: the firmware's `$#` and `$G` (idle or in alarm); the
    /// virtual machine's are the session's already.
    pub fn read_offsets(&mut self) -> Result<(), Error> {
        if self.profile().is_some() {
            return Ok(());
        }
        for q in ["$#", "$G"] {
            let reply = self.machine.raw_line(q).map_err(busy_error)?;
            if let Some(e) = reply.error {
                return Err(Error(format!(
                    "{q}: {e} (the firmware lists its offsets when idle)"
                )));
            }
            self.offsets.read_reply(&reply.lines);
        }
        Ok(())
    }

    /// Homes. Real firmware runs its homing cycle (`$H`, answered only when it is over,
    /// seconds later) as a routine on the device's thread: the returned [`Probing`] is
    /// waited on *without* the session, so status keeps flowing (state `home`) and Stop
    /// reaches the cycle; it ends with what went wrong (refused, an alarm). The virtual
    /// machine moves back to its reference point (the profile's start): `None`, nothing
    /// to wait for.
    pub fn home(&mut self) -> Result<Option<Probing<()>>, Error> {
        self.busy("home")?;
        if self.profile().is_some() {
            let p = self.machine.status().machine_pos;
            let delta = [0, 1, 2].map(|i| self.home[i] - p[i]);
            return self.jog(delta, HOME_FEED).map(|()| None);
        }
        let Some(dev) = self
            .machine
            .as_any_mut()
            .and_then(|m| m.downcast_mut::<GrblDevice>())
        else {
            return Err(Error(
                "home: this machine is neither virtual nor grbl firmware".into(),
            ));
        };
        let r = dev
            .start_routine(|link| {
                let reply = link.line("$H", HOMING_PATIENCE)?;
                homing_outcome(&reply.lines, reply.error)
            })
            .map_err(Error::from_display)?;
        Ok(Some(Probing(r)))
    }

    /// Leaves the alarm state (grbl's `$X`).
    pub fn unlock(&mut self) -> Result<(), Error> {
        self.command(Command::Unlock)
    }

    /// Soft reset: firmware stops at once and restarts (Ctrl-X; in alarm if it was moving,
    /// G54 active again); the virtual machine stops its job or jog (it never loses position).
    pub fn soft_reset(&mut self) -> Result<(), Error> {
        if self.profile().is_none() {
            self.machine.soft_reset().map_err(Error::from_display)?;
            self.offsets.active = 0;
            return Ok(());
        }
        match self.machine.status().state {
            State::Idle | State::Alarm(_) => Ok(()),
            State::Jog => self.command(Command::JogCancel),
            _ => self.command(Command::Stop),
        }
    }

    /// Makes the current point the work zero of the active system for the axes asked:
    /// `G10 L20 P<n>` on firmware, the session's table (the profile's G54) on the virtual
    /// machine. Idle only.
    pub fn zero(&mut self, axes: [bool; 3]) -> Result<(), Error> {
        if !axes.contains(&true) {
            return Err(Error("zero: name at least one axis".into()));
        }
        let status = self.machine.status();
        if status.state != State::Idle {
            return Err(Error(format!(
                "work zero is set when idle, not while {}",
                state_name(&status.state)
            )));
        }
        let n = self.offsets.active;
        let Some(profile) = self.profile().cloned() else {
            let words: String = ["X0", "Y0", "Z0"]
                .iter()
                .zip(axes)
                .filter(|(_, on)| *on)
                .map(|(w, _)| format!(" {w}"))
                .collect();
            self.firmware_lines(&[format!("G10 L20 P{}{words}", n + 1)])?;
            return self.read_offsets();
        };
        let mut profile = profile;
        for i in (0..3).filter(|i| axes[*i]) {
            // The work position is 0 there: the origin is the machine position less G92.
            self.offsets.systems[n][i] = status.machine_pos[i] - self.offsets.g92[i];
        }
        profile.work_offset = self.offsets.systems[0];
        profile.start = status.machine_pos;
        self.rebuild(profile)
    }

    /// A typed `G10 L2`/`L20` on the virtual machine, kept in the session's table (the VM
    /// is rebuilt with it, as [`Session::zero`] does).
    fn set_virtual_origin(&mut self, set: TypedG10) -> Result<(), Error> {
        let Some(mut profile) = self.profile().cloned() else {
            return Ok(());
        };
        let status = self.machine.status();
        let n = set.system.unwrap_or(self.offsets.active);
        for (i, v) in set.values.iter().enumerate() {
            let Some(v) = v else { continue };
            self.offsets.systems[n][i] = if set.relative_to_here {
                // L20: the current point gets work coordinate v (G92 stays on top).
                status.machine_pos[i] - self.offsets.g92[i] - v
            } else {
                *v
            };
        }
        profile.work_offset = self.offsets.systems[0];
        profile.start = status.machine_pos;
        self.rebuild(profile)
    }

    /// Makes G54…G59 (`system` 0…5) the active work system.
    pub fn select_system(&mut self, system: usize) -> Result<(), Error> {
        let name = *SYSTEMS
            .get(system)
            .ok_or_else(|| Error(format!("work system {system}: 0 (G54) to 5 (G59)")))?;
        self.busy(name)?;
        if self.profile().is_none() {
            self.firmware_lines(&[name.to_string()])?;
            self.read_offsets()?;
        }
        self.offsets.active = system;
        Ok(())
    }

    /// Goes to the work zero of the active system, safely: Z first up to a clearance (never
    /// down), then X and Y, then Z to 0 only when `z_too`.
    pub fn go_to_zero(&mut self, z_too: bool) -> Result<(), Error> {
        self.busy("go to zero")?;
        let mz = self.machine.status().machine_pos[2];
        let clear = match self.profile() {
            Some(p) => p.travel[2][1] - 1.0,
            None => FIRMWARE_CLEAR_Z,
        };
        let lines = zero_moves(mz, clear, z_too);
        if self.profile().is_none() {
            return self.firmware_lines(&lines);
        }
        let text = format!("{}{}\nM2\n", self.virtual_preamble(), lines.join("\n"));
        self.run_virtual("go to work zero", text, Pace::Speed(1.0))
            .map(|_| ())
    }

    /// Sends firmware lines one by one; the first refusal ends it, explained.
    fn firmware_lines(&mut self, lines: &[String]) -> Result<(), Error> {
        for l in lines {
            let reply = self.machine.raw_line(l).map_err(busy_error)?;
            if let Some(e) = reply.error {
                return Err(Error(format!("`{l}`: {e}")));
            }
        }
        Ok(())
    }

    /// The values a macro's parameters take now (the firmware's last probe is read first
    /// when the macro uses it).
    pub fn macro_values(&mut self, wants_probe: bool) -> MacroValues {
        if wants_probe {
            let _ = self.read_offsets();
        }
        let s = self.snapshot();
        MacroValues {
            work: s.work_pos,
            machine: s.machine_pos,
            probe: self.offsets.probe.clone(),
        }
    }

    /// Runs a macro's text through typed lines, its parameters replaced from where the
    /// machine is now; stops at the first line refused. Refused as a whole during a job,
    /// and before anything is sent when a parameter is unknown.
    pub fn run_macro(&mut self, text: &str) -> Result<Vec<MdiReply>, Error> {
        self.busy("macro")?;
        let values = self.macro_values(text.to_ascii_lowercase().contains("prb_"));
        let lines = expand(text, &values)?;
        let mut replies = Vec::new();
        for l in lines {
            let r = self.mdi(&l)?;
            let failed = r.error.is_some();
            replies.push(r);
            if failed {
                break;
            }
        }
        Ok(replies)
    }
}

/// The moves to the work zero: Z up to `clear` (machine mm) when below it, X Y, then Z0.
fn zero_moves(mz: f64, clear: f64, z_too: bool) -> Vec<String> {
    let mut lines = Vec::new();
    if mz < clear - 1e-6 {
        lines.push(format!("G53 G0 Z{clear:.3}"));
    }
    lines.push("G90 G0 X0 Y0".into());
    if z_too {
        lines.push("G0 Z0".into());
    }
    lines
}

fn busy_error(e: MachineError) -> Error {
    match e {
        MachineError::Busy(_) => Error(
            "a job is running: typed lines wait until it ends; Hold, Stop and Reset still work"
                .into(),
        ),
        e => Error::from_display(e),
    }
}

#[cfg(test)]
mod tests;
