//! The scripts a new user runs first: the demo talks while it builds, and the README's test
//! command installs (or names) what the tests need, with the same list CI uses.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(p: &str) -> String {
    std::fs::read_to_string(root().join(p)).unwrap_or_else(|e| panic!("{p}: {e}"))
}

#[test]
fn the_demo_announces_its_first_build_and_shows_cargos_progress() {
    let dir = std::env::temp_dir().join(format!("oficina-demo-{}", std::process::id()));
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    // A stand-in cargo: records its arguments, prints what a build prints, runs nothing.
    let log = dir.join("cargo.log");
    let fake = bin.join("cargo");
    std::fs::write(
        &fake,
        format!(
            "#!/bin/sh\necho \"$@\" >> {}\n[ \"$1\" = build ] && echo '   Compiling oficina-cli v0.1.0' >&2\nexit 0\n",
            log.display()
        ),
    )
    .unwrap();
    Command::new("chmod").arg("+x").arg(&fake).status().unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap());
    let out = Command::new("bash")
        .arg(root().join("scripts/demo"))
        .env("PATH", path)
        .env_remove("CARGO")
        .env("OFICINA_DEMO_DIR", dir.join("out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}{stderr}");
    let first = stdout.lines().next().unwrap_or("");
    assert!(
        first.contains("building") && first.contains("minutes"),
        "{stdout}"
    );
    assert!(
        stderr.contains("Compiling"),
        "cargo's progress was hidden: {stderr}"
    );
    let calls = std::fs::read_to_string(&log).unwrap();
    let build = calls.lines().find(|l| l.starts_with("build")).unwrap();
    assert!(
        !build.split(' ').any(|a| a == "-q" || a == "--quiet"),
        "{build}"
    );
}

#[test]
fn the_test_command_installs_or_names_what_the_tests_need() {
    let test_all = read("scripts/test-all");
    let deps = test_all
        .find("scripts/install-deps")
        .expect("test-all installs deps");
    let cargo_test = test_all.find("cargo test").unwrap();
    assert!(deps < cargo_test, "deps must come before the tests");
    // CI runs the same command and keeps no install list of its own.
    let ci = read(".ci/run");
    assert!(
        ci.contains("scripts/test-all") && !ci.contains("apt-get"),
        "{ci}"
    );
    // Without rs274 and without the right to install, it says what to install.
    let out = Command::new("bash")
        .arg(root().join("scripts/install-deps"))
        .env("RS274", "/nonexistent/rs274")
        .env("OFICINA_NO_INSTALL", "1")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("linuxcnc-uspace") && err.contains("rs274") && err.contains("apt-get install"),
        "{err}"
    );
}

#[test]
fn the_readme_says_which_command_ci_runs() {
    let readme = read("README.md");
    assert!(
        readme.contains(".ci/run"),
        "README does not name CI's command"
    );
    assert!(
        readme.contains("scripts/install-deps"),
        "README does not name the installer"
    );
}
