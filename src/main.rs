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
            eprintln!("error: {}", one_line(&error));
            ExitCode::FAILURE
        }
    }
}

/// One line naming the problem: the cause chain joined by ": ", leaving out
/// a cause that its parent's message already quotes (database errors do).
fn one_line(error: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in error.chain().map(|c| c.to_string()) {
        if !line.ends_with(&cause) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&cause);
        }
    }
    line
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_cause_already_quoted_by_its_parent_is_not_repeated() {
        let io = std::io::Error::new(std::io::ErrorKind::ConnectionRefused, "refused");
        let error = anyhow::Error::new(sqlx::Error::Io(io)).context("opening the database");
        assert_eq!(
            super::one_line(&error),
            "opening the database: error communicating with database: refused"
        );
        let plain = anyhow::anyhow!("line 3: expected 3 columns").context("reading x.csv");
        assert_eq!(
            super::one_line(&plain),
            "reading x.csv: line 3: expected 3 columns"
        );
    }
}
