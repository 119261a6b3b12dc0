//! Local refinement along the axis: fine rings where patches are and at both
//! ends, coarse rings along the bare stretches between them.
//!
//! Why this is safe: a stretch of bare tube away from patches and ends inflates
//! uniformly and stays straight, a state that elements of any axial length
//! represent exactly — only the cross-section (`around`, which grading leaves
//! alone) limits its accuracy. A patch disturbs the tube over a few radii, so
//! each patch's axial extent is refined with a margin of `MARGIN_RADII`·R₀, and
//! the element length then grows geometrically (ratio `GROWTH`) to the coarse
//! size.
//!
//! Zone edges are snapped outwards to multiples of the coarse size: a patch
//! moved by less than a coarse element usually keeps the same mesh, and when it
//! does not, the rings inside the zones still sit on one global grid.

use crate::design::Design;

/// Refined margin on either side of a patch and at each end, in radii R₀.
pub const MARGIN_RADII: f64 = 2.0;
/// Ratio of neighbouring element lengths in a transition.
pub const GROWTH: f64 = 1.5;

/// Axial intervals (mm) that get fine elements: every patch's axial extent
/// widened by the margin, the base and the cap end, snapped outwards to the
/// coarse grid, merged where they overlap or leave no room for a transition.
pub fn fine_zones(design: &Design, coarse: f64) -> Vec<(f64, f64)> {
    let length = design.balloon.length_mm;
    let margin = MARGIN_RADII * design.balloon.radius_mm;
    let mut zones: Vec<(f64, f64)> = design
        .patches
        .iter()
        .map(|p| {
            let half = p.axial_half_extent() + margin;
            (p.y_mm - half, p.y_mm + half)
        })
        .chain([(0.0, margin), (length - margin, length)])
        .map(|(a, b)| {
            let snap_down = (a / coarse).floor() * coarse;
            let snap_up = (b / coarse).ceil() * coarse;
            (snap_down.clamp(0.0, length), snap_up.clamp(0.0, length))
        })
        .filter(|(a, b)| b > a)
        .collect();
    zones.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64)> = Vec::with_capacity(zones.len());
    for (a, b) in zones {
        match merged.last_mut() {
            Some(last) if a <= last.1 + 2.0 * coarse => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    merged
}

/// Ring positions from 0 to `length`: elements of about `fine` inside `zones`
/// (sorted, disjoint, covering both ends), graded to about `coarse` between.
pub fn graded_rings(length: f64, zones: &[(f64, f64)], fine: f64, coarse: f64) -> Vec<f64> {
    let mut rings = vec![0.0];
    let mut cursor = 0.0;
    for &(a, b) in zones {
        if a > cursor {
            push_span(&mut rings, a, transition(a - cursor, fine, coarse));
        }
        let n = ((b - a) / fine).round().max(1.0) as usize;
        push_span(&mut rings, b, vec![1.0; n]);
        cursor = b;
    }
    if length > cursor {
        push_span(
            &mut rings,
            length,
            transition(length - cursor, fine, coarse),
        );
    }
    rings
}

/// Appends rings up to `end`, spacing them in proportion to `sizes`.
fn push_span(rings: &mut Vec<f64>, end: f64, sizes: Vec<f64>) {
    let start = *rings.last().expect("starts at 0");
    let scale = (end - start) / sizes.iter().sum::<f64>();
    let mut y = start;
    for size in &sizes[..sizes.len() - 1] {
        y += size * scale;
        rings.push(y);
    }
    rings.push(end);
}

/// Element lengths across a gap of `gap` mm between two fine zones: a
/// geometric ramp up from `fine`, coarse elements, the same ramp down. The
/// caller scales them to fill the gap exactly.
fn transition(gap: f64, fine: f64, coarse: f64) -> Vec<f64> {
    let mut ramp = Vec::new();
    let mut size = fine * GROWTH;
    while size < coarse {
        ramp.push(size);
        size *= GROWTH;
    }
    while 2.0 * ramp.iter().sum::<f64>() > gap {
        ramp.pop();
    }
    let middle = gap - 2.0 * ramp.iter().sum::<f64>();
    // A sliver between the ramps would be a jump in size: let the scaling
    // spread it over the ramps instead.
    let sliver = ramp.last().is_some_and(|&top| middle < 0.5 * top);
    let n = if sliver {
        0
    } else {
        (middle / coarse).ceil() as usize
    };
    let mut sizes = ramp.clone();
    sizes.extend(std::iter::repeat_n(middle / n.max(1) as f64, n));
    sizes.extend(ramp.iter().rev());
    if sizes.is_empty() {
        sizes.push(gap);
    }
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Patch;

    fn one_patch(y: f64) -> Design {
        let mut design = Design::reference(vec![Patch {
            x_mm: 0.0,
            y_mm: y,
            h_mm: 20.0,
            w_mm: 2.0,
            theta_deg: 0.0,
        }]);
        design.balloon.length_mm = 200.0;
        design
    }

    #[test]
    fn zones_cover_the_patch_with_margin_and_both_ends() {
        let design = one_patch(100.0);
        let margin = MARGIN_RADII * design.balloon.radius_mm;
        let zones = fine_zones(&design, 4.0);
        assert_eq!(zones.len(), 3, "{zones:?}");
        assert_eq!(zones[0].0, 0.0);
        assert!(zones[0].1 >= margin);
        assert!(zones[1].0 <= 90.0 - margin && zones[1].1 >= 110.0 + margin);
        assert_eq!(zones[2].1, 200.0);
        for (a, b) in &zones {
            assert_eq!(a % 4.0, 0.0);
            assert_eq!(b % 4.0, 0.0);
        }
    }

    #[test]
    fn a_small_move_keeps_the_zones() {
        let zones = fine_zones(&one_patch(100.0), 4.0);
        assert_eq!(zones, fine_zones(&one_patch(100.3), 4.0));
    }

    #[test]
    fn rings_are_fine_in_zones_graded_between() {
        let zones = fine_zones(&one_patch(100.0), 4.0);
        let rings = graded_rings(200.0, &zones, 1.0, 4.0);
        assert_eq!(rings[0], 0.0);
        assert_eq!(*rings.last().unwrap(), 200.0);
        let sizes: Vec<f64> = rings.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(sizes.iter().all(|&s| s > 0.0));
        for pair in sizes.windows(2) {
            let ratio = pair[1] / pair[0];
            assert!((1.0 / 1.6..=1.6).contains(&ratio), "jump {pair:?}");
        }
        let (a, b) = zones[1];
        for w in rings.windows(2).filter(|w| w[0] >= a && w[1] <= b) {
            assert!((w[1] - w[0] - 1.0).abs() < 1e-9);
        }
        assert!(sizes.iter().cloned().fold(0.0, f64::max) > 3.0);
        assert!(rings.len() < 140, "{} rings for 200 mm", rings.len());
    }

    #[test]
    fn a_short_gap_is_filled_without_overshoot() {
        let rings = graded_rings(10.0, &[(0.0, 2.0), (5.0, 10.0)], 1.0, 4.0);
        assert!(rings.windows(2).all(|w| w[1] > w[0]));
        assert_eq!(*rings.last().unwrap(), 10.0);
    }
}
