//! One test per link fault, through the fault proxy between the sender and the emulator.
//! For each: the RX buffer never overflows, the stop is reported with the file line and
//! grbl's words, and resuming runs every remaining line exactly once to the program's end
//! position (the emulator records each line when its motion completes).

mod common;
use common::*;
use oficina_grbl::Endpoint;
use oficina_grbl::ResumeOptions;
use oficina_grbl::StreamProgram;
use oficina_grbl::{Notice, Sender, StreamEnd, StreamReport};
use oficina_grbl_emu::Emulator;
use oficina_grbl_emu::{Fault, FaultProxy};
use std::time::Duration;

const JOB_LINES: usize = 300;
/// `$I\n` and `$$\n` go out during the handshake before the job.
const HANDSHAKE_BYTES: u64 = 6;

fn resume_opts() -> ResumeOptions {
    ResumeOptions {
        safe_z: 2.0,
        plunge_feed: 3000.0,
        spindle_delay: 0.0,
    }
}

fn with_proxy(faults: Vec<Fault>) -> (Emulator, FaultProxy, Endpoint) {
    let (emu, ep) = emulator(Some(115_200));
    let Endpoint::Tcp { addr } = &ep else {
        unreachable!("emulator serves TCP")
    };
    let proxy = FaultProxy::start(addr.parse().unwrap(), faults).unwrap();
    let ep = Endpoint::Tcp {
        addr: proxy.addr.to_string(),
    };
    (emu, proxy, ep)
}

/// Byte offset (1-based, as the proxy counts) of the newline that ends job line `index`.
fn newline_of(job: &StreamProgram, index: usize) -> u64 {
    HANDSHAKE_BYTES
        + job.lines[..=index]
            .iter()
            .map(|l| l.text.len() as u64 + 1)
            .sum::<u64>()
}

fn connect_retry(ep: &Endpoint) -> Sender {
    for _ in 0..50 {
        if let Ok(s) = Sender::connect(ep, options()) {
            return s;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    panic!("cannot reconnect to {ep}");
}

/// Streams, and after every interrupted stream recovers and resumes, until done.
/// Returns every report and the preambles sent.
fn run_with_resumes(
    ep: &Endpoint,
    job: &StreamProgram,
    fixed: Option<&StreamProgram>,
) -> (Vec<StreamReport>, Vec<Vec<String>>) {
    let mut s = connect_retry(ep);
    let mut reports = vec![s.stream(job, 0, None, None, &mut quiet())];
    let mut preambles = Vec::new();
    let mut current = job;
    for _ in 0..6 {
        let last = reports.last().unwrap().clone();
        if last.end == StreamEnd::Completed {
            break;
        }
        let text = last.describe(current);
        assert!(!text.is_empty());
        if let StreamEnd::Rejected { .. } = last.end {
            // The operator fixes the line in the editor, same line numbers.
            if let Some(f) = fixed {
                current = f;
            }
        }
        if matches!(last.end, StreamEnd::Disconnected(_)) {
            s = connect_retry(ep);
        }
        let at = s.recover_rejected(current, &last, true).unwrap();
        let pre = oficina_grbl::resume_preamble(current, at.index, &resume_opts()).unwrap();
        s.run_preamble(current, at.index, &resume_opts()).unwrap();
        preambles.push(pre);
        reports.push(s.stream(current, at.index, None, None, &mut quiet()));
    }
    for r in &reports {
        eprintln!(
            "stream: {:?} certain {} sent {} acked {} pos {:?} resume {:?}",
            r.end, r.certain, r.sent_end, r.acked_end, r.work_pos, r.resume
        );
    }
    assert_eq!(
        reports.last().unwrap().end,
        StreamEnd::Completed,
        "{:?}",
        reports
    );
    (reports, preambles)
}

/// The emulator's record of completed lines, preambles taken out, must be the job exactly,
/// except after a rejected line: grbl runs the lines already in its buffer past it, and the
/// resume runs them again from the rejected line (`reran_after_rejection` counts them).
fn assert_each_line_once(emu: &Emulator, job: &StreamProgram, preambles: &[Vec<String>]) {
    assert_lines_ran(emu, job, preambles, None)
}

fn assert_lines_ran(
    emu: &Emulator,
    job: &StreamProgram,
    preambles: &[Vec<String>],
    rejected: Option<usize>,
) {
    let mut done = emu.with_core(|c| c.executed.clone());
    if let Some(k) = rejected {
        // Lines k+1.. that ran before the hold: remove that run, checking it is in order.
        let pre0 = oficina_grbl::clean_line(&preambles[0][0]).unwrap();
        let p = done
            .iter()
            .position(|l| *l == pre0)
            .expect("a resume followed");
        let ran_past: Vec<String> = if p > k {
            done.drain(k..p).collect()
        } else {
            Vec::new()
        };
        let expected_past: Vec<String> = job.lines[k + 1..k + 1 + ran_past.len()]
            .iter()
            .map(|l| l.text.clone())
            .collect();
        assert_eq!(
            ran_past, expected_past,
            "lines that ran past the rejected one are its successors, in order"
        );
    }
    for pre in preambles {
        let start = done
            .iter()
            .position(|l| *l == pre[0])
            .expect("preamble ran");
        let cleaned: Vec<String> = pre
            .iter()
            .map(|l| oficina_grbl::clean_line(l).unwrap())
            .collect();
        assert_eq!(done[start..start + pre.len()], cleaned[..]);
        done.drain(start..start + pre.len());
    }
    let expected: Vec<String> = job.lines.iter().map(|l| l.text.clone()).collect();
    if done != expected {
        let first = done
            .iter()
            .zip(&expected)
            .position(|(a, b)| a != b)
            .unwrap_or(done.len().min(expected.len()));
        panic!(
            "lines ran {} times vs {} expected; first difference at {first}: {:?} vs {:?}",
            done.len(),
            expected.len(),
            done.get(first),
            expected.get(first)
        );
    }
}

fn assert_final_position(emu: &Emulator, job: &StreamProgram) {
    let expected = oficina_grbl::replay(job, job.len()).work_pos();
    let wpos = emu.with_core(|c| {
        let w = c.interp.wco();
        [c.mpos[0] - w[0], c.mpos[1] - w[1], c.mpos[2] - w[2]]
    });
    for a in 0..3 {
        assert!(
            (wpos[a] - expected[a]).abs() < 1e-6,
            "{wpos:?} vs {expected:?}"
        );
    }
}

fn assert_no_overflow(emu: &Emulator, reports: &[StreamReport]) {
    assert_eq!(emu.stats().rx_overflows, 0);
    assert!(reports.iter().all(|r| r.max_in_flight <= 127));
}

#[test]
fn fault_dropped_newline_merges_two_lines_and_is_resumed() {
    let job = job(JOB_LINES);
    let (emu, proxy, ep) = with_proxy(vec![Fault::Drop {
        at: newline_of(&job, 120),
    }]);
    let (reports, pre) = run_with_resumes(&ep, &job, None);
    assert!(proxy.fired()[0]);
    // Two G1 words in one block: two axis commands, grbl's error 24 (gcode.c checks that
    // before the modal group), reported on the first line.
    assert!(
        matches!(
            reports[0].end,
            StreamEnd::Rejected {
                index: 120,
                code: 24
            }
        ),
        "{:?}",
        reports[0].end
    );
    assert!(reports[0]
        .describe(&job)
        .contains("More than one g-code command that requires axis words"));
    assert_no_overflow(&emu, &reports);
    // The merged line 120+121 was rejected as one: both run after the resume.
    assert_lines_ran(&emu, &job, &pre, Some(121));
    assert_final_position(&emu, &job);
}

#[test]
fn fault_corrupted_byte_is_rejected_and_resumed() {
    let job = job(JOB_LINES);
    // The 'G' that starts line 150 arrives as '#'.
    let at = newline_of(&job, 149) + 1;
    let (emu, proxy, ep) = with_proxy(vec![Fault::Corrupt { at, with: b'#' }]);
    let (reports, pre) = run_with_resumes(&ep, &job, None);
    assert!(proxy.fired()[0]);
    assert_eq!(
        reports[0].end,
        StreamEnd::Rejected {
            index: 150,
            code: 1
        }
    );
    let text = reports[0].describe(&job);
    assert!(
        text.contains(&format!("test.nc:{}", job.lines[150].file_line))
            && text.contains("Expected command letter"),
        "{text}"
    );
    assert_no_overflow(&emu, &reports);
    assert_lines_ran(&emu, &job, &pre, Some(150));
    assert_final_position(&emu, &job);
}

#[test]
fn fault_firmware_error_mid_stream_stops_then_resumes_after_fix() {
    let good = program(JOB_LINES);
    let mut lines: Vec<&str> = good.lines().collect();
    let fixed_line = lines[200].to_string();
    let bad_line = fixed_line.replace("G1", "G2");
    lines[200] = &bad_line;
    let bad = StreamProgram::from_text("test.nc", &lines.join("\n")).unwrap();
    let fixed = StreamProgram::from_text("test.nc", &good).unwrap();
    let (emu, _proxy, ep) = with_proxy(vec![]);
    let (reports, pre) = run_with_resumes(&ep, &bad, Some(&fixed));
    let StreamEnd::Rejected { index, code } = reports[0].end else {
        panic!("{:?}", reports[0].end)
    };
    assert_eq!(bad.lines[index].file_line, 201);
    assert_eq!(code, 35, "G2 without I/J is grbl's error 35");
    assert!(reports[0].describe(&bad).contains("test.nc:201"));
    // The resume point is never past the rejected line.
    assert!(reports[0].resume.as_ref().unwrap().index <= index);
    assert_no_overflow(&emu, &reports);
    assert_lines_ran(&emu, &fixed, &pre, Some(index));
    assert_final_position(&emu, &fixed);
}

#[test]
fn fault_reset_mid_job_alarms_and_is_resumed() {
    let job = job(JOB_LINES);
    let (emu, proxy, ep) = with_proxy(vec![Fault::Reset {
        at: newline_of(&job, 100),
    }]);
    let (reports, pre) = run_with_resumes(&ep, &job, None);
    assert!(proxy.fired()[0]);
    assert!(
        matches!(
            reports[0].end,
            StreamEnd::Alarm(3) | StreamEnd::FirmwareReset
        ),
        "{:?}",
        reports[0].end
    );
    assert_no_overflow(&emu, &reports);
    assert_each_line_once(&emu, &job, &pre);
    assert_final_position(&emu, &job);
}

#[test]
fn fault_disconnect_mid_job_reconnects_and_resumes() {
    let job = job(JOB_LINES);
    let (emu, proxy, ep) = with_proxy(vec![Fault::Disconnect {
        at: newline_of(&job, 90) - 4,
    }]);
    let (reports, pre) = run_with_resumes(&ep, &job, None);
    assert!(proxy.fired()[0]);
    assert!(
        matches!(reports[0].end, StreamEnd::Disconnected(_)),
        "{:?}",
        reports[0].end
    );
    assert!(reports[0].sent_end >= 90);
    assert_no_overflow(&emu, &reports);
    assert_each_line_once(&emu, &job, &pre);
    assert_final_position(&emu, &job);
}

#[test]
fn fault_slow_firmware_never_overflows_and_completes() {
    let job = job(120);
    let (emu, proxy, ep) = with_proxy(vec![Fault::SlowReplies {
        delay: Duration::from_millis(4),
    }]);
    let (reports, pre) = run_with_resumes(&ep, &job, None);
    assert!(proxy.fired()[0]);
    assert_eq!(reports.len(), 1);
    assert_no_overflow(&emu, &reports);
    assert_each_line_once(&emu, &job, &pre);
    assert_final_position(&emu, &job);
}

#[test]
fn fault_garbage_lines_are_reported_not_counted() {
    let job = job(JOB_LINES);
    let noise = b"\xff\xfe#@!okk error: <Idle|MPos:x> ALARM:".to_vec();
    let (emu, proxy, ep) = with_proxy(vec![Fault::Garbage { every: 9, noise }]);
    let mut s = connect_retry(&ep);
    let mut unexpected = 0;
    let report = s.stream(&job, 0, None, None, &mut |n| {
        if let Notice::Unexpected(_) = n {
            unexpected += 1;
        }
    });
    assert!(proxy.fired()[0]);
    assert_eq!(
        report.end,
        StreamEnd::Completed,
        "{}",
        report.describe(&job)
    );
    assert!(
        unexpected > 10,
        "noise lines surfaced as unexpected: {unexpected}"
    );
    assert_no_overflow(&emu, &[report]);
    assert_each_line_once(&emu, &job, &[]);
    assert_final_position(&emu, &job);
}

#[test]
fn fault_firmware_goes_silent_is_detected_and_resumed() {
    let job = job(JOB_LINES);
    let (emu, proxy, ep) = with_proxy(vec![Fault::Silence {
        at: newline_of(&job, 110),
    }]);
    let mut s = Sender::connect(
        &ep,
        oficina_grbl::SenderOptions {
            silence_timeout: Duration::from_secs(2),
            ..options()
        },
    )
    .unwrap();
    let first = s.stream(&job, 0, None, None, &mut quiet());
    assert!(proxy.fired()[0]);
    let StreamEnd::Disconnected(why) = &first.end else {
        panic!("{:?}", first.end)
    };
    assert!(why.contains("answered nothing"), "{why}");
    // The operator power-cycles the link: a new connection (the fault fired once).
    drop(s);
    let mut s = connect_retry(&ep);
    let at = s
        .recover(&job, first.certain, first.sent_end, first.acked_end, true)
        .unwrap();
    let pre = oficina_grbl::resume_preamble(&job, at.index, &resume_opts()).unwrap();
    s.run_preamble(&job, at.index, &resume_opts()).unwrap();
    let last = s.stream(&job, at.index, None, None, &mut quiet());
    assert_eq!(last.end, StreamEnd::Completed, "{}", last.describe(&job));
    assert_no_overflow(&emu, &[first, last]);
    assert_each_line_once(&emu, &job, &[pre]);
    assert_final_position(&emu, &job);
}
