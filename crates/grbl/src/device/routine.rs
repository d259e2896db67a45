//! Short routines (a probing routine, a height map) on the device's own thread, as a job
//! runs: the worker holds the link for the routine's length and asks the firmware for its
//! status while each line is under way, so a shell that shows the machine (the server's
//! pump) sees it move; the caller waits on the [`Routine`] holding nothing the status needs.
//! Hold, resume, overrides and stop reach the routine as they reach a job.

use super::{lock, translate_status, GrblDevice};
use crate::link::LinkEvent;
use crate::machine::GrblMachine;
use crate::messages;
use crate::probe::ProbeLink;
use crate::realtime::Realtime;
use crate::response::Response;
use crate::sender::Control;
use oficina_machine::{Event, MachineError, RawReply, Status};
use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A routine running on the device's thread: [`Routine::wait`] gives its result.
pub struct Routine<T> {
    rx: Receiver<Result<T, String>>,
}

impl<T> Routine<T> {
    /// Waits for the routine's end.
    pub fn wait(self) -> Result<T, String> {
        self.rx
            .recv()
            .unwrap_or_else(|_| Err("the routine's thread ended without an answer".into()))
    }
}

/// Status is asked this often while a line is under way.
const STATUS_PERIOD: Duration = Duration::from_millis(150);

impl GrblDevice {
    /// Runs `f` over the link on a thread of the device's own, as a job (refused while a job
    /// or another routine runs); its lines are sent one at a time, each waited for.
    pub fn start_routine<T, F>(&mut self, f: F) -> Result<Routine<T>, MachineError>
    where
        T: Send + 'static,
        F: FnOnce(&mut dyn ProbeLink) -> Result<T, String> + Send + 'static,
    {
        let (mut machine, ctl_rx) = self.jobs.take_link("a job or a routine is running")?;
        let (tx, rx) = mpsc::channel();
        let (idle, status, events) = (
            self.jobs.idle.clone(),
            self.jobs.status.clone(),
            self.jobs.events_tx.clone(),
        );
        let wco = machine.sender.last_wco.clone().unwrap_or_else(|| {
            let s = lock(&status);
            std::array::from_fn::<f64, 3, _>(|i| s.machine_pos[i] - s.work_pos[i]).to_vec()
        });
        self.jobs.thread = Some(std::thread::spawn(move || {
            let mut link = Watched {
                machine: &mut machine,
                status: &status,
                events: &events,
                control: &ctl_rx,
                wco,
            };
            let result = f(&mut link);
            let wco = link.wco.clone();
            if let Ok(st) = machine.sender.status() {
                let mut s = lock(&status);
                translate_status(&st, &wco, &mut s);
                let _ = events.send(Event::Status(s.clone()));
            }
            // The link goes back before the answer, so the caller finds the device idle.
            *lock(&idle) = Some(machine);
            let _ = tx.send(result);
        }));
        Ok(Routine { rx })
    }
}

/// The link as a routine sees it: each line waited for while status is asked.
struct Watched<'a> {
    machine: &'a mut GrblMachine,
    status: &'a Arc<Mutex<Status>>,
    events: &'a mpsc::Sender<Event>,
    control: &'a Receiver<Control>,
    wco: Vec<f64>,
}

impl Watched<'_> {
    fn realtime(&mut self, r: Realtime) -> Result<(), String> {
        self.machine.sender.realtime(r).map_err(|e| e.to_string())
    }

    /// After a reset: the firmware's lines until its banner, an alarm it raised (a reset
    /// mid-move, mid-homing) said as it comes.
    fn await_restart(&mut self) {
        let deadline = Instant::now() + self.machine.sender.options.reply_timeout;
        while Instant::now() < deadline {
            match self.machine.sender.link.recv(Duration::from_millis(30)) {
                Some(LinkEvent::Line(Response::Alarm(code), _)) => {
                    let _ = self
                        .events
                        .send(Event::Alarm(messages::describe_alarm(code)));
                }
                Some(LinkEvent::Line(Response::Welcome { .. }, _)) | Some(LinkEvent::Closed(_)) => {
                    return
                }
                _ => {}
            }
        }
    }

    /// Operator requests that came in; `Err` when the operator stopped the routine.
    fn obey(&mut self) -> Result<(), String> {
        while let Ok(c) = self.control.try_recv() {
            match c {
                Control::Hold => self.realtime(Realtime::FeedHold)?,
                Control::Resume => self.realtime(Realtime::CycleStart)?,
                Control::Realtime(r) => self.realtime(r)?,
                Control::Stop => {
                    // Hold first so the reset finds the machine at rest (no lost position).
                    self.realtime(Realtime::FeedHold)?;
                    std::thread::sleep(Duration::from_millis(500));
                    self.realtime(Realtime::SoftReset)?;
                    self.await_restart();
                    return Err("stopped by the operator (feed hold, then reset)".into());
                }
            }
        }
        Ok(())
    }
}

impl ProbeLink for Watched<'_> {
    fn line(&mut self, line: &str, patience: Duration) -> Result<RawReply, String> {
        let description = self.machine.sender.link.description.clone();
        let timeout = patience.max(self.machine.sender.options.reply_timeout);
        self.machine
            .sender
            .link
            .send_line(line)
            .map_err(|e| e.to_string())?;
        let deadline = Instant::now() + timeout;
        let mut lines = Vec::new();
        let mut asked: Option<Instant> = None;
        loop {
            if Instant::now() > deadline {
                return Err(format!(
                    "{description}: no reply to `{line}` within {timeout:?}"
                ));
            }
            self.obey()?;
            if asked.is_none_or(|t| t.elapsed() >= STATUS_PERIOD) {
                self.realtime(Realtime::StatusQuery)?;
                asked = Some(Instant::now());
            }
            match self.machine.sender.link.recv(Duration::from_millis(30)) {
                Some(LinkEvent::Line(Response::Ok, _)) => {
                    return Ok(RawReply { lines, error: None })
                }
                Some(LinkEvent::Line(Response::Error(c), _)) => {
                    return Ok(RawReply {
                        lines,
                        error: Some(messages::describe_error(c)),
                    })
                }
                Some(LinkEvent::Line(Response::Status(st), _)) => {
                    if let Some(w) = st.wco.as_ref().filter(|w| w.len() >= 3) {
                        self.wco = w.clone();
                        self.machine.sender.last_wco = Some(w.clone());
                    }
                    let mut s = lock(self.status);
                    translate_status(&st, &self.wco, &mut s);
                    let _ = self.events.send(Event::Status(s.clone()));
                }
                Some(LinkEvent::Line(Response::Alarm(code), raw)) => {
                    // Said as it comes (the shell shows the alarm), and kept in the reply.
                    let _ = self
                        .events
                        .send(Event::Alarm(messages::describe_alarm(code)));
                    lines.push(raw)
                }
                Some(LinkEvent::Line(Response::Welcome { .. }, raw)) => {
                    // The firmware reset (after an alarm, say): nothing more is answered.
                    lines.push(raw);
                    return Ok(RawReply {
                        lines,
                        error: Some(format!("the firmware restarted before answering `{line}`")),
                    });
                }
                Some(LinkEvent::Line(_, raw)) => lines.push(raw),
                Some(LinkEvent::Closed(why)) => return Err(format!("{description}: {why}")),
                None => {}
            }
        }
    }
}
