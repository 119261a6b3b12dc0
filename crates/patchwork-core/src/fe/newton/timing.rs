//! Where a solve's time goes, for its statistics.

use std::time::{Duration, Instant};

/// Runs `work`, adding its wall time to `total`.
pub fn timed<T>(total: &mut Duration, work: impl FnOnce() -> T) -> T {
    let started = Instant::now();
    let result = work();
    *total += started.elapsed();
    result
}
