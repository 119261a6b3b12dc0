//! The Kinematic Segmentation Algorithm (Baines et al., Adv. Mater. 2023): a
//! geometric first guess at the patches from the target curve alone.
//!
//! 1. κ(s), τ(s) of the target; samples with κ > κ_tol are *marked*.
//! 2. Marked samples form runs; a gap of more than `merge_mm` of arc between
//!    consecutive marked samples starts a new run. As in the authors' code, a
//!    run's deformed centre is the mean arc length of its marked samples, its
//!    deformed length is last − first, and single-sample runs are dropped.
//! 3. Each run's twist φ = ∫τ ds (trapezoid over the run).
//! 4. Undeformed `Y = y/λ`, `H = h/λ`, `tan Θ = φ R₀ / H`.
//! 5. Circumferential position: the patch sits on the concave side, where the
//!    Frenet normal N points. Its angle ψ is measured in the Bishop frame, the
//!    material frame of an untwisted tube, so rotation of N between patches
//!    (torsion on twisted stretches, N flipping across planar inflections) is
//!    accumulated exactly. `X = R₀ (ψ(y) − φ/2)`, shifted so patch 1 sits at 0 and
//!    wrapped into `[0, 2πR₀)`. The authors derive the same quantity by integrating
//!    τ and detecting binormal flips piecewise.

mod stretch;

use std::f64::consts::TAU;

pub use stretch::Stretch;

use crate::curve::interpolate;
use crate::curve::{
    Analysis, AnalysisOptions, Curve, DerivativeScheme, analyse, bishop_frames, frenet_frames,
};
use crate::design::Patch;

/// Positions this close below 2πR₀ are reported as 0: far below any cutting or
/// gluing tolerance, and "19.98 mm" for a patch on the seam only confuses.
const WRAP_SNAP_MM: f64 = 1e-3;

/// KSA inputs. Defaults are the authors' reference scene.
#[derive(Debug, Clone, PartialEq)]
pub struct KsaParams {
    /// Uninflated balloon length L₀ (mm).
    pub l0_mm: f64,
    /// Uninflated balloon radius R₀ (mm).
    pub r0_mm: f64,
    /// Curvature above which a sample needs a patch (mm⁻¹).
    pub kappa_tol: f64,
    /// Marked samples further apart than this (arc length, mm) belong to
    /// different patches.
    pub merge_mm: f64,
    /// Width given to every patch (KSA says nothing about width) (mm).
    pub width_mm: f64,
    /// How deformed lengths map to undeformed ones.
    pub stretch: Stretch,
    /// How κ and τ are estimated for marking. The default is the authors' scheme,
    /// so the segmentation matches theirs sample for sample.
    pub scheme: DerivativeScheme,
    /// The longest patch (undeformed, mm): a longer run becomes a train of
    /// equal patches with gaps of `train_gap_mm`. None: one patch per run
    /// however long (the authors' algorithm).
    pub max_patch_mm: Option<f64>,
    /// The gap between the patches of a train (undeformed, mm).
    pub train_gap_mm: f64,
}

impl Default for KsaParams {
    fn default() -> Self {
        KsaParams {
            l0_mm: 292.0,
            r0_mm: 3.18,
            kappa_tol: 0.01,
            merge_mm: 20.0,
            width_mm: 1.5,
            stretch: Stretch::Uniform,
            scheme: DerivativeScheme::IteratedGradient,
            max_patch_mm: None,
            train_gap_mm: 2.0,
        }
    }
}

/// A KSA parameter outside its domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("KSA parameter {name} = {value}: {reason}")]
pub struct KsaError {
    pub name: &'static str,
    pub value: f64,
    pub reason: &'static str,
}

/// A run of marked samples in the deformed (target) configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Arc length of the first and last marked sample (mm).
    pub s_start: f64,
    pub s_end: f64,
    /// Mean arc length of the marked samples (mm): the deformed patch centre.
    pub s_centre: f64,
    /// ∫τ ds over the run (rad).
    pub twist: f64,
    /// Largest κ in the run (mm⁻¹).
    pub peak_curvature: f64,
}

/// KSA output: the stretch used, one patch per run, and the runs themselves.
#[derive(Debug, Clone, PartialEq)]
pub struct KsaResult {
    /// Axial stretch λ = deformed / undeformed length used for the mapping.
    pub stretch: f64,
    pub patches: Vec<Patch>,
    pub runs: Vec<Run>,
    /// Indices (into `patches`) of patches whose span was clipped to stay on the
    /// balloon.
    pub clipped: Vec<usize>,
    /// Indices (into `runs`) of runs that map entirely beyond the balloon's end
    /// and so have no patch: the balloon is too short for this curve at this
    /// stretch.
    pub off_balloon: Vec<usize>,
}

/// Runs KSA on `target` with the default curve analysis.
pub fn ksa(target: &Curve, params: &KsaParams) -> Result<KsaResult, KsaError> {
    validate(params)?;
    let options = AnalysisOptions {
        scheme: params.scheme,
        ..AnalysisOptions::default()
    };
    let analysis = analyse(target, &options);
    Ok(ksa_on(&analysis, params))
}

fn validate(p: &KsaParams) -> Result<(), KsaError> {
    let checks = [
        ("l0_mm", p.l0_mm),
        ("r0_mm", p.r0_mm),
        ("kappa_tol", p.kappa_tol),
        ("width_mm", p.width_mm),
    ];
    for (name, value) in checks {
        if !(value.is_finite() && value > 0.0) {
            return Err(KsaError {
                name,
                value,
                reason: "must be finite and positive",
            });
        }
    }
    if let Some(max) = p.max_patch_mm
        && !(max.is_finite() && max > 0.0)
    {
        return Err(KsaError {
            name: "max_patch_mm",
            value: max,
            reason: "must be finite and positive",
        });
    }
    if !(p.train_gap_mm.is_finite() && p.train_gap_mm >= 0.0) {
        return Err(KsaError {
            name: "train_gap_mm",
            value: p.train_gap_mm,
            reason: "must be finite and non-negative",
        });
    }
    if !(p.merge_mm.is_finite() && p.merge_mm >= 0.0) {
        return Err(KsaError {
            name: "merge_mm",
            value: p.merge_mm,
            reason: "must be finite and non-negative",
        });
    }
    p.stretch.validate()
}

/// KSA on an existing analysis (lets callers reuse κ, τ they already computed).
pub fn ksa_on(analysis: &Analysis, params: &KsaParams) -> KsaResult {
    let lambda = params.stretch.value(analysis.length(), params.l0_mm);
    let train = params.max_patch_mm.map(|max| Train {
        max_mm: max * lambda,
        gap_mm: params.train_gap_mm * lambda,
    });
    let runs = find_runs(analysis, params.kappa_tol, params.merge_mm, train);
    let angle = normal_angle_in_bishop_frame(analysis);
    let circumference = TAU * params.r0_mm;
    let mut patches = Vec::with_capacity(runs.len());
    let mut clipped = Vec::new();
    let mut off_balloon = Vec::new();
    let mut reference_angle = None;
    for (index, run) in runs.iter().enumerate() {
        let mut y = run.s_centre / lambda;
        let mut h = (run.s_end - run.s_start) / lambda;
        // Keep the patch on the balloon: clip its axial span to [0, L₀].
        let (lo, hi) = ((y - h / 2.0).max(0.0), (y + h / 2.0).min(params.l0_mm));
        if hi <= lo {
            off_balloon.push(index);
            continue;
        }
        if lo > y - h / 2.0 || hi < y + h / 2.0 {
            clipped.push(patches.len());
            y = 0.5 * (lo + hi);
            h = hi - lo;
        }
        let theta = (run.twist * params.r0_mm).atan2(h);
        let psi = interpolate(&analysis.s, &angle, run.s_centre) - run.twist / 2.0;
        let psi0 = *reference_angle.get_or_insert(psi);
        let x = (params.r0_mm * (psi - psi0)).rem_euclid(circumference);
        patches.push(Patch {
            // Rounding noise just below a full turn is the seam itself, 0.
            x_mm: if circumference - x < WRAP_SNAP_MM {
                0.0
            } else {
                x
            },
            y_mm: y,
            h_mm: h,
            w_mm: params.width_mm,
            theta_deg: theta.to_degrees(),
        });
    }
    KsaResult {
        stretch: lambda,
        patches,
        runs,
        clipped,
        off_balloon,
    }
}

/// How long runs are split, in deformed arc length (mm).
#[derive(Debug, Clone, Copy)]
struct Train {
    max_mm: f64,
    gap_mm: f64,
}

/// Splits a run's marked samples (indices, by arc length) into the `k`
/// equal pieces of a train, k = ⌈(L + g) / (max + g)⌉ for a span L: each
/// piece (L − (k − 1) g) / k long, consecutive pieces `gap_mm` apart. A
/// piece keeps the marked samples inside its span; one with fewer than two
/// is dropped (as a single-sample run is).
fn split_into_train(group: Vec<usize>, s: &[f64], train: Option<Train>) -> Vec<Vec<usize>> {
    let (first, last) = (s[group[0]], s[group[group.len() - 1]]);
    let span = last - first;
    let Some(Train { max_mm, gap_mm }) = train.filter(|t| span > t.max_mm) else {
        return vec![group];
    };
    let k = ((span + gap_mm) / (max_mm + gap_mm)).ceil().max(1.0) as usize;
    let piece = (span - (k - 1) as f64 * gap_mm) / k as f64;
    (0..k)
        .map(|j| {
            let from = first + j as f64 * (piece + gap_mm);
            let to = from + piece;
            group
                .iter()
                .copied()
                .filter(|&i| s[i] >= from - 1e-9 && s[i] <= to + 1e-9)
                .collect()
        })
        .collect()
}

fn find_runs(analysis: &Analysis, kappa_tol: f64, merge_mm: f64, train: Option<Train>) -> Vec<Run> {
    let marked: Vec<usize> = (0..analysis.len())
        .filter(|&i| analysis.curvature[i] > kappa_tol)
        .collect();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for &i in &marked {
        match groups.last_mut() {
            Some(group)
                if analysis.s[i] - analysis.s[*group.last().expect("non-empty")] <= merge_mm =>
            {
                group.push(i)
            }
            _ => groups.push(vec![i]),
        }
    }
    groups
        .into_iter()
        .flat_map(|g| split_into_train(g, &analysis.s, train))
        .filter(|g| g.len() > 1)
        .map(|g| {
            let s: Vec<f64> = g.iter().map(|&i| analysis.s[i]).collect();
            let twist = g
                .windows(2)
                .map(|w| {
                    let ds = analysis.s[w[1]] - analysis.s[w[0]];
                    0.5 * ds * (analysis.torsion[w[0]] + analysis.torsion[w[1]])
                })
                .sum();
            Run {
                s_start: s[0],
                s_end: s[s.len() - 1],
                s_centre: s.iter().sum::<f64>() / s.len() as f64,
                twist,
                peak_curvature: g.iter().map(|&i| analysis.curvature[i]).fold(0.0, f64::max),
            }
        })
        .collect()
}

/// Unwrapped angle ψ(s) of the Frenet normal in the Bishop frame (rad).
fn normal_angle_in_bishop_frame(analysis: &Analysis) -> Vec<f64> {
    let bishop = bishop_frames(analysis);
    let frenet = frenet_frames(analysis);
    let mut angles = Vec::with_capacity(analysis.len());
    let mut previous: Option<f64> = None;
    for (b, f) in bishop.iter().zip(&frenet) {
        let raw = f.first.dot(&b.second).atan2(f.first.dot(&b.first));
        let unwrapped = match previous {
            // Keep ψ continuous except where N genuinely flips (an inflection):
            // choose the branch nearest the previous angle.
            Some(prev) => {
                prev + (raw - prev + std::f64::consts::PI).rem_euclid(TAU) - std::f64::consts::PI
            }
            None => raw,
        };
        angles.push(unwrapped);
        previous = Some(unwrapped);
    }
    angles
}
