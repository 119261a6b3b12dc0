//! `patchwork simulate DESIGN.json [--json] [--mesh-mm M] [--straight-mm S] [--rings 72]
//! [--cut-elements laminate|average] [--out DIR]`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use patchwork_core::design::Design;
use patchwork_core::fe::export::{to_ply, to_vtk};
use patchwork_core::fe::mesh::MeshSpec;
use patchwork_core::fe::section::CutElements;
use patchwork_core::fe::{SimulateOptions, Simulation, simulate};

use super::design_summary::contact_line;
use super::output::{emit, emit_json, points_csv};
use crate::reports::SimulateReport;

#[derive(Args)]
#[command(allow_negative_numbers = true)]
pub struct SimulateArgs {
    /// Design JSON: {"balloon", "patch", "pressure_kpa", "patches": [...]}
    /// (all but `patches` default to the reference scene), the design.json
    /// that `design` writes (its `design` is simulated), or what `ksa --json`
    /// writes (its patches on its balloon); `-` reads stdin.
    design: String,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// Element size (mm) [default: 0.5 under patches and at the ends, 4 along
    /// bare stretches: the model designs are verified on, within 0.2 % of
    /// membrane theory]. Given alone, the mesh is uniform: on the bare tube
    /// 1 mm is 0.2 % off theory in hoop stretch and 2 mm 0.7 %, but patched
    /// centrelines converge more slowly: a 2 mm mesh lies up to 1.7 % of the
    /// length from a fine solution and moves a patch's bend by up to 10 %
    /// with its position on the mesh.
    #[arg(long)]
    mesh_mm: Option<f64>,
    /// Axial element size along bare stretches (mm), with `--mesh-mm` only
    /// where patches are and at the ends (local refinement). For a quick
    /// look, `--mesh-mm 1.25 --straight-mm 6`: on three designs (the Hilbert
    /// seed, the helix and grasp presets' draft designs) within 0.2–0.6 % of
    /// the length of a converged solution, in a fourteenth to a half of the
    /// default mesh's time (docs/studies.md, "Loading the facets").
    #[arg(long)]
    straight_mm: Option<f64>,
    /// Cross-section rings for the centreline.
    #[arg(long, default_value_t = 72)]
    rings: usize,
    /// How elements that a patch outline cuts are modelled: `laminate` (a
    /// rank-one laminate along the outline, converges faster with the mesh)
    /// or `average` (area-weighted average of the covered and bare energies;
    /// stiffer on coarse meshes). See docs/studies.md, "Cut elements".
    #[arg(long, default_value = "laminate")]
    cut_elements: CutElements,
    /// Threads the solve assembles on (the same result for any count).
    #[arg(long, default_value_t = patchwork_core::available_cores())]
    threads: usize,
    /// Also write the inflated surface (balloon.vtk, balloon.ply) and the
    /// centreline (centreline.csv) here.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// A design, given as such, as the report `design` writes (an object with
/// a `design` and no `patches` of its own), or as `ksa --json` writes it
/// (its patches on the reference scene with KSA's balloon length and
/// radius).
pub(super) fn design_of(text: &str) -> Result<Design> {
    let value: serde_json::Value = serde_json::from_str(text)?;
    if let Some(design) = ksa_design(&value)? {
        return Ok(design);
    }
    let inner = value
        .get("design")
        .filter(|_| value.get("patches").is_none());
    Ok(serde_json::from_value(inner.unwrap_or(&value).clone())?)
}

/// The design a KSA report describes; none for anything else.
fn ksa_design(value: &serde_json::Value) -> Result<Option<Design>> {
    let field = |name: &str| value.get(name).and_then(serde_json::Value::as_f64);
    let (Some(length), Some(radius), Some(patches)) = (
        field("balloon_length_mm"),
        field("balloon_radius_mm"),
        value
            .get("patches")
            .filter(|_| value.get("clipped").is_some()),
    ) else {
        return Ok(None);
    };
    let mut design = Design::reference(serde_json::from_value(patches.clone())?);
    design.balloon.length_mm = length;
    design.balloon.radius_mm = radius;
    Ok(Some(design))
}

pub fn run(args: SimulateArgs) -> Result<()> {
    anyhow::ensure!(args.threads >= 1, "--threads: must be at least 1");
    let text = super::input::read_text_argument(&args.design)?;
    let design =
        design_of(&text).with_context(|| format!("{}: invalid design JSON", args.design))?;
    let options = SimulateOptions {
        mesh: MeshSpec::from_options(args.mesh_mm, args.straight_mm),
        rings: args.rings,
        cut_elements: args.cut_elements,
        threads: args.threads,
        ..SimulateOptions::default()
    };
    let sim = simulate(&design, &options)?;
    if let Some(dir) = &args.out {
        write_files(dir, &sim)?;
    }
    let report = SimulateReport::new(&sim);
    if args.json {
        return emit_json(&report);
    }
    let tip = sim.centreline.points().last().copied().unwrap_or_default();
    let text = format!(
        "converged   {} Newton iterations, {}, {:.0} ms ({})\n\
         inflated    length {:.1} mm, mid-tube hoop stretch {:.3}, axial stretch {:.3}\n\
         tip         ({:.1}, {:.1}, {:.1}) mm; max curvature {:.4} mm⁻¹\n",
        sim.stats.iterations,
        sim.route(),
        report.elapsed_ms,
        if sim.stats.stable {
            "stable"
        } else {
            "NOT stable: tangent indefinite at the solution"
        },
        sim.inflated_length_mm,
        sim.hoop_stretch_mid,
        sim.axial_stretch_mid,
        tip.x,
        tip.y,
        tip.z,
        sim.curvature.iter().copied().fold(0.0, f64::max),
    );
    let contacts: String = report.self_contact.iter().map(contact_line).collect();
    emit(&(text + &contacts))
}

fn write_files(dir: &PathBuf, sim: &Simulation) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let write = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    write("balloon.vtk", to_vtk(sim, &sim.patch_share))?;
    write("balloon.ply", to_ply(sim))?;
    write("centreline.csv", points_csv(sim.centreline.points()))
}
