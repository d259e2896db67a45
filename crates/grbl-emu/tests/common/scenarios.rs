//! The four failures seen on real grblHAL firmware, each as a scenario run the same way
//! against the emulator (CI) and against grblHAL's Simulator (when it is available).

use super::coverage::{self, Piece};
use oficina_grbl::Endpoint;
use oficina_grbl::GrblState;
use oficina_grbl::Realtime;
use oficina_grbl::ResumeOptions;
use oficina_grbl::StreamProgram;
use oficina_grbl::{Control, Notice, Sender, SenderOptions, StreamEnd, StreamReport};
use std::sync::mpsc;
use std::time::Duration;

pub(crate) fn options() -> SenderOptions {
    SenderOptions {
        status_interval: Duration::from_millis(100),
        stall_after: Duration::from_millis(1500),
        reply_timeout: Duration::from_secs(30),
        ..SenderOptions::default()
    }
}

pub(crate) fn connect(ep: &Endpoint) -> Sender {
    Sender::connect(ep, options()).expect("connect")
}

/// Rates and accelerations both firmwares accept, fast enough for short tests.
pub(crate) fn configure(s: &mut Sender) {
    for (n, v) in [
        (110, 6000.0),
        (111, 6000.0),
        (112, 3000.0),
        (120, 400.0),
        (121, 400.0),
        (122, 200.0),
    ] {
        let r = s.command(&format!("${n}={v}")).expect("setting");
        assert_eq!(r.error, None, "${n}={v} refused");
        s.settings.insert(n, v);
    }
}

pub(crate) fn resume_options() -> ResumeOptions {
    ResumeOptions {
        safe_z: 3.0,
        plunge_feed: 600.0,
        spindle_delay: 0.0,
    }
}

/// Bug 4: the reset banner of the firmware is recognised; a reset is answered.
pub(crate) fn reset_is_recognised(ep: &Endpoint) -> Sender {
    let mut s = connect(ep);
    s.reset()
        .expect("the firmware's reset banner is recognised");
    // And a stop (hold, rest, reset) ends with the machine answering, not a timeout.
    let st = s.status().expect("status after reset");
    assert_eq!(st.state, GrblState::Idle);
    s
}

/// Bug 1: every status query is lost for a while after the last `ok`, during a long move.
/// "done" must still mean at rest at the end of the move. `drop_queries(true/false)` makes
/// the firmware (or its link) lose queries.
pub(crate) fn done_means_at_rest(
    ep: &Endpoint,
    drop_queries: &(dyn Fn(bool) + Sync),
) -> StreamReport {
    let mut s = connect(ep);
    configure(&mut s);
    let job = StreamProgram::from_text("long-move.nc", "G21G90G94\nG1X110F3000\n").unwrap();
    std::thread::scope(|scope| {
        let mut dropping = false;
        let report = s.stream(&job, 0, None, None, &mut |n| {
            if let Notice::Progress { acked, total, .. } = n {
                if acked == total && !dropping {
                    dropping = true;
                    drop_queries(true);
                    scope.spawn(|| {
                        std::thread::sleep(Duration::from_millis(3000));
                        drop_queries(false);
                    });
                }
            }
        });
        assert_eq!(
            report.end,
            StreamEnd::Completed,
            "{}",
            report.describe(&job)
        );
        assert_eq!(
            report.work_pos,
            Some([110.0, 0.0, 0.0]),
            "\"done\" must come with the machine at rest at the end of the move"
        );
        drop_queries(false);
        let st = s.status().unwrap();
        assert_eq!(st.state, GrblState::Idle, "{st:?}");
        report
    })
}

/// Bug 2: a job short enough to be acknowledged at once (grblHAL buffers 100 blocks and
/// 1024 bytes); hold, resume, an override and stop still act until the machine is idle.
pub(crate) fn controls_work_until_idle(ep: &Endpoint) -> StreamReport {
    let mut s = connect(ep);
    configure(&mut s);
    let job = StreamProgram::from_text(
        "square.nc",
        "G21G90G94\nG1X20F1500\nY20\nX0\nY0\nX20\nY20\nX0\nY0\n",
    )
    .unwrap();
    let (tx, rx) = mpsc::channel();
    let mut phase = 0;
    let mut held_at = None;
    let mut saw_override = false;
    let report = s.stream(&job, 0, None, Some(&rx), &mut |n| match n {
        Notice::Progress { acked, total, .. } if acked == total && phase == 0 => {
            phase = 1;
            tx.send(Control::Hold).unwrap();
            tx.send(Control::Realtime(Realtime::FeedOverrideMinus10))
                .unwrap();
        }
        Notice::Status(st) => {
            if st.overrides.is_some_and(|o| o.0 == 90) {
                saw_override = true;
            }
            match (phase, &st.state) {
                (1, GrblState::Hold(0)) => {
                    held_at = st.mpos.clone();
                    phase = 2;
                    tx.send(Control::Resume).unwrap();
                }
                (2, GrblState::Run) if st.mpos != held_at => {
                    phase = 3;
                    tx.send(Control::Stop).unwrap();
                }
                _ => {}
            }
        }
        _ => {}
    });
    assert_eq!(phase, 3, "hold, resume and stop were all seen to act");
    assert!(held_at.is_some());
    assert!(saw_override, "the feed override reached the firmware");
    assert_eq!(report.end, StreamEnd::Stopped, "{}", report.describe(&job));
    let at = report.resume.clone().expect("a resume point");
    assert!(at.index < job.len(), "{at:?}");
    assert!(report.acked_end == job.len());
    report
}

/// Bug 3: stopped in the middle of a run of 1 mm lines, the resume point is the line that
/// holds the reported position (and the point itself), never a later one; resuming from
/// there leaves no gap and cuts nothing twice (the witness: `made()`, the motion record).
pub(crate) fn resume_from_the_position(
    ep: &Endpoint,
    clear_record: &dyn Fn(),
    made: &dyn Fn() -> Vec<Piece>,
) {
    let mut s = connect(ep);
    configure(&mut s);
    let mut text = String::from("G21G90G94\nG0X0Y0Z0\n");
    for i in 1..=40 {
        text += &format!("G1X{i}F600\n");
    }
    let job = StreamProgram::from_text("ruler.nc", &text).unwrap();
    clear_record();
    let (tx, rx) = mpsc::channel();
    let mut stopped = false;
    let report = s.stream(&job, 0, None, Some(&rx), &mut |n| {
        if let Notice::Status(st) = n {
            if !stopped && st.mpos.as_ref().is_some_and(|m| m[0] > 15.2) {
                stopped = true;
                tx.send(Control::Stop).unwrap();
            }
        }
    });
    assert_eq!(report.end, StreamEnd::Stopped, "{}", report.describe(&job));
    let pos = report.work_pos.expect("stop position");
    let at = report.resume.clone().expect("resume point");
    // Line index k (k ≥ 2) runs from X(k-2) to X(k-1).
    let x = pos[0];
    let want = if (x - x.round()).abs() < 1e-6 {
        x.round() as usize + 2
    } else {
        x.ceil() as usize + 1
    };
    assert_eq!(
        at.index, want,
        "stopped at X{x}: the resume line must hold that position ({at:?})"
    );
    if (x - x.round()).abs() >= 1e-6 {
        // Inside a straight line: it is finished from the stop point.
        assert_eq!(at.entry, Some(pos), "{at:?}");
    }
    s.run_preamble_at(&job, at.index, at.entry, &resume_options())
        .unwrap();
    let done = s.stream(&job, at.index, None, None, &mut |_| {});
    assert_eq!(done.end, StreamEnd::Completed, "{}", done.describe(&job));
    let c = coverage::check(&coverage::program_cuts(&job), &made(), 0.01);
    assert!(
        c.worst_gap <= 0.01 && c.worst_double <= 0.01,
        "stopped at X{x}, resumed at {at:?}: {c:?}"
    );
}

/// One stop at `stop_after` seconds into the relief job, then a resume to the end: the
/// coverage of the program path by the motion made.
pub(crate) fn stop_and_resume(
    s: &mut Sender,
    job: &StreamProgram,
    stop_after: Duration,
    made: &dyn Fn() -> Vec<Piece>,
) -> (coverage::Coverage, StreamReport) {
    let (tx, rx) = mpsc::channel();
    let (finished, wait) = mpsc::channel::<()>();
    let report = std::thread::scope(|scope| {
        let tx2 = tx.clone();
        scope.spawn(move || {
            // The stop comes after `stop_after`, unless the job ended first.
            if wait.recv_timeout(stop_after).is_err() {
                let _ = tx2.send(Control::Stop);
            }
        });
        let r = s.stream(job, 0, None, Some(&rx), &mut |_| {});
        let _ = finished.send(());
        r
    });
    drop(tx);
    if report.end == StreamEnd::Stopped {
        let at = report
            .resume
            .clone()
            .unwrap_or_else(|| panic!("no resume point: {report:?}"));
        if at.index < job.len() {
            s.run_preamble_at(job, at.index, at.entry, &resume_options())
                .unwrap();
            let end = s.stream(job, at.index, None, None, &mut |_| {});
            assert_eq!(end.end, StreamEnd::Completed, "{}", end.describe(job));
        }
    } else {
        assert_eq!(report.end, StreamEnd::Completed, "{}", report.describe(job));
    }
    (
        coverage::check(&coverage::program_cuts(job), &made(), 0.01),
        report,
    )
}

/// The work offset is reported (`WCO:`) in the first status after it changes: selecting
/// G55 with an offset, and M2 going back to G54. A sender that kept the old WCO would see
/// the end of a G55 program 101.6 mm off (CAMotics' Botomata). A G10 on a system not in
/// use changes nothing reported. Quiet reports first: grbl repeats WCO every 10–30.
pub(crate) fn wco_reported_when_it_changes(ep: &Endpoint) {
    let mut s = connect(ep);
    let mut quiet = false;
    for _ in 0..40 {
        if s.status().expect("status").wco.is_none() {
            quiet = true;
            break;
        }
    }
    assert!(quiet, "a report without WCO within 40 queries");
    for (line, expect) in [
        ("G10 L2 P2 Y-101.6", None),
        ("G55", Some(vec![0.0, -101.6, 0.0])),
        ("M2", Some(vec![0.0, 0.0, 0.0])),
    ] {
        let reply = s.command(line).expect(line);
        assert_eq!(reply.error, None, "{line}");
        let wco = s.status().expect("status").wco;
        let wco = wco.map(|w| w[..3].to_vec());
        assert_eq!(wco, expect, "after {line}");
    }
}
