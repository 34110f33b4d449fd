//! `rocking`: the command-line front of the library. Every subcommand is a thin shell over
//! library functions; see `src/cmd/`.

mod cmd;

use clap::{Parser, Subcommand};

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

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Analyze(a) => cmd::analyze::run(a),
        Command::Generate(a) => cmd::generate::run(a),
        Command::Planar(a) => cmd::planar::run(a),
        Command::Drop(a) => cmd::drop::run_drop(a),
        Command::Merge(a) => cmd::drop::run_merge(a),
        Command::Perturb(a) => cmd::perturb::run(a),
        Command::Shake(a) => cmd::shake::run(*a),
        Command::Study(a) => cmd::study::run(a),
    };
    if let Err(e) = result {
        match e.downcast_ref::<rocking_stones::Error>() {
            Some(err @ rocking_stones::Error::Parameter { .. }) => eprintln!("error: {}", err.spelled(&cmd::flag)),
            _ => eprintln!("error: {e:#}"),
        }
        std::process::exit(1);
    }
}
