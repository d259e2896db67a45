//! The virtual machine as a `Machine`: jobs to their end point, soft limits, feed hold and resume, feed override mid-move.
use oficina_machine::{Command, Event, Job, Machine, Pace, State, VirtualMachine};
use oficina_motion::Profile;
use std::sync::Arc;
use std::time::Duration;

fn vm() -> VirtualMachine {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../profiles/grbl-router.toml");
    let mut profile = Profile::load(&path).unwrap();
    // These programs are written in machine coordinates: no stored work offset.
    profile.work_offset = [0.0; 3];
    let mut m = VirtualMachine::new(profile);
    m.connect().unwrap();
    m
}

fn job(text: &str, pace: Pace) -> Job {
    Job {
        name: "t.nc".into(),
        text: Arc::new(text.into()),
        start_line: None,
        pace,
    }
}

fn wait_end(m: &mut VirtualMachine) -> (bool, Vec<Event>) {
    let mut seen = Vec::new();
    loop {
        match m.next_event(Duration::from_secs(30)) {
            Some(Event::JobEnd { completed, .. }) => return (completed, seen),
            Some(e) => seen.push(e),
            None => panic!("no end"),
        }
    }
}

#[test]
fn runs_a_job_instantly_to_its_end_point() {
    let mut m = vm();
    m.start(job(
        "G21 G90\nG0 X10 Y10\nG1 X100 Y50 F3000\nG2 X120 Y70 I0 J20\nM2\n",
        Pace::Instant,
    ))
    .unwrap();
    let (done, _) = wait_end(&mut m);
    assert!(done);
    let st = m.status();
    assert_eq!(st.state, State::Idle);
    assert!(
        (st.machine_pos[0] - 120.0).abs() < 1e-6 && (st.machine_pos[1] - 70.0).abs() < 1e-6,
        "{:?}",
        st.machine_pos
    );
}

#[test]
fn soft_limits_refuse_the_job_before_any_motion() {
    let mut m = vm();
    m.start(job("G90 G1 X100 F3000\nG1 X900\nM2\n", Pace::Instant))
        .unwrap();
    let (done, events) = wait_end_or_alarm(&mut m);
    assert!(!done);
    assert!(events.iter().any(|e| matches!(e, Event::Alarm(a) if a.contains("outside the travel") && a.contains("line 2"))), "{events:?}");
    assert_eq!(m.status().machine_pos, [0.0, 0.0, 0.0]);
    assert!(matches!(m.status().state, State::Alarm(_)));
    m.command(Command::Unlock).unwrap();
    assert_eq!(m.status().state, State::Idle);
}

fn wait_end_or_alarm(m: &mut VirtualMachine) -> (bool, Vec<Event>) {
    let mut seen = Vec::new();
    while let Some(e) = m.next_event(Duration::from_secs(10)) {
        let alarm = matches!(e, Event::Alarm(_));
        let end = matches!(
            e,
            Event::JobEnd {
                completed: true,
                ..
            }
        );
        seen.push(e);
        if alarm {
            return (false, seen);
        }
        if end {
            return (true, seen);
        }
    }
    (false, seen)
}

#[test]
fn feed_hold_decelerates_on_the_path_and_resume_finishes() {
    let mut m = vm();
    // 400 mm at 6000 mm/min: 4 s of machine time, run at 8x.
    m.start(job("G90 G1 X400 F6000\nM2\n", Pace::Speed(8.0)))
        .unwrap();
    std::thread::sleep(Duration::from_millis(200));
    if let Err(e) = m.command(Command::Hold) {
        let evs: Vec<Event> = std::iter::from_fn(|| m.next_event(Duration::from_millis(10)))
            .filter(|e| !matches!(e, Event::Status(_)))
            .collect();
        panic!("{e}: {evs:?}");
    }
    let mut last_x = 0.0;
    loop {
        match m.next_event(Duration::from_secs(10)).unwrap() {
            Event::Status(s) => {
                assert!(s.machine_pos[0] + 1e-9 >= last_x, "moved backwards");
                assert!(s.machine_pos[0] - last_x < 100.0 * 0.005 + 1e-6, "jumped");
                assert!(s.machine_pos[1].abs() < 1e-9, "left the path");
                last_x = s.machine_pos[0];
                if s.state == State::Hold {
                    break;
                }
            }
            e => panic!("{e:?}"),
        }
    }
    assert!(last_x > 0.0 && last_x < 400.0);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(m.status().machine_pos[0], last_x, "moved while held");
    m.command(Command::Resume).unwrap();
    let (done, _) = wait_end(&mut m);
    assert!(done);
    assert!((m.status().machine_pos[0] - 400.0).abs() < 1e-6);
}

/// Machine time of G1 X700 F3000 on the router (a = 300 mm/s²) when the override drops to
/// 50 % at x = `xc` while cruising at 50 mm/s: closed form.
fn override_half_time(xc: f64) -> f64 {
    let ramp = 50.0 / 300.0; // 0 → 50 mm/s, 25·ramp mm
    let before = ramp + (xc - 25.0 * ramp) / 50.0;
    let t = 25.0 / 300.0; // 50 → 25 and 25 → 0
    before + 2.0 * t + (700.0 - xc - 37.5 * t - 12.5 * t) / 25.0
}

#[test]
fn feed_override_replans_the_rest_of_a_running_move() {
    let mut m = vm();
    // 14.2 s of machine time at 40x.
    m.start(job("G90 G1 X700 F3000\nM2\n", Pace::Speed(40.0)))
        .unwrap();
    let mut last: Option<oficina_machine::Status> = None;
    let mut sent = false;
    let mut bracket = None;
    let seconds = loop {
        match m.next_event(Duration::from_secs(30)).expect("event") {
            Event::Status(s) => {
                if !sent && s.machine_pos[0] > 150.0 {
                    m.command(Command::FeedOverride(0.5)).unwrap();
                    sent = true;
                }
                if let Some(p) = &last {
                    let dt = s.elapsed - p.elapsed;
                    if dt > 1e-9 {
                        let acc = (s.feed - p.feed) / 60.0 / dt;
                        assert!(acc.abs() <= 300.0 * (1.0 + 1e-6), "{acc} mm/s² at {s:?}");
                    }
                    assert!(s.feed <= 3000.0 + 1e-6);
                    if bracket.is_none() && s.feed_override == 0.5 {
                        // The cut lies between the last status before and this one.
                        bracket = Some((p.machine_pos[0], s.machine_pos[0]));
                    }
                }
                last = Some(s);
            }
            Event::JobEnd { completed, seconds } => {
                assert!(completed);
                break seconds;
            }
            e => panic!("{e:?}"),
        }
    };
    let (lo, hi) = bracket.expect("override seen");
    // A later cut leaves less to run slowly: the time falls as the cut point advances.
    let (t_lo, t_hi) = (override_half_time(hi), override_half_time(lo));
    assert!(
        seconds >= t_lo - 1e-6 && seconds <= t_hi + 1e-6,
        "{seconds} not within [{t_lo}, {t_hi}]"
    );
    // Roughly doubled: the unchanged job takes 14.17 s.
    assert!(seconds > 14.17 + 0.9 * (700.0 - hi) / 50.0, "{seconds}");
    assert!((m.status().machine_pos[0] - 700.0).abs() < 1e-6);
}
