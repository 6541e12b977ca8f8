//! The estimator's work is bounded whatever the depths, and within the wheel's wall-clock
//! budget (MODEL.md#the-estimator-over-the-treads-life).

use super::life::passed_orders;
use super::*;
use crate::classify::budget::{Meter, WheelBudget};
use crate::classify::ClassifierOptions;
use crate::evaluate::{calibrate_wear, solve_wheel};
use crate::model::{Variant, Wheel};
use crate::wear::physics::feedback::FEEDBACK_ORDERS;
use crate::wear::{WearProblem, WearSettings};

/// A tread worn to nothing has f_end = ∞ (f₀/f_end = 0): ν passes every order, and the walk
/// laid them all out (an allocation of 206 GB). The orders walked stop at the loop's.
#[test]
fn a_tread_worn_to_nothing_walks_no_more_orders_than_the_loop_resolves() {
    for nu in [3.5, 19.3, 60.0, 126.2, 400.0] {
        for end in [1.0, 0.67, 0.1, 1e-9, 0.0] {
            let (lo, hi) = passed_orders(nu, end);
            let ceiling = (FEEDBACK_ORDERS as u32).max(nu.ceil() as u32 + 2);
            assert!(
                lo >= 1 && lo <= hi && hi <= ceiling,
                "{nu} {end}: {lo}..={hi}"
            );
            assert_eq!(lo, (nu.floor() as u32).saturating_sub(2).max(1), "{nu}");
        }
    }
    // Where ν's drift stays within the loop's orders, every order it passes is walked.
    assert_eq!(passed_orders(19.3, 0.67), (17, 31));
}

/// A wheel's inputs at `p`, with the shipped settings on `level`.
fn estimate_at(p: &Params, budget: WheelBudget, wait: std::time::Duration) -> WearAnswer {
    let opts = ClassifierOptions::default();
    let cal = calibrate_wear(&Params::default(), Variant::SlidingShare, &opts).unwrap();
    let w = solve_wheel(*p, Variant::SlidingShare, Wheel::Follower, &opts);
    let settings = WearSettings::default();
    let inputs = WearProblem {
        params: *p,
        model: &w.model,
        verdict: &w.verdict,
        settings: &settings,
        calibration: &cal,
    };
    let meter = Meter::new(budget);
    std::thread::sleep(wait);
    inputs.solve(&meter)
}

/// Handled, not refused: a tread whose usable depth is all of it (15 mm of 15, worn out at 0)
/// gets an answer, in bounded work, on every level.
#[test]
fn a_tread_worn_to_nothing_gets_an_answer() {
    let p = Params {
        tread_depth_new_mm: 15.0,
        tread_depth_worn_out_mm: 0.0,
        speed_kmh: 115.0,
        toe_deg: 0.6,
        ..Params::default()
    };
    let e = estimate_at(&p, WheelBudget::default(), std::time::Duration::ZERO);
    assert!(e.reason.is_empty(), "{}", e.reason);
    assert!(!e.distance_to_visible_km.is_nan(), "{e:?}");
}

/// The wear stage runs under the wheel's `max_wheel_seconds`: past it, the wheel's wear
/// figures are unknown with the budget's reason, never figures walked in part (it ran for as
/// long as it took: 2 samples took 118 s under a 5 s limit).
#[test]
fn the_wear_stage_keeps_to_the_wheel_s_wall_clock_budget() {
    let p = Params {
        speed_kmh: 115.0,
        toe_deg: 0.6,
        ..Params::default()
    };
    let in_time = estimate_at(&p, WheelBudget::default(), std::time::Duration::ZERO);
    assert!(in_time.reason.is_empty(), "{}", in_time.reason);
    let budget = WheelBudget {
        max_wheel_seconds: 1e-3,
        ..WheelBudget::default()
    };
    let late = estimate_at(&p, budget, std::time::Duration::from_millis(5));
    assert!(
        late.reason
            .starts_with("budget exceeded (max_wheel_seconds = 0.001 s"),
        "{}",
        late.reason
    );
    assert!(late.distance_to_visible_km.is_nan(), "{late:?}");
}
