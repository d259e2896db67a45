//! Tool changes at M6 on grbl (which has none: `M6` is its error:20), against the emulator:
//! the sender stops streaming at the M6 line until Resume, never sends `M6`, and a job
//! stopped while it waits resumes at the M6 line with the same prompt.

mod common;
use common::*;
use oficina_grbl::{clean_line, GrblDevice, GrblState, Start, ToolChange, ToolPolicy};
use oficina_grbl_emu::Emulator;
use oficina_machine::{Command, Event, Job, Machine, Pace, State};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A program for grbl with two tools, as Fusion 360's and FreeCAD's grbl posts write them.
const TWO_TOOLS: &str = include_str!("../../../samples/grbl/two-tools.nc");

/// The lines grbl is meant to run, (file line, text as grbl reads it), worked out here from
/// the text: comments, blank lines and tape marks dropped, `M6` (and `T` if `drop_t`) out.
fn expected_lines(text: &str, drop_t: bool) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let mut c = clean_line(raw).unwrap();
        if c == "%" {
            continue;
        }
        c = c.replace("M6", "");
        if drop_t {
            c = c.replace("T1", "").replace("T2", "");
        }
        if !c.is_empty() {
            out.push((i + 1, c));
        }
    }
    out
}

fn m6_line(text: &str, tool: u32) -> u32 {
    let l = text
        .lines()
        .position(|l| l.starts_with(&format!("T{tool} M6")))
        .unwrap();
    l as u32 + 1
}

fn device(emu_ep: &oficina_grbl::Endpoint, policy: ToolPolicy, tag: &str) -> GrblDevice {
    let mut dev = GrblDevice::at(emu_ep.clone(), options());
    dev.settings.resume.spindle_delay = 0.0;
    dev.settings.resume.safe_z = 5.0;
    dev.settings.tool_change = ToolChange {
        policy,
        ..ToolChange::default()
    };
    dev.settings.journal = Some(std::env::temp_dir().join(format!(
        "oficina-toolchange-{tag}-{}.journal",
        std::process::id()
    )));
    dev.connect().unwrap();
    dev
}

fn job(start_line: Option<u32>) -> Job {
    Job {
        name: "two-tools.nc".into(),
        text: Arc::new(TWO_TOOLS.to_string()),
        start_line,
        pace: Pace::Instant,
    }
}

fn executed(emu: &Emulator) -> Vec<String> {
    emu.with_core(|c| c.executed.clone())
}

/// `sub` appears in `all` in order (other lines may come between).
fn is_subsequence(sub: &[String], all: &[String]) -> bool {
    let mut it = all.iter();
    sub.iter().all(|s| it.any(|a| a == s))
}

/// Events until the job ends; `on_change` is called at every tool change.
fn run_until_end(
    dev: &mut GrblDevice,
    mut on_change: impl FnMut(&mut GrblDevice, u32, u32, &str),
) -> (bool, Vec<Event>) {
    let mut seen = Vec::new();
    let t = Instant::now();
    while t.elapsed() < Duration::from_secs(120) {
        match dev.next_event(Duration::from_millis(20)) {
            Some(Event::ToolChange { tool, line, prompt }) => {
                on_change(dev, tool, line, &prompt);
                seen.push(Event::ToolChange { tool, line, prompt });
            }
            Some(Event::JobEnd { completed, .. }) => return (completed, seen),
            Some(Event::Status(_)) | None => {}
            Some(e) => seen.push(e),
        }
    }
    panic!("the job did not end: {seen:?}");
}

#[test]
fn pause_stops_streaming_at_each_m6_until_resume_and_grbl_never_gets_m6() {
    let (emu, ep) = emulator(None);
    let mut dev = device(&ep, ToolPolicy::Pause, "pause");
    let want = expected_lines(TWO_TOOLS, false);
    let texts: Vec<String> = want.iter().map(|(_, t)| t.clone()).collect();
    dev.start(job(None)).unwrap();
    let mut changes = Vec::new();
    let (completed, events) = run_until_end(&mut dev, |dev, tool, line, prompt| {
        // Every line before the M6 has run, the machine rests, and nothing after it came.
        let before: Vec<String> = want
            .iter()
            .filter(|(l, _)| (*l as u32) < line)
            .map(|(_, t)| t.clone())
            .collect();
        let ran = executed(&emu);
        assert!(is_subsequence(&before, &ran), "{before:?} in {ran:?}");
        // The last line run is the last before the M6 (the first stop: exactly those).
        assert_eq!(ran.last(), before.last(), "{ran:?}");
        if tool == 1 {
            assert_eq!(ran, before);
        }
        let received = emu.with_core(|c| (c.stats.lines_executed, c.rx_used()));
        assert_eq!(received.1, 0, "nothing waits in grbl's RX buffer");
        assert_eq!(dev.status().state, State::Paused);
        assert_eq!(emu.with_core(|c| c.state.clone()), GrblState::Idle);
        // Still nothing after a while: the stop is a real stop.
        std::thread::sleep(Duration::from_millis(400));
        assert_eq!(
            emu.with_core(|c| (c.stats.lines_executed, c.rx_used())),
            received
        );
        assert_eq!(executed(&emu), ran);
        changes.push((tool, line, prompt.to_string()));
        dev.command(Command::Resume).unwrap();
    });
    assert!(completed, "{events:?}");
    assert_eq!(
        changes.iter().map(|c| (c.0, c.1)).collect::<Vec<_>>(),
        [(1, m6_line(TWO_TOOLS, 1)), (2, m6_line(TWO_TOOLS, 2))]
    );
    assert!(
        changes[1].2.starts_with("change to tool T2 (T2 D=6 CR=3"),
        "{}",
        changes[1].2
    );
    let ran = executed(&emu);
    assert!(is_subsequence(&texts, &ran), "{texts:?} in {ran:?}");
    assert!(!ran.iter().any(|l| l.contains("M6")), "{ran:?}");
    assert_eq!(emu.with_core(|c| c.stats.errors_sent), 0, "no error:20");
    let end = oficina_grbl::replay(
        &oficina_grbl::StreamProgram::from_text("t", &texts.join("\n")).unwrap(),
        usize::MAX,
    )
    .work_pos();
    for a in 0..3 {
        assert!((dev.status().work_pos[a] - end[a]).abs() < 0.01);
    }
}

#[test]
fn ignore_streams_the_program_without_m6_and_t() {
    let (emu, ep) = emulator(None);
    let mut dev = device(&ep, ToolPolicy::Ignore, "ignore");
    dev.start(job(None)).unwrap();
    let (completed, events) = run_until_end(&mut dev, |_, _, _, _| panic!("no pause"));
    assert!(completed, "{events:?}");
    let want: Vec<String> = expected_lines(TWO_TOOLS, true)
        .into_iter()
        .map(|(_, t)| t)
        .collect();
    assert_eq!(
        executed(&emu),
        want,
        "exactly the program, M6 and T left out"
    );
    let notes = events
        .iter()
        .filter(|e| matches!(e, Event::Message(m) if m.contains("M6 T") && m.contains("dropped")))
        .count();
    assert_eq!(notes, 2, "{events:?}");
    assert_eq!(emu.with_core(|c| c.stats.errors_sent), 0);
}

#[test]
fn as_written_grbl_refuses_m6_with_error_20() {
    // What the policies are for: grbl 1.1 has no M6.
    let (_emu, ep) = emulator(None);
    let mut dev = device(&ep, ToolPolicy::Firmware, "firmware");
    dev.start(job(None)).unwrap();
    let (completed, events) = run_until_end(&mut dev, |_, _, _, _| panic!("no pause"));
    assert!(!completed);
    assert!(
        events.iter().any(
            |e| matches!(e, Event::Alarm(a) if a.contains("error:20") || a.contains("Unsupported"))
        ),
        "{events:?}"
    );
}

#[test]
fn a_stop_while_waiting_resumes_at_the_m6_line_from_the_journal_and_from_the_line() {
    let (emu, ep) = emulator(None);
    let mut dev = device(&ep, ToolPolicy::Pause, "stop");
    let _ = std::fs::remove_file(dev.settings.journal.as_ref().unwrap());
    let second = m6_line(TWO_TOOLS, 2);
    dev.start(job(None)).unwrap();
    let (completed, _) = run_until_end(&mut dev, |dev, tool, _, _| {
        let cmd = if tool == 1 {
            Command::Resume
        } else {
            Command::Stop
        };
        dev.command(cmd).unwrap();
    });
    assert!(!completed);
    let report = dev.job_report().unwrap();
    let at = report.resume.as_ref().unwrap();
    assert_eq!(at.file_line, second, "{}", report.summary);
    assert!(report.summary.contains("M6 T2"), "{}", report.summary);
    let ran_before = executed(&emu);

    // From the journal: it asks for T2 again before sending anything.
    dev.settings.start = Start::Journal;
    dev.start(job(None)).unwrap();
    let (completed, seen) = run_until_end(&mut dev, |dev, tool, line, _| {
        assert_eq!((tool, line), (2, second));
        assert_eq!(executed(&emu), ran_before, "nothing ran before the prompt");
        dev.command(Command::Stop).unwrap();
    });
    assert!(!completed);
    assert_eq!(
        seen.iter()
            .filter(|e| matches!(e, Event::ToolChange { .. }))
            .count(),
        1
    );
    assert_eq!(dev.job_report().unwrap().resume.unwrap().file_line, second);

    // From the line: the same prompt, then the rest of the program.
    dev.settings.start = Start::Beginning;
    dev.start(job(Some(second))).unwrap();
    let mut asked = Vec::new();
    let (completed, events) = run_until_end(&mut dev, |dev, tool, line, _| {
        asked.push((tool, line));
        dev.command(Command::Resume).unwrap();
    });
    assert!(completed, "{events:?}");
    assert_eq!(asked, [(2, second)]);
    let rest: Vec<String> = expected_lines(TWO_TOOLS, false)
        .into_iter()
        .filter(|(l, _)| *l as u32 > second)
        .map(|(_, t)| t)
        .collect();
    let ran = executed(&emu);
    assert!(
        is_subsequence(&rest, &ran[ran_before.len()..]),
        "{rest:?} in {ran:?}"
    );
    assert!(!ran.iter().any(|l| l.contains("M6")));
}

#[test]
fn remeasure_on_the_emulated_setter_offsets_the_longer_tool_by_its_length() {
    use oficina_grbl::{setter_at, Approach};
    use oficina_grbl_emu::{Config, LengthSetter, ProbeModel, Tool};
    // The setter's pad: machine X250 Y50, its top at Z−80; tool 2 is 12.5 mm longer.
    let (pad_top, longer) = (-80.0, 12.5);
    let emu = Emulator::start(Config {
        probe: ProbeModel {
            setter: Some(LengthSetter {
                at: [250.0, 50.0],
                top: pad_top,
            }),
            ..ProbeModel::default()
        },
        ..config(None)
    });
    let ep = oficina_grbl::Endpoint::Tcp {
        addr: emu.serve_tcp("127.0.0.1:0").unwrap().to_string(),
    };
    let mut setter = setter_at(250.0, 50.0, -45.0);
    setter.approach = Approach {
        travel: 50.0,
        feed: 3000.0,
        slow_feed: 600.0,
        retract: 2.0,
    };
    let mut dev = GrblDevice::at(ep, options());
    dev.settings.resume.spindle_delay = 0.0;
    dev.settings.tool_change = ToolChange {
        policy: ToolPolicy::Remeasure,
        park: None,
        setter: Some(setter),
        measure_at_start: false,
    };
    dev.settings.journal = Some(std::env::temp_dir().join(format!(
        "oficina-toolchange-remeasure-{}.journal",
        std::process::id()
    )));
    dev.connect().unwrap();
    dev.start(job(None)).unwrap();
    let mut tools = Vec::new();
    let (completed, events) = run_until_end(&mut dev, |dev, tool, _, _| {
        // The operator puts the tool in.
        let length = if tool == 2 { longer } else { 0.0 };
        emu.set_tool(Tool {
            length,
            diameter: 0.0,
        });
        tools.push(tool);
        dev.command(Command::Resume).unwrap();
    });
    assert!(completed, "{events:?}");
    assert_eq!(tools, [1, 2]);
    // Each tool touched the pad (its tip at the pad's top), and the offset is the
    // difference of the two touches: the second tool's extra length.
    let told: Vec<&Event> = events
        .iter()
        .filter(|e| matches!(e, Event::Message(m) if m.starts_with("tool setter touched")))
        .collect();
    assert_eq!(told.len(), 2, "{events:?}");
    let tlo = dev.raw_line("$#").unwrap();
    let tlo: f64 = tlo
        .lines
        .iter()
        .find_map(|l| l.strip_prefix("[TLO:")?.strip_suffix(']')?.parse().ok())
        .unwrap();
    assert!((tlo - longer).abs() < 0.002, "TLO {tlo}");
    assert!(!executed(&emu).iter().any(|l| l.contains("M6")));
    assert_eq!(emu.with_core(|c| c.stats.errors_sent), 0);
}

#[test]
fn park_moves_to_the_park_position_before_the_prompt_and_comes_back() {
    let (emu, ep) = emulator(None);
    let mut dev = device(&ep, ToolPolicy::ParkPause, "park");
    dev.disconnect();
    let park = [-30.0, -20.0, -1.0];
    dev.settings.tool_change.park = Some(park);
    dev.connect().unwrap();
    dev.start(job(None)).unwrap();
    let mut stops = 0;
    let (completed, events) = run_until_end(&mut dev, |dev, _, _, _| {
        // At the prompt the machine rests at the park position (machine coordinates).
        let (mpos, state) = emu.with_core(|c| (c.mpos, c.state.clone()));
        assert_eq!(state, GrblState::Idle);
        for a in 0..3 {
            assert!((mpos[a] - park[a]).abs() < 1e-6, "{mpos:?} vs {park:?}");
        }
        let last = executed(&emu);
        assert!(
            last.ends_with(&["G53G0Z-1".into(), "G53G0X-30Y-20".into()]),
            "{last:?}"
        );
        stops += 1;
        dev.command(Command::Resume).unwrap();
    });
    assert!(completed, "{events:?}");
    assert_eq!(stops, 2);
    // Back on the path: the job ended where the program does (the sender checks it too).
    let texts: Vec<String> = expected_lines(TWO_TOOLS, false)
        .into_iter()
        .map(|(_, t)| t)
        .collect();
    assert!(is_subsequence(&texts, &executed(&emu)));
    assert_eq!(emu.with_core(|c| c.stats.errors_sent), 0);
}

#[test]
fn a_change_with_the_spindle_running_stops_it_and_the_resume_restarts_it() {
    // No M5 before the M6 (some posts leave it to the control): the sender turns the
    // spindle and the coolant off before asking, and back on before the next line.
    let text = "G21 G90\nT1 M6\nS9000 M3 M8\nG0 X1 Y1\nG1 Z-0.5 F600\nG0 Z2\nT2 M6\nG1 X3 F600\nM5 M9\nM30\n";
    let (emu, ep) = emulator(None);
    let mut dev = device(&ep, ToolPolicy::Pause, "spindle");
    dev.start(Job {
        name: "spindle.nc".into(),
        text: Arc::new(text.into()),
        start_line: None,
        pace: Pace::Instant,
    })
    .unwrap();
    let mut at_prompt = Vec::new();
    let (completed, events) = run_until_end(&mut dev, |dev, tool, _, _| {
        let m = emu.with_core(|c| c.interp.modal);
        at_prompt.push((tool, m.spindle, m.flood));
        dev.command(Command::Resume).unwrap();
    });
    assert!(completed, "{events:?}");
    use oficina_grbl::Spindle;
    assert_eq!(
        at_prompt,
        [(1, Spindle::Off, false), (2, Spindle::Off, false)]
    );
    // After the second change the spindle ran again at its speed before "G1 X3".
    let ran = executed(&emu);
    let g1 = ran.iter().position(|l| l == "G1X3F600").unwrap();
    let back = ran[..g1].iter().rposition(|l| l == "S9000M3").unwrap();
    let off = ran[..g1].iter().rposition(|l| l == "M5").unwrap();
    assert!(off < back, "{ran:?}");
    assert!(ran[back..g1].contains(&"M8".to_string()), "{ran:?}");
}
