//! Fuzzing the readers of relief input with proptest: elevation images (PNG, JPEG, TIFF)
//! and raw f32 height fields.
//!
//! Inputs: valid pictures of random size, colour type and format, then mutated (bytes
//! overwritten, runs inserted, cut short, a header's size fields rewritten), and plain random
//! bytes behind each format's signature. Asserted for every input: no panic; a result is
//! either a named error or a height map whose size matches its samples, every height finite
//! and within 0 ..= −depth. A case slower than a second is reported on stderr (a hang would
//! show as a test that never ends).
//!
//! Cases per property: `PROPTEST_CASES` (default 256). A long run:
//! `PROPTEST_CASES=100000 cargo test --release -p oficina-io --test fuzz_readers`.

use image::{DynamicImage, ImageBuffer, ImageFormat, Luma, Rgb, Rgba};
use oficina_io::{load_image_bytes, raw_f32_from_bytes, DepthMapping, Heightmap, Scale};
use proptest::prelude::*;
use std::io::Cursor;
use std::time::Instant;

/// The budget the readers get here: small enough that a hostile header is refused by it.
const BUDGET: u64 = 64 << 20;

fn encode(w: u32, h: u32, kind: u8, format: ImageFormat, seed: u32) -> Vec<u8> {
    let v =
        move |x: u32, y: u32, c: u32| (x.wrapping_mul(31) ^ y.wrapping_mul(17) ^ seed ^ c) as u8;
    let img = match kind % 4 {
        0 => DynamicImage::ImageLuma8(ImageBuffer::from_fn(w, h, |x, y| Luma([v(x, y, 0)]))),
        1 => DynamicImage::ImageLuma16(ImageBuffer::from_fn(w, h, |x, y| {
            Luma([v(x, y, 0) as u16 * 257])
        })),
        2 => DynamicImage::ImageRgb8(ImageBuffer::from_fn(w, h, |x, y| {
            Rgb([v(x, y, 0), v(x, y, 1), v(x, y, 2)])
        })),
        _ => DynamicImage::ImageRgba8(ImageBuffer::from_fn(w, h, |x, y| {
            Rgba([v(x, y, 0), v(x, y, 1), v(x, y, 2), v(x, y, 3)])
        })),
    };
    // JPEG holds 8-bit gray or RGB only.
    let img = match (format, &img) {
        (ImageFormat::Jpeg, DynamicImage::ImageLuma16(_)) => {
            DynamicImage::ImageLuma8(img.to_luma8())
        }
        (ImageFormat::Jpeg, DynamicImage::ImageRgba8(_)) => DynamicImage::ImageRgb8(img.to_rgb8()),
        _ => img,
    };
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format).expect("encodes");
    out.into_inner()
}

#[derive(Clone, Debug)]
enum Mutation {
    Overwrite(usize, u8),
    Insert(usize, Vec<u8>),
    Truncate(usize),
    /// Big-endian u32 at this offset (a size field in PNG's IHDR, JPEG's SOF, TIFF's tags).
    Size(usize, u32),
}

fn mutate(mut bytes: Vec<u8>, mutations: &[Mutation]) -> Vec<u8> {
    for m in mutations {
        let n = bytes.len().max(1);
        match m {
            Mutation::Overwrite(at, b) => {
                if let Some(slot) = bytes.get_mut(at % n) {
                    *slot = *b;
                }
            }
            Mutation::Insert(at, run) => {
                let at = (at % n).min(bytes.len());
                bytes.splice(at..at, run.iter().copied());
            }
            Mutation::Truncate(at) => bytes.truncate(at % n),
            Mutation::Size(at, v) => {
                let at = at % n;
                for (k, b) in v.to_be_bytes().iter().enumerate() {
                    if let Some(slot) = bytes.get_mut(at + k) {
                        *slot = *b;
                    }
                }
            }
        }
    }
    bytes
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<u8>()).prop_map(|(a, b)| Mutation::Overwrite(a, b)),
        1 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..64)).prop_map(|(a, r)| Mutation::Insert(a, r)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        2 => (0usize..64, prop_oneof![Just(0u32), Just(1), Just(u32::MAX), Just(65535), Just(100_000), any::<u32>()])
            .prop_map(|(a, v)| Mutation::Size(a, v)),
    ]
}

fn format() -> impl Strategy<Value = ImageFormat> {
    prop::sample::select(vec![ImageFormat::Png, ImageFormat::Jpeg, ImageFormat::Tiff])
}

/// Pixel sizes, widths and depths, sane and absurd.
fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (-7.0f64..7.0).prop_map(|e| 10f64.powf(e)),
        1 => prop::sample::select(vec![0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, f64::MIN_POSITIVE]),
    ]
}

fn mapping() -> impl Strategy<Value = DepthMapping> {
    (number(), any::<bool>(), any::<bool>()).prop_map(|(max_depth, invert, normalize)| {
        DepthMapping {
            max_depth,
            invert,
            normalize,
        }
    })
}

/// Settings a user would give, so that every case reaches the decoder.
fn sane_settings() -> impl Strategy<Value = (Scale, DepthMapping)> {
    (0.01f64..10.0, 0.1f64..100.0, any::<bool>(), any::<bool>()).prop_map(
        |(p, d, invert, normalize)| {
            (
                Scale::PixelSize(p),
                DepthMapping {
                    max_depth: d,
                    invert,
                    normalize,
                },
            )
        },
    )
}

fn scale() -> impl Strategy<Value = Scale> {
    prop_oneof![
        number().prop_map(Scale::PixelSize),
        number().prop_map(Scale::Width)
    ]
}

/// What a height map from any reader must satisfy.
fn well_formed(m: &Heightmap, depth: Option<f64>) {
    assert_eq!(m.z.len(), m.width * m.height);
    assert!(m.width > 0 && m.height > 0);
    assert!(m.pixel.is_finite() && m.pixel > 0.0, "pixel {}", m.pixel);
    for &z in &m.z {
        assert!(z.is_finite(), "height {z}");
        if let Some(d) = depth {
            assert!(
                z <= 0.0 && z as f64 >= -d * (1.0 + 1e-6),
                "height {z} outside 0..-{d}"
            );
        }
    }
}

fn read(bytes: &[u8], scale: Scale, mapping: DepthMapping) {
    let t = Instant::now();
    let result = load_image_bytes("fuzz.img", bytes, scale, mapping, BUDGET);
    if t.elapsed().as_secs_f64() > 1.0 {
        eprintln!(
            "slow case: {:.2} s, {} bytes",
            t.elapsed().as_secs_f64(),
            bytes.len()
        );
    }
    match result {
        Ok(m) => well_formed(&m, Some(mapping.max_depth)),
        Err(e) => {
            let text = e.to_string();
            assert!(!text.is_empty());
            assert!(
                text.contains("fuzz.img") || text.contains("must be") || text.contains("depth"),
                "an error names the file or the parameter: {text}"
            );
        }
    }
}

proptest! {
    #[test]
    fn mutated_pictures_read_or_fail_cleanly(
        w in 1u32..24, h in 1u32..24, kind in any::<u8>(), fmt in format(), seed in any::<u32>(),
        mutations in prop::collection::vec(mutation(), 0..6),
        (scale, mapping) in sane_settings(),
    ) {
        let bytes = mutate(encode(w, h, kind, fmt, seed), &mutations);
        read(&bytes, scale, mapping);
    }

    #[test]
    fn any_numbers_with_a_valid_picture_read_or_fail_cleanly(
        w in 1u32..6, h in 1u32..6, kind in any::<u8>(), fmt in format(),
        scale in scale(), mapping in mapping(),
    ) {
        read(&encode(w, h, kind, fmt, 7), scale, mapping);
    }

    #[test]
    fn random_bytes_behind_a_signature_fail_cleanly(
        signature in prop::sample::select(vec![
            &b"\x89PNG\r\n\x1a\n"[..], &b"\xff\xd8\xff"[..], &b"II*\0"[..], &b"MM\0*"[..], &b""[..],
        ]),
        tail in prop::collection::vec(any::<u8>(), 0..512),
        (scale, mapping) in sane_settings(),
    ) {
        let mut bytes = signature.to_vec();
        bytes.extend(tail);
        read(&bytes, scale, mapping);
    }

    #[test]
    fn raw_height_fields_read_or_fail_cleanly(
        data in prop::collection::vec(any::<u8>(), 0..600),
        width in prop_oneof![0usize..40, Just(usize::MAX), Just(usize::MAX / 4 + 1), any::<usize>()],
        pixel in number(),
    ) {
        match raw_f32_from_bytes("fuzz.f32", &data, width, pixel) {
            Ok(m) => {
                well_formed(&m, None);
                assert_eq!(m.width, width);
                assert_eq!(m.z.len() * 4, data.len());
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn every_format_and_size_from_one_pixel_reads_back() {
    for fmt in [ImageFormat::Png, ImageFormat::Jpeg, ImageFormat::Tiff] {
        for (w, h) in [(1, 1), (1, 7), (7, 1), (3, 2)] {
            for kind in 0..4 {
                let bytes = encode(w, h, kind, fmt, 5);
                let m = load_image_bytes(
                    "t",
                    &bytes,
                    Scale::PixelSize(0.5),
                    DepthMapping::new(3.0),
                    BUDGET,
                )
                .unwrap_or_else(|e| panic!("{fmt:?} {w}x{h} kind {kind}: {e}"));
                assert_eq!((m.width, m.height), (w as usize, h as usize));
                well_formed(&m, Some(3.0));
            }
        }
    }
}
