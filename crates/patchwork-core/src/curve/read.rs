//! Reading target curves from text (CSV or whitespace-separated) and JSON.

use std::str::FromStr;

use serde::Deserialize;

use super::{Curve, CurveError, Location, Point};

/// Length units accepted on input. Everything inside Patchwork is millimetres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    #[default]
    Mm,
    Cm,
    M,
    In,
}

impl Units {
    /// Millimetres per unit.
    pub fn to_mm(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Cm => 10.0,
            Units::M => 1000.0,
            Units::In => 25.4,
        }
    }
}

impl FromStr for Units {
    type Err = CurveError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim().to_ascii_lowercase().as_str() {
            "mm" => Ok(Units::Mm),
            "cm" => Ok(Units::Cm),
            "m" => Ok(Units::M),
            "in" | "inch" | "inches" => Ok(Units::In),
            _ => Err(CurveError::UnknownUnits(text.to_string())),
        }
    }
}

/// Reads a curve in either format: JSON when the first non-blank character is
/// `{`, text otherwise. `units` applies to text input and to JSON without a
/// `units` field.
pub fn read_curve(input: &str, units: Units) -> Result<Curve, CurveError> {
    let input = input.strip_prefix('\u{feff}').unwrap_or(input);
    if input.trim_start().starts_with('{') {
        read_json(input, units)
    } else {
        read_text(input, units)
    }
}

/// Reads `x y z` per line, separated by commas (CSV) or whitespace. Blank lines
/// and `#` comments are skipped; the first content line may be a header (no
/// numeric field). Errors name the 1-based line.
pub fn read_text(input: &str, units: Units) -> Result<Curve, CurveError> {
    let scale = units.to_mm();
    let mut points = Vec::new();
    let mut lines = Vec::new();
    let mut seen_content = false;
    for (index, raw) in input.lines().enumerate() {
        let line_no = index + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let fields = split_fields(content);
        let first_content = !seen_content;
        seen_content = true;
        if first_content && fields.iter().all(|f| looks_like_column_name(f)) {
            continue; // a header such as `x,y,z` or `X (mm)	Y (mm)	Z (mm)`
        }
        if points.len() >= Curve::MAX_POINTS {
            return Err(CurveError::TooManyPoints {
                found: points.len() + 1,
                max: Curve::MAX_POINTS,
            });
        }
        if fields.len() != 3 {
            return Err(CurveError::WrongColumnCount {
                at: Location::Line(line_no),
                found: fields.len(),
            });
        }
        let mut xyz = [0.0; 3];
        for (column, field) in fields.iter().enumerate() {
            let value = field.parse().map_err(|_| CurveError::NotANumber {
                at: Location::Line(line_no),
                column: column + 1,
                text: field.to_string(),
            })?;
            xyz[column] = within_range(value, Location::Line(line_no), column + 1)?;
        }
        points.push(Point::from(xyz) * scale);
        lines.push(line_no);
    }
    Curve::from_located_points(points, |i| Location::Line(lines[i]))
}

/// A header field names a column: it has a letter, is not itself a number
/// (`nan`, `inf` are numbers here), and holds no control characters (binary junk).
fn looks_like_column_name(field: &str) -> bool {
    field.parse::<f64>().is_err()
        && field.chars().any(char::is_alphabetic)
        && !field.chars().any(char::is_control)
}

fn split_fields(content: &str) -> Vec<&str> {
    if content.contains(',') {
        content.split(',').map(str::trim).collect()
    } else if content.contains(';') {
        content.split(';').map(str::trim).collect()
    } else {
        content.split_whitespace().collect()
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CurveJson {
    points: Vec<Vec<serde_json::Value>>,
    #[serde(default)]
    units: Option<String>,
}

/// Reads `{"points": [[x, y, z], ...], "units": "mm"}`. Errors name the index
/// into `points`.
pub fn read_json(input: &str, units: Units) -> Result<Curve, CurveError> {
    let parsed: CurveJson =
        serde_json::from_str(input).map_err(|e| CurveError::Json(e.to_string()))?;
    let units = match parsed.units {
        Some(text) => text.parse()?,
        None => units,
    };
    points_from_json(&parsed.points, units)
}

/// The largest coordinate magnitude accepted, in the curve's own units
/// (a kilometre in millimetres; beyond it lengths lose their precision).
pub const MAX_COORDINATE: f64 = 1e6;

/// `value` if it is at most [`MAX_COORDINATE`] in magnitude; a non-finite
/// value passes, for the curve's own check to name its axis.
fn within_range(value: f64, at: Location, column: usize) -> Result<f64, CurveError> {
    if value.is_finite() && value.abs() > MAX_COORDINATE {
        return Err(CurveError::OutOfRange { at, column, value });
    }
    Ok(value)
}

/// Converts already-parsed JSON rows (as in an API request) into a curve.
pub fn points_from_json(
    rows: &[Vec<serde_json::Value>],
    units: Units,
) -> Result<Curve, CurveError> {
    if rows.len() > Curve::MAX_POINTS {
        return Err(CurveError::TooManyPoints {
            found: rows.len(),
            max: Curve::MAX_POINTS,
        });
    }
    let scale = units.to_mm();
    let mut points = Vec::with_capacity(rows.len());
    for (index, row) in rows.iter().enumerate() {
        if row.len() != 3 {
            return Err(CurveError::WrongColumnCount {
                at: Location::Index(index),
                found: row.len(),
            });
        }
        let mut xyz = [0.0; 3];
        for (column, value) in row.iter().enumerate() {
            let number = value.as_f64().ok_or_else(|| CurveError::NotANumber {
                at: Location::Index(index),
                column: column + 1,
                text: value.to_string(),
            })?;
            xyz[column] = within_range(number, Location::Index(index), column + 1)?;
        }
        points.push(Point::from(xyz) * scale);
    }
    Curve::from_points(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_csv_with_header_comments_and_units() {
        let text = "# a comment\nx,y,z\n0,0,0\n1,0,0 # trailing\n\n2,0,0\n3,1,0\n";
        let c = read_text(text, Units::Cm).unwrap();
        assert_eq!(c.len(), 4);
        assert_eq!(c.points()[3], Point::new(30.0, 10.0, 0.0));
    }

    #[test]
    fn reads_whitespace_and_semicolons() {
        let c = read_text("0 0 0\n1\t0 0\n2 0  0\n3 0 1\n", Units::Mm).unwrap();
        assert_eq!(c.len(), 4);
        let c = read_text("0;0;0\n1;0;0\n2;0;0\n3;0;1\n", Units::Mm).unwrap();
        assert_eq!(c.len(), 4);
    }

    #[test]
    fn errors_name_the_line() {
        let err = read_text("x,y,z\n0,0,0\n1,0\n", Units::Mm).unwrap_err();
        assert_eq!(
            err.to_string(),
            "line 3: expected 3 columns (x y z), found 2"
        );
        let err = read_text("0,0,0\n1,0,0\n2,abc,0\n3,0,0", Units::Mm).unwrap_err();
        assert_eq!(err.to_string(), "line 3: column 2 is not a number: \"abc\"");
        let err = read_text("0,0,0\n\n1,0,0\n2,0,nan\n3,0,0", Units::Mm).unwrap_err();
        assert_eq!(err.to_string(), "line 4: coordinate z is not finite (NaN)");
        let err = read_text("0,0,0\n1,,0\n", Units::Mm).unwrap_err();
        assert!(err.to_string().starts_with("line 2: column 2"));
    }

    #[test]
    fn header_only_after_comments_and_never_later() {
        let err = read_text("0,0,0\nx,y,z\n", Units::Mm).unwrap_err();
        assert!(matches!(
            err,
            CurveError::NotANumber {
                at: Location::Line(2),
                ..
            }
        ));
    }

    #[test]
    fn reads_json_with_units_and_names_index() {
        let c = read_curve(
            r#"{"points": [[0,0,0],[1,0,0],[2,0,0],[2,1,0]], "units": "m"}"#,
            Units::Mm,
        )
        .unwrap();
        assert_eq!(c.points()[3], Point::new(2000.0, 1000.0, 0.0));
        let err = read_curve(r#"{"points": [[0,0,0],[1,0],[2,0,0],[2,1,0]]}"#, Units::Mm);
        assert_eq!(
            err.unwrap_err().to_string(),
            "points[1]: expected 3 columns (x y z), found 2"
        );
        let err = read_curve(
            r#"{"points": [[0,0,0],[1,0,0],[2,"a",0],[2,1,0]]}"#,
            Units::Mm,
        );
        assert!(
            err.unwrap_err()
                .to_string()
                .starts_with("points[2]: column 2")
        );
        let err = read_curve(r#"{"points": [[0,0,0]], "units": "furlong"}"#, Units::Mm);
        assert!(matches!(err.unwrap_err(), CurveError::UnknownUnits(_)));
        let err = read_curve(r#"{"points": [[0,0,0],[1,0,0],[1e999,0,0]]}"#, Units::Mm);
        assert!(err.is_err());
    }

    #[test]
    fn too_many_points_is_refused_early() {
        let text: String = (0..=Curve::MAX_POINTS)
            .map(|i| format!("{i},0,0\n"))
            .collect();
        assert!(matches!(
            read_text(&text, Units::Mm).unwrap_err(),
            CurveError::TooManyPoints { .. }
        ));
    }

    #[test]
    fn coordinates_beyond_a_million_units_are_named() {
        let text = "0,0,0\n1,0,0\n2,0,2000000\n3,0,0\n";
        let err = read_text(text, Units::Mm).unwrap_err();
        assert_eq!(
            err.to_string(),
            "line 3: column 3 is 2000000, beyond ±1000000 (in the curve's units)"
        );
        let rows = vec![vec![serde_json::json!(-1.5e6), 0.into(), 0.into()]];
        let err = points_from_json(&rows, Units::M).unwrap_err();
        assert!(err.to_string().starts_with("points[0]: column 1"), "{err}");
        assert!(read_text("0,0,0\n1,0,0\n2,0,1000000\n3,0,0\n", Units::Mm).is_ok());
    }
}
