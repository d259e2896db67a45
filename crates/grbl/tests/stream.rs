//! Streaming against the emulator: the whole job arrives once, in order, the RX buffer
//! never overflows, and the final position is the program's.

mod common;
use common::*;
use oficina_grbl::resume;
use oficina_grbl::sender::{Mode, StreamEnd};

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
    let expected = resume::replay(&job, job.len()).work_pos();
    assert_eq!(report.work_pos, Some(expected));
}

#[test]
fn send_response_mode_also_completes() {
    let (emu, ep) = emulator(None);
    let mut s = oficina_grbl::sender::Sender::connect(
        &ep,
        oficina_grbl::sender::SenderOptions {
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
