//! `oficina emulate grbl`: a grbl 1.1 emulator on a pseudo-terminal and/or a TCP port, to
//! dry-run jobs and senders (ours or any other) against the exact protocol.

use anyhow::{bail, Context};
use oficina_grbl_emu::{Config, Emulator};
use std::io::Write;
use std::process::ExitCode;
use std::time::Duration;

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub(crate) enum Firmware {
    /// grbl 1.1h on an ATmega328P: 128-byte RX buffer, 15 planner blocks.
    Grbl,
    /// The seed 000 embroidery machine: receives .BOR programs (9600 7E2), stores, sews them.
    Seed,
}

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Firmware to emulate.
    #[arg(value_enum)]
    pub firmware: Firmware,
    /// Serve on a new pseudo-terminal and print its path (open it as a serial port).
    #[arg(long)]
    pub pty: bool,
    /// Serve on this TCP address, e.g. 127.0.0.1:2323 (port 0 picks a free one).
    #[arg(long, value_name = "HOST:PORT")]
    pub tcp: Option<String>,
    /// Serial line rate to emulate, bits/s (10 bits a byte); 0 = no limit.
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
    /// Which firmware to be: grbl (1.1h: 15 blocks, 128-byte RX), grblhal (100 blocks,
    /// 1024 bytes, `Bf:` freed as soon as a block is prepared, silent TCP port) or fluidnc
    /// (FluidNC's banner and `[MSG:INFO:…]` lines).
    #[arg(long, default_value = "grbl", value_name = "grbl|grblhal|fluidnc")]
    pub flavor: oficina_grbl_emu::Flavor,
    /// Take $100-$132, $11 and $12 from an Oficina machine profile: a TOML file or a bundled
    /// name (e.g. grbl-router); a profile with `[joints.a]` adds grblHAL's 4th axis A
    /// ($103-$133, e.g. router-4axis).
    #[arg(long, alias = "machine", value_name = "PROFILE")]
    pub profile: Option<String>,
    /// Initial settings, e.g. --set 110=5000 --set 22=1 (repeatable; applied after --profile).
    #[arg(long = "set", value_name = "N=VALUE")]
    pub settings: Vec<String>,
    /// What the probe input touches (G38.2…G38.5) and the tool in the spindle.
    #[command(flatten)]
    pub probe: crate::emulate_probe::ProbeArgs,
    /// The board has no limit switches: `$H` (with `$22=1`) searches 1.5 × the Z travel
    /// ($132), then fails with ALARM:9, as a machine without switches does.
    #[arg(long)]
    pub no_limit_switches: bool,
    /// Stop after this many seconds (for scripts); default: run until interrupted.
    #[arg(long, value_name = "SECONDS")]
    pub for_seconds: Option<f64>,
}

fn parse_setting(s: &str) -> anyhow::Result<(u16, f64)> {
    let (n, v) = s
        .split_once('=')
        .with_context(|| format!("--set {s}: expected N=VALUE, e.g. 110=5000"))?;
    let n: u16 = n
        .trim_start_matches('$')
        .parse()
        .with_context(|| format!("--set {s}: '{n}' is not a setting number"))?;
    // grblHAL's 4th axis A ($103 steps/°, $113 °/min, $123 °/s², $133 travel).
    let a_axis = matches!(n, 103 | 113 | 123 | 133);
    if oficina_grbl::setting_info(n).is_none() && !a_axis {
        bail!("--set {s}: grbl 1.1 has no setting ${n}");
    }
    let v: f64 = v
        .parse()
        .with_context(|| format!("--set {s}: '{v}' is not a number"))?;
    Ok((n, v))
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    if let Firmware::Seed = args.firmware {
        return crate::emulate_seed::run(args.pty);
    }
    if !args.pty && args.tcp.is_none() {
        bail!("say where to serve the emulator: --pty, --tcp 127.0.0.1:PORT, or both");
    }
    let mut settings = match &args.profile {
        Some(spec) => {
            let profile = crate::machine_profile::resolve(spec)?;
            oficina_grbl_emu::grbl_settings(&profile).map_err(anyhow::Error::msg)?
        }
        None => Vec::new(),
    };
    let overrides = args
        .settings
        .iter()
        .map(|s| parse_setting(s))
        .collect::<anyhow::Result<Vec<_>>>()?;
    settings.extend(overrides);
    let base = Config::flavored(args.flavor);
    let config = Config {
        probe: crate::emulate_probe::model(&args.probe)?,
        baud: (args.baud > 0).then_some(args.baud),
        limit_switches: !args.no_limit_switches,
        settings: base.settings.iter().copied().chain(settings).collect(),
        ..base
    };
    let emu = Emulator::start(config);
    if args.pty {
        let path = emu.serve_pty().context("cannot open a pseudo-terminal")?;
        say(&format!(
            "{} emulator on pty {path} (open it as a serial port at any baud)",
            args.flavor
        ));
    }
    if let Some(addr) = &args.tcp {
        let local = emu
            .serve_tcp(addr)
            .with_context(|| format!("cannot listen on {addr}"))?;
        say(&format!("{} emulator on tcp://{local}", args.flavor));
    }
    say(&format!(
        "line rate: {}",
        if args.baud > 0 {
            format!("{} baud ({} bytes/s)", args.baud, args.baud / 10)
        } else {
            "unlimited".into()
        }
    ));
    let start = std::time::Instant::now();
    loop {
        std::thread::sleep(Duration::from_millis(100));
        if let Some(limit) = args.for_seconds {
            if start.elapsed().as_secs_f64() >= limit {
                break;
            }
        }
    }
    let st = emu.stats();
    say(&format!(
        "emulator stats: {} bytes received, {} lines executed, {} errors sent, {} RX overflows",
        st.bytes_received, st.lines_executed, st.errors_sent, st.rx_overflows
    ));
    Ok(ExitCode::SUCCESS)
}

/// Prints a line. Whoever started us may have stopped reading our output: that must not
/// take the emulator down.
fn say(s: &str) {
    let mut out = std::io::stdout();
    let _ = writeln!(out, "{s}");
    let _ = out.flush();
}
