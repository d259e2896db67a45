//! `oficina run --machine tcp://…` against `oficina emulate --flavor fluidnc --tcp …`: FluidNC
//! is reached over its network port (telnet, TCP 23 on the board), which greets no one, so
//! the sender must find the firmware by asking.

mod common;

#[test]
fn a_job_runs_on_fluidnc_over_its_network_port() {
    let (emulator, addr, first) = common::emulator(&["--flavor", "fluidnc", "--baud", "0"]);
    assert!(first.contains("fluidnc"), "{first}");
    let out = common::run_program_on(
        &addr,
        "square.nc",
        "G21 G90 G94\nG0 Z2\nG1 Z-0.5 F300\nG1 X10 F1200\nY10\nX0\nY0\nG0 Z2\nM2\n",
    );
    common::assert_ran_to_done(emulator, &out);
}
