//! `patchwork`: the command-line interface and the HTTP service (`patchwork serve`).
//! Thin by design: parse arguments, call the core, print.

mod cli;
mod reports;
mod service;

#[cfg(test)]
mod plan_parity;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::install_panic_hook();
    match cli::run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // One line naming the problem; the full cause chain joined by ": ".
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
