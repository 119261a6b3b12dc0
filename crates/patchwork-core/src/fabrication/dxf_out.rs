//! DXF output (R2000, which keeps LWPOLYLINE; ezdxf audits these cleanly).

use dxf::entities::{Entity, EntityType, Line, LwPolyline, Text};
use dxf::enums::AcadVersion;
use dxf::{Drawing, LwPolylineVertex, Point};

use super::geometry::{cut_layout, sheet_pieces};
use crate::design::Design;

fn polygon(drawing: &mut Drawing, corners: &[[f64; 2]]) {
    let vertices = corners
        .iter()
        .map(|c| LwPolylineVertex {
            x: c[0],
            y: c[1],
            ..Default::default()
        })
        .collect();
    let mut poly = LwPolyline {
        vertices,
        ..Default::default()
    };
    poly.set_is_closed(true);
    drawing.add_entity(Entity::new(EntityType::LwPolyline(poly)));
}

fn text(drawing: &mut Drawing, x: f64, y: f64, height: f64, value: String) {
    let t = Text {
        location: Point::new(x, y, 0.0),
        text_height: height,
        value,
        ..Default::default()
    };
    drawing.add_entity(Entity::new(EntityType::Text(t)));
}

fn line(drawing: &mut Drawing, a: [f64; 2], b: [f64; 2]) {
    let l = Line::new(Point::new(a[0], a[1], 0.0), Point::new(b[0], b[1], 0.0));
    drawing.add_entity(Entity::new(EntityType::Line(l)));
}

fn finish(drawing: Drawing) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    drawing.save(&mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes)
}

fn new_drawing() -> Drawing {
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R2000;
    drawing
}

/// `patches.dxf`: every patch as a closed H × W outline, labelled "P1 18.4×1.5",
/// laid out without overlap on a 200 mm-wide sheet.
pub fn cut_file_dxf(design: &Design) -> Result<Vec<u8>, String> {
    let mut drawing = new_drawing();
    let layout = cut_layout(&design.patches, 200.0);
    for (i, (p, o)) in design.patches.iter().zip(&layout.origins).enumerate() {
        polygon(
            &mut drawing,
            &[
                [o[0], o[1]],
                [o[0] + p.w_mm, o[1]],
                [o[0] + p.w_mm, o[1] + p.h_mm],
                [o[0], o[1] + p.h_mm],
            ],
        );
        text(
            &mut drawing,
            o[0],
            o[1] - 3.0,
            1.8,
            format!("P{} {:.1}x{:.1}", i + 1, p.h_mm, p.w_mm),
        );
    }
    finish(drawing)
}

/// `template.dxf`: the unrolled uninflated balloon (2πR0 × L0) with each patch
/// outline at its X, Y, Θ (and its image across the seam where it straddles
/// it), a base marker and a ruler every 10 mm.
pub fn template_dxf(design: &Design) -> Result<Vec<u8>, String> {
    let mut drawing = new_drawing();
    let (c, l) = (design.balloon.circumference(), design.balloon.length_mm);
    polygon(&mut drawing, &[[0.0, 0.0], [c, 0.0], [c, l], [0.0, l]]);
    text(
        &mut drawing,
        -1.0,
        -4.0,
        2.0,
        "BASE (clamped end)".to_string(),
    );
    text(&mut drawing, 0.0, l + 2.0, 2.0, "seam X=0".to_string());
    for k in 0..=(l / 10.0).floor() as usize {
        let y = 10.0 * k as f64;
        let tick = if k % 5 == 0 { 4.0 } else { 2.0 };
        line(&mut drawing, [-tick, y], [0.0, y]);
        if k % 5 == 0 {
            text(&mut drawing, -12.0, y - 0.8, 1.6, format!("{y:.0}"));
        }
    }
    for (i, p) in design.patches.iter().enumerate() {
        for piece in sheet_pieces(p, c, l) {
            polygon(&mut drawing, &piece);
        }
        text(
            &mut drawing,
            p.x_mm.rem_euclid(c) + 0.5,
            p.y_mm,
            1.6,
            format!("P{}", i + 1),
        );
    }
    finish(drawing)
}
