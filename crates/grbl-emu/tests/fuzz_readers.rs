//! Fuzzing the two readers of the grbl link (issue 8, item 10): the sender's parser of
//! firmware lines, and the emulator's line input (its RX ring, line assembly, `$` commands
//! and G-code parser). Zero panics, and every case finishes in bounded work: the emulator
//! runs a fixed simulated time per case, and must still answer a status query afterwards.
//!
//! Case counts: `PROPTEST_CASES` (default 256 here, a brief run for CI); the long run in
//! docs/grbl-link.md used `PROPTEST_CASES=…` on the release profile.

use oficina_grbl::Realtime;
use oficina_grbl::Response;
use oficina_grbl::StatusReport;
use oficina_grbl_emu::{Config, Core, Flavor};
use proptest::prelude::*;

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// Lines shaped like firmware output (a known prefix, then anything) and raw bytes.
fn firmware_line() -> impl Strategy<Value = String> {
    let prefix = prop::sample::select(vec![
        "",
        "ok",
        "error:",
        "ALARM:",
        "<",
        "<Idle|MPos:",
        "<Run|WPos:",
        "|Bf:",
        "|FS:",
        "|Ov:",
        "|WCO:",
        "[OPT:",
        "[VER:",
        "[MSG:",
        "[GC:",
        "[PRB:",
        "$",
        "$N",
        ">",
        "Grbl ",
        "GrblHAL ",
        "Grbl 3.7 [FluidNC v",
        "[",
    ]);
    let body = prop_oneof![
        any::<Vec<u8>>().prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
        "[0-9.,:|<>\\[\\]a-zA-Z -]{0,60}",
    ];
    (prefix, body, prop::bool::ANY).prop_map(|(p, b, close)| {
        let mut s = format!("{p}{b}");
        if close && p.starts_with('<') {
            s.push('>');
        }
        s
    })
}

/// Bytes shaped like a sender's input: G-code words with extreme numbers, `$` commands,
/// real-time bytes, line ends, and raw bytes.
fn sender_bytes() -> impl Strategy<Value = Vec<u8>> {
    let number = prop_oneof![
        Just("0".to_string()),
        Just("1e308".to_string()),
        Just("-99999999999".to_string()),
        Just("1.".to_string()),
        Just(".".to_string()),
        (-1.0e4f64..1.0e4).prop_map(|v| format!("{v:.4}")),
        (0u32..100).prop_map(|v| v.to_string()),
    ];
    let word = (
        prop::sample::select(b"GMXYZIJKRFSPTNLH$#=[]() ;%".to_vec()),
        number,
    )
        .prop_map(|(l, n)| format!("{}{n}", l as char).into_bytes());
    let piece = prop_oneof![
        4 => word,
        1 => prop::sample::select(vec![
            b"\n".to_vec(), b"\r".to_vec(), b"$$\n".to_vec(), b"$I\n".to_vec(), b"$G\n".to_vec(),
            b"$#\n".to_vec(), b"$C\n".to_vec(), b"$X\n".to_vec(), b"$H\n".to_vec(),
            b"$J=G91X10F1000\n".to_vec(), b"$N0=G20\n".to_vec(), b"$110=-5\n".to_vec(),
            b"$12=0\n".to_vec(), b"G2X10I5F100\n".to_vec(), b"G3R0.0001X1F10\n".to_vec(),
            b"G4P1\n".to_vec(), b"M30\n".to_vec(), b"G38.2Z-5F100\n".to_vec(),
            vec![b'?'], vec![b'!'], vec![b'~'], vec![0x18], vec![0x84], vec![0x85],
            vec![0x90], vec![0x91], vec![0x99], vec![0x9e], vec![0xa0],
        ]),
        1 => any::<Vec<u8>>(),
    ];
    prop::collection::vec(piece, 0..40).prop_map(|v| v.concat())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn response_parser_never_panics(line in firmware_line()) {
        let r = Response::parse(&line);
        // An acknowledgement is exactly `ok` or `error:N`, nothing else.
        let t = line.trim_matches(|c: char| c.is_whitespace() || c == '\0');
        if r.is_ack() {
            prop_assert!(t == "ok" || t.starts_with("error:"), "{line:?} → {r:?}");
        }
        let _ = StatusReport::parse(&line);
    }

    #[test]
    fn emulator_line_input_never_panics_or_hangs(
        bytes in sender_bytes(),
        flavor in prop::sample::select(vec![Flavor::Grbl, Flavor::GrblHal, Flavor::FluidNc]),
        chunk in 1usize..64,
    ) {
        let mut core = Core::new(Config {
            baud: None,
            settings: vec![(110, 60000.0), (111, 60000.0), (112, 60000.0), (120, 5000.0), (121, 5000.0), (122, 5000.0)],
            ..Config::flavored(flavor)
        });
        let mut t = 0.0;
        for part in bytes.chunks(chunk) {
            for b in part {
                core.receive(*b);
            }
            t += 0.002;
            core.tick(t);
        }
        // At most 2 s more of simulated time, then the firmware still answers.
        for _ in 0..200 {
            t += 0.01;
            core.tick(t);
        }
        core.out.clear();
        core.realtime(Realtime::StatusQuery);
        let out: Vec<u8> = core.out.drain(..).collect();
        let text = String::from_utf8_lossy(&out);
        prop_assert!(matches!(Response::parse(&text), Response::Status(_)), "{text:?}");
        // Every output byte is printable ASCII or a line end.
        prop_assert!(out.iter().all(|b| b.is_ascii_graphic() || b" \r\n".contains(b)), "{text:?}");
    }
}
