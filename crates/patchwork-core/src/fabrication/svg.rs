//! SVG output: the placement template at 1:1 (mm units, prints to scale) and
//! the κ, τ profiles, target against achieved.

use std::fmt::Write;

use super::geometry::sheet_pieces;
use crate::chart::{self, Axis, COLOURS, Mark, Panel, Series};
use crate::design::Design;
use crate::inverse::Profiles;

/// Margins of the template sheet round the unrolled balloon, mm.
const LEFT_MM: f64 = 24.0;
const TOP_MM: f64 = 21.0;
const BOTTOM_MM: f64 = 22.0;
const RIGHT_MM: f64 = 20.0;
/// Text height on the template, mm.
const TEXT_MM: f64 = 2.2;

/// `template.svg`: as `template.dxf`, in an SVG whose user unit is 1 mm
/// (prints to scale at 100 %): the unrolled balloon (X round it from the
/// seam, Y along it from the clamped base) with every patch outlined and
/// numbered as in `design.csv`, a Y scale every 10 mm, the circumference and
/// length dimensioned, and a 10 mm bar to check the print scale.
pub fn template_svg(design: &Design, careful: &[usize]) -> String {
    let (c, l) = (design.balloon.circumference(), design.balloon.length_mm);
    let (w, h) = (LEFT_MM + c + RIGHT_MM, TOP_MM + l + BOTTOM_MM);
    let mut sheet = Sheet {
        svg: format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.2}mm" height="{h:.2}mm" viewBox="0 0 {w:.2} {h:.2}" font-family="sans-serif" font-size="{TEXT_MM}"><rect width="100%" height="100%" fill="white"/>"#
        ),
        length_mm: l,
    };
    let (x0, y0) = sheet.at((0.0, l));
    let _ = write!(
        sheet.svg,
        r#"<rect x="{x0}" y="{y0}" width="{c:.3}" height="{l:.3}" fill="none" stroke="black" stroke-width="0.2"/>"#
    );
    for k in 0..=(l / 10.0).floor() as usize {
        let y = 10.0 * k as f64;
        let tick = if k % 5 == 0 { 4.0 } else { 2.0 };
        sheet.line((-tick, y), (0.0, y));
    }
    for k in (0..=(l / 50.0).floor() as usize).map(|k| 50.0 * k as f64) {
        sheet.text((-5.0, k - 0.7), "end", &format!("{k:.0}"));
    }
    let (above, right) = (l + 6.0, c + 6.0);
    sheet.dimension((0.0, above), (c, above));
    sheet.text(
        (c / 2.0, above + 1.0),
        "middle",
        &format!("{c:.2} mm round"),
    );
    sheet.dimension((right, 0.0), (right, l));
    let (lx, ly) = sheet.at((right + 2.5, l / 2.0));
    let _ = write!(
        sheet.svg,
        r#"<text transform="translate({lx:.2} {ly:.2}) rotate(90)" text-anchor="middle">{l:.1} mm to cut</text>"#
    );
    sheet.dimension((0.0, -14.0), (10.0, -14.0));
    sheet.text((12.0, -14.8), "start", "10 mm at 100 %");
    sheet.text((-LEFT_MM + 2.0, l + 10.5), "start", "Y: mm from the base");
    sheet.text(
        (-LEFT_MM + 2.0, l + 13.5),
        "start",
        "X: round from the seam",
    );
    sheet.text((0.0, -5.0), "start", "BASE (clamped end)");
    for (i, p) in design.patches.iter().enumerate() {
        for piece in sheet_pieces(p, c, l) {
            sheet.polygon(&piece, "red");
        }
        let label = (p.x_mm.rem_euclid(c) + 0.5, p.y_mm);
        let care = if careful.contains(&(i + 1)) { " !" } else { "" };
        sheet.text(label, "start", &format!("P{}{care}", i + 1));
    }
    if !careful.is_empty() {
        let names: Vec<String> = careful.iter().map(|p| format!("P{p}")).collect();
        sheet.text(
            (-LEFT_MM + 2.0, l + 16.5),
            "start",
            &format!(
                "! {}: place with most care (the design's spread is most sensitive to them)",
                names.join(", ")
            ),
        );
    }
    sheet.svg.push_str("</svg>\n");
    sheet.svg
}

/// SVG elements drawn in sheet coordinates (mm; X right, Y up from the
/// base), which SVG's y-down frame flips.
struct Sheet {
    svg: String,
    length_mm: f64,
}

impl Sheet {
    fn at(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (LEFT_MM + x, TOP_MM + self.length_mm - y)
    }

    fn line(&mut self, a: (f64, f64), b: (f64, f64)) {
        let ((x1, y1), (x2, y2)) = (self.at(a), self.at(b));
        let _ = write!(
            self.svg,
            r#"<line x1="{x1:.3}" y1="{y1:.3}" x2="{x2:.3}" y2="{y2:.3}" stroke="black" stroke-width="0.2"/>"#
        );
    }

    /// A line from `a` to `b` with a 4 mm mark across each end.
    fn dimension(&mut self, a: (f64, f64), b: (f64, f64)) {
        self.line(a, b);
        let length = (b.0 - a.0).hypot(b.1 - a.1);
        let (nx, ny) = (-(b.1 - a.1) / length, (b.0 - a.0) / length);
        for (x, y) in [a, b] {
            self.line((x - 2.0 * nx, y - 2.0 * ny), (x + 2.0 * nx, y + 2.0 * ny));
        }
    }

    fn polygon(&mut self, corners: &[[f64; 2]], colour: &str) {
        let points: Vec<String> = corners
            .iter()
            .map(|q| {
                let (x, y) = self.at((q[0], q[1]));
                format!("{x:.3},{y:.3}")
            })
            .collect();
        let _ = write!(
            self.svg,
            r#"<polygon points="{}" fill="none" stroke="{colour}" stroke-width="0.2"/>"#,
            points.join(" ")
        );
    }

    fn text(&mut self, at: (f64, f64), anchor: &str, words: &str) {
        let (x, y) = self.at(at);
        let _ = write!(
            self.svg,
            r#"<text x="{x:.2}" y="{y:.2}" text-anchor="{anchor}">{words}</text>"#
        );
    }
}

/// The least span of a profile plot's y axis, 1/mm.
const FLOOR: f64 = 0.01;

/// `profiles.svg`: curvature κ(s) and torsion τ(s) along the curve, the
/// target against the verified design, on the same fractions of length
/// (plotted against the target's length, in mm).
pub fn profiles_svg(profiles: &Profiles, target_length_mm: f64) -> String {
    let along = |values: &[f64]| -> Vec<(f64, f64)> {
        let last = values.len().max(2) - 1;
        values
            .iter()
            .enumerate()
            .map(|(i, v)| (target_length_mm * i as f64 / last as f64, *v))
            .collect()
    };
    let x_axis = || Axis::linear("position along the curve, s (mm)", [0.0, target_length_mm]);
    // Each y axis spans at least `FLOOR`, so that the round-off torsion of
    // a planar design (1e-9/mm) draws as the flat line it is.
    let panel =
        |title: &str, label: &str, target: &[f64], achieved: &[f64], floor: [f64; 2]| Panel {
            title: title.into(),
            x: x_axis(),
            y: Axis::linear(label, target.iter().chain(achieved).copied().chain(floor)),
            series: vec![
                Series {
                    name: Some("target".into()),
                    colour: "#555555",
                    mark: Mark::Dashed,
                    points: along(target),
                },
                Series {
                    name: Some("design, inflated".into()),
                    colour: COLOURS[0],
                    mark: Mark::Line,
                    points: along(achieved),
                },
            ],
        };
    chart::svg(&[
        panel(
            "Curvature",
            "curvature κ (1/mm)",
            &profiles.target_curvature_per_mm,
            &profiles.curvature_per_mm,
            [0.0, FLOOR],
        ),
        panel(
            "Torsion",
            "torsion τ (1/mm)",
            &profiles.target_torsion_per_mm,
            &profiles.torsion_per_mm,
            [-FLOOR / 2.0, FLOOR / 2.0],
        ),
    ])
}
