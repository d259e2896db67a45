//! Runs a G-code file through the whole pipeline, for profiling outside the bench harness:
//! `cargo run --release -p oficina-gcode --example run_file -- FILE [count|print]`.
//! `count` (the default) only counts the canonical operations; `print` writes rs274's text
//! to stdout.

use oficina_gcode::Rs274Printer;
use oficina_gcode::RunOptions;
use std::fs::File;
use std::io::{BufReader, BufWriter, Write};

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: run_file FILE [count|print]");
        std::process::exit(2);
    };
    let mode = args.next().unwrap_or_else(|| "count".into());
    let file = match File::open(&path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("cannot open {path}: {e}");
            std::process::exit(1);
        }
    };
    // As `oficina bench gcode` runs it: splines whole, as rs274 reads them.
    let opts = RunOptions {
        whole_splines: true,
        ..RunOptions::default()
    };
    let mut ops = 0u64;
    let diagnostics = match mode.as_str() {
        "count" => oficina_gcode::run(
            BufReader::with_capacity(256 * 1024, file),
            &opts,
            &mut |_| ops += 1,
        ),
        "print" => {
            let stdout = std::io::stdout();
            let mut out = BufWriter::new(stdout.lock());
            let mut printer = Rs274Printer::new().numbered();
            let d = oficina_gcode::run(BufReader::new(file), &opts, &mut |c| {
                ops += 1;
                // A closed pipe is not this example's concern: stop quietly on error.
                let _ = printer.print(&c, &mut out);
            });
            let _ = out.flush();
            d
        }
        other => {
            eprintln!("unknown mode {other}: use count or print");
            std::process::exit(2);
        }
    };
    for d in &diagnostics {
        eprintln!("{d}");
    }
    eprintln!("{ops} canonical operations");
}
