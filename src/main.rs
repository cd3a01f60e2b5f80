//! `adaptcloth`: parses the command line and runs the command (`adaptcloth::cli`); the exit code
//! comes from the one error type, [`adaptcloth::cli::CliError`].
use adaptcloth::cli::{self, args::Cli};
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = Cli::parse();
    cli::configure_threads(cli.threads, cli.command.parallel_runs());
    // On a worker of the pool, so the force sweeps' parallel splits stay within the pool.
    match rayon::scope(|_| cli::execute(cli.command)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let message = e.to_string();
            if !message.is_empty() {
                adaptcloth::note!("error: {message}");
            }
            ExitCode::from(e.exit_code())
        }
    }
}
