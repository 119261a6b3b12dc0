//! Why a design's shape error stayed high: every design more than
//! `HIGH_ERROR_PERCENT` of its length off the target it aimed at says which
//! of the known causes apply, so that no miss is silent.

use serde::{Deserialize, Serialize};

use super::layout::LayoutTrial;
use super::limits::AtLimit;
use super::reach::ReachReport;

/// A shape error above this (% of the target's length) is explained: twice
/// the median goal for curves within reach, and above the worst of the
/// curve suite within reach under `draft` (BENCHMARKS.md).
pub const HIGH_ERROR_PERCENT: f64 = 1.0;

/// One cause of a high shape error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "cause", rename_all = "snake_case")]
pub enum Shortfall {
    /// The target bends or twists more than a patch within the bounds
    /// makes over these stretches (`reach`).
    OutOfReach { stretches: usize },
    /// Patches sit on fabrication limits (`at_limits`): the bounds stop
    /// what the target asks for.
    AtLimits { patches: usize },
    /// The search's evaluation budget ran out before it settled: a larger
    /// `--budget` (or `standard`) may do better.
    BudgetSpent,
    /// Every layout tried (KSA's, and patches on gentle bends) was refined
    /// and none came lower (`layouts`).
    LayoutsExhausted { tried: usize },
    /// The design has no patch: no layout marked a bend on the target.
    NoPatches,
    /// The robust refine traded shape error for a smaller spread
    /// (`robust`): the nominal design's shape error was `nominal_percent`.
    Robust { nominal_percent: f64 },
    /// The run's time limit cut it short (`time_limited`): a longer limit
    /// may do better.
    TimeLimit { limit_s: f64 },
    /// None of the above: the search settled in a local optimum.
    Settled,
}

impl Shortfall {
    /// The cause in words, for the CLI and the web app.
    pub fn message(&self) -> String {
        match self {
            Shortfall::OutOfReach { stretches } => format!(
                "the target bends or twists beyond what one patch makes over {stretches} stretch(es) (see reach)"
            ),
            Shortfall::AtLimits { patches } => format!(
                "{patches} patch(es) on a fabrication limit (relax the bounds if the fabrication allows)"
            ),
            Shortfall::BudgetSpent => {
                "the search's budget ran out (a larger budget or the standard fidelity may do better)"
                    .into()
            }
            Shortfall::LayoutsExhausted { tried } => {
                format!("the {tried} layouts tried reached no lower")
            }
            Shortfall::NoPatches => "no layout marked a bend for a patch".into(),
            Shortfall::Robust { nominal_percent } => format!(
                "the robust design trades shape error for a smaller spread (the nominal design's was {nominal_percent:.2} %; see robust)"
            ),
            Shortfall::TimeLimit { limit_s } => format!(
                "the run's time limit ({limit_s} s) cut it short (a longer limit may do better; see time_limited)"
            ),
            Shortfall::Settled => {
                "the search settled in a local optimum (another seed may do better)".into()
            }
        }
    }
}

/// A cause with its message, as design.json and the API carry it: every
/// reader shows the same words.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Explained {
    #[serde(flatten)]
    pub cause: Shortfall,
    pub message: String,
}

impl From<&Shortfall> for Explained {
    fn from(cause: &Shortfall) -> Explained {
        Explained {
            cause: cause.clone(),
            message: cause.message(),
        }
    }
}

/// What a finished run knows of itself, for [`shortfalls`].
pub struct RunFacts<'a> {
    pub shape_error_percent: f64,
    pub patches: usize,
    pub reach: Option<&'a ReachReport>,
    pub at_limits: &'a [AtLimit],
    /// The search ended on its evaluation budget.
    pub budget_spent: bool,
    pub layouts: &'a [LayoutTrial],
    /// The nominal design's shape error, where a robust design replaced it.
    pub robust_from_percent: Option<f64>,
    /// The time limit, where it cut the run short.
    pub time_limit_s: Option<f64>,
}

/// The causes of a shape error above `HIGH_ERROR_PERCENT`, most telling
/// first; empty when the error is not high.
pub fn shortfalls(run: &RunFacts<'_>) -> Vec<Shortfall> {
    if run.shape_error_percent.is_finite() && run.shape_error_percent <= HIGH_ERROR_PERCENT {
        return vec![];
    }
    let mut causes = Vec::new();
    if let Some(limit_s) = run.time_limit_s {
        causes.push(Shortfall::TimeLimit { limit_s });
    }
    if let Some(nominal) = run.robust_from_percent
        && nominal < run.shape_error_percent
    {
        causes.push(Shortfall::Robust {
            nominal_percent: nominal,
        });
    }
    if let Some(reach) = run.reach.filter(|r| !r.reachable()) {
        causes.push(Shortfall::OutOfReach {
            stretches: reach.out_of_reach.len(),
        });
    }
    if run.patches == 0 {
        causes.push(Shortfall::NoPatches);
    }
    let pinned = {
        let mut patches: Vec<usize> = run.at_limits.iter().map(|a| a.patch).collect();
        patches.dedup();
        patches.len()
    };
    if pinned > 0 {
        causes.push(Shortfall::AtLimits { patches: pinned });
    }
    if run.budget_spent && run.patches > 0 {
        causes.push(Shortfall::BudgetSpent);
    }
    if run.layouts.len() > 1 {
        causes.push(Shortfall::LayoutsExhausted {
            tried: run.layouts.len(),
        });
    }
    if causes.is_empty() {
        causes.push(Shortfall::Settled);
    }
    causes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts(error: f64, patches: usize, budget_spent: bool) -> RunFacts<'static> {
        RunFacts {
            shape_error_percent: error,
            patches,
            reach: None,
            at_limits: &[],
            budget_spent,
            layouts: &[],
            robust_from_percent: None,
            time_limit_s: None,
        }
    }

    #[test]
    fn a_low_error_needs_no_explanation_and_a_high_one_always_gets_one() {
        let stalled = false;
        assert!(shortfalls(&facts(0.4, 5, stalled)).is_empty());
        assert_eq!(
            shortfalls(&facts(3.0, 5, stalled)),
            vec![Shortfall::Settled]
        );
        assert_eq!(
            shortfalls(&facts(f64::INFINITY, 5, stalled)),
            vec![Shortfall::Settled]
        );
        let spent = true;
        assert_eq!(
            shortfalls(&facts(22.0, 0, spent)),
            vec![Shortfall::NoPatches]
        );
        assert_eq!(
            shortfalls(&facts(2.0, 4, spent)),
            vec![Shortfall::BudgetSpent]
        );
        let cut_short = RunFacts {
            time_limit_s: Some(30.0),
            ..facts(2.0, 4, spent)
        };
        assert_eq!(
            shortfalls(&cut_short),
            vec![
                Shortfall::TimeLimit { limit_s: 30.0 },
                Shortfall::BudgetSpent
            ]
        );
    }

    #[test]
    fn limits_and_layouts_are_counted() {
        let limit = |patch| AtLimit {
            patch,
            field: "h_mm".into(),
            value: 30.0,
            bound: "bounds.h_max_mm".into(),
            limit: 30.0,
            beyond: false,
        };
        let limits = [limit(1), limit(1), limit(3)];
        let trial = |chosen| LayoutTrial {
            layout: "KSA's (refined)".into(),
            patches: 3,
            shape_error_percent: 2.0,
            chosen,
        };
        let layouts = [trial(true), trial(false)];
        let run = RunFacts {
            at_limits: &limits,
            layouts: &layouts,
            ..facts(2.0, 3, false)
        };
        assert_eq!(
            shortfalls(&run),
            vec![
                Shortfall::AtLimits { patches: 2 },
                Shortfall::LayoutsExhausted { tried: 2 }
            ]
        );
    }
}
