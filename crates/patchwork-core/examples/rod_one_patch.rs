//! One patch on a 100 mm balloon (at its middle, X = 0), FE on the `draft`
//! verification mesh against the kinematic rod (`fe::kinematic::rod_frames`
//! at curvature scale 1): the total bend (the angle between the
//! centreline's first and last tangents) and the inflated centreline's
//! length, over patch lengths, widths and angles.
//!
//! `cargo run --release -p patchwork-core --example rod_one_patch`

use patchwork_core::curve::Point;
use patchwork_core::design::{Design, Patch};
use patchwork_core::fe::kinematic::rod_frames;
use patchwork_core::fe::tube_theory::inflate_tube;
use patchwork_core::fe::{SimulateOptions, simulate};
use patchwork_core::inverse::Fidelity;

/// The balloon's uninflated length (mm) and the rod's cross-sections.
const LENGTH_MM: f64 = 100.0;
const SECTIONS: usize = 200;

/// The angle (degrees) between a polyline's first and last tangents.
fn bend_deg(points: &[Point]) -> f64 {
    let n = points.len();
    let first = (points[3] - points[0]).normalize();
    let last = (points[n - 1] - points[n - 4]).normalize();
    first.dot(&last).clamp(-1.0, 1.0).acos().to_degrees()
}

fn length(points: &[Point]) -> f64 {
    points.windows(2).map(|p| (p[1] - p[0]).norm()).sum()
}

/// The rod's centreline of `design` at curvature scale 1.
fn rod(design: &Design) -> Vec<Point> {
    let b = &design.balloon;
    let state = inflate_tube(&b.material, design.pressure_mpa(), b.radius_mm, b.wall_mm)
        .expect("the bare tube inflates");
    let heights: Vec<f64> = (1..=SECTIONS)
        .map(|k| LENGTH_MM * k as f64 / SECTIONS as f64)
        .collect();
    let frames = rod_frames(design, &heights, state, 1.0);
    std::iter::once(Point::zeros())
        .chain(frames.iter().map(|(centre, _)| *centre))
        .collect()
}

fn main() {
    let radius = Design::reference(vec![]).balloon.radius_mm;
    let options = SimulateOptions {
        mesh: Fidelity::Draft.tuning(radius).verify_mesh,
        ..SimulateOptions::default()
    };
    println!("H mm | W mm | Θ° | bend: FE, rod, FE/rod | length mm: FE, rod");
    for h_mm in [10.0, 30.0] {
        for w_mm in [1.0, 2.0, 3.5] {
            for theta_deg in [0.0, 30.0, 60.0] {
                let patch = Patch {
                    x_mm: 0.0,
                    y_mm: LENGTH_MM / 2.0,
                    h_mm,
                    w_mm,
                    theta_deg,
                };
                let mut design = Design::reference(vec![patch]);
                design.balloon.length_mm = LENGTH_MM;
                let Ok(fe) = simulate(&design, &options) else {
                    println!("{h_mm} | {w_mm} | {theta_deg} | did not solve");
                    continue;
                };
                let (fe, rod) = (fe.centreline.points().to_vec(), rod(&design));
                let (fe_bend, rod_bend) = (bend_deg(&fe), bend_deg(&rod));
                println!(
                    "{h_mm} | {w_mm} | {theta_deg} | {fe_bend:.1}, {rod_bend:.1}, {:.2} | {:.1}, {:.1}",
                    fe_bend / rod_bend,
                    length(&fe),
                    length(&rod)
                );
            }
        }
    }
}
