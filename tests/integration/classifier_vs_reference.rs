//! The fast classifier against brute-force integration on a small fixed random set (the full
//! 300-point set is `polywear validate --points 300`): classes agree outside the Hopf band, and
//! limit-cycle amplitudes and frequency agree to 1%.

use polywear_study::validation::compare;

#[test]
fn fast_classifier_agrees_with_brute_force() {
    let rows = compare(2026, 12);
    assert_eq!(rows.len(), 12 * 2 * 3, "12 points x 2 wheels x 3 variants");
    let compared: Vec<_> = rows.iter().filter(|r| r.compared()).collect();
    assert!(compared.len() >= 60, "too few points outside the Hopf band");
    let cycles = compared
        .iter()
        .filter(|r| r.reference.class.vibrates())
        .count();
    assert!(
        cycles >= 4 && cycles < compared.len(),
        "the set must hold both classes: {cycles} cycles"
    );
    for r in &compared {
        assert!(
            r.classes_agree(),
            "point {} {} {}: fast {:?} vs reference {:?}",
            r.index,
            r.wheel,
            r.variant,
            r.fast,
            r.reference
        );
        assert!(
            r.worst_relative_error() < 0.01,
            "point {}: {:?} vs {:?}",
            r.index,
            r.fast,
            r.reference
        );
        // The fast classifier spends far less work than the brute force.
        assert!(
            r.fast.rhs_evals * 50 < r.reference.rhs_evals,
            "{} vs {}",
            r.fast.rhs_evals,
            r.reference.rhs_evals
        );
    }
}
