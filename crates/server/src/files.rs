//! The job folder: uploads land here under a plain name and nothing else is ever touched.

use std::path::{Path, PathBuf};

/// A name is 1–100 of `A-Z a-z 0-9 . _ -`, not starting with a dot: no separators, no `..`,
/// nothing hidden, so `folder.join(name)` stays in the folder.
pub(crate) fn safe_name(name: &str) -> Result<&str, String> {
    let ok = !name.is_empty()
        && name.len() <= 100
        && !name.starts_with('.')
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'.' | b'_' | b'-'));
    if ok {
        Ok(name)
    } else {
        Err(format!(
            "file name {name:?}: use 1 to 100 letters, digits, '.', '_' or '-', not starting with '.'"
        ))
    }
}

pub(crate) fn path_in(folder: &Path, name: &str) -> Result<PathBuf, String> {
    Ok(folder.join(safe_name(name)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_that_leave_the_folder_are_refused() {
        for bad in [
            "",
            "..",
            "../x.nc",
            "a/b.nc",
            "/etc/passwd",
            ".hidden",
            "a\\b",
            "x\0y",
            "é.nc",
        ] {
            assert!(safe_name(bad).is_err(), "{bad:?}");
        }
        assert!(safe_name(&"a".repeat(101)).is_err());
        assert_eq!(safe_name("part_1.v2-final.nc"), Ok("part_1.v2-final.nc"));
    }
}
