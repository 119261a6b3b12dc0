//! Orthonormal frames along a curve.
//!
//! The Frenet frame (T, N, B) follows the curve's bending and is undefined where
//! κ = 0. The Bishop (rotation-minimising) frame (T, U₁, U₂) exists everywhere and
//! does not spin about T: it is the material frame of an untwisted rod, which is
//! what a bare balloon segment is. The angle of N in the Bishop frame therefore
//! tells where around the balloon the bending happens; its rate of change is τ.

use super::{Analysis, Point};

/// A right-handed orthonormal frame: `first × second = tangent`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub tangent: Point,
    /// Frenet: the normal N. Bishop: U₁.
    pub first: Point,
    /// Frenet: the binormal B. Bishop: U₂.
    pub second: Point,
}

/// Frenet frames. Where the normal is undefined (κ below the floor) the last
/// defined normal is carried over, projected normal to the tangent; before the
/// first defined sample the Bishop frame stands in. Which frames the curve itself
/// defines is `analysis.torsion_defined`.
pub fn frenet_frames(analysis: &Analysis) -> Vec<Frame> {
    let bishop = bishop_frames(analysis);
    let mut frames = Vec::with_capacity(analysis.len());
    let mut carried: Option<Point> = None;
    for (i, bishop_frame) in bishop.iter().enumerate() {
        let t = analysis.tangent[i];
        let normal = if analysis.torsion_defined[i] {
            analysis.binormal[i].cross(&t)
        } else {
            carried
                .map(|n| n - t * t.dot(&n))
                .filter(|n| n.norm() > 1e-8)
                .map(|n| n.normalize())
                .unwrap_or(bishop_frame.first)
        };
        carried = Some(normal);
        frames.push(Frame {
            tangent: t,
            first: normal,
            second: t.cross(&normal),
        });
    }
    frames
}

/// Rotation-minimising frames by the double-reflection method (Wang, Jüttler,
/// Zheng & Liu, ACM TOG 27(1), 2008), started from the axis least aligned with the
/// first tangent.
pub fn bishop_frames(analysis: &Analysis) -> Vec<Frame> {
    let n = analysis.len();
    let mut frames = Vec::with_capacity(n);
    if n == 0 {
        return frames;
    }
    let t0 = analysis.tangent[0];
    let seed = least_aligned_axis(&t0);
    let u0 = (seed - t0 * t0.dot(&seed)).normalize();
    frames.push(Frame {
        tangent: t0,
        first: u0,
        second: t0.cross(&u0),
    });
    for i in 1..n {
        let prev = frames[i - 1];
        let t = analysis.tangent[i];
        let chord = analysis.position[i] - analysis.position[i - 1];
        let u = reflect_transport(&prev, chord, t);
        frames.push(Frame {
            tangent: t,
            first: u,
            second: t.cross(&u),
        });
    }
    frames
}

/// One double-reflection step: mirror the previous frame in the plane normal to
/// the chord, then in the plane that maps the mirrored tangent onto the new one.
fn reflect_transport(prev: &Frame, chord: Point, t: Point) -> Point {
    let c1 = chord.dot(&chord);
    if c1 < 1e-300 {
        return prev.first;
    }
    let u_l = prev.first - chord * (2.0 / c1) * chord.dot(&prev.first);
    let t_l = prev.tangent - chord * (2.0 / c1) * chord.dot(&prev.tangent);
    let v2 = t - t_l;
    let c2 = v2.dot(&v2);
    let u = if c2 < 1e-300 {
        u_l
    } else {
        u_l - v2 * (2.0 / c2) * v2.dot(&u_l)
    };
    // Re-orthonormalise against drift over long curves.
    (u - t * t.dot(&u)).normalize()
}

fn least_aligned_axis(t: &Point) -> Point {
    let a = t.abs();
    if a.x <= a.y && a.x <= a.z {
        Point::x()
    } else if a.y <= a.z {
        Point::y()
    } else {
        Point::z()
    }
}
