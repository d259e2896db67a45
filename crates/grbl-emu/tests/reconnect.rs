//! The link life cycle against the emulator: retries until the firmware appears, then gives
//! up on a port where none ever answers.

use oficina_grbl::Endpoint;
use oficina_grbl::SenderOptions;
use oficina_grbl::{connect_with_retry, LinkState, RetryPolicy};
use oficina_grbl_emu::{Config, Emulator};
use std::time::Duration;

#[test]
fn retries_until_the_firmware_appears_then_gives_up_when_it_does_not() {
    // Reserve a port, free it, and bring the emulator up on it a little later.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap();
    let ep = Endpoint::Tcp {
        addr: port.to_string(),
    };
    let starter = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(600));
        let emu = Emulator::start(Config {
            baud: None,
            ..Config::default()
        });
        emu.serve_tcp(&port.to_string()).unwrap();
        std::thread::sleep(Duration::from_secs(3));
        drop(emu);
    });
    let mut states = Vec::new();
    let policy = RetryPolicy {
        deadline: Duration::from_secs(10),
        first_pause: Duration::from_millis(100),
        max_pause: Duration::from_millis(400),
    };
    let s = connect_with_retry(&ep, &SenderOptions::default(), &policy, &mut |st| {
        states.push(st.clone())
    })
    .unwrap();
    assert!(
        states
            .iter()
            .any(|s| matches!(s, LinkState::Waiting { .. })),
        "{states:?}"
    );
    assert!(matches!(states.last(), Some(LinkState::Connected { .. })));
    assert!(s.firmware.starts_with("1.1h"), "{}", s.firmware);
    drop(s);
    starter.join().unwrap();

    let dead = Endpoint::Tcp {
        addr: "127.0.0.1:1".into(),
    };
    let quick = RetryPolicy {
        deadline: Duration::from_millis(500),
        ..policy
    };
    let mut last = None;
    let e = connect_with_retry(&dead, &SenderOptions::default(), &quick, &mut |st| {
        last = Some(st.clone())
    })
    .err()
    .unwrap();
    assert!(e.to_string().contains("gave up after"), "{e}");
    assert!(matches!(last, Some(LinkState::GaveUp { .. })));
}
