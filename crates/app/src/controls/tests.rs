//! The controls against the grbl emulator in its three flavours and the virtual machine.

use super::*;
use crate::JobRequest;
use oficina_grbl_emu::{Config, Emulator, Flavor};

const FLAVORS: [Flavor; 3] = [Flavor::Grbl, Flavor::GrblHal, Flavor::FluidNc];

fn board(flavor: Flavor) -> (Emulator, Session) {
    let mut config = Config::flavored(flavor);
    // Fast axes: the tests wait for moves to end.
    config.settings.extend([
        (110, 6000.0),
        (111, 6000.0),
        (112, 3000.0),
        (120, 1000.0),
        (121, 1000.0),
        (122, 1000.0),
    ]);
    let emu = Emulator::start(config);
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let s = Session::open(&format!("tcp://{addr}")).unwrap();
    (emu, s)
}

/// Polls until `f` holds (the firmware's status arrives through the events).
fn wait(s: &mut Session, what: &str, f: impl Fn(&crate::Snapshot) -> bool) -> crate::Snapshot {
    let t0 = Instant::now();
    loop {
        s.poll(Duration::from_millis(20));
        let snap = s.snapshot();
        if f(&snap) {
            return snap;
        }
        assert!(t0.elapsed() < Duration::from_secs(20), "{what}: {snap:?}");
    }
}

fn near(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-3)
}

#[test]
fn typed_lines_offsets_home_and_reset_on_every_flavour() {
    for flavor in FLAVORS {
        let (_emu, mut s) = board(flavor);
        assert!(s.snapshot().offsets.known, "{flavor:?}: $# read at connect");
        let r = s.mdi("G0 X5 Y3").unwrap();
        assert_eq!(r.error, None, "{flavor:?}");
        assert_eq!(r.console_lines(), ["> G0 X5 Y3", "ok"]);
        wait(&mut s, "moved", |s| {
            s.state == "idle" && near(s.work_pos, [5.0, 3.0, 0.0])
        });
        // Firmware errors come back in words.
        let r = s.mdi("G1 X1").unwrap();
        assert!(
            r.error
                .as_deref()
                .unwrap()
                .starts_with("error:22 (Undefined feed rate"),
            "{r:?}"
        );
        // Zero X alone in G54, then G55 chosen and zeroed whole: G54 stays.
        s.zero([true, false, false]).unwrap();
        let snap = wait(&mut s, "X zeroed", |s| near(s.work_pos, [0.0, 3.0, 0.0]));
        assert_eq!(snap.offsets.systems[0], [5.0, 0.0, 0.0], "{flavor:?}");
        s.select_system(1).unwrap();
        assert_eq!(s.snapshot().offsets.active, 1);
        s.mdi("G0 X7").unwrap();
        wait(&mut s, "moved in G55", |s| {
            s.state == "idle" && (s.machine_pos[0] - 7.0).abs() < 1e-3
        });
        s.zero([true, true, true]).unwrap();
        let o = s.snapshot().offsets;
        assert_eq!(
            (o.systems[0], o.systems[1]),
            ([5.0, 0.0, 0.0], [7.0, 3.0, 0.0]),
            "{flavor:?}"
        );
        // `$#` typed fills the table too.
        let r = s.mdi("$#").unwrap();
        assert!(
            r.lines.iter().any(|l| l.starts_with("[G55:7.000,3.000")),
            "{r:?}"
        );
        // Go to zero: Z up to the clearance first, then XY.
        s.mdi("G0 X12 Y9 Z-5").unwrap();
        wait(&mut s, "away", |s| {
            s.state == "idle" && (s.machine_pos[2] + 5.0).abs() < 1e-3
        });
        s.go_to_zero(false).unwrap();
        let snap = wait(&mut s, "at zero", |s| {
            s.state == "idle" && near(s.machine_pos, [7.0, 3.0, -1.0])
        });
        assert!((snap.work_pos[2] + 1.0).abs() < 1e-3, "{snap:?}");
        // Homing refused with $22=0, explained; enabled, it homes.
        let e = homing(&mut s).wait().unwrap_err().0;
        assert!(e.contains("$22=1") && e.contains("error:5"), "{e}");
        assert_eq!(s.mdi("$22=1").unwrap().error, None);
        homing(&mut s).wait().unwrap();
        wait(&mut s, "homed", |s| {
            s.state == "idle" && near(s.machine_pos, [0.0; 3])
        });
        // Soft reset while moving: alarm (G54 active again); unlock.
        s.mdi("G1 X-100 F300").unwrap();
        wait(&mut s, "moving", |s| s.state == "run");
        s.soft_reset().unwrap();
        let snap = wait(&mut s, "alarm", |s| s.state == "alarm");
        assert_eq!(snap.offsets.active, 0);
        s.unlock().unwrap();
        wait(&mut s, "unlocked", |s| s.state == "idle");
        s.read_offsets().unwrap();
        assert_eq!(
            s.snapshot().offsets.active,
            0,
            "{flavor:?}: G54 after the reset"
        );
    }
}

/// `$H` on firmware: the cycle, under way on the device's thread.
fn homing(s: &mut Session) -> Probing<()> {
    s.home().unwrap().expect("firmware homes as a routine")
}

#[test]
fn homing_on_firmware_runs_beside_the_session_and_reports_its_alarms() {
    let (_emu, mut s) = board(Flavor::GrblHal);
    assert_eq!(s.mdi("$22=1").unwrap().error, None);
    // A slow seek (300 mm/min) from 8 mm below Z0 and 20 mm left of X0: about 5.6 s.
    assert_eq!(s.mdi("$25=300").unwrap().error, None);
    s.unlock().unwrap();
    s.mdi("G0 X-20 Y-5 Z-8").unwrap();
    wait(&mut s, "away", |s| {
        s.state == "idle" && near(s.machine_pos, [-20.0, -5.0, -8.0])
    });
    let cycle = homing(&mut s);
    // The session stays free: the status flows (state home, Z rising first), typed lines
    // are refused in words, and a second homing is refused.
    let seen = wait(&mut s, "homing, Z on its way", |s| {
        s.state == "home" && s.machine_pos[2] > -7.0 && s.machine_pos[2] < -0.5
    });
    assert!((seen.machine_pos[0] + 20.0).abs() < 1e-3, "{seen:?}");
    let e = s.mdi("G0 X1").unwrap_err().0;
    assert!(e.contains("not idle (home)"), "{e}");
    assert!(s.home().is_err());
    wait(&mut s, "Z home, X on its way", |s| {
        s.state == "home" && s.machine_pos[2].abs() < 1e-3 && s.machine_pos[0] > -19.0
    });
    cycle.wait().unwrap();
    wait(&mut s, "homed", |s| {
        s.state == "idle" && near(s.machine_pos, [0.0; 3])
    });

    // Stop during the cycle: grbl's ALARM:6, said as an alarm and as the cycle's end.
    s.mdi("G0 Z-10").unwrap();
    wait(&mut s, "down", |s| {
        s.state == "idle" && s.machine_pos[2] < -9.99
    });
    let cycle = homing(&mut s);
    wait(&mut s, "homing", |s| s.state == "home");
    s.command(Command::Stop).unwrap();
    let e = cycle.wait().unwrap_err().0;
    assert!(e.contains("stopped by the operator"), "{e}");
    let snap = wait(&mut s, "alarm", |s| s.state == "alarm");
    assert!(
        snap.alarm.as_deref().unwrap_or("").contains("ALARM:6"),
        "{snap:?}"
    );
}

#[test]
fn homing_without_switches_ends_in_alarm_9_explained() {
    let mut config = Config::flavored(Flavor::Grbl);
    config.limit_switches = false;
    config
        .settings
        .extend([(22, 1.0), (25, 3000.0), (132, 10.0)]);
    let emu = Emulator::start(config);
    let addr = emu.serve_tcp("127.0.0.1:0").unwrap();
    let mut s = Session::open(&format!("tcp://{addr}")).unwrap();
    let e = homing(&mut s).wait().unwrap_err().0;
    assert!(
        e.starts_with("homing failed: ALARM:9 (Homing fail") && e.contains("re-home"),
        "{e}"
    );
    let snap = wait(&mut s, "alarm", |s| s.state == "alarm");
    assert!(
        snap.alarm.as_deref().unwrap_or("").contains("ALARM:9"),
        "{snap:?}"
    );
}

#[test]
fn typed_lines_and_macros_are_refused_during_a_job() {
    let (_emu, mut s) = board(Flavor::Grbl);
    s.start(JobRequest {
        name: "long.nc".into(),
        text: Arc::new("G1 X200 F100\nG1 X0\n".into()),
        from_line: None,
        speed: None,
    })
    .unwrap();
    wait(&mut s, "running", |s| s.state == "run");
    let e = s.mdi("G0 X1").unwrap_err().0;
    assert!(e.contains("a job is running") && e.contains("Hold"), "{e}");
    assert!(s
        .run_macro("G0 X1")
        .unwrap_err()
        .0
        .contains("a job is running"));
    assert!(s.zero([true; 3]).is_err());
    assert!(s.home().is_err());
    // Real-time controls still work: hold, then a soft reset ends the job.
    s.command(Command::Hold).unwrap();
    wait(&mut s, "held", |s| s.state == "hold");
    s.soft_reset().unwrap();
    let snap = wait(&mut s, "ended", |s| {
        s.job.as_ref().is_some_and(|j| j.completed == Some(false))
    });
    assert_ne!(snap.state, "run", "{snap:?}");
    wait(&mut s, "at rest", |s| matches!(s.state, "idle" | "alarm"));
    assert!(s.mdi("G0 X1").is_ok(), "typed lines again after the job");
}

#[test]
fn macros_run_line_by_line_and_stop_at_the_first_error() {
    let (_emu, mut s) = board(Flavor::GrblHal);
    s.mdi("G0 X2 Y1").unwrap();
    wait(&mut s, "moved", |s| {
        s.state == "idle" && near(s.machine_pos, [2.0, 1.0, 0.0])
    });
    let r = s.run_macro("G0 X[x+1]\nG1 Y5\nG0 X0").unwrap();
    assert_eq!(r.len(), 2, "{r:?}");
    assert_eq!(r[0].line, "G0 X3");
    assert!(r[1].error.as_deref().unwrap().contains("error:22"));
    wait(&mut s, "moved", |s| {
        s.state == "idle" && near(s.machine_pos, [3.0, 1.0, 0.0])
    });
    // Unknown parameters: nothing is sent.
    let e = s.run_macro("G0 X0\nG0 X[q]").unwrap_err().0;
    assert!(e.contains("unknown parameter [q]"), "{e}");
    // The emulator's `$#` reports no probe touch yet.
    assert!(s
        .run_macro("G0 X[prb_x]")
        .unwrap_err()
        .0
        .contains("did not touch"));
    assert!(s.mdi("").is_err() && s.mdi("G0\nG1").is_err());
}

#[test]
fn the_virtual_machine_runs_typed_lines_and_keeps_six_work_systems() {
    let mut s = Session::open("virtual").unwrap();
    let start = s.snapshot();
    assert!(start.is_virtual);
    let e = s.mdi("$$").unwrap_err().0;
    assert!(e.contains("no firmware $ commands"), "{e}");
    let r = s.mdi("G0 X5 Y3").unwrap();
    assert_eq!(r.error, None);
    let snap = s.snapshot();
    assert!(
        near(snap.work_pos, [5.0, 3.0, start.work_pos[2]]),
        "{snap:?}"
    );
    // A refused line moves nothing and leaves the machine unlocked.
    let r = s.mdi("G0 X99999").unwrap();
    assert!(r.error.is_some(), "{r:?}");
    assert_eq!(s.snapshot().state, "idle");
    assert!(near(s.snapshot().machine_pos, snap.machine_pos));
    // Zero X in G54, then G55 whole: a G55 line moves in G55; G54 is kept.
    s.zero([true, false, false]).unwrap();
    assert!((s.snapshot().work_pos[0]).abs() < 1e-9);
    s.select_system(1).unwrap();
    let before = s.snapshot().machine_pos;
    s.mdi("G53 G0 X20").unwrap();
    // The axes a line leaves out stay where they are; G91 counts from there.
    let after = s.snapshot().machine_pos;
    assert_eq!((after[1], after[2]), (before[1], before[2]), "{after:?}");
    s.mdi("G91 G0 Y1").unwrap();
    s.mdi("G91 G0 Y-1").unwrap();
    assert!(near(s.snapshot().machine_pos, [20.0, before[1], before[2]]));
    s.zero([true, true, true]).unwrap();
    let o = s.snapshot().offsets;
    assert_eq!(o.active, 1);
    assert!(
        (o.systems[0][0] - snap.machine_pos[0]).abs() < 1e-9,
        "{o:?}"
    );
    assert!((o.systems[1][0] - 20.0).abs() < 1e-9, "{o:?}");
    s.mdi("G0 X1").unwrap();
    assert!((s.snapshot().machine_pos[0] - 21.0).abs() < 1e-6);
    assert!((s.snapshot().work_pos[0] - 1.0).abs() < 1e-6);
    // A macro runs its lines; go to zero (real time) ends at X0 Y0.
    let r = s.run_macro("G0 X[x+2]\nG0 Y[y-1]").unwrap();
    assert_eq!(r.len(), 2);
    assert!((s.snapshot().work_pos[0] - 3.0).abs() < 1e-6);
    // The events of the lines before are drained (the server's pump does it all the time).
    s.poll(Duration::ZERO);
    s.go_to_zero(true).unwrap();
    let t0 = Instant::now();
    while s.snapshot().job.unwrap().completed.is_none() {
        s.poll(Duration::from_millis(20));
        assert!(t0.elapsed() < Duration::from_secs(30));
    }
    assert!(near(s.snapshot().work_pos, [0.0; 3]), "{:?}", s.snapshot());
    s.soft_reset().unwrap();
    s.home().unwrap();
}

/// A typed G10 on the virtual machine sets the session's table (it was answered ok and
/// forgotten with its one-line job), and the next lines move in it.
#[test]
fn typed_g10_on_the_virtual_machine_sets_the_offsets_table() {
    let mut s = Session::open("virtual").unwrap();
    let z = s.snapshot().offsets.systems[1][2];
    assert_eq!(s.mdi("G10 L2 P2 X60 Y40").unwrap().error, None);
    let o = s.snapshot().offsets;
    assert_eq!(o.systems[1], [60.0, 40.0, z], "{o:?}");
    s.select_system(1).unwrap();
    s.mdi("G0 X1 Y2").unwrap();
    let m = s.snapshot().machine_pos;
    assert!(near([m[0], m[1], 0.0], [61.0, 42.0, 0.0]), "{m:?}");
    // L20: here becomes X5 of G55; P0 is the active system; inches convert.
    assert_eq!(s.mdi("G10 L20 P0 X5").unwrap().error, None);
    assert!((s.snapshot().offsets.systems[1][0] - 56.0).abs() < 1e-9);
    assert!((s.snapshot().work_pos[0] - 5.0).abs() < 1e-9);
    assert_eq!(s.mdi("G20 G10 L2 P3 X1").unwrap().error, None);
    assert!((s.snapshot().offsets.systems[2][0] - 25.4).abs() < 1e-9);
    let e = s.mdi("G92 X0").unwrap_err().0;
    assert!(e.contains("G92"), "{e}");
}
