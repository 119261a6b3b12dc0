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
    /// Search on 3 mm rings, refine and verify on 1 mm: a quick look.
    Draft,
    /// Search on 2 mm elements (600 evaluations), refine and verify on 1 mm.
    #[default]
    Standard,
    /// Draft's search, then the refine on a uniform 0.5 mm mesh, which is
    /// also the verification. (It used to search 1 200 evaluations on the
    /// graded 1 mm model: over two hours for the Hilbert curve here, and 351
    /// evaluations did not beat the KSA seed once; then a CMA-ES polish of
    /// 120 on the 0.5 mm mesh, 14 minutes, which bought nothing there.)
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
    /// dearer, which no search can afford (fine's refine pays it).
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

    /// Solves of the refine (Levenberg–Marquardt on the shape error on the
    /// verification model): about three Gauss–Newton iterations for the
    /// Hilbert curve's 30 variables, ten for a two-patch design (it stops
    /// earlier once a step gains under 0.1 %). Fine's model is the uniform
    /// 0.5 mm mesh, where each solve costs several times more and the shape
    /// error can go further down.
    pub fn refine_budget(self) -> usize {
        match self {
            Fidelity::Draft | Fidelity::Standard => 120,
            Fidelity::Fine => 240,
        }
    }

    /// Sets the search and verification meshes and the refine budget of
    /// `request` for its balloon (set `request.base` first; the search
    /// budget is the caller's choice). No preset runs the CMA-ES polish: on
    /// ten round trips a polish of 120 evaluations reached a median shape
    /// error of 0.28 % with 9 of 10 under 0.5 %, a refine of 60 solves
    /// 0.06 % with 10 of 10 in a quarter of the time (BENCHMARKS.md); a
    /// caller asks for one through `polish_budget`.
    pub fn apply(self, request: &mut DesignRequest) {
        (request.search_mesh, request.verify_mesh) = self.meshes(request.base.balloon.radius_mm);
        request.refine_budget = self.refine_budget();
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
