//! Dynamic time warping of two scalar profiles (κ(s) or τ(s)).

/// Classic DTW distance with cost |a − b|:
/// `D[i][j] = |aᵢ − bⱼ| + min(D[i−1][j], D[i][j−1], D[i−1][j−1])`.
///
/// `window` is a Sakoe–Chiba band half-width |i − j| ≤ w, widened to at least
/// the length difference so a path always exists. `None` when either profile is
/// empty or holds a non-finite value. Memory is O(len(b)).
pub fn dtw(a: &[f64], b: &[f64], window: Option<usize>) -> Option<f64> {
    if a.is_empty() || b.is_empty() || a.iter().chain(b).any(|v| !v.is_finite()) {
        return None;
    }
    let (n, m) = (a.len(), b.len());
    let band = window.map_or(usize::MAX, |w| w.max(n.abs_diff(m)));
    let mut previous = vec![f64::INFINITY; m + 1];
    let mut current = vec![f64::INFINITY; m + 1];
    previous[0] = 0.0;
    for i in 1..=n {
        current.fill(f64::INFINITY);
        let lo = if band == usize::MAX {
            1
        } else {
            i.saturating_sub(band).max(1)
        };
        let hi = i.saturating_add(band).min(m);
        for j in lo..=hi {
            let best = previous[j].min(current[j - 1]).min(previous[j - 1]);
            current[j] = (a[i - 1] - b[j - 1]).abs() + best;
        }
        std::mem::swap(&mut previous, &mut current);
    }
    Some(previous[m])
}

#[cfg(test)]
mod tests {
    use super::dtw;

    #[test]
    fn reference_vectors() {
        assert_eq!(dtw(&[0., 1., 2.], &[0., 0., 1., 1., 2.], None), Some(0.0));
        assert_eq!(dtw(&[1., 2., 3.], &[2., 2., 2., 3., 4.], None), Some(2.0));
        assert_eq!(
            dtw(&[0., 0., 1., 2., 1., 0.], &[0., 1., 1., 2., 0.], None),
            Some(1.0)
        );
        let a = [1., 3., 4., 9., 8., 2., 1., 5., 7., 3.];
        let b = [1., 6., 2., 3., 0., 9., 4., 3., 6., 3.];
        assert_eq!(dtw(&a, &b, None), Some(15.0));
    }

    #[test]
    fn window_constrains_and_never_strands_the_path() {
        let a = [0., 0., 0., 0., 5.];
        let b = [5., 0., 0., 0., 0.];
        let free = dtw(&a, &b, None).unwrap();
        let banded = dtw(&a, &b, Some(0)).unwrap();
        assert!(banded >= free);
        assert_eq!(banded, 10.0);
        assert!(dtw(&[1., 2., 3., 4., 5., 6.], &[1., 2.], Some(0)).is_some());
    }

    #[test]
    fn empty_or_nan_gives_none() {
        assert_eq!(dtw(&[], &[1.0], None), None);
        assert_eq!(dtw(&[f64::NAN], &[1.0], None), None);
    }
}
