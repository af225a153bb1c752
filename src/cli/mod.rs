//! Command-line interface: argument parsing and dispatch to the subcommands.

mod design;
mod reproduce;
mod sdp;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Observer design and certification for plants with sporadic measurements.
#[derive(Debug, Parser)]
#[command(name = "sporadic", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Design an observer for a plant file with one method; print gains and certificate.
    Design(design::DesignArgs),
    /// Find the largest certified sampling window of a plant file with one method.
    MaxInterval(design::MaxIntervalArgs),
    /// Run every applicable method on a plant file and compare the certified windows.
    Compare(design::CompareArgs),
    /// Reproduce the examples of the implemented papers (`all`, or one paper id).
    Reproduce(reproduce::Args),
    /// Solve SDPA sparse files with our interior-point solver, or benchmark it.
    Sdp(sdp::Args),
}

/// Parses the command line, runs the subcommand and maps errors to a non-zero exit code with a
/// one-line message (never a panic backtrace).
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Design(args) => design::design(&args),
        Command::MaxInterval(args) => design::max_interval(&args),
        Command::Compare(args) => design::compare(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Sdp(args) => return sdp::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
