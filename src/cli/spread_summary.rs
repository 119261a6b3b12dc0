//! The spread as `spread` and `design` print it: the centreline's and the
//! tip's spread, the shape error expected as built, and the largest
//! contributors.

use patchwork_core::spread::{AGREEMENT, Spread};

/// The spread as a person reads it.
pub fn summary(s: &Spread, top: usize) -> String {
    let mut text = format!(
        "spread:       {:.2} mm RMS ({:.2} % of the length), at worst {:.2} mm; {} FE solves\n\
         tip:          {:.2} mm RMS from its predicted place, at worst {:.2} mm\n",
        s.rms_mm, s.rms_percent, s.worst_mm, s.solves, s.tip_rms_mm, s.tip_worst_mm
    );
    if s.mean_shift_mm > 0.0 {
        text += &format!(
            "on average:   {:.2} mm RMS from the predicted centreline (of the spread, the part \
             that is an offset rather than scatter)\n",
            s.mean_shift_mm
        );
    }
    if let (Some(nominal), Some(expected)) = (
        s.nominal_shape_error_percent,
        s.expected_shape_error_percent,
    ) {
        text += &format!(
            "shape error:  {nominal:.2} % as designed, {expected:.2} % expected as built\n"
        );
    }
    if let Some(m) = &s.monte_carlo {
        let verdict = match m.agrees {
            true => "agrees".to_string(),
            false => format!(
                "differs by more than {:.0} %: the response is not linear at these tolerances, \
                 the sampled figure holds",
                100.0 * AGREEMENT
            ),
        };
        let failed = match m.failed {
            0 => String::new(),
            f => format!("; {f} samples did not solve"),
        };
        text += &format!(
            "Monte-Carlo:  {} samples (seed {}): {:.2} mm RMS, tip {:.2} mm; {:.2} ± {:.2} × the linear \
             estimate: {verdict}{failed}\n",
            m.samples, m.seed, m.rms_mm, m.tip_rms_mm, m.ratio, m.ratio_sigma
        );
    }
    for (i, line) in s.largest(top).iter().enumerate() {
        let head = if i == 0 {
            "matters most: "
        } else {
            "              "
        };
        text += &format!("{head}{line}\n");
    }
    text
}
