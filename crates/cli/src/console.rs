//! `oficina console`: a terminal to grbl-family firmware (serial, TCP or the built-in
//! emulator) with a live status line, and the job runner: stream a file with progress and
//! ETA, hold / resume / stop from the keyboard, and resume from a line or from the journal
//! after a stop, an error, a crash or a pulled cable.
//!
//! The console drives a [`GrblDevice`] through the [`Machine`] trait: connecting, and the
//! whole job mode (start; hold / resume / stop and the feed and spindle override resets as
//! [`Command`]s; progress from [`Machine::next_event`]; the end summary and resume hint from
//! [`Machine::job_report`]). Two things stay direct, because the trait cannot say them:
//! - the interactive terminal ([`interactive`]) takes the link ([`GrblDevice::take_link`]):
//!   it pipelines whatever is typed (G-code, `$$`, `$N=V`, `$X`, `$H`, real-time keys,
//!   jogs) and echoes every firmware line as it arrives, in the firmware's own words. The
//!   trait's calls are request/reply (each waits for its own `ok`, and would swallow the
//!   replies to lines still in flight), its settings are parsed numbers checked against
//!   grbl's table (a grblHAL-only `$N` would be refused, `$0=10` reprinted as `10.000`),
//!   its unlock drops the firmware's `[MSG:…]`, and it has no home, reset or door key;
//!   a continuous jog streams increments paced by their acknowledgements;
//! - in job mode, the override keys other than the resets (`f+10`, `r50`, `sstop`, `flood`
//!   …) are grbl's relative real-time bytes, sent with [`GrblDevice::realtime`]: the
//!   trait's overrides are absolute factors, and it has no rapid, coolant or spindle-stop key.

use crate::tool_change::ToolChangeArgs;
use anyhow::{bail, Context};
use oficina_grbl::{ContinuousJog, JogRequest};
use oficina_grbl::{Endpoint, GrblDevice, GrblMachine, ResumeOptions, RetryPolicy, StreamProgram};
use oficina_grbl::{LinkEvent, Realtime, Response, RunSettings, Start, StatusReport};
use oficina_grbl::{Mode, Sender, SenderOptions};
use oficina_grbl_emu::{Config, Emulator};
use oficina_machine::{Command, Event, Machine, Pace, State, Status};
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// `println!` that does not panic when whoever reads our output went away.
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Serial port of the board, e.g. /dev/ttyUSB0 or COM3.
    #[arg(long, conflicts_with_all = ["tcp", "emulator"])]
    pub port: Option<String>,
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
    /// Network firmware (grblHAL, FluidNC): HOST:PORT.
    #[arg(long, conflicts_with = "emulator")]
    pub tcp: Option<String>,
    /// Start the built-in grbl emulator and talk to it over a pseudo-terminal.
    #[arg(long)]
    pub emulator: bool,
    /// List serial ports and exit.
    #[arg(long)]
    pub list_ports: bool,
    /// Stream this G-code file instead of the interactive terminal.
    #[arg(long, value_name = "FILE")]
    pub job: Option<PathBuf>,
    /// Resume the job from this line of the file (modal state rebuilt, safe approach).
    #[arg(long, value_name = "N", requires = "job", conflicts_with = "resume")]
    pub from_line: Option<usize>,
    /// Resume the job where its journal says the last run stopped.
    #[arg(long, requires = "job")]
    pub resume: bool,
    /// Journal of acknowledged lines (default: FILE.journal).
    #[arg(long, value_name = "PATH")]
    pub journal: Option<PathBuf>,
    /// Work Z (mm) to travel at when approaching a resume point.
    #[arg(long, default_value_t = 5.0)]
    pub safe_z: f64,
    /// Feed (mm/min) of the final approach move down to the resume point.
    #[arg(long, default_value_t = 300.0)]
    pub plunge_feed: f64,
    /// Seconds to let the spindle reach speed before resuming a cut.
    #[arg(long, default_value_t = 2.0)]
    pub spindle_delay: f64,
    /// On resume, unlock ($X) a machine left in alarm (only if you know its position holds).
    #[arg(long)]
    pub unlock: bool,
    /// After a lost connection, try to reconnect for this many seconds (0: do not).
    #[arg(long, default_value_t = 30.0, value_name = "SECONDS")]
    pub reconnect: f64,
    /// After reconnecting, continue the job by itself (otherwise print where to resume).
    #[arg(long)]
    pub auto_resume: bool,
    /// Run the job through grbl's check mode ($C) first; cut only if every line passes.
    #[arg(long, requires = "job")]
    pub check: bool,
    /// One line at a time instead of filling the firmware's buffer.
    #[arg(long)]
    pub send_response: bool,
    #[command(flatten)]
    pub tool_change: ToolChangeArgs,
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    if args.list_ports {
        let ports = oficina_grbl::list_ports().context("cannot list serial ports")?;
        if ports.is_empty() {
            say!("no serial ports found");
        }
        for p in ports {
            say!("{}\t{}", p.path, p.kind);
        }
        return Ok(ExitCode::SUCCESS);
    }
    // The emulator lives as long as this command.
    let mut _emulator = None;
    let endpoint = if let Some(port) = &args.port {
        Endpoint::Serial {
            path: port.clone(),
            baud: args.baud,
        }
    } else if let Some(addr) = &args.tcp {
        Endpoint::Tcp { addr: addr.clone() }
    } else if args.emulator {
        let emu = Emulator::start(Config {
            settings: vec![
                (110, 5000.0),
                (111, 5000.0),
                (112, 2000.0),
                (120, 500.0),
                (121, 500.0),
                (122, 200.0),
            ],
            ..Config::default()
        });
        let path = emu
            .serve_pty()
            .context("cannot open a pseudo-terminal for the emulator")?;
        eprintln!("emulator on {path}");
        _emulator = Some(emu);
        Endpoint::Serial {
            path,
            baud: 115_200,
        }
    } else {
        bail!("say which machine: --port /dev/ttyUSB0, --tcp HOST:PORT or --emulator (see --list-ports)");
    };
    let options = SenderOptions {
        mode: args.send_response.then_some(Mode::SendResponse),
        ..SenderOptions::default()
    };
    let mut machine = GrblDevice::at(endpoint, options);
    let info = machine.connect().map_err(anyhow::Error::msg)?;
    let firmware = info
        .firmware
        .strip_prefix("grbl")
        .unwrap_or(&info.firmware)
        .trim();
    eprintln!(
        "connected to grbl {} at {}: {}",
        if firmware.is_empty() {
            "(version not reported)"
        } else {
            firmware
        },
        machine.endpoint,
        match machine.link_mode() {
            Some(Mode::CharCounting(n)) => format!("character counting, {n}-byte window"),
            _ => "send-response".into(),
        }
    );
    match &args.job {
        Some(path) => run_job(&mut machine, path, &args),
        None => {
            let mut link = machine.take_link().context("the link closed")?;
            interactive(&mut link.sender)
        }
    }
}

/// StatusReport line shared by the terminal and the job runner.
fn status_line(st: &StatusReport) -> String {
    let pos = st
        .mpos
        .as_ref()
        .map(|p| ("MPos", p))
        .or(st.wpos.as_ref().map(|p| ("WPos", p)));
    let mut s = format!("[{}]", st.state.name());
    if let Some((k, p)) = pos {
        s += &format!(
            " {k} {}",
            p.iter()
                .map(|v| format!("{v:.3}"))
                .collect::<Vec<_>>()
                .join(",")
        );
    }
    if let Some(f) = st.feed {
        s += &format!(" F{f:.0}");
    }
    if let Some(sp) = st.spindle {
        s += &format!(" S{sp:.0}");
    }
    if let Some((a, b, c)) = st.overrides {
        s += &format!(" ov {a}/{b}/{c}%");
    }
    if let Some(pins) = &st.pins {
        s += &format!(" pins {pins}");
    }
    s
}

fn stdin_lines() -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::stdin().lock().lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

fn explain(resp: &Response, raw: &str) -> String {
    match resp {
        Response::Error(c) => oficina_grbl::describe_error(*c),
        Response::Alarm(c) => oficina_grbl::describe_alarm(*c),
        Response::Setting { number, .. } => match oficina_grbl::setting_info(*number) {
            Some(i) => format!("{raw:<18} ({}, {})", i.name, i.unit),
            None => raw.to_string(),
        },
        _ => raw.to_string(),
    }
}

fn interactive(sender: &mut Sender) -> anyhow::Result<ExitCode> {
    eprintln!("type G-code or $ commands; ! hold, ~ resume, ? status, ^X or /reset soft reset,");
    eprintln!("/jog X+10 F500 (step), /jog X- F1000 (continuous until Enter), /ov f+10 (overrides), /quit to leave");
    eprintln!("/probe z --plate 19.5, /probe corner --tool 6, /probe setter (see /probe --help)");
    let input = stdin_lines();
    let mut last_query = Instant::now();
    let mut jogging: Option<ContinuousJog> = None;
    let mut jog_acks = 0;
    // Lines sent that grbl has not yet answered (`ok`/`error`): when the input ends (a
    // pipe), the console waits for them, at most `REPLY_WAIT` after the last reply.
    const REPLY_WAIT: Duration = Duration::from_secs(10);
    let mut unanswered = 0usize;
    let mut input_closed = false;
    let mut last_reply = Instant::now();
    loop {
        if input_closed {
            if unanswered == 0 {
                return Ok(ExitCode::SUCCESS);
            }
            if last_reply.elapsed() > REPLY_WAIT {
                eprintln!(
                    "\r\x1b[Kinput ended; {unanswered} line(s) still unanswered by the firmware after {} s",
                    REPLY_WAIT.as_secs()
                );
                return Ok(ExitCode::FAILURE);
            }
        }
        match if input_closed {
            Err(mpsc::TryRecvError::Empty)
        } else {
            input.try_recv()
        } {
            Ok(line) => {
                let t = line.trim();
                // Any line ends a continuous jog, as releasing the key would.
                if let Some(j) = jogging.take() {
                    j.stop(sender).context("write to the firmware failed")?;
                    if t.is_empty() {
                        continue;
                    }
                }
                let r = match t {
                    "/quit" | "/exit" => return Ok(ExitCode::SUCCESS),
                    "!" => sender.realtime(Realtime::FeedHold),
                    "~" => sender.realtime(Realtime::CycleStart),
                    "?" => sender.realtime(Realtime::StatusQuery),
                    "^X" | "/reset" => sender.realtime(Realtime::SoftReset),
                    "/door" => sender.realtime(Realtime::SafetyDoor),
                    "/jogcancel" => sender.realtime(Realtime::JogCancel),
                    "" => Ok(()),
                    _ if t.starts_with("/ov ") => {
                        match oficina_grbl::override_by_name(t[4..].trim()) {
                            Some(r) => sender.realtime(r),
                            None => {
                                eprintln!("\r\x1b[Koverrides: f+10 f-10 f+1 f-1 f100 r100 r50 r25 s+10 s-10 s+1 s-1 s100 sstop flood mist");
                                Ok(())
                            }
                        }
                    }
                    _ if t == "/probe" || t.starts_with("/probe ") => {
                        // The routine waits for each reply: first the replies to lines
                        // still in flight, or it would take their `ok`s for its own.
                        if settle(sender, &mut unanswered)? {
                            match crate::console_probe::run(sender, t) {
                                Ok(text) | Err(text) => say!("{}", text.trim_end()),
                            }
                        } else {
                            say!("probe not started: {unanswered} line(s) still unanswered");
                        }
                        last_reply = Instant::now();
                        Ok(())
                    }
                    _ if t.starts_with("/jog") => match oficina_grbl::parse_jog(&t[4..], 500.0) {
                        Ok(JogRequest::Step {
                            axis,
                            distance,
                            feed,
                        }) => match oficina_grbl::jog_step_line(axis, distance, feed) {
                            Ok(l) => {
                                unanswered += 1;
                                sender.link().send_line(&l)
                            }
                            Err(e) => {
                                eprintln!("\r\x1b[K{e}");
                                Ok(())
                            }
                        },
                        Ok(JogRequest::Continuous {
                            axis,
                            direction,
                            feed,
                        }) => {
                            match ContinuousJog::start(sender, axis, direction, feed) {
                                Ok(j) => {
                                    eprintln!(
                                        "jogging {axis}{} at F{feed}; press Enter to stop",
                                        if direction > 0.0 { "+" } else { "-" }
                                    );
                                    jogging = Some(j);
                                    jog_acks = 0;
                                }
                                Err(e) => eprintln!("{e}"),
                            }
                            Ok(())
                        }
                        Err(e) => {
                            eprintln!("\r\x1b[K{e}");
                            Ok(())
                        }
                    },
                    _ => {
                        unanswered += 1;
                        sender.link().send_line(t)
                    }
                };
                r.context("write to the firmware failed")?;
            }
            Err(mpsc::TryRecvError::Disconnected) => {
                if let Some(j) = jogging.take() {
                    j.stop(sender).context("write to the firmware failed")?;
                }
                input_closed = true;
                last_reply = Instant::now();
            }
            Err(mpsc::TryRecvError::Empty) => {}
        }
        if let Some(j) = jogging.as_mut() {
            j.keep_up(sender, jog_acks)
                .context("write to the firmware failed")?;
            jog_acks = 0;
        }
        if last_query.elapsed() > Duration::from_millis(500) {
            sender
                .realtime(Realtime::StatusQuery)
                .context("write to the firmware failed")?;
            last_query = Instant::now();
        }
        match sender.link().recv(Duration::from_millis(20)) {
            Some(LinkEvent::Line(Response::Status(st), _)) => {
                eprint!("\r\x1b[K{}", status_line(&st));
            }
            // The increments of a continuous jog are acknowledged silently.
            Some(LinkEvent::Line(Response::Ok, _)) if jogging.is_some() => jog_acks += 1,
            Some(LinkEvent::Line(resp, raw)) => {
                if resp.is_ack() {
                    unanswered = unanswered.saturating_sub(1);
                    last_reply = Instant::now();
                }
                if matches!(resp, Response::Error(_)) {
                    if let Some(j) = jogging.take() {
                        j.stop(sender).context("write to the firmware failed")?;
                    }
                }
                eprint!("\r\x1b[K");
                say!("{}", explain(&resp, &raw));
            }
            Some(LinkEvent::Closed(why)) => bail!("connection closed: {why}"),
            None => {}
        }
    }
}

/// Prints the replies to the lines in flight until all are answered (at most 10 s); says
/// whether they all were.
fn settle(sender: &mut Sender, unanswered: &mut usize) -> anyhow::Result<bool> {
    let deadline = Instant::now() + Duration::from_secs(10);
    while *unanswered > 0 && Instant::now() < deadline {
        match sender.link().recv(Duration::from_millis(20)) {
            Some(LinkEvent::Line(Response::Status(_), _)) | None => {}
            Some(LinkEvent::Line(resp, raw)) => {
                if resp.is_ack() {
                    *unanswered -= 1;
                }
                eprint!("\r\x1b[K");
                say!("{}", explain(&resp, &raw));
            }
            Some(LinkEvent::Closed(why)) => bail!("connection closed: {why}"),
        }
    }
    Ok(*unanswered == 0)
}

/// The job's status line from the trait's [`Status`]: state, machine position, feed and
/// feed override.
fn job_status_line(st: &Status) -> String {
    let state = match &st.state {
        State::Alarm(_) => "Alarm".to_string(),
        s => format!("{s:?}"),
    };
    let [x, y, z] = st.machine_pos;
    format!(
        "[{state}] MPos {x:.3},{y:.3},{z:.3} F{:.0} ov {:.0}%",
        st.feed,
        st.feed_override * 100.0
    )
}

/// A job key (then Enter) in the trait's terms, or a grbl real-time key it cannot say.
enum Key {
    Command(Command),
    Realtime(Realtime),
}

fn job_key(k: &str) -> Option<Key> {
    Some(match k {
        "h" | "!" | "" => Key::Command(Command::Hold),
        "r" | "~" => Key::Command(Command::Resume),
        "s" | "q" => Key::Command(Command::Stop),
        "f100" => Key::Command(Command::FeedOverride(1.0)),
        "s100" => Key::Command(Command::SpindleOverride(1.0)),
        other => Key::Realtime(oficina_grbl::override_by_name(other)?),
    })
}

fn run_job(machine: &mut GrblDevice, path: &Path, args: &Args) -> anyhow::Result<ExitCode> {
    machine.settings = RunSettings {
        start: match (args.from_line, args.resume) {
            (Some(n), _) => Start::FileLine(n),
            (None, true) => Start::Journal,
            (None, false) => Start::Beginning,
        },
        journal: args.journal.clone(),
        resume: ResumeOptions {
            safe_z: args.safe_z,
            plunge_feed: args.plunge_feed,
            spindle_delay: args.spindle_delay,
        },
        unlock_alarm: args.unlock,
        reconnect: (args.reconnect > 0.0).then(|| RetryPolicy {
            deadline: Duration::from_secs_f64(args.reconnect),
            ..RetryPolicy::default()
        }),
        auto_resume: args.auto_resume,
        check_first: args.check,
        tool_change: args.tool_change.settings()?,
    };
    let journal_path = GrblMachine::journal_path(path, &machine.settings);
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let name = path.display().to_string();
    // The device's own reading of the file: line counts for the progress display.
    let lines = StreamProgram::with_tool_change(&name, &text, &machine.settings.tool_change)
        .map_err(anyhow::Error::msg)?;
    eprintln!("keys (then Enter): h hold, r resume, s stop; overrides f+10 f-10 f100 r50 s+10 …");
    let keys = stdin_lines();
    machine
        .start(oficina_machine::Job {
            name,
            text: Arc::new(text),
            start_line: None,       // machine.settings.start says where
            pace: Pace::Speed(1.0), // (firmware runs at its own pace)
        })
        .map_err(anyhow::Error::msg)?;
    // Alarms that are not the job's summary: the reason a job could not run.
    let mut alarms = Vec::new();
    let is_summary =
        |m: &mut GrblDevice, text: &str| m.job_report().is_some_and(|r| r.summary == text);
    loop {
        while let Ok(k) = keys.try_recv() {
            let sent = match job_key(k.trim()) {
                Some(Key::Command(c)) => machine.command(c),
                Some(Key::Realtime(r)) => machine.realtime(r),
                None => Ok(()),
            };
            if let Err(e) = sent {
                eprintln!("\r\x1b[K{e}");
            }
        }
        match machine.next_event(Duration::from_millis(50)) {
            Some(Event::Status(st)) => {
                let last = job_status_line(&st);
                // Lines acknowledged: those up to the source line the machine reports.
                let acked = lines
                    .lines
                    .partition_point(|l| l.file_line <= st.line as usize);
                if acked == 0 {
                    eprint!("\r\x1b[K{last}");
                } else {
                    let left = (st.total - st.elapsed).max(0.0);
                    eprint!(
                        "\r\x1b[K{last} line {acked}/{} ({:.1}%) ETA {}:{:02}",
                        lines.len(),
                        100.0 * acked as f64 / lines.len().max(1) as f64,
                        left as u64 / 60,
                        left as u64 % 60
                    );
                }
            }
            // The summary waits for the end (on stdout).
            Some(Event::Message(m)) if is_summary(machine, &m) => {}
            Some(Event::Alarm(a)) if is_summary(machine, &a) => {}
            Some(Event::Message(m)) => eprintln!("\r\x1b[K{m}"),
            Some(Event::Alarm(a)) => alarms.push(a),
            Some(Event::ToolChange { prompt, .. }) => {
                eprintln!("\r\x1b[KTOOL CHANGE: {prompt}  (r + Enter: resume, s + Enter: stop)")
            }
            Some(Event::JobEnd { .. }) => break,
            None => {}
        }
    }
    eprintln!();
    let Some(report) = machine.job_report() else {
        // The job could not run: its alarm says why.
        bail!("{}", alarms.join("\n"));
    };
    for a in alarms {
        eprintln!("ALARM: {a}");
    }
    say!("{}", report.summary);
    if let Some(r) = &report.resume {
        if r.within_line {
            // Only the journal path finishes the interrupted line from the stop point;
            // --from-line restarts it from its beginning.
            say!(
                "to continue from where the machine stopped: oficina console {} --job {} --resume   (--from-line {} would re-cut line {} from its start)",
                endpoint_flags(args),
                path.display(),
                r.file_line,
                r.file_line
            );
        } else {
            say!(
                "to continue: oficina console {} --job {} --from-line {}   (or --resume to use the journal {})",
                endpoint_flags(args),
                path.display(),
                r.file_line,
                journal_path.display()
            );
        }
    } else if report.link_lost {
        say!(
            "after reconnecting: oficina console {} --job {} --resume",
            endpoint_flags(args),
            path.display()
        );
    }
    Ok(if report.completed {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn endpoint_flags(args: &Args) -> String {
    match (&args.port, &args.tcp) {
        (Some(p), _) => format!("--port {p} --baud {}", args.baud),
        (_, Some(t)) => format!("--tcp {t}"),
        _ => "--emulator".into(),
    }
}
