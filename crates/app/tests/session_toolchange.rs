//! The page's session on grbl firmware (the emulator) with a tool change: the prompt comes
//! as a message, the snapshot shows the state `paused` and the change asked for, and
//! Resume finishes the job (and polling after it returns: real firmware answers every
//! idle poll with a status).

use oficina_app::{JobRequest, Session, SessionEvent};
use oficina_grbl_emu::{Config, Emulator};
use oficina_machine::Command;
use std::sync::Arc;
use std::time::{Duration, Instant};

#[test]
fn a_tool_change_shows_in_the_snapshot_until_resume() {
    let emu = Emulator::start(Config {
        baud: None,
        settings: vec![(110, 60000.0), (111, 60000.0), (112, 60000.0)],
        ..Config::default()
    });
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let mut s = Session::open(&format!("tcp://{addr}")).unwrap();
    let text = "G21 G90\nG0 X1\n(T2 D=6 - ball)\nT2 M6\nG0 X2\nM30\n";
    s.start(JobRequest {
        name: "t.nc".into(),
        text: Arc::new(text.into()),
        from_line: None,
        speed: None,
    })
    .unwrap();
    let t = Instant::now();
    let mut asked = None;
    let mut resumed = false;
    let end = loop {
        assert!(t.elapsed() < Duration::from_secs(60), "no end");
        let events = s.poll(Duration::from_millis(20));
        for e in &events {
            if let SessionEvent::Message { text } = e {
                if text.starts_with("change to tool T2") {
                    asked = Some(text.clone());
                }
            }
        }
        if let Some(e) = events
            .iter()
            .find(|e| matches!(e, SessionEvent::JobEnd { .. }))
        {
            break e.clone();
        }
        let snap = s.snapshot();
        if let (Some(tc), false) = (&snap.tool_change, resumed) {
            assert_eq!(snap.state, "paused");
            assert_eq!((tc.tool, tc.line), (2, 4));
            assert!(tc.prompt.contains("T2 D=6 - ball"), "{}", tc.prompt);
            s.command(Command::Resume).unwrap();
            resumed = true;
        }
    };
    assert!(resumed && asked.is_some());
    assert!(
        matches!(
            end,
            SessionEvent::JobEnd {
                completed: true,
                ..
            }
        ),
        "{end:?}"
    );
    assert_eq!(s.snapshot().tool_change, None);
}
