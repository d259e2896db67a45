//! `oficina`: the command line. Each subcommand lives in its own module and only wires
//! arguments to the library crates.

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "oficina", version, about = "Open CNC workshop: from design to a moving machine")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    match cli.command {}
}
