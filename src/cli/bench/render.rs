//! A suite's rows as `bench.md` (the table) and `bench.svg` (shape error
//! against wall time).

use patchwork_core::chart::{self, Axis, COLOURS, Mark, Panel, Series};

use patchwork_core::inverse::StageName;

use super::row::Row;

/// The rows as a Markdown table under the command that measured them.
pub fn table(rows: &[Row], command: &str) -> String {
    let mut out = format!(
        "`{command}` — medians over the runs\n\n\
         Shape error on the run's own verification model, and of its design \
         re-simulated on the common reference model (uniform 0.5 mm).\n\n\
         | curve | setting | wall s | evaluations | shape error % (own) | shape error % (reference) | against the clean curve % | DTW κ | DTW τ | patches | beyond limits | within reach | failed runs | seconds per stage (first run) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {:.2} | {:.0} | {:.2} | {:.2} | {} | {:.3} | {:.3} | {:.0} | {:.0} | {} | {} | {} |\n",
            r.curve,
            r.setting,
            r.figures.wall_s,
            r.figures.evaluations,
            r.figures.shape_error_percent,
            r.figures.reference_error_percent,
            match r.figures.clean_error_percent.is_finite() {
                true => format!("{:.2}", r.figures.clean_error_percent),
                false => "–".into(),
            },
            r.figures.dtw_curvature,
            r.figures.dtw_torsion,
            r.figures.patches,
            r.figures.beyond_limits,
            r.reach,
            r.failures,
            (r.stages.iter())
                .map(|(stage, s)| format!("{} {s:.1}", stage.as_str()))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    out
}

/// Where one setting's time went over all its curves' first runs: each
/// stage's share of the summed stage seconds, largest first ("search 41 %,
/// refine 33 %, …"); empty without stage times.
pub fn stage_shares(rows: &[Row], setting: &str) -> String {
    let mut totals: Vec<(StageName, f64)> = Vec::new();
    for (stage, seconds) in rows
        .iter()
        .filter(|r| r.setting == setting)
        .flat_map(|r| &r.stages)
    {
        match totals.iter_mut().find(|(s, _)| s == stage) {
            Some((_, total)) => *total += seconds,
            None => totals.push((*stage, *seconds)),
        }
    }
    let all: f64 = totals.iter().map(|(_, s)| s).sum();
    totals.sort_by(|a, b| b.1.total_cmp(&a.1));
    (totals.iter())
        .map(|(stage, s)| format!("{} {:.0} %", stage.as_str(), 100.0 * s / all))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Shape error against wall time (log scale), a colour per curve, each
/// curve's Pareto front (no other setting both faster and more accurate)
/// joined by a line.
pub fn plot(rows: &[Row]) -> String {
    let ok: Vec<&Row> = rows
        .iter()
        .filter(|r| r.figures.wall_s.is_finite() && r.figures.reference_error_percent.is_finite())
        .collect();
    let mut curves: Vec<&str> = Vec::new();
    for r in &ok {
        if !curves.contains(&r.curve.as_str()) {
            curves.push(&r.curve);
        }
    }
    let mut series = Vec::new();
    for (i, name) in curves.iter().enumerate() {
        // Past the palette, the colours repeat with squares for dots.
        let colour = COLOURS[i % COLOURS.len()];
        let mark = match i < COLOURS.len() {
            true => Mark::Dots,
            false => Mark::Squares,
        };
        let mut points: Vec<(f64, f64)> = ok
            .iter()
            .filter(|r| r.curve == *name)
            .map(|r| (r.figures.wall_s, r.figures.reference_error_percent))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best = f64::INFINITY;
        let front = points
            .iter()
            .filter(|(_, error)| {
                let better = *error < best;
                best = best.min(*error);
                better
            })
            .copied()
            .collect();
        series.push(Series {
            name: Some(name.to_string()),
            colour,
            mark,
            points,
        });
        series.push(Series {
            name: None,
            colour,
            mark: Mark::Line,
            points: front,
        });
    }
    chart::svg(&[Panel {
        title: "Shape error against wall time, a dot per setting (line: each curve's Pareto front)"
            .into(),
        x: Axis::log(
            "wall time (s, log scale)",
            ok.iter().map(|r| r.figures.wall_s),
        ),
        y: Axis::log(
            "shape error (% of length, log scale)",
            ok.iter().map(|r| r.figures.reference_error_percent),
        ),
        series,
    }])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::bench::row::Sample;

    fn row(setting: &str, stages: Vec<(StageName, f64)>) -> Row {
        Row {
            curve: "c".into(),
            setting: setting.into(),
            figures: Sample::unknown(),
            runs: Vec::new(),
            reach: String::new(),
            failures: 0,
            stages,
            design: None,
        }
    }

    /// Shares sum a setting's stages over its curves, largest first, and
    /// leave the other settings' out.
    #[test]
    fn stage_shares_sum_one_setting_over_its_curves() {
        let rows = [
            row(
                "draft",
                vec![(StageName::Search, 3.0), (StageName::Refine, 1.0)],
            ),
            row(
                "draft",
                vec![(StageName::Search, 1.0), (StageName::Refine, 5.0)],
            ),
            row("standard", vec![(StageName::Spread, 100.0)]),
        ];
        assert_eq!(stage_shares(&rows, "draft"), "refine 60 %, search 40 %");
        assert_eq!(stage_shares(&rows, "fine"), "");
    }
}
