//! The drive cycle's reading, durations, quasi-static check and summary.

use super::*;

fn cycle(text: &str) -> Result<DriveCycle, CycleError> {
    let dir = std::env::temp_dir().join(format!("polywear-cycle-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(format!("c{}.csv", text.len()));
    std::fs::write(&p, text).unwrap();
    DriveCycle::read(&p)
}

/// A standstill row of the default point, the frame the tests below fill in.
fn standstill_record(p: &Params) -> WheelRecord {
    let opts = ClassifierOptions::default();
    let mut p = *p;
    p.speed_kmh = 0.0;
    evaluate::solve_wheel(
        p,
        Variant::Paper,
        polywear_core::model::Wheel::Follower,
        &opts,
    )
    .record
}

#[test]
fn durations_hold_until_the_next_step() {
    let c = cycle("time_s,speed_kmh\n0,0\n1,50\n3,100\n").unwrap();
    assert_eq!(c.step_durations_s(), vec![1.0, 2.0, 2.0]);
    assert!(c.standstill(0) && !c.standstill(1));
}

#[test]
fn quasi_static_fails_where_re_lambda_changes_faster_than_its_square() {
    // Re λ over 1 s steps: steady at -2 (holds), then through 0 (fails there), and one
    // step without an ODE (not assessed).
    let re = [-2.0, -2.0, -2.0, -1.0, 0.0, 1.0, 2.0, f64::NAN];
    let time: Vec<f64> = (0..re.len()).map(|i| i as f64).collect();
    let p = Params::default();
    let mut steps: Vec<[StepWheel; 2]> = re
        .iter()
        .map(|&r| {
            let mut record = standstill_record(&p);
            record.class = Class::Stable;
            record.eig_re_max = r;
            let w = StepWheel {
                record,
                tread_time_constant_s: f64::NAN,
                stability_change_time_s: f64::NAN,
                quasi_static: true,
            };
            [w.clone(), w]
        })
        .collect();
    assess_quasi_static(&time, &mut steps, 0);
    let qs: Vec<bool> = steps.iter().map(|s| s[0].quasi_static).collect();
    // Step 1: rate 0, T infinite. Step 2: rate 0.5/s, T = 4 s ≥ τ = 0.5 s. Step 3: rate
    // 1/s, T = 1 s = τ (holds, just). Step 4: Re λ = 0, τ infinite (fails). Step 5: T = τ
    // = 1 s. Step 6: one-sided rate 1/s (the next step has no ODE), T = 2 s ≥ τ = 0.5 s.
    assert_eq!(qs, [true, true, true, true, false, true, true, true]);
    assert_eq!(steps[1][0].stability_change_time_s, f64::INFINITY);
    assert_eq!(steps[2][0].stability_change_time_s, 4.0);
    assert_eq!(steps[3][0].tread_time_constant_s, 1.0);
    assert!(steps[7][0].tread_time_constant_s.is_nan());
}

#[test]
fn summary_shares_stretches_and_orders() {
    // Step 2 holds 2 s, the others 1 s; vibrating steps 1, 2 (order 18.4 → 18) and 4
    // (19.6 → 20); step 3 stable; step 0 standstill.
    let c = cycle("time_s,speed_kmh\n0,0\n1,36\n2,72\n4,36\n5,72\n6,36\n").unwrap();
    let p = Params::default();
    let vib = [false, true, true, false, true, false];
    let order = [0.0, 18.4, 18.4, 0.0, 19.6, 0.0];
    let steps: Vec<[StepWheel; 2]> = (0..6)
        .map(|i| {
            let mut record = standstill_record(&p);
            record.class = if i == 0 {
                Class::Standstill
            } else if vib[i] {
                Class::LimitCycle
            } else {
                Class::Stable
            };
            record.polygon_order = order[i];
            let w = StepWheel {
                record,
                tread_time_constant_s: f64::NAN,
                stability_change_time_s: f64::NAN,
                quasi_static: i != 3,
            };
            [w.clone(), w]
        })
        .collect();
    let s = summary::summarise(&c, &steps, 0);
    // Durations 1, 1, 2, 1, 1, 1 (the last as the one before): 7 s in all, 4 vibrating.
    assert!((s.time_share - 4.0 / 7.0).abs() < 1e-12);
    assert_eq!(s.longest_vibration_s, 3.0);
    // Distance: 36 km/h for 1 s = 0.01 km; in all 0.01 + 0.04 + 0.01 + 0.02 + 0.01 km, in
    // vibration 0.01 + 0.04 + 0.02 km, the longest stretch 0.05 km.
    assert!((s.longest_vibration_km - 0.05).abs() < 1e-12);
    assert!((s.distance_share - 0.07 / 0.09).abs() < 1e-12);
    assert!((s.standstill_share - 1.0 / 7.0).abs() < 1e-12);
    assert!((s.not_quasi_static_share - 1.0 / 7.0).abs() < 1e-12);
    assert_eq!(s.order_shares.keys().copied().collect::<Vec<_>>(), [18, 20]);
    assert!((s.order_shares[&18] - 0.75).abs() < 1e-12);
}

#[test]
fn bad_cycles_are_refused_with_row_and_column() {
    let e = cycle("time_s,speed_kmh\n0,10\n0,20\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("row 2 (line 3), column `time_s`"), "{e}");
    let e = cycle("time_s,speed_kmh\n0,10\n1,-2\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("column `speed_kmh`") && e.contains("negative"),
        "{e}"
    );
    let e = cycle("time_s,speed_kmh,load_n\n0,10,4000\n1,20,-1\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("row 2 (line 3), column `load_n`"), "{e}");
    let e = cycle("time_s,speed_kmh,vin\n0,10,1\n1,20,1\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("column `vin`"), "{e}");
    let e = cycle("time_s,speed\n0,10\n1,20\n").unwrap_err().to_string();
    assert!(e.contains("no column `speed_kmh`"), "{e}");
    let e = cycle("time_s,speed_kmh\n0,10\n").unwrap_err().to_string();
    assert!(e.contains("at least two"), "{e}");
    // The toe-in per step is the angle; a column in mm is refused saying how it converts.
    let e = cycle("time_s,speed_kmh,toe_mm\n0,10,2\n1,20,2\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("column `toe_mm` (column 3)")
            && e.contains("toe_deg = atan(toe_mm / rim_diameter_mm)")
            && e.contains("--set toe_mm=..."),
        "{e}"
    );
}
