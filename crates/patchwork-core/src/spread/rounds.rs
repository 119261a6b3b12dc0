//! The spread's solves, in rounds. Those sources whose linearised change
//! is at least [`SOLVED_FRACTION`] of the largest change found are solved
//! both ways — Newton solves at +tolerance, warm-started from the nominal
//! state (all but a patch's X from their linearised state,
//! `models::starts_linearised`), and at −tolerance, started from the
//! first solve less twice the linearised change
//! (`fe::second_order_start`; a patch's X from the nominal reflected
//! through the first solve ring by ring, `fe::reflected_start`), each to
//! `Nominal::source_options` — and the largest is taken again from the
//! solved, until every source above the fraction is solved. The
//! balloon's sources that act as one — the wall and the modulus exactly,
//! the pressure where its linearised move lies along theirs — are solved
//! together in the first round whatever their linearised size: two solves
//! at the nodes of a Gauss–Hermite rule on their joint variable, each
//! source shown with its share (`balloon.rs`). Where a node's solve fails
//! they are taken one by one as the other sources are (solved where due),
//! and of the wall and the modulus only the one with the larger
//! tolerance; the other reads its change (`Source::equivalent`,
//! `Change::scaled`).
//!
//! A round's solves share the threads as one list, each solve on one
//! thread, the longest first (the joined nodes, on the finer model and
//! the furthest moved, then the balloon's other sources, then the
//! patches'), so no thread waits while another finishes a round's last
//! long solve. On nine draft designs (`patchwork spread`, 2 threads,
//! medians of three) this took 0.82–1.02 of the time of solving the
//! joined nodes on their own before a round's other sources, and only
//! once one of them was due (the trefoil 0.82, the helix 0.85), with the
//! same spread.

use super::answer::Estimate;
use super::balloon::{Joined, apportioned};
use super::change::{Change, Nominal, Offsets, offsets_of};
use super::models::{Found, OnModels};
use super::sources::Source;
use super::tolerances::Tolerances;
use crate::curve::{Curve, Point};
use crate::design::Design;
use crate::fe::{Simulation, reflected_start, second_order_start, simulate_with};

/// A source whose linearised change is at least this fraction of the
/// largest change (RMS) is solved; a smaller one keeps its linearised change.
pub const SOLVED_FRACTION: f64 = 0.5;

/// A solve of a round: a node of the balloon's joined sources (σ; the
/// quadrature's other node is a job of its own), or a source at + and −
/// its tolerance.
#[derive(Clone, Copy)]
pub(super) enum Job<'a> {
    Node(&'a Joined, f64),
    Source(usize),
}

impl Job<'_> {
    /// The FE solves it takes: a node one, a source two (each way; a
    /// failed solve counted).
    pub(super) fn solves(&self) -> usize {
        match self {
            Job::Node(..) => 1,
            Job::Source(_) => 2,
        }
    }
}

/// What a job found: a node's offsets, or source k's change.
pub(super) enum Done {
    Node(Result<Offsets, String>),
    Source(usize, Result<(Change, Estimate), String>),
}

/// A round of solves: the joined sources where they are due, and the
/// other sources due.
pub(super) struct Round {
    joined: Option<Joined>,
    pending: Vec<usize>,
}

impl Round {
    /// The next round: `joined` (the balloon's joined sources, due in the
    /// first round) and the sources [`to_solve`] leaves; none when neither
    /// is left.
    pub(super) fn next(changes: &[Found], joined: Option<Joined>) -> Option<Round> {
        let mut pending = to_solve(changes).unwrap_or_default();
        pending.retain(|&k| !joined.as_ref().is_some_and(|j| j.has(k)));
        (joined.is_some() || !pending.is_empty()).then_some(Round { joined, pending })
    }

    /// Its solves, on the threads together, each on one thread: the
    /// joined sources' nodes, then the balloon's other sources, then the
    /// patches' — the longest first, so the threads share them out to the
    /// end.
    pub(super) fn jobs(&self, sources: &[Source]) -> Vec<Job<'_>> {
        let mut pending = self.pending.clone();
        pending.sort_by_key(|&k| matches!(sources[k], Source::Patch { .. }));
        let nodes =
            (self.joined.iter()).flat_map(|j| Joined::nodes().map(move |n| Job::Node(j, n)));
        nodes.chain(pending.into_iter().map(Job::Source)).collect()
    }
}

/// What every solve of the spread reads: the models, the sources, their
/// tolerances, each source's design at + its tolerance and its linearised
/// state.
pub(super) struct Context<'a> {
    pub on: &'a OnModels<'a>,
    pub sources: &'a [Source],
    pub tolerances: &'a Tolerances,
    pub moved: &'a [Design],
    pub starts: &'a [Option<Vec<Point>>],
}

impl Context<'_> {
    pub(super) fn solve(&self, job: Job) -> Done {
        let (sources, tolerances) = (self.sources, self.tolerances);
        match job {
            Job::Node(joined, n) => {
                let (nominal, samples) = self.on.of(sources[joined.members[0].0]);
                let tolerated = (sources, tolerances);
                Done::Node(joined.node(nominal, n, tolerated, self.starts, samples))
            }
            Job::Source(k) => {
                let (nominal, samples) = self.on.of(sources[k]);
                let tolerance = sources[k].tolerance(tolerances).0;
                let other_way = sources[k].moved(nominal.design, -tolerance);
                let start = self.starts[k].as_deref();
                let found = solved_change(nominal, (&self.moved[k], start), &other_way, samples);
                Done::Source(k, found)
            }
        }
    }

    /// A round's findings into `changes`: the joined sources' shares where
    /// every node solved (where one failed they stay as they were, to be
    /// solved one by one), each other source's change; the first source
    /// whose solve failed, and why.
    pub(super) fn take(
        &self,
        round: &Round,
        done: Vec<Done>,
        changes: &mut [Found],
    ) -> Result<(), (Source, String)> {
        let mut nodes = Vec::new();
        for found in done {
            match found {
                Done::Node(offsets) => nodes.push(offsets),
                Done::Source(k, found) => {
                    changes[k] = Some(found.map_err(|reason| (self.sources[k], reason))?);
                }
            }
        }
        let nodes: Result<Vec<Offsets>, String> = nodes.into_iter().collect();
        if let (Some(joined), Ok(nodes)) = (&round.joined, nodes) {
            let change = Joined::change(&nodes);
            for (k, share) in joined.shares() {
                changes[k] = Some((apportioned(&change, share), Estimate::Combined));
            }
        }
        Ok(())
    }
}

/// The sources to solve next: those without a change, and those linearised
/// at `SOLVED_FRACTION` of the largest change or more; none when no source
/// is left to solve.
fn to_solve(changes: &[Found]) -> Option<Vec<usize>> {
    let largest = changes
        .iter()
        .flatten()
        .map(|(c, _)| c.rms_mm())
        .fold(0.0, f64::max);
    let pending: Vec<usize> = (0..changes.len())
        .filter(|&k| match &changes[k] {
            None => true,
            Some((c, Estimate::Linearised)) => c.rms_mm() >= SOLVED_FRACTION * largest,
            Some((_, Estimate::Solved | Estimate::BothWays)) => false,
            Some((_, Estimate::Equivalent | Estimate::Combined)) => false,
        })
        .collect();
    (!pending.is_empty()).then_some(pending)
}

/// A source's change by Newton solves at `plus` (warm-started from
/// `plus_start`, its linearised positions, where given, else from the
/// nominal state) and at `other_way` (started from the first less twice
/// the linearised change where `plus_start` is given,
/// `fe::second_order_start`, else from the nominal reflected through the
/// first, `fe::reflected_start`). Where the second solve
/// fails the first one's change stands alone (`Solved`).
fn solved_change(
    nominal: &Nominal,
    (plus, plus_start): (&Design, Option<&[Point]>),
    other_way: &Design,
    samples: &Curve,
) -> Result<(Change, Estimate), String> {
    let options = nominal.source_options();
    let home = &nominal.simulation.centreline;
    let solve = |design: &Design, start: &Simulation| {
        simulate_with(design, &options, Some(start), nominal.patterns).map_err(|e| e.to_string())
    };
    let linearised = plus_start.map(|positions| Simulation {
        positions: positions.to_vec(),
        ..nominal.simulation.clone()
    });
    let plus_state = solve(plus, linearised.as_ref().unwrap_or(nominal.simulation))?;
    let plus_offsets = offsets_of(&plus_state.centreline, home, samples)?;
    // Where the linearisation answers closely, at second order from it;
    // else the nominal reflected ring by ring through the first solve.
    let second =
        plus_start.and_then(|lin| second_order_start(nominal.simulation, &plus_state, lin));
    let start = second.or_else(|| reflected_start(nominal.simulation, &plus_state));
    let minus = solve(other_way, start.as_ref().unwrap_or(nominal.simulation))
        .and_then(|state| offsets_of(&state.centreline, home, samples));
    Ok(match minus {
        Ok(minus) => (Change::both_ways(&plus_offsets, &minus), Estimate::BothWays),
        Err(_) => (Change::one_way(&plus_offsets), Estimate::Solved),
    })
}
