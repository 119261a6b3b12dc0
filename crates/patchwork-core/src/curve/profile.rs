/// Piecewise-linear interpolation of a profile `ys` sampled at increasing `xs`,
/// clamped at both ends. Needs at least two samples.
pub fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let upper = xs.partition_point(|&v| v < x).clamp(1, xs.len() - 1);
    let (x0, x1) = (xs[upper - 1], xs[upper]);
    let t = if x1 > x0 {
        ((x - x0) / (x1 - x0)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ys[upper - 1] + t * (ys[upper] - ys[upper - 1])
}
