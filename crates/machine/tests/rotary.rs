//! The virtual machine drives a rotary 4th axis: its status reports A along the way and at
//! the end of the job.

use oficina_machine::{Event, Job, Machine, Pace, State, VirtualMachine};
use oficina_motion::resolve;
use std::sync::Arc;
use std::time::Duration;

#[test]
fn a_four_axis_job_ends_with_a_where_the_program_left_it() {
    let mut profile = resolve("router-4axis").unwrap();
    profile.work_offset = [0.0; 3];
    let mut m = VirtualMachine::new(profile);
    m.connect().unwrap();
    m.start(Job {
        name: "t.ngc".into(),
        text: Arc::new(
            "G21 G90 G94\nG1 X10 A90 F600\nG1 A450 F3600\nG1 X20 A405 F600\nM2\n".into(),
        ),
        start_line: None,
        pace: Pace::Instant,
    })
    .unwrap();
    let mut a_seen = Vec::new();
    loop {
        match m.next_event(Duration::from_secs(30)) {
            Some(Event::JobEnd { completed, .. }) => {
                assert!(completed);
                break;
            }
            Some(Event::Status(s)) => a_seen.push(s.rotary_pos[0]),
            Some(_) => {}
            None => panic!("no end"),
        }
    }
    let st = m.status();
    assert_eq!(st.state, State::Idle);
    assert!(
        (st.rotary_pos[0] - 405.0).abs() < 1e-6,
        "{:?}",
        st.rotary_pos
    );
    assert!(
        (st.machine_pos[0] - 20.0).abs() < 1e-6,
        "{:?}",
        st.machine_pos
    );
    // A went past a full turn on the way (it counts turns, it does not jump back).
    let peak = a_seen.iter().cloned().fold(f64::MIN, f64::max);
    assert!((peak - 450.0).abs() < 1e-6, "peak A {peak}");
}
