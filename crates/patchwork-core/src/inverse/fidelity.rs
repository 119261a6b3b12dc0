//! Named fidelity presets: the element sizes of the search and verification
//! models, the default evaluation budgets and the final refine. The time and error each costs on
//! the reference curves are measured in BENCHMARKS.md.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::pipeline::{DesignRequest, FinalRefine};
use crate::fe::mesh::MeshSpec;
use crate::fe::newton::NewtonOptions;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// Search on 3 mm rings, refine on graded 1 mm corrected by graded
    /// 0.5 mm, verify on graded 0.5 mm: a quick look.
    Draft,
    /// Draft's run, then a short final refine on the uniform 0.5 mm mesh
    /// (the rest of 75 solves), which also verifies. (Until the twelfth
    /// session standard searched 600
    /// evaluations on graded 2 mm and then ran as draft: that search beat
    /// draft's on none of the six bench curves, for twice the time.)
    #[default]
    Standard,
    /// Draft's run (search, corrected refine of 60 solves), then a final
    /// refine on the uniform 0.5 mm mesh with the rest of its 240 solves,
    /// which also verifies. (Until the twelfth session fine refined on the
    /// uniform mesh straight from the search's design: its refine stopped
    /// at a local minimum on the pancake and the spring, 0.70 and 1.69 %
    /// where draft reached 0.65 and 1.24 %. Before that it searched 1 200
    /// evaluations on the graded 1 mm model: over two hours for the Hilbert
    /// curve here.)
    Fine,
}

impl Fidelity {
    pub const NAMES: [&'static str; 3] = ["draft", "standard", "fine"];

    /// Meshes of the search and the verification model for a balloon of
    /// radius `radius_mm`, the same in every preset (standard's and fine's
    /// final refine has its own, uniform 0.5 mm). Both are graded (fine
    /// under patches and at the ends, coarse along bare stretches: no loss
    /// of accuracy there, most of a sparse balloon's unknowns saved). The
    /// search mesh (draft's, which every preset now uses) keeps the 2 mm
    /// cross-section (10 sides on the reference balloon): a 1 mm section is
    /// more accurate but makes each factorisation about 5× dearer, which no
    /// search can afford (the final refine pays it).
    pub fn meshes(self, radius_mm: f64) -> (MeshSpec, MeshSpec) {
        let draft_search = MeshSpec {
            element_mm: 3.0,
            around: Some(MeshSpec::around_for(radius_mm, 2.0)),
            straight_mm: Some(6.0),
        };
        // The presets differ only in their refine (`refine_budget`,
        // `final_refine`).
        (draft_search, MeshSpec::graded(1.0, 4.0))
    }

    /// Default forward evaluations of the search (every preset's).
    pub fn budget(self) -> usize {
        200
    }

    /// Evaluations the search may go without improving its best before it
    /// ends (`DesignRequest::search_patience`): every preset's 200-
    /// evaluation search stops after 80 such. On the Hilbert curve and the
    /// pancake the search never beats the KSA seed (80 evaluations instead
    /// of 200, same design); on the spring its improvements come at 49, 65
    /// and 97 evaluations.
    pub fn search_patience(self) -> usize {
        80
    }

    /// Solves of the refine (Levenberg–Marquardt on the shape error on the
    /// verification model, Broyden-updated between Jacobians from
    /// linearised responses, each counted as one solve; it stops earlier
    /// once a fresh Jacobian's step gains under 0.1 %). Draft takes 60.
    /// (With forward-difference Jacobians, 31 solves each on the Hilbert
    /// curve, 60 was one Jacobian and about 25 steps, and 120 bought
    /// 0.155 → 0.146 % on the Hilbert curve and nothing on the pancake and
    /// the spring; since the thirteenth session the same 60 are mostly
    /// steps.) Standard (75) and fine (240) spend 60 as draft does and the
    /// rest on the uniform 0.5 mm mesh, where each solve costs several times
    /// more and the shape error can go further down: standard about 15,
    /// fine until a fresh Jacobian's step gains under 0.1 %. Standard's 15
    /// were 30 until cheap Jacobians let the final refine go on where a
    /// forward-difference Jacobian no longer fitted its budget: 30 then
    /// took the Hilbert curve from 37 to 54 s and the pancake from 62 to
    /// 87 s for the same shape error; 15 take 45 and 61 s, again for the
    /// same error (medians of three, BENCHMARKS.md).
    pub fn refine_budget(self) -> usize {
        match self {
            Fidelity::Draft => 60,
            Fidelity::Standard => 75,
            Fidelity::Fine => 240,
        }
    }

    /// The finer model that corrects the refine and verifies its result
    /// (`correction.rs`): graded 0.5 mm (fine under patches and at the ends,
    /// 4 mm bare stretches), in every preset. On the Hilbert curve the
    /// correction takes draft from 0.33 % to 0.13 % on the uniform 0.5 mm
    /// model for four finer solves (three rounds; medians of three,
    /// BENCHMARKS.md).
    pub fn correction_mesh(self) -> Option<MeshSpec> {
        Some(MeshSpec::graded(0.5, 4.0))
    }

    /// Standard's and fine's last stage: after draft's corrected refine
    /// (its first 60 solves), the refine on the uniform 0.5 mm mesh with the
    /// rest of the budget, from draft's result and its Jacobian.
    pub fn final_refine(self) -> Option<FinalRefine> {
        match self {
            Fidelity::Standard | Fidelity::Fine => Some(FinalRefine {
                mesh: MeshSpec::uniform(0.5),
                staging_solves: Fidelity::Draft.refine_budget(),
                newton: NewtonOptions::default(),
            }),
            Fidelity::Draft => None,
        }
    }

    /// Sets the search, verification and correction meshes, the search's
    /// patience, the refine budget and the final refine of `request` for
    /// its balloon (set `request.base` first; the search budget is the
    /// caller's choice). No preset runs the CMA-ES polish: on
    /// ten round trips a polish of 120 evaluations reached a median shape
    /// error of 0.28 % with 9 of 10 under 0.5 %, a refine of 60 solves
    /// 0.06 % with 10 of 10 in a quarter of the time (BENCHMARKS.md); a
    /// caller asks for one through `polish_budget`.
    pub fn apply(self, request: &mut DesignRequest) {
        (request.search_mesh, request.verify_mesh) = self.meshes(request.base.balloon.radius_mm);
        request.refine_budget = self.refine_budget();
        request.search_patience = self.search_patience();
        request.correction_mesh = self.correction_mesh();
        request.final_refine = self.final_refine();
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
