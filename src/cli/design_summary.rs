//! The summary `patchwork design` prints: lengths, errors, what was done
//! to the target and where it is out of reach, the spread at the
//! tolerances, the stages and what a time limit cut short, limits hit
//! and the patches.

use patchwork_core::fe::contact::SelfContact;
use patchwork_core::inverse::layout::LayoutTrial;
use patchwork_core::inverse::reach::ReachReport;
use patchwork_core::inverse::shortfall::HIGH_ERROR_PERCENT;
use patchwork_core::inverse::{DesignReport, Expected, InputReport, RefineSummary};

use super::output::patch_table;
use super::spread_summary::summary as summary_of_spread;

pub fn summary(r: &DesignReport, dir: &std::path::Path) -> String {
    let m = &r.metrics;
    let mut s = format!(
        "target {:.1} mm; inflated {:.1} mm; cut the balloon {:.1} mm long\n\
         search model: objective {:.4} (KSA seed {:.4})\n\
         verified:     shape error {:.2} mm ({:.2} % of length); objective {:.4}; DTW κ {:.4}, τ {:.4}\n\
         {} evaluations in {:.1} s ({})\n",
        r.target_length_mm,
        r.inflated_length_mm,
        r.uninflated_length_to_cut_mm,
        r.search_objective,
        r.seed_objective,
        m.shape_error_mm,
        m.shape_error_percent,
        m.objective,
        m.dtw_curvature,
        m.dtw_torsion,
        r.evaluations,
        r.elapsed_s,
        r.termination
    );
    s.push_str(&stages_line(r));
    if let Some(limited) = &r.time_limited {
        s.push_str(&format!(
            "time limit:   {} (the design is the best found by then, verified)\n",
            limited.message()
        ));
    }
    s.push_str(&input_line(&r.input));
    s.push_str(&cleared_line(&r.input));
    s.push_str(&as_given_line(r));
    s.push_str(&shortfall_line(r));
    s.push_str(&reach_lines(r.reach.as_ref()));
    s.push_str(&contact_lines(r));
    s.push_str(&spread_lines(r));
    s.push_str(&refine_line("refine:      ", r.refine.as_ref()));
    s.push_str(&layout_lines(&r.layouts));
    s.push_str(&refine_line("final refine:", r.final_refine.as_ref()));
    if let Some(why) = &r.final_refine_skipped {
        s.push_str(&format!("final refine: not run: {why}\n"));
    }
    for hit in &r.at_limits {
        let note = if hit.beyond {
            "beyond: the range was widened to hold KSA's seed"
        } else {
            "pinned: relax it with --bounds if the fabrication allows"
        };
        s.push_str(&format!(
            "limit:        P{} {} {:.2} at {} {} ({note})\n",
            hit.patch, hit.field, hit.value, hit.bound, hit.limit
        ));
    }
    s.push_str(&patch_table(&r.design.patches, |_| ""));
    s.push_str(&format!(
        "files in {}: design.json design.csv patches.dxf template.dxf template.svg profiles.svg\n",
        dir.display()
    ));
    s
}

/// Where the time went: each stage's seconds and solves, in order.
fn stages_line(r: &DesignReport) -> String {
    if r.stages.is_empty() {
        return String::new();
    }
    let parts: Vec<String> = (r.stages.iter())
        .map(|t| {
            format!(
                "{} {:.1} s ({})",
                t.stage.as_str(),
                t.seconds,
                t.evaluations
            )
        })
        .collect();
    format!("stages:       {} (solves)\n", parts.join(", "))
}

/// One line on a refine stage (empty when it did not run).
fn refine_line(label: &str, refine: Option<&RefineSummary>) -> String {
    match refine {
        Some(refine)
            if refine.solves == 0
                && refine.shape_error_before_percent <= refine.tolerance_percent =>
        {
            format!(
                "{label} none needed: shape error {:.2} % is within the refine tolerance {} %\n",
                refine.shape_error_before_percent, refine.tolerance_percent
            )
        }
        Some(refine) if refine.solves == 0 => {
            format!("{label} none: one step needs 2 solves, a Jacobian and a trial (--refine)\n")
        }
        Some(refine) => format!(
            "{label} shape error {:.2} % → {:.2} % in {} steps ({} solves, {} Jacobians{})\n",
            refine.shape_error_before_percent,
            refine.shape_error_after_percent,
            refine.iterations,
            refine.solves,
            refine.jacobians,
            match refine.differenced_jacobians {
                0 => String::new(),
                d => format!(
                    ", {d} of them by forward differences, {} solves each",
                    refine.variables
                ),
            }
        ),
        None => String::new(),
    }
}

/// What was done to the target: its smoothing and whether it is planar.
fn input_line(input: &InputReport) -> String {
    let smoothing = match (input.smoothing_mm > 0.0, input.automatic) {
        (true, true) => format!(
            "noise {:.2} mm on the points: smoothed with σ {:.1} mm (automatic; --smooth-mm overrides)",
            input.noise_mm, input.smoothing_mm
        ),
        (true, false) => format!("smoothed with σ {:.1} mm (--smooth-mm)", input.smoothing_mm),
        (false, true) if input.too_sparse_for_noise() => {
            "as given (points too far apart to find noise)".to_string()
        }
        (false, true) => "as given (no noise found)".to_string(),
        (false, false) => "as given (--smooth-mm 0)".to_string(),
    };
    let planar = match (input.planar, input.planar_design) {
        (true, true) => "; planar: a planar design (patches at Θ = 0 on one line and its opposite)",
        (true, false) => "; planar",
        (false, _) => "",
    };
    let sparse = match &input.interpolated {
        Some(i) => format!(
            "; {} points {:.1} mm apart (chords {:.2} mm off the curve): read through a cubic spline of {} samples",
            i.points, i.median_spacing_mm, i.sagitta_mm, i.samples
        ),
        None => String::new(),
    };
    format!("input:        {smoothing}{sparse}{planar}\n")
}

/// Where the design was kept clear of itself and the target was not: how
/// far a tube along it would have passed into itself, and the clear curve
/// aimed at instead.
fn cleared_line(input: &InputReport) -> String {
    let Some(c) = &input.cleared else {
        return String::new();
    };
    let unfinished = match c.converged {
        true => "",
        false => "; not wholly clear",
    };
    format!(
        "kept clear:   a tube of radius {:.1} mm along the curve would pass {:.1} mm into itself: \
         the design aims at the nearest clear curve, moved up to {:.1} mm ({:.1} mm RMS){unfinished}\n",
        c.radius_mm, c.overlap_mm, c.moved_max_mm, c.moved_rms_mm
    )
}

/// The design against the curve as given, where smoothing, a spline
/// through sparse points or keeping clear of itself made the target the
/// design aimed at another curve
/// (empty otherwise: the figures above are then against the curve as given).
fn as_given_line(r: &DesignReport) -> String {
    match &r.as_given {
        Some(g) if r.input.changed_target() => format!(
            "as given:     shape error {:.2} mm ({:.2} % of length) against the points as given \
             ({:.1} mm long; the target aimed at {:.1} mm)\n",
            g.shape_error_mm, g.shape_error_percent, g.length_mm, r.target_length_mm
        ),
        _ => String::new(),
    }
}

/// Why the shape error is high, when it is.
fn shortfall_line(r: &DesignReport) -> String {
    if r.shortfalls.is_empty() {
        return String::new();
    }
    let causes: Vec<&str> = r.shortfalls.iter().map(|c| c.message.as_str()).collect();
    format!(
        "short:        shape error above {HIGH_ERROR_PERCENT} %: {}\n",
        causes.join("; ")
    )
}

/// The spread at the run's tolerances and its three largest sources, or why
/// there is none.
fn spread_lines(r: &DesignReport) -> String {
    let spread = match (&r.spread, &r.spread_failed) {
        (Some(spread), _) => summary_of_spread(spread, 3),
        (None, Some(why)) => format!("spread:       not found: {why}\n"),
        (None, None) => String::new(),
    };
    let rod = match &r.rod_skipped {
        Some(why) => format!("rod search:   not run, searched on FE: {why}\n"),
        None => String::new(),
    };
    spread + &robust_lines(r) + &rod
}

/// What the robust refine did: both designs' figures and which stands.
fn robust_lines(r: &DesignReport) -> String {
    let Some(robust) = &r.robust else {
        return match &r.robust_skipped {
            Some(why) => format!("robust:       not run: {why}\n"),
            None => String::new(),
        };
    };
    let figures = |e: &Expected| {
        format!(
            "{:.2} % as designed, spread {:.2} %, {:.2} % expected",
            e.shape_error_percent, e.spread_percent, e.expected_percent
        )
    };
    let verdict = match robust.kept {
        true => "kept: the robust design is the one above",
        false => "not kept: the nominal design stands (its expected error is no higher)",
    };
    format!(
        "robust:       weighing {}; {verdict}\n\
         \x20             nominal design {}\n\
         \x20             robust design  {}; {} FE solves\n",
        robust.sources.join(", "),
        figures(&robust.nominal_design),
        figures(&robust.robust_design),
        robust.solves
    )
}

/// Where the predicted tube passes through itself, a line each, and how to
/// design clear of it.
fn contact_lines(r: &DesignReport) -> String {
    let mut lines: String = r.self_contact.iter().map(contact_line).collect();
    if !lines.is_empty() && !r.input.keep_clear {
        lines.push_str(
            "              --tuning '{\"keep_clear\": true}' designs a balloon that keeps clear of itself\n",
        );
    }
    lines
}

/// One self-contact as the CLI prints it (`design` and `simulate`).
pub fn contact_line(c: &SelfContact) -> String {
    format!(
        "contact:      the tube passes {:.1} mm into itself at s {:.0} and {:.0} mm \
         (balloon Y {:.0} and {:.0} mm); the real balloon pushes apart there\n",
        c.overlap_mm, c.s_mm[0], c.s_mm[1], c.y_mm[0], c.y_mm[1]
    )
}

/// Whether the target is within reach, and where not.
fn reach_lines(reach: Option<&ReachReport>) -> String {
    let Some(reach) = reach else {
        return String::new();
    };
    if reach.reachable() {
        return format!(
            "reach:        all within reach (tightest bend radius {:.1} mm, most twist per bend {:.2})\n",
            reach.tightest_bend_radius_mm, reach.most_twist_per_bend
        );
    }
    reach
        .out_of_reach
        .iter()
        .map(|span| {
            format!(
                "out of reach: {}; the design does its best there\n",
                span.message
            )
        })
        .collect()
}

/// The layouts tried after the refine, the chosen one marked.
fn layout_lines(layouts: &[LayoutTrial]) -> String {
    layouts
        .iter()
        .map(|l| {
            format!(
                "layout:       {:<40} {:>3} patches, shape error {:.2} %{}\n",
                l.layout,
                l.patches,
                l.shape_error_percent,
                if l.chosen { "  (chosen)" } else { "" }
            )
        })
        .collect()
}
