//! The target against what the balloon can make: where the target's bend,
//! or its twist per bend, is beyond every patch the bounds allow.
//!
//! The target is judged over windows: its bend over the shortest patch
//! (`h_min_mm`), since a patch cannot make a feature shorter than itself,
//! and its twist per bend over the longest (`h_max_mm`), since one patch
//! makes one twist per bend along it. With the target smoothed (σ a
//! quarter of the bend window), its bend per length is κ̄ = ∫κ ds / w.
//!
//! Its twist per bend is q = |τ|/κ of the helix that best fits the twist
//! window (`helix.rs`, from tangents and curvature vectors: τ itself, a
//! third derivative, is mostly noise on a drawn curve and spikes where a
//! bend starts). On a plane curve q = 0.
//!
//! For each width the table's entries, by angle, trace a path (κ(Θ), |τ(Θ)|),
//! linear between entries, each entry at its peak bend over the bend
//! window (measured on its centreline as targets are) and its helix's twist
//! per bend; a narrower or shorter patch or a gap makes less
//! of both in proportion, so the reachable set of the (κ, |τ|) plane is the
//! union of the segments from 0 to the paths' points. At twist per bend q
//! the tightest bend κ(q) is the farthest crossing of the ray τ = qκ with
//! the paths; a window is out of reach when its κ̄ is beyond κ(q) by more
//! than `MARGIN`, or the ray crosses none.

use serde::{Deserialize, Serialize};

use super::helix::HelixFit;
use super::measure::{analysed, bends};
use super::table::ReachTable;
use crate::curve::Curve;

/// How far beyond the table a window must be to be reported (the table is
/// one model's, and the design has freedoms it does not).
const MARGIN: f64 = 0.1;

/// Twist per bend this small is rounding, not twist (an axial patch's).
const TWIST_ROUNDING: f64 = 1e-6;

/// Windows closer than this (mm of arc) are reported as one span.
const JOIN_MM: f64 = 5.0;

/// A stretch of the target beyond every patch the bounds allow.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutOfReach {
    /// Arc length along the target where it starts and ends (mm).
    pub s_start_mm: f64,
    pub s_end_mm: f64,
    /// The tightest bend radius the stretch asks for (mm), 1/κ̄.
    pub needs_bend_radius_mm: f64,
    /// Its twist per bend there (τ/κ of the best-fitting helix).
    pub needs_twist_per_bend: f64,
    /// The tightest bend radius a patch makes at that twist per bend (mm);
    /// absent when no patch makes that much twist per bend.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tightest_bend_radius_mm: Option<f64>,
    /// The same, in words.
    pub message: String,
}

/// What the balloon can make within the bounds, and where the target asks
/// for more.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReachReport {
    /// The tightest bend radius any patch of the table makes (mm).
    pub tightest_bend_radius_mm: f64,
    /// The most twist per bend any patch of the table makes.
    pub most_twist_per_bend: f64,
    /// The windows the target was judged over.
    pub windows: WindowLengths,
    /// Stretches of the target out of reach; empty when it is all within.
    pub out_of_reach: Vec<OutOfReach>,
    /// The table it was judged against.
    pub table: ReachTable,
}

impl ReachReport {
    pub fn reachable(&self) -> bool {
        self.out_of_reach.is_empty()
    }
}

/// The reach of the table: for each width, the piecewise-linear path of
/// (κ, |τ|) as the angle grows. A patch that makes (κ, τ) can make less of
/// both in proportion (a narrower or shorter patch, a gap), so the
/// reachable set is the union of the segments from 0 to each point of the
/// paths.
struct Envelope {
    /// Per width, (κ, |τ|) by increasing angle.
    paths: Vec<Vec<(f64, f64)>>,
}

impl Envelope {
    fn new(table: &ReachTable) -> Envelope {
        let mut entries = table.entries.clone();
        entries.sort_by(|a, b| {
            (a.width_mm, a.theta_deg)
                .partial_cmp(&(b.width_mm, b.theta_deg))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let paths = entries
            .chunk_by(|a, b| a.width_mm == b.width_mm)
            .map(|run| run.iter().map(|e| e.peak()).collect())
            .collect();
        Envelope { paths }
    }

    /// The most twist per bend of any entry.
    fn most_twist(&self) -> f64 {
        self.paths
            .iter()
            .flatten()
            .filter(|p| p.0 > 0.0)
            .map(|p| p.1 / p.0)
            .fold(0.0, f64::max)
    }

    /// The largest κ at twist per bend q: where the ray τ = qκ crosses the
    /// paths, the farthest crossing; none when it crosses none (no angle
    /// twists that much per bend).
    fn curvature_at(&self, q: f64) -> Option<f64> {
        let mut best: Option<f64> = None;
        for path in &self.paths {
            // Less twist per bend than the path's first (least inclined)
            // entry makes, which is none but for rounding: that entry.
            if let Some(&(k, t)) = path.first()
                && q * k <= t
                && k > 0.0
                && t / k <= TWIST_ROUNDING
            {
                best = Some(best.map_or(k, |b| b.max(k)));
            }
            let single = path.len() == 1;
            for pair in path.windows(if single { 1 } else { 2 }) {
                let ((k0, t0), (k1, t1)) = (pair[0], pair[pair.len() - 1]);
                // τ − qκ along the segment: (t0 − q k0) + s((t1 − t0) − q(k1 − k0)).
                let (start, slope) = (t0 - q * k0, (t1 - t0) - q * (k1 - k0));
                let s = match (slope != 0.0, start == 0.0) {
                    (true, _) => -start / slope,
                    (false, true) => 1.0,
                    (false, false) => continue,
                };
                if (0.0..=1.0).contains(&s) {
                    let k = k0 + s * (k1 - k0);
                    best = Some(best.map_or(k, |b| b.max(k)));
                }
            }
        }
        best.filter(|k| *k > 0.0)
    }
}

/// One window of the target: its bend per length and twist per bend.
#[derive(Debug, Clone, Copy)]
struct Window {
    s_mm: f64,
    curvature: f64,
    twist_per_bend: f64,
}

/// The lengths of arc the target is judged over (mm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowLengths {
    /// Bend per length, over the shortest patch (`h_min_mm`).
    pub bend_mm: f64,
    /// Twist per bend, over the longest patch (`h_max_mm`): one patch at
    /// one angle makes one twist per bend along it, and τ, a third
    /// derivative, needs the longer average on drawn curves.
    pub twist_mm: f64,
}

/// The target's windows centred on each sample, where it bends by more
/// than `kappa_tol`.
fn windows(target: &Curve, lengths: WindowLengths, kappa_tol: f64) -> Vec<Window> {
    let analysis = analysed(target, lengths.bend_mm);
    let helix = HelixFit::new(&analysis);
    bends(&analysis, lengths.bend_mm)
        .into_iter()
        .zip(&analysis.s)
        .filter(|(curvature, _)| *curvature > kappa_tol)
        .map(|(curvature, &s)| Window {
            s_mm: s,
            curvature,
            twist_per_bend: helix.twist_per_bend(s, lengths.twist_mm),
        })
        .collect()
}

/// Where `target` is out of the table's reach, judged over windows of
/// `lengths` where it bends by more than `kappa_tol`.
pub fn judge(
    target: &Curve,
    table: ReachTable,
    lengths: WindowLengths,
    kappa_tol: f64,
) -> ReachReport {
    let envelope = Envelope::new(&table);
    // A table of straight tubes (a patch as soft as the wall) reports a
    // kilometre rather than an infinite radius.
    let tightest = envelope.curvature_at(0.0).unwrap_or(0.0).max(1e-6);
    let most_twist = envelope.most_twist();
    let beyond: Vec<(Window, Option<f64>)> = windows(target, lengths, kappa_tol)
        .into_iter()
        .filter_map(|w| {
            let reach = envelope.curvature_at(w.twist_per_bend);
            let out = match reach {
                Some(k) => w.curvature > (1.0 + MARGIN) * k,
                None => true,
            };
            out.then_some((w, reach))
        })
        .collect();
    ReachReport {
        tightest_bend_radius_mm: 1.0 / tightest,
        most_twist_per_bend: most_twist,
        windows: lengths,
        out_of_reach: spans(&beyond, most_twist, lone_windows_count(target, lengths)),
        table,
    }
}

/// Whether a span of one window counts: on a curve sampled finely against
/// the bend window (four samples or more to it) a window's neighbours
/// overlap it almost wholly, so one window out of reach between two within
/// it is the fit failing (a helix fitted across an inflection twists
/// without bound), not the curve.
fn lone_windows_count(target: &Curve, lengths: WindowLengths) -> bool {
    let spacing = target.length() / (target.len().max(2) - 1) as f64;
    spacing > 0.25 * lengths.bend_mm
}

/// Windows out of reach joined into spans, each described by its
/// tightest window; spans of one window left out unless `lone_counts`.
fn spans(beyond: &[(Window, Option<f64>)], most_twist: f64, lone_counts: bool) -> Vec<OutOfReach> {
    let mut groups: Vec<Vec<(Window, Option<f64>)>> = Vec::new();
    for &(w, reach) in beyond {
        match groups.last_mut() {
            Some(group) if w.s_mm - group[group.len() - 1].0.s_mm <= JOIN_MM => {
                group.push((w, reach))
            }
            _ => groups.push(vec![(w, reach)]),
        }
    }
    groups
        .iter()
        .filter(|group| lone_counts || group.len() > 1)
        .map(|group| {
            let (worst, reach) = group
                .iter()
                .copied()
                .max_by(|a, b| a.0.curvature.total_cmp(&b.0.curvature))
                .expect("groups are not empty");
            let (from, to) = (group[0].0.s_mm, group[group.len() - 1].0.s_mm);
            out_of_reach(from, to, worst, reach, most_twist)
        })
        .collect()
}

fn out_of_reach(
    from: f64,
    to: f64,
    worst: Window,
    reach: Option<f64>,
    most_twist: f64,
) -> OutOfReach {
    let needs = 1.0 / worst.curvature;
    let q = worst.twist_per_bend;
    let message = match reach {
        Some(k) => format!(
            "s = {from:.0}–{to:.0} mm needs a bend radius of {needs:.0} mm \
             (twist per bend {q:.2}); the tightest a patch makes there is {:.0} mm",
            1.0 / k
        ),
        None => format!(
            "s = {from:.0}–{to:.0} mm needs {q:.2} of twist per bend \
             (bend radius {needs:.0} mm); the most a patch makes is {most_twist:.2}"
        ),
    };
    OutOfReach {
        s_start_mm: from,
        s_end_mm: to,
        needs_bend_radius_mm: needs,
        needs_twist_per_bend: q,
        tightest_bend_radius_mm: reach.map(|k| 1.0 / k),
        message,
    }
}

#[cfg(test)]
#[path = "verdict_tests.rs"]
mod tests;
