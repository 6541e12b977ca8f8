//! `polywear reproduce`: the paper's analyses regenerated with polywear's own engine, and a
//! report that sets each result beside the paper's legible values (MODEL.md#targets), for
//! both wheels and all three friction variants, with the driving-vs-follower comparison on the
//! default study and why the literal equations cannot carry the paper's conclusion.
//!
//! Problem → result → render, as the analysis is: a [`Request`] says what to regenerate,
//! `solve` computes it into a [`Reproduction`] (no file is written), and `write()` draws the
//! figures, writes the tables and composes `report.md` from the result.

mod figures;
mod pairs;
mod report;

use std::path::{Path, PathBuf};

use crate::analysis::paired::{PairTally, Paired};
use pairs::{solve_pairs, PairChart};
use polywear_core::classify::ClassifierOptions;
use polywear_core::ensemble::Control;
use polywear_core::model::{brush, tire, Variant, Wheel};
use polywear_core::params::{ParamId, Params};
use polywear_core::records::WheelRecord;
use polywear_study::bifurcation::{linspace, sweep, Sweep};
use polywear_study::trajectory::{time_series, Samples};

pub(crate) use figures::write;

/// The four axes of the paper's bifurcation diagrams and Table 3, with their sweep ranges.
pub(crate) const AXES: [(ParamId, f64, f64); 4] = [
    (ParamId::SpeedKmh, 40.0, 260.0),
    (ParamId::ToeDeg, 0.05, 1.0),
    (ParamId::LoadN, 2000.0, 7000.0),
    (ParamId::PressureKpa, 150.0, 450.0),
];

/// The slip angles of Fig. 4's adhesion ellipse \[deg\].
const ADHESION_ANGLES_DEG: [f64; 4] = [0.5, 1.0, 2.0, 4.0];

/// The paper's simulated operating points (Figs. 8–10, 13, 15, 17, 19) under the default
/// variant, and the driving wheel at 100 km/h under the two other variants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PaperPoint {
    /// Fig. 8: 70 km/h, stable.
    Speed70,
    /// Figs. 9 and 10: 100 km/h, self-excited vibration.
    Speed100,
    /// Fig. 13: toe-in 0.35°.
    Toe035,
    /// Fig. 15: load 5000 N.
    Load5000,
    /// Fig. 17: pressure 200 kPa.
    Pressure200,
    /// Fig. 19: 150 km/h.
    Speed150,
    /// 100 km/h under the `paper` variant.
    Speed100Paper,
    /// 100 km/h under the `combined` variant.
    Speed100Combined,
}

impl PaperPoint {
    /// Every point, in the order of the figures.
    pub const ALL: [PaperPoint; 8] = [
        PaperPoint::Speed70,
        PaperPoint::Speed100,
        PaperPoint::Toe035,
        PaperPoint::Load5000,
        PaperPoint::Pressure200,
        PaperPoint::Speed150,
        PaperPoint::Speed100Paper,
        PaperPoint::Speed100Combined,
    ];

    /// The figure's file stem.
    pub fn stem(self) -> &'static str {
        match self {
            PaperPoint::Speed70 => "fig8_speed70",
            PaperPoint::Speed100 => "fig9_10_speed100",
            PaperPoint::Toe035 => "fig13_toe0.35",
            PaperPoint::Load5000 => "fig15_load5000",
            PaperPoint::Pressure200 => "fig17_pressure200",
            PaperPoint::Speed150 => "fig19_speed150",
            PaperPoint::Speed100Paper => "speed100_paper",
            PaperPoint::Speed100Combined => "speed100_combined",
        }
    }

    /// The parameter the point sets, its value, and the variant.
    pub fn setting(self) -> (ParamId, f64, Variant) {
        let d = Variant::DEFAULT;
        match self {
            PaperPoint::Speed70 => (ParamId::SpeedKmh, 70.0, d),
            PaperPoint::Speed100 => (ParamId::SpeedKmh, 100.0, d),
            PaperPoint::Toe035 => (ParamId::ToeDeg, 0.35, d),
            PaperPoint::Load5000 => (ParamId::LoadN, 5000.0, d),
            PaperPoint::Pressure200 => (ParamId::PressureKpa, 200.0, d),
            PaperPoint::Speed150 => (ParamId::SpeedKmh, 150.0, d),
            PaperPoint::Speed100Paper => (ParamId::SpeedKmh, 100.0, Variant::Paper),
            PaperPoint::Speed100Combined => (ParamId::SpeedKmh, 100.0, Variant::Combined),
        }
    }
}

/// What to regenerate.
#[derive(Debug, Clone, Copy)]
pub struct Request {
    /// The parameters (the shipped defaults, or a `--params` file).
    pub base: Params,
    /// Values per bifurcation sweep.
    pub steps: usize,
    /// Samples of the default study for the driving-vs-follower comparison.
    pub paired_samples: u64,
}

/// Both wheels at one of the paper's points: their rows and 3 s of their trajectories.
#[derive(Debug, Clone)]
pub struct PointRun {
    /// The point.
    pub point: PaperPoint,
    /// Follower then driving.
    pub records: Vec<WheelRecord>,
    /// The time series of each wheel with a model.
    pub series: Vec<(Wheel, Samples)>,
}

/// Fig. 4's rows: (slip angle \[deg\], slip ratio, F_X \[N\], F_Y \[N\]).
pub(crate) type AdhesionRow = (f64, f64, f64, f64);

/// Everything the paper's analyses came to, before any file is written.
pub struct Reproduction {
    /// What was asked.
    pub request: Request,
    /// Fig. 4: the brush model's lateral against longitudinal force.
    pub adhesion: Vec<AdhesionRow>,
    /// Every bifurcation sweep (three variants × four axes, both wheels), variant by variant.
    pub sweeps: Vec<Sweep>,
    /// The paper's points, in [`PaperPoint::ALL`] order.
    pub points: Vec<PointRun>,
    /// The six stability charts of the operating axes (default variant).
    pub charts: Vec<PairChart>,
    /// Driving against follower on samples of the default study, per variant.
    pub paired: Vec<Paired>,
}

impl Reproduction {
    /// The sweep of `param` under `variant`.
    pub fn sweep(&self, param: ParamId, variant: Variant) -> &Sweep {
        self.sweeps
            .iter()
            .find(|s| s.param == param && s.variant == variant)
            .expect("every axis is swept under every variant")
    }

    /// A wheel's row at one of the paper's points.
    pub fn record(&self, point: PaperPoint, wheel: Wheel) -> Option<&WheelRecord> {
        self.points
            .iter()
            .find(|p| p.point == point)
            .and_then(|p| p.records.iter().find(|r| r.wheel == wheel))
    }
}

/// Why the paper's analyses cannot be regenerated: a file that cannot be written, or a stage
/// that failed (in that stage's words).
#[derive(Debug, thiserror::Error)]
pub enum ReproduceError {
    /// The output folder or the report cannot be written.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The model cannot be built for a point of a figure.
    #[error("{0}")]
    Model(polywear_core::model::tire::FlatTire),
    /// A figure cannot be drawn.
    #[error("{0}")]
    Figure(crate::plot::PlotError),
    /// A stability chart cannot be drawn or written.
    #[error("{0}")]
    Chart(pairs::ChartError),
    /// A table cannot be written.
    #[error("{0}")]
    Table(String),
    /// The built-in default study cannot be read.
    #[error("{0}")]
    Study(String),
}

impl ReproduceError {
    fn io(path: &Path, e: impl std::fmt::Display) -> ReproduceError {
        ReproduceError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// Computes every analysis of the paper (no file is written).
pub(crate) fn solve(request: &Request) -> Result<Reproduction, ReproduceError> {
    let base = &request.base;
    let opts = ClassifierOptions::default();
    let adhesion = adhesion_ellipse(base)?;
    // Bifurcation diagrams (Figs. 6, 7, 12, 14, 16, 18, 20, 22, 23) for all three variants.
    let values = |from, to| linspace(from, to, request.steps);
    let sweeps = Variant::ALL
        .iter()
        .flat_map(|&v| AXES.map(|(axis, from, to)| sweep(base, axis, &values(from, to), v, &opts)))
        .collect();
    // Time histories, phase portraits and spectra at the paper's points, both wheels.
    let points = PaperPoint::ALL
        .iter()
        .map(|&point| point_run(base, point, &opts))
        .collect();
    // Stability charts of the four axes two at a time, both wheels (default variant).
    let charts = solve_pairs(base, Variant::DEFAULT, &AXES);
    let paired = paired_comparison(base, request.paired_samples)?;
    Ok(Reproduction {
        request: *request,
        adhesion,
        sweeps,
        points,
        charts,
        paired,
    })
}

/// Regenerates the paper's analyses into `dir`, figures in `format`: `solve`,
/// then `write()`. Returns the result and every file written.
pub fn reproduce(
    request: &Request,
    dir: &Path,
    format: crate::plot::FigureFormat,
) -> Result<(Reproduction, Vec<PathBuf>), ReproduceError> {
    let result = solve(request)?;
    let files = write(&result, dir, format)?;
    Ok((result, files))
}

/// Fig. 4: lateral against longitudinal force as the slip ratio grows, for several slip angles.
fn adhesion_ellipse(base: &Params) -> Result<Vec<AdhesionRow>, ReproduceError> {
    let slips: Vec<f64> = (0..=200)
        .map(|i| 0.5 * (i as f64 / 200.0).powi(2))
        .collect();
    let mut rows = Vec::new();
    for a in ADHESION_ANGLES_DEG {
        let p = Params {
            toe_deg: a,
            ..*base
        };
        let patch = tire::contact_patch(&p).map_err(ReproduceError::Model)?;
        rows.extend(slips.iter().map(|&s| {
            (
                a,
                s,
                brush::longitudinal_force_n(&p, &patch, s),
                brush::lateral_force_n(&p, &patch, s),
            )
        }));
    }
    Ok(rows)
}

/// Both wheels at one of the paper's points, each on its own, with 3 s of trajectory.
fn point_run(base: &Params, point: PaperPoint, opts: &ClassifierOptions) -> PointRun {
    let (param, value, variant) = point.setting();
    let mut p = *base;
    p[param] = value;
    let mut records = Vec::new();
    let mut series = Vec::new();
    for wheel in Wheel::BOTH {
        let w = polywear_core::evaluate::solve_wheel(p, variant, wheel, opts);
        if let Ok(m) = &w.model {
            let ts = time_series(m, 3.0, 20_000.0, opts.disturbance_m);
            series.push((wheel, ts.samples));
        }
        records.push(w.record);
    }
    PointRun {
        point,
        records,
        series,
    }
}

/// Draws `samples` points of the built-in default study (its tire-structure uncertainty around
/// `base`), classifies both wheels under every variant, and pairs them as the analysis does
/// (`PairTally`): driving against follower on the same samples, per variant.
pub fn paired_comparison(base: &Params, samples: u64) -> Result<Vec<Paired>, ReproduceError> {
    let mut study =
        polywear_study::study::Study::parse_with_base(polywear_study::study::DEFAULT_STUDY, *base)
            .map_err(|e| ReproduceError::Study(e.to_string()))?;
    study.variants = Variant::ALL.to_vec();
    let sampler = study.sampler(study.seed, samples);
    let opts = ClassifierOptions::default();
    let sample = |i: usize| {
        polywear_study::explore::evaluate_sample(&study, &sampler, i as u64, &opts, None)
    };
    let rows = polywear_core::ensemble::solve(samples as usize, sample, &Control::QUIET).all();
    let mut tally = PairTally::default();
    for s in &rows {
        for &variant in &Variant::ALL {
            let class = |w: Wheel| {
                s.records
                    .iter()
                    .find(|r| r.variant == variant && r.wheel == w)
                    .map(|r| r.class)
            };
            if let (Some(f), Some(d)) = (class(Wheel::Follower), class(Wheel::Driving)) {
                tally.add(variant, f, d);
            }
        }
    }
    Ok(tally.paired())
}
