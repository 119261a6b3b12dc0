//! Seeded random feasible designs for round trips with an unknown layout:
//! 4–12 patches on a 400 mm reference balloon, single patches and trains of
//! 2–5 adjacent patches 2–4 mm apart whose widths and angles are graded
//! along the train and whose X follows the inclined patches round the tube.
//! The first design of a set opens with a five-patch train at 20–30°, which
//! makes a helix. Every patch lies within the default fabrication bounds
//! (H 12–28 mm, W 1.2–3 mm, |Θ| ≤ 35°).

use super::{Balloon, Design, Patch};
use crate::cmaes::rng::SeededRng;

/// The balloon length of every round-trip design (mm).
pub const ROUND_TRIP_BALLOON_MM: f64 = 400.0;

/// `count` designs from one seeded stream: the same seed gives the same
/// designs.
pub fn round_trip_designs(count: usize, seed: u64) -> Vec<Design> {
    let mut rng = SeededRng::new(seed);
    (0..count)
        .map(|i| Design {
            balloon: Balloon {
                length_mm: ROUND_TRIP_BALLOON_MM,
                ..Balloon::default()
            },
            ..Design::reference(random_layout(&mut rng, i == 0))
        })
        .collect()
}

/// A random layout of 4–12 patches (fewer if the balloon ends first).
fn random_layout(rng: &mut SeededRng, helix_first: bool) -> Vec<Patch> {
    let mut between = |lo: f64, hi: f64| lo + (hi - lo) * rng.uniform();
    let circumference = Balloon::default().circumference();
    let wanted = between(4.0, 12.99) as usize;
    let mut patches = Vec::new();
    let mut y = between(15.0, 30.0);
    let mut first = true;
    while patches.len() < wanted {
        let room = wanted - patches.len();
        let helix = first && helix_first;
        let count = match (helix, between(0.0, 1.0) < 0.4) {
            (true, _) => 5,
            (false, true) => 1,
            (false, false) => between(2.0, 5.99).min(room as f64) as usize,
        };
        let (h, gap) = (between(12.0, 28.0), between(2.0, 4.0));
        let (w0, w1) = (between(1.2, 3.0), between(1.2, 3.0));
        let (t0, t1) = match helix {
            true => (between(20.0, 30.0), between(20.0, 30.0)),
            false => (between(-35.0, 35.0), between(-35.0, 35.0)),
        };
        let mut x = between(0.0, circumference);
        for i in 0..count {
            let f = match count {
                1 => 0.0,
                _ => i as f64 / (count - 1) as f64,
            };
            let theta: f64 = t0 + f * (t1 - t0);
            if y + h > ROUND_TRIP_BALLOON_MM - 10.0 {
                return patches;
            }
            patches.push(Patch {
                x_mm: x.rem_euclid(circumference),
                y_mm: y + 0.5 * h,
                h_mm: h,
                w_mm: w0 + f * (w1 - w0),
                theta_deg: theta,
            });
            // The next patch of the train starts where this one's end went
            // round the tube.
            x += (h + gap) * theta.to_radians().tan();
            y += h + gap;
        }
        y += between(15.0, 40.0);
        first = false;
    }
    patches
}

/// The layout's groups of adjacent patches (less than 5 mm apart along the
/// balloon), as their sizes: "5+1+3".
pub fn trains(patches: &[Patch]) -> String {
    let mut groups: Vec<usize> = Vec::new();
    for (i, p) in patches.iter().enumerate() {
        let joined = i > 0 && {
            let before = &patches[i - 1];
            p.y_mm - 0.5 * p.h_mm - (before.y_mm + 0.5 * before.h_mm) < 5.0
        };
        match (joined, groups.last_mut()) {
            (true, Some(last)) => *last += 1,
            _ => groups.push(1),
        }
    }
    groups
        .iter()
        .map(|g| g.to_string())
        .collect::<Vec<_>>()
        .join("+")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn designs_are_valid_seeded_and_varied() {
        let designs = round_trip_designs(10, 2027);
        assert_eq!(designs, round_trip_designs(10, 2027));
        for d in &designs {
            d.validate().expect("a valid design");
            assert!((1..=12).contains(&d.patches.len()), "{}", d.patches.len());
            for p in &d.patches {
                assert!((12.0..=28.0).contains(&p.h_mm) && (1.2..=3.0).contains(&p.w_mm));
                assert!(p.theta_deg.abs() <= 35.0);
            }
        }
        // The first opens with a five-patch helix train.
        assert!(trains(&designs[0].patches).starts_with('5'));
        assert!(designs[0].patches[..5].iter().all(|p| p.theta_deg >= 20.0));
        // Some design has a train and some a lone patch.
        let groups: Vec<String> = designs.iter().map(|d| trains(&d.patches)).collect();
        assert!(
            groups.iter().any(|g| g.split('+').any(|n| n == "1")),
            "{groups:?}"
        );
        assert!(
            groups
                .iter()
                .filter(|g| g.split('+').any(|n| n != "1"))
                .count()
                >= 3,
            "{groups:?}"
        );
    }

    #[test]
    fn trains_groups_adjacent_patches() {
        let patch = |y: f64| Patch {
            x_mm: 0.0,
            y_mm: y,
            h_mm: 10.0,
            w_mm: 2.0,
            theta_deg: 0.0,
        };
        // 3 mm gaps join; a 20 mm gap starts a new train.
        let patches = [patch(20.0), patch(33.0), patch(63.0)];
        assert_eq!(trains(&patches), "2+1");
        assert_eq!(trains(&[]), "");
    }
}
