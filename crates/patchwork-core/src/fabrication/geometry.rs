use crate::design::Patch;

/// Gap between cut outlines and around the sheet (mm).
const GAP_MM: f64 = 4.0;
/// Room under each outline for its label (mm).
const LABEL_MM: f64 = 5.0;

/// Corners of a patch on the unrolled balloon (X, Y), counter-clockwise; its
/// long axis makes angle Θ with the balloon axis (Y).
pub fn patch_outline(p: &Patch) -> [[f64; 2]; 4] {
    let (s, c) = p.theta().sin_cos();
    let u = [s, c];
    let v = [c, -s];
    let (hh, hw) = (p.h_mm / 2.0, p.w_mm / 2.0);
    let corner = |a: f64, b: f64| {
        [
            p.x_mm + a * hh * u[0] + b * hw * v[0],
            p.y_mm + a * hh * u[1] + b * hw * v[1],
        ]
    };
    [
        corner(-1.0, -1.0),
        corner(-1.0, 1.0),
        corner(1.0, 1.0),
        corner(1.0, -1.0),
    ]
}

/// Where each patch outline goes on the cutting sheet: upright H × W rectangles
/// on shelves no wider than `sheet_width`, never overlapping.
#[derive(Debug, Clone, PartialEq)]
pub struct CutLayout {
    /// Lower-left corner of each patch's rectangle (mm).
    pub origins: Vec<[f64; 2]>,
    pub width: f64,
    pub height: f64,
}

pub fn cut_layout(patches: &[Patch], sheet_width: f64) -> CutLayout {
    let mut origins = Vec::with_capacity(patches.len());
    let (mut x, mut y, mut shelf, mut width) = (GAP_MM, GAP_MM + LABEL_MM, 0.0_f64, 0.0_f64);
    for p in patches {
        if x > GAP_MM && x + p.w_mm + GAP_MM > sheet_width {
            x = GAP_MM;
            y += shelf + GAP_MM + LABEL_MM;
            shelf = 0.0;
        }
        origins.push([x, y]);
        x += p.w_mm.max(14.0) + GAP_MM; // labels are wider than thin patches
        shelf = shelf.max(p.h_mm);
        width = width.max(x);
    }
    CutLayout {
        origins,
        width,
        height: y + shelf + GAP_MM,
    }
}
