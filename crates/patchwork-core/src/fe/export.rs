//! Export of the deformed surface: legacy VTK (ParaView) and ASCII PLY.

use std::fmt::Write;

use super::Simulation;

/// Legacy-VTK polydata: deformed node positions, triangles, and per-cell
/// `patch_share` (fraction of each element covered by patches).
pub fn to_vtk(sim: &Simulation, patch_share: &[f64]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# vtk DataFile Version 3.0\nPatchwork inflated balloon (mm)\nASCII\nDATASET POLYDATA"
    );
    let _ = writeln!(out, "POINTS {} double", sim.positions.len());
    for p in &sim.positions {
        let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
    }
    let n = sim.mesh.triangles.len();
    let _ = writeln!(out, "POLYGONS {n} {}", 4 * n);
    for t in &sim.mesh.triangles {
        let _ = writeln!(out, "3 {} {} {}", t[0], t[1], t[2]);
    }
    let _ = writeln!(
        out,
        "CELL_DATA {n}\nSCALARS patch_share double 1\nLOOKUP_TABLE default"
    );
    for share in patch_share.iter().take(n) {
        let _ = writeln!(out, "{share}");
    }
    out
}

/// ASCII PLY of the deformed surface.
pub fn to_ply(sim: &Simulation) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "ply\nformat ascii 1.0\ncomment Patchwork inflated balloon, mm"
    );
    let _ = writeln!(
        out,
        "element vertex {}\nproperty double x\nproperty double y\nproperty double z",
        sim.positions.len()
    );
    let _ = writeln!(
        out,
        "element face {}\nproperty list uchar int vertex_indices\nend_header",
        sim.mesh.triangles.len()
    );
    for p in &sim.positions {
        let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
    }
    for t in &sim.mesh.triangles {
        let _ = writeln!(out, "3 {} {} {}", t[0], t[1], t[2]);
    }
    out
}
