//! Fixed designs the benchmark report and the tests share.

use super::{Design, Patch};

/// A 1000 mm balloon (the reference tube lengthened) with 30 patches of
/// 15 × 2 mm every 32 mm, their X and Θ spread over the tube by golden-ratio
/// sequences, rounded to 0.001 mm and degree: about 3.1 m long inflated,
/// the design that `docs/studies.md` writes as JSON with a one-line script.
pub fn long_balloon() -> Design {
    let thousandths = |v: f64| (v * 1e3).round() / 1e3;
    let patches = (0..30)
        .map(|i| {
            let i = i as f64;
            Patch {
                x_mm: thousandths(20.0 * (i * 0.618034).fract()),
                y_mm: 16.0 + 32.0 * i,
                h_mm: 15.0,
                w_mm: 2.0,
                theta_deg: thousandths(60.0 * (i * 0.381966 + 0.1).fract() - 30.0),
            }
        })
        .collect();
    let mut design = Design::reference(patches);
    design.balloon.length_mm = 1000.0;
    design
}
