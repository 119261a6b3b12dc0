//! Scans whose centreline is known: a tube swept along a helix and closed
//! by a hemisphere, scanned with noise and holes; a simulated balloon's
//! surface; shapes that are not tubes; the file formats.

use super::read::{ScanFormat, read_scan};
use super::*;
use crate::cmaes::SeededRng;
use crate::curve::{AnalysisOptions, Preset, Units, analyse, bishop_frames};

/// The distance from `p` to the polyline `axis`.
fn distance_to(axis: &[Point], p: &Point) -> f64 {
    axis.windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let t = ((p - w[0]).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (w[0] + d * t - p).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// `n` points on the tube of radius `r` around `axis`, closed at its end by
/// a hemisphere; Gaussian noise of 0.2 mm on each coordinate; the
/// points inside `holes` balls of radius r around random surface points
/// taken out (as a scanner misses); with the fraction of the surface
/// taken out.
fn scanned_tube(axis: &Curve, r: f64, n: usize, holes: usize, seed: u64) -> (Vec<Point>, f64) {
    let noise = 0.2;
    let analysis = analyse(axis, &AnalysisOptions::default());
    let frames = bishop_frames(&analysis);
    let mut rng = SeededRng::new(seed);
    let length = axis.length();
    let cap_area = 2.0 * std::f64::consts::PI * r * r;
    let tube_area = 2.0 * std::f64::consts::PI * r * length;
    let surface = |rng: &mut SeededRng| {
        let theta = std::f64::consts::TAU * rng.uniform();
        if rng.uniform() * (tube_area + cap_area) < tube_area {
            let s = length * rng.uniform();
            let k = analysis.s.partition_point(|&v| v < s).min(frames.len() - 1);
            let f = &frames[k];
            axis.point_at(s) + (f.first * theta.cos() + f.second * theta.sin()) * r
        } else {
            let f = &frames[frames.len() - 1];
            let z = rng.uniform(); // uniform in height: uniform area on a sphere
            let ring = (1.0 - z * z).sqrt() * r;
            axis.point_at(length)
                + f.tangent * (z * r)
                + (f.first * theta.cos() + f.second * theta.sin()) * ring
        }
    };
    let holes: Vec<Point> = (0..holes).map(|_| surface(&mut rng)).collect();
    let mut points = Vec::with_capacity(n);
    let mut missed = 0;
    while points.len() < n {
        let p = surface(&mut rng);
        if holes.iter().any(|h| (h - p).norm() < r) {
            missed += 1;
            continue;
        }
        let jitter = Point::new(rng.normal(), rng.normal(), rng.normal()) * noise;
        points.push(p + jitter);
    }
    (points, missed as f64 / (missed + n) as f64)
}

#[test]
fn a_scan_with_noise_and_a_fifth_missing_gives_the_axis_within_0_15_mm() {
    // A 16 mm tube along 1.2 turns of a helix (radius 60 mm, pitch 80 mm).
    let axis = Preset::helix(60.0, 80.0, 1.2).generate(2000).unwrap();
    let (points, missed) = scanned_tube(&axis, 16.0, 400_000, 12, 11);
    assert!(
        (0.15..0.25).contains(&missed),
        "{missed} of the surface missed"
    );
    let whole = centreline_from_scan(&points).unwrap();
    // Its cap is at the end nearer the helix's last point.
    let (base, tip) = (axis.points()[0], axis.points()[axis.len() - 1]);
    let last = Point::from(whole.centreline_mm[whole.centreline_mm.len() - 1]);
    let first = Point::from(whole.centreline_mm[0]);
    let scan = whole.base_to_tip((last - tip).norm() < (first - tip).norm(), None);
    let centreline = scan.curve().unwrap();
    let off: Vec<f64> = centreline
        .points()
        .iter()
        .map(|p| distance_to(axis.points(), p))
        .collect();
    let rms = (off.iter().map(|d| d * d).sum::<f64>() / off.len() as f64).sqrt();
    assert!(rms < 0.15, "RMS {rms} mm off the axis");
    // The cap cut where a hemisphere begins; the open base at its rim.
    let ends = [
        centreline.points()[0],
        centreline.points()[centreline.len() - 1],
    ];
    assert!(
        (ends[1] - tip).norm() < 1.5,
        "tip {}",
        (ends[1] - tip).norm()
    );
    assert!(
        (ends[0] - base).norm() < 0.5,
        "base {}",
        (ends[0] - base).norm()
    );
    let mut radii = scan.radius_mm.clone();
    radii.sort_by(f64::total_cmp);
    assert!(
        (radii[radii.len() / 2] - 16.0).abs() < 0.1,
        "{}",
        radii[radii.len() / 2]
    );
    assert!(
        (scan.section_residual_mm - 0.2).abs() < 0.1,
        "{}",
        scan.section_residual_mm
    );
}

#[test]
fn what_is_not_a_tube_is_refused_saying_so() {
    let mut rng = SeededRng::new(5);
    let ball: Vec<Point> = (0..5000)
        .map(|_| Point::new(rng.normal(), rng.normal(), rng.normal()).normalize() * 20.0)
        .collect();
    let error = centreline_from_scan(&ball).unwrap_err();
    assert!(matches!(error, ScanError::NotATube(_)), "{error}");
    let plane: Vec<Point> = (0..5000)
        .map(|_| Point::new(100.0 * rng.uniform(), 100.0 * rng.uniform(), 0.0))
        .collect();
    let error = centreline_from_scan(&plane).unwrap_err();
    assert!(matches!(error, ScanError::NotATube(_)), "{error}");
    let few = vec![Point::zeros(); 10];
    assert_eq!(
        centreline_from_scan(&few).unwrap_err(),
        ScanError::TooFewPoints { found: 10 }
    );
}

#[test]
fn every_format_reads_the_same_points_and_meshes_are_sampled_over_their_faces() {
    let points = [[0.0, 1.0, 2.0], [3.5, -4.0, 5.25], [6.0, 7.0, -8.5]];
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n";
    let rows: String = points
        .iter()
        .map(|p| format!("{} {} {} 200\n", p[0], p[1], p[2]))
        .collect();
    let ply = format!("{header}end_header\n{rows}");
    let ply_mesh = format!(
        "{header}element face 1\nproperty list uchar int vertex_indices\nend_header\n{rows}3 0 1 2\n"
    );
    let xyz: String = points
        .iter()
        .map(|p| format!("{},{},{},0.1,0.2,0.3\n", p[0], p[1], p[2]))
        .collect();
    let obj: String = points
        .iter()
        .map(|p| format!("v {} {} {}\n", p[0], p[1], p[2]))
        .collect();
    let obj_mesh = obj.clone() + "f 1 2 3\n";
    let triangle = stl_io::Triangle {
        normal: stl_io::Normal::new([0.0, 0.0, 1.0]),
        vertices: points.map(|p| stl_io::Vertex::new(p.map(|v| v as f32))),
    };
    let mut stl = Vec::new();
    stl_io::write_stl(&mut stl, [triangle].iter()).unwrap();
    let expected: Vec<Point> = points.iter().map(|p| Point::from(*p)).collect();
    for (bytes, format) in [
        (ply.as_bytes(), ScanFormat::Ply),
        (xyz.as_bytes(), ScanFormat::Xyz),
        (obj.as_bytes(), ScanFormat::Obj),
    ] {
        let read = read_scan(bytes, format, Units::Mm).unwrap();
        assert_eq!(read, expected, "{format:?}");
    }
    // A mesh: points over its one triangle, on its plane, inside it.
    let (a, b, c) = (expected[0], expected[1], expected[2]);
    let normal = (b - a).cross(&(c - a)).normalize();
    for (bytes, format) in [
        (ply_mesh.as_bytes(), ScanFormat::Ply),
        (obj_mesh.as_bytes(), ScanFormat::Obj),
        (&stl[..], ScanFormat::Stl),
    ] {
        let read = read_scan(bytes, format, Units::Mm).unwrap();
        assert_eq!(read.len(), 300_000, "{format:?}");
        let inside = |p: &Point| {
            let area = |u: &Point, v: &Point| (u - p).cross(&(v - p)).norm();
            let whole = (b - a).cross(&(c - a)).norm();
            (area(&a, &b) + area(&b, &c) + area(&c, &a) - whole).abs() < 1e-4 * whole
        };
        assert!(
            read.iter()
                .all(|p| (p - a).dot(&normal).abs() < 1e-4 && inside(p)),
            "{format:?}"
        );
    }
    let in_cm = read_scan(xyz.as_bytes(), ScanFormat::Xyz, Units::Cm).unwrap();
    assert_eq!(in_cm[1], expected[1] * 10.0);
    assert_eq!(ScanFormat::from_name("scan.PLY"), Some(ScanFormat::Ply));
    assert_eq!(ScanFormat::from_name("points.csv"), None);
    let error = read_scan(b"1,2\n", ScanFormat::Xyz, Units::Mm).unwrap_err();
    assert!(error.to_string().contains("line 1"), "{error}");
    let error = read_scan(
        b"ply\nformat ascii 1.0\nend_header\n",
        ScanFormat::Ply,
        Units::Mm,
    )
    .unwrap_err();
    assert!(error.to_string().contains("vertex"), "{error}");
    let dangling = format!(
        "{header}element face 1\nproperty list uchar int vertex_indices\nend_header\n{rows}3 0 1 7\n"
    );
    let error = read_scan(dangling.as_bytes(), ScanFormat::Ply, Units::Mm).unwrap_err();
    assert!(error.to_string().contains("vertex 7 of 3"), "{error}");
}

#[test]
fn no_bytes_make_a_reader_panic() {
    let mut rng = SeededRng::new(17);
    let binary_header = b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\nproperty float z\nelement face 10\nproperty list uchar int vertex_indices\nend_header\n";
    for round in 0..200 {
        let length = (rng.uniform() * 400.0) as usize;
        let noise: Vec<u8> = (0..length).map(|_| (rng.next_u64() & 0xff) as u8).collect();
        let mut truncated = binary_header.to_vec();
        truncated.extend(&noise);
        for format in [
            ScanFormat::Ply,
            ScanFormat::Obj,
            ScanFormat::Stl,
            ScanFormat::Xyz,
        ] {
            for bytes in [&noise[..], &truncated[..]] {
                // Errors are fine; a panic or non-finite points are not.
                if let Ok(points) = read_scan(bytes, format, Units::Mm) {
                    let finite = points.iter().all(|p| p.iter().all(|v| v.is_finite()));
                    let rejected = centreline_from_scan(&points).is_err();
                    assert!(finite || rejected, "round {round}, {format:?}");
                }
            }
        }
    }
}
