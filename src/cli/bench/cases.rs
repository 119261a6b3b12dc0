//! What a suite is made of: which suite (`Suite`), its target curves
//! (`Target`) and its fidelity settings (`Setting`), and the preset curves
//! the suites draw from.

use anyhow::Result;
use patchwork_core::curve::{Curve, Preset};
use patchwork_core::inverse::{Fidelity, TuningOverrides};
use serde_json::json;

/// Which suite a bench runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Suite {
    /// Two short curves, small budgets: minutes.
    Quick,
    /// The three reference curves, a helix, a trefoil knot and a noisy arc
    /// under every preset and its variants: hours.
    Reference,
    /// Curves unlike the references (long bends, spirals, an S with and
    /// without a kink, grasps, a hook, a knot, hand-drawn input) and the
    /// references, under the three presets as users get them and draft's variants.
    Curves,
    /// Round trips with an unknown layout: ten seeded random feasible
    /// designs of 4–12 patches (lone patches and graded trains), simulated,
    /// then designed from the centreline alone under draft and standard.
    RoundTrips,
    /// Curves as users send them: gentle arcs, sparse CAD exports, noisy
    /// strokes with their clean strokes, and five kinds the other suites
    /// lack, under draft.
    Users,
    /// How sure a design is: five curves designed robust under draft, each
    /// with a Monte-Carlo check of 200 designs: half an hour.
    Sure,
    /// The benchmark report: the forward solve per mesh, the curve suite
    /// under draft and standard, the run-time goals' curves at three seeds,
    /// the round trips and the users' suite under draft, and how sure a
    /// design is.
    Report,
}

/// The suite's target curves, by name.
pub type Targets = Vec<Target>;

/// One curve of a suite; a drawn one knows the clean curve it was drawn
/// from, to judge the design against.
pub struct Target {
    pub name: String,
    pub curve: Curve,
    pub clean: Option<Curve>,
}

impl From<(String, Curve)> for Target {
    fn from((name, curve): (String, Curve)) -> Target {
        Target {
            name,
            curve,
            clean: None,
        }
    }
}

pub(super) fn targets(curves: Vec<(String, Curve)>) -> Targets {
    curves.into_iter().map(Target::from).collect()
}

/// One fidelity setting of the suite.
pub struct Setting {
    pub name: &'static str,
    pub fidelity: Fidelity,
    pub budget: usize,
    pub warm_starts: bool,
    /// Refine solves, stated per setting rather than taken from the preset,
    /// so that each row says what it ran.
    pub refine: usize,
    /// The preset's correction of the refine by a finer model (off: refine
    /// and verify on the verification model).
    pub correction: bool,
    /// Long bends as trains of patches within the bounds (off: KSA's one
    /// patch per bend).
    pub trains: bool,
    /// Try patches on gentle bends after the refine (off: KSA's layout).
    pub gentle_bends: bool,
    /// A planar target gets a planar design (off: X and Θ free).
    pub planar_designs: bool,
    /// KSA's curvature tolerance (mm⁻¹) instead of the preset's.
    pub kappa_tol: Option<f64>,
}

impl Setting {
    pub(super) fn new(
        name: &'static str,
        fidelity: Fidelity,
        budget: usize,
        refine: usize,
    ) -> Setting {
        Setting {
            name,
            fidelity,
            budget,
            warm_starts: false,
            refine,
            correction: true,
            trains: true,
            gentle_bends: true,
            planar_designs: true,
            kappa_tol: None,
        }
    }

    /// The preset as users get it (cold starts, its budgets, corrected).
    pub(super) fn preset(name: &'static str, fidelity: Fidelity) -> Setting {
        Setting::new(name, fidelity, fidelity.budget(), fidelity.refine_budget())
    }

    /// What this row changes of its preset.
    pub fn overrides(&self) -> TuningOverrides {
        TuningOverrides {
            warm_starts: Some(self.warm_starts),
            refine_budget: Some(self.refine),
            correction: Some(self.correction),
            trains: Some(self.trains),
            gentle_bends: Some(self.gentle_bends),
            planar_designs: Some(self.planar_designs),
            kappa_tol: self.kappa_tol,
            ..TuningOverrides::default()
        }
    }
}

pub(super) fn preset(name: &str, params: serde_json::Value) -> Result<Curve> {
    sampled_preset(name, params, None)
}

/// A preset curve with `points` samples (None: its default).
pub(super) fn sampled_preset(
    name: &str,
    params: serde_json::Value,
    points: Option<usize>,
) -> Result<Curve> {
    Ok(Preset::from_name(name, params)
        .map_err(anyhow::Error::msg)?
        .curve(points)?)
}

pub(super) fn reference_curve(name: &str) -> Result<Curve> {
    preset("reference", json!({ "name": name }))
}

/// `base` with every field `over` gives laid on it: a bench row's own
/// overrides under the user's `--tuning` (a field left out is not
/// serialised, so the objects' union is the merge).
pub(super) fn laid_over(base: &TuningOverrides, over: &TuningOverrides) -> Result<TuningOverrides> {
    let mut laid = serde_json::to_value(base)?;
    if let (Some(fields), serde_json::Value::Object(given)) =
        (laid.as_object_mut(), serde_json::to_value(over)?)
    {
        fields.extend(given);
    }
    Ok(serde_json::from_value(laid)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_users_tuning_replaces_the_fields_it_gives_and_keeps_the_rows_others() {
        let row = Setting::preset("draft", Fidelity::Draft).overrides();
        let over: TuningOverrides =
            serde_json::from_value(json!({"refine_budget": 0, "rod_search": false}))
                .expect("valid");
        let laid = laid_over(&row, &over).expect("valid");
        assert_eq!(laid.refine_budget, Some(0));
        assert_eq!(laid.rod_search, Some(false));
        assert_eq!(laid.trains, row.trains);
        assert_eq!(laid.correction, row.correction);
        assert_ne!(row.refine_budget, Some(0));
        assert_eq!(
            laid_over(&row, &TuningOverrides::default()).expect("valid"),
            row
        );
    }
}
