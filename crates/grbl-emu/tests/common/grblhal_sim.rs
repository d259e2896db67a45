//! grblHAL's own Simulator as a test peer. Its binary is not part of this repository (GPL-3
//! sources, built by whoever runs these tests): the path comes from `OFICINA_GRBLHAL_SIM`,
//! and each test reports itself as skipped when it is unset.
//!
//! The simulator talks over its stdin/stdout; here they are a pseudo-terminal (a pipe would
//! leave its replies in stdio's buffer), bridged to a loopback TCP port for the sender. The
//! bridge also shields the simulator from its SIGPIPE death when a client leaves with output
//! pending, and can drop status queries on purpose (`drop_queries`). The simulator's
//! position record (`-r`: steps every few ms of simulated time, and at every block change)
//! is the witness of the motion made.

use oficina_grbl::{Endpoint, Pty};
use std::io::{Read, Write};
use std::net::TcpListener;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::Duration;

pub(crate) struct Sim {
    child: Mutex<Child>,
    master: std::fs::File,
    pub(crate) endpoint: Endpoint,
    pub(crate) dir: PathBuf,
    /// While set, every `?` from the sender is dropped before it reaches the simulator.
    pub(crate) drop_queries: Arc<AtomicBool>,
    stop: Arc<AtomicBool>,
    _pty: Pty,
}

/// The simulator, or `None` (with a SKIPPED line on stderr) when `OFICINA_GRBLHAL_SIM` is
/// unset. `record_every`: seconds between position samples in `steps.out` (None: none).
pub(crate) fn start(test: &str, record_every: Option<f64>) -> Option<Sim> {
    let Some(bin) = std::env::var_os("OFICINA_GRBLHAL_SIM") else {
        eprintln!("SKIPPED {test}: set OFICINA_GRBLHAL_SIM to a grblHAL Simulator binary (grblHAL_sim) to run it against real firmware");
        return None;
    };
    let dir = std::env::temp_dir().join(format!("oficina-grblhal-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let pty = Pty::open().expect("pty");
    let slave = || {
        std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(&pty.slave_path)
            .expect("open pty slave")
    };
    let mut cmd = Command::new(&bin);
    // -n: no comment marks before replies; -b: planned blocks; the EEPROM file lands in
    // `dir` (its working directory), so every run starts from grblHAL's defaults.
    cmd.arg("-n").arg("-b").arg(dir.join("blocks.out"));
    if let Some(r) = record_every {
        cmd.arg("-r")
            .arg(format!("{r}"))
            .arg("-s")
            .arg(dir.join("steps.out"));
    }
    let child = cmd
        .current_dir(&dir)
        .stdin(Stdio::from(slave()))
        .stdout(Stdio::from(slave()))
        .stderr(Stdio::null())
        .spawn()
        .expect("start the grblHAL simulator");
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind loopback");
    let endpoint = Endpoint::Tcp {
        addr: listener.local_addr().unwrap().to_string(),
    };
    let drop_queries = Arc::new(AtomicBool::new(false));
    let stop = Arc::new(AtomicBool::new(false));
    let master = pty.master.try_clone().expect("pty master");
    let (drop2, stop2) = (drop_queries.clone(), stop.clone());
    let client: Arc<std::sync::Mutex<Option<std::net::TcpStream>>> = Default::default();
    // Simulator → current client (output with no client is discarded, as a UART would).
    {
        let mut m = master.try_clone().unwrap();
        let client = client.clone();
        let stop = stop.clone();
        thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while !stop.load(Ordering::Relaxed) {
                let Ok(n) = m.read(&mut buf) else { break };
                if n == 0 {
                    break;
                }
                if let Some(c) = client.lock().unwrap().as_mut() {
                    let _ = c.write_all(&buf[..n]);
                }
            }
        });
    }
    // Clients → simulator, one at a time (a reconnecting sender takes over).
    thread::spawn(move || {
        for conn in listener.incoming() {
            if stop2.load(Ordering::Relaxed) {
                break;
            }
            let Ok(mut conn) = conn else { continue };
            let _ = conn.set_nodelay(true);
            *client.lock().unwrap() = conn.try_clone().ok();
            let mut m = master.try_clone().unwrap();
            let drop3 = drop2.clone();
            thread::spawn(move || {
                let mut buf = [0u8; 1024];
                while let Ok(n) = conn.read(&mut buf) {
                    if n == 0 {
                        break;
                    }
                    let bytes: Vec<u8> = buf[..n]
                        .iter()
                        .copied()
                        .filter(|b| !(*b == b'?' && drop3.load(Ordering::Relaxed)))
                        .collect();
                    if m.write_all(&bytes).is_err() {
                        break;
                    }
                }
            });
        }
    });
    // The simulator reads nothing for its first simulated second.
    thread::sleep(Duration::from_millis(1200));
    Some(Sim {
        child: Mutex::new(child),
        master: pty.master.try_clone().expect("pty master"),
        endpoint,
        dir,
        drop_queries,
        stop,
        _pty: pty,
    })
}

impl Sim {
    /// Ends the simulator the clean way (Ctrl-F: it exits once idle, flushing its position
    /// record; grblHAL's harness writes the last block's end point only then).
    pub(crate) fn finish(&self) {
        let mut child = self.child.lock().unwrap();
        if let Ok(None) = child.try_wait() {
            let _ = (&self.master).write_all(&[0x06]);
            for _ in 0..100 {
                if let Ok(Some(_)) = child.try_wait() {
                    break;
                }
                thread::sleep(Duration::from_millis(50));
            }
        }
    }

    /// The position record: (simulated seconds, steps per axis) in order.
    pub(crate) fn samples(&self) -> Vec<(f64, [i64; 3])> {
        let text = std::fs::read_to_string(self.dir.join("steps.out")).unwrap_or_default();
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .filter_map(|l| {
                let mut it = l.split([' ', ',']).filter(|s| !s.is_empty());
                let t = it.next()?.parse().ok()?;
                let x = it.next()?.parse().ok()?;
                let y = it.next()?.parse().ok()?;
                let z = it.next()?.parse().ok()?;
                Some((t, [x, y, z]))
            })
            .collect()
    }

    /// The motion made, as straight pieces in machine mm (`steps_per_mm` from `$100…`).
    /// Calls [`Sim::finish`] first.
    pub(crate) fn pieces(&self, steps_per_mm: f64) -> Vec<([f64; 3], [f64; 3])> {
        self.finish();
        let pts: Vec<[f64; 3]> = self
            .samples()
            .iter()
            .map(|(_, s)| s.map(|v| v as f64 / steps_per_mm))
            .collect();
        pts.windows(2)
            .filter(|w| w[0] != w[1])
            .map(|w| (w[0], w[1]))
            .collect()
    }
}

impl Drop for Sim {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        // The simulator ignores SIGTERM (it only saves its EEPROM file): kill it.
        if let Ok(mut c) = self.child.lock() {
            let _ = c.kill();
            let _ = c.wait();
        }
        if std::env::var_os("OFICINA_KEEP_SIM_DIR").is_none() {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}
