//! Issue 27, "G-code as it is written": programs nobody here wrote, read as their control
//! reads them. LinuxCNC's: `oficina gcode canon` against `rs274 -g` with no tool table (its
//! standalone default) and on LinuxCNC's own spline example (`lcnc_systems.ngc`, 548 G5.1
//! moves); grbl's: CAM output for grbl checks clean with `--dialect grbl`, and what grbl 1.1
//! refuses stays an error with grbl's number and a hint at the post-processor that wrote it.

use oficina_testkit::{rs274, scratch_file};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn oficina() -> Command {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The shared folder of real-world files (outside the checkout), when this machine has it.
fn realworld(name: &str) -> Option<PathBuf> {
    Some(oficina_testkit::realworld("gcode")?.join(name)).filter(|p| p.is_file())
}

/// The calls that move the machine or set what a move means, `rs274 -g`'s prefix stripped.
fn moves(stdout: &str) -> Vec<String> {
    const KEPT: &[&str] = &[
        "STRAIGHT_TRAVERSE(",
        "STRAIGHT_FEED(",
        "ARC_FEED(",
        "NURBS_FEED(",
        "USE_TOOL_LENGTH_OFFSET(",
        "SELECT_TOOL(",
        "CHANGE_TOOL(",
    ];
    stdout
        .lines()
        .map(|l| match l.find(" N..... ") {
            Some(k) => &l[k + 8..],
            None => l,
        })
        .map(str::trim)
        .filter(|l| KEPT.iter().any(|k| l.starts_with(k)))
        .map(|l| l.replace("-0.0000", "0.0000"))
        .collect()
}

/// The same call with the same words, numbers within a unit of their 4th decimal (both print
/// 4 decimals; a value on a rounding boundary may print one unit apart).
fn same_call(a: &str, b: &str) -> bool {
    let split = |s: &str| -> Vec<String> {
        s.split(|c: char| c == '(' || c == ')' || c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .map(String::from)
            .collect()
    };
    let (a, b) = (split(a), split(b));
    a.len() == b.len()
        && a.iter()
            .zip(&b)
            .all(|(x, y)| match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(p), Ok(q)) => (p - q).abs() <= 1e-4 + 1e-9,
                _ => x == y,
            })
}

fn assert_same_calls(rs274_out: &str, ours: &Output, what: &str) {
    assert!(
        ours.status.success(),
        "oficina rejects {what}: {}",
        String::from_utf8_lossy(&ours.stderr)
    );
    let (theirs, mine) = (
        moves(rs274_out),
        moves(&String::from_utf8_lossy(&ours.stdout)),
    );
    assert!(!theirs.is_empty());
    for (i, (t, m)) in theirs.iter().zip(&mine).enumerate() {
        assert!(same_call(t, m), "{what}: call {} differs:\n{t}\n{m}", i + 1);
    }
    assert_eq!(theirs.len(), mine.len(), "{what}: number of calls");
}

/// rs274 run with no `-t`: (success, stdout, stderr).
fn rs274_without_table(file: &Path) -> Option<(bool, String, String)> {
    if !rs274::installed() {
        eprintln!("!!!!!!!! SKIPPED: rs274 (LinuxCNC) is not installed !!!!!!!!");
        return None;
    }
    let home = oficina_testkit::scratch_dir("rs274-home-27");
    let out = {
        let _alone = rs274::alone();
        rs274::command(&home).arg("-g").arg(file).output().unwrap()
    };
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let ok = out.status.success() && rs274::complaints(&stderr).is_empty();
    Some((
        ok,
        String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr,
    ))
}

#[test]
fn without_a_tool_table_tools_1_to_3_are_rs274s_standalone_defaults() {
    // T1 and T3 lengths under G20 and G21, T2's radius under G41: all from rs274's default.
    // (G43 on its own line: after an M6 in the same block rs274 keeps the position it had
    // before the change, a deliberate difference of Oficina's.)
    let program = "G20 G17 G90\nT1 M6\nG43\nG0 X1 Y1 Z1\nT3 M6\nG43\nG0 Z1\nG0 Z0.5\n\
                   T2 M6\nG43\nG0 X-1 Y-1\nG41 G1 X0 Y0 F10\nX2\nY2\nG40 G0 X-1 Y-1\nM2\n";
    let file = scratch_file("default_tools.ngc", program);
    let Some((ok, theirs, err)) = rs274_without_table(&file) else {
        return;
    };
    assert!(ok, "rs274 rejects it: {err}");
    let ours = oficina()
        .args(["gcode", "canon"])
        .arg(&file)
        .output()
        .unwrap();
    assert_same_calls(&theirs, &ours, "T1/T2/T3 without a tool table");
    // `check` (a millimetre machine) reads the same table without --tool-table.
    let out = oficina().arg("check").arg(&file).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn without_a_tool_table_tool_4_is_not_found_as_in_rs274() {
    let file = scratch_file("tool4.ngc", "G21\nT4 M6\nM2\n");
    let Some((ok, _, err)) = rs274_without_table(&file) else {
        return;
    };
    assert!(!ok && err.contains("Requested tool 4 not found"), "{err}");
    let out = oficina().arg("check").arg(&file).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains(":2:1: error: Requested tool 4 not found in the tool table")
            && stderr.contains("--tool-table"),
        "{stderr}"
    );
    // With a table, the table decides; in the grbl dialect there is none to consult.
    let tbl = scratch_file("tool4.tbl", "T4 P4 D6 Z10\n");
    let out = oficina()
        .arg("check")
        .arg(&file)
        .arg("--tool-table")
        .arg(&tbl)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = oficina()
        .args(["check", "--dialect", "grbl"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn linuxcncs_g76_example_stops_where_rs274_stops_without_a_tool_table() {
    let Some(file) = realworld("lcnc_g76.ngc") else {
        eprintln!("!!!!!!!! SKIPPED: realworld lcnc_g76.ngc not on this machine !!!!!!!!");
        return;
    };
    let Some((ok, _, err)) = rs274_without_table(&file) else {
        return;
    };
    // Tool 1 of the default table has a 1/16 inch radius: the o100 entry move is too short.
    let why = "Length of cutter compensation entry move is not greater than the tool radius";
    assert!(!ok && err.contains(why), "{err}");
    // rs274 stops there; `check` goes on, so its first error is the one to compare.
    let out = oficina().arg("check").arg(&file).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let first = stderr
        .lines()
        .find(|l| l.contains(": error"))
        .unwrap_or_default();
    assert!(
        first.ends_with(&format!("lcnc_g76.ngc:26:1: error: {why}")),
        "{stderr}"
    );
}

#[test]
fn linuxcncs_spline_example_reads_as_rs274_reads_it() {
    let Some(file) = realworld("lcnc_systems.ngc") else {
        eprintln!("!!!!!!!! SKIPPED: realworld lcnc_systems.ngc not on this machine !!!!!!!!");
        return;
    };
    let Some((ok, theirs, err)) = rs274_without_table(&file) else {
        return;
    };
    assert!(ok, "{err}");
    assert_eq!(theirs.matches("NURBS_FEED(3, ...)").count(), 548);
    let ours = oficina()
        .args(["gcode", "canon"])
        .arg(&file)
        .output()
        .unwrap();
    assert_same_calls(&theirs, &ours, "lcnc_systems.ngc");
    let out = oficina().arg("check").arg(&file).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("0 errors") || stdout.contains("0 errors"),
        "{stderr}{stdout}"
    );
}

fn grbl_cam_files() -> Vec<PathBuf> {
    let dir = repo().join("tests/data/grbl-cam");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "nc" || x == "gcode"))
        .collect();
    files.sort();
    files
}

#[test]
fn cam_programs_for_grbl_check_clean_with_notes_for_what_the_sender_handles() {
    let files = grbl_cam_files();
    assert!(files.len() >= 6, "{files:?}");
    for f in &files {
        let out = oficina()
            .args(["check", "--dialect", "grbl"])
            .arg(f)
            .output()
            .unwrap();
        let said = String::from_utf8_lossy(&out.stderr) + String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{}: {said}", f.display());
        assert!(
            said.contains(": 0 errors, 0 warnings"),
            "{}: {said}",
            f.display()
        );
    }
    // The Fusion 360 program's tape marks and M6 are the sender's: notes on their lines.
    let fusion = repo().join("tests/data/grbl-cam/fusion360-grbl.nc");
    let out = oficina()
        .args(["check", "--dialect", "grbl"])
        .arg(&fusion)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    for place in [":1:1: note:", ":12:4: note:", ":42:1: note:"] {
        assert!(stderr.contains(place), "{place} in {stderr}");
    }
}

#[test]
fn what_grbl_refuses_keeps_its_number_and_names_the_post_that_wrote_it() {
    for (program, col, code, hint) in [
        (
            "G21 G64 P0.01\nM2\n",
            5,
            20,
            "a LinuxCNC post; grbl has no path blending mode",
        ),
        (
            "G21\nG81 X1 Y1 Z-1 R1 F100\nM2\n",
            1,
            20,
            "grbl has no canned cycles",
        ),
        ("G21\nG43 H1\nM2\n", 5, 20, "H is a tool length offset"),
        ("G21\nG98\nM2\n", 1, 20, "canned-cycle retract mode"),
        ("G21\nO1000\nM2\n", 1, 20, "O is a program number"),
        ("G21\nG0 X1 (open (nested) tail)\nM2\n", 22, 2, ""),
    ] {
        let file = scratch_file("refused.nc", program);
        let out = oficina()
            .args(["check", "--dialect", "grbl"])
            .arg(&file)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{program}");
        let line = if program.starts_with("G21 G64") { 1 } else { 2 };
        let place = format!(":{line}:{col}: error[grbl:{code}]:");
        assert!(stderr.contains(&place), "{program}: {place} in {stderr}");
        assert!(stderr.contains(hint), "{program}: {hint} in {stderr}");
    }
}

/// `oficina emulate grbl` on a free TCP port, its machine clock `scale` times real time;
/// the child and its address.
fn grbl_emulator(scale: u32) -> (std::process::Child, String) {
    use std::io::{BufRead, BufReader};
    let mut child = oficina()
        .args(["emulate", "grbl", "--tcp", "127.0.0.1:0", "--baud", "0"])
        .args(["--time-scale", &scale.to_string()])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let uri = line
        .split_whitespace()
        .find(|w| w.starts_with("tcp://"))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    (child, uri)
}

/// A grbl-dialect program of the shared folder run to its end on the grbl emulator as a user
/// runs it (single tool: `--tool-change ignore`), from a copy (the journal is written beside).
fn runs_to_the_end_on_grbl(name: &str) {
    let Some(file) = realworld(name) else {
        eprintln!("note: {name} is not on this machine; skipped");
        return;
    };
    let copy = scratch_file(name, std::fs::read(&file).unwrap());
    let (mut emu, uri) = grbl_emulator(200);
    let out = oficina()
        .arg("run")
        .arg(&copy)
        .args(["--machine", &uri, "--tool-change", "ignore"])
        .output()
        .unwrap();
    let _ = emu.kill();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && stdout.contains("done:"),
        "{name} did not run to its end:\n{stdout}\n{stderr}"
    );
}

#[test]
fn grbl_programs_of_senders_run_to_the_end_on_the_grbl_emulator() {
    for name in [
        "bcnc_sample.gcode",
        "cncjs_jsdc.gcode",
        "ugs_ShapeOko_Calibration_Pattern_01b.ngc",
        "ugs_arc_rword_test.gcode",
    ] {
        runs_to_the_end_on_grbl(name);
    }
}

#[test]
fn camotics_botomata_runs_to_the_end_on_the_grbl_emulator() {
    runs_to_the_end_on_grbl("camotics_botomata_bottom.nc");
}
