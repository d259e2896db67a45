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
    // A 0x1A after END (DOS end of file), or after the last record of a file without END
    // or of an EXP: read as pyembroidery and machines read it.
    let mut eof = dst.clone();
    eof.push(0x1A);
    assert_eq!(
        Format::Dst.read(&eof, "x").unwrap().counts(),
        Format::Dst.read(&dst, "x").unwrap().counts()
    );
    let mut eof = dst[..dst.len() - 3].to_vec();
    eof.push(0x1A);
    assert_eq!(
        Format::Dst.read(&eof, "x").unwrap().counts().stitches,
        small_plan().counts().stitches
    );
    let mut eof = dst[..dst.len() - 3].to_vec();
    eof.push(0x05);
    let e = Format::Dst.read(&eof, "x").unwrap_err();
    assert!(e.to_string().contains("1 of 3 bytes"), "{e}");
    let exp = Format::Exp.write(&small_plan()).unwrap();
    let mut eof = exp.clone();
    eof.push(0x1A);
    assert_eq!(
        Format::Exp.read(&eof, "x").unwrap().counts(),
        Format::Exp.read(&exp, "x").unwrap().counts()
    );
    // No END record (PEmbroider writes none): read to the file's end, as pyembroidery does.
    let cut = Format::Dst.read(&dst[..dst.len() - 3], "x").unwrap();
    assert_eq!(cut.counts().stitches, small_plan().counts().stitches);
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

/// A plan with two colours, a trim and a stop, for the formats' broken-file tests.
fn two_colours() -> StitchPlan {
    let mut p = small_plan();
    let mut b = small_plan().blocks.remove(0);
    b.thread = Thread::rgb(200, 0, 0);
    b.stitches.insert(0, Stitch::new(30.0, 10.0, Kind::Jump));
    for s in &mut b.stitches[1..] {
        s.x += 30.0;
        s.y += 10.0;
    }
    p.blocks[0]
        .stitches
        .push(Stitch::new(27.3, 3.0, Kind::Trim));
    p.blocks.push(b);
    p
}

/// The new formats: an empty file, a file cut inside a record or its header, and absurd
/// counts each get an error naming the format and the byte; trailing bytes after the end
/// and a missing end are read as pyembroidery reads them.
#[test]
fn broken_files_of_every_format_are_refused_at_their_byte() {
    let plan = two_colours();
    for f in [
        Format::Pes,
        Format::PesV1,
        Format::Pec,
        Format::Jef,
        Format::Vp3,
        Format::Xxx,
        Format::U01,
    ] {
        let e = f.read(&[], "x").unwrap_err();
        assert!(e.to_string().contains("empty"), "{f}: {e}");
        let good = f.write(&plan).unwrap();
        let back = f.read(&good, "x").unwrap();
        assert_eq!(back.counts().stitches, plan.counts().stitches, "{f}");
        // Cut in the header. (A PES file of either version reads as PES.)
        let e = f.read(&good[..20], "x").unwrap_err();
        let reader = if f == Format::PesV1 { Format::Pes } else { f };
        assert!(
            e.to_string().starts_with(&format!("{reader} file: byte ")),
            "{f}: {e}"
        );
        // Trailing bytes after the end are ignored (a 0x1A, padding).
        let mut tail = good.clone();
        tail.extend_from_slice(&[0x1A, 0, 0, 0]);
        let t = f
            .read(&tail, "x")
            .unwrap_or_else(|e| panic!("{f} with trailing bytes: {e}"));
        assert_eq!(t.counts(), back.counts(), "{f} with trailing bytes");
    }
    // Cut inside a stitch record: the stitches of a JEF start after the header and colours.
    let jef = Format::Jef.write(&plan).unwrap();
    let start = u32::from_le_bytes([jef[0], jef[1], jef[2], jef[3]]) as usize;
    let e = Format::Jef.read(&jef[..start + 5], "x").unwrap_err();
    assert!(
        e.to_string().contains(&format!("byte {}", start + 4))
            && e.to_string().contains("truncated"),
        "{e}"
    );
    // A missing end: what is there is read.
    let no_end = Format::Jef.read(&jef[..jef.len() - 2], "x").unwrap();
    assert_eq!(no_end.counts().stitches, plan.counts().stitches);
    let u01 = Format::U01.write(&plan).unwrap();
    let e = Format::U01.read(&u01[..u01.len() - 4], "x").unwrap_err();
    assert!(e.to_string().contains("cut after 2 of 3 bytes"), "{e}");
    let xxx = Format::Xxx.write(&plan).unwrap();
    let e = Format::Xxx.read(&xxx[..0x100 + 40], "x").unwrap_err();
    assert!(e.to_string().contains("no end record"), "{e}");
    // Absurd counts: a JEF claiming 10⁹ colours, a VP3 claiming 65535 colour blocks, a PES
    // whose PEC section lies beyond the file, a PEC stitch block longer than the file.
    let mut j = jef.clone();
    j[24..28].copy_from_slice(&1_000_000_000u32.to_le_bytes());
    let e = Format::Jef.read(&j, "x").unwrap_err();
    assert!(
        e.to_string().contains("byte 24") && e.to_string().contains("colour count 1000000000"),
        "{e}"
    );
    let vp3 = Format::Vp3.write(&plan).unwrap();
    let at = vp3.windows(6).position(|w| w == b"xxPP\x01\x00").unwrap() + 6;
    let at = at + 2 + u16::from_be_bytes([vp3[at], vp3[at + 1]]) as usize;
    let mut v = vp3.clone();
    v[at..at + 2].copy_from_slice(&[0xFF, 0xFF]);
    let e = Format::Vp3.read(&v, "x").unwrap_err();
    assert!(
        e.to_string().contains(&format!("byte {at}"))
            && e.to_string().contains("65535 colour blocks"),
        "{e}"
    );
    let mut pes = Format::Pes.write(&plan).unwrap();
    pes[8..12].copy_from_slice(&0x7FFF_FFFFu32.to_le_bytes());
    let e = Format::Pes.read(&pes, "x").unwrap_err();
    assert!(
        e.to_string().contains("byte 8") && e.to_string().contains("outside the file"),
        "{e}"
    );
    let mut pec = Format::Pec.write(&plan).unwrap();
    pec[8 + 0x202..8 + 0x205].copy_from_slice(&[0xFF, 0xFF, 0xFF]);
    let e = Format::Pec.read(&pec, "x").unwrap_err();
    assert!(
        e.to_string().contains(&format!("byte {}", 8 + 0x202))
            && e.to_string().contains("does not fit"),
        "{e}"
    );
    // Not the format at all.
    let e = Format::Pes.read(b"hello, world", "x").unwrap_err();
    assert!(e.to_string().contains("not a PES file"), "{e}");
    let e = Format::Vp3.read(b"hello, world", "x").unwrap_err();
    assert!(e.to_string().contains("not a VP3 file"), "{e}");
}

/// A plan with nothing to sew writes a valid file of every format, read back as nothing.
#[test]
fn empty_plans_write_and_read_back_empty() {
    let empty = StitchPlan {
        name: "nothing".into(),
        blocks: vec![ColorBlock {
            thread: Thread::rgb(10, 20, 30),
            stitches: Vec::new(),
        }],
    };
    for plan in [StitchPlan::default(), empty] {
        for f in Format::ALL {
            let bytes = f.write(&plan).unwrap_or_else(|e| panic!("{f}: {e}"));
            if f == Format::Exp {
                // EXP has no header: nothing to sew is a 0-byte file, which reads as empty.
                assert!(bytes.is_empty());
                continue;
            }
            let back = f.read(&bytes, "x").unwrap_or_else(|e| panic!("{f}: {e}"));
            assert!(back.is_empty(), "{f}: {:?}", back.counts());
        }
    }
}

/// Every format's own file is recognised by its first bytes where it has a signature.
#[test]
fn files_are_recognised_by_content() {
    let plan = two_colours();
    for f in Format::ALL {
        let bytes = f.write(&plan).unwrap();
        let want = match f {
            Format::Exp | Format::Xxx | Format::U01 => None,
            Format::PesV1 => Some(Format::Pes),
            f => Some(f),
        };
        assert_eq!(Format::sniff(&bytes), want, "{f}");
    }
    assert_eq!(Format::sniff(b""), None);
    assert_eq!(Format::sniff(b"<svg/>"), None);
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
        for f in Format::EVERY {
            let _ = f.read(&body, "fuzz");
        }
        let _ = Format::SeedRam.read(&body, "fuzz");
        let mut ram = vec![0u8, 0, 1, 0, 0, 0x80, 0, 0x80, 7];
        ram.extend_from_slice(&body);
        let _ = Format::SeedRam.read(&ram, "fuzz");
    }

    /// Valid files of every format with bytes changed, cut or added never panic a reader.
    #[test]
    fn damaged_files_never_panic(seed in any::<u64>(), changes in 1usize..12, cut in any::<u16>(), extra in proptest::collection::vec(any::<u8>(), 0..8)) {
        let plan = two_colours();
        for f in Format::ALL {
            let mut bytes = f.write(&plan).unwrap();
            let mut x = seed | 1;
            for _ in 0..changes {
                x ^= x << 13; x ^= x >> 7; x ^= x << 17;
                let i = (x % bytes.len() as u64) as usize;
                bytes[i] = (x >> 32) as u8;
            }
            let keep = bytes.len() - (cut as usize % bytes.len());
            bytes.truncate(keep);
            bytes.extend_from_slice(&extra);
            let _ = f.read(&bytes, "fuzz");
        }
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
