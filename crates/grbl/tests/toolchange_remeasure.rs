//! `--tool-change remeasure` against a fake grbl whose tool setter is touched at a height the
//! test chooses for each tool: the sender's `G43.1 Z` must be the difference of the two
//! touches, worked out here, and a resume after the change must put it back from the journal.
//!
//! The fake is grbl's protocol over TCP on Oficina's grbl interpreter (instant motion):
//! `?` status with `MPos` and `WCO` (the tool length offset in it, as grbl reports), `$I`,
//! `$$`, `$G`, `$#`, soft reset, and `G38.2` answered `[PRB:x,y,z:1]` then `ok` when the
//! setter is within the travel, else `ALARM:5`, `[PRB:…:0]`, `ok` (grbl's "probe fail").

use oficina_grbl::{
    clean_line, setter_at, Control, Endpoint, GrblMachine, Interp, Notice, RunOutcome, RunSettings,
    SenderOptions, Start, StreamEnd, StreamProgram, ToolChange, ToolPolicy,
};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

#[derive(Default)]
struct Shared {
    /// Every line received, as grbl reads it.
    lines: Vec<String>,
    /// Machine Z at which the tool in the spindle touches the setter.
    touch: f64,
}

fn reply(stream: &mut TcpStream, text: &str) {
    let _ = stream.write_all(text.as_bytes());
}

fn serve(mut stream: TcpStream, shared: Arc<Mutex<Shared>>) {
    let mut interp = Interp::default();
    let mut line = Vec::new();
    let mut buf = [0u8; 256];
    loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        for &b in &buf[..n] {
            match b {
                b'?' => {
                    let p = interp.pos;
                    let o = interp.wco();
                    let s = format!(
                        "<Idle|MPos:{:.3},{:.3},{:.3}|FS:0,0|WCO:{:.3},{:.3},{:.3}>\r\n",
                        p[0], p[1], p[2], o[0], o[1], o[2]
                    );
                    reply(&mut stream, &s);
                }
                0x18 => {
                    // A reset keeps the position and forgets the modes and offsets.
                    let pos = interp.pos;
                    interp = Interp {
                        pos,
                        ..Interp::default()
                    };
                    line.clear();
                    reply(&mut stream, "\r\nGrbl 1.1h ['$' for help]\r\n");
                }
                b'\n' => {
                    let raw = String::from_utf8_lossy(&line).to_string();
                    line.clear();
                    let answer = execute(&mut interp, &raw, &shared);
                    reply(&mut stream, &answer);
                }
                b'\r' => {}
                b if b >= 0x80 || b == b'~' || b == b'!' => {}
                b => line.push(b),
            }
        }
    }
}

fn execute(interp: &mut Interp, raw: &str, shared: &Mutex<Shared>) -> String {
    let clean = clean_line(raw).unwrap_or_default();
    shared.lock().unwrap().lines.push(clean.clone());
    match clean.as_str() {
        "" => return "ok\r\n".into(),
        "$I" => return "[VER:1.1h.20190825:]\r\n[OPT:V,15,128]\r\nok\r\n".into(),
        "$G" => {
            let m = interp.modal;
            return format!(
                "[GC:G0 G54 G17 {} {} G94 M5 M9 T0 F0 S0]\r\nok\r\n",
                if m.inches { "G20" } else { "G21" },
                if m.absolute { "G90" } else { "G91" }
            );
        }
        "$#" => return "[G54:0.000,0.000,0.000]\r\n[TLO:0.000]\r\nok\r\n".into(),
        c if c.starts_with('$') => return "ok\r\n".into(),
        _ => {}
    }
    let z0 = interp.pos[2];
    match interp.execute(&clean) {
        Err(code) => format!("error:{code}\r\n"),
        Ok(effect) if effect.probe.is_some() => {
            let target = interp.pos[2];
            let touch = shared.lock().unwrap().touch;
            if touch <= z0 && touch >= target {
                interp.pos[2] = touch;
                let p = interp.pos;
                format!("[PRB:{:.3},{:.3},{:.3}:1]\r\nok\r\n", p[0], p[1], p[2])
            } else {
                // grbl's mc_probe_cycle: the alarm, the report of no contact, then `ok`.
                let p = interp.pos;
                format!(
                    "ALARM:5\r\n[PRB:{:.3},{:.3},{:.3}:0]\r\nok\r\n",
                    p[0], p[1], p[2]
                )
            }
        }
        Ok(_) => "ok\r\n".into(),
    }
}

fn fake_grbl() -> (Endpoint, Arc<Mutex<Shared>>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap().to_string();
    let shared = Arc::new(Mutex::new(Shared::default()));
    let s = shared.clone();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            serve(stream, s.clone());
        }
    });
    (Endpoint::Tcp { addr }, shared)
}

const PROGRAM: &str = "%
(T1 D=3.175 - flat end mill)
(T2 D=6 - ball end mill)
G21 G90 G94
T1 M6
S10000 M3
G0 X10 Y10
G0 Z5
G1 Z-1 F300
G1 X20 F800
G0 Z5
M5
T2 M6
S12000 M3
G0 X30 Y10
G1 Z-0.5 F300
G1 X40 F800
G0 Z5
M5
M30
%
";

/// The touches of tool 1 and tool 2 on the setter, machine Z.
const TOUCH: [f64; 2] = [-40.123, -37.456];

fn settings(journal: &std::path::Path) -> RunSettings {
    let mut s = RunSettings {
        journal: Some(journal.to_path_buf()),
        tool_change: ToolChange {
            policy: ToolPolicy::Remeasure,
            park: None,
            setter: Some(setter_at(100.0, 50.0, -5.0)),
            measure_at_start: false,
        },
        reconnect: None,
        ..RunSettings::default()
    };
    s.resume.spindle_delay = 0.0;
    s
}

fn options() -> SenderOptions {
    SenderOptions {
        status_interval: Duration::from_millis(20),
        reply_timeout: Duration::from_secs(10),
        ..SenderOptions::default()
    }
}

/// The values of every `G43.1 Z…` the fake received since line `from`.
fn offsets(shared: &Mutex<Shared>, from: usize) -> Vec<f64> {
    shared.lock().unwrap().lines[from..]
        .iter()
        .filter_map(|l| l.split("G43.1Z").nth(1))
        .map(|v| v.parse().unwrap())
        .collect()
}

#[test]
fn remeasure_applies_the_difference_of_the_two_touches_and_a_resume_restores_it() {
    let (ep, shared) = fake_grbl();
    let journal =
        std::env::temp_dir().join(format!("oficina-remeasure-{}.journal", std::process::id()));
    let _ = std::fs::remove_file(&journal);
    let settings = settings(&journal);
    let job = StreamProgram::with_tool_change("two.nc", PROGRAM, &settings.tool_change).unwrap();
    let mut m = GrblMachine::connect_to(ep, options()).unwrap();
    let (tx, rx) = mpsc::channel();
    let mut prompts = Vec::new();
    let outcome = m
        .run(&job, &journal, &settings, Some(&rx), &mut |n| {
            if let Notice::ToolChange { tool, prompt, .. } = n {
                // The operator puts the tool in: it touches the setter at its own height.
                shared.lock().unwrap().touch = TOUCH[tool as usize - 1];
                prompts.push(prompt);
                tx.send(Control::Resume).unwrap();
            }
        })
        .unwrap();
    let RunOutcome::Streamed(report) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(
        report.end,
        StreamEnd::Completed,
        "{}",
        report.describe(&job)
    );
    assert_eq!(prompts.len(), 2, "{prompts:?}");
    assert!(
        prompts[1].contains("measures it on the tool setter"),
        "{}",
        prompts[1]
    );
    let expected = TOUCH[1] - TOUCH[0];
    let applied = offsets(&shared, 0);
    assert_eq!(applied.len(), 2, "{applied:?}");
    assert!(
        applied[0].abs() < 1e-9,
        "the first tool is the reference: {applied:?}"
    );
    assert!(
        (applied[1] - expected).abs() < 1e-4,
        "{applied:?} vs {expected}"
    );
    let lines = shared.lock().unwrap().lines.clone();
    assert_eq!(
        lines.iter().filter(|l| l.contains("G38.2")).count(),
        4,
        "a fast and a slow touch per tool"
    );
    assert!(!lines.iter().any(|l| l.contains("M6")));

    // Resume after the change (a new run from a line of tool 2): the offset comes back from
    // the journal, nothing is probed.
    let seen = lines.len();
    let mut again = settings.clone();
    again.start = Start::FileLine(17); // G1 X40 F800
    let outcome = m
        .run(&job, &journal, &again, Some(&rx), &mut |_| {})
        .unwrap();
    let RunOutcome::Streamed(report) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(
        report.end,
        StreamEnd::Completed,
        "{}",
        report.describe(&job)
    );
    let after = shared.lock().unwrap().lines[seen..].to_vec();
    assert!(!after.iter().any(|l| l.contains("G38")), "{after:?}");
    let restored = offsets(&shared, seen);
    assert_eq!(restored.len(), 1, "{after:?}");
    assert!((restored[0] - expected).abs() < 1e-4, "{restored:?}");

    // Without the journal the length is not known: the resume is refused, naming the M6.
    let _ = std::fs::remove_file(&journal);
    let e = m
        .run(&job, &journal, &again, Some(&rx), &mut |_| {})
        .unwrap_err();
    assert!(e.contains("line 13"), "{e}");
    let _ = std::fs::remove_file(&journal);
}

#[test]
fn a_setter_out_of_reach_ends_in_grbls_probe_alarm_at_the_m6() {
    let (ep, shared) = fake_grbl();
    let journal = std::env::temp_dir().join(format!(
        "oficina-remeasure-miss-{}.journal",
        std::process::id()
    ));
    let _ = std::fs::remove_file(&journal);
    let settings = settings(&journal);
    let job = StreamProgram::with_tool_change("two.nc", PROGRAM, &settings.tool_change).unwrap();
    let mut m = GrblMachine::connect_to(ep, options()).unwrap();
    let (tx, rx) = mpsc::channel();
    let outcome = m
        .run(&job, &journal, &settings, Some(&rx), &mut |n| {
            if let Notice::ToolChange { .. } = n {
                shared.lock().unwrap().touch = -500.0; // beyond the 50 mm of travel
                tx.send(Control::Resume).unwrap();
            }
        })
        .unwrap();
    let RunOutcome::Streamed(report) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(report.end, StreamEnd::Alarm(5));
    let text = report.describe(&job);
    assert!(text.contains("two.nc:5 (M6 T1)"), "{text}");
    let _ = std::fs::remove_file(&journal);
}
