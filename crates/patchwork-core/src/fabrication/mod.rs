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

/// One output file of a design run.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputFile {
    pub name: &'static str,
    pub content_type: &'static str,
    pub body: Vec<u8>,
}

/// design.json: the design report, pretty-printed, with a final newline.
pub fn design_json(report: &crate::inverse::DesignReport) -> Result<String, String> {
    let mut json = serde_json::to_string_pretty(report).map_err(|e| e.to_string())?;
    json.push('\n');
    Ok(json)
}

/// Every file of a design run, as the CLI writes them to `--out` and the API
/// serves them: design.json, design.csv, patches.dxf, template.dxf,
/// template.svg, profiles.svg.
pub fn design_files(report: &crate::inverse::DesignReport) -> Result<Vec<OutputFile>, String> {
    let file = |name, content_type, body| OutputFile {
        name,
        content_type,
        body,
    };
    let json = design_json(report)?;
    let profiles = profiles_svg(&report.profiles, report.target_length_mm);
    Ok(vec![
        file("design.json", "application/json", json.into_bytes()),
        file(
            "design.csv",
            "text/csv; charset=utf-8",
            patch_table_csv(&report.design).into_bytes(),
        ),
        file(
            "patches.dxf",
            "application/dxf",
            cut_file_dxf(&report.design),
        ),
        file(
            "template.dxf",
            "application/dxf",
            template_dxf(&report.design),
        ),
        file(
            "template.svg",
            "image/svg+xml",
            template_svg(
                &report.design,
                &report
                    .spread
                    .as_ref()
                    .map_or(Vec::new(), |s| s.careful_patches(3)),
            )
            .into_bytes(),
        ),
        file("profiles.svg", "image/svg+xml", profiles.into_bytes()),
    ])
}
