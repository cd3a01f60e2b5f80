//! `adaptcloth`: parses the command line and runs the command (`adaptcloth::cli`); the exit code
//! comes from the one error type, [`adaptcloth::cli::CliError`].
use adaptcloth::cli::{self, args::Cli};
use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = Cli::parse();
    match cli::set_threads(args.threads).and_then(|()| cli::execute(args.command)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let message = e.to_string();
            if !message.is_empty() {
                eprintln!("error: {message}");
            }
            ExitCode::from(e.exit_code())
        }
    }
}
