//! `oficina console`: a terminal to grbl-family firmware (serial, TCP or the built-in
//! emulator) with a live status line, and the job runner: stream a file with progress and
//! ETA, hold / resume / stop from the keyboard, and resume from a line or from the journal
//! after a stop, an error, a crash or a pulled cable.

use anyhow::{bail, Context};
use oficina_grbl::Endpoint;
use oficina_grbl::Job;
use oficina_grbl::LinkEvent;
use oficina_grbl::Realtime;
use oficina_grbl::Response;
use oficina_grbl::ResumeOptions;
use oficina_grbl::RetryPolicy;
use oficina_grbl::StatusReport;
use oficina_grbl::{ContinuousJog, JogRequest};
use oficina_grbl::{Control, Mode, Notice, Sender, SenderOptions, StreamEnd};
use oficina_grbl::{GrblMachine, RunOutcome, RunSettings, Start};
use oficina_grbl_emu::{Config, Emulator};
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// `println!` that does not panic when whoever reads our output went away.
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

#[derive(clap::Args, Debug)]
pub struct Args {
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
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
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
    let mut machine = GrblMachine::connect_to(endpoint, options).map_err(anyhow::Error::msg)?;
    eprintln!(
        "connected to grbl {} at {}: {}",
        if machine.sender.firmware.is_empty() {
            "(version not reported)"
        } else {
            &machine.sender.firmware
        },
        machine.endpoint,
        match machine.sender.mode {
            Mode::CharCounting(n) => format!("character counting, {n}-byte window"),
            Mode::SendResponse => "send-response".into(),
        }
    );
    match &args.job {
        Some(path) => run_job(&mut machine, path, &args),
        None => interactive(&mut machine.sender),
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

fn run_job(machine: &mut GrblMachine, path: &Path, args: &Args) -> anyhow::Result<ExitCode> {
    let settings = RunSettings {
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
    };
    let journal_path = GrblMachine::journal_path(path, &settings);
    eprintln!("keys (then Enter): h hold, r resume, s stop; overrides f+10 f-10 f100 r50 s+10 …");
    let keys = stdin_lines();
    let (ctl_tx, ctl_rx) = mpsc::channel();
    std::thread::spawn(move || {
        for k in keys.iter() {
            let c = match k.trim() {
                "h" | "!" | "" => Control::Hold,
                "r" | "~" => Control::Resume,
                "s" | "q" => Control::Stop,
                other => match oficina_grbl::override_by_name(other) {
                    Some(r) => Control::Realtime(r),
                    None => continue,
                },
            };
            if ctl_tx.send(c).is_err() {
                break;
            }
        }
    });
    let start = Instant::now();
    let mut last = String::new();
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let job = Job::from_text(&path.display().to_string(), &text).map_err(anyhow::Error::msg)?;
    // Machine time per line from grbl's timing model and the board's own $110… rates.
    let cumulative = oficina_grbl::cumulative_seconds(&job, &machine.sender.settings);
    let mut progress: Option<(usize, usize, usize)> = None;
    let mut observer = |n: Notice| {
        match n {
            Notice::Progress { acked, total, .. } => {
                let started = progress.map(|p| p.2).unwrap_or(acked.saturating_sub(1));
                progress = Some((acked, total, started));
            }
            Notice::Status(st) => last = status_line(&st),
            Notice::Message(m) => eprintln!("\r\x1b[K{m}"),
            Notice::Unexpected(u) => eprintln!("\r\x1b[Kignored unexpected firmware line: {u:?}"),
        }
        let Some((acked, total, started)) = progress else {
            eprint!("\r\x1b[K{last}");
            return;
        };
        let left =
            oficina_grbl::eta_remaining(&cumulative, started, acked, start.elapsed().as_secs_f64());
        eprint!(
            "\r\x1b[K{last} line {acked}/{total} ({:.1}%) ETA {}:{:02}",
            100.0 * acked as f64 / total.max(1) as f64,
            left as u64 / 60,
            left as u64 % 60
        );
    };
    let outcome = machine
        .run(&job, &journal_path, &settings, Some(&ctl_rx), &mut observer)
        .map_err(anyhow::Error::msg)?;
    eprintln!();
    let report = match outcome {
        RunOutcome::AlreadyDone => {
            say!(
                "{}: nothing left to run: the job already completed",
                path.display()
            );
            return Ok(ExitCode::SUCCESS);
        }
        RunOutcome::Streamed(r) => r,
    };
    say!("{}", report.describe(&job));
    if let Some(r) = &report.resume {
        if r.index < job.len() && r.entry.is_some() {
            // Only the journal path finishes the interrupted line from the stop point;
            // --from-line restarts it from its beginning.
            say!(
                "to continue from where the machine stopped: oficina console {} --job {} --resume   (--from-line {} would re-cut line {} from its start)",
                endpoint_flags(args),
                path.display(),
                job.lines[r.index].file_line,
                job.lines[r.index].file_line
            );
        } else if r.index < job.len() {
            say!(
                "to continue: oficina console {} --job {} --from-line {}   (or --resume to use the journal {})",
                endpoint_flags(args),
                path.display(),
                job.lines[r.index].file_line,
                journal_path.display()
            );
        }
    } else if let StreamEnd::Disconnected(_) = report.end {
        say!(
            "after reconnecting: oficina console {} --job {} --resume",
            endpoint_flags(args),
            path.display()
        );
    }
    Ok(if report.end == StreamEnd::Completed {
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
