//! Planned motion against rs274's path on programs in the styles of LinuxCNC's
//! trajectory-planner stress programs (`tests/data/lcnc-style/`, written here): arcs and
//! helices in every plane, tiny segments, G64 P / G61 / G61.1 switches, inch programs,
//! offsets and rotation, inverse time, splines. rs274 gives the path where it is installed.
//!
//! `scripts/lcnc-trajectory [SRC]` runs the ignored test below over LinuxCNC's own programs.

mod trajectory;

use oficina_motion::Profile;
use std::path::{Path, PathBuf};
use trajectory::Outcome;

fn profile() -> Profile {
    Profile::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcnc-tp-xyz.toml"))
        .unwrap()
}

fn programs(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            // Linked directories (LinuxCNC's auto-test/) repeat programs already listed.
            if e.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("ngc")) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn rs274_installed() -> bool {
    std::process::Command::new("rs274")
        .arg("-h")
        .stdin(std::process::Stdio::null())
        .output()
        .is_ok()
}

/// Runs every program under `dir`, prints a verdict per program and the totals; returns
/// (checked clean, accepted by rs274 (or by Oficina without rs274), failures).
fn survey(dir: &Path) -> (usize, usize, Vec<String>) {
    let p = profile();
    let work = tempfile_dir();
    let oracle = rs274_installed();
    if !oracle {
        eprintln!("rs274 not installed: the path is Oficina's own canon");
    }
    let (mut clean, mut accepted, mut failures) = (0, 0, Vec::new());
    for prog in programs(dir) {
        let name = prog
            .strip_prefix(dir)
            .unwrap_or(&prog)
            .display()
            .to_string();
        let verdict = match trajectory::run(&prog, &p, &work, oracle) {
            Outcome::Checked(v) => {
                accepted += 1;
                if v.violations.is_empty() {
                    clean += 1;
                    format!(
                        "ok      path ≤ {:.4} mm, speed ≤ {:.1} % of feed, accel ≤ {:.1} % ({} samples)",
                        v.worst_path,
                        v.worst_speed_ratio * 100.0,
                        v.worst_accel_ratio * 100.0,
                        v.samples
                    )
                } else {
                    failures.push(format!("{name}: {}", v.violations[0]));
                    format!("FAIL    {}", v.violations.join("\n          "))
                }
            }
            Outcome::Refused(why) => {
                accepted += 1;
                failures.push(format!("{name}: refused: {why}"));
                format!("REFUSED {why}")
            }
            Outcome::BothRefused(theirs, ours) => {
                // The same reason: rs274's message opens Oficina's (after its place).
                let reason: String = theirs.chars().take(20).collect();
                if !ours.contains(&reason) {
                    failures.push(format!(
                        "{name}: rs274 refuses «{theirs}», oficina «{ours}»"
                    ));
                }
                format!("both refuse: rs274 «{theirs}», oficina «{}»", ours.trim())
            }
            Outcome::OnlyRs274Refused(theirs) => {
                failures.push(format!(
                    "{name}: rs274 refuses «{theirs}», oficina plans it"
                ));
                format!("rs274 refuses «{theirs}», oficina does not")
            }
        };
        println!("{name:<50} {verdict}");
    }
    let _ = std::fs::remove_dir_all(&work);
    println!(
        "{clean} of {accepted} accepted programs planned on rs274's path without violations ({:.1} %)",
        100.0 * clean as f64 / accepted.max(1) as f64
    );
    (clean, accepted, failures)
}

fn tempfile_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("oficina-lcnc-tp-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn own_programs_in_the_stress_styles_stay_on_rs274s_path() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcnc-style");
    let (clean, accepted, failures) = survey(&dir);
    assert!(accepted >= 10, "only {accepted} programs ran");
    assert_eq!(clean, accepted, "{}", failures.join("\n"));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// LinuxCNC's stress programs: `LCNC_TRAJECTORY_SRC=DIR` (scripts/lcnc-trajectory).
#[test]
#[ignore = "needs LinuxCNC's nc_files: scripts/lcnc-trajectory"]
fn linuxcnc_stress_programs() {
    let Ok(dir) = std::env::var("LCNC_TRAJECTORY_SRC") else {
        panic!("set LCNC_TRAJECTORY_SRC to tests/trajectory-planner/circular-arcs/nc_files");
    };
    let (clean, accepted, failures) = survey(Path::new(&dir));
    for f in &failures {
        println!("failure: {f}");
    }
    let share = clean as f64 / accepted.max(1) as f64;
    let want: f64 = std::env::var("LCNC_TRAJECTORY_MIN")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.98);
    assert!(share >= want, "{clean}/{accepted} below {want}");
    // What rs274 refuses, Oficina refuses for the same reason.
    let refusals: Vec<_> = failures
        .iter()
        .filter(|f| f.contains("rs274 refuses"))
        .collect();
    assert!(refusals.is_empty(), "{refusals:?}");
}

/// The checker can fail: motion planned on a machine with three times the acceleration
/// breaks the real machine's acceleration limit, and motion planned with a fifty times looser
/// junction deviation takes corners faster than a blend within the tolerance allows.
#[test]
fn the_checker_rejects_a_plan_made_for_looser_limits() {
    let real = profile();
    let mut fast = real.clone();
    for j in fast.joints.iter_mut().flatten() {
        j.acceleration *= 3.0;
    }
    let mut sloppy = real.clone();
    sloppy.junction_deviation *= 50.0;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcnc-style");
    for name in ["reversals_and_rapids.ngc", "path_mode_switches.ngc"] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let ops = trajectory::interpret(&text).unwrap();
        let elems = trajectory::rs274_path::read(&trajectory::own_text(&ops), real.start);
        let check = |planned_on: &Profile| {
            let segs = trajectory::planned(&ops, planned_on).unwrap();
            trajectory::checker::check(&elems, &segs, &real, real.path_tolerance).violations
        };
        assert!(check(&real).is_empty(), "{name}: {:?}", check(&real));
        let v = check(&fast);
        assert!(v.iter().any(|v| v.contains("accelerates")), "{name}: {v:?}");
        let v = check(&sloppy);
        assert!(v.iter().any(|v| v.contains("corner")), "{name}: {v:?}");
    }
}
