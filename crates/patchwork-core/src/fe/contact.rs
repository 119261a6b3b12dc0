//! Self-contact of the inflated balloon: where the tube, as the membrane
//! model predicts it, would pass through itself (a knot, a tight helix, a
//! hook closing on its stem). The model has no contact, so such a shape is
//! not what the balloon does: the report says where and by how much.
//!
//! The tube is the chain of capsules between consecutive fitted rings: the
//! centre and the radius linear between them. Two stretches touch where the
//! distance between their centrelines is less than the sum of their radii.
//! Stretches close along the balloon always "touch" in that sense (a bend's
//! inner side), so a pair counts only when the arc length between its two
//! points exceeds π/2 times the sum of the radii: a hairpin of radius r
//! (the tightest a tube of radius r makes) brings its legs together exactly
//! at that arc length, so anything closer along the tube is a bend, not a
//! contact.

use serde::{Deserialize, Serialize};

use super::centreline::Ring;
use crate::curve::{Point, cumulative_length};

/// Overlaps smaller than this (mm) are touching, not passing through.
const TOUCHING_MM: f64 = 0.01;

/// Where two stretches of the inflated tube pass through each other.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SelfContact {
    /// The deepest point of the contact on each stretch: arc length along
    /// the inflated centreline from the base (mm), the first < the second.
    pub s_mm: [f64; 2],
    /// The same points on the uninflated balloon (Y from the base, mm): where
    /// to look on the cut balloon and its template.
    pub y_mm: [f64; 2],
    /// How far the two surfaces pass into each other there (mm): the sum of
    /// the radii less the distance between the centres.
    pub overlap_mm: f64,
}

/// A point between ring `k` and `k + 1` at fraction `t`.
#[derive(Debug, Clone, Copy)]
struct OnTube {
    segment: usize,
    t: f64,
}

/// Two points of the tube closer than their radii allow, and by how much.
#[derive(Debug, Clone, Copy)]
struct Touch {
    overlap: f64,
    p: OnTube,
    q: OnTube,
}

/// A point's arc length, material Y and radius along the tube of `rings`
/// (`s`: the centres' cumulative length).
fn along(rings: &[Ring], s: &[f64], p: OnTube) -> (f64, f64, f64) {
    let (a, b) = (&rings[p.segment], &rings[p.segment + 1]);
    let lerp = |x: f64, y: f64| x + p.t * (y - x);
    (
        lerp(s[p.segment], s[p.segment + 1]),
        lerp(a.y, b.y),
        lerp(a.radius, b.radius),
    )
}

/// For every segment of the tube, its deepest overlap with any segment
/// further along and far enough along not to be a bend, with `margin_mm`
/// added to the sum of the radii (0: the surfaces themselves); none where
/// the overlap is not above `floor_mm`.
fn deepest_touches(rings: &[Ring], s: &[f64], margin_mm: f64, floor_mm: f64) -> Vec<Option<Touch>> {
    let mut deepest: Vec<Option<Touch>> = Vec::new();
    for i in 0..rings.len().saturating_sub(1) {
        let mut best: Option<Touch> = None;
        for j in i + 1..rings.len() - 1 {
            let (u, v, distance) = closest(
                [rings[i].centre, rings[i + 1].centre],
                [rings[j].centre, rings[j + 1].centre],
            );
            let (p, q) = (OnTube { segment: i, t: u }, OnTube { segment: j, t: v });
            let ((sp, _, rp), (sq, _, rq)) = (along(rings, s, p), along(rings, s, q));
            let overlap = rp + rq + margin_mm - distance;
            let apart = sq - sp > std::f64::consts::FRAC_PI_2 * (rp + rq);
            if apart && overlap > floor_mm && best.is_none_or(|b| overlap > b.overlap) {
                best = Some(Touch { overlap, p, q });
            }
        }
        deepest.push(best);
    }
    deepest
}

/// How far each segment of a tube along `centres`, of radius `radii_mm` at
/// each, comes within `margin_mm` of passing through another stretch of
/// itself (mm, 0 where it keeps clear): one value per segment, the deepest,
/// for a design that must keep clear of itself (the objective's and the
/// refine's clearance). Continuous in the centres; the deepest partner may
/// change.
pub fn clearance_overlaps(centres: &[Point], radii_mm: &[f64], margin_mm: f64) -> Vec<f64> {
    let rings: Vec<Ring> = (centres.iter().zip(radii_mm))
        .map(|(&centre, &radius)| Ring {
            y: 0.0,
            centre,
            radius,
        })
        .collect();
    let s = cumulative_length(centres);
    (deepest_touches(&rings, &s, margin_mm, 0.0).iter())
        .map(|t| t.map_or(0.0, |t| t.overlap))
        .collect()
}

/// Every contact of the tube described by `rings` (base to tip), deepest
/// point per contact, ordered along the tube.
pub fn self_contacts(rings: &[Ring]) -> Vec<SelfContact> {
    let centres: Vec<Point> = rings.iter().map(|r| r.centre).collect();
    let s = cumulative_length(&centres);
    let at = |p: OnTube| along(rings, &s, p);
    let deepest = deepest_touches(rings, &s, 0.0, TOUCHING_MM);
    // Consecutive segments in contact with one stretch make one contact
    // (the partner moving on by less than twice the radii between them);
    // its deepest point.
    let same = |a: &Option<Touch>, b: &Option<Touch>| match (a, b) {
        (Some(a), Some(b)) => {
            let ((sa, _, ra), (sb, _, rb)) = (at(a.q), at(b.q));
            (sb - sa).abs() < 2.0 * (ra + rb)
        }
        (None, None) => true,
        _ => false,
    };
    let mut contacts = Vec::new();
    for run in deepest.chunk_by(same) {
        let Some(touch) = run
            .iter()
            .flatten()
            .max_by(|a, b| a.overlap.total_cmp(&b.overlap))
        else {
            continue;
        };
        let ((sp, yp, _), (sq, yq, _)) = (at(touch.p), at(touch.q));
        contacts.push(SelfContact {
            s_mm: [sp, sq],
            y_mm: [yp, yq],
            overlap_mm: touch.overlap,
        });
    }
    contacts
}

/// The closest points of segments `a` and `b`: their parameters in [0, 1]
/// and the distance between them (the clamped solution of the 2×2 normal
/// equations; Ericson, Real-Time Collision Detection, §5.1.9).
pub(crate) fn closest(a: [Point; 2], b: [Point; 2]) -> (f64, f64, f64) {
    let (d1, d2, r) = (a[1] - a[0], b[1] - b[0], a[0] - b[0]);
    let (aa, ee, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&r));
    let (c, bb) = (d1.dot(&r), d1.dot(&d2));
    let (mut s, mut t);
    if aa <= f64::EPSILON && ee <= f64::EPSILON {
        (s, t) = (0.0, 0.0);
    } else if aa <= f64::EPSILON {
        (s, t) = (0.0, (f / ee).clamp(0.0, 1.0));
    } else if ee <= f64::EPSILON {
        (s, t) = ((-c / aa).clamp(0.0, 1.0), 0.0);
    } else {
        let denom = aa * ee - bb * bb;
        s = match denom > 0.0 {
            true => ((bb * f - c * ee) / denom).clamp(0.0, 1.0),
            false => 0.0,
        };
        t = (bb * s + f) / ee;
        if t < 0.0 {
            (s, t) = ((-c / aa).clamp(0.0, 1.0), 0.0);
        } else if t > 1.0 {
            (s, t) = (((bb - c) / aa).clamp(0.0, 1.0), 1.0);
        }
    }
    let distance = ((a[0] + d1 * s) - (b[0] + d2 * t)).norm();
    (s, t, distance)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// Rings of radius `radius` along `f(u)`, u in [0, 1], at `count`
    /// material positions 1 mm apart.
    fn tube(count: usize, radius: f64, f: impl Fn(f64) -> Point) -> Vec<Ring> {
        (0..count)
            .map(|i| Ring {
                y: i as f64,
                centre: f(i as f64 / (count - 1) as f64),
                radius,
            })
            .collect()
    }

    fn helix(radius: f64, pitch: f64, turns: f64) -> impl Fn(f64) -> Point {
        move |u| {
            let a = TAU * turns * u;
            Point::new(radius * a.cos(), radius * a.sin(), pitch * turns * u)
        }
    }

    #[test]
    fn segments_closest_points_are_exact() {
        let x = |v: f64| Point::new(v, 0.0, 0.0);
        // Crossing at right angles, 2 apart.
        let (s, t, d) = closest(
            [x(-1.0), x(1.0)],
            [Point::new(0.0, -1.0, 2.0), Point::new(0.0, 1.0, 2.0)],
        );
        assert!((s - 0.5).abs() < 1e-12 && (t - 0.5).abs() < 1e-12 && (d - 2.0).abs() < 1e-12);
        // Parallel and offset along: the ends are closest.
        let (_, _, d) = closest([x(0.0), x(1.0)], [x(3.0), x(4.0)]);
        assert!((d - 2.0).abs() < 1e-12);
        // A point against a segment.
        let (s, _, d) = closest([x(0.0), x(2.0)], [Point::new(1.0, 1.0, 0.0); 2]);
        assert!((s - 0.5).abs() < 1e-12 && (d - 1.0).abs() < 1e-12);
    }

    /// A helix whose pitch (12 mm) is less than the tube's diameter (16 mm)
    /// passes through itself by 4 mm between turns; one whose pitch is more
    /// (40 mm) does not, nor does a straight tube or a hairpin as tight as
    /// the tube allows (its legs touch, radius r, 2r apart).
    #[test]
    fn overlapping_turns_are_found_and_bends_are_not() {
        let tight = self_contacts(&tube(400, 8.0, helix(30.0, 12.0, 3.0)));
        assert!(!tight.is_empty());
        for c in &tight {
            assert!((c.overlap_mm - 4.0).abs() < 0.2, "{c:?}");
            // A turn apart: 2π·30 mm of arc, and the material positions follow.
            let turn = (TAU * 30.0).hypot(12.0);
            assert!(((c.s_mm[1] - c.s_mm[0]) / turn - 1.0).abs() < 0.05, "{c:?}");
            assert!(c.y_mm[1] > c.y_mm[0]);
        }
        assert!(self_contacts(&tube(400, 8.0, helix(30.0, 40.0, 3.0))).is_empty());
        let straight = tube(100, 8.0, |u| Point::new(0.0, 0.0, 300.0 * u));
        assert!(self_contacts(&straight).is_empty());
        // Two legs joined by a half circle of radius 8 mm: the legs 16 mm apart.
        let r = 8.0;
        let hairpin = |u: f64| {
            let s = 300.0 * u;
            match s {
                s if s < 100.0 => Point::new(-r, 100.0 - s, 0.0),
                s if s < 100.0 + TAU * r / 2.0 => {
                    let a = (s - 100.0) / r;
                    Point::new(-r * a.cos(), -r * a.sin(), 0.0)
                }
                s => Point::new(r, s - 100.0 - TAU * r / 2.0, 0.0),
            }
        };
        assert!(self_contacts(&tube(600, r, hairpin)).is_empty());
        // The same hairpin on a fatter tube: the legs pass through each other.
        let fat = self_contacts(&tube(600, 10.0, hairpin));
        assert_eq!(fat.len(), 1, "{fat:?}");
        assert!((fat[0].overlap_mm - 4.0).abs() < 0.1, "{fat:?}");
    }

    /// The clearance residuals: the tight helix's every segment between
    /// turns is 4 mm through the next turn, 4.5 mm within a 0.5 mm margin;
    /// the loose helix is clear even with the margin; and the overlaps
    /// change continuously as the pitch opens (no jump where a segment
    /// comes clear).
    #[test]
    fn clearance_overlaps_measure_every_segment_and_change_continuously() {
        let centres = |pitch: f64| -> Vec<Point> {
            let f = helix(30.0, pitch, 3.0);
            (0..400).map(|i| f(i as f64 / 399.0)).collect()
        };
        let radii = [8.0; 400];
        let tight = clearance_overlaps(&centres(12.0), &radii, 0.5);
        assert_eq!(tight.len(), 399);
        // The first two turns' segments have a turn after them.
        let inner = &tight[..250];
        assert!(inner.iter().all(|d| (d - 4.5).abs() < 0.2), "{inner:?}");
        assert!(
            clearance_overlaps(&centres(40.0), &radii, 0.5)
                .iter()
                .all(|&d| d == 0.0)
        );
        // Pitch 16.4–16.5 mm: the turns' surfaces 0.4–0.5 mm apart, within
        // the 0.5 mm margin, the overlap falling evenly; 17.1 mm: clear.
        let total = |pitch| {
            clearance_overlaps(&centres(pitch), &radii, 0.5)
                .iter()
                .sum::<f64>()
        };
        let (a, b, c) = (total(16.4), total(16.45), total(16.5));
        assert!(a > b && b > c && c > 0.0, "{a} {b} {c}");
        assert!((a - b - (b - c)).abs() < 0.05 * (a - c), "{a} {b} {c}");
        assert_eq!(total(17.1), 0.0);
    }
}
