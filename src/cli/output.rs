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

/// The human patch table shared by `ksa` and `design`; `note(i)` adds a
/// remark after row i.
pub fn patch_table(
    patches: &[patchwork_core::design::Patch],
    note: impl Fn(usize) -> &'static str,
) -> String {
    let mut text = String::from("patch    X (mm)    Y (mm)    H (mm)    W (mm)    Θ (deg)\n");
    for (i, p) in patches.iter().enumerate() {
        // Rounded for display so −1e−12 shows as 0.00, not −0.00.
        let theta = (p.theta_deg * 100.0).round() / 100.0 + 0.0;
        text.push_str(&format!(
            "P{:<5} {:>8.3}  {:>8.2}  {:>8.2}  {:>8.2}  {:>9.2}{}\n",
            i + 1,
            p.x_mm,
            p.y_mm,
            p.h_mm,
            p.w_mm,
            theta,
            note(i)
        ));
    }
    text
}

/// Points as `x,y,z` CSV with a header, each coordinate in full (the
/// shortest decimal that reads back to the same number): `simulate`'s
/// centreline, the bench's curves.
pub fn points_csv(points: &[patchwork_core::curve::Point]) -> String {
    std::iter::once("x,y,z\n".to_string())
        .chain(points.iter().map(|p| format!("{},{},{}\n", p.x, p.y, p.z)))
        .collect()
}
