//! `patchwork design CURVE --out DIR [--fidelity draft|standard|fine] [--seed S]
//! [--budget EVALS] [--options JSON] [--bounds JSON] [--fix-length] [--threads N]
//! [--checkpoint FILE] [--json] [--tuning JSON] [--time-limit SECONDS]`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::curve::Curve;
use patchwork_core::design::Design;
use patchwork_core::fabrication::design_files;
use patchwork_core::inverse::{
    Caches, DesignCheckpoint, DesignProgress, DesignReport, Fidelity, Observer, Plan,
    SettingsError, Smoothing, TuningOverrides, UserSettings, design_resumable,
};

use super::design_summary::summary;
use super::input::{CurveInput, json_argument};
use super::output::{emit, emit_json};

#[derive(Args)]
#[command(allow_negative_numbers = true)]
pub struct DesignArgs {
    #[command(flatten)]
    input: CurveInput,
    /// Folder for design.json, design.csv, the DXF/SVG cut files and profiles.svg.
    #[arg(long)]
    out: PathBuf,
    #[command(flatten)]
    flags: DesignFlags,
    /// Balloon, patch material and pressure as design JSON, inline, a file or `-` (default: the reference scene).
    #[arg(long, value_name = "JSON")]
    options: Option<String>,
    /// Save the run after every generation here, and resume from it if it exists.
    #[arg(long, value_name = "FILE")]
    checkpoint: Option<PathBuf>,
    /// Print design.json to stdout instead of the summary.
    #[arg(long)]
    json: bool,
}

/// The search's settings, shared by `design` and `redesign`.
#[derive(Args)]
#[command(allow_negative_numbers = true)]
pub struct DesignFlags {
    /// Preset: draft (the quickest: 2–64 s on two cores for the curves in
    /// BENCHMARKS.md, up to 1.4 m long on balloons of about 400 mm; a longer
    /// curve takes longer, every solve growing with its balloon), standard or
    /// fine (most accurate, slowest).
    #[arg(long, default_value = "standard")]
    fidelity: Fidelity,
    /// Random seed: the same seed reproduces the same design.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Forward simulations the search may spend [default: 200].
    #[arg(long)]
    budget: Option<usize>,
    /// Fabrication limits as JSON, inline or a file, e.g. `{"w_min_mm": 0.5}` (fields: the API's `bounds`).
    #[arg(long, value_name = "JSON")]
    bounds: Option<String>,
    /// Keep the balloon length given (`--options`; `redesign`: the built
    /// design's) instead of fitting it to the curve.
    #[arg(long)]
    fix_length: bool,
    /// Threads: a generation's candidates side by side, and a lone solve's
    /// assembly (the same design for any count).
    #[arg(long, default_value_t = patchwork_core::available_cores())]
    threads: usize,
    /// Expert tuning over the preset as JSON (file, `-` or inline); fields in docs/tuning.md.
    #[arg(long, value_name = "JSON")]
    tuning: Option<String>,
    /// Tolerances the design's spread is reported at, as JSON (inline or a
    /// file), each one standard deviation; fields left out keep their
    /// defaults: {"placement_mm": 1, "angle_deg": 2, "size_mm": 0.2,
    /// "pressure_kpa": 0.5, "wall_percent": 5, "modulus_percent": 3}.
    #[arg(long, value_name = "JSON")]
    tolerances: Option<String>,
    /// Seconds the whole run may take: once they have passed, the stage
    /// under way stops at its next step with its best design so far, the
    /// later stages but the verification are skipped, and the summary and
    /// design.json say what was cut short [default: none].
    #[arg(long, value_name = "SECONDS")]
    time_limit: Option<f64>,
}

/// Writes the checkpoint to a temporary file and renames it over the old one,
/// so an interrupted write never leaves a torn checkpoint.
fn write_atomically(path: &std::path::Path, checkpoint: &DesignCheckpoint) -> Result<()> {
    let text = serde_json::to_string(checkpoint)?;
    let temporary = path.with_extension("tmp");
    std::fs::write(&temporary, text)
        .with_context(|| format!("cannot write {}", temporary.display()))?;
    std::fs::rename(&temporary, path).with_context(|| format!("cannot write {}", path.display()))
}

impl DesignArgs {
    /// The plan these options ask for: the user's settings and `--tuning`'s
    /// overrides, resolved as the API resolves a job.
    pub fn plan(&self) -> Result<Plan> {
        let base: Design = match &self.options {
            Some(argument) => {
                let mut value: serde_json::Value = json_argument("options", argument)?;
                if let Some(object) = value.as_object_mut() {
                    object.entry("patches").or_insert(serde_json::json!([]));
                }
                serde_json::from_value(value).map_err(|e| anyhow::anyhow!("--options: {e}"))?
            }
            None => Design::reference(vec![]),
        };
        self.flags.plan(base, self.input.smoothing())
    }
}

impl DesignFlags {
    /// The plan for designing on `base` (balloon, patch, pressure) with
    /// these settings and `--tuning`'s overrides, resolved as the API
    /// resolves a job.
    pub fn plan(&self, base: Design, smoothing: Smoothing) -> Result<Plan> {
        let bounds = match &self.bounds {
            Some(argument) => json_argument("bounds", argument)?,
            None => Default::default(),
        };
        let settings = UserSettings {
            base,
            fidelity: self.fidelity,
            seed: self.seed,
            budget: self.budget,
            bounds,
            freedom: Default::default(),
            fix_length: self.fix_length,
            smoothing,
            threads: self.threads,
            tolerances: match &self.tolerances {
                Some(argument) => json_argument("tolerances", argument)?,
                None => Default::default(),
            },
            time_limit_s: self.time_limit,
        };
        let overrides: TuningOverrides = match &self.tuning {
            Some(argument) => json_argument("tuning", argument)?,
            None => TuningOverrides::default(),
        };
        Plan::resolve(settings, &overrides).map_err(flag_error)
    }
}

/// A settings error in the words of the command line: the flag that set it.
pub(super) fn flag_error(error: SettingsError) -> anyhow::Error {
    let SettingsError { field, reason } = error;
    let flag = match field.as_str() {
        "budget" | "threads" => field,
        "smoothing" => "smooth-mm".into(),
        "time_limit_s" => "time-limit".into(),
        f if f.starts_with("tuning.") => {
            return anyhow::anyhow!("--tuning: {}: {reason}", &f["tuning.".len()..]);
        }
        f if f.starts_with("bounds.") => return anyhow::anyhow!("--bounds: {reason}"),
        f if f.starts_with("tolerances.") => {
            return anyhow::anyhow!("--tolerances: {}: {reason}", &f["tolerances.".len()..]);
        }
        f if f.starts_with("design.") => return anyhow::anyhow!("--options: {f}: {reason}"),
        _ => return anyhow::anyhow!("{field}: {reason}"),
    };
    anyhow::anyhow!("--{flag}: {reason}")
}

/// The terminal's progress line and the checkpoint file.
struct CliObserver<'a> {
    terminal: bool,
    total_budget: usize,
    checkpoint: Option<&'a std::path::Path>,
    save_error: Option<anyhow::Error>,
}

impl Observer for CliObserver<'_> {
    fn progress(&mut self, p: &DesignProgress) {
        if !self.terminal {
            return;
        }
        let stage = p.stage.as_str();
        eprint!(
            "\r{stage:<12} generation {:>4}  evaluations {:>5}/{}  best {:>9.5}  σ {:.3}  {:>6.1} s ",
            p.generation, p.evaluations, self.total_budget, p.best_objective, p.sigma, p.elapsed_s
        );
    }

    fn checkpoint(&mut self, c: &DesignCheckpoint) {
        if let Some(path) = self.checkpoint
            && let Err(e) = write_atomically(path, c)
        {
            self.save_error.get_or_insert(e);
        }
    }
}

pub fn run(args: DesignArgs) -> Result<()> {
    let target = args.input.load_as_given()?;
    // Checked before the output folder is created: a bad option changes nothing.
    let plan = args.plan()?;
    let report = design_into(&target, &plan, &args.out, args.checkpoint.as_deref())?;
    if args.json {
        return emit_json(&report);
    }
    emit(&summary(&report, &args.out))
}

/// Designs for `target` by `plan` and writes design.json and the cut files
/// into `out` (created), resuming from `checkpoint` when it exists.
pub fn design_into(
    target: &Curve,
    plan: &Plan,
    out: &Path,
    checkpoint: Option<&Path>,
) -> Result<DesignReport> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let terminal = std::io::stderr().is_terminal();
    let cancel = AtomicBool::new(false);
    let resume = match checkpoint {
        Some(path) if path.exists() => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            let checkpoint: DesignCheckpoint = serde_json::from_str(&text)
                .with_context(|| format!("{}: not a design checkpoint", path.display()))?;
            eprintln!(
                "resuming from {} ({} evaluations done)",
                path.display(),
                checkpoint.evaluations
            );
            Some(checkpoint)
        }
        _ => None,
    };
    if terminal {
        eprintln!("plan: {}", plan.describe());
        eprintln!("budgets: {}", plan.describe_budgets());
    }
    let mut observer = CliObserver {
        terminal,
        total_budget: plan.total_budget(),
        checkpoint,
        save_error: None,
    };
    let outcome = design_resumable(
        target,
        plan,
        resume,
        &Caches::default(),
        &cancel,
        &mut observer,
    )?;
    if let Some(e) = observer.save_error {
        return Err(e);
    }
    if terminal {
        eprintln!();
    }
    let report = DesignReport::new(&outcome, plan.settings().seed);
    write_files(out, &report)?;
    Ok(report)
}

fn write_files(dir: &std::path::Path, report: &DesignReport) -> Result<()> {
    for file in design_files(report).map_err(anyhow::Error::msg)? {
        let path = dir.join(file.name);
        std::fs::write(&path, &file.body)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
