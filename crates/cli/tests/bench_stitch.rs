//! `oficina bench stitch` at a small size: its table's rows are there, and our stitch counts
//! and pyembroidery's agree on the same DST and PES files (times are not asserted).

use std::process::Command;

fn stitches(text: &str, row: &str) -> usize {
    let line = text
        .lines()
        .find(|l| l.starts_with(row))
        .unwrap_or_else(|| panic!("no row '{row}' in\n{text}"));
    let i = line.find("stitches").unwrap() + "stitches".len();
    line[i..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn bench_stitch_counts_agree_with_pyembroidery() {
    let peer = Command::new("python3")
        .args(["-c", "import pyembroidery"])
        .status()
        .is_ok_and(|s| s.success());
    let mut args = vec!["bench", "stitch", "--stitches", "3000"];
    if !peer {
        eprintln!("pyembroidery is not installed: the peer is not run");
        args.push("--no-peer");
    }
    let o = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(&args)
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{}\n{out}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.starts_with("design: 36 fills, 4 colours"), "{out}");
    let made = stitches(&out, "oficina fill + routing ");
    // About the size asked: each small shape adds its underlay and lock stitches.
    assert!((2000..9000).contains(&made), "{out}");
    assert_eq!(stitches(&out, "oficina read DST + PES"), made, "{out}");
    assert!(out.contains("oficina fill + routing + write"), "{out}");
    assert!(out.contains("peak memory (VmHWM):"), "{out}");
    if peer {
        assert_eq!(stitches(&out, "pyembroidery read DST + PES"), made, "{out}");
        assert!(out.contains("pyembroidery peak memory"), "{out}");
        assert!(out.contains("(agree)"), "{out}");
    }
}
