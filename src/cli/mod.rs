//! Command-line interface: argument parsing, dispatch to the subcommands, and the exit-code
//! policy shared by every subcommand.

mod design;
mod init;
mod reproduce;
mod sdp;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Observer design and certification for plants with sporadic measurements.
///
/// Exit status, for every subcommand: 0 = ran and certified (design/verify with --prove: and
/// proved; compare: at least one method
/// certified the file's sampling or a searched window, andrieu2014's own sampling rule aside;
/// reproduce: the reproductions ran, whatever their claims' statuses; sdp solve: an
/// optimal status); 1 = ran, but nothing was certified or the method does not apply (sdp solve:
/// any non-optimal status); 2 = invalid or unreadable input, or a usage error.
#[derive(Debug, Parser)]
#[command(name = "sporadic", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Design an observer for a plant file with one method; print gains and certificate.
    ///
    /// A plant file is TOML; `sporadic init [--kind linear|round-robin|lipschitz|bounds]`
    /// writes a commented template.
    Design(design::DesignArgs),
    /// Check gains designed elsewhere (a design report's `gains`, edited or from MATLAB) for a
    /// plant file, optionally with a rigorous proof (`--prove`).
    Verify(design::VerifyArgs),
    /// Find the largest certified sampling window of a plant file with one method.
    ///
    /// The search keeps the file's T1 and moves T2. With round-robin sensors, T2 is the upper
    /// end of every sensor's window, raised to a sensor's own T1 where it is below it (the
    /// certified windows are printed with the certificate).
    MaxInterval(design::MaxIntervalArgs),
    /// Run every method on a plant file and compare the certified windows.
    Compare(design::CompareArgs),
    /// Reproduce the examples of the implemented papers (`all`, or one paper id).
    Reproduce(reproduce::Args),
    /// Solve SDPA sparse files with our interior-point solver, or benchmark it.
    Sdp(sdp::Args),
    /// Write a commented plant-file template (the plant-file format, with every field).
    Init(init::Args),
}

/// What a subcommand established (exit 0 or 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Certified (or: ran, for commands without a verdict).
    Certified,
    /// Ran, but nothing was certified or the method does not apply.
    NothingCertified,
}

/// Why a subcommand did not run to its verdict.
#[derive(Debug)]
pub enum Failure {
    /// Invalid or unreadable input, a usage error (exit 2).
    Input(String),
    /// The run itself failed (exit 1).
    Run(String),
}

/// Parses the command line, runs the subcommand and maps the outcome to the exit status (never
/// a panic backtrace; errors are one line on standard error).
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Design(args) => design::design(&args),
        Command::Verify(args) => design::verify(&args),
        Command::MaxInterval(args) => design::max_interval(&args),
        Command::Compare(args) => design::compare(&args),
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Init(args) => init::run(&args),
        Command::Sdp(args) => return sdp::run(&args),
    };
    match result {
        Ok(Outcome::Certified) => ExitCode::SUCCESS,
        Ok(Outcome::NothingCertified) => ExitCode::from(1),
        Err(Failure::Run(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
        Err(Failure::Input(message)) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}
