//! `GrblMachine`: one object for "run this job on that grbl", the API the `oficina run
//! --machine grbl:…` path and the console call. It starts at the top, at a file line or
//! where the journal says the last run stopped; journals every line; survives a lost link
//! by reconnecting, recovering and (if allowed) resuming by itself.

use crate::job::StreamProgram;
use crate::journal::Journal;
use crate::reconnect::{connect_with_retry, LinkState, RetryPolicy};
use crate::resume::{Located, ResumeOptions};
use crate::sender::{Control, Notice, Sender, SenderOptions, StreamEnd, StreamReport};
use crate::toolchange::{self, ToolChange, ToolError, ToolLengths, ToolPolicy, ToolStop};
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
    /// What happens at `M6` (grbl 1.1 has no tool changer): applied when the program is
    /// read ([`StreamProgram::with_tool_change`]).
    pub tool_change: ToolChange,
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
            tool_change: ToolChange::default(),
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
        let job = StreamProgram::with_tool_change(
            &path.display().to_string(),
            &text,
            &settings.tool_change,
        )?;
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
        // What the last run measured (remeasure): read before the journal is reopened.
        let past = Journal::load(journal_path, job).ok();
        let mut journal = Journal::open(journal_path, job)
            .map_err(|e| format!("cannot write journal {}: {e}", journal_path.display()))?;
        let mut lengths = ToolLengths::default();
        if job.tool_change.policy == ToolPolicy::Ignore {
            for s in job.tool_stops.iter().filter(|s| s.index >= from) {
                observer(Notice::Message(format!(
                    "{}:{}: M6 T{} dropped (--tool-change ignore): the tool is not changed",
                    job.name, s.file_line, s.tool
                )));
            }
        }
        if job.tool_change.policy == ToolPolicy::Remeasure {
            lengths = self.tool_lengths_at(job, from, past.as_ref())?;
            if let (true, None, Some(setter)) = (
                job.tool_change.measure_at_start && from == 0,
                lengths.reference,
                &job.tool_change.setter,
            ) {
                observer(Notice::Message(
                    "measuring the tool in the spindle on the tool setter (the reference)".into(),
                ));
                toolchange::remeasure(
                    &mut self.sender,
                    setter,
                    &mut lengths,
                    None,
                    &mut journal,
                    observer,
                )
                .map_err(|e| format!("measuring the first tool: {e}"))?;
            }
        }
        // A resume approaches line `from` first (unless a tool change there does it).
        let mut approach = from > 0;
        loop {
            if let Some(stop) = job.tool_stop_at(from) {
                let changed = toolchange::change_tool(
                    &mut self.sender,
                    job,
                    stop,
                    &settings.resume,
                    &mut lengths,
                    &mut journal,
                    control,
                    observer,
                );
                if let Err(e) = changed {
                    return self.tool_change_failed(job, stop, e);
                }
                approach = false;
            }
            if approach {
                observer(Notice::Message(format!(
                    "resume at {}:{}: restoring modal state and approaching at Z{}",
                    job.name, job.lines[from].file_line, settings.resume.safe_z
                )));
                self.sender
                    .run_preamble_at(job, from, entry, &settings.resume)?;
                if job.tool_change.policy == ToolPolicy::Remeasure {
                    toolchange::apply_offset(&mut self.sender, lengths.offset)
                        .map_err(|e| format!("restoring the tool length offset: {e}"))?;
                }
                approach = false;
            }
            let until = job.next_stop_after(from);
            let report =
                self.sender
                    .stream_range(job, from, until, Some(&mut journal), control, observer);
            if report.end == StreamEnd::Completed && until < job.len() {
                from = until;
                continue;
            }
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
            from = at.index;
            entry = at.entry;
            approach = true;
        }
    }

    /// The tool lengths in force at line `from` under `remeasure`, from the journal of the
    /// last run: the first tool's touch, and the offset applied at the last tool stop
    /// before `from` (a stop at `from` measures again). Refuses when a length is needed
    /// and the journal does not have it.
    fn tool_lengths_at(
        &self,
        job: &StreamProgram,
        from: usize,
        past: Option<&crate::journal::JournalState>,
    ) -> Result<ToolLengths, String> {
        if from == 0 {
            // A run from the top measures its first tool afresh.
            return Ok(ToolLengths::default());
        }
        let mut lengths = ToolLengths {
            reference: past.and_then(|p| p.tool_reference),
            offset: None,
        };
        if let Some(stop) = job.tool_stops.iter().rev().find(|s| s.index < from) {
            let known =
                past.and_then(|p| p.tool_lengths.iter().rev().find(|(i, _)| *i == stop.index));
            match known {
                Some((_, d)) => lengths.offset = Some(*d),
                None => {
                    return Err(format!(
                        "{}: resume at line {} needs the length of T{} measured after the M6 at line {}, and the journal does not have it: resume from line {} so the tool is changed and measured again",
                        job.name,
                        job.lines.get(from).map(|l| l.file_line).unwrap_or(0),
                        stop.tool,
                        stop.file_line,
                        stop.file_line
                    ))
                }
            }
        }
        Ok(lengths)
    }

    /// A tool change that did not finish, as a stream that ended at its stop: the resume
    /// point is the stop, so a resume asks for the tool again.
    fn tool_change_failed(
        &mut self,
        job: &StreamProgram,
        stop: &ToolStop,
        e: ToolError,
    ) -> Result<RunOutcome, String> {
        let end = match &e {
            ToolError::Stopped => StreamEnd::Stopped,
            ToolError::Alarm(c) => StreamEnd::Alarm(*c),
            ToolError::Lost(why) => StreamEnd::Disconnected(why.clone()),
            ToolError::Failed(why) => {
                return Err(format!(
                    "{}: tool change to T{} at line {}: {why}; resume from line {} to try again",
                    job.name, stop.tool, stop.file_line, stop.file_line
                ))
            }
        };
        let work_pos = match end {
            StreamEnd::Disconnected(_) => None,
            _ => self.sender.wait_at_rest().ok(),
        };
        Ok(RunOutcome::Streamed(StreamReport {
            end,
            acked_end: stop.index,
            sent_end: stop.index,
            certain: stop.index,
            work_pos,
            resume: Some(Located {
                index: stop.index,
                reason: format!(
                    "the change to T{} at line {} did not finish",
                    stop.tool, stop.file_line
                ),
                entry: None,
            }),
            recovery_error: None,
            bytes_sent: 0,
            elapsed: std::time::Duration::ZERO,
            max_in_flight: 0,
            sender_stalls: 0,
        }))
    }
}
