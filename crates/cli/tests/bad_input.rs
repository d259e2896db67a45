//! Issue 8, the G-code side: what a user feeds `check`, `gcode canon`, `run` and `plan` is
//! read by one rule, and every error fits a terminal.

mod common;

use common::root;

use oficina_testkit::scratch_file;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn dir() -> PathBuf {
    oficina_testkit::scratch_dir("bad-input")
}

fn oficina(args: &[&str], file: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(args)
        .arg(file)
        .output()
        .unwrap()
}

/// The four commands that read a program, each as a user would run it.
const COMMANDS: [&[&str]; 4] = [
    &["check"],
    &["gcode", "canon"],
    &["run", "--instant"],
    &["plan"],
];

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Each command with what it printed on stderr for `f`, which every one must refuse.
fn refusals(f: &Path) -> Vec<(&'static [&'static str], String)> {
    COMMANDS
        .iter()
        .map(|&cmd| {
            let o = oficina(cmd, f);
            assert!(!o.status.success(), "{cmd:?} accepted it");
            (cmd, stderr(&o))
        })
        .collect()
}

#[test]
fn a_latin1_byte_in_a_comment_is_accepted_by_every_command() {
    let f = scratch_file(
        "latin1.nc",
        b"G21 G90 F600\n(temp 20\xb0C)\n(MSG, 20\xb0C)\nG1 X1 Y1\nM2\n",
    );
    for cmd in COMMANDS {
        let o = oficina(cmd, &f);
        assert!(o.status.success(), "{cmd:?}: {}", stderr(&o));
    }
    // Kept as the Latin-1 character it is, by the same rule in every command.
    let canon = oficina(&["gcode", "canon"], &f);
    assert!(String::from_utf8_lossy(&canon.stdout).contains("MESSAGE(\" 20°C\")"));
    let run = oficina(&["run", "--instant"], &f);
    assert!(stderr(&run).contains("20°C"), "{}", stderr(&run));
}

#[test]
fn a_byte_outside_utf8_elsewhere_is_an_error_at_its_line_and_column_everywhere() {
    let f = scratch_file("latin1-code.nc", b"G21 G90 F600\nG1 X1\xb0\nM2\n");
    for (cmd, e) in refusals(&f) {
        assert!(
            e.contains("latin1-code.nc:2:6:") && e.contains("0xB0"),
            "{cmd:?}: {e}"
        );
    }
}

#[test]
fn a_byte_order_mark_is_named_as_such_everywhere() {
    let f = scratch_file("bom.nc", b"\xef\xbb\xbfG21 G90 F600\nG1 X1\nM2\n");
    for (cmd, e) in refusals(&f) {
        assert!(
            e.contains("bom.nc:1:1:") && e.contains("byte-order mark"),
            "{cmd:?}: {e}"
        );
        // The invisible mark is shown, not printed raw.
        assert!(!e.contains('\u{feff}'), "{cmd:?}: {e:?}");
    }
}

#[test]
fn a_five_megabyte_line_is_not_echoed_by_any_command() {
    let mut text = b"G21 G90 F600\nG1 X".to_vec();
    text.extend(std::iter::repeat_n(b'1', 5_000_000));
    text.extend_from_slice(b"\nM2\n");
    let f = scratch_file("long.nc", &text);
    for (cmd, e) in refusals(&f) {
        assert!(e.len() < 2_000, "{cmd:?} printed {} bytes", e.len());
        assert!(e.contains("long.nc:2:1:"), "{cmd:?}: {e}");
        // The limit it says can be raised is raised by a real option.
        assert!(e.contains("--max-line-kb"), "{cmd:?}: {e}");
    }
    let o = oficina(&["check", "--max-line-kb", "8000"], &f);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A file of 400 lines of binary noise: escape bytes and all.
fn noise() -> Vec<u8> {
    let mut x: u32 = 12345;
    let mut v = Vec::new();
    for _ in 0..400 {
        for _ in 0..60 {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
            let b = (x >> 16) as u8;
            v.push(if b == b'\n' { 0x1b } else { b });
        }
        v.extend_from_slice(b"\x1b[2J\x07\n");
    }
    v
}

#[test]
fn check_of_a_binary_file_stops_printing_after_the_error_limit_and_escapes_control_bytes() {
    let f = scratch_file("noise.bin", noise());
    let o = oficina(&["check"], &f);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        !o.stderr.iter().any(|&b| b < 0x20 && b != b'\n'),
        "raw control bytes reached the terminal"
    );
    let shown = e.lines().filter(|l| l.contains(": error")).count();
    assert_eq!(shown, 50, "{e}");
    assert!(
        e.contains("more not shown") && e.contains("--max-errors"),
        "{e}"
    );
    let o = oficina(&["check", "--max-errors", "3"], &f);
    assert_eq!(
        stderr(&o).lines().filter(|l| l.contains(": error")).count(),
        3
    );
    // The summary still counts every error.
    let out = String::from_utf8_lossy(&o.stdout);
    let errors: usize = out
        .split(": ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(errors >= 400, "{out}");
}

#[test]
fn no_message_says_error_twice_or_repeats_the_os_error() {
    let missing = dir().join("no-such-file.nc");
    for cmd in COMMANDS {
        let o = oficina(cmd, &missing);
        let e = stderr(&o);
        assert!(!o.status.success());
        assert_eq!(
            e.matches("No such file or directory").count(),
            1,
            "{cmd:?}: {e}"
        );
    }
    let f = scratch_file("badword.nc", b"G21\nG1 X1 Q\nM2\n");
    let table = scratch_file("bad.tbl", b"T1 Znan\n");
    let with_table = ["check", "--tool-table", table.to_str().unwrap()];
    for cmd in COMMANDS.iter().copied().chain([&with_table[..]]) {
        let o = oficina(cmd, &f);
        assert!(!o.status.success(), "{cmd:?}");
        for line in stderr(&o).lines() {
            assert!(
                line.matches("error").count() <= 1,
                "{cmd:?} says error twice: {line}"
            );
        }
    }
}

fn sample(name: &str) -> PathBuf {
    root().join("samples/motion").join(name)
}

#[test]
fn a_sample_that_needs_a_machine_names_it_and_every_command_uses_it() {
    let f = sample("hotwire-pinwheel.nc");
    for cmd in [&["check"][..], &["run", "--instant"], &["plan"]] {
        let o = oficina(cmd, &f);
        let e = stderr(&o);
        assert!(o.status.success(), "{cmd:?}: {e}");
        assert!(e.contains("machine: hotwire-xy"), "{cmd:?}: {e}");
    }
    // --machine still decides.
    let o = oficina(&["plan", "--machine", "grbl-router"], &f);
    assert!(!o.status.success());
    assert!(!stderr(&o).contains("machine: hotwire-xy"));
}

#[test]
fn every_bundled_sample_runs_without_naming_a_machine() {
    for entry in std::fs::read_dir(root().join("samples/motion")).unwrap() {
        let f = entry.unwrap().path();
        let o = oficina(&["run", "--instant"], &f);
        assert!(o.status.success(), "{}: {}", f.display(), stderr(&o));
    }
}

/// A job with a tool change prompt and a pause early on, motion after it.
fn job_with_a_pause() -> PathBuf {
    let mut text = String::from("G21 G90 F600\nG1 X5\nT2 M6 (MSG, put tool 2 in)\nM0\nG1 X10\n");
    for i in 0..10 {
        text.push_str(&format!("G1 Y{}\n", i + 1));
    }
    text.push_str("M2\n");
    scratch_file("toolchange.nc", text.as_bytes())
}

#[test]
fn resuming_after_a_pause_skips_the_pause_and_its_prompt() {
    let f = job_with_a_pause();
    let o = oficina(&["run", "--instant"], &f);
    let e = stderr(&o);
    assert!(e.contains("put tool 2 in") && e.contains("pause"), "{e}");
    let o = oficina(&["run", "--instant", "--from-line", "8"], &f);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(
        !e.contains("put tool 2 in") && !e.contains("pause"),
        "announced before the resume line: {e}"
    );
}

#[test]
fn resuming_past_the_last_line_is_an_error() {
    let f = job_with_a_pause(); // 16 lines
    let o = oficina(&["run", "--instant", "--from-line", "99"], &f);
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("--from-line 99") && e.contains("16 lines"),
        "{e}"
    );
    let o = oficina(&["run", "--instant", "--from-line", "16"], &f);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `h:mm:ss.s` in seconds.
fn seconds(hms: &str) -> f64 {
    let p: Vec<f64> = hms.split(':').map(|x| x.parse().unwrap()).collect();
    p[0] * 3600.0 + p[1] * 60.0 + p[2]
}

fn figure(out: &str, label: &str) -> Option<f64> {
    let line = out.lines().find(|l| l.trim_start().starts_with(label))?;
    let rest = line.trim_start()[label.len()..].trim_start();
    let hms = rest.split_whitespace().next()?;
    hms.contains(':').then(|| seconds(hms))
}

#[test]
fn the_feed_rate_time_is_a_lower_bound_of_the_planners_on_every_machine() {
    let machines = [
        "grbl-router",
        "hotwire-xy",
        "polar-plotter",
        "polargraph-wall",
        "embroidery-xy",
    ];
    let mut compared = 0;
    for entry in std::fs::read_dir(root().join("samples/motion")).unwrap() {
        let f = entry.unwrap().path();
        for m in machines {
            let o = oficina(&["check", "--machine", m], &f);
            let out = String::from_utf8_lossy(&o.stdout);
            let (Some(bound), Some(planned)) = (
                figure(&out, "feed-rate time"),
                figure(&out, "time estimate"),
            ) else {
                continue;
            };
            compared += 1;
            // Both are printed to 0.1 s.
            assert!(
                bound <= planned + 0.1,
                "{} on {m}: feed-rate time {bound} s > planner {planned} s",
                f.display()
            );
        }
    }
    assert!(
        compared >= 5,
        "only {compared} sample/machine pairs planned"
    );
}

#[test]
fn canon_numbered_does_not_claim_rs274s_numbers() {
    let o = common::oficina(&["gcode", "canon", "--help"]);
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(help.contains("--numbered"), "{help}");
    assert!(!help.contains("exactly as"), "{help}");
    assert!(
        help.contains("compare the calls, not the numbers"),
        "{help}"
    );
}

#[test]
fn plan_refuses_an_output_larger_than_the_limit_before_writing_it() {
    // 100 s of motion at 1 ms: 100,000 rows, about 13 MB.
    let f = scratch_file("slow.nc", b"G21 G90 G1 X100 F60\nM2\n");
    let trace = dir().join("slow.csv");
    let _ = std::fs::remove_file(&trace);
    let o = oficina(
        &[
            "plan",
            "--trace",
            trace.to_str().unwrap(),
            "--max-output-mb",
            "1",
        ],
        &f,
    );
    let e = stderr(&o);
    assert!(!o.status.success());
    assert!(
        e.contains("--max-output-mb 1") && e.contains("rows") && e.contains("MB"),
        "{e}"
    );
    assert!(!trace.exists(), "the refused trace was created");
    let steps = dir().join("slow-steps.csv");
    let o = oficina(
        &[
            "plan",
            "--steps",
            steps.to_str().unwrap(),
            "--max-output-mb",
            "0",
        ],
        &f,
    );
    assert!(stderr(&o).contains("motor steps"), "{}", stderr(&o));
    let o = oficina(&["plan", "--trace", trace.to_str().unwrap()], &f);
    assert!(o.status.success(), "{}", stderr(&o));
    let written = std::fs::metadata(&trace).unwrap().len();
    assert!(written > 1_000_000 && written < 20_000_000, "{written}");
}

#[test]
fn trace_columns_have_unique_names() {
    let f = sample("router-square.nc");
    let trace = dir().join("square.csv");
    let o = oficina(&["plan", "--trace", trace.to_str().unwrap()], &f);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&trace).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let mut unique = header.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), header.len(), "{header:?}");
    assert!(header.contains(&"x") && header.contains(&"joint_x"));
}
