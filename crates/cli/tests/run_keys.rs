//! `oficina run` under a pseudo-terminal: the keyboard holds, resumes and stops a job on the
//! virtual machine. The real binary runs with the pty as its terminal; its output is read
//! with poll() and every wait is bounded, so a broken key never hangs the test.

use nix::poll::{poll, PollFd, PollFlags};
use nix::pty::{openpty, Winsize};
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Generous bounds for a loaded machine; they only end a broken run, no figure depends on them.
const START_TIMEOUT: Duration = Duration::from_secs(60);
const STATE_TIMEOUT: Duration = Duration::from_secs(30);
const END_TIMEOUT: Duration = Duration::from_secs(120);

/// Twelve 100 mm feeds at 600 mm/min: two minutes of machine time, six seconds at 20x, so the
/// keys arrive well before the end.
fn long_program(dir: &Path) -> PathBuf {
    let mut text = String::from("G21 G90 G1 F600\n");
    for i in 0..12 {
        text.push_str(if i % 2 == 0 { "X100\n" } else { "X0\n" });
    }
    text.push_str("M2\n");
    let path = dir.join("long.nc");
    std::fs::write(&path, text).unwrap();
    path
}

/// One status line as `run` draws it: `line N  ETA h:mm:ss  X… Y… Z…  F…[ [State]]`.
#[derive(Clone, Debug, PartialEq)]
struct StatusLine {
    pos: [f64; 3],
    /// `None` while running; the machine state's name otherwise (Hold, Holding, …).
    state: Option<String>,
}

/// Drops terminal control sequences (CSI `ESC [ … final`), keeping the text.
fn strip_ansi(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\u{1b}' {
            out.push(c);
            continue;
        }
        if chars.peek() == Some(&'[') {
            chars.next();
            for c in chars.by_ref() {
                if ('\u{40}'..='\u{7e}').contains(&c) {
                    break;
                }
            }
        }
    }
    out
}

fn parse_status(fragment: &str) -> Option<StatusLine> {
    let at = fragment.find("ETA ")?;
    let words: Vec<&str> = fragment[at..].split_whitespace().collect();
    let axis = |letter: char| -> Option<f64> {
        words
            .iter()
            .find_map(|w| w.strip_prefix(letter).and_then(|v| v.parse().ok()))
    };
    let pos = [axis('X')?, axis('Y')?, axis('Z')?];
    let state = fragment
        .rfind('[')
        .filter(|&open| open > at)
        .and_then(|open| fragment[open + 1..].split(']').next())
        .map(str::to_string);
    Some(StatusLine { pos, state })
}

/// Every complete status line drawn so far, in order.
fn statuses(output: &str) -> Vec<StatusLine> {
    strip_ansi(output)
        .split(['\r', '\n'])
        .filter_map(parse_status)
        .collect()
}

/// The binary on a pty, with everything it has written so far.
struct Session {
    child: Child,
    master: File,
    output: String,
}

impl Session {
    fn start(program: &Path) -> Session {
        // A wide terminal, so the progress bar never cuts the status line short.
        let size = Winsize {
            ws_row: 24,
            ws_col: 200,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        let pty = openpty(Some(&size), None).expect("a pseudo-terminal");
        let stdio = || Stdio::from(pty.slave.try_clone().expect("a copy of the pty fd"));
        let child = Command::new(env!("CARGO_BIN_EXE_oficina"))
            .args(["run", "--speed", "20x"])
            .arg(program)
            .env("TERM", "xterm")
            .stdin(stdio())
            .stdout(stdio())
            .stderr(stdio())
            .spawn()
            .expect("the binary starts");
        // Only the child keeps the slave open: its exit then ends our reads.
        drop(pty.slave);
        Session {
            child,
            master: File::from(pty.master),
            output: String::new(),
        }
    }

    /// Reads what is ready within `wait`; false once the child's side is closed.
    fn pump(&mut self, wait: Duration) -> bool {
        let ms = wait.as_millis().min(u16::MAX as u128) as u16;
        let mut fds = [PollFd::new(self.master.as_fd(), PollFlags::POLLIN)];
        match poll(&mut fds, ms) {
            Ok(0) => return true,
            Ok(_) => {}
            Err(nix::errno::Errno::EINTR) => return true,
            Err(e) => panic!("poll on the pty: {e}"),
        }
        let mut buf = [0u8; 4096];
        match self.master.read(&mut buf) {
            // Linux reports EIO on the master once every slave fd is closed.
            Ok(0) | Err(_) => false,
            Ok(n) => {
                self.output.push_str(&String::from_utf8_lossy(&buf[..n]));
                true
            }
        }
    }

    /// Reads until `done` holds for the output so far; panics naming `what` after `timeout`.
    fn wait_for(&mut self, what: &str, timeout: Duration, done: impl Fn(&str) -> bool) {
        let deadline = Instant::now() + timeout;
        while !done(&self.output) {
            if Instant::now() > deadline || !self.pump(Duration::from_millis(100)) {
                panic!("no {what} within {timeout:?}; output:\n{}", self.output);
            }
        }
    }

    /// Reads everything for `span` (or until the child closes the pty).
    fn watch(&mut self, span: Duration) {
        let end = Instant::now() + span;
        while Instant::now() < end && self.pump(Duration::from_millis(50)) {}
    }

    fn press(&mut self, key: &[u8]) {
        self.master
            .write_all(key)
            .expect("writing a key to the pty");
        self.master.flush().unwrap();
    }

    /// Reads to the end and returns the exit status.
    fn finish(&mut self) -> ExitStatus {
        let deadline = Instant::now() + END_TIMEOUT;
        loop {
            let open = self.pump(Duration::from_millis(100));
            if let Some(status) = self.child.try_wait().expect("waiting for the child") {
                // What the child wrote just before exiting is still in the pty.
                while self.pump(Duration::from_millis(100)) {}
                return status;
            }
            if Instant::now() > deadline {
                panic!(
                    "run did not end within {END_TIMEOUT:?} (pty open: {open}); output:\n{}",
                    self.output
                );
            }
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        // A failed assertion must not leave the job running.
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

fn running(output: &str) -> bool {
    statuses(output).iter().any(|s| s.state.is_none())
}

#[test]
fn space_holds_and_tilde_resumes_to_the_end() {
    let dir = tempfile::tempdir().unwrap();
    let mut run = Session::start(&long_program(dir.path()));
    run.wait_for("running status line", START_TIMEOUT, running);

    run.press(b" ");
    run.wait_for("[Hold] status", STATE_TIMEOUT, |o| {
        statuses(o)
            .iter()
            .any(|s| s.state.as_deref() == Some("Hold"))
    });
    let before = statuses(&run.output).len();
    let held = statuses(&run.output).last().unwrap().clone();
    assert_eq!(held.state.as_deref(), Some("Hold"), "{}", run.output);
    // 1.5 s of wall time is 30 s of machine time at 20x: a run not held would cover 300 mm.
    run.watch(Duration::from_millis(1500));
    let during: Vec<StatusLine> = statuses(&run.output)[before..].to_vec();
    assert!(
        during.len() >= 3,
        "the status line keeps being drawn while held; output:\n{}",
        run.output
    );
    assert!(
        during.iter().all(|s| *s == held),
        "held at {held:?}, but the status moved: {during:?}"
    );
    assert!(!run.output.contains("done:"), "{}", run.output);

    run.press(b"~");
    let status = run.finish();
    let after = &statuses(&run.output)[before + during.len()..];
    assert!(
        after.iter().any(|s| s.state.is_none() && s.pos != held.pos),
        "motion goes on after resume: {after:?}"
    );
    assert!(run.output.contains("done:"), "{}", run.output);
    assert!(status.success(), "{status:?}; output:\n{}", run.output);
}

/// A stop key ends the job early: `stopped after …` and exit code 2.
fn stops_with(key: &[u8]) {
    let dir = tempfile::tempdir().unwrap();
    let mut run = Session::start(&long_program(dir.path()));
    run.wait_for("running status line", START_TIMEOUT, running);
    run.press(key);
    let status = run.finish();
    assert!(run.output.contains("stopped after"), "{}", run.output);
    assert!(!run.output.contains("done:"), "{}", run.output);
    assert_eq!(status.code(), Some(2), "output:\n{}", run.output);
}

#[test]
fn q_stops_the_job() {
    stops_with(b"q");
}

#[test]
fn ctrl_c_stops_the_job() {
    stops_with(b"\x03");
}

#[test]
fn the_status_parser_reads_run_and_hold_lines() {
    let text = "\r\x1b[2K\u{2588}\u{2588}   3% line      2  ETA 0:01:52  X12.500 Y0.000 Z40.000  F600\r\x1b[2K   3% line      2  ETA 0:01:52  X12.900 Y-1.000 Z40.000  F0 [Hold]";
    let s = statuses(text);
    assert_eq!(s.len(), 2);
    assert_eq!(s[0].pos, [12.5, 0.0, 40.0]);
    assert_eq!(s[0].state, None);
    assert_eq!(s[1].pos, [12.9, -1.0, 40.0]);
    assert_eq!(s[1].state.as_deref(), Some("Hold"));
}
