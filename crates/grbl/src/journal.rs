//! An append-only journal of a stream: which lines went out and which the firmware
//! acknowledged, flushed as it happens, so after a crash, a power cut or a pulled cable the
//! next run knows exactly where the last one was.
//!
//! Format, one record a line: a header `oficina-grbl-journal 1 <lines> <fingerprint>`, then
//! `S i` (line i written to the wire), `A i` (acknowledged by ok), `E i code` (error:code),
//! `C i` (every line before i completed: the machine was seen idle), `X note` (stream end),
//! and for tool changes that re-measure: `R z` (the first tool's touch on the setter, machine
//! Z), `L i delta` (the tool length offset applied at the tool stop before line i).

use crate::job::StreamProgram;
use std::fs::{File, OpenOptions};
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

pub struct Journal {
    out: BufWriter<File>,
    pub path: PathBuf,
}

/// What a journal file says about a past stream.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JournalState {
    /// One past the highest line written to the wire.
    pub sent_end: usize,
    /// One past the highest line acknowledged.
    pub acked_end: usize,
    /// Lines before this index certainly ran to completion.
    pub completed: usize,
    pub errors: Vec<(usize, u8)>,
    pub end_note: Option<String>,
    /// The first tool's touch on the tool setter (machine Z, mm).
    pub tool_reference: Option<f64>,
    /// (tool stop index, `G43.1` offset applied there), in the order written.
    pub tool_lengths: Vec<(usize, f64)>,
}

impl Journal {
    /// Opens the journal for `job`, appending when it belongs to the same program (a resumed
    /// stream continues the record) and starting afresh otherwise.
    pub fn open(path: &Path, job: &StreamProgram) -> io::Result<Journal> {
        let header = format!(
            "oficina-grbl-journal 1 {} {:016x}",
            job.len(),
            job.fingerprint()
        );
        let same = std::fs::read_to_string(path)
            .ok()
            .and_then(|t| t.lines().next().map(|l| l == header))
            .unwrap_or(false);
        let file = if same {
            OpenOptions::new().append(true).open(path)?
        } else {
            let mut f = File::create(path)?;
            writeln!(f, "{header}")?;
            f
        };
        Ok(Journal {
            out: BufWriter::new(file),
            path: path.to_path_buf(),
        })
    }

    fn record(&mut self, rec: std::fmt::Arguments) -> io::Result<()> {
        self.out.write_fmt(rec)?;
        self.out.write_all(b"\n")?;
        self.out.flush()
    }

    pub fn sent(&mut self, i: usize) -> io::Result<()> {
        self.record(format_args!("S {i}"))
    }

    pub fn acked(&mut self, i: usize) -> io::Result<()> {
        self.record(format_args!("A {i}"))
    }

    pub fn error(&mut self, i: usize, code: u8) -> io::Result<()> {
        self.record(format_args!("E {i} {code}"))
    }

    pub fn completed(&mut self, i: usize) -> io::Result<()> {
        self.record(format_args!("C {i}"))
    }

    pub fn tool_reference(&mut self, z: f64) -> io::Result<()> {
        self.record(format_args!("R {z}"))
    }

    pub fn tool_length(&mut self, i: usize, delta: f64) -> io::Result<()> {
        self.record(format_args!("L {i} {delta}"))
    }

    pub fn end(&mut self, note: &str) -> io::Result<()> {
        let note = note.replace('\n', " ");
        self.record(format_args!("X {note}"))
    }

    /// Reads a journal written for `job`. A journal for another program is an error that
    /// says so; a torn last record (crash mid-write) is ignored.
    pub fn load(path: &Path, job: &StreamProgram) -> Result<JournalState, String> {
        let f = File::open(path)
            .map_err(|e| format!("{}: cannot read journal: {e}", path.display()))?;
        let mut lines = BufReader::new(f).lines();
        let header = lines.next().and_then(|l| l.ok()).unwrap_or_default();
        let expected = format!(
            "oficina-grbl-journal 1 {} {:016x}",
            job.len(),
            job.fingerprint()
        );
        if header != expected {
            return Err(format!(
                "{}: journal belongs to another program (or the program changed since)",
                path.display()
            ));
        }
        let mut st = JournalState::default();
        for line in lines.map_while(Result::ok) {
            let mut it = line.splitn(3, ' ');
            let kind = it.next().unwrap_or("");
            if kind == "X" {
                st.end_note = Some(line[1..].trim().to_string());
                continue;
            }
            if kind == "R" {
                if let Some(z) = it.next().and_then(|v| v.parse::<f64>().ok()) {
                    st.tool_reference = Some(z).filter(|z| z.is_finite());
                }
                continue;
            }
            let Some(i) = it.next().and_then(|v| v.parse::<usize>().ok()) else {
                continue;
            };
            match kind {
                "S" => st.sent_end = st.sent_end.max(i + 1),
                "A" => st.acked_end = st.acked_end.max(i + 1),
                "C" => st.completed = st.completed.max(i),
                "L" => {
                    if let Some(d) = it.next().and_then(|v| v.parse::<f64>().ok()) {
                        if d.is_finite() {
                            st.tool_lengths.push((i, d));
                        }
                    }
                }
                "E" => {
                    if let Some(code) = it.next().and_then(|c| c.parse().ok()) {
                        st.errors.push((i, code));
                        st.acked_end = st.acked_end.max(i + 1);
                    }
                }
                _ => {}
            }
        }
        Ok(st)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_survive_and_torn_tail_is_ignored() {
        let dir = std::env::temp_dir().join(format!("oficina-journal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("j.journal");
        let job = StreamProgram::from_text("t", "G0X1\nG0X2\nG0X3\n").unwrap();
        {
            let mut j = Journal::open(&p, &job).unwrap();
            j.sent(0).unwrap();
            j.sent(1).unwrap();
            j.acked(0).unwrap();
            j.completed(1).unwrap();
            j.error(1, 33).unwrap();
            j.tool_reference(-40.5).unwrap();
            j.tool_length(2, 1.25).unwrap();
        }
        std::fs::OpenOptions::new()
            .append(true)
            .open(&p)
            .unwrap()
            .write_all(b"A 2")
            .unwrap();
        let st = Journal::load(&p, &job).unwrap();
        assert_eq!(st.sent_end, 2);
        assert_eq!(st.completed, 1);
        assert_eq!(st.errors, vec![(1, 33)]);
        assert_eq!(st.tool_reference, Some(-40.5));
        assert_eq!(st.tool_lengths, vec![(2, 1.25)]);
        // The torn "A 2" without newline still parses as a whole record or not at all.
        assert!(st.acked_end == 2 || st.acked_end == 3);
        let other = StreamProgram::from_text("t", "G0X9\n").unwrap();
        assert!(Journal::load(&p, &other)
            .unwrap_err()
            .contains("another program"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
