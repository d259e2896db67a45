//! The Marlin link against the Marlin emulator: a real drawing plotted `--format marlin`
//! streams to the end through a corrupted and a lost line, every line runs once and in
//! order, and the pen draws the program's path; checksums agree with Python's; keep-alives
//! outlast the reply timeout; `M0` waits for `M108`; a stopped job resumes from its journal.

mod common;

use common::{emulate_firmware, oficina, pen_down_path, run_program_on, text};
use oficina_grbl::{
    marlin_frame, marlin_program, Endpoint, MarlinControl, MarlinEnd, MarlinLink, MarlinNotice,
    MarlinOptions,
};
use oficina_grbl_emu::{MarlinConfig, MarlinEmulator, Move};
use oficina_machine::{Command, Event, Job, Machine, Pace};
use std::path::{Path, PathBuf};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// The pen servo's "up" angle in `oficina plot --format marlin` (the first M280).
const UP: f64 = 90.0;

/// `oficina plot SVG --machine polargraph-wall --format marlin` into `dir`.
fn plot_marlin(svg: &Path, dir: &Path) -> PathBuf {
    let out = dir.join("plot.gcode");
    let o = oficina(&[
        "plot",
        svg.to_str().unwrap(),
        "--machine",
        "polargraph-wall",
        "--layout",
        "a3",
        "--format",
        "marlin",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    out
}

/// A real drawing plotted for Marlin: its scratch folder (kept while it lives), file and
/// text; `None` (skipped, with a note) where the real-world files are absent.
fn real_plot(svg: &str) -> Option<(tempfile::TempDir, PathBuf, String)> {
    let dir = oficina_testkit::realworld("plot-svg")?;
    let scratch = tempfile::tempdir().unwrap();
    let file = plot_marlin(&dir.join(svg), scratch.path());
    let text = std::fs::read_to_string(&file).unwrap();
    Some((scratch, file, text))
}

fn fast() -> MarlinOptions {
    MarlinOptions {
        reply_timeout: Duration::from_millis(400),
        banner_wait: Duration::from_millis(500),
        max_timeouts: 5,
    }
}

fn connect(pty: &str, options: MarlinOptions) -> MarlinLink {
    MarlinLink::connect(
        &Endpoint::Serial {
            path: pty.into(),
            baud: 250_000,
        },
        options,
    )
    .unwrap()
}

/// The program's pen-down segments, read from its text (the servo's M280 angle, G0/G1 X Y).
fn program_segments(program: &str) -> Vec<[[f64; 2]; 2]> {
    let strokes = pen_down_path(program, |l| {
        l.strip_prefix("M280 P0 S")
            .map(|a| a.trim().parse::<f64>().unwrap() != UP)
    });
    strokes
        .iter()
        .flat_map(|s| s.windows(2).map(|w| [w[0], w[1]]))
        .collect()
}

/// The emulator's pen-down moves.
fn drawn_segments(moves: &[Move]) -> Vec<[[f64; 2]; 2]> {
    moves
        .iter()
        .filter(|m| m.servo.is_some_and(|s| s != UP))
        .map(|m| [[m.from[0], m.from[1]], [m.to[0], m.to[1]]])
        .collect()
}

fn assert_same_path(a: &[[[f64; 2]; 2]], b: &[[[f64; 2]; 2]]) {
    assert_eq!(a.len(), b.len(), "pen-down segments");
    for (s, t) in a.iter().zip(b) {
        for k in 0..2 {
            let d = (s[k][0] - t[k][0]).hypot(s[k][1] - t[k][1]);
            assert!(d < 1e-9, "{s:?} vs {t:?}");
        }
    }
}

#[test]
fn a_real_plot_streams_through_a_corrupted_and_a_lost_line() {
    let Some((_scratch, _, text)) = real_plot("axidraw_AxiDraw_First.svg") else {
        return;
    };
    let job = marlin_program("plot.gcode", &text).unwrap();
    assert!(job.len() > 1000, "{} lines", job.len());

    let emu = MarlinEmulator::start(MarlinConfig {
        corrupt_line: Some(40),
        drop_every: Some(500),
        ..Default::default()
    });
    let pty = emu.serve_pty().unwrap();
    let mut link = connect(&pty, fast());
    assert!(link.firmware.contains("Marlin"), "{}", link.firmware);
    let mut resent = Vec::new();
    let t = Instant::now();
    let report = link.stream(&job, 0, None, None, &mut |n| {
        if let MarlinNotice::Resent { n, why } = n {
            resent.push((n, why));
        }
    });
    let seconds = t.elapsed().as_secs_f64();
    assert_eq!(report.end, MarlinEnd::Completed, "{report:?}");
    assert_eq!(report.acked, job.len());
    let st = emu.stats();
    assert_eq!(st.corrupted, 1);
    assert_eq!(st.checksum_errors, 1, "{st:?}");
    assert!(st.dropped >= 2, "{st:?}");
    // Each refused line went again at Marlin's request, each lost one after the timeout.
    assert_eq!(report.resends, 1, "{resent:?}");
    assert_eq!(report.timeouts as u64, st.dropped, "{resent:?}");
    assert!(resent.iter().any(|(n, _)| *n == 40), "{resent:?}");

    // Every program line executed exactly once, in order, under consecutive numbers.
    let executed = emu.executed();
    let numbered: Vec<_> = executed.iter().filter(|e| e.n.is_some()).collect();
    assert_eq!(numbered.len(), job.len());
    for (k, (e, l)) in numbered.iter().zip(&job.lines).enumerate() {
        assert_eq!(e.n, Some(k as u32 + 1));
        assert_eq!(e.command, l.text);
    }
    // The pen drew the program's path.
    let program = program_segments(&text);
    assert!(program.len() > 500, "{} segments", program.len());
    assert_same_path(&program, &drawn_segments(&emu.moves()));
    eprintln!(
        "{} lines in {seconds:.2} s over a pty with {} timeouts of 0.4 s: {:.0} lines/s; {} written for {} lines",
        job.len(),
        report.timeouts,
        job.len() as f64 / (seconds - report.timeouts as f64 * 0.4).max(1e-3),
        report.lines_written,
        job.len()
    );
}

#[test]
fn checksums_agree_with_python() {
    let commands = [
        "G28",
        "M280 P0 S90",
        "G1 X345.539 Y-642.117 F3000",
        "M0 Pen 2: #0000ff",
    ];
    let mut script = String::from("from functools import reduce\n");
    for (k, c) in commands.iter().enumerate() {
        let body = format!("N{} {c}", k + 1);
        script.push_str(&format!(
            "print('{body}*%d' % reduce(lambda a, b: a ^ b, b'{body}', 0))\n"
        ));
    }
    let out = std::process::Command::new("python3")
        .args(["-c", &script])
        .output()
        .expect("python3 runs");
    assert!(out.status.success());
    let python: Vec<String> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(String::from)
        .collect();
    let ours: Vec<String> = commands
        .iter()
        .enumerate()
        .map(|(k, c)| marlin_frame(k as u32 + 1, c))
        .collect();
    assert_eq!(ours, python);
}

#[test]
fn keep_alives_longer_than_the_timeout_do_not_abort() {
    let emu = MarlinEmulator::start(MarlinConfig {
        busy_ms: 2000,
        keepalive_ms: 50,
        ..Default::default()
    });
    let pty = emu.serve_pty().unwrap();
    // Each busy wait is 2.5 reply timeouts; keep-alives come 16 times a timeout.
    let mut link = connect(
        &pty,
        MarlinOptions {
            reply_timeout: Duration::from_millis(800),
            ..fast()
        },
    );
    let job = marlin_program("busy", "G28\nG1 X10 Y5 F3000\nM400\nG1 X0\n").unwrap();
    let report = link.stream(&job, 0, None, None, &mut |_| {});
    assert_eq!(report.end, MarlinEnd::Completed, "{report:?}");
    assert_eq!(report.timeouts, 0, "a busy line was taken for a lost one");
    let ran: Vec<_> = emu
        .executed()
        .into_iter()
        .filter(|e| e.n.is_some())
        .collect();
    assert_eq!(ran.len(), 4, "{ran:?}");
    assert_eq!(emu.stats().line_number_errors, 0);
}

#[test]
fn m0_waits_until_resume_sends_m108() {
    let emu = Arc::new(MarlinEmulator::start(MarlinConfig {
        keepalive_ms: 50,
        ..Default::default()
    }));
    let pty = emu.serve_pty().unwrap();
    let mut link = connect(&pty, fast());
    let job = marlin_program("pause", "G1 X5 F3000\nM0 Pen 2: red\nG1 X9\n").unwrap();
    let (ctl_tx, ctl_rx) = mpsc::channel();
    let (pause_tx, pause_rx) = mpsc::channel();
    let streamer = std::thread::spawn(move || {
        link.stream(&job, 0, None, Some(&ctl_rx), &mut |n| {
            if let MarlinNotice::Pause { file_line, text } = n {
                let _ = pause_tx.send((file_line, text));
            }
        })
    });
    let (line, text) = pause_rx.recv_timeout(Duration::from_secs(5)).unwrap();
    assert_eq!((line, text.as_str()), (2, "M0 Pen 2: red"));
    // Waiting: ten reply timeouts pass and nothing after the M0 runs.
    std::thread::sleep(Duration::from_millis(1000));
    let last = emu.executed().last().unwrap().command.clone();
    assert_eq!(last, "M0 Pen 2: red");
    ctl_tx.send(MarlinControl::Resume).unwrap();
    let report = streamer.join().unwrap();
    assert_eq!(report.end, MarlinEnd::Completed, "{report:?}");
    assert_eq!(report.timeouts, 0);
    let commands: Vec<String> = emu.executed().into_iter().map(|e| e.command).collect();
    let m0 = commands.iter().position(|c| c.starts_with("M0")).unwrap();
    assert_eq!(commands[m0 + 1..m0 + 3], ["M108", "G1 X9"], "{commands:?}");
    assert_eq!(emu.moves().last().unwrap().to[0], 9.0);
}

/// Waits for the job's end, stopping it once `stop_after` lines were acknowledged.
fn run_to_end(m: &mut dyn Machine, stop_at_line: Option<u32>) -> bool {
    let deadline = Instant::now() + Duration::from_secs(60);
    let mut stopped = false;
    while Instant::now() < deadline {
        match m.next_event(Duration::from_millis(50)) {
            Some(Event::Status(s)) if !stopped && stop_at_line.is_some_and(|l| s.line >= l) => {
                m.command(Command::Stop).unwrap();
                stopped = true;
            }
            Some(Event::JobEnd { completed, .. }) => return completed,
            _ => {}
        }
    }
    panic!("the job did not end");
}

#[test]
fn a_stopped_plot_resumes_from_its_journal_and_draws_each_segment_once() {
    let Some((_scratch, file, text)) = real_plot("axidraw_AxiDraw_First.svg") else {
        return;
    };
    let emu = MarlinEmulator::start(MarlinConfig::default());
    let pty = emu.serve_pty().unwrap();
    let mut device = oficina_grbl::MarlinDevice::new(&format!("marlin:{pty}")).unwrap();
    device.options = fast();
    device.connect().unwrap();
    let job = || Job {
        name: file.display().to_string(),
        text: Arc::new(text.clone()),
        start_line: None,
        pace: Pace::Instant,
    };
    device.start(job()).unwrap();
    assert!(
        !run_to_end(&mut device, Some(600)),
        "the stop was not honoured"
    );
    let first = emu.moves().len();
    let report = device.job_report().unwrap();
    assert!(!report.completed && report.resume.is_some(), "{report:?}");
    device.resume = true;
    device.start(job()).unwrap();
    assert!(run_to_end(&mut device, None));
    // The first run drew a prefix of the program's path; the resumed run the rest, from a
    // point on a segment no more than Marlin's planner depth (16 moves and the line in
    // flight) before where the first stopped: the position alone cannot tell the hatch
    // lines that pass the same point apart, so a few may be drawn twice, none skipped.
    let program = program_segments(&text);
    let moves = emu.moves();
    let before = drawn_segments(&moves[..first]);
    let after = drawn_segments(&moves[first..]);
    assert!(
        before.len() > 100,
        "{} segments before the stop",
        before.len()
    );
    assert_same_path(&program[..before.len()], &before);
    let j = program.len() - after.len();
    assert!(
        j <= before.len() && before.len() - j <= 17,
        "resumed at segment {j} after {} were drawn",
        before.len()
    );
    assert_same_path(&program[j + 1..], &after[1..]);
    let [a, b] = program[j];
    let [p, q] = after[0];
    assert!((q[0] - b[0]).hypot(q[1] - b[1]) < 1e-9, "{q:?} vs {b:?}");
    // p lies on a–b, to M114's two decimals.
    let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let off = (ab[0] * ap[1] - ab[1] * ap[0]).abs() / ab[0].hypot(ab[1]).max(1e-12);
    assert!(
        off < 0.0075,
        "the restart point {p:?} is {off} mm off its segment"
    );
}

#[test]
fn oficina_run_draws_on_oficina_emulate_marlin_past_a_pen_change() {
    let Some((_scratch, _, program)) = real_plot("vpype_two_layers_a4.svg") else {
        return;
    };
    assert!(program.contains("\nM0 Pen 2"), "two pens, a pause between");
    let emu = emulate_firmware("marlin", &["--corrupt-line", "30", "--keepalive-ms", "100"]);
    let machine = format!("marlin+{}", emu.uri);
    let out = run_program_on(&machine, "two.gcode", &program);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("Error:checksum mismatch, Last Line: 29"),
        "{stderr}"
    );
    assert!(
        stderr.contains("Marlin waits for you at file line"),
        "{stderr}"
    );
}

#[test]
fn oficina_run_stopped_at_the_pen_change_resumes_from_the_journal() {
    let Some((scratch, file, program)) = real_plot("vpype_two_layers_a4.svg") else {
        return;
    };
    let emu = MarlinEmulator::start(MarlinConfig::default());
    let machine = format!("marlin+tcp://{}", emu.serve_tcp("127.0.0.1:0").unwrap());
    let run = |extra: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_oficina"))
            .args(["run", file.to_str().unwrap(), "--machine", &machine, extra])
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap()
    };
    let o = run("--stop-at-pauses");
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(stdout.contains("--resume"), "{stdout}");
    assert!(scratch.path().join("plot.gcode.journal").is_file());
    let first = drawn_segments(&emu.moves()).len();
    let o = run("--resume");
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("resuming at file line"), "{stderr}");
    // Stopped with the pen up at the change: the two runs draw the program's path once.
    let drawn = drawn_segments(&emu.moves());
    assert!(
        first > 100 && drawn.len() > first,
        "{first} then {}",
        drawn.len()
    );
    assert_same_path(&program_segments(&program), &drawn);
}

#[test]
fn a_hold_sends_no_new_line_until_resumed() {
    let emu = MarlinEmulator::start(MarlinConfig {
        busy_ms: 300,
        keepalive_ms: 50,
        ..Default::default()
    });
    let pty = emu.serve_pty().unwrap();
    let mut device = oficina_grbl::MarlinDevice::new(&format!("marlin:{pty}")).unwrap();
    device.options = fast();
    let scratch = tempfile::tempdir().unwrap();
    device.journal = Some(scratch.path().join("hold.journal"));
    device.connect().unwrap();
    let text = "G28\nG1 X1 F3000\nG1 X2\nG1 X3\n";
    device
        .start(Job {
            name: "hold".into(),
            text: Arc::new(text.into()),
            start_line: None,
            pace: Pace::Instant,
        })
        .unwrap();
    // Held while G28 (busy for 300 ms) runs: it finishes, nothing follows.
    let until = Instant::now() + Duration::from_secs(5);
    while !emu.executed().iter().any(|e| e.command == "G28") {
        assert!(Instant::now() < until, "G28 never arrived");
        std::thread::sleep(Duration::from_millis(5));
    }
    device.command(Command::Hold).unwrap();
    std::thread::sleep(Duration::from_millis(900));
    assert_eq!(device.status().state, oficina_machine::State::Hold);
    let ran = |emu: &MarlinEmulator| emu.executed().iter().filter(|e| e.n.is_some()).count();
    assert_eq!(ran(&emu), 1, "{:?}", emu.executed());
    device.command(Command::Resume).unwrap();
    assert!(run_to_end(&mut device, None));
    assert_eq!(ran(&emu), 4);
    assert_eq!(emu.moves().last().unwrap().to[0], 3.0);
}
