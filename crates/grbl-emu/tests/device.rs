//! grbl behind Oficina's `Machine` trait, against the emulator: a job with hold, resume,
//! stop, and a second start from the stop line that finishes the program.

mod common;
use common::*;
use oficina_grbl::GrblDevice;
use oficina_machine::{Command, Event, Job, Machine, Pace, State};
use std::sync::Arc;
use std::time::Duration;

fn events_until_end(
    dev: &mut GrblDevice,
    mut on_status: impl FnMut(&mut GrblDevice, &oficina_machine::Status),
) -> Event {
    for _ in 0..20_000 {
        match dev.next_event(Duration::from_millis(20)) {
            Some(Event::Status(s)) => on_status(dev, &s),
            Some(e @ (Event::JobEnd { .. } | Event::Alarm(_))) => return e,
            _ => {}
        }
    }
    panic!("no end of job within the bound");
}

#[test]
fn machine_trait_hold_resume_stop_and_restart_from_a_line() {
    let (_emu, ep) = emulator(Some(115_200));
    let mut dev = GrblDevice::new(&ep.to_string()).unwrap();
    dev.settings.resume.spindle_delay = 0.0;
    dev.settings.resume.safe_z = 2.0;
    dev.settings.journal =
        Some(std::env::temp_dir().join(format!("oficina-device-{}.journal", std::process::id())));
    let info = dev.connect().unwrap();
    assert!(info.firmware.starts_with("grbl 1.1h"), "{info:?}");
    let text = Arc::new(program(300));
    let job = Job {
        name: "dev.nc".into(),
        text: text.clone(),
        start_line: None,
        pace: Pace::Speed(1.0),
    };
    dev.start(job.clone()).unwrap();
    assert!(matches!(
        dev.start(job.clone()),
        Err(oficina_machine::MachineError::Busy(_))
    ));
    let mut step = 0;
    let mut stop_line = 0;
    let end = events_until_end(&mut dev, |dev, s| match step {
        0 if s.line > 50 && s.state == State::Run => {
            dev.command(Command::Hold).unwrap();
            step = 1;
        }
        1 if s.state == State::Hold => {
            dev.command(Command::Resume).unwrap();
            step = 2;
        }
        2 if s.line > 150 => {
            dev.command(Command::Stop).unwrap();
            stop_line = s.line;
            step = 3;
        }
        _ => {}
    });
    assert_eq!(step, 3, "held, resumed and stopped");
    assert!(
        matches!(
            end,
            Event::JobEnd {
                completed: false,
                ..
            }
        ),
        "{end:?}"
    );
    // Start again from the line it was stopped at (a few lines back is safe: re-traced).
    let again = Job {
        start_line: Some(stop_line),
        ..job
    };
    dev.start(again).unwrap();
    let end = events_until_end(&mut dev, |_, _| {});
    assert!(
        matches!(
            end,
            Event::JobEnd {
                completed: true,
                ..
            }
        ),
        "{end:?}"
    );
    let expected = oficina_grbl::replay(&job_of(&text), usize::MAX).work_pos();
    let st = dev.status();
    for a in 0..3 {
        assert!(
            (st.work_pos[a] - expected[a]).abs() < 0.01,
            "{:?} vs {expected:?}",
            st.work_pos
        );
    }
    // Idle: jog and unlock go straight to the firmware.
    dev.command(Command::Jog {
        delta: [1.0, 0.0, 0.0],
        feed: 3000.0,
    })
    .unwrap();
    assert!(dev.command(Command::FeedOverride(5.0)).is_err());
    dev.disconnect();
}

fn job_of(text: &str) -> oficina_grbl::StreamProgram {
    oficina_grbl::StreamProgram::from_text("dev.nc", text).unwrap()
}

#[test]
fn machine_trait_raw_lines_and_firmware_settings() {
    let (_emu, ep) = emulator(None);
    let mut dev = GrblDevice::new(&ep.to_string()).unwrap();
    // Nothing is open before connect.
    assert!(matches!(
        dev.raw_line("$I"),
        Err(oficina_machine::MachineError::NotConnected)
    ));
    dev.connect().unwrap();
    let info = dev.raw_line("$I").unwrap();
    assert!(
        info.lines.iter().any(|l| l.starts_with("[VER:1.1h")),
        "{info:?}"
    );
    assert_eq!(info.error, None);
    // A line the firmware refuses comes back with grbl's explanation.
    let bad = dev.raw_line("G5 X1").unwrap();
    assert!(bad.error.as_deref().unwrap_or("").contains("20"), "{bad:?}");
    dev.write_firmware_setting(110, 4321.0).unwrap();
    let all = dev.firmware_settings().unwrap();
    assert!(all.contains(&(110, 4321.0)), "{all:?}");
    // Checked before it reaches the firmware: $20 is a boolean.
    assert!(dev.write_firmware_setting(20, 2.0).is_err());
    // The virtual machine has no firmware language and says so.
    let profile = oficina_motion::resolve("grbl-router").unwrap();
    let mut vm = oficina_machine::VirtualMachine::new(profile);
    assert!(matches!(
        vm.raw_line("$$"),
        Err(oficina_machine::MachineError::Refused(_))
    ));
}

/// A caller that drains events until none is left (the web server's pump does, holding its
/// session lock) must come back from an idle board, which always has a fresh status to give.
#[test]
fn draining_an_idle_board_ends() {
    let (_emu, ep) = emulator(Some(115_200));
    let mut dev = GrblDevice::new(&ep.to_string()).unwrap();
    dev.connect().unwrap();
    for round in 0..5 {
        let mut n = 0;
        while let Some(e) = dev.next_event(Duration::ZERO) {
            n += 1;
            assert!(n <= 3, "round {round}: event {n} from an idle board: {e:?}");
        }
        std::thread::sleep(Duration::from_millis(60));
    }
    // And the status it gives is the board's: idle at the emulator's origin.
    assert_eq!(dev.status().state, State::Idle);
}

/// The line a page shows is the one the machine is on, not the last one acknowledged:
/// grblHAL (100 blocks, 1024 bytes) takes a short program whole before it has moved.
#[test]
fn the_line_shown_is_the_one_the_machine_is_on() {
    let emu = oficina_grbl_emu::Emulator::start(oficina_grbl_emu::Config::flavored(
        oficina_grbl_emu::Flavor::GrblHal,
    ));
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let mut dev = GrblDevice::new(&format!("tcp://{addr}")).unwrap();
    dev.connect().unwrap();
    // Four sides of 30 mm at 900 mm/min: 2 s each; lines 2 to 5.
    let text = "G21 G90 G0 X0 Y0\nG1 X30 F900\nY30\nX0\nY0\nM2\n";
    dev.start(Job {
        name: "square.nc".into(),
        text: Arc::new(text.into()),
        start_line: None,
        pace: Pace::Speed(1.0),
    })
    .unwrap();
    let mut seen = Vec::new();
    let end = events_until_end(&mut dev, |_, s| {
        let [x, y, _] = s.work_pos;
        // Well inside one side (not at a corner), the line is that side's.
        let side = if y.abs() < 1e-6 && (1.0..29.0).contains(&x) {
            Some(2)
        } else if (x - 30.0).abs() < 1e-6 && (1.0..29.0).contains(&y) {
            Some(3)
        } else if (y - 30.0).abs() < 1e-6 && (1.0..29.0).contains(&x) {
            Some(4)
        } else {
            None
        };
        if let (Some(line), State::Run) = (side, &s.state) {
            seen.push((line, s.line));
        }
    });
    assert!(
        matches!(
            end,
            Event::JobEnd {
                completed: true,
                ..
            }
        ),
        "{end:?}"
    );
    assert!(seen.len() >= 5, "too few reports on the sides: {seen:?}");
    // The status and the position come from the same report, the line from the one
    // before it: allow one report of lag, never a line ahead.
    let ahead: Vec<_> = seen.iter().filter(|(want, got)| *got > *want).collect();
    assert!(
        ahead.is_empty(),
        "lines ahead of the machine: {ahead:?} of {seen:?}"
    );
    assert!(
        seen.iter().filter(|(want, got)| want == got).count() * 10 >= seen.len() * 8,
        "{seen:?}"
    );
}
