//! Streaming against the emulator: the whole job arrives once, in order, the RX buffer
//! never overflows, and the final position is the program's.

mod common;
use common::*;
use oficina_grbl::{Mode, StreamEnd};

#[test]
fn character_counting_stream_completes_exactly() {
    let (emu, ep) = emulator(None);
    let mut s = connect(&ep);
    assert_eq!(s.mode, Mode::CharCounting(127), "sized from [OPT:V,15,128]");
    let job = job(400);
    let report = s.stream(&job, 0, None, None, &mut quiet());
    assert_eq!(
        report.end,
        StreamEnd::Completed,
        "{}",
        report.describe(&job)
    );
    assert!(report.max_in_flight <= 127);
    let stats = emu.stats();
    assert_eq!(stats.rx_overflows, 0);
    let executed = emu.with_core(|c| c.executed.clone());
    let sent: Vec<String> = job.lines.iter().map(|l| l.text.clone()).collect();
    assert_eq!(executed, sent);
    let expected = oficina_grbl::replay(&job, job.len()).work_pos();
    assert_eq!(report.work_pos, Some(expected));
}

#[test]
fn send_response_mode_also_completes() {
    let (emu, ep) = emulator(None);
    let mut s = oficina_grbl::Sender::connect(
        &ep,
        oficina_grbl::SenderOptions {
            mode: Some(Mode::SendResponse),
            ..options()
        },
    )
    .unwrap();
    let job = job(60);
    let report = s.stream(&job, 0, None, None, &mut quiet());
    assert_eq!(report.end, StreamEnd::Completed);
    assert!(report.max_in_flight <= 30);
    assert_eq!(emu.with_core(|c| c.executed.len()), job.len());
}

#[test]
fn operator_hold_resume_stop_then_resume_from_the_located_line() {
    use oficina_grbl::GrblState;
    use oficina_grbl::ResumeOptions;
    use oficina_grbl::{Control, Notice};
    let (emu, ep) = emulator(Some(115_200));
    let mut s = connect(&ep);
    let job = job(300);
    let (tx, rx) = std::sync::mpsc::channel();
    let mut acks = 0;
    let mut held_seen = false;
    let mut step = 0;
    let report = s.stream(&job, 0, None, Some(&rx), &mut |n| match n {
        Notice::Progress { acked, .. } => {
            acks = acked;
            if acked == 60 && step == 0 {
                tx.send(Control::Hold).unwrap();
                step = 1;
            }
        }
        Notice::Status(st) => {
            if step == 1 && st.state == GrblState::Hold(0) {
                held_seen = true;
                tx.send(Control::Resume).unwrap();
                step = 2;
            } else if step == 2 && acks >= 150 {
                tx.send(Control::Stop).unwrap();
                step = 3;
            }
        }
        _ => {}
    });
    assert!(held_seen, "the machine reached Hold:0 after a hold");
    assert_eq!(report.end, StreamEnd::Stopped);
    let at = report
        .resume
        .clone()
        .expect("a stop at rest names the resume line");
    assert!(at.index >= 100 && at.index <= report.acked_end, "{at:?}");
    // The machine was reset at rest: idle, not in alarm, position kept.
    assert_eq!(s.status().unwrap().state, GrblState::Idle);
    let opts = ResumeOptions {
        safe_z: 2.0,
        plunge_feed: 3000.0,
        spindle_delay: 0.0,
    };
    s.run_preamble(&job, at.index, &opts).unwrap();
    let done = s.stream(&job, at.index, None, None, &mut quiet());
    assert_eq!(done.end, StreamEnd::Completed, "{}", done.describe(&job));
    assert_eq!(emu.stats().rx_overflows, 0);
    let expected = oficina_grbl::replay(&job, job.len()).work_pos();
    assert_eq!(done.work_pos, Some(expected));
}

/// Ten laps of the same square at the same depth: every stop position lies on ten lines.
/// With `$10=3` the sender reads `Bf:` and knows which one the machine was executing.
#[test]
fn stop_on_a_path_that_retraces_itself_resumes_on_the_right_lap() {
    use oficina_grbl::Endpoint;
    use oficina_grbl::ResumeOptions;
    use oficina_grbl::{Control, Notice};
    use oficina_grbl_emu::Emulator;
    let mut cfg = config(Some(115_200));
    cfg.settings.push((10, 3.0));
    let emu = Emulator::start(cfg);
    let ep = Endpoint::Tcp {
        addr: emu.serve_tcp("127.0.0.1:0").unwrap().to_string(),
    };
    let mut text = String::from("G21G90\nG0Z1\nG0X0Y0\nG1Z-1F9000\n");
    for _lap in 0..10 {
        for k in 1..=80 {
            let (x, y) = match (k - 1) / 20 {
                0 => (k as f64, 0.0),
                1 => (20.0, (k - 20) as f64),
                2 => (20.0 - (k - 40) as f64, 20.0),
                _ => (0.0, 20.0 - (k - 60) as f64),
            };
            text += &format!("G1X{x}Y{y}\n");
        }
    }
    text += "G0Z1\n";
    let job = oficina_grbl::StreamProgram::from_text("laps.nc", &text).unwrap();
    let mut s = connect(&ep);
    let (tx, rx) = std::sync::mpsc::channel();
    let mut sent_stop = false;
    let report = s.stream(&job, 0, None, Some(&rx), &mut |n| {
        if let Notice::Progress { acked, .. } = n {
            if acked >= 450 && !sent_stop {
                tx.send(Control::Stop).unwrap();
                sent_stop = true;
            }
        }
    });
    assert_eq!(report.end, StreamEnd::Stopped);
    let at = report.resume.clone().unwrap();
    // Lap 6 of 10 (lines 404..483), nowhere near the first laps on the same path.
    assert!(
        at.index > 400 && at.index <= report.acked_end,
        "{at:?} {report:?}"
    );
    let opts = ResumeOptions {
        safe_z: 1.0,
        plunge_feed: 2000.0,
        spindle_delay: 0.0,
    };
    let pre = oficina_grbl::resume_preamble(&job, at.index, &opts).unwrap();
    s.run_preamble(&job, at.index, &opts).unwrap();
    let done = s.stream(&job, at.index, None, None, &mut quiet());
    assert_eq!(done.end, StreamEnd::Completed, "{}", done.describe(&job));
    let mut ran = emu.with_core(|c| c.executed.clone());
    let p = ran.iter().position(|l| *l == pre[0]).unwrap();
    ran.drain(p..p + pre.len());
    let expected: Vec<String> = job.lines.iter().map(|l| l.text.clone()).collect();
    assert_eq!(
        ran.len(),
        expected.len(),
        "every line ran once: none skipped, none twice"
    );
    assert_eq!(ran, expected);
}

#[test]
fn continuous_jog_moves_at_the_feed_and_cancel_stops_it() {
    use oficina_grbl::GrblState;
    use oficina_grbl::LinkEvent;
    use oficina_grbl::Response;
    use oficina_grbl::{jog_step_line, ContinuousJog};
    use std::time::{Duration, Instant};
    let (_emu, ep) = emulator(None);
    let mut s = connect(&ep);
    // A step first: exactly 2 mm.
    let r = s
        .command(&jog_step_line('Y', 2.0, 6000.0).unwrap())
        .unwrap();
    assert_eq!(r.error, None);
    let mut jog = ContinuousJog::start(&s, 'X', 1.0, 600.0).unwrap();
    let t0 = Instant::now();
    let mut acks = 0;
    while t0.elapsed() < Duration::from_millis(800) {
        jog.keep_up(&mut s, acks).unwrap();
        acks = 0;
        while let Some(ev) = s.link().recv(Duration::from_millis(5)) {
            match ev {
                LinkEvent::Line(Response::Ok, _) => acks += 1,
                LinkEvent::Line(Response::Error(e), _) => panic!("jog rejected: error:{e}"),
                _ => {}
            }
        }
    }
    let sent = jog.increments_sent;
    jog.stop(&mut s).unwrap();
    let st = loop {
        let st = s.status().unwrap();
        if st.state == GrblState::Idle {
            break st;
        }
    };
    let m = st.mpos.unwrap();
    // Each increment is 10 mm/s × 25 ms = 0.25 mm: it moved, never beyond what was sent,
    // and after the cancel it stays put.
    assert!(
        m[0] > 0.0 && m[0] <= sent as f64 * 0.25 + 1e-9,
        "x {} after {sent} increments",
        m[0]
    );
    assert_eq!(s.status().unwrap().mpos.unwrap()[0], m[0]);
    assert!((m[1] - 2.0).abs() < 1e-9);
    assert!(sent >= 3);
}

#[test]
fn check_mode_reports_every_bad_line_without_moving() {
    let (emu, ep) = emulator(None);
    let mut s = connect(&ep);
    let mut text = common::program(100);
    text = text.replacen("G1 X", "G1 Q1 X", 1); // error:20 on the first move
    text.push_str("G2 X1\n"); // error:35 near the end
    let job = oficina_grbl::StreamProgram::from_text("c.nc", &text).unwrap();
    let bad = s.check_job(&job).unwrap();
    let codes: Vec<u8> = bad.iter().map(|(_, c)| *c).collect();
    assert_eq!(codes, vec![20, 35], "{bad:?}");
    assert_eq!(job.lines[bad[0].0].text, "G1Q1X0.400Y0.000");
    assert_eq!(emu.with_core(|c| c.mpos), [0.0; 3]);
    // Back to normal: a move now moves.
    assert_eq!(s.command("G0X1").unwrap().error, None);
    assert_eq!(s.wait_at_rest().unwrap(), [1.0, 0.0, 0.0]);
}

#[test]
fn settings_overrides_and_safety_door() {
    use oficina_grbl::GrblState;
    use oficina_grbl::Realtime;
    let (_emu, ep) = emulator(None);
    let mut s = connect(&ep);
    let all = oficina_grbl::read_settings(&mut s).unwrap();
    assert_eq!(all.len(), 34);
    let x = all.iter().find(|st| st.number == 110).unwrap();
    assert_eq!(x.describe(), "$110=60000 (X-axis maximum rate, mm/min)");
    assert_eq!(
        oficina_grbl::write_setting(&mut s, 111, 4321.5)
            .unwrap()
            .value,
        4321.5
    );
    // grbl's own rule: soft limits need homing enabled (error:10).
    assert!(oficina_grbl::write_setting(&mut s, 20, 1.0)
        .unwrap_err()
        .contains("error:10"));
    // Overrides: +10 % twice on feed, rapid to 25 %.
    for r in [
        Realtime::FeedOverridePlus10,
        Realtime::FeedOverridePlus10,
        Realtime::RapidOverride25,
    ] {
        s.realtime(r).unwrap();
    }
    let ov = (0..40)
        .find_map(|_| s.status().unwrap().overrides)
        .expect("Ov appears in status reports");
    assert_eq!(ov, (120, 25, 100));
    // Safety door while idle, then cycle start closes it.
    s.realtime(Realtime::SafetyDoor).unwrap();
    assert_eq!(s.status().unwrap().state, GrblState::Door(0));
    s.realtime(Realtime::CycleStart).unwrap();
    assert_eq!(s.status().unwrap().state, GrblState::Idle);
}

#[test]
fn soft_limit_alarm_mid_job_is_reported_and_the_machine_left_resumable() {
    use oficina_grbl::Endpoint;
    use oficina_grbl_emu::Emulator;
    let mut cfg = config(None);
    cfg.settings.extend([(22, 1.0), (20, 1.0)]);
    let emu = Emulator::start(cfg);
    let ep = Endpoint::Tcp {
        addr: emu.serve_tcp("127.0.0.1:0").unwrap().to_string(),
    };
    let mut s = connect(&ep);
    assert_eq!(s.command("$H").unwrap().error, None);
    let text = "G21G90\nG0X-5Y-5\nG1X-10F3000\nG1X-10Y-250\nG1X-20\n";
    let job = oficina_grbl::StreamProgram::from_text("limits.nc", text).unwrap();
    let report = s.stream(&job, 0, None, None, &mut quiet());
    assert_eq!(report.end, StreamEnd::Alarm(2));
    assert!(
        report.describe(&job).contains("Soft limit"),
        "{}",
        report.describe(&job)
    );
    // grbl holds and resets on a soft-limit violation, so the moves queued before the bad
    // one did not finish either: the resume point is at or before it, never after, and the
    // machine is unlocked and at rest inside its travel.
    let at = s
        .recover(
            &job,
            report.certain,
            report.sent_end,
            report.acked_end,
            true,
        )
        .unwrap();
    assert!(at.index <= 3, "{at:?}");
    let st = s.status().unwrap();
    assert_eq!(st.state, oficina_grbl::GrblState::Idle);
    assert!(st.mpos.unwrap().iter().all(|v| *v <= 0.0 && *v >= -200.0));
}

#[test]
fn streaming_from_past_the_end_finishes_at_once() {
    let (_emu, ep) = emulator(None);
    let mut s = connect(&ep);
    let job = job(5);
    let r = s.stream(&job, job.len(), None, None, &mut quiet());
    assert_eq!(
        r.end,
        StreamEnd::PositionMismatch {
            expected: oficina_grbl::replay(&job, job.len()).work_pos(),
            actual: [0.0; 3]
        }
    );
}

#[test]
fn connecting_to_a_busy_machine_sizes_the_window_once_it_rests() {
    let (_emu, ep) = emulator(None);
    let mut first = connect(&ep);
    // A 3-second move keeps the machine busy while a second sender connects.
    assert_eq!(first.command("G1X50F1000").unwrap().error, None);
    drop(first);
    let mut s = connect(&ep);
    assert_eq!(
        s.mode,
        Mode::SendResponse,
        "$I is refused while running (error:8)"
    );
    let job = oficina_grbl::StreamProgram::from_text("busy.nc", "G1X50F1000\n").unwrap();
    let at = s.recover(&job, 0, 1, 1, false).unwrap();
    assert_eq!(s.mode, Mode::CharCounting(127));
    assert_eq!(at.index, 1, "{at:?}");
}
