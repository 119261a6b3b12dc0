//! SVG output: the placement template at 1:1 (mm units, prints to scale) and
//! the κ, τ profiles, target against achieved.

use std::fmt::Write;

use super::geometry::sheet_pieces;
use crate::design::Design;

/// `template.svg`: as `template.dxf`, in an SVG whose user unit is 1 mm.
pub fn template_svg(design: &Design) -> String {
    let (c, l) = (design.balloon.circumference(), design.balloon.length_mm);
    let (margin, w, h) = (20.0, c + 40.0, l + 30.0);
    let mut s = String::new();
    // y grows downward in SVG: draw with Y up by flipping about the sheet.
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}mm" height="{h}mm" viewBox="0 0 {w} {h}">"#
    );
    let _ = write!(
        s,
        r#"<g transform="translate({margin} {}) scale(1 -1)" fill="none" stroke="black" stroke-width="0.2">"#,
        l + 10.0
    );
    let _ = write!(s, r#"<rect x="0" y="0" width="{c}" height="{l}"/>"#);
    for k in 0..=(l / 10.0).floor() as usize {
        let y = 10.0 * k as f64;
        let tick = if k % 5 == 0 { 4.0 } else { 2.0 };
        let _ = write!(s, r#"<line x1="{}" y1="{y}" x2="0" y2="{y}"/>"#, -tick);
    }
    for p in &design.patches {
        for piece in sheet_pieces(p, c, l) {
            let points: Vec<String> = piece
                .iter()
                .map(|q| format!("{:.3},{:.3}", q[0], q[1]))
                .collect();
            let _ = write!(
                s,
                r#"<polygon points="{}" stroke="red"/>"#,
                points.join(" ")
            );
        }
    }
    s.push_str("</g>");
    let label = |s: &mut String, x: f64, y: f64, text: &str| {
        let _ = write!(
            s,
            r#"<text x="{:.2}" y="{:.2}" font-size="2" font-family="sans-serif">{text}</text>"#,
            x + margin,
            l + 10.0 - y
        );
    };
    label(&mut s, -1.0, -4.0, "BASE (clamped end)");
    for k in (0..=(l / 50.0).floor() as usize).map(|k| 50.0 * k as f64) {
        label(&mut s, -18.0, k - 0.7, &format!("{k:.0}"));
    }
    for (i, p) in design.patches.iter().enumerate() {
        label(
            &mut s,
            p.x_mm.rem_euclid(c) + 0.5,
            p.y_mm,
            &format!("P{}", i + 1),
        );
    }
    s.push_str("</svg>\n");
    s
}

/// `profiles.svg`: κ(s) and τ(s) on normalised arc length, target (grey)
/// against achieved (blue).
pub fn profiles_svg(target: (&[f64], &[f64]), achieved: (&[f64], &[f64])) -> String {
    let (w, h, pad) = (640.0, 220.0, 40.0);
    let mut s = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{}" viewBox="0 0 {w} {}" font-family="sans-serif" font-size="11">"#,
        2.0 * h,
        2.0 * h
    );
    for (row, (name, t, a)) in [
        ("curvature κ (1/mm)", target.0, achieved.0),
        ("torsion τ (1/mm)", target.1, achieved.1),
    ]
    .into_iter()
    .enumerate()
    {
        let top = row as f64 * h;
        let all = t.iter().chain(a).copied().filter(|v| v.is_finite());
        let (lo, hi) = all.fold((0.0_f64, 0.0_f64), |(l, u), v| (l.min(v), u.max(v)));
        let span = (hi - lo).max(1e-9);
        let map = |i: usize, n: usize, v: f64| {
            let x = pad + (w - 2.0 * pad) * i as f64 / (n.max(2) - 1) as f64;
            let y = top + h - pad / 2.0 - (h - pad) * (v - lo) / span;
            format!("{x:.1},{y:.1}")
        };
        let _ = write!(
            s,
            r#"<text x="{pad}" y="{}">{name}; s / L from 0 to 1; target grey, achieved blue</text>"#,
            top + 14.0
        );
        let _ = write!(
            s,
            r##"<rect x="{pad}" y="{}" width="{}" height="{}" fill="none" stroke="#ccc"/>"##,
            top + pad / 2.0,
            w - 2.0 * pad,
            h - pad
        );
        for (values, colour) in [(t, "#888"), (a, "#1f5fd0")] {
            let points: Vec<String> = values
                .iter()
                .enumerate()
                .map(|(i, v)| map(i, values.len(), if v.is_finite() { *v } else { 0.0 }))
                .collect();
            let _ = write!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.5"/>"#,
                points.join(" ")
            );
        }
    }
    s.push_str("</svg>\n");
    s
}
