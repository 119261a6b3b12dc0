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
    /// Search on 3 mm rings, verify on 1 mm: a quick look.
    Draft,
    /// Search on 2 mm elements, verify on 1 mm.
    #[default]
    Standard,
    /// Draft's search, then a polish of 120 evaluations on a uniform 0.5 mm
    /// mesh, which is also the verification. (It used to search 1 200
    /// evaluations on the graded 1 mm model: over two hours for the Hilbert
    /// curve here, and 351 evaluations did not beat the KSA seed once; the
    /// improvements measured come from polishing on the fine model.)
    Fine,
}

impl Fidelity {
    pub const NAMES: [&'static str; 3] = ["draft", "standard", "fine"];

    /// Meshes of the search and the verification model for a balloon of
    /// radius `radius_mm`. All but fine's verification are graded (fine under
    /// patches and at the ends, coarse along bare stretches: no loss of
    /// accuracy there, most of a sparse balloon's unknowns saved). The search
    /// meshes keep the 2 mm cross-section (10 sides on the reference balloon):
    /// a 1 mm section is more accurate but makes each factorisation about 5×
    /// dearer, which no search can afford (fine's polish pays it).
    pub fn meshes(self, radius_mm: f64) -> (MeshSpec, MeshSpec) {
        let draft_search = MeshSpec {
            element_mm: 3.0,
            around: Some(MeshSpec::around_for(radius_mm, 2.0)),
            straight_mm: Some(6.0),
        };
        match self {
            Fidelity::Draft => (draft_search, MeshSpec::graded(1.0, 4.0)),
            Fidelity::Standard => (MeshSpec::graded(2.0, 6.0), MeshSpec::graded(1.0, 4.0)),
            Fidelity::Fine => (draft_search, MeshSpec::uniform(0.5)),
        }
    }

    /// Default forward evaluations of the search.
    pub fn budget(self) -> usize {
        match self {
            Fidelity::Draft => 200,
            Fidelity::Standard => 600,
            Fidelity::Fine => 200,
        }
    }

    /// Evaluations of the coarse-to-fine polish on the verification model.
    /// Draft skips it to stay fast; with 60, draft's ten round trips reach a
    /// median shape error of 0.31 % instead of 0.55 %, and the Hilbert curve
    /// a median 1.15 % over three seeds instead of 1.24 %, at 1.1–1.4 times
    /// the time (BENCHMARKS.md).
    pub fn polish_budget(self) -> usize {
        match self {
            Fidelity::Draft => 0,
            Fidelity::Standard => 60,
            Fidelity::Fine => 120,
        }
    }

    /// Sets the search and verification meshes and the polish budget of
    /// `request` for its balloon (set `request.base` first; the search
    /// budget is the caller's choice).
    pub fn apply(self, request: &mut DesignRequest) {
        (request.search_mesh, request.verify_mesh) = self.meshes(request.base.balloon.radius_mm);
        request.polish_budget = self.polish_budget();
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
