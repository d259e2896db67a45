//! Differential test: Oficina's G-code interpreter against LinuxCNC's standalone `rs274`.
//!
//! Every program in `tests/corpus/*.ngc` is run through `rs274 -g -t tool.tbl FILE` and
//! `oficina gcode canon FILE --tool-table tool.tbl`; both print LinuxCNC canonical calls. The
//! outputs are normalised (see [`normalise`]) and compared call by call, numbers within
//! [`TOLERANCE`]. Every program in `tests/corpus/bad/` must be rejected by both; the line each
//! one stops at is reported (rs274 prints the offending block's text, not its number, so its
//! line is found by matching that text against the source).
//!
//! The test fails unless every file agrees or is listed in [`ALLOWED`] with a reason. It needs
//! `rs274` (Debian package `linuxcnc-uspace`): when it is missing the test fails under CI (env
//! `CI` set) and is skipped loudly elsewhere.
//!
//! Run: `cargo test -p oficina-cli --test differential -- --nocapture`.

use std::collections::HashSet;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Both programs print 4 decimals; a value that sits on a rounding boundary may print one unit
/// of the last digit apart, hence the small slack above 1e-4.
const TOLERANCE: f64 = 1e-4 + 1e-9;

/// A program that runs longer than this in either interpreter is counted as a failure (an
/// endless loop must not hang the test suite).
const TIME_LIMIT: Duration = Duration::from_secs(30);

/// Files whose difference is deliberate, each with the reason (see
/// docs/linuxcnc-differences.md). Keep this short: everything else must agree.
const ALLOWED: &[(&str, &str)] = &[];

// Canonical calls that are compared: `oficina_testkit::rs274::COMPARED` (which says why the
// others are dropped); besides, `COMMENT("interpreter: …")` is rs274 narrating its own mode
// changes (see `is_narration`) and is dropped too; user comments are still compared.
use oficina_testkit::rs274::COMPARED;

/// The calls that move the machine or pass time: compared first and reported on their own.
const MOTION: &[&str] = &[
    "STRAIGHT_TRAVERSE",
    "STRAIGHT_FEED",
    "ARC_FEED",
    "NURBS_FEED",
    "RIGID_TAP",
    "DWELL",
];

/// One canonical call as printed, with the 1-based line of the output it came from.
#[derive(Clone, Debug)]
struct Call {
    out_line: usize,
    name: String,
    args: Vec<Arg>,
    text: String,
}

#[derive(Clone, Debug, PartialEq)]
enum Arg {
    Num(f64),
    Word(String),
}

/// What one interpreter did with one file.
struct Run {
    ok: bool,
    /// Killed by a signal (or by the time limit) rather than exiting.
    crashed: bool,
    stdout: String,
    stderr: String,
}

#[derive(Debug)]
enum Verdict {
    Agree,
    /// Bad program rejected by both; `same_line` is None when a line could not be determined.
    BothReject {
        same_line: Option<bool>,
        detail: String,
    },
    /// Motion (moves and dwells) agrees; some other state call differs.
    StateMismatch(String),
    Mismatch(String),
}

struct Outcome {
    file: String,
    verdict: Verdict,
    allowed: Option<&'static str>,
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus")
}

fn find_in_path(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// Runs a command with a time limit, collecting stdout and stderr.
fn run_command(mut cmd: Command) -> Run {
    let started = Instant::now();
    let mut child = match cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => {
            return Run {
                ok: false,
                crashed: false,
                stdout: String::new(),
                stderr: format!("cannot start: {e}"),
            }
        }
    };
    // Drain both pipes on threads so a chatty child never blocks on a full pipe.
    let mut out_pipe = child.stdout.take().expect("stdout is piped");
    let mut err_pipe = child.stderr.take().expect("stderr is piped");
    let out_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out_pipe.read_to_end(&mut s);
        String::from_utf8_lossy(&s).into_owned()
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err_pipe.read_to_end(&mut s);
        String::from_utf8_lossy(&s).into_owned()
    });
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if started.elapsed() > TIME_LIMIT => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(2)),
            Err(_) => break None,
        }
    };
    let stdout = out_reader.join().unwrap_or_default();
    let mut stderr = err_reader.join().unwrap_or_default();
    if status.is_none() {
        stderr.push_str(&format!("\n(killed after {} s)", TIME_LIMIT.as_secs()));
    }
    Run {
        ok: status.is_some_and(|s| s.success()),
        crashed: status.is_none_or(|s| s.code().is_none()),
        stdout,
        stderr,
    }
}

/// Attempts at a run of rs274 that dies by a signal: another rs274 started outside this test
/// (by someone else's test) can still collide with ours.
const RS274_ATTEMPTS: usize = 3;

fn run_rs274(file: &Path) -> Run {
    let mut run = run_rs274_once(file);
    for _ in 1..RS274_ATTEMPTS {
        if !run.crashed {
            break;
        }
        std::thread::sleep(Duration::from_millis(200));
        run = run_rs274_once(file);
    }
    if run.crashed {
        run.stderr.push_str("\n(rs274 crashed on every attempt)");
    }
    run
}

fn run_rs274_once(file: &Path) -> Run {
    // A private HOME, created once per test binary (see `oficina_testkit::rs274::command`).
    let home = std::env::temp_dir().join(format!("oficina-differential-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&home);
    let mut cmd = oficina_testkit::rs274::command(&home);
    if uses_subroutine_path(file) {
        cmd.arg("-i").arg(SUBROUTINE_INI);
    }
    if uses_settings_ini(file) {
        cmd.arg("-i").arg(SETTINGS_INI);
    }
    // rs274 writes its parameter file back at the end: it gets a copy.
    let var_copy = uses_var_file(file).then(|| {
        // A short name: rs274 keeps the file's name in a short buffer.
        let copy = home.join("start.var");
        std::fs::copy(corpus_dir().join(VAR_FILE), &copy).expect("copy var/start.var");
        copy
    });
    if let Some(copy) = &var_copy {
        cmd.arg("-v").arg(copy);
    }
    cmd.current_dir(corpus_dir())
        .arg("-g")
        .arg("-t")
        .arg("tool.tbl")
        .arg(file);
    // rs274 instances share state (it dies with SIGBUS when several run at once), so they
    // run one at a time; Oficina runs in parallel beside them.
    let _alone = oficina_testkit::rs274::alone();
    let mut run = run_command(cmd);
    // A good program must run silently: anything besides rs274's "executing" banner on
    // stderr (an error, a (print,…) line) means it did not run as the corpus intends.
    if run.ok && stderr_error_text(&run.stderr).is_some() {
        run.ok = false;
    }
    run
}

fn run_oficina(file: &Path) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_oficina"));
    cmd.current_dir(corpus_dir())
        .args(["gcode", "canon"])
        .arg(file)
        .arg("--tool-table")
        .arg("tool.tbl");
    if uses_subroutine_path(file) {
        cmd.arg("--subroutine-path").arg(SUBROUTINE_DIR);
    }
    if uses_settings_ini(file) {
        cmd.arg("--ini").arg(SETTINGS_INI);
    }
    if uses_var_file(file) {
        cmd.arg("--var-file").arg(VAR_FILE);
    }
    run_command(cmd)
}

/// Programs named `oword_lib_*.ngc` call subroutines kept in their own files in
/// [`SUBROUTINE_DIR`]: rs274 finds them through the INI file's SUBROUTINE_PATH, Oficina
/// through `--subroutine-path`. (The directory's own .ngc files are not corpus programs: the
/// corpus is read one level deep.)
const SUBROUTINE_DIR: &str = "oword_lib";
const SUBROUTINE_INI: &str = "oword_lib/paths.ini";

fn uses_subroutine_path(file: &Path) -> bool {
    file.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("oword_lib_"))
}

/// Programs named `ini_*.ngc` (good and bad) read LinuxCNC INI settings (ORIENT_OFFSET,
/// `#<_ini[section]name>`) from [`SETTINGS_INI`]: rs274 with `-i`, Oficina with `--ini`.
const SETTINGS_INI: &str = "ini/settings.ini";

fn uses_settings_ini(file: &Path) -> bool {
    file.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("ini_"))
}

/// Programs named `var_*.ngc` start from the parameter file [`VAR_FILE`] (a saved G92
/// offset, G54): rs274 with `-v` on a copy (it writes the file back), Oficina `--var-file`.
const VAR_FILE: &str = "var/start.var";

fn uses_var_file(file: &Path) -> bool {
    file.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("var_"))
}

/// rs274's stderr without its "executing" banner, or None when nothing else was said.
fn stderr_error_text(stderr: &str) -> Option<String> {
    let lines: Vec<&str> = oficina_testkit::rs274::complaints(stderr)
        .into_iter()
        .map(str::trim_end)
        .collect();
    (!lines.is_empty()).then(|| lines.join(" | "))
}

/// Strips rs274's `"   12 N..... "` counter and line-number prefix; Oficina prints none.
fn strip_prefix(line: &str) -> &str {
    let t = line.trim_start();
    let digits = t.len() - t.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    if digits == 0 {
        return t;
    }
    let rest = t[digits..].trim_start();
    match rest.strip_prefix('N') {
        Some(r) => r
            .trim_start_matches(|c: char| c == '.' || c.is_ascii_digit())
            .trim_start(),
        None => t,
    }
}

/// Parses `NAME(args)`; None for anything that is not a canonical call.
fn parse_call(out_line: usize, raw: &str) -> Option<Call> {
    let line = strip_prefix(raw).trim_end();
    let open = line.find('(')?;
    let name = &line[..open];
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_' || c == '.')
    {
        return None;
    }
    let inner = line[open + 1..].strip_suffix(')')?;
    let args = if name == "MESSAGE" || name == "COMMENT" {
        vec![Arg::Word(inner.to_string())]
    } else {
        inner
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>()
                    .map(Arg::Num)
                    .unwrap_or_else(|_| Arg::Word(s.to_string()))
            })
            .collect()
    };
    Some(Call {
        out_line,
        name: name.to_string(),
        args,
        text: line.to_string(),
    })
}

fn is_narration(call: &Call) -> bool {
    call.name == "COMMENT"
        && matches!(call.args.first(), Some(Arg::Word(w)) if w.starts_with("\"interpreter:"))
}

/// The calls that are compared, in order: bookkeeping, narration and repeated state dropped.
fn normalise(stdout: &str) -> Vec<Call> {
    let compared: HashSet<&str> = COMPARED.iter().copied().collect();
    let calls = stdout
        .lines()
        .enumerate()
        .filter_map(|(i, l)| parse_call(i + 1, l))
        .filter(|c| compared.contains(c.name.as_str()) && !is_narration(c));
    drop_repeated_state(calls)
}

/// The machine state before the first block, as the repeated-state filter assumes it: rs274
/// announces these again on the first G94/G17/G49/M5/M9 of a program, Oficina need not.
const INITIAL_STATE: &[&str] = &[
    "SET_FEED_RATE(0.0000)",
    "SET_FEED_MODE(0, 0)",
    "SELECT_PLANE(CANON_PLANE_XY)",
    "USE_TOOL_LENGTH_OFFSET(0 0 0, 0 0 0, 0 0 0)",
    "SET_SPINDLE_SPEED(0, 0)",
    "SET_SPINDLE_MODE(0 0)",
    "STOP_SPINDLE_TURNING(0)",
    "MIST_OFF()",
    "FLOOD_OFF()",
];

/// Which piece of machine state a call sets; calls that set the same state share a key
/// (`MIST_ON` and `MIST_OFF`). None for calls that do something (motion, dwell, messages).
fn state_key(name: &str) -> Option<&'static str> {
    Some(match name {
        "SET_FEED_RATE" => "feed rate",
        "SET_FEED_MODE" => "feed mode",
        "SELECT_PLANE" => "plane",
        "USE_LENGTH_UNITS" => "units",
        "USE_TOOL_LENGTH_OFFSET" => "tool length offset",
        "SET_G5X_OFFSET" => "work offset",
        "SET_G92_OFFSET" => "g92 offset",
        "SET_XY_ROTATION" => "rotation",
        "SET_MOTION_CONTROL_MODE" => "motion control mode",
        "SET_NAIVECAM_TOLERANCE" => "naivecam tolerance",
        "SET_SPINDLE_SPEED" => "spindle speed",
        "SET_SPINDLE_MODE" => "spindle mode",
        // M19 stops the spindle (rs274 starts it again on the next M3/M4).
        "START_SPINDLE_CLOCKWISE"
        | "START_SPINDLE_COUNTERCLOCKWISE"
        | "STOP_SPINDLE_TURNING"
        | "ORIENT_SPINDLE" => "spindle",
        "MIST_ON" | "MIST_OFF" => "mist",
        "FLOOD_ON" | "FLOOD_OFF" => "flood",
        "ENABLE_FEED_OVERRIDE" | "DISABLE_FEED_OVERRIDE" => "feed override",
        "ENABLE_SPEED_OVERRIDE" | "DISABLE_SPEED_OVERRIDE" => "speed override",
        "ENABLE_ADAPTIVE_FEED" | "DISABLE_ADAPTIVE_FEED" => "adaptive feed",
        "ENABLE_FEED_HOLD" | "DISABLE_FEED_HOLD" => "feed hold",
        _ => return None,
    })
}

/// Drops every state call that sets the value already in force: re-announcing a state carries
/// no information, and the two interpreters differ in how eagerly they re-announce.
fn drop_repeated_state(calls: impl Iterator<Item = Call>) -> Vec<Call> {
    let mut in_force: Vec<(&'static str, Call)> = INITIAL_STATE
        .iter()
        .filter_map(|t| parse_call(0, t))
        .filter_map(|c| state_key(&c.name).map(|k| (k, c)))
        .collect();
    let mut kept = Vec::new();
    for call in calls {
        let Some(key) = state_key(&call.name) else {
            kept.push(call);
            continue;
        };
        match in_force.iter_mut().find(|(k, _)| *k == key) {
            Some((_, old)) if old.name == call.name && args_agree(&old.args, &call.args) => {}
            Some((_, old)) => {
                *old = call.clone();
                kept.push(call);
            }
            None => {
                in_force.push((key, call.clone()));
                kept.push(call);
            }
        }
    }
    kept
}

fn is_motion(call: &Call) -> bool {
    MOTION.contains(&call.name.as_str())
}

fn args_agree(a: &[Arg], b: &[Arg]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| match (x, y) {
            (Arg::Num(p), Arg::Num(q)) => (p - q).abs() <= TOLERANCE,
            _ => x == y,
        })
}

/// The first difference between two call sequences, described with both lines.
fn first_difference(reference: &[Call], ours: &[Call]) -> Option<String> {
    for (i, (r, o)) in reference.iter().zip(ours).enumerate() {
        if r.name != o.name || !args_agree(&r.args, &o.args) {
            return Some(format!(
                "call #{}: rs274 (out line {}): {}\n        oficina (out line {}): {}",
                i + 1,
                r.out_line,
                r.text,
                o.out_line,
                o.text
            ));
        }
    }
    match reference.len().cmp(&ours.len()) {
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Greater => {
            let r = &reference[ours.len()];
            Some(format!(
                "oficina stops after {} calls; rs274 continues (out line {}): {}",
                ours.len(),
                r.out_line,
                r.text
            ))
        }
        std::cmp::Ordering::Less => {
            let o = &ours[reference.len()];
            Some(format!(
                "rs274 stops after {} calls; oficina continues (out line {}): {}",
                reference.len(),
                o.out_line,
                o.text
            ))
        }
    }
}

/// Source lines (1-based) whose text is the block rs274 names in its error message: rs274
/// prints the message, then the offending block as written.
fn rs274_error_lines(stderr: &str, source: &str) -> Vec<u32> {
    let lines: Vec<&str> = stderr
        .lines()
        .map(str::trim_end)
        .filter(|l| !l.is_empty() && *l != "executing")
        .collect();
    let Some(block) = lines.get(1) else {
        return Vec::new();
    };
    source
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == block.trim())
        .map(|(i, _)| i as u32 + 1)
        .collect()
}

/// The line of Oficina's first error, from a `file:LINE:COL: error: …` diagnostic.
fn oficina_error_line(stderr: &str) -> Option<u32> {
    stderr.lines().find_map(|l| {
        let head = &l[..l.find(": error")?];
        let mut parts = head.rsplit(':');
        let _col: u32 = parts.next()?.trim().parse().ok()?;
        parts.next()?.trim().parse().ok()
    })
}

fn first_line(s: &str) -> String {
    s.lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && *l != "executing")
        .unwrap_or("")
        .to_string()
}

fn compare_good(file: &Path) -> Verdict {
    let reference = run_rs274(file);
    if !reference.ok {
        return Verdict::Mismatch(format!(
            "corpus error: rs274 rejects this good program: {}",
            stderr_error_text(&reference.stderr).unwrap_or_default()
        ));
    }
    let ours = run_oficina(file);
    if !ours.ok {
        return Verdict::Mismatch(format!("oficina rejects it: {}", first_line(&ours.stderr)));
    }
    let (theirs, mine) = (normalise(&reference.stdout), normalise(&ours.stdout));
    let motion = |calls: &[Call]| {
        calls
            .iter()
            .filter(|c| is_motion(c))
            .cloned()
            .collect::<Vec<_>>()
    };
    if let Some(d) = first_difference(&motion(&theirs), &motion(&mine)) {
        return Verdict::Mismatch(format!("motion differs: {d}"));
    }
    match first_difference(&theirs, &mine) {
        None => Verdict::Agree,
        Some(d) => Verdict::StateMismatch(format!("motion agrees, state differs: {d}")),
    }
}

fn compare_bad(file: &Path) -> Verdict {
    let source = std::fs::read_to_string(file).unwrap_or_default();
    let reference = run_rs274(file);
    if reference.ok {
        return Verdict::Mismatch("corpus error: rs274 accepts this bad program".into());
    }
    let ours = run_oficina(file);
    if ours.ok {
        return Verdict::Mismatch(format!(
            "oficina accepts it; rs274: {}",
            stderr_error_text(&reference.stderr).unwrap_or_default()
        ));
    }
    let theirs = rs274_error_lines(&reference.stderr, &source);
    // A rejection must name its line; a failure without one (a crash, a usage error) is not
    // the interpreter rejecting the program.
    let Some(mine) = oficina_error_line(&ours.stderr) else {
        return Verdict::Mismatch(format!(
            "oficina fails without a `file:line:col: error:` diagnostic: {}",
            first_line(&ours.stderr)
        ));
    };
    let same_line = (!theirs.is_empty()).then(|| theirs.contains(&mine));
    let detail = format!(
        "rs274 line {:?}: {} | oficina line {}: {}",
        theirs,
        first_line(&reference.stderr),
        mine,
        first_line(&ours.stderr)
    );
    Verdict::BothReject { same_line, detail }
}

fn ngc_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read corpus directory {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ngc"))
        .collect();
    files.sort();
    files
}

/// Compares all files on a few worker threads (each run is a separate process).
fn compare_all(jobs: Vec<(PathBuf, bool)>) -> Vec<Outcome> {
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .clamp(1, 4);
    let next = AtomicUsize::new(0);
    let results = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some((path, is_bad)) = jobs.get(i) else {
                    break;
                };
                let verdict = if *is_bad {
                    compare_bad(path)
                } else {
                    compare_good(path)
                };
                let name = path.file_name().unwrap_or_default().to_string_lossy();
                let file = if *is_bad {
                    format!("bad/{name}")
                } else {
                    name.into_owned()
                };
                let allowed = ALLOWED
                    .iter()
                    .find(|(f, _)| *f == file)
                    .map(|(_, why)| *why);
                results.lock().unwrap().push(Outcome {
                    file,
                    verdict,
                    allowed,
                });
            });
        }
    });
    let mut out = results.into_inner().unwrap();
    out.sort_by(|a, b| a.file.cmp(&b.file));
    out
}

fn report(outcomes: &[Outcome]) -> usize {
    let (mut failures, mut allowed, mut agree, mut motion_agree) = (0, 0, 0, 0);
    let (mut lines_same, mut lines_known) = (0, 0);
    println!("\n{:<44} RESULT", "FILE");
    for o in outcomes {
        let (tag, detail) = match &o.verdict {
            Verdict::Agree => ("agree".to_string(), None),
            Verdict::BothReject { same_line, detail } => {
                if let Some(same) = same_line {
                    lines_known += 1;
                    lines_same += *same as usize;
                }
                let tag = match same_line {
                    Some(true) => "both reject, same line",
                    Some(false) => "both reject, DIFFERENT line",
                    None => "both reject",
                };
                (tag.to_string(), Some(detail))
            }
            Verdict::StateMismatch(d) | Verdict::Mismatch(d) => match o.allowed {
                Some(why) => (format!("ALLOWED difference ({why})"), Some(d)),
                None => ("MISMATCH".to_string(), Some(d)),
            },
        };
        match (&o.verdict, o.allowed) {
            (Verdict::Agree | Verdict::BothReject { .. }, _) => {
                agree += 1;
                motion_agree += 1;
            }
            (Verdict::StateMismatch(_), allowance) => {
                motion_agree += 1;
                failures += allowance.is_none() as usize;
                allowed += allowance.is_some() as usize;
            }
            (Verdict::Mismatch(_), allowance) => {
                failures += allowance.is_none() as usize;
                allowed += allowance.is_some() as usize;
            }
        }
        println!("{:<44} {tag}", o.file);
        if let Some(d) = detail {
            println!("        {d}");
        }
    }
    let total = outcomes.len();
    let pct = |n: usize| 100.0 * n as f64 / total.max(1) as f64;
    println!(
        "\nagreement: {agree}/{total} files ({:.1}%); motion alone: {motion_agree}/{total} ({:.1}%); \
         {allowed} allowed differences, {failures} failures; \
         bad programs stopped on the same line: {lines_same}/{lines_known}",
        pct(agree),
        pct(motion_agree),
    );
    failures
}

#[test]
fn oficina_agrees_with_linuxcnc_rs274_on_the_corpus() {
    if find_in_path("rs274").is_none() {
        let msg = "rs274 (LinuxCNC, Debian package linuxcnc-uspace) is not installed";
        if std::env::var_os("CI").is_some() {
            panic!("{msg}: the differential test cannot run in CI without it");
        }
        eprintln!("\n!!!!!!!! SKIPPED differential test: {msg} !!!!!!!!\n");
        return;
    }
    let dir = corpus_dir();
    let mut jobs: Vec<(PathBuf, bool)> = ngc_files(&dir).into_iter().map(|p| (p, false)).collect();
    jobs.extend(ngc_files(&dir.join("bad")).into_iter().map(|p| (p, true)));
    assert!(
        jobs.len() >= 180,
        "corpus too small: {} programs in {}",
        jobs.len(),
        dir.display()
    );
    let started = Instant::now();
    let outcomes = compare_all(jobs);
    let failures = report(&outcomes);
    println!(
        "compared {} programs in {:.1} s",
        outcomes.len(),
        started.elapsed().as_secs_f64()
    );
    assert_eq!(
        failures, 0,
        "{failures} corpus files differ from rs274 (table above)"
    );
}

#[test]
fn normalisation_strips_prefixes_and_compares_within_tolerance() {
    let rs = "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n    6 N..... ON_RESET()\n   \
              7 N..... COMMENT(\"interpreter: motion mode set to none\")\n   \
              9 N..... STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)\n   \
              10 N..... SET_FEED_REFERENCE(CANON_XYZ)\n";
    let calls = normalise(rs);
    assert_eq!(
        calls.len(),
        2,
        "narration and bookkeeping dropped: {calls:?}"
    );
    assert_eq!(calls[0].args, vec![Arg::Word("CANON_UNITS_MM".into())]);
    assert_eq!(calls[1].name, "STRAIGHT_TRAVERSE");
    assert_eq!(calls[1].args[2], Arg::Num(3.0));

    let units = "USE_LENGTH_UNITS(CANON_UNITS_MM)\n";
    let ours = "STRAIGHT_TRAVERSE(1.00005, 2.0000, 3.0000, 0.0000, 0.0000, -0.0000)\n";
    assert_eq!(
        first_difference(&calls, &normalise(&format!("{units}{ours}"))),
        None
    );
    let off = "STRAIGHT_TRAVERSE(1.0002, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)\n";
    assert!(first_difference(&calls, &normalise(&format!("{units}{off}"))).is_some());
    let inch = "USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n";
    assert!(first_difference(&calls, &normalise(&format!("{inch}{ours}"))).is_some());
    let short = first_difference(&calls, &normalise(units)).unwrap();
    assert!(short.contains("oficina stops"), "{short}");
}

#[test]
fn error_lines_are_found_in_both_formats() {
    let source = "G21\nG0 X1\nG1 X2\nM2\n";
    assert_eq!(
        rs274_error_lines(
            "executing\nCannot do g1 with zero feed rate\nG1 X2\n",
            source
        ),
        vec![3]
    );
    assert_eq!(
        oficina_error_line("f.ngc:3:1: error: G1 needs a feed rate\n"),
        Some(3)
    );
    assert_eq!(oficina_error_line("no diagnostics here"), None);
}
