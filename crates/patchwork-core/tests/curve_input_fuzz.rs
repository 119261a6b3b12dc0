//! Whatever bytes arrive, the curve readers answer Ok or a typed error: no panic.

use patchwork_core::curve::{Units, read_curve, read_json, read_text};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

proptest! {
    // A fixed seed: every run draws the same cases, so a failure reproduces.
    #![proptest_config(ProptestConfig {
        rng_seed: RngSeed::Fixed(0xF022_5EED),
        failure_persistence: None,
        ..ProptestConfig::with_cases(512)
    })]

    #[test]
    fn random_text_never_panics(text in ".{0,400}") {
        let _ = read_curve(&text, Units::Mm);
        let _ = read_text(&text, Units::In);
        let _ = read_json(&text, Units::Cm);
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = read_curve(&text, Units::Mm);
    }

    #[test]
    fn random_numbers_give_a_curve_or_a_named_error(
        rows in prop::collection::vec(
            prop::collection::vec(prop_oneof![any::<f64>(), -1e3f64..1e3], 0..5), 0..30)
    ) {
        let text: String = rows
            .iter()
            .map(|r| r.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(",") + "\n")
            .collect();
        match read_text(&text, Units::Mm) {
            Ok(curve) => {
                prop_assert!(curve.len() >= 4);
                prop_assert!(curve.length() > 0.0 && curve.length().is_finite());
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
        let json = format!("{{\"points\": {}}}", serde_json::to_string(&rows).unwrap_or_default());
        let _ = read_json(&json, Units::Mm);
    }
}
