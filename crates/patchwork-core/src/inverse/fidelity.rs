//! Named fidelity presets: the element sizes of the search and verification
//! models, and the default evaluation budget. The time and error each costs on
//! the reference curves are measured in BENCHMARKS.md.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::pipeline::DesignRequest;
use crate::fe::mesh::MeshSpec;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// Search on 3 mm elements, verify on 2 mm: a quick look.
    Draft,
    /// Search on 2 mm elements, verify on 1 mm.
    #[default]
    Standard,
    /// Search on 1 mm elements, verify on 0.5 mm.
    Fine,
}

impl Fidelity {
    pub const NAMES: [&'static str; 3] = ["draft", "standard", "fine"];

    /// Element sizes (mm) of the search and the verification model.
    pub fn element_sizes(self) -> (f64, f64) {
        match self {
            Fidelity::Draft => (3.0, 2.0),
            Fidelity::Standard => (2.0, 1.0),
            Fidelity::Fine => (1.0, 0.5),
        }
    }

    /// Default forward evaluations of the search.
    pub fn budget(self) -> usize {
        match self {
            Fidelity::Draft => 200,
            Fidelity::Standard => 600,
            Fidelity::Fine => 1200,
        }
    }

    /// Sets the meshes of `request` (its budget is the caller's choice).
    pub fn apply(self, request: &mut DesignRequest) {
        let (search, verify) = self.element_sizes();
        request.search_mesh = MeshSpec::uniform(search);
        request.verify_mesh = MeshSpec::uniform(verify);
    }
}

impl FromStr for Fidelity {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "draft" => Ok(Fidelity::Draft),
            "standard" => Ok(Fidelity::Standard),
            "fine" => Ok(Fidelity::Fine),
            _ => Err(format!(
                "unknown fidelity {text:?}: choose one of {}",
                Fidelity::NAMES.join(", ")
            )),
        }
    }
}
