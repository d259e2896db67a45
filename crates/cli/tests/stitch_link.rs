//! `oficina embroider A --link B --link-at X,Y` (what the page's stitch editor links by) on two
//! real files, read by pyembroidery: A's sewn stitches, then B's moved by (X, Y) exactly
//! (0.1 mm), with at most the one joining point between; and `--section-speed` refused by
//! name where it cannot apply. Skipped with a note when pyembroidery or the files are missing.

mod common;
#[path = "../../stitch/tests/common/pyembroidery.rs"]
mod pyembroidery;

use common::{oficina, text};
use pyembroidery::{peer_read, python_with_pyembroidery};

#[test]
fn linked_designs_are_placed_by_their_offsets_as_pyembroidery_reads_them() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let Some(dir) = oficina_testkit::realworld("embroidery-files") else {
        return;
    };
    let (a, b) = (
        dir.join("emm_Star.JEF"),
        dir.join("pembr_Hello_PEmbroider.dst"),
    );
    let out = oficina_testkit::scratch_dir("stitch-link").join("linked.pes");
    let o = oficina(&[
        "embroider",
        a.to_str().unwrap(),
        "--link",
        b.to_str().unwrap(),
        "--link-at",
        "80.5,-12",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}{stderr}");
    let (pa, ta) = peer_read(&py, &a);
    let (pb, _) = peer_read(&py, &b);
    let (got, threads) = peer_read(&py, &out);
    let moved: Vec<(i64, i64)> = pb
        .stitches
        .iter()
        .map(|&(x, y)| (x + 805, y - 120))
        .collect();
    let n = pa.stitches.len() + moved.len();
    assert!(
        got.stitches.len() == n || got.stitches.len() == n + 1,
        "{} stitches for {} + {}",
        got.stitches.len(),
        pa.stitches.len(),
        moved.len()
    );
    assert_eq!(got.stitches[..pa.stitches.len()], pa.stitches[..]);
    assert_eq!(got.stitches[got.stitches.len() - moved.len()..], moved[..]);
    // A's two threads and the DST's one, joined by one more colour change.
    assert_eq!(threads.len(), ta.len() + 1, "{threads:?}");
    assert_eq!(got.color_changes, pa.color_changes + pb.color_changes + 1);
}

#[test]
fn section_speed_and_link_offsets_are_refused_by_name() {
    let Some(dir) = oficina_testkit::realworld("embroidery-files") else {
        return;
    };
    let a = dir.join("emm_Star.JEF");
    let out = oficina_testkit::scratch_dir("stitch-link").join("refused.dst");
    let cases: [(&[&str], &str); 3] = [
        (&["--section-speed", "0:12"], "entry 0: not a sewn stitch"),
        (&["--section-speed", "5:3"], "codes 4 to 12"),
        (&["--section-speed", "5:4"], "only a faster code"),
    ];
    for (args, want) in cases {
        let mut all = vec![
            "embroider",
            a.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        all.extend_from_slice(args);
        let o = oficina(&all);
        let (stdout, stderr) = text(&o);
        assert!(!o.status.success(), "{args:?}: {stdout}");
        assert!(
            stderr.contains("--section-speed") && stderr.contains(want),
            "{args:?}: {stderr}"
        );
    }
    let o = oficina(&["embroider", a.to_str().unwrap(), "--link-at", "1,2"]);
    assert!(!o.status.success());
    assert!(text(&o).1.contains("--link"), "{}", text(&o).1);
}
