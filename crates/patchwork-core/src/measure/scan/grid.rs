//! A spatial hash of points in cubic cells: the points near a place are in
//! the few cells around it, and voxel downsampling is one pass over it.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::curve::Point;

/// A cell's integer coordinates.
pub type Key = [i64; 3];

/// Multiply-and-rotate hashing of the three cell coordinates (the cells of
/// a scan are millions; SipHash's strength is not needed here).
#[derive(Default)]
pub struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_i64(&mut self, value: i64) {
        self.write_u64(value as u64);
    }
    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(23) ^ value).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

type Cells = HashMap<Key, Vec<u32>, BuildHasherDefault<CellHasher>>;

/// The points' indices bucketed by cell of side `cell` (mm).
pub struct Grid {
    cell: f64,
    cells: Cells,
}

impl Grid {
    pub fn new(points: &[Point], cell: f64) -> Grid {
        let mut cells = Cells::default();
        for (i, p) in points.iter().enumerate() {
            cells.entry(key(p, cell)).or_default().push(i as u32);
        }
        Grid { cell, cells }
    }

    /// The cells, each with the indices of its points.
    pub fn cells(&self) -> impl Iterator<Item = (&Key, &Vec<u32>)> {
        self.cells.iter()
    }

    /// The indices of the `points` (those the grid was built on) within
    /// `radius` of `centre`, appended to `found`.
    pub fn within(&self, points: &[Point], centre: &Point, radius: f64, found: &mut Vec<u32>) {
        let reach = (radius / self.cell).ceil() as i64;
        let middle = key(centre, self.cell);
        let r2 = radius * radius;
        for dx in -reach..=reach {
            for dy in -reach..=reach {
                for dz in -reach..=reach {
                    let k = [middle[0] + dx, middle[1] + dy, middle[2] + dz];
                    let Some(members) = self.cells.get(&k) else {
                        continue;
                    };
                    found.extend(
                        members
                            .iter()
                            .filter(|&&i| (points[i as usize] - centre).norm_squared() <= r2),
                    );
                }
            }
        }
    }
}

/// The cell holding `p`.
pub fn key(p: &Point, cell: f64) -> Key {
    [
        (p.x / cell).floor() as i64,
        (p.y / cell).floor() as i64,
        (p.z / cell).floor() as i64,
    ]
}

/// Voxel downsampling: the centroid of the points in each occupied cell of
/// side `cell`, and for every point the index of its voxel's centroid.
pub fn voxel_centroids(points: &[Point], cell: f64) -> (Vec<Point>, Vec<u32>) {
    let grid = Grid::new(points, cell);
    let mut centroids = Vec::with_capacity(grid.cells.len());
    let mut voxel_of = vec![0u32; points.len()];
    // In a fixed order (the cells' keys sorted), so that results do not
    // depend on the hash map's iteration order.
    let mut cells: Vec<(&Key, &Vec<u32>)> = grid.cells().collect();
    cells.sort_unstable_by_key(|(k, _)| **k);
    for (_, members) in cells {
        let sum: Point = members.iter().map(|&i| points[i as usize]).sum();
        for &i in members {
            voxel_of[i as usize] = centroids.len() as u32;
        }
        centroids.push(sum / members.len() as f64);
    }
    (centroids, voxel_of)
}
