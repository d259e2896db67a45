//! Proptest fuzzing of the HPGL reader: arbitrary bytes, encoded polylines (PE) of any bytes,
//! and HPGL-shaped noise with PCL and device-control escapes never panic,
//! and every path it returns has finite coordinates.

use oficina_io::hpgl_from_bytes;
use proptest::prelude::*;

fn check(bytes: &[u8]) {
    if let Ok(h) = hpgl_from_bytes(bytes, "fuzz.plt") {
        for p in h.imported.drawing.paths() {
            for q in p.flatten(0.5).iter().take(10_000) {
                assert!(q.x.is_finite() && q.y.is_finite());
            }
        }
    }
}

fn instruction() -> impl Strategy<Value = String> {
    let mn = prop::sample::select(vec![
        "IN", "SP", "PU", "PD", "PA", "PR", "CI", "AA", "AR", "LB", "DT", "SI", "DI", "VS", "zz",
        "SC", "IP", "BZ", "BR", "EA", "ER", "EW", "PM", "EP", "SM", "PE", "\x1b.(", "\x1b%1B",
        "\x1b%0A", "\x1b*b3W", "\x1bE", "!PZ", "LT", "AT", "RT", "RO", "CO",
    ]);
    let num = prop_oneof![
        (-100_000i64..100_000).prop_map(|v| v.to_string()),
        any::<f64>().prop_map(|v| v.to_string()),
        Just("-".to_string()),
        Just(".".to_string()),
        Just("1e999".to_string()),
    ];
    let sep = prop::sample::select(vec![",", " ", ";", "\n", "\x03", ""]);
    (mn, prop::collection::vec((num, sep.clone()), 0..6), sep).prop_map(|(m, ps, end)| {
        let mut s = m.to_string();
        for (n, sep) in ps {
            s.push_str(&n);
            s.push_str(sep);
        }
        s.push_str(end);
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        check(&bytes);
    }

    #[test]
    fn encoded_polylines_of_any_bytes_never_panic(
        body in prop::collection::vec(any::<u8>(), 0..200),
        seven in any::<bool>(),
    ) {
        let head: &[u8] = if seven { b"IN;SP1;SC0,3,0,7;PE7" } else { b"IN;SP1;PE" };
        check(&[head, &body].concat());
    }

    #[test]
    fn hpgl_shaped_noise_never_panics(prog in prop::collection::vec(instruction(), 0..40)) {
        check(prog.concat().as_bytes());
    }
}
