//! A program's text shared with the interpreter thread without a copy.

use std::io::Cursor;
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
