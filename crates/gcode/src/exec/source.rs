//! Lines from a seekable reader, one at a time, each with its byte offset so loops and calls
//! can jump back to it (as LinuxCNC seeks in the file). A line longer than the limit is
//! consumed without being kept: memory stays bounded whatever the input.

use std::io::{self, BufRead, ErrorKind, Seek, SeekFrom};

/// 256 KiB: far above any real G-code line, far below a file without newlines.
pub const DEFAULT_MAX_LINE_LEN: usize = 256 * 1024;

/// What one read produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Read {
    /// The line is in [`LineSource::text`].
    Line {
        offset: u64,
        number: u32,
    },
    /// The line was longer than the limit: it was skipped, its length is given.
    TooLong {
        number: u32,
        len: u64,
    },
    Eof,
}

pub(super) struct LineSource<R> {
    reader: R,
    /// Byte offset of the next line.
    pos: u64,
    /// 1-based number of the next line.
    next_line: u32,
    /// The last line when it had to be gathered from several reads of the reader.
    buf: Vec<u8>,
    /// The last line is instead the first `len` bytes of the reader's own buffer, read in
    /// place (no copy); it and its newline are consumed at the next read.
    in_place: Option<usize>,
    max_len: usize,
}

impl<R: BufRead + Seek> LineSource<R> {
    pub(super) fn new(mut reader: R) -> LineSource<R> {
        let pos = reader.stream_position().unwrap_or(0);
        LineSource {
            reader,
            pos,
            next_line: 1,
            buf: Vec::new(),
            in_place: None,
            max_len: DEFAULT_MAX_LINE_LEN,
        }
    }

    pub(super) fn set_max_len(&mut self, max: usize) {
        self.max_len = max.max(1);
    }

    pub(super) fn max_len(&self) -> usize {
        self.max_len
    }

    /// The text of the last line read (without its newline).
    pub(super) fn text(&mut self) -> &[u8] {
        match self.in_place {
            // Nothing was consumed since the read: `fill_buf` hands back the same buffer
            // without reading (the `BufRead` contract), so this cannot fail or differ.
            Some(len) => match self.reader.fill_buf() {
                Ok(b) => b.get(..len).unwrap_or_default(),
                Err(_) => &[],
            },
            None => &self.buf,
        }
    }

    /// Where the next line starts, and its number.
    pub(super) fn position(&self) -> (u64, u32) {
        (self.pos, self.next_line)
    }

    pub(super) fn seek(&mut self, offset: u64, line: u32) -> io::Result<()> {
        // The line read in place is left behind with the buffer the seek discards.
        self.in_place = None;
        self.reader.seek(SeekFrom::Start(offset))?;
        self.pos = offset;
        self.next_line = line;
        Ok(())
    }

    /// The bytes the reader holds from the next line on (reading more only when it holds
    /// none), for a caller that finds the line's end itself and then takes it with
    /// [`LineSource::take_line`]. Empty at the end of the input or on an error, which the
    /// next [`LineSource::read`] then meets.
    #[inline]
    pub(super) fn buffered(&mut self) -> &[u8] {
        if let Some(len) = self.in_place.take() {
            self.reader.consume(len + 1);
        }
        self.reader.fill_buf().unwrap_or_default()
    }

    /// Take the first `len` bytes of [`LineSource::buffered`] and the newline after them
    /// as the next line.
    pub(super) fn take_line(&mut self, len: usize) {
        self.take_lines(len + 1, 1);
    }

    /// Take the first `bytes` bytes of [`LineSource::buffered`], `lines` whole lines with
    /// their newlines, at once.
    #[inline]
    pub(super) fn take_lines(&mut self, bytes: usize, lines: u32) {
        self.reader.consume(bytes);
        self.pos += bytes as u64;
        self.next_line = self.next_line.saturating_add(lines);
    }

    pub(super) fn read(&mut self) -> io::Result<Read> {
        if let Some(len) = self.in_place.take() {
            self.reader.consume(len + 1);
        }
        self.buf.clear();
        let offset = self.pos;
        // Usually the whole line, newline included, is already in the reader's buffer:
        // it is read there, in place.
        if let Ok(chunk) = self.reader.fill_buf() {
            if let Some(len) = crate::bytes::find_byte(b'\n', chunk) {
                if len <= self.max_len {
                    self.in_place = Some(len);
                    self.pos += len as u64 + 1;
                    let number = self.next_line;
                    self.next_line = self.next_line.saturating_add(1);
                    return Ok(Read::Line { offset, number });
                }
            }
        }
        let mut len: u64 = 0;
        let mut too_long = false;
        let mut any = false;
        loop {
            let chunk = match self.reader.fill_buf() {
                Ok(c) => c,
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if chunk.is_empty() {
                break;
            }
            any = true;
            let (take, done) = match crate::bytes::find_byte(b'\n', chunk) {
                Some(i) => (i, true),
                None => (chunk.len(), false),
            };
            if !too_long {
                if self.buf.len() + take > self.max_len {
                    too_long = true;
                    self.buf.clear();
                } else {
                    self.buf.extend_from_slice(&chunk[..take]);
                }
            }
            let used = take + usize::from(done);
            self.reader.consume(used);
            len += take as u64;
            self.pos += used as u64;
            if done {
                break;
            }
        }
        if !any {
            return Ok(Read::Eof);
        }
        let number = self.next_line;
        self.next_line = self.next_line.saturating_add(1);
        Ok(if too_long {
            Read::TooLong { number, len }
        } else {
            Read::Line { offset, number }
        })
    }
}

/// The program and, above it, the subroutine files being run (`o<name> call` of a
/// subroutine found on the search path opens `name.ngc`): every read and seek goes to the
/// innermost. At most one file per call level is open.
pub(super) struct Sources<R> {
    main: LineSource<R>,
    /// One entry per subroutine call that changed file: a subroutine file, or `None` for a
    /// call from such a file back into a subroutine of the main program.
    files: Vec<Option<LineSource<io::BufReader<std::fs::File>>>>,
}

impl<R: BufRead + Seek> Sources<R> {
    pub(super) fn new(reader: R) -> Sources<R> {
        Sources {
            main: LineSource::new(reader),
            files: Vec::new(),
        }
    }

    pub(super) fn set_max_len(&mut self, max: usize) {
        self.main.set_max_len(max);
    }

    pub(super) fn max_len(&self) -> usize {
        self.main.max_len()
    }

    fn file(&self) -> Option<&LineSource<io::BufReader<std::fs::File>>> {
        self.files.last().and_then(Option::as_ref)
    }

    fn file_mut(&mut self) -> Option<&mut LineSource<io::BufReader<std::fs::File>>> {
        self.files.last_mut().and_then(Option::as_mut)
    }

    /// Lines come from the main program (not a subroutine file).
    pub(super) fn in_main(&self) -> bool {
        self.file().is_none()
    }

    pub(super) fn text(&mut self) -> &[u8] {
        match self.files.last_mut() {
            Some(Some(f)) => f.text(),
            _ => self.main.text(),
        }
    }

    #[inline]
    pub(super) fn buffered(&mut self) -> &[u8] {
        match self.files.last_mut() {
            Some(Some(f)) => f.buffered(),
            _ => self.main.buffered(),
        }
    }

    #[inline]
    pub(super) fn take_line(&mut self, len: usize) {
        match self.file_mut() {
            Some(f) => f.take_line(len),
            None => self.main.take_line(len),
        }
    }

    /// [`LineSource::take_lines`] of the innermost file.
    #[inline]
    pub(super) fn take_lines(&mut self, bytes: usize, lines: u32) {
        match self.file_mut() {
            Some(f) => f.take_lines(bytes, lines),
            None => self.main.take_lines(bytes, lines),
        }
    }

    pub(super) fn position(&self) -> (u64, u32) {
        match self.file() {
            Some(f) => f.position(),
            None => self.main.position(),
        }
    }

    pub(super) fn seek(&mut self, offset: u64, line: u32) -> io::Result<()> {
        match self.file_mut() {
            Some(f) => f.seek(offset, line),
            None => self.main.seek(offset, line),
        }
    }

    pub(super) fn read(&mut self) -> io::Result<Read> {
        match self.file_mut() {
            Some(f) => f.read(),
            None => self.main.read(),
        }
    }

    /// Run lines of `file` from its start until it is closed by [`Sources::close_to`].
    pub(super) fn open(&mut self, file: std::fs::File) {
        let mut source = LineSource::new(io::BufReader::new(file));
        source.set_max_len(self.main.max_len());
        self.files.push(Some(source));
    }

    /// Run lines of the main program again (a call from a subroutine file of a subroutine
    /// the main program defines), until closed by [`Sources::close_to`].
    pub(super) fn enter_main(&mut self) {
        self.files.push(None);
    }

    /// How many file changes the calls in progress made.
    pub(super) fn depth(&self) -> usize {
        self.files.len()
    }

    /// Undo the file changes above `depth`.
    pub(super) fn close_to(&mut self, depth: usize) {
        self.files.truncate(depth);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    #[test]
    fn lines_offsets_and_seeking_back() {
        let mut s = LineSource::new(Cursor::new(b"G0 X1\r\n\nG1 X2".to_vec()));
        assert_eq!(
            s.read().unwrap(),
            Read::Line {
                offset: 0,
                number: 1
            }
        );
        assert_eq!(s.text(), b"G0 X1\r");
        assert_eq!(
            s.read().unwrap(),
            Read::Line {
                offset: 7,
                number: 2
            }
        );
        assert_eq!(s.text(), b"");
        assert_eq!(
            s.read().unwrap(),
            Read::Line {
                offset: 8,
                number: 3
            }
        );
        assert_eq!(s.text(), b"G1 X2");
        assert_eq!(s.read().unwrap(), Read::Eof);
        s.seek(7, 2).unwrap();
        assert_eq!(
            s.read().unwrap(),
            Read::Line {
                offset: 7,
                number: 2
            }
        );
    }

    #[test]
    fn over_long_lines_are_skipped_without_being_kept() {
        let mut text = vec![b'x'; 10_000];
        text.extend_from_slice(b"\nG0\n");
        // A tiny reader buffer: the long line arrives in many chunks.
        let reader = io::BufReader::with_capacity(64, Cursor::new(text));
        let mut s = LineSource::new(reader);
        s.set_max_len(100);
        assert_eq!(
            s.read().unwrap(),
            Read::TooLong {
                number: 1,
                len: 10_000
            }
        );
        assert!(s.buf.capacity() <= 200, "the long line was never buffered");
        assert_eq!(
            s.read().unwrap(),
            Read::Line {
                offset: 10_001,
                number: 2
            }
        );
        assert_eq!(s.text(), b"G0");
    }
}
