//! Trajectories of one wheel from the disturbed equilibrium (MODEL.md#step-9-attractor), sampled on
//! a uniform grid (its figure, the paper's Figs. 8–10, is `polywear-analysis`'s).

use polywear_core::classify::Scales;
use polywear_core::columns::Column;
use polywear_core::model::{Wheel, WheelModel};
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
