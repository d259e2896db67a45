//! The session over grbl firmware (the emulator), as the page shows it.

use oficina_app::{JobRequest, Session};
use oficina_grbl_emu::{Config, Emulator};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// grbl's status says only `Alarm`; the page must still name which (a probe that touched
/// nothing: ALARM:5) and what it means, until the machine leaves the alarm.
#[test]
fn an_alarm_is_shown_with_its_number_until_it_is_cleared() {
    let emu = Emulator::start(Config::default());
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let mut s = Session::open(&format!("tcp://{addr}")).unwrap();
    s.start(JobRequest {
        name: "probe.nc".into(),
        // No stock, no plate: nothing to touch.
        text: Arc::new("G21 G91\nG38.2 Z-5 F200\nG90\nM2\n".into()),
        from_line: None,
        speed: None,
    })
    .unwrap();
    let t = Instant::now();
    let snap = loop {
        s.poll(Duration::from_millis(20));
        let snap = s.snapshot();
        if snap.state == "alarm" && snap.job.as_ref().is_some_and(|j| j.completed.is_some()) {
            break snap;
        }
        assert!(t.elapsed() < Duration::from_secs(60), "{snap:?}");
    };
    let alarm = snap.alarm.unwrap();
    assert!(alarm.contains("ALARM:5"), "{alarm}");
    assert!(
        snap.alarm_meaning.unwrap().to_lowercase().contains("probe"),
        "{alarm}"
    );
    // Unlocked, the alarm is gone for good.
    s.command(oficina_machine::Command::Unlock).unwrap();
    let t = Instant::now();
    loop {
        s.poll(Duration::from_millis(20));
        let snap = s.snapshot();
        if snap.state == "idle" {
            assert!(snap.alarm.is_none());
            break;
        }
        assert!(t.elapsed() < Duration::from_secs(20), "{snap:?}");
    }
}
