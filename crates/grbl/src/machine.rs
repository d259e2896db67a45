//! `GrblMachine`: one object for "run this job on that grbl", the API the `oficina run
//! --machine grbl:…` path and the console call. It starts at the top, at a file line or
//! where the journal says the last run stopped; journals every line; survives a lost link
//! by reconnecting, recovering and (if allowed) resuming by itself.

use crate::job::StreamProgram;
use crate::journal::Journal;
use crate::reconnect::{connect_with_retry, LinkState, RetryPolicy};
use crate::resume::ResumeOptions;
use crate::sender::{Control, Notice, Sender, SenderOptions, StreamEnd, StreamReport};
use crate::transport::Endpoint;
use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;

/// Where a run starts.
#[derive(Clone, Debug, PartialEq)]
pub enum Start {
    /// From the first line.
    Beginning,
    /// The first G-code line at or after this 1-based file line.
    FileLine(usize),
    /// Where the journal says the last run stopped (after a crash, power cut, pulled cable).
    Journal,
}

/// How a job is run: where it starts, its journal, how it resumes.
#[derive(Clone, Debug)]
pub struct RunSettings {
    /// Where the run starts.
    pub start: Start,
    /// Default: the program's path with `.journal` appended.
    pub journal: Option<PathBuf>,
    /// How a stopped job is resumed.
    pub resume: ResumeOptions,
    /// Clear an alarm with `$X` when recovering (only when the position is known to hold).
    pub unlock_alarm: bool,
    /// Reconnect after a lost link (None: give up at once).
    pub reconnect: Option<RetryPolicy>,
    /// After reconnecting, continue without asking.
    pub auto_resume: bool,
    /// Run the whole program through grbl's check mode (`$C`) first and refuse to cut if
    /// the firmware rejects any line.
    pub check_first: bool,
}

impl Default for RunSettings {
    fn default() -> Self {
        RunSettings {
            start: Start::Beginning,
            journal: None,
            resume: ResumeOptions::default(),
            unlock_alarm: false,
            reconnect: Some(RetryPolicy::default()),
            auto_resume: false,
            check_first: false,
        }
    }
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub enum RunOutcome {
    /// The job had already completed (journal, or the machine rests at its end); nothing
    /// was sent.
    AlreadyDone,
    /// The job was streamed; how it ended.
    Streamed(StreamReport),
}

/// A grbl board driven from this thread: connect, stream a job with a journal, resume.
pub struct GrblMachine {
    /// Where the board is.
    pub endpoint: Endpoint,
    /// The streaming protocol over the link.
    pub sender: Sender,
}

impl GrblMachine {
    /// `uri`: `grbl:/dev/ttyUSB0`, `/dev/ttyUSB0@250000`, `tcp://192.168.1.5:23`.
    pub fn connect(uri: &str) -> Result<GrblMachine, String> {
        let endpoint: Endpoint = uri.parse()?;
        GrblMachine::connect_to(endpoint, SenderOptions::default())
    }

    /// Connects to `endpoint` with `options`.
    pub fn connect_to(endpoint: Endpoint, options: SenderOptions) -> Result<GrblMachine, String> {
        let sender = Sender::connect(&endpoint, options)
            .map_err(|e| format!("cannot talk to grbl at {endpoint}: {e}"))?;
        Ok(GrblMachine { endpoint, sender })
    }

    /// The journal of `program`: the one `settings` name, else `<program>.journal`.
    pub fn journal_path(program: &Path, settings: &RunSettings) -> PathBuf {
        settings.journal.clone().unwrap_or_else(|| {
            let mut p = program.as_os_str().to_owned();
            p.push(".journal");
            PathBuf::from(p)
        })
    }

    /// Reads and runs the program at `path`. Controls (hold, resume, stop, overrides) come
    /// from `control`; progress, status and events go to `observer`.
    pub fn run_file(
        &mut self,
        path: &Path,
        settings: &RunSettings,
        control: Option<&Receiver<Control>>,
        observer: &mut dyn FnMut(Notice),
    ) -> Result<(StreamProgram, RunOutcome), String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let job = StreamProgram::from_text(&path.display().to_string(), &text)?;
        let journal = GrblMachine::journal_path(path, settings);
        let outcome = self.run(&job, &journal, settings, control, observer)?;
        Ok((job, outcome))
    }

    /// Streams `job`, journalling progress to `journal_path`, resuming as `settings` say; `control`
    /// carries the operator's requests and `observer` hears progress.
    pub fn run(
        &mut self,
        job: &StreamProgram,
        journal_path: &Path,
        settings: &RunSettings,
        control: Option<&Receiver<Control>>,
        observer: &mut dyn FnMut(Notice),
    ) -> Result<RunOutcome, String> {
        if job.is_empty() {
            return Err(format!("{}: no G-code lines to send", job.name));
        }
        if settings.check_first {
            observer(Notice::Message(format!(
                "checking {} in grbl's check mode ($C)",
                job.name
            )));
            let bad = self.sender.check_job(job)?;
            if !bad.is_empty() {
                let list: Vec<String> = bad
                    .iter()
                    .map(|(i, code)| {
                        format!(
                            "  {}:{} `{}`: {}",
                            job.name,
                            job.lines[*i].file_line,
                            job.lines[*i].text,
                            crate::messages::describe_error(*code)
                        )
                    })
                    .collect();
                return Err(format!(
                    "grbl rejects {} line(s); nothing was cut:\n{}",
                    bad.len(),
                    list.join("\n")
                ));
            }
        }
        let mut entry = None;
        let mut from = match settings.start {
            Start::Beginning => 0,
            Start::FileLine(n) => job
                .index_of_file_line(n)
                .ok_or_else(|| format!("{}: no G-code at or after line {n}", job.name))?,
            Start::Journal => {
                let st = Journal::load(journal_path, job)?;
                if st.completed >= job.len() {
                    return Ok(RunOutcome::AlreadyDone);
                }
                let at = self.sender.recover(
                    job,
                    st.completed,
                    st.sent_end,
                    st.acked_end,
                    settings.unlock_alarm,
                )?;
                observer(Notice::Message(format!("resuming: {}", at.reason)));
                entry = at.entry;
                at.index
            }
        };
        if from >= job.len() {
            return Ok(RunOutcome::AlreadyDone);
        }
        if from > 0 {
            observer(Notice::Message(format!(
                "resume at {}:{}: restoring modal state and approaching at Z{}",
                job.name, job.lines[from].file_line, settings.resume.safe_z
            )));
            self.sender
                .run_preamble_at(job, from, entry, &settings.resume)?;
        }
        let mut journal = Journal::open(journal_path, job)
            .map_err(|e| format!("cannot write journal {}: {e}", journal_path.display()))?;
        loop {
            let report = self
                .sender
                .stream(job, from, Some(&mut journal), control, observer);
            let StreamEnd::Disconnected(why) = &report.end else {
                return Ok(RunOutcome::Streamed(report));
            };
            let Some(policy) = &settings.reconnect else {
                return Ok(RunOutcome::Streamed(report));
            };
            observer(Notice::Message(format!(
                "connection lost ({why}); reconnecting for up to {:.0} s",
                policy.deadline.as_secs_f64()
            )));
            let options = self.sender.options.clone();
            let reconnected = connect_with_retry(&self.endpoint, &options, policy, &mut |st| {
                if let LinkState::Waiting { error, retry_in } = st {
                    observer(Notice::Message(format!(
                        "not yet: {error}; next try in {:.1} s",
                        retry_in.as_secs_f64()
                    )));
                }
            });
            match reconnected {
                Ok(s) => self.sender = s,
                Err(e) => {
                    observer(Notice::Message(e.to_string()));
                    return Ok(RunOutcome::Streamed(report));
                }
            }
            let at = self.sender.recover(
                job,
                report.certain,
                report.sent_end,
                report.acked_end,
                settings.unlock_alarm,
            )?;
            observer(Notice::Message(format!("reconnected: {}", at.reason)));
            if !settings.auto_resume || at.index >= job.len() {
                return Ok(RunOutcome::Streamed(StreamReport {
                    resume: Some(at),
                    ..report
                }));
            }
            self.sender
                .run_preamble_at(job, at.index, at.entry, &settings.resume)?;
            from = at.index;
        }
    }
}
