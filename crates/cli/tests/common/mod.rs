//! What several CLI test binaries share.
// Each test binary compiles this module and uses part of it.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Output, Stdio};

/// The repository's root (samples, profiles).
pub(crate) fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `oficina args…`, run to its end.
pub(crate) fn oficina(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// `oficina args…` run in the folder `dir`.
pub(crate) fn oficina_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the binary runs")
}

/// A command's stdout and stderr as text.
pub(crate) fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A program `{name}.ngc` in a scratch folder.
pub(crate) fn program(name: &str, body: &str) -> PathBuf {
    oficina_testkit::scratch_file(&format!("{name}.ngc"), body)
}

/// The "total time: N s" figure `oficina plan` prints.
pub(crate) fn total_time(out: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.starts_with("total time:"))
        .unwrap_or_else(|| panic!("no total time in {out}"));
    line["total time:".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// A running `oficina emulate grbl`, killed when dropped, however the test ends.
pub(crate) struct Emulator {
    child: Child,
    /// Its stdout, kept open: the emulator may still print to it.
    _stdout: BufReader<ChildStdout>,
    /// Where it listens: `tcp://127.0.0.1:PORT`.
    pub(crate) uri: String,
}

impl Emulator {
    /// `host:port`, as `oficina console --tcp` takes it.
    pub(crate) fn host_port(&self) -> &str {
        self.uri.trim_start_matches("tcp://")
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `oficina emulate FIRMWARE extra…` on a free loopback port: the process, its
/// stdout after the banner, the `tcp://` address and the banner (its first line).
fn spawn_emulator(
    firmware: &str,
    extra: &[&str],
) -> (Child, BufReader<ChildStdout>, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["emulate", firmware])
        .args(extra)
        .args(["--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("the emulator starts");
    let mut stdout = BufReader::new(child.stdout.take().expect("piped stdout"));
    let mut first = String::new();
    stdout
        .read_line(&mut first)
        .expect("the emulator prints its banner");
    let uri = first
        .split_whitespace()
        .find(|w| w.starts_with("tcp://"))
        .unwrap_or_else(|| panic!("no tcp:// address in the banner: {first}"))
        .to_string();
    (child, stdout, uri, first)
}

/// An `oficina emulate grbl …` on a free local TCP port (`extra` before the port options),
/// with the `tcp://` address and the first line it printed (its banner).
pub(crate) fn emulator(extra: &[&str]) -> (Child, String, String) {
    let (child, _, uri, first) = spawn_emulator("grbl", extra);
    (child, uri, first)
}

/// [`emulator`], stopped when the [`Emulator`] is dropped.
pub(crate) fn emulate(extra: &[&str]) -> Emulator {
    emulate_firmware("grbl", extra)
}

/// `oficina emulate FIRMWARE extra…` (grbl, marlin), stopped when dropped.
pub(crate) fn emulate_firmware(firmware: &str, extra: &[&str]) -> Emulator {
    let (child, stdout, uri, _) = spawn_emulator(firmware, extra);
    Emulator {
        child,
        _stdout: stdout,
        uri,
    }
}

/// [`emulate`] a fast machine: `extra`, then rates of 60000 mm/min and accelerations of
/// `accel` mm/s² on X, Y and Z (the emulator accelerates: fast ramps keep tests short).
pub(crate) fn emulate_fast(accel: u32, extra: &[&str]) -> Emulator {
    let accel = accel.to_string();
    let mut args = extra.to_vec();
    let settings: Vec<String> = ["110", "111", "112"]
        .iter()
        .map(|n| format!("{n}=60000"))
        .chain(["120", "121", "122"].iter().map(|n| format!("{n}={accel}")))
        .collect();
    for s in &settings {
        args.extend(["--set", s.as_str()]);
    }
    emulate(&args)
}

/// `oficina run` of `program` (written to a scratch file named `name`) on the machine at
/// `addr`, with no terminal.
pub(crate) fn run_program_on(addr: &str, name: &str, program: &str) -> Output {
    let path = oficina_testkit::scratch_file(name, program);
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .arg("run")
        .arg(&path)
        .args(["--machine", addr])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
    out
}

/// The shipped size-34 sole contour, read by the library's point-list reader.
pub(crate) fn sole_sample() -> Vec<oficina_geom::Point> {
    oficina_io::load_points(&root().join("samples/sole/size34.csv")).unwrap()
}

/// Stops the `emulator` once `out`, a run on it, has ended; the run must have succeeded and
/// said `done:`.
pub(crate) fn assert_ran_to_done(mut emulator: Child, out: &Output) {
    let _ = emulator.kill();
    let _ = emulator.wait();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");
}

/// `oficina mill ARGS… -o OUT` in the repository's root (sample paths are relative to it).
pub(crate) fn mill(args: &[&str], out: &Path) -> Output {
    let mut all = vec!["mill"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    oficina_in(&root(), &all)
}

/// The number after `letter` on a line (words may be glued: `G1X1Y2`).
pub(crate) fn word(line: &str, letter: char) -> Option<f64> {
    let i = line.find(letter)? + 1;
    let rest = &line[i..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .unwrap_or(rest.len());
    rest[..end].parse().ok()
}

/// The strokes drawn: polylines of the points visited with the pen down. `down(line)` says
/// whether a line puts the pen down (Some(true)), lifts it (Some(false)) or neither.
pub(crate) fn pen_down_path(
    program: &str,
    down: impl Fn(&str) -> Option<bool>,
) -> Vec<Vec<[f64; 2]>> {
    let (mut at, mut pen) = ([0.0, 0.0], false);
    let mut strokes: Vec<Vec<[f64; 2]>> = Vec::new();
    for line in program.lines() {
        let code = line.split(';').next().unwrap_or("").trim();
        if let Some(d) = down(code) {
            if d && !pen {
                strokes.push(vec![at]);
            }
            pen = d;
            continue;
        }
        if code.starts_with("G0") || code.starts_with("G1") {
            at = [
                word(code, 'X').unwrap_or(at[0]),
                word(code, 'Y').unwrap_or(at[1]),
            ];
            if pen {
                strokes.last_mut().unwrap().push(at);
            }
        }
    }
    strokes
}
