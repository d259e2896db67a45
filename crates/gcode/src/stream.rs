//! A program interpreted on its own thread, its operations read as an iterator: the
//! push-style interpreter ([`crate::program::run`]) and a pull-style consumer (the planner,
//! the virtual machine) meet in bounded memory.

use crate::program::{run, RunOptions};
use crate::Diagnostic;
use oficina_canon::Canon;
use std::io::{BufRead, Seek};
use std::sync::mpsc::{sync_channel, Receiver};
use std::thread::JoinHandle;

/// Operations handed over per message: large enough that the channel costs nothing per op.
const CHUNK: usize = 1024;
/// Chunks in flight: bounds the memory between the interpreter and its consumer.
const CHUNKS_IN_FLIGHT: usize = 8;

/// Canonical operations of a program interpreted on another thread, as an iterator: the
/// interpreter runs ahead by a bounded number of chunks.
pub struct CanonStream {
    rx: Receiver<Vec<Canon>>,
    chunk: std::vec::IntoIter<Canon>,
    worker: Option<JoinHandle<Vec<Diagnostic>>>,
    diagnostics: Vec<Diagnostic>,
}

impl CanonStream {
    /// Start interpreting `source` with `opts`.
    pub fn spawn<R: BufRead + Seek + Send + 'static>(source: R, opts: RunOptions) -> CanonStream {
        let (tx, rx) = sync_channel::<Vec<Canon>>(CHUNKS_IN_FLIGHT);
        let worker = std::thread::spawn(move || {
            let mut pending = Vec::with_capacity(CHUNK);
            let mut consumer_gone = false;
            let diags = run(source, &opts, &mut |c| {
                if consumer_gone {
                    return;
                }
                pending.push(c);
                if pending.len() == CHUNK {
                    let full = std::mem::replace(&mut pending, Vec::with_capacity(CHUNK));
                    consumer_gone = tx.send(full).is_err();
                }
            });
            if !pending.is_empty() && !consumer_gone {
                let _ = tx.send(pending);
            }
            diags
        });
        CanonStream {
            rx,
            chunk: Vec::new().into_iter(),
            worker: Some(worker),
            diagnostics: Vec::new(),
        }
    }

    /// What the interpreter reported; complete once the iterator has returned `None`.
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.diagnostics
    }

    /// Wait for the interpreter (dropping whatever was not read) and take its diagnostics.
    pub fn finish(mut self) -> Vec<Diagnostic> {
        // Unblock the worker, then collect what it said.
        let (_, dead) = sync_channel(0);
        self.rx = dead;
        self.join();
        std::mem::take(&mut self.diagnostics)
    }

    fn join(&mut self) {
        if let Some(w) = self.worker.take() {
            self.diagnostics = w.join().unwrap_or_else(|_| {
                vec![Diagnostic::error(
                    crate::Span::line(0),
                    "the interpreter stopped unexpectedly (internal error)",
                )]
            });
        }
    }
}

impl Iterator for CanonStream {
    type Item = Canon;
    fn next(&mut self) -> Option<Canon> {
        loop {
            if let Some(c) = self.chunk.next() {
                return Some(c);
            }
            match self.rx.recv() {
                Ok(chunk) => self.chunk = chunk.into_iter(),
                Err(_) => {
                    self.join();
                    return None;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    fn program(blocks: usize) -> String {
        let mut s = String::from("G21 G90 F600\n");
        for i in 0..blocks {
            s.push_str(&format!("G1 X{} Y{}\n", i % 100, i % 7));
        }
        s.push_str("M2\n");
        s
    }

    #[test]
    fn yields_every_operation_of_the_direct_run_in_order() {
        let text = program(5000);
        let (direct, _) = crate::program::canon_of(&text, &RunOptions::default());
        let mut stream = CanonStream::spawn(Cursor::new(text.into_bytes()), RunOptions::default());
        let streamed: Vec<Canon> = stream.by_ref().collect();
        assert_eq!(streamed, direct);
        assert!(stream.diagnostics().is_empty());
    }

    #[test]
    fn diagnostics_arrive_after_the_last_operation() {
        let text = "G21\nG1 X1\nM2\n"; // G1 with no feed rate
        let mut stream =
            CanonStream::spawn(Cursor::new(text.as_bytes().to_vec()), RunOptions::default());
        for _ in stream.by_ref() {}
        assert_eq!(stream.diagnostics().len(), 1);
        assert_eq!(stream.diagnostics()[0].span.line, 2);
    }

    #[test]
    fn a_consumer_that_stops_early_does_not_hang_the_interpreter() {
        let text = program(50_000);
        let mut stream = CanonStream::spawn(Cursor::new(text.into_bytes()), RunOptions::default());
        assert!(stream.next().is_some());
        assert!(stream.finish().is_empty());
    }
}
