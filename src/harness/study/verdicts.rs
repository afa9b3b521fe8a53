//! The classification of a case's oscillation indicator `r = TV(λ_h) / TV(λ)` on the finest
//! level ([`crate::harness::study::CaseStudy::oscillation_indicator`]): analysis, which the
//! studies' verdicts and findings use and the reports only print.
//!
//! The thresholds are decades of the variation ratio, chosen once for every case: `No` for
//! `r < 5` (the multiplier varies like the exact one up to an overshoot at each impact),
//! `Small` for `5 ≤ r < 100`, `Yes` for `100 ≤ r < 2000`, `Big` for `r ≥ 2000`. They are the
//! thresholds of the words *oscillates* (from `Small`) and *oscillates spuriously* (from `Yes`)
//! of `crate::harness::vocabulary`, which re-exports them: the indicator is one run's, decided
//! as measured.

/// The smallest oscillation indicator that counts as oscillating (the boundary between `No`
/// and `Small` of [`oscillation_word`]).
pub const OSCILLATES_FROM: f64 = 5.0;

/// The boundary between `Small` and `Yes` of [`oscillation_word`].
pub const OSCILLATION_YES_FROM: f64 = 100.0;

/// The boundary between `Yes` and `Big` of [`oscillation_word`].
pub const OSCILLATION_BIG_FROM: f64 = 2000.0;

/// Whether the indicator counts as oscillating: at least [`OSCILLATES_FROM`].
pub fn oscillates(indicator: f64) -> bool {
    indicator >= OSCILLATES_FROM
}

/// The oscillation indicator `r` as a table shows it: three decimals, or in scientific notation
/// from `10⁶` on (a diverged run's total variation is astronomically large).
pub fn oscillation_ratio_text(ratio: f64) -> String {
    if ratio.abs() < 1e6 {
        format!("{ratio:.3}")
    } else {
        format!("{ratio:.3e}")
    }
}

/// The word for the oscillation indicator `r` (see the module): `No`, `Small`, `Yes` or `Big`.
pub fn oscillation_word(ratio: f64) -> &'static str {
    if ratio < OSCILLATES_FROM {
        "No"
    } else if ratio < OSCILLATION_YES_FROM {
        "Small"
    } else if ratio < OSCILLATION_BIG_FROM {
        "Yes"
    } else {
        "Big"
    }
}
