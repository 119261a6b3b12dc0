//! The rows of a bench.md table read back, to redraw its plot
//! (`patchwork bench --replot bench.md`): the figures the plot uses (curve,
//! setting, wall time, shape error on the reference model); the others NaN.

use anyhow::{Context, Result};

use super::row::{Row, Sample};

/// Every row of the table in `text` (the format `render::table` writes).
pub fn rows(text: &str) -> Result<Vec<Row>> {
    let mut lines = text.lines().filter(|l| l.starts_with('|'));
    let header = cells(lines.next().context("no table in the file")?);
    let column = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .with_context(|| format!("the table has no column {name:?}"))
    };
    let (curve, setting) = (column("curve")?, column("setting")?);
    let (wall, error) = (column("wall s")?, column("shape error % (reference)")?);
    let number = |cells: &[&str], i: usize| cells.get(i).and_then(|c| c.parse().ok());
    let mut rows = Vec::new();
    for line in lines.filter(|l| !l.starts_with("|---")) {
        let cells = cells(line);
        rows.push(Row {
            curve: cells
                .get(curve)
                .context("a row without its curve")?
                .to_string(),
            setting: cells
                .get(setting)
                .context("a row without its setting")?
                .to_string(),
            figures: Sample {
                wall_s: number(&cells, wall).unwrap_or(f64::NAN),
                reference_error_percent: number(&cells, error).unwrap_or(f64::NAN),
                ..Sample::unknown()
            },
            runs: Vec::new(),
            reach: String::new(),
            failures: 0,
            stages: Vec::new(),
            design: None,
        });
    }
    Ok(rows)
}

fn cells(line: &str) -> Vec<&str> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    inner.split('|').map(str::trim).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_reads_back_into_rows() {
        let text = "`cmd`\n\n| curve | setting | wall s | shape error % (reference) | x |\n\
                    |---|---|---|---|---|\n| hook | draft | 12.0 | 0.13 | – |\n| hook | standard | 15.8 | 0.04 | – |\n";
        let rows = rows(text).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(
            (rows[1].curve.as_str(), rows[1].setting.as_str()),
            ("hook", "standard")
        );
        assert_eq!(rows[1].figures.wall_s, 15.8);
        assert_eq!(rows[0].figures.reference_error_percent, 0.13);
        assert!(rows[0].figures.evaluations.is_nan());
        assert!(super::rows("no table").is_err());
    }
}
