//! What several crates' integration tests share: LinuxCNC's `rs274` run as the oracle
//! ([`rs274`]), private scratch folders, a command's output checked for success, the
//! sample shapes more than one crate cuts ([`shapes`]) and seeded random numbers ([`random`]). Dev-only: never published.

pub mod random;
pub mod rs274;
pub mod shapes;

use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A new empty folder under the system temp folder, `oficina-{tag}-{pid}-{n}`: private to
/// this call, so tests running in parallel (and other checkouts) never share one.
pub fn scratch_dir(tag: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "oficina-{tag}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::SeqCst)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// `contents` written to a file `name` in a new [`scratch_dir`]; its path.
pub fn scratch_file(name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = scratch_dir("file").join(name);
    std::fs::write(&path, contents).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    path
}

/// The command's stdout; panics with its stdout and stderr unless it exited with success.
pub fn assert_success(out: &Output) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// A folder of the shared real-world files (`kind`: `gcode`, `mill-dxf-svg`, `plot-svg`,
/// `embroidery-files`…; licences in its SOURCES.md), looked for in `$OFICINA_REALWORLD`, then
/// `shared/data/realworld` beside the checkout (or beside a worktree's folder), then
/// `/work/shared/data/realworld`. `None`, with a note on stderr saying the test skipped it,
/// when this machine has none: the files are not the project's to commit.
pub fn realworld(kind: &str) -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let candidates: Vec<PathBuf> = match std::env::var_os("OFICINA_REALWORLD") {
        Some(d) => vec![PathBuf::from(d)],
        None => vec![
            root.join("../shared/data/realworld"),
            root.join("../../shared/data/realworld"),
            PathBuf::from("/work/shared/data/realworld"),
        ],
    };
    let found = candidates.iter().map(|d| d.join(kind)).find(|d| d.is_dir());
    if found.is_none() {
        eprintln!("note: no realworld/{kind} folder in {candidates:?}: skipped");
    }
    found
}
