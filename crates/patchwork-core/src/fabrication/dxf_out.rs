//! DXF output: AutoCAD R12 ASCII (AC1009), the version every laser cutter's
//! software reads. A file is a HEADER (version, millimetres, extents) and an
//! ENTITIES section of closed POLYLINEs (patch outlines), LINEs (ruler
//! ticks) and TEXTs (labels), all on layer 0; R12 needs no tables, blocks or
//! handles. Each value is a group code line then a value line.

use std::fmt::Write;

use super::geometry::{cut_layout, sheet_pieces};
use crate::design::Design;

/// An R12 drawing under construction: its ENTITIES section and extents.
struct Drawing {
    body: String,
    min: [f64; 2],
    max: [f64; 2],
}

impl Drawing {
    fn new() -> Drawing {
        Drawing {
            body: String::new(),
            min: [f64::INFINITY; 2],
            max: [f64::NEG_INFINITY; 2],
        }
    }

    fn group(&mut self, code: u16, value: impl std::fmt::Display) {
        group(&mut self.body, code, value);
    }

    /// A point's groups, widening the extents.
    fn point(&mut self, code: u16, p: [f64; 2]) {
        for ((min, max), v) in self.min.iter_mut().zip(&mut self.max).zip(p) {
            *min = min.min(v);
            *max = max.max(v);
        }
        point(&mut self.body, code, p);
    }

    /// An entity's head: its type and layer 0.
    fn entity(&mut self, kind: &str) {
        self.group(0, kind);
        self.group(8, "0");
    }

    /// A closed polyline through `corners` (POLYLINE, flag 1 = closed, its
    /// VERTEXes, SEQEND).
    fn polygon(&mut self, corners: &[[f64; 2]]) {
        self.entity("POLYLINE");
        self.group(66, 1);
        self.point(10, [0.0, 0.0]);
        self.group(70, 1);
        for &c in corners {
            self.entity("VERTEX");
            self.point(10, c);
        }
        self.entity("SEQEND");
    }

    fn line(&mut self, a: [f64; 2], b: [f64; 2]) {
        self.entity("LINE");
        self.point(10, a);
        self.point(11, b);
    }

    /// A one-line label at `at` (its baseline's left end), `height` mm tall.
    /// R12 text is in the ANSI code page: anything outside ASCII becomes `?`.
    fn text(&mut self, at: [f64; 2], height: f64, value: &str) {
        let ascii: String = value
            .chars()
            .map(|c| {
                if c.is_ascii_graphic() || c == ' ' {
                    c
                } else {
                    '?'
                }
            })
            .collect();
        self.entity("TEXT");
        self.point(10, at);
        self.group(40, format_args!("{height:.4}"));
        self.group(1, ascii);
    }

    /// The file: HEADER ($ACADVER AC1009, $INSUNITS 4 = millimetres,
    /// $EXTMIN/$EXTMAX), ENTITIES, EOF.
    fn finish(self) -> Vec<u8> {
        let mut out = String::new();
        for (code, value) in [
            (0, "SECTION"),
            (2, "HEADER"),
            (9, "$ACADVER"),
            (1, "AC1009"),
        ] {
            group(&mut out, code, value);
        }
        group(&mut out, 9, "$INSUNITS");
        group(&mut out, 70, 4);
        let (min, max) = match self.min[0].is_finite() {
            true => (self.min, self.max),
            false => ([0.0; 2], [0.0; 2]),
        };
        group(&mut out, 9, "$EXTMIN");
        point(&mut out, 10, min);
        group(&mut out, 9, "$EXTMAX");
        point(&mut out, 10, max);
        for (code, value) in [(0, "ENDSEC"), (0, "SECTION"), (2, "ENTITIES")] {
            group(&mut out, code, value);
        }
        out.push_str(&self.body);
        group(&mut out, 0, "ENDSEC");
        group(&mut out, 0, "EOF");
        out.into_bytes()
    }
}

/// One group: its code, then its value, each on a line.
fn group(out: &mut String, code: u16, value: impl std::fmt::Display) {
    // Writing to a String cannot fail.
    let _ = write!(out, "{code}\n{value}\n");
}

/// A point's groups: x at `code`, y at `code + 10`, z = 0 at `code + 20`,
/// to 0.1 µm.
fn point(out: &mut String, code: u16, p: [f64; 2]) {
    group(out, code, format_args!("{:.4}", p[0]));
    group(out, code + 10, format_args!("{:.4}", p[1]));
    group(out, code + 20, "0.0");
}

/// `patches.dxf`: every patch as a closed H × W outline, labelled "P1 18.4x1.5",
/// laid out without overlap on a 200 mm-wide sheet.
pub fn cut_file_dxf(design: &Design) -> Vec<u8> {
    let mut drawing = Drawing::new();
    let layout = cut_layout(&design.patches, 200.0);
    for (i, (p, o)) in design.patches.iter().zip(&layout.origins).enumerate() {
        drawing.polygon(&[
            [o[0], o[1]],
            [o[0] + p.w_mm, o[1]],
            [o[0] + p.w_mm, o[1] + p.h_mm],
            [o[0], o[1] + p.h_mm],
        ]);
        let label = format!("P{} {:.1}x{:.1}", i + 1, p.h_mm, p.w_mm);
        drawing.text([o[0], o[1] - 3.0], 1.8, &label);
    }
    drawing.finish()
}

/// `template.dxf`: the unrolled uninflated balloon (2πR0 × L0) with each patch
/// outline at its X, Y, Θ (and its image across the seam where it straddles
/// it), a base marker and a ruler every 10 mm.
pub fn template_dxf(design: &Design) -> Vec<u8> {
    let mut drawing = Drawing::new();
    let (c, l) = (design.balloon.circumference(), design.balloon.length_mm);
    drawing.polygon(&[[0.0, 0.0], [c, 0.0], [c, l], [0.0, l]]);
    drawing.text([-1.0, -4.0], 2.0, "BASE (clamped end)");
    drawing.text([0.0, l + 2.0], 2.0, "seam X=0");
    for k in 0..=(l / 10.0).floor() as usize {
        let y = 10.0 * k as f64;
        let tick = if k % 5 == 0 { 4.0 } else { 2.0 };
        drawing.line([-tick, y], [0.0, y]);
        if k % 5 == 0 {
            drawing.text([-12.0, y - 0.8], 1.6, &format!("{y:.0}"));
        }
    }
    for (i, p) in design.patches.iter().enumerate() {
        for piece in sheet_pieces(p, c, l) {
            drawing.polygon(&piece);
        }
        drawing.text(
            [p.x_mm.rem_euclid(c) + 0.5, p.y_mm],
            1.6,
            &format!("P{}", i + 1),
        );
    }
    drawing.finish()
}
