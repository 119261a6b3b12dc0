//! A job as the service keeps and runs it. A design job ([`DesignSpec`]) is
//! the target curve in millimetres and the run's resolved plan; a
//! calibration ([`CalibrateSpec`]) is the measurements, the starting
//! materials and the parameters to fit, and the profile to save the answer
//! as. Job kinds
//! are the variants of [`JobSpec`], so a new kind is a variant the compiler
//! then asks the worker and the job's detail to handle. A spec is made once, when
//! the job is submitted (`request.rs` turns the HTTP body into one, naming
//! the field of anything wrong), stored with the job in a versioned form
//! (`version`), and read back by the worker as it is: no request format, no
//! HTTP type and no second validation on the way to the run.
//!
//! The stored form carries what the user chose (settings and tuning
//! overrides), not the resolved tuning, so a stored job runs under the
//! presets of the server that runs it — as a job resumed after an upgrade
//! always has.

use patchwork_core::calibrate::{Measurements, Parameter};
use patchwork_core::curve::{Curve, Point};
use patchwork_core::design::{Balloon, Design, PatchSpec};
use patchwork_core::inverse::{
    Fidelity, Freedom, Plan, SettingsError, Smoothing, TuningOverrides, UserSettings,
    VariableBounds,
};
use patchwork_core::spread::Tolerances;
use serde::{Deserialize, Serialize};

/// The stored form's version; a reader refuses any other.
pub const SPEC_VERSION: u32 = 1;

/// A validated job of any kind: what the worker runs.
#[derive(Debug, Clone, PartialEq)]
pub enum JobSpec {
    Design(Box<DesignSpec>),
    Calibrate(Box<CalibrateSpec>),
}

/// The kinds of job, as the API names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JobKind {
    Design,
    Calibrate,
}

/// A validated calibration: stored as it is (every field a plain value).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrateSpec {
    /// The uninflated bare balloon and the material to start from.
    pub balloon: Balloon,
    /// The patch and the patch material to start from.
    pub patch: PatchSpec,
    pub measurements: Measurements,
    pub fit: Vec<Parameter>,
    /// The balloon profile of the job's owner to store the answer as.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub save_as: Option<String>,
}

/// A validated design job.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSpec {
    target: Curve,
    overrides: TuningOverrides,
    plan: Plan,
}

/// Why a stored spec cannot be run.
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    #[error("the stored job spec is not readable: {0}")]
    Unreadable(#[from] serde_json::Error),
    #[error("the stored job spec has version {0}; this server reads version {SPEC_VERSION}")]
    Version(u32),
    #[error("the stored job spec no longer holds: {0}")]
    Invalid(String),
}

impl JobSpec {
    /// The kind of a stored spec, read without the rest of it; none where
    /// it is not a readable spec.
    pub fn stored_kind(text: &str) -> Option<JobKind> {
        #[derive(Deserialize)]
        struct Kind {
            kind: JobKind,
        }
        serde_json::from_str::<Kind>(text).ok().map(|k| k.kind)
    }

    /// The stored form (JSON): `{"version": 1, "kind": "design", …}`.
    pub fn to_stored(&self) -> String {
        let job = match self {
            JobSpec::Design(design) => StoredJob::Design(Box::new(design.stored())),
            JobSpec::Calibrate(calibrate) => StoredJob::Calibrate(calibrate.clone()),
        };
        let stored = Stored {
            version: SPEC_VERSION,
            job,
        };
        // Every field is a plain value with a JSON form (finite numbers:
        // the curve's and the design's are checked when they are made).
        serde_json::to_string(&stored).unwrap_or_default()
    }

    /// The job stored by [`JobSpec::to_stored`].
    pub fn from_stored(text: &str) -> Result<JobSpec, SpecError> {
        let version: Versioned = serde_json::from_str(text)?;
        if version.version != SPEC_VERSION {
            return Err(SpecError::Version(version.version));
        }
        let stored: Stored = serde_json::from_str(text)?;
        match stored.job {
            StoredJob::Design(design) => {
                DesignSpec::from_stored(*design).map(|d| JobSpec::Design(Box::new(d)))
            }
            StoredJob::Calibrate(calibrate) => Ok(JobSpec::Calibrate(calibrate)),
        }
    }
}

impl DesignSpec {
    /// The job of `target` under `settings` with `overrides` laid over the
    /// fidelity's preset; the error names the settings' field.
    pub fn new(
        target: Curve,
        settings: UserSettings,
        overrides: TuningOverrides,
    ) -> Result<DesignSpec, SettingsError> {
        let plan = Plan::resolve(settings, &overrides)?;
        Ok(DesignSpec {
            target,
            overrides,
            plan,
        })
    }

    pub fn target(&self) -> &Curve {
        &self.target
    }

    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    fn stored(&self) -> StoredDesign {
        let s = self.plan.settings();
        StoredDesign {
            target_mm: self
                .target
                .points()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect(),
            design: s.base.clone(),
            fidelity: s.fidelity,
            seed: s.seed,
            budget: s.budget,
            bounds: s.bounds,
            freedom: s.freedom,
            fix_length: s.fix_length,
            smoothing: s.smoothing,
            threads: s.threads,
            tuning: self.overrides.clone(),
            tolerances: s.tolerances,
            time_limit_s: s.time_limit_s,
        }
    }

    fn from_stored(stored: StoredDesign) -> Result<DesignSpec, SpecError> {
        let points = stored
            .target_mm
            .iter()
            .map(|&[x, y, z]| Point::new(x, y, z))
            .collect();
        let target = Curve::from_points(points).map_err(|e| SpecError::Invalid(e.to_string()))?;
        let settings = UserSettings {
            base: stored.design,
            fidelity: stored.fidelity,
            seed: stored.seed,
            budget: stored.budget,
            bounds: stored.bounds,
            freedom: stored.freedom,
            fix_length: stored.fix_length,
            smoothing: stored.smoothing,
            threads: stored.threads,
            tolerances: stored.tolerances,
            time_limit_s: stored.time_limit_s,
        };
        DesignSpec::new(target, settings, stored.tuning)
            .map_err(|e| SpecError::Invalid(e.to_string()))
    }
}

/// Only the version, read first so that another version is named as such
/// rather than as a field this reader does not know.
#[derive(Deserialize)]
struct Versioned {
    version: u32,
}

/// The stored form, version 1: the version and the job, tagged by kind.
#[derive(Serialize, Deserialize)]
struct Stored {
    version: u32,
    #[serde(flatten)]
    job: StoredJob,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum StoredJob {
    Design(Box<StoredDesign>),
    Calibrate(Box<CalibrateSpec>),
}

/// A design job as stored.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StoredDesign {
    /// The target's points (mm): units applied, a preset sampled.
    target_mm: Vec<[f64; 3]>,
    /// Balloon, patch material and pressure (no patches).
    design: Design,
    fidelity: Fidelity,
    seed: u64,
    budget: Option<usize>,
    bounds: VariableBounds,
    freedom: Freedom,
    fix_length: bool,
    smoothing: Smoothing,
    threads: usize,
    tuning: TuningOverrides,
    /// The spread's tolerances (specs stored before them: the defaults).
    #[serde(default)]
    tolerances: Tolerances,
    /// The run's time limit, seconds (specs stored before it: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    time_limit_s: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use patchwork_core::curve::Preset;

    fn spec(settings: UserSettings, overrides: TuningOverrides) -> JobSpec {
        let target = Preset::from_name("helix", serde_json::json!({}))
            .unwrap()
            .curve(Some(97))
            .unwrap();
        JobSpec::Design(Box::new(
            DesignSpec::new(target, settings, overrides).unwrap(),
        ))
    }

    #[test]
    fn a_stored_spec_reads_back_as_the_same_job() {
        let mut settings = UserSettings {
            fidelity: Fidelity::Draft,
            seed: 9_007_199_254_740_991,
            budget: Some(37),
            fix_length: true,
            smoothing: Smoothing::Sigma(0.7),
            time_limit_s: Some(45.0),
            ..UserSettings::default()
        };
        settings.base.pressure_kpa = 21.5;
        settings.bounds.h_max_mm = 61.0;
        settings.freedom.theta = false;
        let overrides = TuningOverrides {
            refine_budget: Some(12),
            initial_step: Some(0.15),
            ..TuningOverrides::default()
        };
        let job = spec(settings, overrides);
        let back = JobSpec::from_stored(&job.to_stored()).unwrap();
        assert_eq!(back, job);
        assert_eq!(back.to_stored(), job.to_stored());
        let plain = spec(UserSettings::default(), TuningOverrides::default());
        assert_eq!(JobSpec::from_stored(&plain.to_stored()).unwrap(), plain);
    }

    #[test]
    fn another_version_or_a_damaged_spec_is_refused_by_name() {
        let job = spec(UserSettings::default(), TuningOverrides::default());
        let mut value: serde_json::Value = serde_json::from_str(&job.to_stored()).unwrap();
        value["version"] = 2.into();
        let error = JobSpec::from_stored(&value.to_string()).unwrap_err();
        assert!(matches!(error, SpecError::Version(2)), "{error}");
        value["version"] = SPEC_VERSION.into();
        value["target_mm"] = serde_json::json!([[0, 0, 0], [1, 0, 0]]);
        let error = JobSpec::from_stored(&value.to_string()).unwrap_err();
        assert!(matches!(error, SpecError::Invalid(_)), "{error}");
        value["design"]["pressure_kpa"] = (-3.0).into();
        let JobSpec::Design(design) = &job else {
            unreachable!("a design job")
        };
        value["target_mm"] = serde_json::to_value(
            design
                .target()
                .points()
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect::<Vec<_>>(),
        )
        .unwrap();
        let error = JobSpec::from_stored(&value.to_string()).unwrap_err();
        assert!(error.to_string().contains("pressure_kpa"), "{error}");
        assert!(matches!(
            JobSpec::from_stored("{\"version\": 1}").unwrap_err(),
            SpecError::Unreadable(_)
        ));
        value["design"]["pressure_kpa"] = 20.0.into();
        assert!(JobSpec::from_stored(&value.to_string()).is_ok());
        value["kind"] = "survey".into();
        assert!(matches!(
            JobSpec::from_stored(&value.to_string()).unwrap_err(),
            SpecError::Unreadable(_)
        ));
        value["kind"] = "design".into();
        value["seeds"] = 3.into();
        let error = JobSpec::from_stored(&value.to_string()).unwrap_err();
        assert!(error.to_string().contains("seeds"), "{error}");
    }

    #[test]
    fn a_stored_calibration_reads_back_and_names_its_kind() {
        use patchwork_core::calibrate::Inflation;
        let job = JobSpec::Calibrate(Box::new(CalibrateSpec {
            balloon: Balloon::default(),
            patch: PatchSpec::default(),
            measurements: Measurements {
                inflation: vec![Inflation {
                    pressure_kpa: 20.0,
                    length_mm: Some(412.5),
                    diameter_mm: None,
                }],
                ..Measurements::default()
            },
            fit: vec![Parameter::Modulus],
            save_as: Some("batch-7".into()),
        }));
        let stored = job.to_stored();
        assert_eq!(JobSpec::from_stored(&stored).unwrap(), job);
        assert_eq!(JobSpec::stored_kind(&stored), Some(JobKind::Calibrate));
        let design = spec(UserSettings::default(), TuningOverrides::default());
        assert_eq!(
            JobSpec::stored_kind(&design.to_stored()),
            Some(JobKind::Design)
        );
        assert_eq!(JobSpec::stored_kind("{\"version\": 1}"), None);
    }
}
