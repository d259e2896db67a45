//! A live connection: a reader thread turns the byte stream into classified lines, the
//! owner writes lines and real-time bytes. A closed or failing transport becomes one
//! `Closed` event carrying the reason, never a panic.

use crate::realtime::Realtime;
use crate::response::Response;
use crate::transport::{self, Connection, Endpoint};
use std::io::{self, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// A line longer than this without a newline is line noise: it is cut and reported.
const MAX_INCOMING_LINE: usize = 512;

/// What the reader thread reports.
#[derive(Debug, Clone, PartialEq)]
pub enum LinkEvent {
    /// A line from the firmware, classified, with its raw text.
    Line(Response, String),
    /// The connection ended; the reason says how.
    Closed(String),
}

/// A line-oriented connection to the firmware, read on a thread of its own.
pub struct Link {
    writer: Box<dyn Write + Send>,
    events: Receiver<LinkEvent>,
    stop: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
    /// Where it is connected, for messages.
    pub description: String,
}

impl Link {
    /// Connects to `endpoint`.
    pub fn open(endpoint: &Endpoint) -> io::Result<Link> {
        let conn = transport::open(endpoint)?;
        Ok(Link::from_connection(conn, endpoint.to_string()))
    }

    /// A link over an open connection.
    pub fn from_connection(conn: Connection, description: String) -> Link {
        let (tx, rx) = mpsc::channel();
        let stop = Arc::new(AtomicBool::new(false));
        let stop_r = stop.clone();
        let mut reader = conn.reader;
        let handle = std::thread::spawn(move || {
            let mut line: Vec<u8> = Vec::new();
            let mut buf = [0u8; 1024];
            while !stop_r.load(Ordering::Relaxed) {
                match reader.read(&mut buf) {
                    Ok(0) => {
                        let _ = tx.send(LinkEvent::Closed(
                            "the firmware closed the connection".into(),
                        ));
                        return;
                    }
                    Ok(n) => {
                        for &b in &buf[..n] {
                            if b == b'\n' || line.len() >= MAX_INCOMING_LINE {
                                let text = String::from_utf8_lossy(&line)
                                    .trim_end_matches('\r')
                                    .to_string();
                                line.clear();
                                if text.trim().is_empty() {
                                    continue;
                                }
                                if tx
                                    .send(LinkEvent::Line(Response::parse(&text), text))
                                    .is_err()
                                {
                                    return;
                                }
                            } else {
                                line.push(b);
                            }
                        }
                    }
                    Err(e) if transport::is_timeout(&e) => {}
                    Err(e) => {
                        let _ = tx.send(LinkEvent::Closed(format!("read failed: {e}")));
                        return;
                    }
                }
            }
        });
        Link {
            writer: conn.writer,
            events: rx,
            stop,
            reader: Some(handle),
            description,
        }
    }

    /// Writes one line and its newline in one write, so real-time bytes cannot split it.
    pub fn send_line(&mut self, line: &str) -> io::Result<()> {
        let mut bytes = Vec::with_capacity(line.len() + 1);
        bytes.extend_from_slice(line.as_bytes());
        bytes.push(b'\n');
        self.write_raw(&bytes)
    }

    /// Sends one real-time byte at once.
    pub fn send_realtime(&mut self, r: Realtime) -> io::Result<()> {
        self.write_raw(&[r.byte()])
    }

    /// Writes bytes as they are.
    pub fn write_raw(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.writer.write_all(bytes)?;
        self.writer.flush()
    }

    /// The next event, or `None` after `timeout`.
    pub fn recv(&self, timeout: Duration) -> Option<LinkEvent> {
        match self.events.recv_timeout(timeout) {
            Ok(e) => Some(e),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => Some(LinkEvent::Closed("reader stopped".into())),
        }
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.reader.take() {
            let _ = h.join();
        }
    }
}
