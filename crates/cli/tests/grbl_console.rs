//! End-to-end: `oficina emulate grbl` in one process, `oficina console` in another, over
//! loopback TCP, as a user would run them; and a short `oficina bench stream`.

mod common;

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

const BIN: &str = env!("CARGO_BIN_EXE_oficina");

use common::Emulator;

fn start_emulator() -> (Emulator, String) {
    start_emulator_with(&[])
}

fn start_emulator_with(extra: &[&str]) -> (Emulator, String) {
    let mut args = vec!["--for-seconds", "60"];
    args.extend_from_slice(extra);
    launch(common::emulate_fast(20000, &args))
}

/// `oficina emulate grbl --tcp 127.0.0.1:0 args…`, and the `host:port` it listens on.
fn launch_emulator(args: &[&str]) -> (Emulator, String) {
    launch(common::emulate(args))
}

fn launch(emu: Emulator) -> (Emulator, String) {
    let addr = emu.host_port().to_string();
    (emu, addr)
}

/// `oficina console --tcp addr args…` running, its stdin, stdout and stderr piped (or all
/// three null when `quiet`).
fn spawn_console(addr: &str, args: &[&str], quiet: bool) -> Child {
    let io = || if quiet { Stdio::null() } else { Stdio::piped() };
    Command::new(BIN)
        .args(["console", "--tcp", addr])
        .args(args)
        .stdin(io())
        .stdout(io())
        .stderr(io())
        .spawn()
        .unwrap()
}

fn write_job(name: &str, lines: usize) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("oficina-grbl-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("job.nc");
    let mut s = String::from("(test job)\nG21 G90\nG0 Z1\nG1 Z-0.2 F3000\n");
    for i in 1..=lines {
        s += &format!("G1 X{:.2} Y{:.2}\n", i as f64 * 0.5, (i % 2) as f64);
    }
    s += "G0 Z1\nM30\n";
    std::fs::write(&path, s).unwrap();
    path
}

fn console(addr: &str, extra: &[&str]) -> std::process::Output {
    Command::new(BIN)
        .args(["console", "--tcp", addr])
        .args(extra)
        .stdin(Stdio::null())
        .output()
        .expect("run console")
}

/// `console --job JOB args…` with a 1 mm safe height and no spindle delay, as the resume
/// tests run it.
fn console_job(addr: &str, job: &std::path::Path, args: &[&str]) -> std::process::Output {
    let mut all = vec!["--job", job.to_str().unwrap()];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--safe-z", "1", "--spindle-delay", "0"]);
    console(addr, &all)
}

/// Runs an interactive console on `addr`, types `lines`, waits (bounded) until its output
/// holds every `until` text, then quits; returns what it printed.
fn console_session(addr: &str, lines: &[&str], until: &[&str]) -> String {
    let mut child = Command::new(BIN)
        .args(["console", "--tcp", addr])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    for l in lines {
        writeln!(stdin, "{l}").unwrap();
    }
    let mut text = String::new();
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    while until.iter().any(|u| !text.contains(u)) && std::time::Instant::now() < deadline {
        if let Ok(line) = rx.recv_timeout(Duration::from_millis(100)) {
            text.push_str(&line);
            text.push('\n');
        }
    }
    let _ = writeln!(stdin, "/quit");
    let _ = child.wait();
    text
}

#[test]
fn console_streams_a_job_then_resumes_from_a_line() {
    let (_emu, addr) = start_emulator();
    let job = write_job("run", 80);
    let out = console(&addr, &["--job", job.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("all 85 lines done"), "{stdout}");
    // Resume from file line 50 (G1 X23.00 Y0.00): preamble, approach, then the rest.
    let out = console_job(&addr, &job, &["--from-line", "50"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains(":50: restoring modal state"), "{stderr}");
    // A line past the end is refused with the file named.
    let out = console(
        &addr,
        &["--job", job.to_str().unwrap(), "--from-line", "999"],
    );
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no G-code at or after line 999"));
}

#[test]
fn console_terminal_names_settings_and_errors() {
    let (_emu, addr) = start_emulator();
    let want = [
        "(X-axis maximum rate, mm/min)",
        "error:22 (Undefined feed rate",
    ];
    let stdout = console_session(&addr, &["$$", "G1 X1"], &want);
    for w in want {
        assert!(stdout.contains(w), "{w} missing in:\n{stdout}");
    }
}

#[test]
fn emulate_refuses_bad_settings_and_bench_stream_reports_figures() {
    let out = Command::new(BIN)
        .args(["emulate", "grbl", "--tcp", "127.0.0.1:0", "--set", "999=1"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no setting $999"));
    let out = Command::new(BIN)
        .args(["bench", "stream", "--lines", "400", "--run", "link"])
        .output()
        .unwrap();
    let stdout = oficina_testkit::assert_success(&out);
    assert!(
        stdout.contains("% of the line rate") && stdout.contains(" 0 overflows"),
        "{stdout}"
    );
}

#[test]
fn console_resumes_from_the_journal_after_the_sender_is_killed() {
    let (_emu, addr) = start_emulator();
    let job = write_job("crash", 400);
    let journal = job.with_extension("nc.journal");
    let mut child = spawn_console(&addr, &["--job", job.to_str().unwrap()], true);
    // Let it get part way, then kill it as a crash would (no chance to clean up).
    let mut acked = 0;
    for _ in 0..600 {
        std::thread::sleep(Duration::from_millis(25));
        acked = std::fs::read_to_string(&journal)
            .map(|t| t.lines().filter(|l| l.starts_with("A ")).count())
            .unwrap_or(0);
        if acked >= 100 {
            break;
        }
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        acked >= 100,
        "the stream made progress before the crash ({acked} acks)"
    );
    let out = console_job(&addr, &job, &["--resume"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    // Success means the sender also found the machine at the program's final position.
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("resuming: machine"), "{stderr}");
    assert!(stdout.contains("all 405 lines done"), "{stdout}");
}

#[test]
fn console_reconnects_after_a_cut_cable_and_finishes_the_job() {
    use oficina_grbl_emu::{Fault, FaultProxy};
    let (_emu, addr) = start_emulator();
    let job = write_job("cable", 300);
    // Cut the line about a third of the way through the job's bytes.
    let proxy =
        FaultProxy::start(addr.parse().unwrap(), vec![Fault::Disconnect { at: 2500 }]).unwrap();
    let out = console_job(
        &proxy.addr.to_string(),
        &job,
        &["--auto-resume", "--reconnect", "10"],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(proxy.fired()[0], "the cable was cut");
    assert!(
        stderr.contains("connection lost") && stderr.contains("reconnected:"),
        "{stderr}"
    );
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("all 305 lines done"), "{stdout}");
}

#[test]
fn console_check_first_refuses_a_job_grbl_would_reject() {
    let (_emu, addr) = start_emulator();
    let job = write_job("check", 20);
    let text = std::fs::read_to_string(&job)
        .unwrap()
        .replace("G1 X5.00", "G1 X5.00 R2");
    std::fs::write(&job, text).unwrap();
    let out = console(&addr, &["--job", job.to_str().unwrap(), "--check"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("grbl rejects 1 line(s); nothing was cut"),
        "{stderr}"
    );
    assert!(
        stderr.contains("job.nc:14 `G1X5.00R2Y0.00`: error:36"),
        "{stderr}"
    );
}

#[test]
fn emulator_takes_its_settings_from_a_machine_profile() {
    let profile = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../profiles/grbl-router.toml"
    );
    let (_emu, addr) = launch_emulator(&["--for-seconds", "30", "--profile", profile]);
    let want = [
        "$110=6000.000",
        "$112=1500.000",
        "$120=300.000",
        "$130=800.000",
        "$132=100.000",
    ];
    let text = console_session(&addr, &["$$"], &want);
    // profiles/grbl-router.toml: X 6000 mm/min, Z 1500 mm/min, 300 mm/s², 800 x 450 x 100 mm.
    for w in want {
        assert!(text.contains(w), "{w} missing in:\n{text}");
    }
}

/// `console` fed by a pipe: every line is written at once and the input ends; the console
/// waits (bounded) for the firmware's answers to all of them before it exits.
#[test]
fn console_fed_by_a_pipe_waits_for_every_reply() {
    let (_emu, addr) = start_emulator_with(&["--flavor", "grblhal"]);
    let mut child = spawn_console(&addr, &[], false);
    {
        let mut stdin = child.stdin.take().unwrap();
        stdin.write_all(b"$I\n$$\n$G\n$#\nG4P0.5\nG0X5\n").unwrap();
    }
    let out = child.wait_with_output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    // grblHAL's build info (the emulator's grblhal flavour), its settings, parser state
    // and offsets; the last two replies come after a half-second dwell.
    for want in ["[OPT:VNML+,100,1024,3,0]", "$110=", "[GC:G0", "[G54:"] {
        assert!(text.contains(want), "missing {want}: {text}");
    }
}

/// The job keys reach the firmware (hold, resume, then stop): the console reports the stop
/// once, on stdout, with where to continue, and exits with failure.
#[test]
fn console_job_keys_hold_resume_and_stop_with_a_resume_hint() {
    let (_emu, addr) = start_emulator();
    let job = write_job("keys", 400);
    let journal = job.with_extension("nc.journal");
    let mut child = spawn_console(&addr, &["--job", job.to_str().unwrap()], false);
    let mut stdin = child.stdin.take().unwrap();
    let acked = || {
        std::fs::read_to_string(&journal)
            .map(|t| t.lines().filter(|l| l.starts_with("A ")).count())
            .unwrap_or(0)
    };
    for _ in 0..600 {
        if acked() >= 30 {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    writeln!(stdin, "h").unwrap();
    std::thread::sleep(Duration::from_millis(300));
    writeln!(stdin, "r").unwrap();
    std::thread::sleep(Duration::from_millis(100));
    writeln!(stdin, "s").unwrap();
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stdout}\n{stderr}");
    assert!(!stdout.contains("lines done"), "{stdout}");
    assert_eq!(
        stdout.matches("stopped by the operator").count(),
        1,
        "{stdout}\n{stderr}"
    );
    assert!(!stderr.contains("stopped by the operator"), "{stderr}");
    assert!(
        stdout.contains("to continue") && stdout.contains("--resume"),
        "{stdout}"
    );
}

/// `$H` typed in the console: the terminal keeps asking for status while the cycle runs
/// (`[Home]` with the position moving), prints `ok` when it is over; a board without limit
/// switches answers with ALARM:9, in words.
#[test]
fn console_homing_shows_the_cycle_and_its_alarm() {
    let (_emu, addr) = start_emulator_with(&["--set", "22=1", "--set", "25=600"]);
    let mut child = spawn_console(&addr, &[], false);
    {
        let mut stdin = child.stdin.take().unwrap();
        // From 10 mm down and 20 mm out: about 3 s of homing at 600 mm/min.
        stdin
            .write_all(b"$X\nG0 X-20 Z-10\nG4 P0\n$H\nG4 P0\n")
            .unwrap();
    }
    let out = child.wait_with_output().unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert_eq!(stdout.matches("ok").count(), 5, "{stdout}");
    let homing: std::collections::BTreeSet<&str> = stderr
        .split(['\r', '\n'])
        .filter_map(|l| l.split("[Home] MPos ").nth(1))
        .map(|p| p.split(' ').next().unwrap_or(""))
        .collect();
    assert!(
        homing.len() >= 3,
        "the status flows while homing: {homing:?}\n{stderr}"
    );

    let (_bare, addr) =
        start_emulator_with(&["--no-limit-switches", "--set", "22=1", "--set", "132=10"]);
    let mut child = spawn_console(&addr, &[], false);
    child.stdin.take().unwrap().write_all(b"$H\n").unwrap();
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("ALARM:9 (Homing fail: "),
        "the alarm in words: {stdout}"
    );
}
