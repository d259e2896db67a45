//! Fuzzing the whole carve input path with proptest: picture bytes → height map → settings
//! → CAM job → plan → G-code → interpreter → simulated stock → time estimate, with every
//! numeric option drawn from sane and absurd values and a random memory budget.
//!
//! Asserted for every input: no panic; a refusal is a user error (never the "internal
//! error" of a program our own post wrote and our interpreter rejects); a carved job never
//! gouges the design and its program ends with M30. A case slower than a second is reported
//! on stderr.
//!
//! Cases: `PROPTEST_CASES` (default 256). A long run:
//! `PROPTEST_CASES=20000 cargo test --release -p oficina-sim --test fuzz_carve`.

use image::{ImageBuffer, Luma};
use oficina_cam::relief::Direction;
use oficina_io::{load_image_bytes, DepthMapping, Scale};
use oficina_post::{PostDialect, PostOptions};
use oficina_sim::carve::{evaluate, CarveError, Settings};
use proptest::prelude::*;
use std::io::Cursor;

fn png(w: u32, h: u32, pixels: &[u8]) -> Vec<u8> {
    let img = ImageBuffer::from_fn(w, h, |x, y| {
        Luma([pixels[((y * w + x) as usize) % pixels.len()]])
    });
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// Mostly a user's range (log-uniform between `lo` and `hi`), sometimes absurd: rarely
/// enough per number that most cases, with a dozen numbers, still run the whole path.
fn num(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        60 => (lo.ln()..hi.ln()).prop_map(f64::exp),
        1 => (-9.0f64..12.0).prop_map(|e| 10f64.powf(e)),
        1 => prop::sample::select(vec![
            0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::MAX,
            f64::MIN_POSITIVE,
            1e-300
        ]),
    ]
}

fn tool() -> impl Strategy<Value = String> {
    prop_oneof![
        12 => (num(0.5, 20.0), prop::sample::select(vec!["ball", "flat"]))
            .prop_map(|(d, s)| format!("{s}:{d}")),
        1 => (num(0.5, 20.0), num(20.0, 150.0)).prop_map(|(d, a)| format!("v:{d}:{a}")),
        1 => (num(2.0, 20.0), num(0.1, 1.0)).prop_map(|(d, c)| format!("bull:{d}:{c}")),
        1 => (num(0.2, 3.0), num(1.0, 30.0)).prop_map(|(d, a)| format!("taper:{d}:{a}")),
        1 => "[a-z:0-9.,=-]{0,16}",
    ]
}

prop_compose! {
    fn settings()(
        tool in tool(),
        rough_tool in prop::option::of(tool()),
        scallop in num(0.005, 0.2),
        stepover in prop::option::of(num(0.1, 10.0)),
        rough_stepover in num(0.1, 1.0),
        stepdown in num(0.5, 10.0),
        allowance in num(0.05, 2.0),
        direction in prop::sample::select(vec![Direction::X, Direction::Y, Direction::Both]),
        one_way in any::<bool>(),
        no_rest in any::<bool>(),
        feed in num(100.0, 10000.0),
        plunge_feed in num(50.0, 3000.0),
        rpm in num(1000.0, 30000.0),
        safe_z in num(1.0, 50.0),
    ) -> Settings {
        Settings {
            tool, rough_tool, scallop, stepover, rough_stepover, stepdown, allowance,
            direction, one_way, no_rest, feed, plunge_feed, rpm, safe_z,
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { max_shrink_iters: 500, ..ProptestConfig::default() })]

    #[test]
    fn any_picture_and_options_carve_or_are_refused(
        w in 1u32..12, h in 1u32..12,
        pixels in prop::collection::vec(any::<u8>(), 1..64),
        damage in prop::option::weighted(0.2, (any::<usize>(), any::<u8>())),
        pixel in num(0.05, 5.0),
        width in prop::option::of(num(1.0, 500.0)),
        depth in num(0.5, 50.0),
        invert in any::<bool>(), normalize in any::<bool>(),
        settings in settings(),
        budget_mb in 1u64..128,
        linuxcnc in any::<bool>(), allow_m6 in any::<bool>(),
    ) {
        let mut bytes = png(w, h, &pixels);
        if let Some((at, b)) = damage {
            let n = bytes.len();
            bytes[at % n] = b;
        }
        let scale = width.map_or(Scale::PixelSize(pixel), Scale::Width);
        let mapping = DepthMapping { max_depth: depth, invert, normalize };
        let budget = budget_mb << 20;
        let Ok(design) = load_image_bytes("fuzz.png", &bytes, scale, mapping, budget) else {
            return Ok(());
        };
        let Ok(job) = settings.job() else { return Ok(()) };
        let post = PostOptions {
            dialect: if linuxcnc { PostDialect::LinuxCnc } else { PostDialect::Grbl },
            allow_m6,
            title: "fuzz".into(),
            settings: settings.describe(),
        };
        let profile = oficina_motion::bundled("grbl-router").unwrap().unwrap();
        let t = std::time::Instant::now();
        let result = evaluate(&design, &job, Some(&profile), &post, budget, &|_, _| {});
        if t.elapsed().as_secs_f64() > 1.0 {
            eprintln!(
                "slow case: {:.1} s, {} x {} px of {} mm, {settings:?}",
                t.elapsed().as_secs_f64(), design.width, design.height, design.pixel
            );
        }
        match result {
            Ok(e) => {
                prop_assert!(e.program.trim_end().ends_with("M30"));
                prop_assert!(
                    e.report.max_gouge <= 1e-3,
                    "gouge {} at {:?}", e.report.max_gouge, e.report.gouge_at
                );
            }
            Err(CarveError::Interpreter { first, .. }) => {
                prop_assert!(false, "our own program was rejected: {}", first);
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
