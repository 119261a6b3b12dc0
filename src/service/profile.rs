//! A balloon profile's content: the balloon and the patch as a design takes
//! them (what a calibration's options.json holds). The HTTP resource is
//! `balloons.rs`; a calibration job's ending writes one.

use patchwork_core::design::{Balloon, PatchSpec};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    pub balloon: Balloon,
    #[serde(default)]
    pub patch: PatchSpec,
}
