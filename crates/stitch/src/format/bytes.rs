//! Reading and writing little- and big-endian fields, with errors that name the byte.

use super::{Format, FormatError};

/// A cursor over a file's bytes; every read past the end is an error naming the offset and
/// what was being read.
pub(super) struct Reader<'a> {
    pub(super) buf: &'a [u8],
    pub(super) pos: usize,
    pub(super) format: Format,
}

impl<'a> Reader<'a> {
    pub(super) fn new(buf: &'a [u8], format: Format) -> Reader<'a> {
        Reader {
            buf,
            pos: 0,
            format,
        }
    }

    pub(super) fn err(&self, offset: usize, message: impl Into<String>) -> FormatError {
        FormatError::new(self.format, offset, message)
    }

    /// The next `n` bytes, for `what`.
    pub(super) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], FormatError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        let Some(end) = end else {
            return Err(self.err(
                self.pos,
                format!(
                    "{what} needs {n} bytes, {} remain: the file is truncated",
                    self.buf.len().saturating_sub(self.pos)
                ),
            ));
        };
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    pub(super) fn skip(&mut self, n: usize, what: &str) -> Result<(), FormatError> {
        self.take(n, what).map(|_| ())
    }

    pub(super) fn seek(&mut self, to: usize, what: &str) -> Result<(), FormatError> {
        if to > self.buf.len() {
            return Err(self.err(
                self.pos,
                format!(
                    "{what} is at byte {to}, beyond the file's {} bytes",
                    self.buf.len()
                ),
            ));
        }
        self.pos = to;
        Ok(())
    }

    pub(super) fn u8(&mut self, what: &str) -> Result<u8, FormatError> {
        Ok(self.take(1, what)?[0])
    }

    pub(super) fn u16le(&mut self, what: &str) -> Result<u16, FormatError> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    pub(super) fn u16be(&mut self, what: &str) -> Result<u16, FormatError> {
        let b = self.take(2, what)?;
        Ok(u16::from_be_bytes([b[0], b[1]]))
    }

    pub(super) fn u24le(&mut self, what: &str) -> Result<u32, FormatError> {
        let b = self.take(3, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], 0]))
    }

    pub(super) fn u32le(&mut self, what: &str) -> Result<u32, FormatError> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub(super) fn i32be(&mut self, what: &str) -> Result<i32, FormatError> {
        let b = self.take(4, what)?;
        Ok(i32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub(super) fn remaining(&self) -> usize {
        self.buf.len().saturating_sub(self.pos)
    }
}

pub(super) fn put_u16le(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_le_bytes());
}

pub(super) fn put_u32le(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

pub(super) fn put_i32le(out: &mut Vec<u8>, v: i32) {
    out.extend_from_slice(&v.to_le_bytes());
}

pub(super) fn put_u16be(out: &mut Vec<u8>, v: u16) {
    out.extend_from_slice(&v.to_be_bytes());
}

pub(super) fn put_i32be(out: &mut Vec<u8>, v: i32) {
    out.extend_from_slice(&v.to_be_bytes());
}

pub(super) fn put_f32le(out: &mut Vec<u8>, v: f32) {
    out.extend_from_slice(&v.to_le_bytes());
}

/// Overwrites 4 bytes at `at` (a placeholder written earlier).
pub(super) fn patch_u32le(out: &mut [u8], at: usize, v: u32) {
    out[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

pub(super) fn patch_u32be(out: &mut [u8], at: usize, v: u32) {
    out[at..at + 4].copy_from_slice(&v.to_be_bytes());
}

pub(super) fn patch_u24le(out: &mut [u8], at: usize, v: u32) {
    out[at..at + 3].copy_from_slice(&v.to_le_bytes()[..3]);
}
