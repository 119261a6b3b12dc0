//! Curves for what labs ask a balloon to do: grasp a cylinder, hang as a
//! hook, wind as a spiral, and the planar S (with or without a kink) that a
//! hand sketch often is.

use std::f64::consts::TAU;

use super::super::{Curve, CurveError, Point};
use super::sampling::{by_arc_length, finite, positive};
use super::{GraspParams, HookParams, SCurveParams, SpiralParams};

/// A helix whose radius and pitch vary linearly with the turn angle:
/// r(u) = r₀ + (r₁ − r₀) u, pitch p(u) = p₀ + (p₁ − p₀) u, u ∈ [0, 1]; the
/// rise is z = ∫ p/2π dt = N (p₀ u + (p₁ − p₀) u²/2) over N turns.
pub(super) fn spiral(p: &SpiralParams, n: usize) -> Result<Curve, CurveError> {
    positive("start_radius_mm", p.start_radius_mm)?;
    positive("end_radius_mm", p.end_radius_mm)?;
    finite("start_pitch_mm", p.start_pitch_mm)?;
    finite("end_pitch_mm", p.end_pitch_mm)?;
    positive("turns", p.turns)?;
    let (r0, r1, p0, p1, turns) = (
        p.start_radius_mm,
        p.end_radius_mm,
        p.start_pitch_mm,
        p.end_pitch_mm,
        p.turns,
    );
    let end = TAU * turns;
    by_arc_length(
        |t| {
            let u = t / end;
            let r = r0 + (r1 - r0) * u;
            let z = turns * (p0 * u + (p1 - p0) * u * u / 2.0);
            Point::new(r * t.cos(), r * t.sin(), z)
        },
        end,
        n,
    )
}

/// Two equal arcs in the xy plane, the first turning left and the second
/// right, joined at a corner that turns the heading by `kink_deg` (0: a
/// smooth S). Exactly uniform in arc length.
pub(super) fn s_curve(p: &SCurveParams, n: usize) -> Result<Curve, CurveError> {
    positive("radius_mm", p.radius_mm)?;
    positive("angle_deg", p.angle_deg)?;
    finite("kink_deg", p.kink_deg)?;
    below("angle_deg", p.angle_deg, 180.0, "must be below 180")?;
    below("kink_deg", p.kink_deg.abs(), 90.0, "must be within ±90")?;
    let (r, a) = (p.radius_mm, p.angle_deg.to_radians());
    let joint = Point::new(r * a.sin(), r * (1.0 - a.cos()), 0.0);
    let heading = a + p.kink_deg.to_radians();
    // The second arc turns right: its centre is on the right of the heading.
    let centre = joint + r * Point::new(heading.sin(), -heading.cos(), 0.0);
    let total = 2.0 * r * a;
    uniform(n, total, |s| {
        if s <= r * a {
            Point::new(r * (s / r).sin(), r * (1.0 - (s / r).cos()), 0.0)
        } else {
            let turned = heading - (s - r * a) / r;
            centre + r * Point::new(-turned.sin(), turned.cos(), 0.0)
        }
    })
}

/// A straight shank along x, then an arc of diameter `opening_mm` turning
/// left through `angle_deg`: a planar hook.
pub(super) fn hook(p: &HookParams, n: usize) -> Result<Curve, CurveError> {
    positive("shank_mm", p.shank_mm)?;
    positive("opening_mm", p.opening_mm)?;
    positive("angle_deg", p.angle_deg)?;
    below("angle_deg", p.angle_deg, 360.0, "must be below 360")?;
    let (l, r, a) = (p.shank_mm, p.opening_mm / 2.0, p.angle_deg.to_radians());
    uniform(n, l + r * a, |s| {
        if s <= l {
            Point::new(s, 0.0, 0.0)
        } else {
            let t = (s - l) / r;
            Point::new(l + r * t.sin(), r * (1.0 - t.cos()), 0.0)
        }
    })
}

/// A straight lead of `lead_mm`, then a helix wrapped around a cylinder of
/// diameter `diameter_mm` (its axis along z): the centreline's radius is the
/// cylinder's plus the inflated tube's, `tube_radius_mm` (16.5 mm: the
/// reference balloon, the paper's, at 20 kPa by membrane theory, 3.18 mm ×
/// a hoop stretch of 5.19). The lead is the
/// helix's tangent at its start, so the curve is smooth (its curvature
/// jumps from 0 to the helix's).
pub(super) fn grasp(p: &GraspParams, n: usize) -> Result<Curve, CurveError> {
    positive("diameter_mm", p.diameter_mm)?;
    positive("turns", p.turns)?;
    finite("pitch_mm", p.pitch_mm)?;
    finite("lead_mm", p.lead_mm)?;
    positive("tube_radius_mm", p.tube_radius_mm)?;
    if p.lead_mm < 0.0 {
        return Err(CurveError::InvalidParameter {
            name: "lead_mm",
            value: p.lead_mm,
            reason: "must not be negative",
        });
    }
    let (r, b) = (p.diameter_mm / 2.0 + p.tube_radius_mm, p.pitch_mm / TAU);
    let speed = (r * r + b * b).sqrt();
    let start = Point::new(r, 0.0, 0.0);
    let tangent = Point::new(0.0, r, b) / speed;
    let helix_length = TAU * p.turns * speed;
    uniform(n, p.lead_mm + helix_length, |s| {
        if s <= p.lead_mm {
            start - tangent * (p.lead_mm - s)
        } else {
            let t = (s - p.lead_mm) / speed;
            Point::new(r * t.cos(), r * t.sin(), b * t)
        }
    })
}

/// `n` samples of a curve given by arc length on [0, total].
fn uniform(n: usize, total: f64, at: impl Fn(f64) -> Point) -> Result<Curve, CurveError> {
    Curve::from_points(
        (0..n)
            .map(|i| at(total * i as f64 / (n - 1) as f64))
            .collect(),
    )
}

/// `value` below `limit`, else the parameter error with `reason`.
fn below(
    name: &'static str,
    value: f64,
    limit: f64,
    reason: &'static str,
) -> Result<(), CurveError> {
    if value < limit {
        return Ok(());
    }
    Err(CurveError::InvalidParameter {
        name,
        value,
        reason,
    })
}

#[cfg(test)]
mod tests {
    use super::super::Preset;
    use super::*;

    fn sample(preset: &str, params: serde_json::Value, n: usize) -> Curve {
        Preset::from_name(preset, params)
            .unwrap()
            .generate(n)
            .unwrap()
    }

    /// The unit tangent between samples i and i + 1.
    fn tangent(c: &Curve, i: usize) -> Point {
        (c.points()[i + 1] - c.points()[i]).normalize()
    }

    #[test]
    fn a_spiral_of_constant_radius_and_pitch_is_the_helix() {
        let spiral = sample(
            "spiral",
            serde_json::json!({"start_radius_mm": 20, "end_radius_mm": 20,
                "start_pitch_mm": 60, "end_pitch_mm": 60, "turns": 2}),
            300,
        );
        let helix = Preset::helix(20.0, 60.0, 2.0).generate(300).unwrap();
        for (a, b) in spiral.points().iter().zip(helix.points()) {
            assert!((a - b).norm() < 1e-3, "{a} against {b}");
        }
    }

    #[test]
    fn a_conical_spiral_widens_from_its_start_radius_to_its_end_radius() {
        let c = sample("spiral", serde_json::json!({}), 400);
        let radius = |p: &Point| p.x.hypot(p.y);
        assert!((radius(&c.points()[0]) - 25.0).abs() < 1e-9);
        assert!((radius(c.points().last().unwrap()) - 60.0).abs() < 1e-9);
        // The rise over 1.5 turns of a 20 mm pitch.
        assert!((c.points().last().unwrap().z - 30.0).abs() < 1e-9);
    }

    #[test]
    fn an_s_curve_has_its_two_arcs_length_and_turns_back_to_its_start_heading() {
        // Smooth S: 2 R a long, the heading turned left by a and back.
        let c = sample(
            "s_curve",
            serde_json::json!({"radius_mm": 50, "angle_deg": 90}),
            401,
        );
        let expected = 2.0 * 50.0 * std::f64::consts::FRAC_PI_2;
        assert!((c.length() - expected).abs() / expected < 1e-4);
        let (first, last) = (tangent(&c, 0), tangent(&c, 399));
        assert!((first - last).norm() < 0.01, "{first} {last}");
        assert!(c.points().iter().all(|p| p.z == 0.0));
        // With a 30° kink the tangent turns by 30° across the joint.
        let kinked = sample(
            "s_curve",
            serde_json::json!({"radius_mm": 50, "angle_deg": 90, "kink_deg": 30}),
            401,
        );
        let (before, after) = (tangent(&kinked, 198), tangent(&kinked, 201));
        let turned = before.dot(&after).clamp(-1.0, 1.0).acos().to_degrees();
        assert!((turned - 30.0).abs() < 2.0, "{turned}°");
    }

    #[test]
    fn a_hook_is_a_shank_and_an_arc_of_its_opening() {
        let c = sample(
            "hook",
            serde_json::json!({"shank_mm": 100, "opening_mm": 40, "angle_deg": 180}),
            401,
        );
        let expected = 100.0 + 20.0 * std::f64::consts::PI;
        assert!((c.length() - expected).abs() / expected < 1e-4);
        // Half a turn: the tip is back above the shank's end, 40 mm across.
        let tip = c.points().last().unwrap();
        assert!((tip - Point::new(100.0, 40.0, 0.0)).norm() < 1e-9, "{tip}");
    }

    #[test]
    fn a_grasp_wraps_the_cylinder_at_its_diameter_plus_the_tube() {
        let c = sample(
            "grasp",
            serde_json::json!({"diameter_mm": 40, "turns": 1, "pitch_mm": 30, "lead_mm": 50}),
            600,
        );
        let r = 20.0 + 16.5;
        let on_helix: Vec<&Point> = c.points().iter().filter(|p| p.z > 0.5).collect();
        assert!(on_helix.iter().all(|p| (p.x.hypot(p.y) - r).abs() < 1e-9));
        let helix = std::f64::consts::TAU * (r * r + (30.0 / std::f64::consts::TAU).powi(2)).sqrt();
        assert!((c.length() - (50.0 + helix)).abs() / c.length() < 1e-4);
        // The lead is straight and meets the helix tangentially.
        assert!((tangent(&c, 0) - tangent(&c, 20)).norm() < 1e-9);
    }

    #[test]
    fn out_of_range_parameters_are_named() {
        for (preset, params, name) in [
            (
                "s_curve",
                serde_json::json!({"angle_deg": 200}),
                "angle_deg",
            ),
            ("s_curve", serde_json::json!({"kink_deg": 95}), "kink_deg"),
            ("hook", serde_json::json!({"opening_mm": 0}), "opening_mm"),
            ("grasp", serde_json::json!({"lead_mm": -5}), "lead_mm"),
            ("spiral", serde_json::json!({"turns": -1}), "turns"),
        ] {
            let error = Preset::from_name(preset, params)
                .unwrap()
                .generate(100)
                .unwrap_err();
            assert!(error.to_string().contains(name), "{preset}: {error}");
        }
    }
}
