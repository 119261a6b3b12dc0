use crate::design::Patch;
use crate::fe::overlap::{area, clip};

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

/// The parts of a patch's outline that lie on the unrolled balloon
/// `[0, C] × [0, L]`: the outline and its images shifted by ±C (a patch across
/// the seam shows as two pieces, one at each edge), each clipped to the sheet
/// (Sutherland–Hodgman against the four edges; the outline is convex, so each
/// piece is one convex polygon). Pieces of no area are dropped.
pub fn sheet_pieces(p: &Patch, circumference: f64, length: f64) -> Vec<Vec<[f64; 2]>> {
    let outline = patch_outline(p);
    [-circumference, 0.0, circumference]
        .into_iter()
        .filter_map(|shift| {
            let mut piece: Vec<[f64; 2]> = outline.iter().map(|q| [q[0] + shift, q[1]]).collect();
            // The sheet as four half-planes n·p ≤ offset.
            let edges = [
                ([-1.0, 0.0], 0.0),
                ([1.0, 0.0], circumference),
                ([0.0, -1.0], 0.0),
                ([0.0, 1.0], length),
            ];
            for (normal, offset) in edges {
                piece = clip(&piece, normal, offset);
            }
            (area(&piece) > 1e-9).then_some(piece)
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(x_mm: f64, y_mm: f64, theta_deg: f64) -> Patch {
        Patch {
            x_mm,
            y_mm,
            h_mm: 20.0,
            w_mm: 3.0,
            theta_deg,
        }
    }

    fn within(piece: &[[f64; 2]], c: f64, l: f64) -> bool {
        piece
            .iter()
            .all(|q| (-1e-9..=c + 1e-9).contains(&q[0]) && (-1e-9..=l + 1e-9).contains(&q[1]))
    }

    #[test]
    fn a_patch_inside_the_sheet_is_one_whole_piece() {
        let pieces = sheet_pieces(&patch(10.0, 50.0, 20.0), 20.0, 100.0);
        assert_eq!(pieces.len(), 1);
        assert!((area(&pieces[0]) - 60.0).abs() < 1e-9);
    }

    #[test]
    fn a_patch_across_the_seam_splits_into_two_pieces_of_its_area() {
        let (c, l) = (20.0, 100.0);
        let pieces = sheet_pieces(&patch(0.5, 50.0, 30.0), c, l);
        assert_eq!(pieces.len(), 2);
        assert!(pieces.iter().all(|p| within(p, c, l)));
        let total: f64 = pieces.iter().map(|p| area(p)).sum();
        assert!((total - 60.0).abs() < 1e-9, "{total}");
    }

    #[test]
    fn a_patch_off_the_end_is_clipped_to_the_balloon() {
        let pieces = sheet_pieces(&patch(10.0, 95.0, 0.0), 20.0, 100.0);
        assert_eq!(pieces.len(), 1);
        assert!(within(&pieces[0], 20.0, 100.0));
        assert!((area(&pieces[0]) - 15.0 * 3.0).abs() < 1e-9);
    }
}
