//! `rocking`: the command-line front of the library. Every subcommand is a thin shell over
//! library functions; see `src/cmd/`.

mod cmd;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

/// Equilibria, flocks and rocking positions of pebbles and rocking stones.
#[derive(Parser)]
#[command(name = "rocking", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Micro-equilibria (and flocks) of one or more scans; the bundled pebble if none is given.
    Analyze(cmd::analyze::Args),
    /// Write a synthetic shape (Platonic solid, box, ellipsoid, pebble) to a mesh file.
    Generate(cmd::generate::Args),
    /// The planar case: discretised ellipses and their flocks (paper §1.1).
    Planar(cmd::planar::Args),
    /// Drop the scanned hull many times in rapier3d: resting statistics vs the static theory.
    Drop(cmd::drop::Args),
    /// Combine partial drop results (shards, checkpoints) into the report of one run.
    Merge(cmd::drop::MergeArgs),
    /// Push a pebble resting on a stable micro-equilibrium: how robust is it, does it topple?
    Perturb(cmd::perturb::Args),
    /// Shake the ground under a resting pebble: fragility curves.
    Shake(Box<cmd::shake::Args>),
    /// Field study over a folder of scans, synthetic hand experiments, fitting ν.
    Study(cmd::study::Args),
}

/// Every command and subcommand takes a negative number as an option's value (`--nu -0.5`), so
/// that the option's own check, not the parser, says what values are allowed.
fn negative_numbers_allowed(mut c: clap::Command) -> clap::Command {
    let names: Vec<String> = c.get_subcommands().map(|s| s.get_name().to_string()).collect();
    for name in names {
        c = c.mut_subcommand(name, negative_numbers_allowed);
    }
    c.allow_negative_numbers(true)
}

/// The command line as parsed (clap's own errors, help and version exit here).
fn parse() -> Cli {
    let matches = negative_numbers_allowed(Cli::command()).get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}

/// Printing into a closed pipe (`rocking analyze | head`) ends the program quietly, as Unix
/// tools do, instead of a panic in `println!`: the signal's default action is restored (Rust
/// ignores SIGPIPE, which turns the write into an error that `println!` panics on).
fn exit_quietly_on_a_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to its default before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() {
    exit_quietly_on_a_closed_pipe();
    let cli = parse();
    let result = match cli.command {
        Command::Analyze(a) => cmd::analyze::run_analyze(a),
        Command::Generate(a) => cmd::generate::run_generate(a),
        Command::Planar(a) => cmd::planar::run_planar(a),
        Command::Drop(a) => cmd::drop::run_drop(a),
        Command::Merge(a) => cmd::drop::run_merge(a),
        Command::Perturb(a) => cmd::perturb::run_perturb(a),
        Command::Shake(a) => cmd::shake::run_shake(*a),
        Command::Study(a) => cmd::study::run_study(a),
    };
    if let Err(e) = result {
        match e.downcast_ref::<rocking_stones::Error>() {
            Some(err @ rocking_stones::Error::Parameter { .. }) => eprintln!("error: {}", err.spelled(&cmd::flag)),
            _ => eprintln!("error: {e:#}"),
        }
        std::process::exit(1);
    }
}
