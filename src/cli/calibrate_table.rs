//! The CSV tables `calibrate` reads: a header naming the columns, one
//! measurement per line, `#` comments and blank lines skipped, an empty cell
//! not measured. Errors name the line and the column.

use anyhow::{Result, anyhow, bail};

/// The cells of the columns asked for, required ones first, by line.
pub struct Table {
    /// (line number from 1, one cell per column asked for).
    pub rows: Vec<(usize, Vec<Option<f64>>)>,
    /// Which columns asked for the header has.
    present: Vec<bool>,
}

impl Table {
    /// Whether column `i` (as asked for) is in the header.
    pub fn has(&self, i: usize) -> bool {
        self.present[i]
    }
}

/// `text`'s columns `required` (each must be in the header and in every
/// line) and `optional`.
pub fn read_table(text: &str, required: &[&str], optional: &[&str]) -> Result<Table> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (header_index, header) = lines.next().ok_or_else(|| anyhow!("no header line"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let column = |name: &str| names.iter().position(|n| *n == name);
    let mut columns = Vec::new();
    for name in required {
        columns.push(Some(column(name).ok_or_else(|| {
            anyhow!("line {}: no `{name}` column", header_index + 1)
        })?));
    }
    columns.extend(optional.iter().map(|name| column(name)));
    let present = columns.iter().map(Option::is_some).collect();
    let mut rows = Vec::new();
    for (number, line) in lines {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let mut values = Vec::new();
        for (k, index) in columns.iter().enumerate() {
            let cell = index.and_then(|i| cells.get(i)).filter(|c| !c.is_empty());
            let value = match cell {
                None if k < required.len() => {
                    bail!("line {}: no `{}`", number + 1, required[k])
                }
                None => None,
                Some(text) => Some(
                    text.parse::<f64>()
                        .map_err(|_| anyhow!("line {}: {text:?} is not a number", number + 1))?,
                ),
            };
            values.push(value);
        }
        rows.push((number + 1, values));
    }
    Ok(Table { rows, present })
}
