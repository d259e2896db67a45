//! Shared set-up for the link tests: an emulator on a loopback port and a sender on it.
#![allow(dead_code)]

pub(crate) mod clocked;
pub(crate) mod coverage;
pub(crate) mod grblhal_sim;
pub(crate) mod scenarios;

use oficina_grbl::Endpoint;
use oficina_grbl::StreamProgram;
use oficina_grbl::{Notice, Sender, SenderOptions};
use oficina_grbl_emu::{Config, Emulator};
use std::time::Duration;

/// Fast axes so tests finish quickly; the line rate stays grbl's 115200 baud unless asked.
pub(crate) fn config(baud: Option<u32>) -> Config {
    Config {
        baud,
        settings: vec![
            (110, 60000.0),
            (111, 60000.0),
            (112, 60000.0),
            (120, 2000.0),
            (121, 2000.0),
            (122, 2000.0),
        ],
        record_lines: true,
        ..Config::default()
    }
}

pub(crate) fn emulator(baud: Option<u32>) -> (Emulator, Endpoint) {
    let emu = Emulator::start(config(baud));
    let addr = emu.serve_tcp("127.0.0.1:0").expect("bind loopback");
    (
        emu,
        Endpoint::Tcp {
            addr: addr.to_string(),
        },
    )
}

pub(crate) fn options() -> SenderOptions {
    SenderOptions {
        status_interval: Duration::from_millis(50),
        stall_after: Duration::from_millis(600),
        reply_timeout: Duration::from_secs(20),
        ..SenderOptions::default()
    }
}

pub(crate) fn connect(ep: &Endpoint) -> Sender {
    Sender::connect(ep, options()).expect("connect to emulator")
}

/// A staircase of short G1 moves (it never crosses itself, so a stop position names one
/// line) ending at a known point, with modal lines mixed in.
pub(crate) fn program(n: usize) -> String {
    let mut s = String::from("G21 G90 G94 (setup)\nG0 Z2\nS1000 M3\nG1 Z-0.5 F3000\n");
    let (mut x, mut y) = (0.0f64, 0.0f64);
    for i in 0..n {
        if i % 2 == 0 {
            x += 0.4 + (i % 7) as f64 * 0.1;
        } else {
            y += 0.3 + (i % 5) as f64 * 0.1;
        }
        if i % 50 == 25 {
            s += "F6000\n";
        }
        s += &format!("G1 X{x:.3} Y{y:.3}\n");
    }
    s += "G0 Z2\nM5\nM30\n";
    s
}

pub(crate) fn job(n: usize) -> StreamProgram {
    StreamProgram::from_text("test.nc", &program(n)).unwrap()
}

pub(crate) fn quiet() -> impl FnMut(Notice) {
    |_| {}
}
