//! The plumbing of a firmware [`oficina_machine::Machine`] (grbl's and Marlin's): the link
//! parked while no job runs, the job's thread that takes it and gives it back before it
//! announces the end (so a start right after the end finds it), the operator's control
//! channel to that thread, the status snapshot and events it sends, and how the last job
//! ended.

use oficina_machine::{Event, JobReport, MachineError, Status};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;

/// A lock that a panicked holder does not poison for the others.
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// The link `L` and the job thread that borrows it, controlled by `C` messages.
pub(crate) struct Worker<L, C> {
    /// The link while no job runs; a running job's thread holds it.
    pub(crate) idle: Arc<Mutex<Option<L>>>,
    pub(crate) status: Arc<Mutex<Status>>,
    pub(crate) events_tx: Sender<Event>,
    pub(crate) events_rx: Receiver<Event>,
    pub(crate) control: Option<Sender<C>>,
    pub(crate) thread: Option<JoinHandle<()>>,
    /// How the last job ended ([`oficina_machine::Machine::job_report`]).
    pub(crate) report: Arc<Mutex<Option<JobReport>>>,
}

impl<L, C> Worker<L, C> {
    pub(crate) fn new() -> Worker<L, C> {
        let (events_tx, events_rx) = mpsc::channel();
        Worker {
            idle: Arc::new(Mutex::new(None)),
            status: Arc::new(Mutex::new(Status::idle([0.0; 3]))),
            events_tx,
            events_rx,
            control: None,
            thread: None,
            report: Arc::new(Mutex::new(None)),
        }
    }

    /// The job thread has not finished.
    pub(crate) fn alive(&self) -> bool {
        self.thread.as_ref().is_some_and(|w| !w.is_finished())
    }

    /// A job holds the link: its thread took it and has not given it back.
    pub(crate) fn job_running(&self) -> bool {
        lock(&self.idle).is_none() && self.alive()
    }

    /// The parked link for a new job (the last job's thread is joined first), and a fresh
    /// control channel's receiving end for the new thread.
    pub(crate) fn take_link(&mut self, busy: &str) -> Result<(L, Receiver<C>), MachineError> {
        if self.job_running() {
            return Err(MachineError::Busy(busy.into()));
        }
        if let Some(w) = self.thread.take() {
            let _ = w.join();
        }
        let link = lock(&self.idle).take().ok_or(MachineError::NotConnected)?;
        let (tx, rx) = mpsc::channel();
        self.control = Some(tx);
        Ok((link, rx))
    }

    /// Sends `c` to the running job.
    pub(crate) fn send(&self, c: C) -> Result<(), MachineError> {
        match (&self.control, self.job_running()) {
            (Some(tx), true) => tx.send(c).map_err(|_| MachineError::NotConnected),
            _ => Err(MachineError::Refused("no job is running".into())),
        }
    }

    /// Ends the job with `stop` (if one runs), waits for its thread and drops the link.
    pub(crate) fn close(&mut self, stop: C) {
        if let Some(c) = self.control.take() {
            let _ = c.send(stop);
        }
        if let Some(w) = self.thread.take() {
            let _ = w.join();
        }
        *lock(&self.idle) = None;
    }
}
