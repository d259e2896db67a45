//! The seed's one-way RS-232 link (§5.4, TRANS): the PC sends a numbered program to the
//! machine at 9600 baud, 7 data bits, even parity, 2 stop bits, with no handshake, reply or
//! retry; and a virtual seed machine that receives, stores and sews the programs.
//!
//! The thesis leaves the wire encoding open; 7 data bits cannot carry the RAM program's
//! bytes, so Oficina sends the `.BOR` text (ASCII, lines ended by CR LF) with the program
//! number in its first line `000 N`. The end record `999` and the stitch count that follows
//! it end the program and are its error check: the machine refuses a program whose count
//! disagrees with its records (a lost line), as [`crate::read_bor`] does.
//!
//! The machine stores each program as the firmware did (§10.4): appended after the others in
//! its 8 KB program RAM, in the compact RAM format; a program that does not fit is refused
//! with a message, a program number received again replaces the old one.

use crate::format::seed_ram::{self, SeedHeader};
use crate::plan::StitchPlan;
use crate::table::{run, HeadSpeed, Pauses, RunReport, Table};
use std::io::{self, Read, Write};
use std::time::Duration;

/// The seed's line: 9600 baud.
pub const SEED_BAUD: u32 = 9600;
/// The machine's program RAM, bytes.
pub const SEED_RAM_BYTES: usize = 8192;

/// Opens a serial port with the seed's framing: 9600 baud, 7 data bits, even parity, 2 stop
/// bits, no flow control.
pub fn open_seed_port(path: &str) -> io::Result<Box<dyn serialport::SerialPort>> {
    serialport::new(path, SEED_BAUD)
        .data_bits(serialport::DataBits::Seven)
        .parity(serialport::Parity::Even)
        .stop_bits(serialport::StopBits::Two)
        .flow_control(serialport::FlowControl::None)
        .timeout(Duration::from_millis(200))
        .open()
        .map_err(|e| io::Error::other(format!("cannot open {path}: {e}")))
}

/// The `.BOR` text of a program as sent: the program number `program`, lines ended by CR LF.
/// Errors as the `.BOR` writer does.
pub fn transmission(plan: &StitchPlan, header: &SeedHeader) -> Result<Vec<u8>, String> {
    let text = crate::format::write_bor(plan, header).map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&text).replace('\n', "\r\n");
    Ok(text.into_bytes())
}

/// Sends a program one way (TRANS): writes it and waits until the port has sent it.
pub fn send(port: &mut dyn Write, plan: &StitchPlan, header: &SeedHeader) -> Result<usize, String> {
    let bytes = transmission(plan, header)?;
    let failed = |e: std::io::Error| format!("sending program {}: {e}", header.program);
    port.write_all(&bytes).map_err(failed)?;
    // Then wait for the bytes to leave (tcdrain). On a pseudo-terminal that wait can fail
    // (the serial crate says only "flush failed") while the bytes are in the line's buffer and
    // are read: the written bytes are the transmission, so a failed wait is retried briefly and
    // then not taken as a failed send.
    for _ in 0..5 {
        if port.flush().is_ok() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    Ok(bytes.len())
}

/// A program the machine holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Stored {
    /// Its number.
    pub program: u16,
    /// Its header (Zero-Peça, hoop).
    pub header: SeedHeader,
    /// Its stitches, as the RAM program reads back.
    pub plan: StitchPlan,
    /// Its size in the program RAM, bytes.
    pub bytes: usize,
}

/// What the machine did with one received program.
#[derive(Clone, Debug)]
pub enum Received {
    /// Stored, and sewn on the table.
    Stored {
        /// The program number.
        program: u16,
        /// Sewn stitches.
        stitches: usize,
        /// The table's run.
        run: Box<RunReport>,
    },
    /// Refused (bad record, wrong count, no room): the message the machine shows.
    Refused(String),
}

/// The virtual seed machine: its program store and the table it sews on.
#[derive(Clone, Debug)]
pub struct SeedMachine {
    /// Programs in memory order.
    pub programs: Vec<Stored>,
    /// The table.
    pub table: Table,
    pending: Vec<u8>,
}

impl Default for SeedMachine {
    fn default() -> SeedMachine {
        SeedMachine::new()
    }
}

impl SeedMachine {
    /// An empty machine on the seed's table.
    pub fn new() -> SeedMachine {
        SeedMachine {
            programs: Vec::new(),
            table: Table::embroidery_table(),
            pending: Vec::new(),
        }
    }

    /// Bytes of program RAM in use.
    pub fn used(&self) -> usize {
        self.programs.iter().map(|p| p.bytes).sum()
    }

    /// The program numbered `n`.
    pub fn program(&self, n: u16) -> Option<&Stored> {
        self.programs.iter().find(|p| p.program == n)
    }

    /// Feeds received bytes (7-bit: the parity bit is stripped); returns what each program
    /// completed by them came to.
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<Received> {
        let mut out = Vec::new();
        for &b in bytes {
            self.pending.push(b & 0x7f);
            if b & 0x7f != b'\n' {
                continue;
            }
            // A program is complete at the line after a `999` line.
            let text = String::from_utf8_lossy(&self.pending).into_owned();
            let lines: Vec<&str> = text
                .split('\n')
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            let n = lines.len();
            if n >= 2 && lines[n - 2] == "999" {
                let bytes = std::mem::take(&mut self.pending);
                out.push(self.store(&bytes));
            } else if self.pending.len() > 1 << 20 {
                self.pending.clear();
                out.push(Received::Refused(
                    "more than 1 MB without an end record".into(),
                ));
            }
        }
        out
    }

    fn store(&mut self, text: &[u8]) -> Received {
        let (plan, header) = match crate::format::read_bor(text) {
            Ok(r) => r,
            Err(e) => return Received::Refused(e.to_string()),
        };
        let ram = match seed_ram::write(&plan, &header) {
            Ok(b) => b,
            Err(e) => return Received::Refused(e.to_string()),
        };
        let (plan, _) = match seed_ram::read(&ram) {
            Ok(r) => r,
            Err(e) => return Received::Refused(e.to_string()),
        };
        let program = header.program;
        let others: usize = self
            .programs
            .iter()
            .filter(|p| p.program != program)
            .map(|p| p.bytes)
            .sum();
        if others + ram.len() > SEED_RAM_BYTES {
            return Received::Refused(format!(
                "program {program} needs {} bytes, {} of {SEED_RAM_BYTES} are free",
                ram.len(),
                SEED_RAM_BYTES - others
            ));
        }
        let report = match run(&plan, &self.table, HeadSpeed::Table, Pauses::default()) {
            Ok(r) => r,
            Err(e) => return Received::Refused(e),
        };
        let stitches = plan.counts().stitches;
        // Received again: the old copy is deleted, those after it move down (Fig 4.10).
        self.programs.retain(|p| p.program != program);
        self.programs.push(Stored {
            program,
            header,
            plan,
            bytes: ram.len(),
        });
        Received::Stored {
            program,
            stitches,
            run: Box::new(report),
        }
    }

    /// Receives from `port` until `stop` says so, calling `report` for each program.
    pub fn serve(
        &mut self,
        port: &mut dyn Read,
        stop: &dyn Fn() -> bool,
        report: &mut dyn FnMut(&Received),
    ) -> io::Result<()> {
        let mut buf = [0u8; 1024];
        while !stop() {
            match port.read(&mut buf) {
                Ok(0) => std::thread::sleep(Duration::from_millis(20)),
                Ok(n) => {
                    for r in self.feed(&buf[..n]) {
                        report(&r);
                    }
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::TimedOut
                            | io::ErrorKind::WouldBlock
                            | io::ErrorKind::Interrupted
                    ) => {}
                // A pty master reads EIO while no one holds the slave open.
                Err(e) if e.raw_os_error() == Some(5) => {
                    std::thread::sleep(Duration::from_millis(20))
                }
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{ColorBlock, Kind, Stitch, Thread};

    fn plan(n: usize) -> StitchPlan {
        StitchPlan {
            name: "p".into(),
            blocks: vec![ColorBlock {
                thread: Thread::rgb(0, 0, 0),
                stitches: (1..=n)
                    .map(|i| Stitch::new(i as f64 * 0.4, (i % 2) as f64 * 2.0, Kind::Stitch))
                    .collect(),
            }],
        }
    }

    fn header(program: u16) -> SeedHeader {
        SeedHeader {
            program,
            start: [0.0, 0.0],
            hoop: None,
        }
    }

    #[test]
    fn programs_are_stored_by_number_and_refused_when_broken_or_too_big() {
        let mut m = SeedMachine::new();
        let t = transmission(&plan(50), &header(3)).unwrap();
        // Fed in pieces, as a UART delivers it.
        let mut got = Vec::new();
        for c in t.chunks(7) {
            got.extend(m.feed(c));
        }
        assert_eq!(got.len(), 1);
        match &got[0] {
            Received::Stored {
                program, stitches, ..
            } => assert_eq!((*program, *stitches), (3, 50)),
            r => panic!("{r:?}"),
        }
        assert_eq!(m.program(3).unwrap().plan.counts().stitches, 50);
        // A lost line: the count disagrees; refused, nothing stored.
        let text = String::from_utf8(transmission(&plan(10), &header(4)).unwrap()).unwrap();
        let lost: String = text
            .split_inclusive('\n')
            .enumerate()
            .filter(|(i, _)| *i != 6)
            .map(|(_, l)| l)
            .collect();
        match &m.feed(lost.as_bytes())[..] {
            [Received::Refused(e)] => assert!(e.contains("records hold"), "{e}"),
            r => panic!("{r:?}"),
        }
        assert!(m.program(4).is_none());
        // 5000 stitches need ~10 KB of RAM: more than the 8 KB.
        match &m.feed(&transmission(&plan(5000), &header(5)).unwrap())[..] {
            [Received::Refused(e)] => assert!(e.contains("bytes"), "{e}"),
            r => panic!("{r:?}"),
        }
        assert_eq!(m.programs.len(), 1);
    }
}

#[cfg(test)]
mod pty_tests {
    use super::*;
    use crate::plan::{ColorBlock, Kind, Stitch, Thread};
    use std::fs::File;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::{Arc, Mutex};

    /// Over a pseudo-terminal opened with the seed's framing: the machine stores program 3
    /// and sews as many stitches as the plan has, at the plan's points (0.2 mm grid).
    #[test]
    fn a_program_sent_over_a_pty_is_stored_and_sewn() {
        let pair = nix::pty::openpty(None, None).unwrap();
        let mut t = nix::sys::termios::tcgetattr(&pair.slave).unwrap();
        nix::sys::termios::cfmakeraw(&mut t);
        nix::sys::termios::tcsetattr(&pair.slave, nix::sys::termios::SetArg::TCSANOW, &t).unwrap();
        let path = nix::unistd::ttyname(&pair.slave).unwrap();
        let mut master = File::from(pair.master);
        let _slave = File::from(pair.slave);
        let plan = StitchPlan {
            name: "t".into(),
            blocks: vec![
                ColorBlock {
                    thread: Thread::rgb(0, 0, 0),
                    stitches: (1..=40)
                        .map(|i| Stitch::new(i as f64, (i % 3) as f64, Kind::Stitch))
                        .collect(),
                },
                ColorBlock {
                    thread: Thread::rgb(9, 9, 9),
                    stitches: vec![
                        Stitch::new(-20.0, 10.0, Kind::Jump),
                        Stitch::new(-18.0, 10.0, Kind::Stitch),
                    ],
                },
            ],
        };
        let done = Arc::new(AtomicBool::new(false));
        let got = Arc::new(Mutex::new(None));
        let (d, g) = (done.clone(), got.clone());
        let machine = std::thread::spawn(move || {
            let mut m = SeedMachine::new();
            m.serve(&mut master, &|| d.load(Ordering::SeqCst), &mut |r| {
                *g.lock().unwrap() = Some(r.clone());
                d.store(true, Ordering::SeqCst);
            })
            .unwrap();
            m
        });
        let mut port = open_seed_port(path.to_str().unwrap()).unwrap();
        let h = SeedHeader {
            program: 3,
            start: [10.0, -4.0],
            hoop: None,
        };
        send(&mut *port, &plan, &h).unwrap();
        for _ in 0..500 {
            if done.load(Ordering::SeqCst) {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        done.store(true, Ordering::SeqCst);
        let m = machine.join().unwrap();
        match got.lock().unwrap().take() {
            Some(Received::Stored {
                program, stitches, ..
            }) => assert_eq!((program, stitches), (3, 41)),
            r => panic!("{r:?}"),
        }
        let stored = m.program(3).unwrap();
        assert_eq!(stored.header.start, [10.0, -4.0]);
        let a: Vec<_> = stored
            .plan
            .entries()
            .map(|(_, s)| (s.x, s.y, s.kind))
            .collect();
        let b: Vec<_> = plan.entries().map(|(_, s)| (s.x, s.y, s.kind)).collect();
        assert_eq!(a.len(), b.len());
        for (p, q) in a.iter().zip(&b) {
            assert!(
                (p.0 - q.0).abs() < 1e-9 && (p.1 - q.1).abs() < 1e-9 && p.2 == q.2,
                "{p:?} {q:?}"
            );
        }
    }
}
