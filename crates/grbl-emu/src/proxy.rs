//! A fault-injecting TCP proxy between a sender and a firmware (real or emulated), for
//! tests and for rehearsing a flaky cable: it drops or corrupts bytes, resets the firmware,
//! cuts the connection, slows replies and mixes in line noise, each fault once, at a byte
//! count that makes a test repeatable.

use oficina_grbl::Realtime;
use std::io::{self, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::Duration;

/// One fault. Byte positions count the sender's line bytes only (not real-time bytes, whose
/// number depends on timing), from 1, across reconnections.
#[derive(Clone, Debug, PartialEq)]
pub enum Fault {
    /// The byte never reaches the firmware.
    Drop {
        /// Byte position, from 1.
        at: u64,
    },
    /// The byte arrives as `with`.
    Corrupt {
        /// Byte position, from 1.
        at: u64,
        /// The byte that arrives instead.
        with: u8,
    },
    /// A soft reset (Ctrl-X) reaches the firmware right after this byte, as if the board
    /// was reset behind the sender's back.
    Reset {
        /// Byte position, from 1.
        at: u64,
    },
    /// The connection is cut before this byte (cable pulled); later connections pass.
    Disconnect {
        /// Byte position, from 1.
        at: u64,
    },
    /// From this upstream byte on, the firmware's replies stop reaching the sender (a hung
    /// board or a half-dead link); the connection stays open. Ends with the connection.
    Silence {
        /// Byte position, from 1.
        at: u64,
    },
    /// Every firmware line is held back this long (a slow or busy firmware).
    SlowReplies {
        /// How long each line is held.
        delay: Duration,
    },
    /// Before every `every`-th firmware line, a line of noise.
    Garbage {
        /// Every how many firmware lines.
        every: u64,
        /// The noise bytes written.
        noise: Vec<u8>,
    },
}

#[derive(Default)]
struct Counters {
    upstream: u64,
    downstream_lines: u64,
    fired: Vec<bool>,
}

/// A TCP proxy between a sender and the emulator that injects [`Fault`]s.
pub struct FaultProxy {
    /// The address the sender connects to.
    pub addr: SocketAddr,
    stop: Arc<AtomicBool>,
    state: Arc<Mutex<Counters>>,
}

impl FaultProxy {
    /// Listens on a free local port and forwards to `upstream`, injecting `faults`.
    pub fn start(upstream: SocketAddr, faults: Vec<Fault>) -> io::Result<FaultProxy> {
        let listener = TcpListener::bind("127.0.0.1:0")?;
        listener.set_nonblocking(true)?;
        let addr = listener.local_addr()?;
        let stop = Arc::new(AtomicBool::new(false));
        let state = Arc::new(Mutex::new(Counters {
            fired: vec![false; faults.len()],
            ..Counters::default()
        }));
        let faults = Arc::new(faults);
        let (stop2, state2) = (stop.clone(), state.clone());
        thread::spawn(move || {
            while !stop2.load(Ordering::Relaxed) {
                match listener.accept() {
                    Ok((client, _)) => {
                        if let Ok(server) = TcpStream::connect(upstream) {
                            pump_pair(
                                client,
                                server,
                                faults.clone(),
                                state2.clone(),
                                stop2.clone(),
                            );
                        }
                    }
                    Err(_) => thread::sleep(Duration::from_millis(5)),
                }
            }
        });
        Ok(FaultProxy { addr, stop, state })
    }

    /// Faults that have fired so far (by index in the plan).
    pub fn fired(&self) -> Vec<bool> {
        self.state
            .lock()
            .map(|s| s.fired.clone())
            .unwrap_or_default()
    }

    /// Line bytes that went from the sender to the firmware.
    pub fn upstream_bytes(&self) -> u64 {
        self.state.lock().map(|s| s.upstream).unwrap_or(0)
    }
}

impl Drop for FaultProxy {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

fn pump_pair(
    client: TcpStream,
    server: TcpStream,
    faults: Arc<Vec<Fault>>,
    state: Arc<Mutex<Counters>>,
    stop: Arc<AtomicBool>,
) {
    let _ = client.set_nodelay(true);
    let _ = server.set_nodelay(true);
    let _ = client.set_read_timeout(Some(Duration::from_millis(50)));
    let _ = server.set_read_timeout(Some(Duration::from_millis(50)));
    let (Ok(mut c_read), Ok(mut s_write), Ok(mut s_read), Ok(mut c_write)) = (
        client.try_clone(),
        server.try_clone(),
        server.try_clone(),
        client.try_clone(),
    ) else {
        return;
    };
    let cut = Arc::new(AtomicBool::new(false));
    let mute = Arc::new(AtomicBool::new(false));
    let close = {
        let (client, server) = (client, server);
        move || {
            let _ = client.shutdown(Shutdown::Both);
            let _ = server.shutdown(Shutdown::Both);
        }
    };
    let close = Arc::new(close);
    // Sender → firmware.
    {
        let (faults, state, stop, cut, close, mute) = (
            faults.clone(),
            state.clone(),
            stop.clone(),
            cut.clone(),
            close.clone(),
            mute.clone(),
        );
        thread::spawn(move || {
            let mut buf = [0u8; 512];
            while !stop.load(Ordering::Relaxed) && !cut.load(Ordering::Relaxed) {
                let n = match c_read.read(&mut buf) {
                    Ok(0) => break,
                    Ok(n) => n,
                    Err(e) if oficina_grbl::is_timeout(&e) => continue,
                    Err(_) => break,
                };
                let mut out = Vec::with_capacity(n + 1);
                let mut disconnect = false;
                {
                    let Ok(mut st) = state.lock() else { break };
                    for &b in &buf[..n] {
                        if Realtime::is_realtime_byte(b) {
                            out.push(b);
                            continue;
                        }
                        let at = st.upstream + 1;
                        let mut byte = Some(b);
                        let mut reset_after = false;
                        for (k, f) in faults.iter().enumerate() {
                            if st.fired[k] {
                                continue;
                            }
                            match f {
                                Fault::Drop { at: a } if *a == at => byte = None,
                                Fault::Corrupt { at: a, with } if *a == at => byte = Some(*with),
                                Fault::Reset { at: a } if *a == at => reset_after = true,
                                Fault::Disconnect { at: a } if *a == at => disconnect = true,
                                Fault::Silence { at: a } if *a == at => {
                                    mute.store(true, Ordering::Relaxed)
                                }
                                _ => continue,
                            }
                            st.fired[k] = true;
                        }
                        if disconnect {
                            break;
                        }
                        st.upstream = at;
                        out.extend(byte);
                        if reset_after {
                            out.push(Realtime::SoftReset.byte());
                        }
                    }
                }
                if s_write.write_all(&out).is_err() {
                    break;
                }
                if disconnect {
                    break;
                }
            }
            cut.store(true, Ordering::Relaxed);
            close();
        });
    }
    // Firmware → sender, line by line.
    thread::spawn(move || {
        let mut buf = [0u8; 512];
        let mut line = Vec::new();
        while !stop.load(Ordering::Relaxed) && !cut.load(Ordering::Relaxed) {
            let n = match s_read.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if oficina_grbl::is_timeout(&e) => continue,
                Err(_) => break,
            };
            for &b in &buf[..n] {
                line.push(b);
                if b != b'\n' {
                    continue;
                }
                let mut out = Vec::new();
                let mut delay = None;
                if let Ok(mut st) = state.lock() {
                    st.downstream_lines += 1;
                    for (k, f) in faults.iter().enumerate() {
                        match f {
                            Fault::SlowReplies { delay: d } => {
                                delay = Some(*d);
                                st.fired[k] = true;
                            }
                            Fault::Garbage { every, noise }
                                if *every > 0 && st.downstream_lines % every == 0 =>
                            {
                                out.extend_from_slice(noise);
                                out.extend_from_slice(b"\r\n");
                                st.fired[k] = true;
                            }
                            _ => {}
                        }
                    }
                }
                if let Some(d) = delay {
                    thread::sleep(d);
                }
                out.append(&mut line);
                if mute.load(Ordering::Relaxed) {
                    continue;
                }
                if c_write.write_all(&out).is_err() {
                    cut.store(true, Ordering::Relaxed);
                    break;
                }
            }
        }
        cut.store(true, Ordering::Relaxed);
        close();
    });
}
