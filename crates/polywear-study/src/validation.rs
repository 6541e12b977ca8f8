//! The fast classifier against the brute-force reference on random operating points:
//! class agreement outside the Hopf band, amplitude and frequency errors, and the cost of each.

use std::time::Instant;

use polywear_core::classify::envelope::reference_verdict;
use polywear_core::classify::{Class, ClassifierOptions, WheelVerdict};
use polywear_core::ensemble::{self, Control};
use polywear_core::evaluate;
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::params::{Params, OPERATING_AXES};

use crate::parquet_out::Column;
use polywear_core::sampling::uniform;

/// Points closer to the Hopf boundary than this (|Re λ| in 1/s) are not compared: there even
/// the reference's horizon is too short to settle.
pub const HOPF_BAND: f64 = 0.05;

/// Operating point `index` of the validation set: speed 40–250 km/h, toe 0.05–1.0°,
/// load 2000–7000 N, pressure 150–450 kPa, other parameters at their defaults.
pub(crate) fn random_point(seed: u64, index: u64) -> Params {
    Params {
        speed_kmh: uniform(seed, index, 0, 40.0, 250.0),
        toe_deg: uniform(seed, index, 1, 0.05, 1.0),
        load_n: uniform(seed, index, 2, 2000.0, 7000.0),
        pressure_kpa: uniform(seed, index, 3, 150.0, 450.0),
        ..Params::default()
    }
}

/// One wheel of one point, judged both ways.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// The point's index in the random set.
    pub index: u64,
    /// The point's parameters.
    pub params: Params,
    /// The wheel.
    pub wheel: Wheel,
    /// The friction variant.
    pub variant: Variant,
    /// The fast classifier's verdict.
    pub fast: WheelVerdict,
    /// Its wall time \[µs\].
    pub fast_us: f64,
    /// The brute-force verdict.
    pub reference: WheelVerdict,
    /// Its wall time \[µs\].
    pub reference_us: f64,
}

impl Comparison {
    /// Whether this wheel is outside the Hopf band and so must agree.
    pub fn compared(&self) -> bool {
        self.fast.eig_re_max.abs() >= HOPF_BAND
    }

    /// Whether both say the same about vibration (a failed fast verdict never agrees).
    pub fn classes_agree(&self) -> bool {
        self.fast.class.vibrates() == (self.reference.class == Class::LimitCycle)
            && self.fast.class != Class::Failed
    }

    /// Largest relative error of amp_y, amp_v and frequency (0 when both are stable).
    pub fn worst_relative_error(&self) -> f64 {
        let rel = |a: f64, b: f64| {
            if b == 0.0 {
                a.abs()
            } else {
                ((a - b) / b).abs()
            }
        };
        rel(self.fast.amp_y_m, self.reference.amp_y_m)
            .max(rel(self.fast.amp_v_mps, self.reference.amp_v_mps))
            .max(rel(self.fast.freq_hz, self.reference.freq_hz))
    }
}

/// Evaluates `n_points` random points × both wheels × both variants. The fast classifier runs
/// one call at a time on one thread (its timings are single-thread costs); the reference runs
/// in parallel, each call still on one thread.
pub fn compare(seed: u64, n_points: u64) -> Vec<Comparison> {
    compare_with(seed, n_points, &ClassifierOptions::default())
}

/// [`compare`] with the fast classifier's options given.
pub fn compare_with(seed: u64, n_points: u64, opts: &ClassifierOptions) -> Vec<Comparison> {
    let mut jobs = Vec::new();
    for index in 0..n_points {
        let p = random_point(seed, index);
        for variant in Variant::ALL {
            for wheel in Wheel::BOTH {
                if let Ok(m) = WheelModel::build(&p, wheel, variant) {
                    jobs.push((index, p, m));
                }
            }
        }
    }
    let fast: Vec<(WheelVerdict, f64)> = jobs
        .iter()
        .map(|(_, p, m)| {
            let t = Instant::now();
            let v = evaluate::solve_wheel(*p, m.variant, m.wheel, opts).verdict;
            (v, t.elapsed().as_secs_f64() * 1e6)
        })
        .collect();
    let compare = |k: usize| {
        let (index, p, m) = &jobs[k];
        let (fast, fast_us) = fast[k].clone();
        let t = Instant::now();
        let reference = reference_verdict(&m.ode, WheelModel::rotation_hz(p));
        Comparison {
            index: *index,
            params: *p,
            wheel: m.wheel,
            variant: m.variant,
            fast,
            fast_us,
            reference,
            reference_us: t.elapsed().as_secs_f64() * 1e6,
        }
    };
    ensemble::solve(jobs.len(), compare, &Control::QUIET).all()
}

/// Median of a list (NaN when empty).
pub fn median(mut xs: Vec<f64>) -> f64 {
    if xs.is_empty() {
        return f64::NAN;
    }
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n % 2 == 1 {
        xs[n / 2]
    } else {
        0.5 * (xs[n / 2 - 1] + xs[n / 2])
    }
}
/// The comparisons as columns, one row per point, wheel and variant: the operating point, both
/// verdicts, their figures and their costs.
pub fn comparison_columns(rows: &[Comparison]) -> Vec<Column> {
    let f = |g: &dyn Fn(&Comparison) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let mut cols = vec![
        Column::i64("point", "", rows.iter().map(|r| r.index as i64).collect()),
        Column::str("wheel", rows.iter().map(|r| r.wheel.to_string()).collect()),
        Column::str(
            "variant",
            rows.iter().map(|r| r.variant.to_string()).collect(),
        ),
    ];
    for id in OPERATING_AXES {
        cols.push(Column::f64(id.name(), id.spec().unit, f(&|r| r.params[id])));
    }
    cols.extend([
        Column::f64("eig_re_max", "1/s", f(&|r| r.fast.eig_re_max)),
        Column::str(
            "fast_class",
            rows.iter().map(|r| r.fast.class.as_str().into()).collect(),
        ),
        Column::str(
            "reference_class",
            rows.iter()
                .map(|r| r.reference.class.as_str().into())
                .collect(),
        ),
        Column::f64("fast_amp_v_mps", "m/s", f(&|r| r.fast.amp_v_mps)),
        Column::f64("reference_amp_v_mps", "m/s", f(&|r| r.reference.amp_v_mps)),
        Column::f64("fast_freq_hz", "Hz", f(&|r| r.fast.freq_hz)),
        Column::f64("reference_freq_hz", "Hz", f(&|r| r.reference.freq_hz)),
        Column::f64("fast_us", "us", f(&|r| r.fast_us)),
        Column::f64("reference_us", "us", f(&|r| r.reference_us)),
        Column::f64("fast_rhs_evals", "", f(&|r| r.fast.rhs_evals as f64)),
        Column::f64(
            "reference_rhs_evals",
            "",
            f(&|r| r.reference.rhs_evals as f64),
        ),
    ]);
    cols
}
