//! The job request (`POST /v1/jobs`) and the quick-look bodies: the HTTP
//! body formats, checked at the boundary. A job request becomes a
//! [`DesignSpec`] (`spec.rs`) — whatever passes is a design run that can start —
//! and a refusal is a [`SettingsError`] naming the request's field, which
//! the handler answers as problem+json.

use patchwork_core::curve::{Curve, Preset, Units, points_from_json, read_text};
use patchwork_core::design::{Balloon, Design, PatchSpec};
use patchwork_core::inverse::input::check_smoothing;
use patchwork_core::inverse::{
    Fidelity, Freedom, SettingsError, Smoothing, TuningOverrides, UserSettings, VariableBounds,
};
use patchwork_core::spread::Tolerances;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::problem::field_of;
use super::spec::DesignSpec;

/// Most forward evaluations one job may ask for.
pub const MAX_BUDGET: usize = 100_000;
/// The largest seed: 2⁵³ − 1, the largest integer every JSON reader (a
/// browser's included) keeps exact, so that a result's seed reproduces it.
pub const MAX_SEED: u64 = (1 << 53) - 1;

/// The target curve: exactly one of `points`, `csv` or `preset`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<Vec<Vec<Value>>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub csv: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub params: Option<Value>,
    /// Sample count for presets.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
}

#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobOptions {
    /// Forward evaluations of the search (default: the fidelity's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budget: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fidelity: Option<Fidelity>,
    /// Keep `design.balloon.length_mm` instead of matching the target length.
    #[serde(default)]
    pub fix_length: bool,
    /// Gaussian smoothing of the target along arc length, σ in mm (0: the
    /// curve as given); absent: chosen from the noise found on its points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub smooth_mm: Option<f64>,
    /// Seconds the whole run may take (absent: no limit): once passed, the
    /// stage under way stops with its best design so far and the later
    /// stages but the verification are skipped; the result's
    /// `time_limited` says what was cut short.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_limit_s: Option<f64>,
}

/// `POST /v1/jobs`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobRequest {
    pub curve: CurveSpec,
    #[serde(default)]
    pub units: Units,
    /// Balloon, patch and pressure: the design JSON without `patches`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<Value>,
    #[serde(default)]
    pub options: JobOptions,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<VariableBounds>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub freedom: Option<Freedom>,
    /// Expert tuning laid over the fidelity's preset (docs/tuning.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tuning: Option<TuningOverrides>,
    /// The tolerances the design's spread is reported at (fields left out:
    /// the defaults).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerances: Option<Tolerances>,
    /// A balloon profile of this key (`/v1/balloons`): its balloon and
    /// patch replace the design's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balloon_profile: Option<String>,
}

impl JobRequest {
    /// The job this request asks for, checked once: every check a run would
    /// otherwise fail late on, naming the request's field. `profile` is the
    /// balloon and patch of the `balloon_profile` named, read by the caller.
    pub fn spec(&self, profile: Option<(Balloon, PatchSpec)>) -> Result<DesignSpec, SettingsError> {
        let target = self.curve.load(self.units, "curve")?;
        let mut base = design_base(self.design.as_ref(), "design")?;
        if let Some((balloon, patch)) = profile {
            let own = (self.design.as_ref().and_then(Value::as_object))
                .is_some_and(|d| d.contains_key("balloon") || d.contains_key("patch"));
            if own {
                return Err(SettingsError::new(
                    "balloon_profile",
                    "give the balloon either by `design.balloon`/`design.patch` or by `balloon_profile`",
                ));
            }
            (base.balloon, base.patch) = (balloon, patch);
        }
        if let Some(budget) = self.options.budget
            && !(1..=MAX_BUDGET).contains(&budget)
        {
            return Err(SettingsError::new(
                "options.budget",
                format!("must be between 1 and {MAX_BUDGET} evaluations, got {budget}"),
            ));
        }
        let seed = self.options.seed.unwrap_or(1);
        if seed > MAX_SEED {
            return Err(SettingsError::new(
                "options.seed",
                format!("must be at most {MAX_SEED} (2^53 - 1), got {seed}"),
            ));
        }
        let tuning = self.tuning.clone().unwrap_or_default();
        for (field, value) in [
            ("tuning.search_patience", tuning.search_patience),
            ("tuning.polish_budget", tuning.polish_budget),
            ("tuning.refine_budget", tuning.refine_budget),
        ] {
            if value.is_some_and(|v| v > MAX_BUDGET) {
                return Err(SettingsError::new(
                    field,
                    format!("must be at most {MAX_BUDGET} evaluations"),
                ));
            }
        }
        let settings = UserSettings {
            base,
            fidelity: self.options.fidelity.unwrap_or_default(),
            seed,
            budget: self.options.budget,
            bounds: self.bounds.unwrap_or_default(),
            freedom: self.freedom.unwrap_or_default(),
            fix_length: self.options.fix_length,
            smoothing: self
                .options
                .smooth_mm
                .map_or(Smoothing::Auto, Smoothing::Sigma),
            // One job per worker, one worker per core.
            threads: 1,
            tolerances: self.tolerances.unwrap_or_default(),
            time_limit_s: self.options.time_limit_s,
        };
        check_smoothing(&target, settings.smoothing)
            .map_err(|e| SettingsError::new("options.smooth_mm", e.to_string()))?;
        DesignSpec::new(target, settings, tuning).map_err(request_field)
    }
}

/// A settings error, its field named as the request names it.
fn request_field(error: SettingsError) -> SettingsError {
    let SettingsError { field, reason } = error;
    let field = match field.as_str() {
        "budget" => "options.budget".to_string(),
        "smoothing" => "options.smooth_mm".to_string(),
        "time_limit_s" => "options.time_limit_s".to_string(),
        _ => field,
    };
    SettingsError { field, reason }
}

impl CurveSpec {
    pub fn load(&self, units: Units, field: &str) -> Result<Curve, SettingsError> {
        let given = [
            self.points.is_some(),
            self.csv.is_some(),
            self.preset.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(SettingsError::new(
                field,
                "give exactly one of `points`, `csv` or `preset`",
            ));
        }
        if self.params.is_some() && self.preset.is_none() {
            return Err(SettingsError::new(
                format!("{field}.params"),
                "`params` belongs to a `preset`",
            ));
        }
        if let Some(points) = &self.points {
            return points_from_json(points, units)
                .map_err(|e| SettingsError::new(format!("{field}.points"), e.to_string()));
        }
        if let Some(csv) = &self.csv {
            return read_text(csv, units)
                .map_err(|e| SettingsError::new(format!("{field}.csv"), e.to_string()));
        }
        let name = self.preset.as_deref().unwrap_or_default();
        let params = self
            .params
            .clone()
            .unwrap_or(Value::Object(Default::default()));
        let preset = Preset::from_name(name, params)
            .map_err(|e| SettingsError::new(format!("{field}.preset"), e))?;
        // Presets are defined in millimetres; `units` applies to points and CSV.
        preset
            .curve(self.samples)
            .map_err(|e| SettingsError::new(format!("{field}.params"), e.to_string()))
    }
}

/// The design JSON without patches (defaults: the reference scene), validated.
pub fn design_base(value: Option<&Value>, field: &str) -> Result<Design, SettingsError> {
    let mut value = value.cloned().unwrap_or(Value::Object(Default::default()));
    let Some(object) = value.as_object_mut() else {
        return Err(SettingsError::new(field, "must be an object"));
    };
    if object.contains_key("patches") {
        return Err(SettingsError::new(
            format!("{field}.patches"),
            "a job designs the patches: leave `patches` out",
        ));
    }
    object.insert("patches".into(), Value::Array(vec![]));
    let design: Design = serde_path_to_error::deserialize(value).map_err(|e| {
        let inner = field_of(&e.path().to_string(), &e.inner().to_string());
        let path = if inner.is_empty() {
            field.to_string()
        } else {
            format!("{field}.{inner}")
        };
        SettingsError::new(path.clone(), format!("{path}: {}", e.inner()))
    })?;
    validate_design(&design, field)?;
    Ok(design)
}

/// `Design::validate`, the field path prefixed.
pub fn validate_design(design: &Design, field: &str) -> Result<(), SettingsError> {
    design.validate().map_err(|e| {
        let path = if field.is_empty() {
            e.field.clone()
        } else {
            format!("{field}.{}", e.field)
        };
        SettingsError::new(path.clone(), format!("{path}: {}", e.reason))
    })
}
