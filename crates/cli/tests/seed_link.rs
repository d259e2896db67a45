//! Seed 000 from the command line: a CADTEC `.pub` to `.bor`, the `.bor` read back to the same
//! program, and the program sent over a pty to `oficina emulate seed`, which stores it under
//! its number and sews as many stitches as the sheet counts.

mod common;

use common::{oficina, text};
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

const PUB: &str = "$ EMPRESA ITAUTEC INFORMATICA\n$ TIPOARQ ARQUIVO PUBLICO\n\
P 1 2 3 1 0 5\n0.0 0.0 30.0 0.0 30.0 20.0 0.0 20.0 0.0 0.0\n\
A 1 4 1 1 0 15.0 10.0 8.0 0.0 180.0\nP 1 1 1 1 23 2\n-80.0 0.0 80.0 0.0\n";

#[test]
fn pub_to_bor_back_and_over_the_wire() {
    let dir = oficina_testkit::scratch_dir("seed-link");
    let (pubf, bor, again) = (
        dir.join("emc.pub"),
        dir.join("emc.bor"),
        dir.join("again.bor"),
    );
    std::fs::write(&pubf, PUB).unwrap();
    let o = oficina(&[
        "embroider",
        pubf.to_str().unwrap(),
        "-o",
        bor.to_str().unwrap(),
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}{err}");
    assert!(out.contains("1 satin, 1 running"), "{out}");
    let o = oficina(&[
        "embroider",
        bor.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    assert_eq!(std::fs::read(&bor).unwrap(), std::fs::read(&again).unwrap());
    let stitches: usize = text(&o)
        .0
        .lines()
        .find_map(|l| l.strip_prefix("Stitches"))
        .and_then(|v| v.trim().parse().ok())
        .expect("the sheet's stitch count");
    // A bad record names its line.
    let bad = dir.join("bad.pub");
    std::fs::write(&bad, "P 1 2 3 1 0 2\n1 2 x 4\n").unwrap();
    let o = oficina(&[
        "embroider",
        bad.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(text(&o).1.contains("line 2"), "{:?}", text(&o));

    let mut emu = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["emulate", "seed", "--pty"])
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(emu.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    let pts = first
        .split_whitespace()
        .find(|w| w.starts_with("/dev/"))
        .unwrap()
        .to_string();
    let o = oficina(&[
        "embroider",
        bor.to_str().unwrap(),
        "--send",
        &pts,
        "--program",
        "3",
    ]);
    assert!(o.status.success(), "{:?}", text(&o));
    let got = lines.next().unwrap().unwrap();
    let _ = emu.kill();
    let _ = emu.wait();
    assert!(
        got.starts_with(&format!("program 3 stored: {stitches} stitches sewn")),
        "{got}"
    );
    assert!(got.ends_with("0 fault(s)"), "{got}");
}
