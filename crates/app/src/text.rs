//! A program's text: shared with the interpreter thread without a copy, and single lines
//! fetched again to quote them under a diagnostic.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Cursor, Read};
use std::path::Path;
use std::sync::Arc;

pub(crate) struct SharedText(pub Arc<String>);

impl AsRef<[u8]> for SharedText {
    fn as_ref(&self) -> &[u8] {
        self.0.as_bytes()
    }
}

pub(crate) fn reader(text: &Arc<String>) -> Cursor<SharedText> {
    Cursor::new(SharedText(text.clone()))
}

/// Bytes of a line kept to quote a place at `col`: the characters up to a screen past it,
/// at most 4 bytes each, and never more than 1 MiB (the line limit is checked elsewhere).
fn quoted_bytes(col: u32) -> u64 {
    ((u64::from(col) + oficina_gcode::text::QUOTE_WIDTH as u64) * 4).min(1 << 20)
}

/// Fetch the text of the given 1-based lines (each up to the column it is quoted at) by
/// streaming the file once more; long lines are skipped without being kept.
pub fn source_lines(
    path: &Path,
    wanted: impl IntoIterator<Item = (u32, u32)>,
) -> BTreeMap<u32, String> {
    let mut cols: BTreeMap<u32, u32> = BTreeMap::new();
    for (line, col) in wanted {
        let c = cols.entry(line).or_insert(col);
        *c = (*c).max(col);
    }
    let mut out = BTreeMap::new();
    let Some(&last) = cols.keys().next_back() else {
        return out;
    };
    let Ok(f) = File::open(path) else { return out };
    let mut reader = BufReader::new(f);
    let mut buf = Vec::new();
    for line_no in 1..=last {
        buf.clear();
        let keep = cols.get(&line_no).map_or(1, |&c| quoted_bytes(c));
        let n = (&mut reader)
            .take(keep)
            .read_until(b'\n', &mut buf)
            .unwrap_or(0);
        if n == 0 {
            break;
        }
        if !buf.ends_with(b"\n") {
            let mut sink = Vec::new();
            loop {
                sink.clear();
                let m = (&mut reader)
                    .take(1 << 16)
                    .read_until(b'\n', &mut sink)
                    .unwrap_or(0);
                if m == 0 || sink.ends_with(b"\n") {
                    break;
                }
            }
        }
        if cols.contains_key(&line_no) {
            let text = oficina_gcode::text::decode(&buf);
            out.insert(line_no, text.trim_end_matches(['\n', '\r']).to_string());
        }
    }
    out
}
