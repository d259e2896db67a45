//! `oficina emulate grbl`: a grbl 1.1 emulator on a pseudo-terminal and/or a TCP port, to
//! dry-run jobs and senders (ours or any other) against the exact protocol; `oficina emulate
//! marlin`: a Marlin 2.x board (a Makelangelo) with faults injected on the wire.

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
    /// Marlin 2.x as a Makelangelo runs it: numbered, checksummed lines, Resend, keep-alives.
    Marlin,
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
    /// grbl: run the machine's clock N times faster than real time (motion and dwells; the
    /// wire is unchanged), e.g. to dry-run a long program to its end.
    #[arg(long, default_value_t = 1.0, value_name = "N")]
    pub time_scale: f64,
    /// marlin: the first time line N arrives, one of its bytes is changed on the wire
    /// (Marlin answers `Error:checksum mismatch` and `Resend: N`).
    #[arg(long, value_name = "N")]
    pub corrupt_line: Option<u32>,
    /// marlin: every K-th numbered line is lost on the wire (no reply: the host must time
    /// out and send it again).
    #[arg(long, value_name = "K")]
    pub drop_every: Option<u32>,
    /// marlin: G28 and M400 take this long, printing `busy: processing` keep-alives, ms.
    #[arg(long, default_value_t = 0, value_name = "MS")]
    pub busy_ms: u64,
    /// marlin: keep-alive period (Marlin's M113; 2 s by default), ms.
    #[arg(long, default_value_t = 2000, value_name = "MS")]
    pub keepalive_ms: u64,
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
    if let Firmware::Marlin = args.firmware {
        return run_marlin(&args);
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
    if !(args.time_scale.is_finite() && (0.01..=10_000.0).contains(&args.time_scale)) {
        anyhow::bail!("--time-scale {}: between 0.01 and 10000", args.time_scale);
    }
    let base = Config::flavored(args.flavor);
    let config = Config {
        probe: crate::emulate_probe::model(&args.probe)?,
        baud: (args.baud > 0).then_some(args.baud),
        limit_switches: !args.no_limit_switches,
        time_scale: args.time_scale,
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

/// `oficina emulate marlin`: serves until `--for-seconds` pass, then prints what it did.
fn run_marlin(args: &Args) -> anyhow::Result<ExitCode> {
    if args.drop_every == Some(1) {
        bail!("--drop-every 1 would lose every line: use 2 or more");
    }
    let emu = oficina_grbl_emu::MarlinEmulator::start(oficina_grbl_emu::MarlinConfig {
        corrupt_line: args.corrupt_line,
        drop_every: args.drop_every,
        busy_ms: args.busy_ms,
        keepalive_ms: args.keepalive_ms.max(1),
        ..Default::default()
    });
    if args.pty {
        let path = emu.serve_pty().context("cannot open a pseudo-terminal")?;
        say(&format!(
            "marlin emulator on pty {path} (use --machine marlin:{path})"
        ));
    }
    if let Some(addr) = &args.tcp {
        let local = emu
            .serve_tcp(addr)
            .with_context(|| format!("cannot listen on {addr}"))?;
        say(&format!(
            "marlin emulator on tcp://{local} (use --machine marlin+tcp://{local})"
        ));
    }
    let start = std::time::Instant::now();
    while args
        .for_seconds
        .is_none_or(|limit| start.elapsed().as_secs_f64() < limit)
    {
        std::thread::sleep(Duration::from_millis(100));
    }
    let st = emu.stats();
    let at = emu.moves().last().map_or([0.0; 3], |m| m.to);
    say(&format!(
        "emulator stats: {} lines received, {} executed, {} refused by checksum, {} by line number, {} dropped, {} corrupted; at X{:.3} Y{:.3} Z{:.3}",
        st.lines_received,
        st.lines_executed,
        st.checksum_errors,
        st.line_number_errors,
        st.dropped,
        st.corrupted,
        at[0],
        at[1],
        at[2]
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
