//! How the target preparation treats hand-drawn strokes: Catmull–Rom
//! splines through eight seeded random points (350 samples, 500–800 mm),
//! with 0.3 mm of seeded noise per coordinate, prepared as a design prepares
//! them (automatic smoothing), and compared with their clean curves — beside
//! one Gaussian convolution along the raw arc length at the same σ.
//!
//! cargo run --release -p patchwork-core --example stroke_smoothing
use patchwork_core::cmaes::SeededRng;
use patchwork_core::curve::{Curve, Point, shape_error};
use patchwork_core::inverse::input::{Smoothing, prepare};

/// `n` points of the Catmull–Rom spline through `p` (ends extended by reflection).
fn catmull(p: &[Point], n: usize) -> Vec<Point> {
    let mut out = Vec::new();
    let segs = p.len() - 1;
    for i in 0..n {
        let u = i as f64 / (n - 1) as f64 * segs as f64;
        let k = (u.floor() as usize).min(segs - 1);
        let t = u - k as f64;
        let p0 = if k == 0 { 2.0 * p[0] - p[1] } else { p[k - 1] };
        let p1 = p[k];
        let p2 = p[k + 1];
        let p3 = if k + 2 > segs {
            2.0 * p[segs] - p[segs - 1]
        } else {
            p[k + 2]
        };
        let t2 = t * t;
        let t3 = t2 * t;
        out.push(
            0.5 * ((2.0 * p1)
                + (-p0 + p2) * t
                + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
                + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3),
        );
    }
    out
}

fn main() {
    for seed in 1..=8u64 {
        let mut rng = SeededRng::new(seed);
        let ctrl: Vec<Point> = (0..8)
            .map(|i| {
                Point::new(
                    40.0 * i as f64 + 10.0 * rng.normal(),
                    40.0 * rng.normal(),
                    40.0 * rng.normal(),
                )
            })
            .collect();
        let clean = Curve::from_points(catmull(&ctrl, 350)).unwrap();
        let noisy = clean.with_noise(0.3 / clean.length(), seed).unwrap();
        let (prepared, report) = prepare(&noisy, Smoothing::Auto, 0.01).unwrap();
        let e = shape_error(&prepared, &clean, 200).unwrap();
        let sp: Vec<f64> = prepared
            .points()
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .collect();
        let (mn, mx) = sp
            .iter()
            .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        let once = noisy.convolved(report.smoothing_mm).unwrap();
        let e1 = shape_error(&once, &clean, 200).unwrap();
        println!(
            "seed {seed}: clean {:.1} mm noisy {:.1} prepared {:.1}; σ {:.2}; prepared vs clean {:.2} % (spacing {mn:.3}..{mx:.2}); one convolution {:.2} % len {:.1}",
            clean.length(),
            noisy.length(),
            prepared.length(),
            report.smoothing_mm,
            e.percent_of_length,
            e1.percent_of_length,
            once.length()
        );
    }
}
