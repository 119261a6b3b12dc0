//! A run's time limit as a moment on the clock: what every stage and the
//! loops inside them (the search's generations, the refine's steps, the
//! layouts tried) check to stop at their next step once it has passed.

use std::time::{Duration, Instant};

/// When a run's time limit passes (`UserSettings::time_limit_s`): a
/// moment on this process's clock, or never. Copied into what loops
/// without the context (the refine's problem, the polish's scorer).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Deadline(Option<Instant>);

impl Deadline {
    /// `limit_s` after a run that started `earlier_s` ago (never without a
    /// limit).
    pub fn after(limit_s: Option<f64>, earlier_s: f64) -> Deadline {
        Deadline(
            limit_s.map(|limit| {
                Instant::now() + Duration::from_secs_f64((limit - earlier_s).max(0.0))
            }),
        )
    }

    pub fn passed(self) -> bool {
        self.0.is_some_and(|at| Instant::now() >= at)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_limit_never_passes_and_a_spent_one_has() {
        assert!(!Deadline::after(None, 1e9).passed());
        assert!(Deadline::after(Some(10.0), 10.0).passed());
        assert!(Deadline::after(Some(5.0), 60.0).passed());
        assert!(!Deadline::after(Some(3600.0), 0.0).passed());
    }
}
