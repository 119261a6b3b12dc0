//! The forward solve per mesh, for the benchmark report: the bare
//! reference tube against membrane theory (hoop and axial stretch in the
//! middle of the tube), the Hilbert seed's centreline (the six KSA patches
//! of the Hilbert curve: the reference scene, 20 kPa) against a converged
//! uniform 0.25 mm solution of it, and the wall time of one cold solve,
//! bare and with those patches (one thread; median of three); and one cold
//! solve of a long balloon, 1 m uninflated with 30 patches, on the default
//! mesh.

use std::time::Instant;

use anyhow::{Context, Result};
use patchwork_core::curve::{ReferenceCurve, shape_error};
use patchwork_core::design::Design;
use patchwork_core::design::scenes::long_balloon;
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::{SimulateOptions, Simulation, simulate};
use patchwork_core::ksa::{KsaParams, ksa};

/// Solves per case; the table shows the median time.
const REPEATS: usize = 3;

/// The element size of the converged solution the meshes are measured
/// against (its Hilbert seed solve takes about 12 s).
const CONVERGED_MM: f64 = 0.25;

/// Samples of the shape error against the converged solution.
const SAMPLES: usize = 200;

/// The accuracy the headline's quickest mesh must keep, % (against theory
/// on the bare tube, against the converged solution with patches).
const WITHIN_PERCENT: f64 = 1.0;

pub struct ForwardRow {
    pub mesh: &'static str,
    pub nodes: usize,
    /// FE against membrane theory, per cent.
    pub hoop_error_percent: f64,
    pub axial_error_percent: f64,
    /// The Hilbert seed's centreline from its converged (uniform 0.25 mm)
    /// solution: shape error, % of the length.
    pub converged_percent: f64,
    pub bare_ms: f64,
    pub hilbert_ms: f64,
}

/// The forward measurements: per mesh, and the long balloon.
pub struct Forward {
    pub meshes: Vec<ForwardRow>,
    pub long: LongRow,
}

/// One cold solve of [`long_balloon`] on the default mesh.
pub struct LongRow {
    pub inflated_mm: f64,
    pub iterations: usize,
    /// How the solve reached the design (`Simulation::route`).
    pub route: String,
    pub ms: f64,
}

/// The meshes a user meets: the default of `simulate` and of every
/// preset's verification, a quick graded one (`--mesh-mm 1.25
/// --straight-mm 6`), and the uniform meshes `--mesh-mm` gives.
fn meshes() -> [(&'static str, MeshSpec); 5] {
    [
        (
            "default: 0.5 mm at patches and ends, 4 mm between",
            MeshSpec::default_simulation(),
        ),
        (
            "quick: 1.25 mm at patches and ends, 6 mm between",
            MeshSpec::graded(1.25, 6.0),
        ),
        ("uniform 0.5 mm", MeshSpec::uniform(0.5)),
        ("uniform 1 mm", MeshSpec::uniform(1.0)),
        ("uniform 2 mm", MeshSpec::uniform(2.0)),
    ]
}

pub fn measure() -> Result<Forward> {
    // The default mesh, the table's first row.
    let default = on(meshes()[0].1);
    let rows = per_mesh()?;
    let (long, ms) =
        timed(&long_balloon(), &default, 1).context("the 1 m balloon with 30 patches")?;
    eprintln!("forward solve, 1 m balloon: done");
    let long = LongRow {
        inflated_mm: long.inflated_length_mm,
        iterations: long.stats.iterations,
        route: long.route(),
        ms,
    };
    Ok(Forward { meshes: rows, long })
}

/// One forward solve's options on `mesh` (`SimulateOptions::default()`'s
/// own mesh is the uniform 2 mm one), the rest the defaults: one thread.
fn on(mesh: MeshSpec) -> SimulateOptions {
    SimulateOptions {
        mesh,
        ..SimulateOptions::default()
    }
}

fn per_mesh() -> Result<Vec<ForwardRow>> {
    let bare = Design::reference(vec![]);
    let seed = ksa(&ReferenceCurve::Hilbert.curve(), &KsaParams::default())?;
    let hilbert = Design::reference(seed.patches);
    let converged = simulate(&hilbert, &on(MeshSpec::uniform(CONVERGED_MM)))
        .context("Hilbert scene, the converged solution")?
        .centreline;
    let mut rows = Vec::new();
    for (name, mesh) in meshes() {
        let options = on(mesh);
        let (tube, bare_ms) =
            timed(&bare, &options, REPEATS).with_context(|| format!("bare tube, {name}"))?;
        let (patched, hilbert_ms) =
            timed(&hilbert, &options, REPEATS).with_context(|| format!("Hilbert scene, {name}"))?;
        let converged_percent = shape_error(&patched.centreline, &converged, SAMPLES)
            .with_context(|| format!("Hilbert scene, {name}: no shape error"))?
            .percent_of_length;
        let theory = tube.tube_state;
        rows.push(ForwardRow {
            mesh: name,
            nodes: tube.mesh.nodes.len(),
            hoop_error_percent: 100.0 * (tube.hoop_stretch_mid / theory.hoop - 1.0),
            axial_error_percent: 100.0 * (tube.axial_stretch_mid / theory.axial - 1.0),
            converged_percent,
            bare_ms,
            hilbert_ms,
        });
        eprintln!("forward solve, {name}: done");
    }
    Ok(rows)
}

/// The last of `repeats` cold solves and their median wall time, ms.
fn timed(design: &Design, options: &SimulateOptions, repeats: usize) -> Result<(Simulation, f64)> {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..repeats {
        let started = Instant::now();
        last = Some(simulate(design, options)?);
        times.push(started.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let simulation = last.context("no solve ran")?;
    Ok((simulation, times[repeats / 2]))
}

/// The headline's row: the default mesh, and the quickest within
/// [`WITHIN_PERCENT`] of theory and of the converged solution.
pub fn headline(forward: &Forward) -> String {
    let Some(default) = forward.meshes.first() else {
        return String::new();
    };
    let quickest = (forward.meshes.iter())
        .filter(|r| r.within(WITHIN_PERCENT))
        .min_by(|a, b| a.hilbert_ms.total_cmp(&b.hilbert_ms))
        .map(|r| {
            format!(
                "; the quickest mesh within {WITHIN_PERCENT} % of theory and of a converged solution ({}) {:.0} ms with six patches, {:.2} % from it",
                r.mesh, r.hilbert_ms, r.converged_percent
            )
        })
        .unwrap_or_default();
    format!(
        "| one forward solve, default mesh | {:.0} ms bare, {:.0} ms with six patches ({:.2} % of the length from a converged solution), {:.1} s for a 1 m balloon with 30 patches; hoop stretch {:+.2} % and axial {:+.2} % against membrane theory{quickest} |\n",
        default.bare_ms,
        default.hilbert_ms,
        default.converged_percent,
        forward.long.ms / 1e3,
        default.hoop_error_percent,
        default.axial_error_percent
    )
}

impl ForwardRow {
    /// Whether the bare tube's stretches lie within `percent` of theory and
    /// the Hilbert seed's centreline within `percent` of the converged one.
    fn within(&self, percent: f64) -> bool {
        let off = [
            self.hoop_error_percent.abs(),
            self.axial_error_percent.abs(),
            self.converged_percent,
        ];
        off.iter().all(|e| *e <= percent)
    }
}

/// The report's section: a table and how to read it.
pub fn section(forward: &Forward) -> String {
    let rows = &forward.meshes;
    let mut out = String::from(
        "| mesh | nodes (bare tube) | hoop stretch vs theory | axial stretch vs theory | Hilbert scene from a converged solution | bare tube | Hilbert scene, 6 patches |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        out.push_str(&format!(
            "| {} | {} | {:+.2} % | {:+.2} % | {:.2} % | {:.0} ms | {:.0} ms |\n",
            r.mesh,
            r.nodes,
            r.hoop_error_percent,
            r.axial_error_percent,
            r.converged_percent,
            r.bare_ms,
            r.hilbert_ms
        ));
    }
    out.push_str(&format!(
        "\nThe reference balloon (292 mm, radius 3.18 mm, wall 0.183 mm) at 20 kPa: hoop and axial stretch in the middle of the bare tube \
         against the closed-form membrane solution; the Hilbert scene's \
         centreline against a uniform {CONVERGED_MM} mm solution of it (shape \
         error: RMS after the best rigid alignment, % of the length); and the \
         wall time of one cold solve (median of {REPEATS}, one thread). The section's flat facets are \
         loaded with P / cos(π/n), the round wall's load (docs/studies.md, \
         \"Loading the facets\"); what error remains grows with the element size. \
         The default mesh is fine where the shape is decided (under patches) and \
         coarse between; the quick mesh (`patchwork simulate --mesh-mm 1.25 \
         --straight-mm 6`) grades the same way with coarser elements, for a \
         quick look.\n"
    ));
    let long = &forward.long;
    out.push_str(&format!(
        "\nA long balloon, 1 m uninflated with 30 patches (`long_balloon` in \
         crates/patchwork-core/src/design/scenes.rs; docs/studies.md writes it as \
         design JSON), solved cold on the default mesh, one thread, once: {:.1} s, \
         {} Newton iterations, {}, {:.0} mm long inflated.\n",
        long.ms / 1e3,
        long.iterations,
        long.route,
        long.inflated_mm
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(hoop: f64, axial: f64, converged: f64) -> ForwardRow {
        ForwardRow {
            mesh: "m",
            nodes: 0,
            hoop_error_percent: hoop,
            axial_error_percent: axial,
            converged_percent: converged,
            bare_ms: 0.0,
            hilbert_ms: 0.0,
        }
    }

    /// A mesh counts as within a per cent only if the bare tube (either
    /// sign) and the patched centreline both are.
    #[test]
    fn within_needs_theory_and_the_converged_solution_alike() {
        assert!(row(0.3, -0.5, 0.54).within(1.0));
        assert!(!row(0.69, 0.95, 1.59).within(1.0));
        assert!(!row(-1.2, 0.1, 0.2).within(1.0));
    }
}
