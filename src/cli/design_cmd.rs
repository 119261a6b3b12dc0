//! `patchwork design CURVE --out DIR [--seed S] [--budget EVALS] [--patience EVALS] [--polish EVALS] [--refine SOLVES] [--no-correction] [--threads N] [--json]
//! [--fidelity draft|standard|fine]`.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::design::Design;
use patchwork_core::fabrication::design_files;
use patchwork_core::inverse::{
    Caches, DesignCheckpoint, DesignProgress, DesignReport, Fidelity, ObjectiveOptions, Observer,
    Plan, SettingsError, Stage, Start, TuningOverrides, UserSettings, design_resumable,
};

use super::design_summary::summary;
use super::input::{CurveInput, read_text_argument};
use super::output::{emit, emit_json};

#[derive(Args)]
#[command(allow_negative_numbers = true)]
pub struct DesignArgs {
    #[command(flatten)]
    input: CurveInput,
    /// Folder for design.json, design.csv, patches.dxf, template.dxf,
    /// template.svg and profiles.svg (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Random seed: the same seed reproduces the same design.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Forward simulations the search may spend (default 200 in every
    /// fidelity).
    #[arg(long)]
    budget: Option<usize>,
    /// End the search once this many evaluations pass without a better
    /// design (default 80 in every fidelity; 0: spend the whole budget).
    #[arg(long)]
    patience: Option<usize>,
    /// Evaluations of a coarse-to-fine polish: a short CMA-ES run on the
    /// verification model after the search (default 0: the refine does the
    /// job better; on ten round trips with draft, `--polish 120` reached a
    /// median 0.28 % shape error with 9 of 10 under 0.5 %, a 60-solve refine
    /// 0.06 % with 10 of 10 in a quarter of the time).
    #[arg(long)]
    polish: Option<usize>,
    /// Solves of the refine: Levenberg–Marquardt on the shape error on the
    /// verification model (default: the fidelity's, 60/75/240 for
    /// draft/standard/fine; 0 turns it off). Standard and fine spend the
    /// first 60 as draft does and the rest on a final refine on the uniform
    /// 0.5 mm mesh.
    /// A Jacobian (linearised responses of the solved state, one
    /// factorisation) counts as one solve, a trial step as one (steps
    /// between Jacobians use Broyden updates).
    #[arg(long)]
    refine: Option<usize>,
    /// Refine on the verification model without the finer model's
    /// correction, and verify there (every preset corrects the refine by a
    /// graded 0.5 mm model and verifies on it: on the Hilbert curve
    /// 0.33 % → 0.13 % shape error for four finer solves; standard and
    /// fine then refine on the uniform 0.5 mm mesh all the same).
    #[arg(long)]
    no_correction: bool,
    /// Weight of the shape error (aligned RMS distance / curve length) added
    /// to the κ/τ mismatch in the objective; 0 leaves it out [default: 10].
    #[arg(long)]
    shape_weight: Option<f64>,
    /// Use the squared form of the κ/τ mismatch (the paper's) instead of the
    /// authors' code's sum of norms.
    #[arg(long)]
    squared: bool,
    /// CMA-ES's initial step as a fraction of each variable's range
    /// [default: 0.2].
    #[arg(long)]
    initial_step: Option<f64>,
    /// Where CMA-ES starts: `ksa` (KSA's patches, windows around them) or
    /// `even` (unseeded: as many patches spread evenly, free over the whole
    /// balloon — to measure what the seed is worth).
    #[arg(long)]
    start: Option<Start>,
    /// Threads evaluating a generation in parallel.
    #[arg(long, default_value_t = std::thread::available_parallelism().map_or(1, |n| n.get()))]
    threads: usize,
    /// Print design.json to stdout.
    #[arg(long)]
    json: bool,
    /// Balloon, patch material and pressure as design JSON (patches ignored);
    /// defaults to the reference scene.
    #[arg(long)]
    options: Option<String>,
    /// Fabrication limits and search windows as JSON, e.g.
    /// `{"w_min_mm": 0.5}`; fields left out keep their defaults (h 10–30 mm,
    /// w 1–3 mm, |Θ| ≤ 80°, windows X ±5 mm, Y ±5 mm, Θ ±30° around the
    /// seed). The report names every patch that ends on one of these limits.
    #[arg(long)]
    bounds: Option<String>,
    /// Keep the balloon length from --options instead of choosing it so the
    /// inflated balloon is as long as the curve (the mismatch is reported).
    #[arg(long)]
    fix_length: bool,
    /// Model fidelity: draft (search on 3 mm rings, refine on 1 mm
    /// corrected by 0.5 mm, verify on 0.5 mm), standard (draft's run, then
    /// about 15 solves of a final refine on a uniform 0.5 mm mesh, which is
    /// also the verification) or fine (the same final refine, until it
    /// converges or 240 solves in all); graded meshes are fine under
    /// patches, coarse along bare stretches.
    #[arg(long, default_value = "standard")]
    fidelity: Fidelity,
    /// Element size of the search model (mm), overriding the fidelity's with
    /// uniform meshes; the refine and verification then use half of it,
    /// uncorrected (and standard's and fine's final refine is dropped).
    #[arg(long)]
    mesh_mm: Option<f64>,
    /// Expert tuning as JSON (a file, `-` for stdin, or inline `{…}`), laid over the fidelity
    /// preset: search_patience, initial_step, start, warm_starts, objective,
    /// uniform_mesh_mm, polish_budget, refine_budget, correction,
    /// final_refine, trains, gentle_bends, planar_designs, kappa_tol. The flags above win over it.
    #[arg(long)]
    tuning: Option<String>,
    /// Write the run's state here after every generation; if the file exists,
    /// resume from it (same curve and options) instead of starting again.
    #[arg(long)]
    checkpoint: Option<PathBuf>,
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
    /// The plan these options ask for: the user's settings and the research
    /// flags as tuning overrides, resolved as the API resolves a job.
    pub fn plan(&self) -> Result<Plan> {
        let base: Design = match &self.options {
            Some(name) => {
                let text = read_text_argument(name)?;
                let mut value: serde_json::Value =
                    serde_json::from_str(&text).with_context(|| format!("{name}: invalid JSON"))?;
                if let Some(object) = value.as_object_mut() {
                    object.entry("patches").or_insert(serde_json::json!([]));
                }
                serde_json::from_value(value)
                    .with_context(|| format!("{name}: invalid design options"))?
            }
            None => Design::reference(vec![]),
        };
        let bounds = match &self.bounds {
            Some(text) => {
                serde_json::from_str(text).map_err(|e| anyhow::anyhow!("--bounds: {e}"))?
            }
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
            smoothing: self.input.smoothing(),
            threads: self.threads,
        };
        let objective = (self.shape_weight.is_some() || self.squared).then(|| ObjectiveOptions {
            shape_weight: self
                .shape_weight
                .unwrap_or(ObjectiveOptions::default().shape_weight),
            squared: self.squared,
            ..ObjectiveOptions::default()
        });
        let file: TuningOverrides = match &self.tuning {
            Some(inline) if inline.trim_start().starts_with('{') => {
                serde_json::from_str(inline).map_err(|e| anyhow::anyhow!("--tuning: {e}"))?
            }
            Some(name) => serde_json::from_str(&read_text_argument(name)?)
                .map_err(|e| anyhow::anyhow!("--tuning: {name}: {e}"))?,
            None => TuningOverrides::default(),
        };
        let overrides = TuningOverrides {
            search_patience: self.patience.or(file.search_patience),
            initial_step: self.initial_step.or(file.initial_step),
            start: self.start.or(file.start),
            objective: objective.or(file.objective),
            uniform_mesh_mm: self.mesh_mm.or(file.uniform_mesh_mm),
            polish_budget: self.polish.or(file.polish_budget),
            refine_budget: self.refine.or(file.refine_budget),
            correction: self.no_correction.then_some(false).or(file.correction),
            ..file
        };
        Plan::resolve(settings, &overrides).map_err(flag_error)
    }
}

/// A settings error in the words of the command line: the flag that set it.
fn flag_error(error: SettingsError) -> anyhow::Error {
    let SettingsError { field, reason } = error;
    let flag = match field.as_str() {
        "budget" | "threads" | "initial_step" => field.replace('_', "-"),
        "smoothing" => "smooth-mm".into(),
        "uniform_mesh_mm" | "search_mesh" | "verify_mesh" => "mesh-mm".into(),
        f if f.starts_with("objective.") => f.trim_start_matches("objective.").replace('_', "-"),
        f if f.starts_with("bounds.") => return anyhow::anyhow!("--bounds: {reason}"),
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
        let stage = match p.stage {
            Stage::Seed => "seed  ",
            Stage::Reach => "reach ",
            Stage::Search => "search",
            Stage::Polish => "polish",
            Stage::Verify => "verify",
            Stage::Refine => "refine",
        };
        eprint!(
            "\r{stage} generation {:>4}  evaluations {:>5}/{}  best {:>9.5}  σ {:.3}  {:>6.1} s ",
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
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let terminal = std::io::stderr().is_terminal();
    let cancel = AtomicBool::new(false);
    let resume = match &args.checkpoint {
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
    let mut observer = CliObserver {
        terminal,
        total_budget: plan.total_budget(),
        checkpoint: args.checkpoint.as_deref(),
        save_error: None,
    };
    let outcome = design_resumable(
        &target,
        &plan,
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
    let report = DesignReport::new(&outcome, args.seed);
    write_files(&args.out, &report)?;
    if args.json {
        return emit_json(&report);
    }
    emit(&summary(&report, &args.out))
}

fn write_files(dir: &std::path::Path, report: &DesignReport) -> Result<()> {
    for file in design_files(report).map_err(anyhow::Error::msg)? {
        let path = dir.join(file.name);
        std::fs::write(&path, &file.body)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}
