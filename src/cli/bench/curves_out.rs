//! The curves a suite designs, written as `x,y,z` CSV files beside its
//! table (`--out`/curves/NAME.csv), so that any of its cases — a round
//! trip's simulated target, a drawn stroke with its jitter — can be
//! designed again from the command line with `patchwork design`.

use std::path::Path;

use anyhow::{Context, Result};

use super::super::output::points_csv;
use super::cases::Target;

/// Writes each target's curve to `dir`/[`file_name`] ([`points_csv`]).
pub fn write_curves(dir: &Path, targets: &[Target]) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for target in targets {
        let path = dir.join(file_name(&target.name));
        std::fs::write(&path, points_csv(target.curve.points()))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}

/// A case's file name: its name in lower case, every run of other
/// characters than ASCII letters and digits one hyphen ("trip 8: 6
/// patches, 2+3+1" → `trip-8-6-patches-2-3-1.csv`).
pub fn file_name(name: &str) -> String {
    let mut slug = String::new();
    for c in name.chars() {
        match c.is_ascii_alphanumeric() {
            true => slug.push(c.to_ascii_lowercase()),
            false if !slug.is_empty() && !slug.ends_with('-') => slug.push('-'),
            false => {}
        }
    }
    format!("{}.csv", slug.trim_end_matches('-'))
}

#[cfg(test)]
mod tests {
    use super::*;
    use patchwork_core::curve::{Curve, Point, Units, read_curve};

    #[test]
    fn a_case_name_becomes_a_plain_file_name() {
        assert_eq!(
            file_name("trip 8: 6 patches, 2+3+1"),
            "trip-8-6-patches-2-3-1.csv"
        );
        assert_eq!(
            file_name("helix r30→50, pitch 40→80"),
            "helix-r30-50-pitch-40-80.csv"
        );
        assert_eq!(
            file_name("hand-drawn hook (±0.3 mm)"),
            "hand-drawn-hook-0-3-mm.csv"
        );
    }

    /// The written points read back, through the reader `patchwork design`
    /// uses, to the same numbers, bit for bit.
    #[test]
    fn a_written_curve_reads_back_exactly() {
        let points: Vec<Point> = (0..5)
            .map(|i| {
                let t = i as f64 / 3.0;
                Point::new(10.0 * t, t.sqrt(), 1e-9 * t.exp())
            })
            .collect();
        let curve = Curve::from_points(points.clone()).unwrap();
        let dir = std::env::temp_dir().join(format!("pw-curves-out-{}", std::process::id()));
        let target = Target {
            name: "a case: one".into(),
            curve,
            clean: None,
        };
        write_curves(&dir, &[target]).unwrap();
        let text = std::fs::read_to_string(dir.join("a-case-one.csv")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let read = read_curve(&text, Units::Mm).unwrap().points().to_vec();
        for (p, r) in points.iter().zip(&read) {
            assert_eq!([p.x, p.y, p.z], [r.x, r.y, r.z]);
        }
        assert_eq!(read.len(), points.len());
    }
}
