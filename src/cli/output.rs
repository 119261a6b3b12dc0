//! Writing results to stdout without panicking when the reader goes away
//! (`patchwork preset helix | head`).

use std::io::{ErrorKind, Write};

use anyhow::Result;
use serde::Serialize;

/// Writes `text` to stdout; a closed pipe ends output quietly.
pub fn emit(text: &str) -> Result<()> {
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() != ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// Pretty JSON with a trailing newline.
pub fn emit_json(value: &impl Serialize) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    emit(&text)
}
