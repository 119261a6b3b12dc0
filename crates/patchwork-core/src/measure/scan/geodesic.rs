//! Distances along the scanned surface: a graph joining every voxel
//! centroid to those within reach, its largest connected part, and
//! Dijkstra's shortest paths on it. On a tube, the distance from one end
//! grows along the tube whatever its shape: it orders the cross-sections.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::grid::Grid;
use crate::curve::Point;

/// Neighbours within reach, with the distance to each.
pub struct SurfaceGraph {
    edges: Vec<Vec<(u32, f64)>>,
}

impl SurfaceGraph {
    /// Every point joined to the points within `reach` (mm).
    pub fn new(points: &[Point], reach: f64) -> SurfaceGraph {
        let grid = Grid::new(points, reach);
        let mut found = Vec::new();
        let edges = points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                found.clear();
                grid.within(points, p, reach, &mut found);
                found
                    .iter()
                    .filter(|&&j| j as usize != i)
                    .map(|&j| (j, (points[j as usize] - p).norm()))
                    .collect()
            })
            .collect();
        SurfaceGraph { edges }
    }

    /// Shortest-path distances from `source` (infinite where unreached).
    pub fn distances(&self, source: usize) -> Vec<f64> {
        let mut distance = vec![f64::INFINITY; self.edges.len()];
        let mut queue = BinaryHeap::new();
        distance[source] = 0.0;
        queue.push(Entry(0.0, source as u32));
        while let Some(Entry(d, i)) = queue.pop() {
            if d > distance[i as usize] {
                continue;
            }
            for &(j, w) in &self.edges[i as usize] {
                let candidate = d + w;
                if candidate < distance[j as usize] {
                    distance[j as usize] = candidate;
                    queue.push(Entry(candidate, j));
                }
            }
        }
        distance
    }

    /// A point of the largest connected part (parts smaller than it are
    /// stray points: dust, the clamp, a reflection) and that part's size.
    pub fn largest_part(&self) -> (usize, usize) {
        let mut part = vec![usize::MAX; self.edges.len()];
        let mut best = (0, 0);
        for start in 0..self.edges.len() {
            if part[start] != usize::MAX {
                continue;
            }
            part[start] = start;
            let (mut stack, mut size) = (vec![start], 0);
            while let Some(i) = stack.pop() {
                size += 1;
                for &(j, _) in &self.edges[i] {
                    if part[j as usize] == usize::MAX {
                        part[j as usize] = start;
                        stack.push(j as usize);
                    }
                }
            }
            if size > best.1 {
                best = (start, size);
            }
        }
        best
    }
}

/// The farthest reached point of `distances`.
pub fn farthest(distances: &[f64]) -> usize {
    distances
        .iter()
        .enumerate()
        .filter(|(_, d)| d.is_finite())
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i)
}

/// A queue entry ordered by distance, nearest first.
#[derive(PartialEq)]
struct Entry(f64, u32);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
