//! Broken embroidery files get an error naming the format, the byte and the problem; random
//! bytes never panic a reader.

use oficina_stitch::{ColorBlock, Format, Kind, Stitch, StitchPlan, Thread};
use proptest::prelude::*;

fn small_plan() -> StitchPlan {
    let stitches = (0..40)
        .map(|i| Stitch::new(i as f64 * 0.7, (i % 2) as f64 * 3.0, Kind::Stitch))
        .collect();
    StitchPlan {
        name: "small".into(),
        blocks: vec![ColorBlock {
            thread: Thread::rgb(1, 2, 3),
            stitches,
        }],
    }
}

#[test]
fn empty_files_are_refused() {
    for f in Format::EVERY {
        let e = f.read(&[], "x").unwrap_err();
        assert!(e.to_string().contains("empty"), "{e}");
    }
}

#[test]
fn truncated_files_say_so() {
    let dst = Format::Dst.write(&small_plan()).unwrap();
    let e = Format::Dst.read(&dst[..300], "x").unwrap_err();
    assert!(
        e.to_string().contains("shorter than the 512-byte header"),
        "{e}"
    );
    let e = Format::Dst.read(&dst[..dst.len() - 1], "x").unwrap_err();
    assert!(e.to_string().contains("truncated"), "{e}");
    let e = Format::Dst.read(&dst[..dst.len() - 3], "x").unwrap_err();
    assert!(e.to_string().contains("no END record"), "{e}");
    let exp = Format::Exp.write(&small_plan()).unwrap();
    let e = Format::Exp.read(&exp[..exp.len() - 1], "x").unwrap_err();
    assert!(e.to_string().contains("truncated"), "{e}");
    let e = Format::Exp.read(&[1, 1, 0x80, 0x04, 5], "x").unwrap_err();
    assert!(
        e.to_string().contains("byte 2") && e.to_string().contains("truncated"),
        "{e}"
    );
}

#[test]
fn absurd_headers_are_refused() {
    let mut dst = Format::Dst.write(&small_plan()).unwrap();
    dst[0] = b'X';
    assert!(Format::Dst
        .read(&dst, "x")
        .unwrap_err()
        .to_string()
        .contains("not a DST file"));
    let mut dst = Format::Dst.write(&small_plan()).unwrap();
    let st = dst.windows(3).position(|w| w == b"ST:").unwrap();
    dst[st + 3..st + 10].copy_from_slice(b"  12x34");
    let e = Format::Dst.read(&dst, "x").unwrap_err();
    assert!(
        e.to_string().contains("header field ST") && e.to_string().contains("not a number"),
        "{e}"
    );
    let e = Format::Exp.read(&[0x80, 0x33, 0, 0], "x").unwrap_err();
    assert!(e.to_string().contains("unknown command 80 33"), "{e}");
}

#[test]
fn absurd_plans_are_refused_by_writers() {
    let mut p = small_plan();
    p.blocks[0]
        .stitches
        .push(Stitch::new(f64::NAN, 0.0, Kind::Stitch));
    for f in Format::ALL {
        let e = f.write(&p).unwrap_err();
        assert!(e.to_string().contains("not finite"), "{e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn readers_never_panic(body in proptest::collection::vec(any::<u8>(), 0..600), keep_header: bool) {
        let mut dst = Format::Dst.write(&small_plan()).unwrap();
        if keep_header {
            dst.truncate(512);
            dst.extend_from_slice(&body);
        } else {
            dst = body.clone();
        }
        let _ = Format::Dst.read(&dst, "fuzz");
        let _ = Format::Exp.read(&body, "fuzz");
        let _ = Format::SeedRam.read(&body, "fuzz");
        let mut ram = vec![0u8, 0, 1, 0, 0, 0x80, 0, 0x80, 7];
        ram.extend_from_slice(&body);
        let _ = Format::SeedRam.read(&ram, "fuzz");
    }

    #[test]
    fn write_read_round_trips(points in proptest::collection::vec((-900i32..900, -900i32..900, 0u8..4), 1..80)) {
        let stitches: Vec<Stitch> = points.iter().map(|&(x, y, k)| {
            let kind = if k == 0 { Kind::Jump } else { Kind::Stitch };
            Stitch::new(x as f64 / 10.0, y as f64 / 10.0, kind)
        }).collect();
        let plan = StitchPlan { name: "p".into(), blocks: vec![ColorBlock { thread: Thread::rgb(0, 0, 0), stitches }] };
        for f in Format::ALL {
            let back = f.read(&f.write(&plan).unwrap(), "p").unwrap();
            // Every planned stitch is sewn at its exact point, in order.
            let want: Vec<(i64, i64)> = plan.entries().filter(|e| e.1.kind == Kind::Stitch)
                .map(|e| ((e.1.x * 10.0).round() as i64, (e.1.y * 10.0).round() as i64)).collect();
            let got: Vec<(i64, i64)> = back.entries().filter(|e| e.1.kind == Kind::Stitch)
                .map(|e| ((e.1.x * 10.0).round() as i64, (e.1.y * 10.0).round() as i64)).collect();
            let mut it = got.iter();
            for w in &want {
                prop_assert!(it.any(|g| g == w), "{f}: {w:?} missing");
            }
        }
    }
}
