//! Reach tables kept between design runs (`inverse::memo`): a table costs
//! 21 solves on the verification mesh (about two seconds on two cores, a
//! fifth of a short `draft` design).

use crate::design::Design;
use crate::fe::{SimulateError, SimulateOptions};

use super::super::memo::{Kept, scene_key};
use super::super::variables::VariableBounds;
use super::table::ReachTable;

/// The reach tables this process keeps.
pub static KEPT: Kept<ReachTable> = Kept::new();

/// What a table for `base`'s scene within `bounds` on `model` is computed
/// from, written out: the scene without its patches or length, the bounds,
/// the model (less its thread count and time limits, which do not change a
/// complete table) and the grid.
pub fn key(base: &Design, bounds: &VariableBounds, model: &SimulateOptions) -> String {
    scene_key(
        "reach table 1",
        base,
        bounds,
        model,
        &ReachTable::grid(bounds),
    )
}

/// The table under `key`: kept in memory, else from the store, else
/// `compute`d (and kept where complete).
pub fn table_for(
    key: &str,
    compute: impl FnOnce() -> Result<ReachTable, SimulateError>,
    complete: impl Fn(&ReachTable) -> bool,
) -> Result<ReachTable, SimulateError> {
    KEPT.table_for(key, compute, complete)
}

#[cfg(test)]
#[path = "memo_tests.rs"]
mod tests;
