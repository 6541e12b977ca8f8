//! Trajectories of one wheel from the disturbed equilibrium (MODEL.md#step-9-attractor), sampled on
//! a uniform grid (its figure, the paper's Figs. 8–10, is `polywear-analysis`'s).

use polywear_core::classify::{ClassifierOptions, Scales};
use polywear_core::columns::Column;
use polywear_core::evaluate;
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::params::Params;
use polywear_core::records::WheelRecord;
use polywear_core::solver::{sample_uniform, IntegrationError, SolverOptions};

/// (t, [z, y, v]) samples.
pub type Samples = Vec<(f64, [f64; 3])>;

/// A wheel's sampled trajectory, and why it ends before the requested duration if it does.
#[derive(Debug, Clone)]
pub struct TimeSeries {
    /// The samples, up to where the integration went.
    pub samples: Samples,
    /// Set when the integration failed before the end (the caller warns).
    pub ended_early: Option<EndedEarly>,
}

/// A time series that ends before its duration because the integration failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{wheel} wheel time series ends early: {error}")]
pub struct EndedEarly {
    /// The wheel.
    pub wheel: Wheel,
    /// Why the integration stopped.
    pub error: IntegrationError,
}

/// Trajectory from the equilibrium with y disturbed by `disturbance_m`, sampled at
/// `sample_rate_hz` for `duration_s`; a failing integration ends the series early, and the
/// series says why.
pub fn time_series(
    m: &WheelModel,
    duration_s: f64,
    sample_rate_hz: f64,
    disturbance_m: f64,
) -> TimeSeries {
    let scales = Scales::new(&m.ode);
    let x0 = [scales.z_eq, scales.y_eq + disturbance_m, 0.0];
    let sopts = SolverOptions::transient(1e-9, scales.atol(1e-9), 100_000_000);
    let (samples, outcome) = sample_uniform(&m.ode, x0, duration_s, 1.0 / sample_rate_hz, &sopts);
    TimeSeries {
        samples,
        ended_early: outcome.err().map(|error| EndedEarly {
            wheel: m.wheel,
            error,
        }),
    }
}

/// The time series as columns: one row per wheel and sample (`wheel`, `t_s`, `z_m`, `y_m`,
/// `v_mps`), as `simulate --out` writes them.
pub fn series_columns(series: &[(Wheel, Samples)]) -> Vec<Column> {
    let all = || {
        series
            .iter()
            .flat_map(|(w, s)| s.iter().map(move |x| (*w, x)))
    };
    vec![
        Column::str(
            "wheel",
            all().map(|(w, _)| w.as_str().to_string()).collect(),
        ),
        Column::f64("t_s", "s", all().map(|(_, x)| x.0).collect()),
        Column::f64("z_m", "m", all().map(|(_, x)| x.1[0]).collect()),
        Column::f64("y_m", "m", all().map(|(_, x)| x.1[1]).collect()),
        Column::f64("v_mps", "m/s", all().map(|(_, x)| x.1[2]).collect()),
    ]
}

/// One operating point's wheels: a record per wheel, and the time series of every wheel with a
/// model when one was asked for.
#[derive(Debug, Clone)]
pub struct PointRun {
    /// The verdict of each wheel, in the order asked.
    pub records: Vec<WheelRecord>,
    /// Each wheel's time series (wheels without a model have none).
    pub series: Vec<(Wheel, Samples)>,
    /// The series that end before their duration, for the caller to warn about.
    pub ended_early: Vec<EndedEarly>,
}

/// Solves each of `wheels` at `params` on its own (no shooting hint from the other: the verdict
/// of one wheel does not depend on which others were asked for, MODEL.md#classes-and-verdicts),
/// and samples its trajectory for `series` = (duration \[s\], sample rate \[Hz\]) when given.
pub fn simulate_point(
    params: Params,
    variant: Variant,
    wheels: &[Wheel],
    opts: &ClassifierOptions,
    series: Option<(f64, f64)>,
) -> PointRun {
    let mut run = PointRun {
        records: Vec::new(),
        series: Vec::new(),
        ended_early: Vec::new(),
    };
    for &wheel in wheels {
        let w = evaluate::solve_wheel(params, variant, wheel, opts);
        run.records.push(w.record);
        if let (Ok(m), Some((duration_s, rate_hz))) = (&w.model, series) {
            let ts = time_series(m, duration_s, rate_hz, opts.disturbance_m);
            run.ended_early.extend(ts.ended_early);
            run.series.push((wheel, ts.samples));
        }
    }
    run
}
