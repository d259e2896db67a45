//! `oficina level probe` on an emulated tilted block (work zero set from the console),
//! `oficina level apply` into a file, `oficina run --level` and `--level-probe` on the same
//! board, and a malformed map refused naming the file.

mod common;

use oficina_grbl::{line_words, HeightMap};
use std::io::Write;
use std::process::{Command, Stdio};

const PROGRAM: &str = "G21 G90\nG0 Z5\nG0 X0 Y0\nG0 Z1\nG1 Z-0.1 F1500\nG1 X30 Y0 F3000\nG2 X30 Y20 I0 J10\nG1 X0 Y0\nG0 Z5\nM2\n";

/// Two tools over the same area, each cutting 0.1 mm deep.
const TWO_TOOLS: &str = "G21 G90\nT1 M6\nG0 Z5\nG0 X0 Y0\nG1 Z-0.1 F1500\nG1 X30 F3000\nG0 Z5\nT2 M6\nG0 X0 Y20\nG1 Z-0.1 F1500\nG1 X30 F3000\nG0 Z5\nM2\n";

/// The block's top in work coordinates: machine top −29.8 + tilt, work zero at machine
/// (−50, −40, −30).
fn surface(x: f64, y: f64) -> f64 {
    let (mx, my) = (x - 50.0, y - 40.0);
    -29.8 + 0.006 * mx - 0.009 * my + 30.0
}

#[test]
fn probe_apply_and_run_levelled_on_the_emulator() {
    let emu = common::emulate_fast(
        3000,
        &[
            "--baud",
            "0",
            "--for-seconds",
            "120",
            "--probe-block",
            "-80,-70,20,20,-29.8",
            "--probe-tilt",
            "0.006,-0.009",
        ],
    );
    let (addr, tcp) = (emu.uri.clone(), emu.host_port());
    let mut console = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["console", "--tcp", tcp])
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    console
        .stdin
        .take()
        .unwrap()
        .write_all(b"G10 L2 P1 X-50 Y-40 Z-30\n")
        .unwrap();
    assert!(console.wait().unwrap().success());

    let file = common::program("level", PROGRAM);
    let dir = file.parent().unwrap().to_path_buf();
    let map_path = dir.join("level.map.json");
    let out = common::oficina(&[
        "level",
        "probe",
        file.to_str().unwrap(),
        "--machine",
        &addr,
        "--grid",
        "4x3",
        "--probe-feed",
        "600",
        "-o",
        map_path.to_str().unwrap(),
    ]);
    let (stdout, stderr) = common::text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("probe 12/12"), "{stderr}");
    assert!(stdout.contains("height map: 4 × 3 points"), "{stdout}");
    let map = HeightMap::from_json(&std::fs::read_to_string(&map_path).unwrap()).unwrap();
    assert_eq!(map.wcs.as_deref(), Some("G54"));
    for j in 0..map.ny {
        for i in 0..map.nx {
            let (x, y) = (
                map.origin[0] + i as f64 * map.spacing[0],
                map.origin[1] + j as f64 * map.spacing[1],
            );
            assert!(
                (map.at_node(i, j) - surface(x, y)).abs() < 2e-3,
                "({i}, {j})"
            );
        }
    }

    // A file for any sender: every cut point 0.1 mm below the block's top.
    let levelled = dir.join("level.levelled.nc");
    let out = common::oficina(&[
        "level",
        "apply",
        file.to_str().unwrap(),
        "--map",
        map_path.to_str().unwrap(),
        "-o",
        levelled.to_str().unwrap(),
    ]);
    let (stdout, stderr) = common::text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("levelled:"), "{stdout}");
    let text = std::fs::read_to_string(&levelled).unwrap();
    let mut at = [f64::NAN; 3];
    let mut cuts = 0;
    for line in text.lines().filter(|l| !l.starts_with('(')) {
        for (letter, v) in line_words(line).unwrap() {
            if let Some(a) = "XYZ".find(letter) {
                at[a] = v;
            }
        }
        if at[2] < 0.5 + surface(at[0], at[1]) {
            cuts += 1;
            let depth = at[2] - surface(at[0], at[1]);
            assert!((depth + 0.1).abs() < 3e-3, "{line}: {depth}");
        }
    }
    assert!(cuts > 60, "{cuts} cut points");

    // The same program run levelled by the map, on the same board.
    let out = common::oficina(&[
        "run",
        file.to_str().unwrap(),
        "--machine",
        &addr,
        "--level",
        map_path.to_str().unwrap(),
    ]);
    let (stdout, stderr) = common::text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");

    // Probe and run in one go, keeping the map.
    let again = dir.join("level.again.map.json");
    let out = common::oficina(&[
        "run",
        file.to_str().unwrap(),
        "--machine",
        &addr,
        "--level-probe",
        "3x3",
        "--level-save",
        again.to_str().unwrap(),
        "--probe-feed",
        "600",
    ]);
    let (stdout, stderr) = common::text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("probe 9/9"), "{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");
    let kept = HeightMap::from_json(&std::fs::read_to_string(&again).unwrap()).unwrap();
    assert_eq!((kept.nx, kept.ny), (3, 3));

    // A two-tool program levelled by the same map: M6 goes to the sender's tool-change
    // policy as in a plain job. Under remeasure, with no terminal to resume from, the run
    // stops at the first change with its prompt (not refused by the transform)…
    let two = common::program("two-tools", TWO_TOOLS);
    let run_two = |policy: &[&str]| {
        let mut args = vec![
            "run",
            two.to_str().unwrap(),
            "--machine",
            &addr,
            "--level",
            map_path.to_str().unwrap(),
        ];
        args.extend(policy);
        common::oficina(&args)
    };
    let out = run_two(&["--tool-change", "remeasure", "--tool-setter", "10,10,-5"]);
    let (stdout, stderr) = common::text(&out);
    assert_eq!(out.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("TOOL CHANGE: change to tool T1 (M6 at line 2), then resume: the sender measures it on the tool setter"),
        "{stderr}"
    );
    assert!(stderr.contains("stopping here"), "{stderr}");
    assert!(stdout.contains("--resume"), "{stdout}");
    // …under ignore it runs through, the dropped change noted by the levelling and the sender…
    let out = run_two(&["--tool-change", "ignore"]);
    let (stdout, stderr) = common::text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");
    assert!(
        format!("{stdout}{stderr}").contains("line 8: M6 T2 dropped (--tool-change ignore): the whole job is cut with the tool the map was probed with"),
        "{stdout}\n{stderr}"
    );
    // …and the firmware's own change is refused before anything moves, a map to probe
    // first included.
    for map in [
        ["--level", map_path.to_str().unwrap()],
        ["--level-probe", "2x2"],
    ] {
        let mut args = vec!["run", two.to_str().unwrap(), "--machine", &addr];
        args.extend(map);
        args.extend(["--tool-change", "firmware"]);
        let out = common::oficina(&args);
        let (_, stderr) = common::text(&out);
        assert!(!out.status.success());
        assert!(
            stderr
                .contains("line 2: M6: with --tool-change firmware the firmware changes the tool"),
            "{stderr}"
        );
        assert!(!stderr.contains("probe 1/"), "{stderr}");
    }

    // A malformed map is refused naming the file, before anything moves.
    let bad = dir.join("bad.map.json");
    std::fs::write(&bad, "{\"format\": \"oficina-height-map\"").unwrap();
    let out = common::oficina(&[
        "level",
        "apply",
        file.to_str().unwrap(),
        "--map",
        bad.to_str().unwrap(),
        "-o",
        dir.join("never.nc").to_str().unwrap(),
    ]);
    let (_, stderr) = common::text(&out);
    assert!(!out.status.success());
    assert!(
        stderr.contains("bad.map.json: height map: not a map file"),
        "{stderr}"
    );
}
