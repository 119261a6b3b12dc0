//! Which state each source of a spread is found on, and the sources'
//! linearised changes there.

use super::answer::Estimate;
use super::change::{Change, Nominal, SAMPLES, offsets_of};
use super::sources::{PatchQuantity, Source};
use crate::CurveError;
use crate::curve::Curve;
use crate::curve::Point;
use crate::design::Design;
use crate::fe::sensitivity::linearised_states;
use crate::fe::{SimulateOptions, Simulation};

/// The nominal states a spread's sources are found on: the balloon's three
/// (pressure, wall, modulus) on `balloon`, each patch's on `patches` — the
/// same state, or the design on a coarser model. A patch's change is a
/// local bend, which a coarse model resolves as the fine one does; the
/// balloon's sources change the whole tube's stretch, which it does not
/// (`spread::linear`'s note).
#[derive(Clone, Copy)]
pub struct Models<'a> {
    pub balloon: Nominal<'a>,
    pub patches: Nominal<'a>,
}

impl<'a> Models<'a> {
    /// Every source on `nominal`.
    pub fn one(nominal: Nominal<'a>) -> Models<'a> {
        Models {
            balloon: nominal,
            patches: nominal,
        }
    }

    /// The balloon's sources on `nominal`, the patches' on the same
    /// design's state and model `patches` where given (else on `nominal`).
    pub fn pair(
        nominal: Nominal<'a>,
        patches: Option<(&'a Simulation, &'a SimulateOptions)>,
    ) -> Models<'a> {
        let patches = patches.map(|(simulation, options)| Nominal {
            simulation,
            options,
            ..nominal
        });
        Models {
            balloon: nominal,
            patches: patches.unwrap_or(nominal),
        }
    }

    /// Whether every source is found on one state.
    pub fn shared(&self) -> bool {
        std::ptr::eq(self.balloon.simulation, self.patches.simulation)
    }
}

/// A source's change found so far, and how.
pub(super) type Found = Option<(Change, Estimate)>;

/// Each source's change linearised (none where it has none), and the
/// linearised state where it is a better start for the source's solve
/// than the nominal (all but a patch's X: [`starts_linearised`]).
pub(super) struct LinearisedSources {
    pub changes: Vec<Found>,
    pub starts: Vec<Option<Vec<Point>>>,
    /// Each linearised change's move at every sample of its nominal
    /// (after the best rigid alignment), where it has one.
    pub fields: Vec<Option<Vec<Point>>>,
    /// The linearisations run (each a factorisation, counted as a solve).
    pub runs: usize,
}

/// Whether `source`'s solve starts from its linearised state: every
/// source's but a patch's placement around the tube (X). A balloon source
/// moves the whole tube's stretch and a patch's Y, angle and size its bend
/// by about as much as the linearisation predicts, and Newton takes about
/// half the iterations from there (on the verification model: the Hilbert,
/// trefoil and conical spiral's draft designs' balloon sources; on graded
/// 2 mm, the helix's, Hilbert's and grasp's patches: angle 97 → 58, width
/// 86 → 46, Y 91 → 65, length 35 → 19 iterations over their sources). A
/// patch's X it overstates up to sixfold: from its linearised state the
/// same patches' X took 226 → 300 iterations (fewer on the Hilbert, more
/// on the helix and the grasp).
pub(super) fn starts_linearised(source: Source) -> bool {
    !matches!(
        source,
        Source::Patch {
            quantity: PatchQuantity::X,
            ..
        }
    )
}

/// [`Models`] with each nominal's samples of its centreline, at which its
/// sources' changes are measured.
pub(super) struct OnModels<'a> {
    models: &'a Models<'a>,
    balloon: Curve,
    patches: Curve,
}

impl<'a> OnModels<'a> {
    pub(super) fn new(models: &'a Models<'a>) -> Result<OnModels<'a>, CurveError> {
        let samples = |n: &Nominal| n.simulation.centreline.resample(SAMPLES);
        Ok(OnModels {
            models,
            balloon: samples(&models.balloon)?,
            patches: samples(&models.patches)?,
        })
    }

    /// The nominal `source` is found on, and its samples.
    pub(super) fn of(&self, source: Source) -> (&Nominal<'a>, &Curve) {
        match source {
            Source::Patch { .. } => (&self.models.patches, &self.patches),
            Source::Pressure | Source::Wall | Source::Modulus => {
                (&self.models.balloon, &self.balloon)
            }
        }
    }

    /// Each source's linearised change (`moved`: each source's design at
    /// its tolerance) on its nominal: one linearisation where every source
    /// shares a state, else one per state that has sources.
    pub(super) fn linearised(
        &self,
        sources: &[Source],
        moved: &[Design],
        threads: usize,
    ) -> LinearisedSources {
        let groups: Vec<Vec<usize>> = match self.models.shared() {
            true => vec![(0..sources.len()).collect()],
            false => {
                let (patches, balloon) =
                    (0..sources.len()).partition(|&k| matches!(sources[k], Source::Patch { .. }));
                vec![patches, balloon]
            }
        };
        let mut found = LinearisedSources {
            changes: sources.iter().map(|_| None).collect(),
            starts: sources.iter().map(|_| None).collect(),
            fields: sources.iter().map(|_| None).collect(),
            runs: 0,
        };
        for group in groups.into_iter().filter(|g| !g.is_empty()) {
            let (nominal, samples) = self.of(sources[group[0]]);
            let designs: Vec<Design> = group.iter().map(|&k| moved[k].clone()).collect();
            let Some(states) = linearised_changes(nominal, &designs, samples, threads) else {
                continue;
            };
            found.runs += 1;
            for (k, (change, start)) in group.into_iter().zip(states) {
                let Some((change, field)) = change else {
                    continue;
                };
                found.changes[k] = Some((change, Estimate::Linearised));
                found.fields[k] = Some(field);
                found.starts[k] = start.filter(|_| starts_linearised(sources[k]));
            }
        }
        found
    }
}

/// A linearised change and its move at each sample.
type Linearised = Option<(Change, Vec<Point>)>;

/// Each moved design's linearised change and state (none where it has
/// none: the change leaving a material's domain); none at all where the
/// linearisation did not run (the nominal state unstable).
fn linearised_changes(
    nominal: &Nominal,
    moved: &[Design],
    samples: &Curve,
    threads: usize,
) -> Option<Vec<(Linearised, Option<Vec<Point>>)>> {
    let (design, simulation) = (nominal.design, nominal.simulation);
    let states = linearised_states(
        design,
        simulation,
        nominal.options,
        moved,
        threads,
        nominal.patterns,
    );
    let states = states.filter(|_| !moved.is_empty())?;
    let changes = states.into_iter().map(|state| {
        let Some(state) = state else {
            return (None, None);
        };
        let offsets = offsets_of(&state.centreline, &simulation.centreline, samples).ok();
        let found = offsets.map(|o| (Change::one_way(&o), o.residuals));
        (found, Some(state.positions))
    });
    Some(changes.collect())
}
