//! One forward solve of a design, from the closed-form bare tube to the patched
//! equilibrium.

use std::time::{Duration, Instant};

use super::carry::carried_state;
use super::centreline::{Ring, rings};
use super::continuation::{continuation, initial_state};
use super::kinematic::{calibrated_scale, kinematic_state};
use super::mesh::{MeshSpec, TubeMesh};
use super::model::Model;
use super::newton::{
    COLD_SHIFT_FLOOR, NewtonOptions, PatternCache, SolveError, SolveStats, Solver,
};
use super::section::CutElements;
use super::tube_theory::{MAX_HOOP, TubeState, inflate_tube};
use crate::curve::{AnalysisOptions, Curve, Point, analyse};
use crate::design::{Design, DesignError};

/// Cold solves on fine meshes start from coarser models: each mesh from the
/// converged state of one with elements twice as large (3 × as large along
/// bare stretches), the coarsest at most this size (mm: 10 sides round the
/// reference balloon). The carried state is a few Newton iterations from the
/// finer solution, where the kinematic start can be far: on the paper's
/// compressible balloon the spring's KSA seed on the verification mesh
/// takes 141 iterations from it (47 s) (`cargo run --release -p
/// patchwork-core --example coarse_start`).
const COARSEST_START_MM: f64 = 2.0;

/// Fidelity and limits of a forward solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulateOptions {
    pub mesh: MeshSpec,
    /// Cross-section rings for the centreline (the authors used 72).
    pub rings: usize,
    pub newton: NewtonOptions,
    /// Smallest continuation step in patch stiffness before giving up.
    pub min_continuation_step: f64,
    /// How elements cut by a patch outline are modelled.
    pub cut_elements: CutElements,
    /// Wall time of the whole simulation (its starts and every continuation
    /// step together), besides each solve's `newton.time_limit`; `None`:
    /// only the per-solve limit. A caller answering a person sets it.
    pub time_limit: Option<Duration>,
    /// Whether a cold solve on a fine mesh starts from the converged state
    /// of coarser models (elements twice as large, down to 2 mm) rather
    /// than the kinematic estimate alone.
    pub coarse_start: bool,
    /// Threads one solve's assemblies split the elements over (at least 1).
    /// Every count gives the same result to the last bit; more than one
    /// only shortens a solve that runs while cores are idle, not solves
    /// already run side by side.
    pub threads: usize,
}

impl Default for SimulateOptions {
    fn default() -> Self {
        SimulateOptions {
            mesh: MeshSpec::uniform(2.0),
            rings: 72,
            newton: NewtonOptions::default(),
            min_continuation_step: 1.0 / 64.0,
            cut_elements: CutElements::default(),
            time_limit: None,
            coarse_start: true,
            threads: 1,
        }
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulateError {
    // The inner errors are part of the message, not a `source`, so that a
    // cause chain printed by the caller does not repeat them.
    #[error("invalid design: {0}")]
    Design(DesignError),
    #[error("invalid options: {0}")]
    Options(String),
    #[error(
        "the bare tube has no stable inflated state at {pressure_kpa} kPa with this material: no rising branch of its inflation curve reaches that pressure below a hoop stretch of 12, past any latex balloon's burst"
    )]
    NoTubeState { pressure_kpa: f64 },
    #[error(
        "the balloon bursts: its widest ring inflates to {hoop:.1} times its radius, past a hoop stretch of {MAX_HOOP} (past any latex balloon's burst); a lower pressure or stiffer patches"
    )]
    Burst { hoop: f64 },
    #[error("forward solve failed at patch stiffness {stiffness:.3}: {reason}")]
    Solve { stiffness: f64, reason: SolveError },
    #[error("the inflated centreline is degenerate: {0}")]
    Centreline(String),
}

impl From<DesignError> for SimulateError {
    fn from(e: DesignError) -> Self {
        SimulateError::Design(e)
    }
}

/// The inflated state and what a user reads from it.
#[derive(Debug, Clone)]
pub struct Simulation {
    pub positions: Vec<Point>,
    pub mesh: TubeMesh,
    pub rings: Vec<Ring>,
    pub centreline: Curve,
    pub curvature: Vec<f64>,
    pub torsion: Vec<f64>,
    pub inflated_length_mm: f64,
    pub hoop_stretch_mid: f64,
    pub axial_stretch_mid: f64,
    /// The closed-form bare-tube state used as the start.
    pub tube_state: TubeState,
    /// Solves that reached the design: 1 when Newton converged from a
    /// start (a neighbour's state, the coarse model's or the kinematic
    /// estimate), more when continuation in patch stiffness took over.
    pub continuation_steps: usize,
    pub volume_mm3: f64,
    pub elapsed: Duration,
    /// Newton iterations, final residual, stability, and times of the solves
    /// that produced this state (continuation steps included; a failed warm or
    /// kinematic attempt before them is not counted).
    pub stats: SolveStats,
    /// Fraction of each element covered by patches (for export and plots).
    pub patch_share: Vec<f64>,
}

impl Simulation {
    /// Each ring's radius (mm), base to tip.
    pub fn radii(&self) -> Vec<f64> {
        self.rings.iter().map(|r| r.radius).collect()
    }

    /// How far the cap's pole (the mesh's last node) lies past the last
    /// ring's centre along the centreline's end (mm): the inflated cap's
    /// height, which a scan's centreline is cut by.
    pub fn cap_height(&self) -> Option<f64> {
        let points = self.centreline.points();
        let (last, before) = (points.last()?, points.get(points.len().checked_sub(2)?)?);
        let pole = self.positions.last()?;
        Some((pole - last).dot(&(last - before).normalize()))
    }

    /// How the solve reached the design, in words: "no continuation" (Newton
    /// converged from a start), or "N continuation steps" in patch stiffness.
    pub fn route(&self) -> String {
        match self.continuation_steps {
            0 | 1 => "no continuation".to_string(),
            n => format!("{n} continuation steps"),
        }
    }
}

/// The most mesh nodes one solve may use: a solve takes about 8 KB of
/// memory per node (docs/studies.md, "Forward solve"), so this is about
/// 3 GB — a 5 m balloon on a uniform 0.5 mm mesh (the 2 m helix of the
/// stress suite has 0.16 million).
pub const MAX_NODES: f64 = 4e5;

/// Simulates `design` under `options`, starting from the closed-form bare tube.
pub fn simulate(design: &Design, options: &SimulateOptions) -> Result<Simulation, SimulateError> {
    simulate_from(design, options, None)
}

/// Simulates `design`, warm-started from `previous` — the converged state of a
/// nearby design on the same mesh (same balloon and element size), as in a
/// design loop. The state is carried across a graded mesh whose fine zones
/// moved; the cold start is the fallback if the meshes are incompatible or the
/// warm solve fails.
pub fn simulate_from(
    design: &Design,
    options: &SimulateOptions,
    previous: Option<&Simulation>,
) -> Result<Simulation, SimulateError> {
    simulate_with(design, options, previous, &PatternCache::default())
}

/// [`simulate_from`], the mesh's tangent pattern taken from `patterns` (or
/// built and stored there): a sequence of solves on meshes of one topology
/// pays the pattern's setup once.
pub fn simulate_with(
    design: &Design,
    options: &SimulateOptions,
    previous: Option<&Simulation>,
    patterns: &PatternCache,
) -> Result<Simulation, SimulateError> {
    let started = Instant::now();
    check(design, options)?;
    let b = &design.balloon;
    let tube_state = inflate_tube(&b.material, design.pressure_mpa(), b.radius_mm, b.wall_mm)
        .ok_or(SimulateError::NoTubeState {
            pressure_kpa: design.pressure_kpa,
        })?;
    let mesh = TubeMesh::for_design(design, options.mesh);
    let model = Model::new(design, mesh, options.cut_elements).with_threads(options.threads);
    let setup = Instant::now();
    let solver = Solver::new(&model, patterns).map_err(|reason| SimulateError::Solve {
        stiffness: 0.0,
        reason,
    })?;
    let setup_time = setup.elapsed();
    let mut stats = SolveStats {
        setup_time,
        ..SolveStats::default()
    };
    // A neighbour's converged state (if given) or else a coarse model's,
    // then the kinematic (bent) start, each at full patch stiffness; if
    // Newton fails from both, the straight tube and continuation. The
    // stats count the coarse solve's iterations and times.
    let coarse = match previous {
        None => coarse_solution(design, options, patterns),
        Some(_) => None,
    };
    if let Some(c) = &coarse {
        stats.accumulate(&c.stats);
    }
    let warm = previous
        .or(coarse.as_ref())
        .and_then(|p| carried_state(&p.mesh, &p.positions, &model.mesh));
    let kinematic = std::iter::once_with(|| {
        (!design.patches.is_empty()).then(|| {
            kinematic_state(
                design,
                &model.mesh,
                tube_state,
                calibrated_scale(&design.balloon.material),
            )
        })
    })
    .flatten();
    let left = || time_left(options, started);
    // A cold solve's starts cross a long tube's soft modes with a lower
    // shift floor; continuation, and warm starts, keep the options' own.
    let start = || NewtonOptions {
        shift_floor: match previous {
            None => options.newton.shift_floor.min(COLD_SHIFT_FLOOR),
            Some(_) => options.newton.shift_floor,
        },
        ..left()
    };
    let solved = warm.into_iter().chain(kinematic).find_map(|mut x| {
        let s = solver
            .solve(&model, &model.sections, &mut x, &start())
            .ok()?;
        Some((x, s))
    });
    if let Some((x, s)) = solved {
        stats.accumulate(&s);
        return finish(design, options, model, x, tube_state, stats, 1, started);
    }
    let mut x = initial_state(&model.mesh, tube_state);
    let min_step = options.min_continuation_step;
    let steps = continuation(design, min_step, &model, &solver, &mut x, &left, &mut stats)
        .map_err(|(stiffness, reason)| SimulateError::Solve { stiffness, reason })?;
    finish(design, options, model, x, tube_state, stats, steps, started)
}

/// The options of one solve of a simulation started at `started`: its own
/// time limit, or what is left of the whole simulation's when that is less.
fn time_left(options: &SimulateOptions, started: Instant) -> NewtonOptions {
    NewtonOptions {
        time_limit: options
            .time_limit
            .map_or(options.newton.time_limit, |total| {
                total
                    .saturating_sub(started.elapsed())
                    .min(options.newton.time_limit)
            }),
        ..options.newton
    }
}

/// The design's and the options' checks before any solve.
fn check(design: &Design, options: &SimulateOptions) -> Result<(), SimulateError> {
    design.validate()?;
    options
        .mesh
        .validate(design.balloon.radius_mm)
        .map_err(SimulateError::Options)?;
    if !(2..=10_000).contains(&options.rings) {
        return Err(SimulateError::Options(format!(
            "rings = {} must be between 2 and 10000",
            options.rings
        )));
    }
    let nodes = options
        .mesh
        .most_nodes(design.balloon.radius_mm, design.balloon.length_mm);
    if nodes > MAX_NODES {
        return Err(SimulateError::Options(format!(
            "a {:.0} mm balloon of radius {} mm on {} elements needs up to {nodes:.0} nodes, \
             more than the {MAX_NODES:.0} one solve may use: a shorter or thinner balloon, \
             or a coarser mesh",
            design.balloon.length_mm, design.balloon.radius_mm, options.mesh
        )));
    }
    Ok(())
}

/// The converged state of the next coarser model (see
/// [`COARSEST_START_MM`]), where `options` ask for it and the design has
/// patches; none otherwise, or if that solve fails (the fine solve then
/// starts from the kinematic estimate).
fn coarse_solution(
    design: &Design,
    options: &SimulateOptions,
    patterns: &PatternCache,
) -> Option<Simulation> {
    let element_mm = 2.0 * options.mesh.element_mm;
    if !options.coarse_start || design.patches.is_empty() || element_mm > COARSEST_START_MM {
        return None;
    }
    let coarse = SimulateOptions {
        mesh: MeshSpec::graded(element_mm, 3.0 * element_mm),
        ..*options
    };
    simulate_with(design, &coarse, None, patterns).ok()
}

#[allow(clippy::too_many_arguments)]
fn finish(
    design: &Design,
    options: &SimulateOptions,
    model: Model,
    x: Vec<Point>,
    tube_state: TubeState,
    stats: SolveStats,
    steps: usize,
    started: Instant,
) -> Result<Simulation, SimulateError> {
    let rings = rings(&model.mesh, &x, options.rings);
    // Newton can settle where the wall has thinned past any latex's burst
    // (a nearly bare tube near its limit pressure on a coarse mesh: hoop
    // stretch 400): that is no answer to give.
    let widest = rings.iter().map(|r| r.radius).fold(0.0, f64::max) / design.balloon.radius_mm;
    if widest > MAX_HOOP {
        return Err(SimulateError::Burst { hoop: widest });
    }
    let centres: Vec<Point> = rings.iter().map(|r| r.centre).collect();
    let centreline =
        Curve::from_points(centres).map_err(|e| SimulateError::Centreline(e.to_string()))?;
    let analysis = analyse(&centreline, &AnalysisOptions::default());
    let mid = rings.len() / 2;
    let hoop_stretch_mid = rings[mid].radius / design.balloon.radius_mm;
    let dy = rings[mid + 1].y - rings[mid - 1].y;
    let axial_stretch_mid = centreline.arc_length()[mid + 1] - centreline.arc_length()[mid - 1];
    let volume_mm3 = model.volume(&x);
    let patch_share = model.patch_share();
    let Model { mesh, .. } = model;
    Ok(Simulation {
        inflated_length_mm: centreline.length(),
        hoop_stretch_mid,
        axial_stretch_mid: axial_stretch_mid / dy,
        curvature: analysis.curvature,
        torsion: analysis.torsion,
        centreline,
        rings,
        positions: x,
        mesh,
        tube_state,
        continuation_steps: steps,
        volume_mm3,
        elapsed: started.elapsed(),
        stats,
        patch_share,
    })
}
