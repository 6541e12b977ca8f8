//! `polywear reproduce`: the paper's analyses regenerated with polywear's own engine, and a
//! report that sets each result beside the paper's legible values (MODEL.md#targets), for
//! both wheels and all three friction variants, with the driving-vs-follower comparison on the
//! default study and why the literal equations cannot carry the paper's conclusion.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::analysis::paired::{PairTally, Paired};
use crate::bifurcation::{linspace, sweep, Sweep};
use crate::classify::{classify_point, ClassifierOptions};
use crate::model::{brush, tire, Variant, Wheel};
use crate::params::{ParamId, Params};
use crate::parquet_out::{write_csv, write_table, Column};
use crate::plot::{self, Series};
use crate::records::{record_columns, WheelRecord};
use crate::trajectory::{plot_point, time_series};

/// The four axes of the paper's bifurcation diagrams and Table 3, with their sweep ranges.
pub const AXES: [(ParamId, f64, f64); 4] = [
    (ParamId::SpeedKmh, 40.0, 260.0),
    (ParamId::ToeDeg, 0.05, 1.0),
    (ParamId::LoadN, 2000.0, 7000.0),
    (ParamId::PressureKpa, 150.0, 450.0),
];

/// What was reproduced, for the report and the command's summary.
pub struct Reproduction {
    /// Every bifurcation sweep (four axes, three variants, both wheels).
    pub sweeps: Vec<Sweep>,
    /// Every file written.
    pub files: Vec<PathBuf>,
    /// The text of `report.md`.
    pub report: String,
    /// Driving against follower on samples of the default study, per variant.
    pub paired: Vec<Paired>,
}

/// Vibration intervals for people: an interval reaching an end of the sweep reads "≥ a" / "≤ b".
fn fmt_ranges(r: &[(f64, f64)], unit: &str, (from, to): (f64, f64)) -> String {
    if r.is_empty() {
        return "none".into();
    }
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    r.iter()
        .map(|&(a, b)| match (a <= from, b >= to) {
            (true, true) => format!("everywhere in {from}–{to}{unit}"),
            (true, false) => format!("≤ {b:.4}{unit}"),
            (false, true) => format!("≥ {a:.4}{unit}"),
            (false, false) => format!("{a:.4}–{b:.4}{unit}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn bounds(axis: ParamId) -> (f64, f64) {
    AXES.iter()
        .find(|a| a.0 == axis)
        .map_or((f64::NAN, f64::NAN), |a| (a.1, a.2))
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
    Model(crate::model::tire::FlatTire),
    /// A figure cannot be drawn.
    #[error("{0}")]
    Figure(crate::plot::PlotError),
    /// A stability chart cannot be drawn or written.
    #[error("{0}")]
    Chart(crate::chart::pairs::ChartError),
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

/// Fig. 4: lateral against longitudinal force as the slip ratio grows, for several slip angles.
fn adhesion_ellipse(
    base: &Params,
    dir: &Path,
    ext: &str,
    files: &mut Vec<PathBuf>,
) -> Result<(), ReproduceError> {
    let angles = [0.5, 1.0, 2.0, 4.0];
    let slips: Vec<f64> = (0..=200)
        .map(|i| 0.5 * (i as f64 / 200.0).powi(2))
        .collect();
    let mut rows: Vec<(f64, f64, f64, f64)> = Vec::new();
    let labels: Vec<String> = angles.iter().map(|a| format!("alpha = {a} deg")).collect();
    let mut series = Vec::new();
    for (a, label) in angles.iter().zip(&labels) {
        let p = Params {
            toe_deg: *a,
            ..*base
        };
        let patch = tire::contact_patch(&p).map_err(ReproduceError::Model)?;
        let pts: Vec<(f64, f64)> = slips
            .iter()
            .map(|s| {
                (
                    brush::longitudinal_force_n(&p, &patch, *s),
                    brush::lateral_force_n(&p, &patch, *s),
                )
            })
            .collect();
        rows.extend(
            slips
                .iter()
                .zip(&pts)
                .map(|(s, (fx, fy))| (*a, *s, *fx, *fy)),
        );
        series.push(Series { label, points: pts });
    }
    let png = dir.join(format!("fig4_adhesion.{ext}"));
    plot::panels(
        &png,
        (1000, 760),
        (1, 1),
        "Fig. 4: lateral vs longitudinal force as the slip ratio grows (brush model)",
        |_, area| {
            plot::line_panel(
                area,
                &format!("F_Z = {} N, P = {} kPa", base.load_n, base.pressure_kpa),
                "longitudinal force F_X [N]",
                "lateral force F_Y [N]",
                &series,
                false,
            )
        },
    )
    .map_err(ReproduceError::Figure)?;
    files.push(png);
    let csv = dir.join("fig4_adhesion.csv");
    write_csv(
        &csv,
        &[
            Column::f64("toe_deg", "deg", rows.iter().map(|r| r.0).collect()),
            Column::f64("slip_ratio", "-", rows.iter().map(|r| r.1).collect()),
            Column::f64("f_x_n", "N", rows.iter().map(|r| r.2).collect()),
            Column::f64("f_y_n", "N", rows.iter().map(|r| r.3).collect()),
        ],
    )
    .map_err(|e| ReproduceError::Table(e.to_string()))?;
    files.push(csv);
    Ok(())
}

/// Regenerates the paper's analyses into `dir` with `base` parameters, `steps` values per sweep
/// and `paired_samples` samples of the default study for the driving-vs-follower comparison.
pub fn reproduce(
    base: &Params,
    dir: &Path,
    steps: usize,
    paired_samples: u64,
) -> Result<Reproduction, ReproduceError> {
    reproduce_as(base, dir, steps, paired_samples, "png")
}

/// [`reproduce`] with the figures written as `ext` files: `png` or `svg`.
pub fn reproduce_as(
    base: &Params,
    dir: &Path,
    steps: usize,
    paired_samples: u64,
    ext: &str,
) -> Result<Reproduction, ReproduceError> {
    crate::safe_write::create_dir(dir).map_err(|e| ReproduceError::io(dir, e))?;
    let mut files = Vec::new();
    let opts = ClassifierOptions::default();
    adhesion_ellipse(base, dir, ext, &mut files)?;

    // Bifurcation diagrams (Figs. 6, 7, 12, 14, 16, 18, 20, 22, 23) for all three variants.
    let mut sweeps = Vec::new();
    for variant in Variant::ALL {
        for (axis, from, to) in AXES {
            let sw = sweep(base, axis, &linspace(from, to, steps), variant, &opts);
            let png = dir.join(format!("bifurcation_{axis}_{variant}.{ext}"));
            sw.draw(&png).map_err(ReproduceError::Figure)?;
            files.push(png);
            sweeps.push(sw);
        }
    }
    let mut cols = vec![
        Column::str(
            "sweep_param",
            sweeps
                .iter()
                .flat_map(|s| s.jobs.iter().map(|_| s.param.to_string()))
                .collect(),
        ),
        Column::f64(
            "sweep_value",
            "",
            sweeps
                .iter()
                .flat_map(|s| s.jobs.iter().map(|j| j.0))
                .collect(),
        ),
    ];
    let all: Vec<WheelRecord> = sweeps
        .iter()
        .flat_map(|s| s.records.iter().cloned())
        .collect();
    cols.extend(record_columns(&all));
    let pq = dir.join("bifurcation.parquet");
    write_table(
        &pq,
        &cols,
        &[("params".into(), serde_json::to_string(base).expect("json"))],
    )
    .map_err(|e| ReproduceError::Table(e.to_string()))?;
    files.push(pq);

    // Fig. 18: the cycle amplitude against speed, follower beside the driving wheel of each
    // variant (the follower is the same in every variant).
    amplitude_vs_speed(&sweeps, dir, ext, &mut files)?;

    // Time histories, phase portraits and spectra at the paper's points (Figs. 8–10, 13, 15, 17,
    // 19), both wheels in each figure, under the default variant; the driving wheel at 100 km/h
    // also under the two other variants.
    let d = Variant::DEFAULT;
    let points: [(&str, ParamId, f64, Variant); 8] = [
        ("fig8_speed70", ParamId::SpeedKmh, 70.0, d),
        ("fig9_10_speed100", ParamId::SpeedKmh, 100.0, d),
        ("fig13_toe0.35", ParamId::ToeDeg, 0.35, d),
        ("fig15_load5000", ParamId::LoadN, 5000.0, d),
        ("fig17_pressure200", ParamId::PressureKpa, 200.0, d),
        ("fig19_speed150", ParamId::SpeedKmh, 150.0, d),
        ("speed100_paper", ParamId::SpeedKmh, 100.0, Variant::Paper),
        (
            "speed100_combined",
            ParamId::SpeedKmh,
            100.0,
            Variant::Combined,
        ),
    ];
    let mut point_records = Vec::new();
    for (name, param, value, variant) in points {
        let mut p = *base;
        p[param] = value;
        let mut records = Vec::new();
        let mut series = Vec::new();
        for wheel in Wheel::BOTH {
            let (model, verdict) = classify_point(&p, wheel, variant, &opts);
            records.push(WheelRecord::new(&p, wheel, variant, &model, &verdict));
            if let Ok(m) = &model {
                let ts = time_series(m, 3.0, 20_000.0, opts.disturbance_m);
                series.push((wheel, ts.samples));
            }
        }
        let png = dir.join(format!("{name}.{ext}"));
        plot_point(&png, &series, &records, 20_000.0).map_err(ReproduceError::Figure)?;
        files.push(png);
        point_records.push((name, records));
    }

    // Stability charts of the four axes two at a time, both wheels (default variant).
    let (chart_files, charts_md) =
        crate::chart::pairs::operating_pairs(base, Variant::DEFAULT, &AXES, dir)
            .map_err(ReproduceError::Chart)?;
    files.extend(chart_files);

    let paired = paired_comparison(base, paired_samples)?;
    let report = report(base, &sweeps, &point_records, &paired, &files).replacen(
        "## Figures\n",
        &format!("{charts_md}\n## Figures\n"),
        1,
    );
    let md = dir.join("report.md");
    crate::safe_write::write_file(&md, report.as_bytes())
        .map_err(|e| ReproduceError::io(&md, e))?;
    files.push(md);
    Ok(Reproduction {
        sweeps,
        files,
        report,
        paired,
    })
}

/// Fig. 18 (both wheels): limit-cycle amplitude of y against speed, from the speed sweeps.
fn amplitude_vs_speed(
    sweeps: &[Sweep],
    dir: &Path,
    ext: &str,
    files: &mut Vec<PathBuf>,
) -> Result<(), ReproduceError> {
    let mut labels = Vec::new();
    let mut points = Vec::new();
    for (variant, wheel) in [
        (Variant::DEFAULT, Wheel::Follower),
        (Variant::Paper, Wheel::Driving),
        (Variant::Combined, Wheel::Driving),
        (Variant::SlidingShare, Wheel::Driving),
    ] {
        let sw = find(sweeps, ParamId::SpeedKmh, variant);
        labels.push(match wheel {
            Wheel::Follower => "follower (every variant)".to_string(),
            Wheel::Driving => format!("driving, {variant}"),
        });
        points.push(
            sw.jobs
                .iter()
                .zip(&sw.records)
                .filter(|(j, _)| j.1 == wheel)
                .map(|(j, r)| {
                    (
                        j.0,
                        if r.amp_y_m.is_finite() {
                            r.amp_y_m
                        } else {
                            0.0
                        },
                    )
                })
                .collect::<Vec<_>>(),
        );
    }
    let series: Vec<Series> = labels
        .iter()
        .zip(points)
        .map(|(label, points)| Series { label, points })
        .collect();
    let png = dir.join(format!("fig18_amplitude_vs_speed.{ext}"));
    plot::panels(
        &png,
        (1000, 700),
        (1, 1),
        "Fig. 18: self-excited vibration amplitude against speed, follower and driving wheel",
        |_, area| {
            plot::line_panel(
                area,
                "half peak-to-peak of y on the limit cycle (0: stable)",
                "vehicle speed [km/h]",
                "amplitude of y [m]",
                &series,
                false,
            )
        },
    )
    .map_err(ReproduceError::Figure)?;
    files.push(png);
    Ok(())
}

/// Draws `samples` points of the built-in default study (its tire-structure uncertainty around
/// `base`), classifies both wheels under every variant, and pairs them as the analysis does
/// ([`PairTally`]): driving against follower on the same samples, per variant.
pub fn paired_comparison(base: &Params, samples: u64) -> Result<Vec<Paired>, ReproduceError> {
    use rayon::prelude::*;
    let mut study = crate::study::Study::parse_with_base(crate::study::DEFAULT_STUDY, *base)
        .map_err(|e| ReproduceError::Study(e.to_string()))?;
    study.variants = Variant::ALL.to_vec();
    let sampler = study.sampler(study.seed, samples);
    let opts = ClassifierOptions::default();
    let rows: Vec<crate::explore::SampleRows> = (0..samples)
        .into_par_iter()
        .map(|i| crate::explore::evaluate_sample(&study, &sampler, i, &opts))
        .collect();
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

fn find(sweeps: &[Sweep], param: ParamId, variant: Variant) -> &Sweep {
    sweeps
        .iter()
        .find(|s| s.param == param && s.variant == variant)
        .expect("swept")
}

/// The paper's Table 3 as legible (MODEL.md#targets): (axis, follower,
/// driving).
const PAPER_TABLE3: [(&str, &str, &str); 4] = [
    (
        "speed_kmh",
        "Hopf ≈ 80 (eigenvalues); 1x.7–19x.5 (simulation)",
        "narrower",
    ),
    ("toe_deg", "0.2x–0.41", "0.x–0.35"),
    ("load_n", "> 351x", "> 3 + lost digits (38xx)"),
    ("pressure_kpa", "< 33x", "< 2x7 or 27x"),
];

fn report(
    base: &Params,
    sweeps: &[Sweep],
    points: &[(&str, Vec<WheelRecord>)],
    paired: &[Paired],
    files: &[PathBuf],
) -> String {
    let mut s = String::new();
    let name = |f: &PathBuf| {
        f.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let d = Variant::DEFAULT;
    let _ = writeln!(
        s,
        "# Zuo, Duan & Li (2014) reproduced with polywear {}\n",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        s,
        "Every number here comes from polywear's engine (`polywear reproduce`), with the shipped \
         parameters (`polywear params`) unless a `--params` file says otherwise. The paper's only \
         copy lost the digits 0, 2, 4 and 8, so its values are quoted as legible, with `x` for a \
         lost digit. Three friction variants are shown; they differ for the driving wheel only \
         (the follower rolls freely, S = 0):\n\n\
         | variant | sliding speed in the Stribeck curve (MODEL.md#step-6-tread-ode) | driving wheel |\n\
         |---|---|---|\n\
         | `sliding_share` (default) | sqrt(w² + (q·V cos α·S/(1+S))²): patch-mean longitudinal sliding | narrower ranges, lower amplitude, less often: the paper's conclusion |\n\
         | `paper` | \\|w\\| (the paper's Eq. 21 as printed) | almost identical to the follower, marginally *less* stable: contradicts the paper |\n\
         | `combined` | sqrt(w² + (V cos α·S/(1+S))²): full longitudinal sliding | stable everywhere: too strong |\n"
    );
    let rec = |pt: &str, wheel: Wheel| -> Option<&WheelRecord> {
        points
            .iter()
            .find(|(n, _)| *n == pt)
            .and_then(|(_, r)| r.iter().find(|r| r.wheel == wheel))
    };
    let f = Wheel::Follower;
    let sp = find(sweeps, ParamId::SpeedKmh, d);
    let fr = |r: &[(f64, f64)], axis: ParamId| fmt_ranges(r, "", bounds(axis));
    let _ = writeln!(s, "## The paper's results beside polywear's (follower)\n");
    let _ = writeln!(
        s,
        "| result | paper (legible) | polywear, follower | comment |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    let r100 = rec("fig9_10_speed100", f);
    let r70 = rec("fig8_speed70", f);
    let _ = writeln!(
        s,
        "| eigenvalue analysis vs speed | stable at low speed, Hopf near 80 km/h (decoded), stable again at high speed | unstable on {} km/h | see (1) |",
        fr(&sp.unstable_ranges(f), ParamId::SpeedKmh)
    );
    let _ = writeln!(
        s,
        "| simulation at 70 km/h | stable | {} | agrees |",
        r70.map_or("?", |r| r.class.as_str())
    );
    let _ = writeln!(
        s,
        "| simulation at 100 km/h | self-excited vibration | {} (amplitude of v {:.4} m/s) | agrees |",
        r100.map_or("?", |r| r.class.as_str()),
        r100.map_or(f64::NAN, |r| r.amp_v_mps)
    );
    let _ = writeln!(
        s,
        "| vibration frequency | about 27x Hz (model); 250 Hz measured | {:.1} Hz (cycle), {:.1} Hz (linear) at 100 km/h | G is fitted to both wheels' Table 3 with the frequency among the targets |",
        r100.map_or(f64::NAN, |r| r.freq_hz),
        r100.map_or(f64::NAN, |r| r.eig_freq_hz)
    );
    let _ = writeln!(
        s,
        "| polygon order | 18-gon observed | {:.2} at 100 km/h | the observed wear integrates speeds; f/f_rot falls with speed |",
        r100.map_or(f64::NAN, |r| r.polygon_order)
    );

    let _ = writeln!(
        s,
        "\n## Table 3 from the engine: where self-excited vibration occurs, both wheels\n"
    );
    let _ = writeln!(s, "Intervals of each parameter (others at their defaults: {} km/h, {}°, {} N, {} kPa) where the equilibrium is unstable, bounded by Hopf points located to 1e-6 relative within the swept ranges. The follower is the same in every variant.\n", base.speed_kmh, base.toe_deg, base.load_n, base.pressure_kpa);
    let _ = writeln!(s, "| parameter | paper, follower | paper, driving | follower (every variant) | driving, `sliding_share` | driving, `paper` | driving, `combined` |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (&(axis, from, to), (_, pf, pd)) in AXES.iter().zip(PAPER_TABLE3) {
        let unit = axis.spec().unit;
        let cell = |v: Variant, w: Wheel| {
            fmt_ranges(&find(sweeps, axis, v).unstable_ranges(w), unit, (from, to))
        };
        let _ = writeln!(
            s,
            "| {axis} (swept {from}–{to}) | {pf} | {pd} | {} | {} | {} | {} |",
            cell(d, Wheel::Follower),
            cell(Variant::SlidingShare, Wheel::Driving),
            cell(Variant::Paper, Wheel::Driving),
            cell(Variant::Combined, Wheel::Driving)
        );
    }

    let _ = writeln!(s, "\n## Figs. 18 and 19: driving against follower\n");
    let _ = writeln!(
        s,
        "At 100 km/h (defaults otherwise), each wheel's limit cycle:\n"
    );
    let _ = writeln!(s, "| variant | wheel | class | amplitude of y [m] | amplitude of v [m/s] | frequency [Hz] | energy per cycle [J] |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (pt, variant) in [
        ("fig9_10_speed100", d),
        ("speed100_paper", Variant::Paper),
        ("speed100_combined", Variant::Combined),
    ] {
        for w in Wheel::BOTH {
            if let Some(r) = rec(pt, w) {
                let _ = writeln!(
                    s,
                    "| `{variant}` | {w} | {} | {:.4e} | {:.4e} | {:.2} | {:.4e} |",
                    r.class, r.amp_y_m, r.amp_v_mps, r.freq_hz, r.energy_per_cycle_j
                );
            }
        }
    }
    let amp = |pt: &str, w: Wheel| rec(pt, w).map_or(f64::NAN, |r| r.amp_y_m);
    let _ = writeln!(
        s,
        "\nUnder `{d}` the driving wheel's amplitude at 100 km/h is {:.0}% of the follower's (the paper: lower oscillation energy). `fig18_amplitude_vs_speed` draws the amplitude against speed for the follower and each variant's driving wheel; `fig9_10_speed100` and `fig19_speed150` show both wheels' time histories.",
        100.0 * amp("fig9_10_speed100", Wheel::Driving) / amp("fig9_10_speed100", f)
    );

    let _ = writeln!(
        s,
        "\n## Which wheel vibrates more often: the default study, paired\n"
    );
    let n = paired.first().map_or(0, |r| r.pairs);
    let _ = writeln!(s, "The same {n} samples of the built-in default study (`studies/default.toml`: speed, toe-in, load, pressure and tire-structure uncertainty), both wheels of each, under each variant. Samples where a wheel failed or lost traction are left out of this table.\n");
    let _ = writeln!(s, "| variant | samples | P(follower vibrates) | P(driving vibrates) | both | follower only | driving only |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for r in paired {
        let _ = writeln!(
            s,
            "| `{}` | {} | {:.2}% | {:.2}% | {} | {} | {} |",
            r.variant,
            r.pairs,
            100.0 * r.p_follower(),
            100.0 * r.p_driving(),
            r.both,
            r.only_follower,
            r.only_driving
        );
    }

    let hopf = |v: Variant, w: Wheel| {
        find(sweeps, ParamId::SpeedKmh, v)
            .hopf
            .iter()
            .find(|h| h.wheel == w && h.destabilizing)
            .map_or(f64::NAN, |h| h.value)
    };
    let _ = writeln!(
        s,
        "\n## Why the literal equations cannot carry the paper's conclusion\n"
    );
    let _ = writeln!(s, "The paper concludes that the driving wheel vibrates over narrower ranges, with less energy, and less often than the follower. Its equations as printed (`paper` variant) say the opposite, and loudly so in the table above:\n");
    let (fm_f, fm_d, slip, q) = match (
        rec("speed100_paper", f),
        rec("speed100_paper", Wheel::Driving),
    ) {
        (Some(a), Some(b)) => (a.f_m, b.f_m, b.slip_ratio, b.q),
        _ => (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
    };
    let p100 = Params {
        speed_kmh: 100.0,
        ..*base
    };
    let (v, alpha) = (p100.speed_mps(), p100.toe_rad());
    let v_sx_full = crate::model::longitudinal_sliding_mps(Variant::Combined, v, alpha, slip, q);
    let v_sx_share =
        crate::model::longitudinal_sliding_mps(Variant::SlidingShare, v, alpha, slip, q);
    let _ = writeln!(s, "- In Eq. 19 the driving wheel's slip ratio S enters F_m and F_s through the same factor q(3−2q)(1+S)tan α / r(S). At 100 km/h both friction levels move together by {:+.2}%, and in this regime *lower* friction levels destabilise, so the driving wheel comes out marginally less stable than the follower (onset {:.2} km/h against {:.2} km/h), vibrates slightly more often, and there are samples where only the driving wheel vibrates and none where only the follower does.", 100.0 * (fm_d / fm_f - 1.0), hopf(Variant::Paper, Wheel::Driving), hopf(d, f));
    let _ = writeln!(s, "- Eq. 21 lets only the lateral sliding speed w reach the Stribeck curve. A driving wheel also slides lengthwise, and a Stribeck curve is a function of the total sliding speed: that is the missing mechanism. Taking the full longitudinal sliding speed V cos α S/(1+S) (`combined`, a 2-D LuGre law) is too strong: {v_sx_full:.4} m/s at 100 km/h against U = V sin α = {:.4} m/s and V_s = {} m/s, it pushes the driving wheel past the Stribeck drop and makes it stable everywhere.", v * alpha.sin(), base.v_s);
    let share = paired.iter().find(|r| r.variant == Variant::SlidingShare);
    let _ = writeln!(s, "- `sliding_share` assumes what the brush model itself says: only the sliding share q of the contact length slides; the adhesion zone moves with the road. The patch-mean longitudinal sliding speed is therefore q·V cos α S/(1+S) ({v_sx_share:.4} m/s at 100 km/h, q = {q:.4}). With it the driving wheel's vibration ranges lie inside the follower's on every axis (Table 3 above), its amplitude is lower, it vibrates in {:.1}% of the default-study samples against the follower's {:.1}%, and {} samples vibrate on the driving wheel alone: the paper's Table 3 and conclusion.", share.map_or(f64::NAN, |r| 100.0 * r.p_driving()), share.map_or(f64::NAN, |r| 100.0 * r.p_follower()), share.map_or(0, |r| r.only_driving));
    let _ = writeln!(s, "- The shipped constants G, C and α2 (reconstructed, MODEL.md#constants; α2's digits were all lost) are fitted to both wheels' legible Table 3 results under `sliding_share` (`polywear calibrate studies/paper_targets.toml`), with the decoded constants kept at values their legible digits allow. The reference constants R0 (MODEL.md#r0-and-the-shipped-defaults) remain available as `--params studies/params_r0.toml`. `studies/decoding.toml` checks that the conclusion does not hang on one reading of the lost digits.\n");

    let _ = writeln!(s, "## Figures\n");
    let is_figure = |f: &PathBuf| {
        f.extension()
            .is_some_and(|e| crate::plot::backend::FORMATS.iter().any(|x| e == *x))
    };
    for f in files.iter().filter(|f| is_figure(f)) {
        let stem = f
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let _ = writeln!(s, "### {stem}\n\n![]({})\n", name(f));
    }
    let _ = writeln!(s, "Tables: `bifurcation.parquet` (every sweep, both wheels, all three variants), `fig4_adhesion.csv`.");
    s
}
