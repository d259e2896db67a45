//! `oficina emulate seed --pty`: the seed's embroidery machine on a pseudo-terminal. It
//! receives numbered `.BOR` programs one way (9600 baud, 7E2, as `oficina embroider x.bor
//! --send /dev/pts/N --program 3` sends them), stores them in its 8 KB program RAM and sews
//! each on the needle-synchronised table model, printing what it sewed.

use anyhow::{bail, Context};
use oficina_grbl::Pty;
use oficina_stitch::{duration, Received, SeedMachine};
use std::io::Write;
use std::process::ExitCode;

pub(crate) fn run(pty: bool) -> anyhow::Result<ExitCode> {
    if !pty {
        bail!("the seed machine serves on a pseudo-terminal: give --pty");
    }
    let p = Pty::open().context("opening a pseudo-terminal")?;
    println!(
        "seed machine on {} (9600 baud, 7E2; Ctrl-C to stop)",
        p.slave_path
    );
    let _ = std::io::stdout().flush();
    let mut master = p.master.try_clone().context("the pty's master")?;
    let mut m = SeedMachine::new();
    let mut report = |r: &Received| {
        match r {
            Received::Stored {
                program,
                stitches,
                run,
            } => println!(
                "program {program} stored: {stitches} stitches sewn in {}, {} fault(s)",
                duration(run.total_seconds),
                run.faults.len()
            ),
            Received::Refused(e) => println!("refused: {e}"),
        }
        let _ = std::io::stdout().flush();
    };
    m.serve(&mut master, &|| false, &mut report)
        .context("reading the pseudo-terminal")?;
    drop(p);
    Ok(ExitCode::SUCCESS)
}
