//! What the lab takes to the laser cutter and the gluing bench: the patch cut
//! file, the placement template (the unrolled balloon with every patch at its
//! X, Y, Θ), the profile plot and the patch table. Everything in millimetres;
//! functions return file contents and do no I/O.

mod dxf_out;
mod geometry;
mod svg;

pub use dxf_out::{cut_file_dxf, template_dxf};
pub use geometry::{CutLayout, cut_layout, patch_outline};
pub use svg::{profiles_svg, template_svg};

use crate::design::Design;

/// The patch table as CSV, one row per patch, units in the header.
pub fn patch_table_csv(design: &Design) -> String {
    let mut out = String::from("patch,x_mm,y_mm,h_mm,w_mm,theta_deg\n");
    for (i, p) in design.patches.iter().enumerate() {
        out.push_str(&format!(
            "P{},{:.3},{:.3},{:.3},{:.3},{:.2}\n",
            i + 1,
            p.x_mm,
            p.y_mm,
            p.h_mm,
            p.w_mm,
            p.theta_deg
        ));
    }
    out
}
