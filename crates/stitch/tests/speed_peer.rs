//! A section sewn at a faster head-speed code (`sew_at_speed`), on a real Janome file, written
//! as PES and DST and read by pyembroidery: every stitch of the section is within the code's
//! longest stitch as pyembroidery's coordinates give it, the original points are still sewn
//! in order, the rest of the design is untouched, and the files agree with our plan stitch
//! for stitch. Skipped with a note when pyembroidery or the shared files are missing.

mod common;
#[path = "common/pyembroidery.rs"]
mod pyembroidery;

use oficina_stitch::{sections, sew_at_speed, Format, SPEED_CODES};
use pyembroidery::{agree, ours_as, peer_read, python_with_pyembroidery};

#[test]
fn a_faster_code_sews_within_its_length_as_pyembroidery_reads_the_file() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let Some(dir) = oficina_testkit::realworld("embroidery-files") else {
        return;
    };
    let path = dir.join("emm_Star.JEF");
    let plan = Format::Jef
        .read(&std::fs::read(&path).unwrap(), "star")
        .unwrap();
    // The section with the longest stitches the machine still sews, sped up to code 12.
    let slowest = sections(&plan)
        .into_iter()
        .filter(|s| s.code.is_some())
        .max_by(|a, b| a.longest.total_cmp(&b.longest))
        .unwrap();
    assert!(slowest.code < Some(12), "{slowest:?}");
    let fast = sew_at_speed(&plan, slowest.start, 12).unwrap();
    let limit = SPEED_CODES[0].max_stitch;
    let scratch = oficina_testkit::scratch_dir("stitch-speed-peer");
    let (before, _) = {
        let f = scratch.join("before.dst");
        std::fs::write(&f, Format::Dst.write(&plan).unwrap()).unwrap();
        peer_read(&py, &f)
    };
    for format in [Format::Pes, Format::Dst] {
        let file = scratch.join(format!("fast.{}", format.extension()));
        std::fs::write(&file, format.write(&fast).unwrap()).unwrap();
        let (peer, _) = peer_read(&py, &file);
        agree(&format!("{format}"), &ours_as(&fast, format), &peer);
        // The section in pyembroidery's reading: the stitches sewn from the one before the
        // section's first (counted among sewn stitches) to its last original point.
        let sewn_before = plan
            .entries()
            .take(slowest.start)
            .filter(|(_, s)| s.kind == oficina_stitch::Kind::Stitch)
            .count();
        let n_orig = slowest.end - slowest.start;
        let added = peer.stitches.len() - before.stitches.len();
        assert!(added > 0, "{format}: the long stitches are split");
        let sec = &peer.stitches[sewn_before..sewn_before + n_orig + added];
        // Between the section's own points (its first stitch comes from a jump's end, which
        // the reading leaves out).
        for (i, w) in sec.windows(2).enumerate() {
            let d = ((w[1].0 - w[0].0) as f64).hypot((w[1].1 - w[0].1) as f64) / 10.0;
            assert!(
                d <= limit + 1e-9,
                "{format}: stitch {} of the section is {d} mm, over code 12's {limit} mm",
                i + 1
            );
        }
        // The original points, in order, are among them; the rest is as it was.
        let orig = &before.stitches[sewn_before..sewn_before + n_orig];
        let mut it = sec.iter();
        for p in orig {
            assert!(it.any(|q| q == p), "{format}: original point {p:?} is sewn");
        }
        assert_eq!(peer.stitches[..sewn_before], before.stitches[..sewn_before]);
        assert_eq!(
            peer.stitches[sewn_before + n_orig + added..],
            before.stitches[sewn_before + n_orig..]
        );
        eprintln!(
            "{format}: section {}–{} (longest {:.2} mm, code {:?}) sewn at code 12: {added} stitches added, every one ≤ {limit} mm in pyembroidery's reading",
            slowest.start, slowest.end, slowest.longest, slowest.code
        );
    }
}
