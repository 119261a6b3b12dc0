//! The users' suite in the benchmark report: its goals (issue 42's: the
//! median and worst shape error within reach against the curve meant,
//! patches on every curve, a noisy stroke beside its clean stroke) and its
//! section.

use std::path::Path;

use super::row::{Row, median};
use super::users::clean_stroke_of;

/// A row's shape error against the curve the user meant: the clean curve a
/// drawn target was drawn from, or the curve as given.
fn meant_error(row: &Row) -> f64 {
    match row.figures.clean_error_percent.is_finite() {
        true => row.figures.clean_error_percent,
        false => row.figures.reference_error_percent,
    }
}

/// The users' suite against issue 42's goals.
pub struct UsersGoals {
    pub curves: usize,
    /// Median and worst within reach, against the curve meant (%).
    pub median: f64,
    pub worst: f64,
    /// Curves designed without any patch.
    without_patches: Vec<String>,
    /// Most a noisy copy's error (against its clean curve) exceeds its
    /// clean curve's design (percentage points).
    noisy_gap: f64,
}

impl UsersGoals {
    pub fn of(rows: &[Row]) -> UsersGoals {
        let within: Vec<f64> = rows
            .iter()
            .filter(|r| r.reach == "yes")
            .map(meant_error)
            .collect();
        let noisy_gap = rows
            .iter()
            .filter(|r| r.figures.clean_error_percent.is_finite())
            .filter_map(|noisy| {
                let clean = clean_stroke_of(&noisy.curve)?;
                let clean = rows.iter().find(|r| r.curve == clean)?;
                Some(noisy.figures.clean_error_percent - clean.figures.reference_error_percent)
            })
            .fold(f64::NAN, f64::max);
        UsersGoals {
            curves: rows.len(),
            median: median(within.clone()),
            worst: within.iter().copied().fold(f64::NAN, f64::max),
            without_patches: rows
                .iter()
                .filter(|r| r.figures.patches < 1.0)
                .map(|r| r.curve.clone())
                .collect(),
            noisy_gap,
        }
    }

    /// (goal, result, met) per goal.
    fn rows(&self) -> [(String, String, bool); 4] {
        let none = self.without_patches.is_empty();
        [
            (
                "median within reach ≤ 0.5 %".into(),
                format!("{:.2} %", self.median),
                self.median <= 0.5,
            ),
            (
                "worst within reach ≤ 1.5 %".into(),
                format!("{:.2} %", self.worst),
                self.worst <= 1.5,
            ),
            (
                "every curve gets patches".into(),
                match none {
                    true => "all do".into(),
                    false => format!("none on {}", self.without_patches.join(", ")),
                },
                none,
            ),
            (
                "a noisy stroke within 0.3 points of its clean stroke's design".into(),
                format!("at most {:+.2} points", self.noisy_gap),
                self.noisy_gap <= 0.3,
            ),
        ]
    }

    pub fn met(&self) -> usize {
        self.rows().iter().filter(|(_, _, met)| *met).count()
    }
}

pub fn users_section(rows: &[Row], goals: &UsersGoals, out: &Path) -> String {
    let mut s = format!(
        "## Curves as users send them\n\n\
         Curves as they arrive rather than as presets write them, each designed \
         under `draft` from the points alone (seed 1): gentle arcs (radius \
         200–600 mm), sparse CAD exports (15–22 points) of helices, a conical \
         spiral and a spline, seeded 3D strokes with 0.3, 0.6 and 1 mm of noise \
         beside the clean strokes they were drawn from, and five kinds the suite \
         above lacks (a saddle, a planar wave, Viviani's curve, a planar \
         Archimedean spiral, a question mark: a straight stem into a 240° bend). \
         Shape error on the reference model against the curve as given, and \
         for a noisy stroke against its clean stroke (the curve meant). Every \
         figure: [`{0}/users.md`]({0}/users.md).\n\n\
         | goal (curves within reach) | result | met |\n|---|---|---|\n",
        out.display()
    );
    for (goal, result, met) in goals.rows() {
        let met = if met { "yes" } else { "**no**" };
        s.push_str(&format!("| {goal} | {result} | {met} |\n"));
    }
    s.push_str(
        "\n| curve | shape error % (as given) | against the curve meant % | patches | within reach | wall s |\n\
         |---|---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {:.2} | {:.2} | {:.0} | {} | {:.1} |\n",
            r.curve,
            r.figures.reference_error_percent,
            meant_error(r),
            r.figures.patches,
            r.reach,
            r.figures.wall_s
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::bench::row::Sample;

    fn row(curve: &str, error: f64, clean: f64, patches: f64, reach: &str) -> Row {
        Row {
            curve: curve.into(),
            setting: "draft".into(),
            figures: Sample {
                reference_error_percent: error,
                clean_error_percent: clean,
                patches,
                ..Sample::unknown()
            },
            runs: Vec::new(),
            reach: reach.into(),
            failures: 0,
            stages: Vec::new(),
            design: None,
        }
    }

    /// The goals count curves within reach only, a noisy stroke against its
    /// clean stroke (the curve meant) and beside its clean stroke's design,
    /// and name the curves left without patches.
    #[test]
    fn the_users_goals_judge_the_curve_meant_within_reach() {
        let nan = f64::NAN;
        let rows = [
            row("gentle arc", 0.4, nan, 3.0, "yes"),
            row("stroke A (±0.3 mm)", 0.2, 0.7, 6.0, "yes"),
            row("stroke A, clean", 0.3, nan, 5.0, "yes"),
            row("kink", 9.0, nan, 0.0, "no: s 10–12 mm needs r 3 mm"),
        ];
        let goals = UsersGoals::of(&rows);
        assert_eq!(goals.curves, 4);
        // Within reach, against the curve meant: 0.4, 0.7 (not 0.2), 0.3.
        assert!((goals.median - 0.4).abs() < 1e-12, "{}", goals.median);
        assert!((goals.worst - 0.7).abs() < 1e-12, "{}", goals.worst);
        assert!((goals.noisy_gap - 0.4).abs() < 1e-12, "{}", goals.noisy_gap);
        assert_eq!(goals.without_patches, ["kink"]);
        let met: Vec<bool> = goals.rows().iter().map(|(_, _, met)| *met).collect();
        assert_eq!(met, [true, true, false, false]);
        assert_eq!(goals.met(), 2);
    }
}
