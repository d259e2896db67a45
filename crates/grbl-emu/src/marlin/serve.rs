//! Runs a [`MarlinCore`] behind a pty or TCP clients. Each connection has a reader thread
//! (the serial RX buffer, and Marlin's emergency parser acting on `M108`/`M112`/`M410` as
//! they arrive) and a command thread (the queue: it blocks in `G28`, `M400` and `M0`
//! while keep-alives go out).

use super::core::{command_of, Action, Executed, MarlinConfig, MarlinCore, MarlinStats, Move};
use std::io::{self, BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread;
use std::time::{Duration, Instant};

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// The banner a booting Marlin prints.
const BANNER: &str = "start\necho:Marlin 2.1.2 (Oficina emulator)\necho: Last Updated: 2026-11-27 | Author: (Oficina)\n";

/// A Marlin board in software.
pub struct MarlinEmulator {
    core: Arc<Mutex<MarlinCore>>,
    pty_keep: Mutex<Vec<oficina_grbl::Pty>>,
}

/// Flags the emergency parser sets from the reader thread.
#[derive(Default)]
struct Emergency {
    /// `M108` arrived: an `M0` wait ends.
    user_continue: AtomicBool,
    /// `M112` arrived: the board halts.
    killed: AtomicBool,
}

impl MarlinEmulator {
    /// A board configured by `config`; nothing served until [`MarlinEmulator::serve_pty`]
    /// or [`MarlinEmulator::serve_tcp`].
    pub fn start(config: MarlinConfig) -> MarlinEmulator {
        MarlinEmulator {
            core: Arc::new(Mutex::new(MarlinCore::new(config))),
            pty_keep: Mutex::new(Vec::new()),
        }
    }

    /// Serves on a new pseudo-terminal; returns its path, to open as a serial port.
    pub fn serve_pty(&self) -> io::Result<String> {
        let pty = oficina_grbl::Pty::open()?;
        let path = pty.slave_path.clone();
        let reader = pty.master.try_clone()?;
        let writer = pty.master.try_clone()?;
        attach(self.core.clone(), Box::new(reader), Box::new(writer))?;
        lock(&self.pty_keep).push(pty);
        Ok(path)
    }

    /// Listens on `addr` (port 0 picks one); every client is a board that just booted its
    /// serial line (the machine state carries over).
    pub fn serve_tcp(&self, addr: &str) -> io::Result<SocketAddr> {
        let listener = TcpListener::bind(addr)?;
        let local = listener.local_addr()?;
        let core = self.core.clone();
        thread::spawn(move || {
            for stream in listener.incoming().flatten() {
                let _ = stream.set_nodelay(true);
                if let Ok(w) = stream.try_clone() {
                    let _ = attach(core.clone(), Box::new(stream), Box::new(w));
                }
            }
        });
        Ok(local)
    }

    /// Counters so far.
    pub fn stats(&self) -> MarlinStats {
        lock(&self.core).stats.clone()
    }

    /// Every line executed, in order.
    pub fn executed(&self) -> Vec<Executed> {
        lock(&self.core).executed.clone()
    }

    /// Every move, in order.
    pub fn moves(&self) -> Vec<Move> {
        lock(&self.core).moves.clone()
    }
}

fn attach(
    core: Arc<Mutex<MarlinCore>>,
    reader: Box<dyn Read + Send>,
    writer: Box<dyn Write + Send>,
) -> io::Result<()> {
    let writer = Arc::new(Mutex::new(writer));
    say(&writer, BANNER.trim_end().lines())?;
    let emergency = Arc::new(Emergency::default());
    let (tx, rx) = mpsc::channel::<String>();
    let (core_r, em_r) = (core.clone(), emergency.clone());
    thread::spawn(move || {
        let mut lines = BufReader::new(reader);
        let mut buf = Vec::new();
        loop {
            buf.clear();
            match lines.read_until(b'\n', &mut buf) {
                Ok(0) => return,
                Ok(_) => {}
                Err(e) if oficina_grbl::is_timeout(&e) => continue,
                Err(_) => return,
            }
            let raw = String::from_utf8_lossy(&buf);
            let Some(line) = lock(&core_r).wire(raw.trim_end_matches(['\n', '\r'])) else {
                continue;
            };
            match command_of(&line) {
                "M108" => em_r.user_continue.store(true, Ordering::SeqCst),
                "M112" => em_r.killed.store(true, Ordering::SeqCst),
                _ => {}
            }
            if tx.send(line).is_err() {
                return;
            }
        }
    });
    thread::spawn(move || run_queue(core, rx, writer, emergency));
    Ok(())
}

/// The command queue: one line at a time, replies written as Marlin prints them.
fn run_queue(
    core: Arc<Mutex<MarlinCore>>,
    rx: Receiver<String>,
    writer: Arc<Mutex<Box<dyn Write + Send>>>,
    emergency: Arc<Emergency>,
) {
    let keepalive = Duration::from_millis(lock(&core).config.keepalive_ms.max(1));
    while let Ok(line) = rx.recv() {
        if emergency.killed.load(Ordering::SeqCst) && command_of(&line) != "M112" {
            continue;
        }
        let action = lock(&core).receive(&line);
        let out = match action {
            None => continue,
            Some(Action::Reply(r)) => r,
            Some(Action::Refused(r)) => {
                // Marlin empties its RX buffer after a refused line.
                while rx.try_recv().is_ok() {}
                r
            }
            Some(Action::Busy { ms, then }) => {
                let until = Instant::now() + Duration::from_millis(ms);
                while Instant::now() < until {
                    thread::sleep(keepalive.min(until - Instant::now()));
                    if Instant::now() < until && say(&writer, ["echo:busy: processing"]).is_err() {
                        return;
                    }
                }
                then
            }
            Some(Action::WaitForUser(text)) => {
                emergency.user_continue.store(false, Ordering::SeqCst);
                if !text.is_empty() && say(&writer, [format!("echo:{text}").as_str()]).is_err() {
                    return;
                }
                let mut last = Instant::now();
                let _ = say(&writer, ["echo:busy: paused for user"]);
                while !emergency.user_continue.load(Ordering::SeqCst)
                    && !emergency.killed.load(Ordering::SeqCst)
                {
                    thread::sleep(Duration::from_millis(5));
                    if last.elapsed() >= keepalive {
                        last = Instant::now();
                        if say(&writer, ["echo:busy: paused for user"]).is_err() {
                            return;
                        }
                    }
                }
                vec!["ok".into()]
            }
            Some(Action::Kill(text)) => vec![text],
        };
        if say(&writer, out.iter().map(String::as_str)).is_err() {
            return;
        }
    }
}

fn say<'a>(
    writer: &Mutex<Box<dyn Write + Send>>,
    lines: impl IntoIterator<Item = &'a str>,
) -> io::Result<()> {
    let mut text = String::new();
    for l in lines {
        text.push_str(l);
        text.push('\n');
    }
    let mut w = lock(writer);
    w.write_all(text.as_bytes())?;
    w.flush()
}
