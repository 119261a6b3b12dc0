//! Other layouts than KSA's: patches added where the target bends more
//! gently than KSA's curvature tolerance marks, and what each tried layout
//! reached.
//!
//! KSA marks the samples whose curvature is above `kappa_tol`; a bend
//! gentler than that all along (an arc of radius 150 mm against 0.01 mm⁻¹)
//! gets no patch, and a lower tolerance everywhere adds patches to stretches
//! that are straight but for sampling noise. So the finer layout is tried
//! after the refine, as a candidate: KSA at a `FINER` fraction of the
//! tolerance, its patches (or the part of each that the design's patches
//! leave free, if at least the shortest patch long) added to the
//! design, their circumferential positions brought into the design's frame
//! (KSA measures X from its own first patch) by the patches the two
//! layouts share. The candidate is refined like the design, and kept only
//! if its verified shape error is lower.
//!
//! A target that bends more gently still (an arc of radius 300 mm,
//! κ = 0.0033 mm⁻¹, under even that fraction) would get no patch at all;
//! on a curved target the finer tolerance is therefore also at most
//! `GENTLE` of the target's 90th-percentile curvature, so its bends are
//! marked however gentle. A target is curved when it strays from its
//! best-fit line by more than `CURVED` of its length (RMS): a straight
//! noisy stroke, whose smoothed curvature is noise, is not.

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use super::limits::at_weakest;
use super::variables::VariableBounds;
use crate::curve::{AnalysisOptions, Curve, analyse};
use crate::design::{Design, Patch};
use crate::ksa::{KsaParams, Stretch, ksa_on};

/// The finer layout's curvature tolerance, as a fraction of the run's.
pub const FINER: f64 = 0.4;

/// The finer tolerance on a curved target is at most this fraction of its
/// 90th-percentile curvature.
pub const GENTLE: f64 = 0.5;

/// A target straying from its best-fit line by more than this fraction of
/// its length (RMS) is curved (a 100° arc: 13 %; 0.3 mm of noise on a
/// 300 mm line: 0.1 %).
const CURVED: f64 = 0.01;

/// Space kept between an added patch and the design's own (mm).
const CLEARANCE_MM: f64 = 1.0;

/// A layout the run tried, and what it reached.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayoutTrial {
    /// What the layout is, in words.
    pub layout: String,
    pub patches: usize,
    /// Its verified shape error after its refine (% of length).
    pub shape_error_percent: f64,
    /// Whether the design is this layout's.
    pub chosen: bool,
}

/// The design with the finer layout's patches added where it has none (the
/// free part of each, [`free_part`]: at least `h_min_mm` long), or none
/// when the finer layout adds nothing.
pub fn with_gentle_bends(
    design: &Design,
    target: &Curve,
    kappa_tol: f64,
    params: &KsaParams,
    h_min_mm: f64,
) -> Option<Design> {
    // One analysis for the tolerance and the marking, with KSA's scheme:
    // the tolerance is judged on the curvature KSA marks by.
    let options = AnalysisOptions {
        scheme: params.scheme,
        ..AnalysisOptions::default()
    };
    let analysis = analyse(target, &options);
    let finer = KsaParams {
        kappa_tol: finer_tolerance(target, &analysis.curvature, kappa_tol),
        l0_mm: design.balloon.length_mm,
        r0_mm: design.balloon.radius_mm,
        stretch: Stretch::Fixed(target.length() / design.balloon.length_mm),
        ..params.clone()
    };
    let candidates = ksa_on(&analysis, &finer).patches;
    let circumference = TAU * design.balloon.radius_mm;
    let offset = frame_offset(&design.patches, &candidates, circumference);
    let added: Vec<Patch> = candidates
        .iter()
        .filter_map(|c| free_part(c, &design.patches, h_min_mm))
        .map(|c| Patch {
            x_mm: (c.x_mm + offset).rem_euclid(circumference),
            ..c
        })
        .collect();
    if added.is_empty() {
        return None;
    }
    let mut patches = design.patches.clone();
    patches.extend(added);
    patches.sort_by(|a, b| a.y_mm.total_cmp(&b.y_mm));
    Some(Design {
        patches,
        ..design.clone()
    })
}

/// KSA's tolerance for the finer layout: `FINER` of the run's, and on a
/// curved target at most `GENTLE` of the 90th percentile of its
/// `curvature` (per sample).
pub fn finer_tolerance(target: &Curve, curvature: &[f64], kappa_tol: f64) -> f64 {
    let finer = FINER * kappa_tol;
    if !is_curved(target) {
        return finer;
    }
    let mut kappa = curvature.to_vec();
    kappa.sort_by(f64::total_cmp);
    let bend = kappa[kappa.len() * 9 / 10];
    match bend > 0.0 {
        true => finer.min(GENTLE * bend),
        false => finer,
    }
}

/// Whether the curve strays from its best-fit line by more than `CURVED`
/// of its length (RMS).
fn is_curved(curve: &Curve) -> bool {
    curve.off_line_and_plane().0.sqrt() > CURVED * curve.length()
}

/// The part of `candidate`'s axial span that `design`'s patches leave free
/// (each kept `CLEARANCE_MM` away), as a patch: the candidate itself where
/// none comes near it; else its longest free stretch, the candidate's
/// other dimensions kept, if that is at least `h_min_mm` long; else none.
/// A refine moves patches into the gentle bends around them, so a bend
/// the design half covers still gets a patch on its other half.
fn free_part(candidate: &Patch, design: &[Patch], h_min_mm: f64) -> Option<Patch> {
    let (low, high) = span(candidate, 0.0);
    let mut blocked: Vec<(f64, f64)> = (design.iter())
        .filter(|p| overlap(p, candidate))
        .map(|p| span(p, CLEARANCE_MM))
        .collect();
    if blocked.is_empty() {
        return Some(*candidate);
    }
    blocked.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The free stretches between the blocked spans, within the candidate's.
    let (mut from, mut longest) = (low, (low, low));
    for (start, end) in blocked.into_iter().chain([(high, high)]) {
        let to = start.min(high);
        if to - from > longest.1 - longest.0 {
            longest = (from, to);
        }
        from = from.max(end);
    }
    let height = longest.1 - longest.0;
    (height >= h_min_mm).then_some(Patch {
        y_mm: 0.5 * (longest.0 + longest.1),
        h_mm: height,
        ..*candidate
    })
}

/// A patch's axial span, widened by `margin` at both ends.
fn span(patch: &Patch, margin: f64) -> (f64, f64) {
    let half = 0.5 * patch.h_mm + margin;
    (patch.y_mm - half, patch.y_mm + half)
}

/// Whether two patches' axial spans come within `CLEARANCE_MM`.
fn overlap(a: &Patch, b: &Patch) -> bool {
    (a.y_mm - b.y_mm).abs() < 0.5 * (a.h_mm + b.h_mm) + CLEARANCE_MM
}

/// The circumferential shift taking KSA's frame to the design's: the
/// circular mean of X(design) − X(KSA) over the pairs of patches that
/// overlap; 0 when none do (a design without patches has no frame yet).
fn frame_offset(design: &[Patch], candidates: &[Patch], circumference: f64) -> f64 {
    let (mut sin, mut cos) = (0.0, 0.0);
    for p in design {
        for c in candidates.iter().filter(|c| overlap(p, c)) {
            let angle = TAU * (p.x_mm - c.x_mm) / circumference;
            sin += angle.sin();
            cos += angle.cos();
        }
    }
    match sin == 0.0 && cos == 0.0 {
        true => 0.0,
        false => sin.atan2(cos) / TAU * circumference,
    }
}

/// The design less one of its weakest patches, and which one (its number
/// as in the tables), or none when no patch is at its weakest or the
/// design has only one.
///
/// A patch the refine left at both its smallest height and its narrowest
/// width bends the tube more than the target wants even so: a gentle bend
/// laid out as a train of patches (an arc of radius 600 mm) needs fewer of
/// them, further apart. Of the longest run of consecutive weakest patches
/// the middle one goes, and the run's others are spaced evenly between its
/// first and last (each refine moves a patch only within its Y window, so
/// the spacing has to be set here).
pub fn thinned(design: &Design, bounds: &VariableBounds) -> Option<(Design, usize)> {
    // A design keeps one patch at least: a curved target never ends bare.
    if design.patches.len() < 2 {
        return None;
    }
    let run = weakest_run(design, bounds)?;
    let removed = run[run.len() / 2];
    let kept: Vec<usize> = run.iter().copied().filter(|&i| i != removed).collect();
    let (first, last) = (
        design.patches[run[0]].y_mm,
        design.patches[run[run.len() - 1]].y_mm,
    );
    let mut patches = design.patches.clone();
    for (k, &index) in kept.iter().enumerate() {
        let f = match kept.len() {
            1 => 0.5,
            n => k as f64 / (n - 1) as f64,
        };
        patches[index].y_mm = first + f * (last - first);
    }
    patches.remove(removed);
    Some((
        Design {
            patches,
            ..design.clone()
        },
        removed + 1,
    ))
}

/// Whether two or more patches next to each other along the tube are at
/// their weakest: a train on a bend gentler than its patches make even at
/// their smallest and narrowest, which [`thinned`] shortens whatever the
/// design's shape error.
pub fn overfull(design: &Design, bounds: &VariableBounds) -> bool {
    weakest_run(design, bounds).is_some_and(|run| run.len() >= 2)
}

/// The longest run of patches next to each other along the tube (by Y)
/// that are all at their weakest, as indices into the design's patches.
fn weakest_run(design: &Design, bounds: &VariableBounds) -> Option<Vec<usize>> {
    let mut order: Vec<usize> = (0..design.patches.len()).collect();
    order.sort_by(|&a, &b| design.patches[a].y_mm.total_cmp(&design.patches[b].y_mm));
    let run = longest_run(&order, |i| at_weakest(&design.patches[i], bounds))?;
    Some(run.to_vec())
}

/// The longest run of consecutive entries of `order` that are `weakest`.
fn longest_run(order: &[usize], weakest: impl Fn(usize) -> bool) -> Option<&[usize]> {
    order
        .chunk_by(|&a, &b| weakest(a) == weakest(b))
        .filter(|run| weakest(run[0]))
        .rev()
        .max_by_key(|run| run.len())
}

#[cfg(test)]
#[path = "layout_tests.rs"]
mod tests;
