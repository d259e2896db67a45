//! Runs a [`Core`] in real time and connects it to a pty or TCP clients. The wire is paced
//! at the emulated baud rate in both directions, so a sender meets the same byte timing as
//! on a USB-serial grbl board.

use super::core::{Config, Core, Stats};
use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread;
use std::time::{Duration, Instant};

const TICK: Duration = Duration::from_millis(1);
/// Late bytes may catch up at most this much, so a sleep overshoot does not slow the wire
/// while an idle pause does not turn into a burst faster than the line rate.
const PACING_SLACK: Duration = Duration::from_millis(1);
/// A byte this far behind its wire slot means the host, not the wire, held it up.
const HOST_LATE: Duration = Duration::from_millis(3);
/// How far a late reader may catch up on bytes that were already waiting on a busy wire.
const CATCH_UP: Duration = Duration::from_millis(20);

struct Shared {
    core: Mutex<Core>,
    start: Instant,
    /// [`Config::time_scale`](super::core::Config::time_scale).
    time_scale: f64,
    stop: AtomicBool,
    /// The connection that owns the wire now; older ones end when this moves on.
    generation: AtomicU64,
}

/// A running emulator. Dropping it stops its threads (blocked pty reads end with the process).
pub struct Emulator {
    shared: Arc<Shared>,
    ticker: Option<thread::JoinHandle<()>>,
    pty_keep: Mutex<Vec<oficina_grbl::Pty>>,
}

struct Pacer {
    byte_time: Option<Duration>,
    next: Instant,
}

impl Pacer {
    fn new(baud: Option<u32>) -> Pacer {
        Pacer {
            byte_time: baud.map(|b| Duration::from_secs_f64(10.0 / b.max(1) as f64)),
            next: Instant::now(),
        }
    }

    /// Waits for the wire slot of one byte. `was_waiting` says the byte was already queued
    /// when read (the reader was late, the wire was busy: keep the schedule) rather than
    /// just arrived on an idle wire (start the schedule now).
    /// Returns whether this byte is late: it was already waiting and its slot passed more
    /// than a couple of milliseconds ago (the emulator's host did not run the reader).
    fn wait(&mut self, was_waiting: bool) -> bool {
        let Some(bt) = self.byte_time else {
            return false;
        };
        let now = Instant::now();
        let late = was_waiting && now > self.next + HOST_LATE;
        let slack = if was_waiting { CATCH_UP } else { PACING_SLACK };
        if now > self.next + slack {
            self.next = now - slack;
        }
        if self.next > now + PACING_SLACK {
            thread::sleep(self.next - now);
        }
        self.next += bt;
        late
    }

    /// How many bytes the wire can carry now without waiting.
    fn budget(&mut self) -> usize {
        let Some(bt) = self.byte_time else {
            return usize::MAX;
        };
        let now = Instant::now();
        if now > self.next + PACING_SLACK {
            self.next = now - PACING_SLACK;
        }
        if self.next > now {
            return 0;
        }
        ((now - self.next).as_secs_f64() / bt.as_secs_f64()) as usize + 1
    }

    fn spent(&mut self, n: usize) {
        if let Some(bt) = self.byte_time {
            self.next += bt * n as u32;
        }
    }
}

impl Shared {
    /// The machine's time, s: the wall clock since start, scaled.
    fn clock(&self) -> f64 {
        self.start.elapsed().as_secs_f64() * self.time_scale
    }
}

impl Emulator {
    /// Starts the emulator on a pseudo-terminal or TCP port as `config` says.
    pub fn start(config: Config) -> Emulator {
        let time_scale = if config.time_scale > 0.0 {
            config.time_scale
        } else {
            1.0
        };
        let shared = Arc::new(Shared {
            core: Mutex::new(Core::new(config)),
            start: Instant::now(),
            time_scale,
            stop: AtomicBool::new(false),
            generation: AtomicU64::new(0),
        });
        let s = shared.clone();
        let ticker = thread::spawn(move || {
            while !s.stop.load(Ordering::Relaxed) {
                lock(&s.core).tick(s.clock());
                thread::sleep(TICK);
            }
        });
        Emulator {
            shared,
            ticker: Some(ticker),
            pty_keep: Mutex::new(Vec::new()),
        }
    }

    /// Runs `f` on the firmware model (inspection and test set-up).
    pub fn with_core<R>(&self, f: impl FnOnce(&mut Core) -> R) -> R {
        f(&mut lock(&self.shared.core))
    }

    /// Puts another tool in the spindle, as an operator does at an M6 (see
    /// [`Core::set_tool`]): the probe then touches with its length and diameter.
    pub fn set_tool(&self, tool: super::probe::Tool) {
        lock(&self.shared.core).set_tool(tool);
    }

    /// A copy of the counters so far.
    pub fn stats(&self) -> Stats {
        lock(&self.shared.core).stats.clone()
    }

    /// Opens a pseudo-terminal and serves it; returns the path a sender opens.
    pub fn serve_pty(&self) -> io::Result<String> {
        let pty = oficina_grbl::Pty::open()?;
        let path = pty.slave_path.clone();
        let reader = pty.master.try_clone()?;
        let writer = pty.master.try_clone()?;
        self.attach(Box::new(reader), Box::new(writer), None);
        lock(&self.pty_keep).push(pty);
        Ok(path)
    }

    /// Listens on `addr` (e.g. `127.0.0.1:0`) and serves one client at a time; a new client
    /// takes the wire over, as a reconnecting sender does. The firmware keeps running in
    /// between.
    pub fn serve_tcp(&self, addr: &str) -> io::Result<SocketAddr> {
        let listener = TcpListener::bind(addr)?;
        listener.set_nonblocking(true)?;
        let local = listener.local_addr()?;
        let shared = self.shared.clone();
        let emu = EmuHandle { shared };
        thread::spawn(move || {
            while !emu.shared.stop.load(Ordering::Relaxed) {
                match listener.accept() {
                    Ok((stream, _)) => {
                        if let Err(e) = emu.attach_tcp(stream) {
                            eprintln!("emulator: client dropped at connect: {e}");
                        }
                    }
                    Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                        thread::sleep(Duration::from_millis(10))
                    }
                    Err(_) => thread::sleep(Duration::from_millis(10)),
                }
            }
        });
        Ok(local)
    }

    fn attach(
        &self,
        reader: Box<dyn Read + Send>,
        writer: Box<dyn Write + Send>,
        tcp: Option<TcpStream>,
    ) {
        EmuHandle {
            shared: self.shared.clone(),
        }
        .attach(reader, writer, tcp)
    }
}

struct EmuHandle {
    shared: Arc<Shared>,
}

impl EmuHandle {
    fn attach_tcp(&self, stream: TcpStream) -> io::Result<()> {
        stream.set_nodelay(true)?;
        stream.set_nonblocking(false)?;
        stream.set_read_timeout(Some(Duration::from_millis(50)))?;
        let reader = stream.try_clone()?;
        let writer = stream.try_clone()?;
        // Classic grbl emulations greet a network client with the banner (a serial open
        // resets an Arduino); grblHAL's and FluidNC's telnet ports say nothing.
        let greeting = {
            let c = &lock(&self.shared.core).config;
            c.flavor
                .greets_tcp_clients()
                .then(|| format!("\r\n{}\r\n", c.flavor.banner(&c.version)))
        };
        let mut w = writer;
        if let Some(g) = greeting {
            w.write_all(g.as_bytes())?;
        }
        self.attach(Box::new(reader), Box::new(w), Some(stream));
        Ok(())
    }

    fn attach(
        &self,
        mut reader: Box<dyn Read + Send>,
        mut writer: Box<dyn Write + Send>,
        tcp: Option<TcpStream>,
    ) {
        let generation = self.shared.generation.fetch_add(1, Ordering::SeqCst) + 1;
        let baud = lock(&self.shared.core).config.baud;
        // Replies produced while nobody listened are gone, as on an unplugged UART.
        lock(&self.shared.core).out.clear();
        let s = self.shared.clone();
        let current = move |s: &Shared| {
            s.generation.load(Ordering::SeqCst) == generation && !s.stop.load(Ordering::Relaxed)
        };
        let current_r = current;
        thread::spawn(move || {
            let mut pacer = Pacer::new(baud);
            let mut buf = [0u8; 256];
            while current_r(&s) {
                let asked = Instant::now();
                match reader.read(&mut buf) {
                    Ok(0) => break,
                    Ok(n) => {
                        // A read that returns at once found bytes queued behind earlier ones.
                        let mut was_waiting = asked.elapsed() < Duration::from_micros(50);
                        for &b in &buf[..n] {
                            let late = pacer.wait(was_waiting);
                            was_waiting = true;
                            let mut core = lock(&s.core);
                            core.host_late = late;
                            core.receive(b);
                            if b == b'\n' {
                                // grbl's main loop picks a completed line up within
                                // microseconds; do not wait for the next tick.
                                core.tick(s.clock());
                            }
                        }
                    }
                    Err(e) if oficina_grbl::is_timeout(&e) => {}
                    Err(_) => break,
                }
            }
            if let Some(t) = tcp {
                let _ = t.shutdown(std::net::Shutdown::Both);
            }
        });
        let s = self.shared.clone();
        thread::spawn(move || {
            let mut pacer = Pacer::new(baud);
            while current(&s) {
                let chunk: Vec<u8> = {
                    let mut core = lock(&s.core);
                    let n = pacer.budget().min(core.out.len()).min(512);
                    core.out.drain(..n).collect()
                };
                if chunk.is_empty() {
                    thread::sleep(TICK);
                    continue;
                }
                pacer.spent(chunk.len());
                if writer
                    .write_all(&chunk)
                    .and_then(|_| writer.flush())
                    .is_err()
                {
                    break;
                }
            }
        });
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.ticker.take() {
            let _ = t.join();
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic in another thread must not take the emulator down with a poisoned lock.
    m.lock().unwrap_or_else(|p| p.into_inner())
}
