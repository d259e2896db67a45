//! `oficina`: the command line. Each subcommand lives in its own module and only wires
//! arguments to the library crates; no domain logic here.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "oficina", version, about = "Open CNC workshop: from design to a moving machine")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Benchmarks that print figures beside the named peer's on the same input.
    #[command(subcommand)]
    Bench(BenchCommand),
}

#[derive(Subcommand)]
enum BenchCommand {}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: anyhow::Result<ExitCode> = match cli.command {
        Command::Bench(which) => match which {},
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("oficina: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
