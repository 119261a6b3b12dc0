//! Runs a CalculiX deck in a folder and reads back what ccx wrote.

use std::path::Path;
use std::process::Command;

/// What one ccx run left.
pub struct Output {
    /// ccx's standard output.
    pub log: String,
    /// The `.dat` file: what the deck's `*NODE PRINT` asked for.
    pub dat: String,
    /// Exit status zero and no `*ERROR` in the log.
    pub clean: bool,
    pub seconds: f64,
}

/// Writes `deck` as `tube.inp` into `dir` and runs `ccx` there on 2 threads.
pub fn run_deck(dir: &Path, deck: &str) -> Result<Output, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::write(dir.join("tube.inp"), deck).map_err(|e| format!("writing tube.inp: {e}"))?;
    let started = std::time::Instant::now();
    let output = Command::new("ccx")
        .args(["-i", "tube"])
        .current_dir(dir)
        .env("OMP_NUM_THREADS", "2")
        .output()
        .map_err(|e| format!("cannot run ccx: {e}"))?;
    let seconds = started.elapsed().as_secs_f64();
    let log = String::from_utf8_lossy(&output.stdout).into_owned();
    let dat = std::fs::read_to_string(dir.join("tube.dat")).map_err(|e| {
        format!(
            "ccx wrote no tube.dat ({e}); its output ends:\n{}",
            tail(&log)
        )
    })?;
    Ok(Output {
        clean: output.status.success() && !log.contains("*ERROR"),
        log,
        dat,
        seconds,
    })
}

/// The last lines of ccx's log, for an error message.
pub fn tail(log: &str) -> String {
    let lines: Vec<&str> = log.lines().collect();
    lines[lines.len().saturating_sub(15)..].join("\n")
}
