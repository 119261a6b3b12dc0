//! A simulated balloon scanned: points sampled on the inflated FE surface
//! (area-weighted over its triangles), 0.2 mm of noise on each coordinate,
//! a fifth of the surface missing in holes; the centreline extracted from
//! them against the simulation's own (ring centres), within 0.3 mm RMS,
//! and its radius against the rings'.

use patchwork_core::Point;
use patchwork_core::cmaes::SeededRng;
use patchwork_core::design::{Design, Patch};
use patchwork_core::fe::{SimulateOptions, Simulation, simulate};
use patchwork_core::measure::scan::centreline_from_scan;
use patchwork_core::measure::{Prediction, compare_scan};

/// A 120 mm balloon with three patches turned alike: it inflates into
/// part of a helix, 305 mm long, 33 mm across on its bare stretches.
fn sim_design() -> Design {
    let patch = |y_mm: f64| Patch {
        x_mm: 0.0,
        y_mm,
        h_mm: 20.0,
        w_mm: 3.0,
        theta_deg: 25.0,
    };
    let mut design = Design::reference(vec![patch(30.0), patch(60.0), patch(90.0)]);
    design.balloon.length_mm = 120.0;
    design
}

fn simulated() -> Simulation {
    simulate(&sim_design(), &SimulateOptions::default()).expect("converges")
}

/// `n` points on the inflated surface, as a scanner with 0.2 mm of noise
/// that missed a fifth of the surface, in round holes, sees it.
fn scan_of(sim: &Simulation, n: usize, seed: u64) -> (Vec<Point>, f64) {
    let x = &sim.positions;
    let triangles = &sim.mesh.triangles;
    let mut cumulative = Vec::with_capacity(triangles.len());
    let mut total = 0.0;
    for t in triangles {
        total += 0.5 * (x[t[1]] - x[t[0]]).cross(&(x[t[2]] - x[t[0]])).norm();
        cumulative.push(total);
    }
    let mut rng = SeededRng::new(seed);
    let sample = |rng: &mut SeededRng| {
        let u = rng.uniform() * total;
        let k = cumulative.partition_point(|&c| c < u);
        let t = triangles[k.min(triangles.len() - 1)];
        let (mut a, mut b) = (rng.uniform(), rng.uniform());
        if a + b > 1.0 {
            (a, b) = (1.0 - a, 1.0 - b);
        }
        x[t[0]] + (x[t[1]] - x[t[0]]) * a + (x[t[2]] - x[t[0]]) * b
    };
    // Holes of half the tube's median radius (none reaches the far side,
    // under a patch either), as many as make a fifth of the area.
    let mut radii: Vec<f64> = sim.rings.iter().map(|r| r.radius).collect();
    radii.sort_by(f64::total_cmp);
    let hole = 0.5 * radii[radii.len() / 2];
    let count = (0.2 * total / (std::f64::consts::PI * hole * hole)).round() as usize;
    let holes: Vec<Point> = (0..count).map(|_| sample(&mut rng)).collect();
    let (mut points, mut missed) = (Vec::with_capacity(n), 0usize);
    while points.len() < n {
        let p = sample(&mut rng);
        if holes.iter().any(|h| (h - p).norm() < hole) {
            missed += 1;
            continue;
        }
        points.push(p + Point::new(rng.normal(), rng.normal(), rng.normal()) * 0.2);
    }
    (points, missed as f64 / (missed + n) as f64)
}

fn distance_to(polyline: &[Point], p: &Point) -> f64 {
    polyline
        .windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let t = ((p - w[0]).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (w[0] + d * t - p).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_scan_of_a_simulated_balloon_gives_its_centreline_within_0_3_mm() {
    let sim = simulated();
    let (points, missed) = scan_of(&sim, 600_000, 3);
    assert!((0.15..0.25).contains(&missed), "{missed}");
    let whole = centreline_from_scan(&points).unwrap();
    // The base is at the origin, where the balloon is clamped.
    let first = Point::from(whole.centreline_mm[0]);
    let last = Point::from(whole.centreline_mm[whole.centreline_mm.len() - 1]);
    let scan = whole.base_to_tip(last.norm() > first.norm(), sim.cap_height());
    let extracted = scan.curve().unwrap();
    let base = Point::from(scan.centreline_mm[0]);
    println!("base {base:?}, rim radius {:.3} mm", scan.radius_mm[0]);
    let truth = sim.centreline.points();
    let off: Vec<f64> = extracted
        .points()
        .iter()
        .map(|p| distance_to(truth, p))
        .collect();
    let rms = (off.iter().map(|d| d * d).sum::<f64>() / off.len() as f64).sqrt();
    println!(
        "{} points, {:.0} % missed: {} sections, {rms:.3} mm RMS off the simulated centreline, \
         length {:.1} mm against {:.1} mm",
        points.len(),
        100.0 * missed,
        extracted.len(),
        extracted.length(),
        sim.centreline.length()
    );
    assert!(rms < 0.3, "{rms} mm RMS");
    // The base at the clamp's ring, the scan's open edge, though holes hide
    // part of it and the tube flares from 3.2 to 12 mm within a few
    // millimetres behind it: measured 0.37 mm from the clamp's centre. The
    // tip where the predicted cap's height puts it: 0.7 mm short in all.
    assert!(base.norm() < 0.6, "{base:?}");
    assert!((extracted.length() - sim.centreline.length()).abs() < 1.5);
    // Through the comparison: the cap found at the right end, the shape and
    // the radius (at the same fractions of length) against the simulation.
    let radii: Vec<f64> = sim.rings.iter().map(|r| r.radius).collect();
    let prediction = Prediction::new(sim_design(), sim.centreline.points(), None)
        .unwrap()
        .with_radius(radii, sim.cap_height());
    let comparison = compare_scan(&prediction, &whole).unwrap();
    println!(
        "{:?} {:?}",
        comparison.against_prediction, comparison.radius
    );
    // A balloon built exactly as predicted: 0.07 % of the length.
    assert!(comparison.against_prediction.shape_error_percent < 0.15);
    let radius = comparison.radius.unwrap();
    // The scan's points lie on the triangles, the rings' fits go through
    // their corners: 2.3 % smaller.
    assert!(radius.difference_percent.abs() < 3.0, "{radius:?}");
}
