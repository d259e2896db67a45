//! `oficina plan` and `oficina run` take `--tool-table` as `check` and `gcode canon` do: a
//! G43 tool length offset moves the planned motion and the virtual machine by the tool's
//! length (grbl-router: travel Z −100…0 mm, stored G54 Z −40 mm).

mod common;

use common::oficina;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("oficina-tool-table-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Lowest and highest Z of a `--trace` CSV.
fn z_range(trace: &Path) -> (f64, f64) {
    let text = std::fs::read_to_string(trace).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let z = header.iter().position(|&h| h == "z").unwrap();
    lines
        .map(|l| l.split(',').nth(z).unwrap().parse::<f64>().unwrap())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// Tool 1 is 10 mm long (tables given to plan and run are in mm).
const TABLE: &str = "T1 P1 D6 Z10 ;10 mm end mill\n";

#[test]
fn plan_moves_the_motion_by_the_tool_length() {
    let dir = scratch("plan");
    let table = dir.join("tools.tbl");
    let program = dir.join("p.ngc");
    std::fs::write(&table, TABLE).unwrap();
    std::fs::write(
        &program,
        "G21 G90\nT1 M6\nG43 H1\nG0 X10 Y10 Z5\nG1 Z-1 F300\nG0 Z5\nM2\n",
    )
    .unwrap();
    let (without, with) = (dir.join("a.csv"), dir.join("b.csv"));
    let p = program.to_str().unwrap();
    let out = oficina(&["plan", p, "--trace", without.to_str().unwrap()]);
    oficina_testkit::assert_success(&out);
    let out = oficina(&[
        "plan",
        p,
        "--trace",
        with.to_str().unwrap(),
        "--tool-table",
        table.to_str().unwrap(),
    ]);
    oficina_testkit::assert_success(&out);
    // Program Z −1 is machine Z −41 (G54 Z −40) with no table, −31 with the 10 mm tool.
    let (lo_a, _) = z_range(&without);
    let (lo_b, _) = z_range(&with);
    assert!(
        (lo_a + 41.0).abs() < 1e-3,
        "without a table: lowest Z {lo_a}"
    );
    assert!(
        (lo_b + 31.0).abs() < 1e-3,
        "with the table: lowest Z {lo_b}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_applies_the_tool_length_on_the_virtual_machine() {
    let dir = scratch("run");
    let table = dir.join("tools.tbl");
    let program = dir.join("q.ngc");
    std::fs::write(&table, TABLE).unwrap();
    // Program Z 35 is machine Z −5 bare, +5 with the tool: above the top of travel.
    std::fs::write(
        &program,
        "G21 G90\nT1 M6\nG43 H1\nG0 X10 Y10 Z35\nG1 Z30 F300\nM2\n",
    )
    .unwrap();
    let p = program.to_str().unwrap();
    let out = oficina(&["run", p, "--instant"]);
    oficina_testkit::assert_success(&out);
    let t = table.to_str().unwrap();
    let out = oficina(&["run", p, "--instant", "--tool-table", t]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("line 4") && err.contains("Z = 5.0000 mm") && err.contains("travel limits"),
        "{err}"
    );
    // Real firmware has no tool table: refused before anything is sent.
    let out = oficina(&[
        "run",
        p,
        "--instant",
        "--tool-table",
        t,
        "--machine",
        "grbl:/dev/null",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("--tool-table is for the virtual machine"),
        "{err}"
    );
    // A table that cannot be read names itself.
    let missing = dir.join("missing.tbl");
    let out = oficina(&["plan", p, "--tool-table", missing.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("missing.tbl"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// grbl-router with a `tool_table = "…"` line, written to `dir/router.toml`.
fn profile_naming(dir: &Path, table: &str) -> PathBuf {
    let router = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../profiles/grbl-router.toml"
    ))
    .unwrap();
    let path = dir.join("router.toml");
    std::fs::write(&path, format!("tool_table = \"{table}\"\n{router}")).unwrap();
    path
}

/// `oficina ARGS` run from the filesystem root, so a table found relative to the working
/// folder would be missed.
fn oficina_elsewhere(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(args)
        .current_dir("/")
        .output()
        .unwrap()
}

#[test]
fn a_profile_names_its_tool_table_and_the_option_overrides_it() {
    let dir = scratch("profile");
    std::fs::create_dir_all(dir.join("tables")).unwrap();
    std::fs::write(dir.join("tables/mill.tbl"), TABLE).unwrap();
    let longer = dir.join("longer.tbl");
    std::fs::write(&longer, "T1 P1 D6 Z20\n").unwrap();
    let machine = profile_naming(&dir, "tables/mill.tbl");
    let m = machine.to_str().unwrap();
    let program = dir.join("p.ngc");
    std::fs::write(
        &program,
        "G21 G90\nT1 M6\nG43 H1\nG0 X10 Y10 Z5\nG1 Z-1 F300\nG0 Z5\nM2\n",
    )
    .unwrap();
    let p = program.to_str().unwrap();
    let lowest_z = |extra: &[&str]| {
        let trace = dir.join("t.csv");
        let mut args = vec![
            "plan",
            p,
            "--machine",
            m,
            "--trace",
            trace.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = oficina_elsewhere(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        z_range(&trace).0
    };
    // The profile's 10 mm tool: program Z −1 is machine Z −31 (G54 Z −40).
    let z = lowest_z(&[]);
    assert!((z + 31.0).abs() < 1e-3, "profile's table: lowest Z {z}");
    // --tool-table wins: the 20 mm tool puts it at −21.
    let z = lowest_z(&["--tool-table", longer.to_str().unwrap()]);
    assert!((z + 21.0).abs() < 1e-3, "--tool-table: lowest Z {z}");

    // check reads it too: the offset lifts the lowest point the summary reports.
    let check = |extra: &[&str]| {
        let mut args = vec!["check", p, "--machine", m];
        args.extend_from_slice(extra);
        let out = oficina_elsewhere(&args);
        oficina_testkit::assert_success(&out);
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let with_profile = check(&[]);
    let with_option = check(&["--tool-table", longer.to_str().unwrap()]);
    assert_ne!(with_profile, with_option, "{with_profile}");

    // run on the virtual machine: Z 35 lies above travel only with the profile's tool.
    let high = dir.join("q.ngc");
    std::fs::write(
        &high,
        "G21 G90\nT1 M6\nG43 H1\nG0 X10 Y10 Z35\nG1 Z30 F300\nM2\n",
    )
    .unwrap();
    let out = oficina_elsewhere(&["run", high.to_str().unwrap(), "--instant", "--machine", m]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("line 4") && err.contains("travel limits"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_or_bad_profile_tool_table_names_the_profile_and_the_line() {
    let dir = scratch("profile-bad");
    let program = dir.join("p.ngc");
    std::fs::write(&program, "G21 G90\nG0 X10 Y10 Z5\nM2\n").unwrap();
    let p = program.to_str().unwrap();
    let machine = profile_naming(&dir, "nope.tbl");
    let m = machine.to_str().unwrap();
    for command in [
        vec!["plan", p, "--machine", m],
        vec!["check", p, "--machine", m],
        vec!["run", p, "--instant", "--machine", m],
    ] {
        let out = oficina_elsewhere(&command);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains("nope.tbl") && err.contains("router.toml"),
            "{}: {err}",
            command[0]
        );
    }
    // A table the option names instead is used, and the profile's is not read.
    let good = dir.join("good.tbl");
    std::fs::write(&good, TABLE).unwrap();
    let out = oficina_elsewhere(&[
        "plan",
        p,
        "--machine",
        m,
        "--tool-table",
        good.to_str().unwrap(),
    ]);
    oficina_testkit::assert_success(&out);
    // A bad line: the table's path, line and column, and the profile.
    std::fs::write(dir.join("bad.tbl"), "T1 P1 D6 Z10\nT2 P2 Dx Z5\n").unwrap();
    let machine = profile_naming(&dir, "bad.tbl");
    let out = oficina_elsewhere(&["plan", p, "--machine", machine.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("bad.tbl:2:7") && err.contains("router.toml"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
