//! `oficina run FILE`: execute a program on the virtual machine with a progress bar, and
//! keyboard hold / resume / stop when stdin is a terminal.

use crate::gcode_input::{load_tool_table, machine_for, HeldProgram};
use crate::tool_change::ToolChangeArgs;
use anyhow::{bail, Context};
use crossterm::event::{self, Event as Key, KeyCode, KeyModifiers};
use crossterm::terminal;
use indicatif::{ProgressBar, ProgressStyle};
use oficina_canon::Units;
use oficina_machine::{Command, Event, Job, Pace, State, Status};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;

#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    program: HeldProgram,
    /// The machine: a profile of the built-in virtual machine (a TOML file or a bundled name:
    /// grbl-router, hotwire-xy, polar-plotter, polargraph-wall, embroidery-xy; `virtual` is
    /// grbl-router), or real grbl-family firmware: `grbl:/dev/ttyUSB0[@baud]`,
    /// `tcp://HOST:PORT` (grblHAL, FluidNC), or Marlin (a Makelangelo):
    /// `marlin:/dev/ttyUSB0[@baud]` (250000 unless given), `marlin+tcp://HOST:PORT`.
    /// Default: the program's `(machine: NAME)` opening comment, else grbl-router.
    #[arg(long)]
    machine: Option<String>,
    /// Run faster than real time, e.g. `10x` or `2.5`.
    #[arg(long, default_value = "1x")]
    speed: String,
    /// No waiting at all: as fast as the computer goes.
    #[arg(long)]
    instant: bool,
    /// Resume from this source line (earlier motion, pauses and messages are skipped; the
    /// modes and the tool they set are kept; rapids take the tool there).
    #[arg(long)]
    from_line: Option<u32>,
    /// On firmware (grbl, Marlin): continue where the job's journal (FILE.journal) says
    /// the last run stopped.
    #[arg(long, conflicts_with = "from_line")]
    resume: bool,
    /// Without a terminal to press resume on, a program pause (M0/M1) is passed by itself;
    /// this stops the run there instead.
    #[arg(long)]
    stop_at_pauses: bool,
    /// A LinuxCNC tool table (.tbl) for G43 and M6, lengths in mm (virtual machine only).
    #[arg(long)]
    tool_table: Option<PathBuf>,
    #[command(flatten)]
    level: crate::level::RunFlags,
    #[command(flatten)]
    tool_change: ToolChangeArgs,
}

/// Leaves raw mode however the run ends.
struct RawMode(bool);
impl Drop for RawMode {
    fn drop(&mut self) {
        if self.0 {
            let _ = terminal::disable_raw_mode();
        }
    }
}

fn parse_speed(s: &str) -> anyhow::Result<f64> {
    let v: f64 = s
        .trim_end_matches(['x', 'X'])
        .parse()
        .with_context(|| format!("--speed {s:?}: expected a factor such as 10x"))?;
    if !(v.is_finite() && v > 0.0 && v <= 1e6) {
        bail!("--speed {s:?}: the factor must be > 0 and at most 1e6");
    }
    Ok(v)
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    let machine = machine_for(args.machine.as_deref(), &args.program.file);
    let tools = match &args.tool_table {
        Some(path) => Some(load_tool_table(path, Units::Mm)?),
        None => None,
    };
    let text = args.program.read()?;
    if let Some(line) = args.from_line {
        oficina_machine::job::check_start_line(&text, line).map_err(anyhow::Error::msg)?;
    }
    let pace = if args.instant {
        Pace::Instant
    } else {
        Pace::Speed(parse_speed(&args.speed)?)
    };
    let factor = if let Pace::Speed(f) = pace {
        f
    } else {
        f64::INFINITY
    };
    let name = args.program.file.display().to_string();
    let (mut vm, info) = match args.level.source() {
        // Levelled: probed or loaded map, then the levelled lines stream to the firmware.
        Some(source) => {
            if tools.is_some() {
                bail!("--tool-table is for the virtual machine; levelling runs on grbl firmware");
            }
            let run = oficina_app::run_levelled(
                &machine,
                &name,
                &text,
                args.from_line,
                &source,
                &args.level.tuning(),
                args.tool_change.settings()?,
                &mut |m| eprintln!("{m}"),
            )
            .map_err(anyhow::Error::msg)?;
            crate::level::print_map(&run.map);
            crate::level::print_report(&run.report);
            (run.machine, run.info)
        }
        None => {
            // Firmware takes the tool-change policy (grbl has no M6); the virtual machine
            // its tool table.
            let mut vm = if oficina_app::is_firmware(&machine)
                && tools.is_none()
                && args.program.work_offset.is_none()
            {
                oficina_app::open_firmware(&machine, args.tool_change.settings()?)?
            } else {
                oficina_app::open_machine_with_tools(
                    &machine,
                    args.program.work_offset,
                    args.program.line_limit.bytes(),
                    tools,
                )?
            };
            if args.resume {
                resume_from_journal(vm.as_mut())?;
            }
            let info = vm.connect().map_err(|e| anyhow::anyhow!("{e}"))?;
            vm.start(Job {
                name: name.clone(),
                text: Arc::new(text),
                start_line: args.from_line,
                pace,
            })
            .map_err(|e| anyhow::anyhow!("{e}"))?;
            (vm, info)
        }
    };
    let interactive = std::io::stdin().is_terminal() && !args.instant;
    let _raw = RawMode(interactive && terminal::enable_raw_mode().is_ok());
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {percent:>3}% {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    eprintln!(
        "{} on {}{}",
        name,
        info.name,
        if interactive {
            "  [space/! hold · ~/r resume · q stop]\r"
        } else {
            ""
        }
    );
    let mut result = ExitCode::SUCCESS;
    let mut passed_pause = false;
    // A tool change waits for the operator's resume; with no terminal it stops the job.
    // It is over once the machine, paused for it, runs again.
    let (mut tool_wait, mut tool_paused) = (false, false);
    loop {
        if _raw.0 {
            while event::poll(Duration::ZERO).unwrap_or(false) {
                if let Ok(Key::Key(k)) = event::read() {
                    let cmd = match k.code {
                        KeyCode::Char(' ') | KeyCode::Char('!') => Some(Command::Hold),
                        KeyCode::Char('~') | KeyCode::Char('r') => Some(Command::Resume),
                        KeyCode::Char('c') if k.modifiers.contains(KeyModifiers::CONTROL) => {
                            Some(Command::Stop)
                        }
                        KeyCode::Char('q') | KeyCode::Esc => Some(Command::Stop),
                        _ => None,
                    };
                    if let Some(c) = cmd {
                        let _ = vm.command(c);
                    }
                }
            }
        }
        // A pause waits for the operator; with no terminal there is none, so pass it (or stop).
        // The state is read before the events are drained: a tool change queues its event
        // before it pauses, so a pause seen here has its reason queued by then, and is taken
        // for an M0 only once the queue is empty.
        let paused = vm.status().state == State::Paused;
        tool_paused |= tool_wait && paused;
        if tool_paused && !paused {
            (tool_wait, tool_paused) = (false, false);
        }
        let event = vm.next_event(Duration::from_millis(50));
        let drained = event.is_none();
        if drained {
            let m0 = paused && !tool_wait;
            if m0 && !interactive && !passed_pause {
                if args.stop_at_pauses {
                    let _ = vm.command(Command::Stop);
                } else {
                    bar.suspend(|| {
                        eprintln!(
                            "(no terminal to resume from: going on; --stop-at-pauses stops here)"
                        )
                    });
                    let _ = vm.command(Command::Resume);
                }
            }
            passed_pause = m0;
        }
        match event {
            Some(Event::Status(s)) => show_status(&bar, &s, factor),
            // The bar draws at most ~20 times a second, so the last updates before a hold
            // (decelerating takes milliseconds) can be dropped; with no events while held the
            // line would stay on a stale Run. Redraw the latest snapshot when idle.
            None => show_status(&bar, &vm.status(), factor),
            // Through stderr: a hidden bar (no terminal) would swallow println.
            Some(Event::Message(m)) => bar.suspend(|| eprintln!("{m}")),
            Some(Event::ToolChange { prompt, .. }) => {
                tool_wait = true;
                if interactive {
                    bar.suspend(|| eprintln!("TOOL CHANGE: {prompt}  [~/r resume · q stop]\r"));
                } else {
                    bar.suspend(|| {
                        eprintln!("TOOL CHANGE: {prompt}\n(no terminal to answer it: stopping here; change the tool, then continue with --resume as below, or run with --tool-change ignore if one tool does it all)")
                    });
                    let _ = vm.command(Command::Stop);
                }
            }
            Some(Event::Alarm(a)) => {
                bar.suspend(|| eprintln!("ALARM: {a}"));
                result = ExitCode::FAILURE;
            }
            Some(Event::JobEnd { completed, seconds }) => {
                bar.finish_and_clear();
                drop(_raw);
                // A board's job time is the stream's wall time (an emulator may run its
                // clock faster); the virtual machine's is its own clock.
                let of = if oficina_app::is_firmware(&machine) {
                    "streaming"
                } else {
                    "machine time"
                };
                if completed {
                    println!("done: {} of {of}", clock(seconds));
                } else if result == ExitCode::SUCCESS {
                    println!("stopped after {} of {of}", clock(seconds));
                    result = ExitCode::from(2);
                }
                if !completed && oficina_app::is_firmware(&machine) {
                    println!("to continue: oficina run {name} --machine {machine} --resume");
                }
                return Ok(result);
            }
        }
    }
}

/// Makes firmware start the next job where its journal says the last run stopped.
fn resume_from_journal(vm: &mut dyn oficina_machine::Machine) -> anyhow::Result<()> {
    let refused = "--resume reads a firmware job's journal (grbl, Marlin); the virtual machine keeps none: use --from-line";
    let any = vm.as_any_mut().context(refused)?;
    if let Some(m) = any.downcast_mut::<oficina_grbl::MarlinDevice>() {
        m.resume = true;
    } else if let Some(g) = any.downcast_mut::<oficina_grbl::GrblDevice>() {
        g.settings.start = oficina_grbl::Start::Journal;
    } else {
        bail!(refused);
    }
    Ok(())
}

/// The progress and the status line: line, ETA, work position, feed and any non-Run state.
fn show_status(bar: &ProgressBar, s: &Status, factor: f64) {
    let frac = if s.total > 0.0 {
        (s.elapsed / s.total).clamp(0.0, 1.0)
    } else {
        0.0
    };
    bar.set_position((frac * 1000.0) as u64);
    // ETA in wall time: machine time left at the chosen pace; frozen while held.
    let left = (s.total - s.elapsed).max(0.0) / factor;
    let state = match &s.state {
        State::Run => String::new(),
        other => format!(" [{other:?}]"),
    };
    bar.set_message(format!(
        "line {:>6}  ETA {}  X{:.3} Y{:.3} Z{:.3}  F{:.0}{state}",
        s.line,
        clock(left),
        s.work_pos[0],
        s.work_pos[1],
        s.work_pos[2],
        s.feed
    ));
}

/// `h:mm:ss`, or `--:--` for a time that never comes (nothing left to divide by).
fn clock(s: f64) -> String {
    if s.is_finite() {
        oficina_motion::format_hms(s, 0)
    } else {
        "--:--".into()
    }
}
