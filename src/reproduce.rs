//! `polywear reproduce`: the paper's analyses regenerated with polywear's own engine, and a
//! report that sets each result beside the paper's legible values (MODEL.md, "Targets").

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::bifurcation::{linspace, sweep, Sweep};
use crate::classify::{classify_point, ClassifierOptions};
use crate::model::{brush, tire, Variant, Wheel};
use crate::params::Params;
use crate::parquet_out::{write_csv, write_table, Column};
use crate::plot::{self, Series};
use crate::records::{record_columns, WheelRecord};
use crate::trajectory::{plot_point, time_series};

/// The four axes of the paper's bifurcation diagrams and Table 3, with their sweep ranges.
pub const AXES: [(&str, f64, f64); 4] = [
    ("speed_kmh", 40.0, 260.0),
    ("toe_deg", 0.05, 1.0),
    ("load_n", 2000.0, 7000.0),
    ("pressure_kpa", 150.0, 450.0),
];

/// What was reproduced, for the report and the command's summary.
pub struct Reproduction {
    pub sweeps: Vec<Sweep>,
    pub files: Vec<PathBuf>,
    pub report: String,
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

fn bounds(axis: &str) -> (f64, f64) {
    AXES.iter()
        .find(|a| a.0 == axis)
        .map_or((f64::NAN, f64::NAN), |a| (a.1, a.2))
}

/// Fig. 4: lateral against longitudinal force as the slip ratio grows, for several slip angles.
fn adhesion_ellipse(base: &Params, dir: &Path, files: &mut Vec<PathBuf>) -> Result<(), String> {
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
        let patch = tire::contact_patch(&p)?;
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
    let png = dir.join("fig4_adhesion.png");
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
    )?;
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
    .map_err(|e| e.to_string())?;
    files.push(csv);
    Ok(())
}

/// Regenerates the paper's analyses into `dir` with `base` parameters and `steps` values per sweep.
pub fn reproduce(base: &Params, dir: &Path, steps: usize) -> Result<Reproduction, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut files = Vec::new();
    let opts = ClassifierOptions::default();
    adhesion_ellipse(base, dir, &mut files)?;

    // Bifurcation diagrams (Figs. 6, 7, 12, 14, 16, 18, 20, 22, 23) for both variants.
    let mut sweeps = Vec::new();
    for variant in Variant::ALL {
        for (axis, from, to) in AXES {
            let name = crate::params::spec(axis).expect("known").name;
            let sw = sweep(base, name, &linspace(from, to, steps), variant, &opts);
            let png = dir.join(format!("bifurcation_{axis}_{variant}.png"));
            sw.draw(&png)?;
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
    .map_err(|e| e.to_string())?;
    files.push(pq);

    // Time histories, phase portraits and spectra at the paper's points (Figs. 8–10, 13, 15, 17, 19, 21).
    let points: [(&str, &str, f64, Variant); 7] = [
        ("fig8_speed70", "speed_kmh", 70.0, Variant::Paper),
        ("fig9_10_speed100", "speed_kmh", 100.0, Variant::Paper),
        ("fig13_toe0.35", "toe_deg", 0.35, Variant::Paper),
        ("fig15_load5000", "load_n", 5000.0, Variant::Paper),
        ("fig17_pressure200", "pressure_kpa", 200.0, Variant::Paper),
        ("fig19_speed150", "speed_kmh", 150.0, Variant::Paper),
        (
            "fig21_speed100_combined",
            "speed_kmh",
            100.0,
            Variant::Combined,
        ),
    ];
    let mut point_records = Vec::new();
    for (name, param, value, variant) in points {
        let mut p = *base;
        *p.get_mut(param).expect("known") = value;
        let mut records = Vec::new();
        let mut series = Vec::new();
        for wheel in Wheel::BOTH {
            let (model, verdict) = classify_point(&p, wheel, variant, &opts);
            records.push(WheelRecord::new(&p, wheel, variant, &model, &verdict));
            if let Ok(m) = &model {
                series.push((wheel, time_series(m, 3.0, 20_000.0, opts.disturbance_m)));
            }
        }
        let png = dir.join(format!("{name}.png"));
        plot_point(&png, &series, &records, 20_000.0)?;
        files.push(png);
        point_records.push((name, records));
    }

    let report = report(base, &sweeps, &point_records, &files);
    let md = dir.join("report.md");
    std::fs::write(&md, &report).map_err(|e| format!("{}: {e}", md.display()))?;
    files.push(md);
    Ok(Reproduction {
        sweeps,
        files,
        report,
    })
}

fn find<'a>(sweeps: &'a [Sweep], param: &str, variant: Variant) -> &'a Sweep {
    sweeps
        .iter()
        .find(|s| s.param == param && s.variant == variant)
        .expect("swept")
}

fn report(
    base: &Params,
    sweeps: &[Sweep],
    points: &[(&str, Vec<WheelRecord>)],
    files: &[PathBuf],
) -> String {
    let mut s = String::new();
    let name = |f: &PathBuf| {
        f.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let _ = writeln!(
        s,
        "# Zuo, Duan & Li (2014) reproduced with polywear {}\n",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        s,
        "Every number here comes from polywear's engine (`polywear reproduce`), with the parameters of \
         MODEL.md (defaults unless a `--params` file says otherwise). The paper's only copy lost the digits \
         0, 2, 4 and 8, so its values are quoted as legible, with `x` for a lost digit. Both friction \
         variants are shown: `paper` is the paper's Eq. 21; `combined` adds the driving wheel's \
         longitudinal sliding to the Stribeck curve (a 2-D LuGre extension).\n"
    );
    let sp = find(sweeps, "speed_kmh", Variant::Paper);
    let toe = find(sweeps, "toe_deg", Variant::Paper);
    let load = find(sweeps, "load_n", Variant::Paper);
    let pres = find(sweeps, "pressure_kpa", Variant::Paper);
    let rec = |pt: &str, wheel: &str| -> Option<&WheelRecord> {
        points
            .iter()
            .find(|(n, _)| *n == pt)
            .and_then(|(_, r)| r.iter().find(|r| r.wheel == wheel))
    };
    let fr = |r: &[(f64, f64)], axis: &str| fmt_ranges(r, "", bounds(axis));
    let _ = writeln!(s, "## The paper's results beside polywear's\n");
    let _ = writeln!(s, "| result | paper (legible) | MODEL.md reference model | polywear, `paper` variant, follower | comment |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    let r100 = rec("fig9_10_speed100", "follower");
    let r70 = rec("fig8_speed70", "follower");
    let _ = writeln!(
        s,
        "| eigenvalue analysis vs speed | stable at low speed, Hopf near 80 km/h (decoded), stable again at high speed | window ≈ 93–224 km/h | unstable on {} km/h | see (1) |",
        fr(&sp.unstable_ranges(Wheel::Follower), "speed_kmh")
    );
    let _ = writeln!(
        s,
        "| simulation at 70 km/h | stable | stable | {} | agrees |",
        r70.map_or("?", |r| r.class)
    );
    let _ = writeln!(
        s,
        "| simulation at 100 km/h | self-excited vibration | limit cycle | {} (amplitude of v {:.4} m/s) | agrees |",
        r100.map_or("?", |r| r.class),
        r100.map_or(f64::NAN, |r| r.amp_v_mps)
    );
    let _ = writeln!(
        s,
        "| vibration frequency | about 27x Hz (model); 250 Hz measured | ≈ 270 Hz | {:.1} Hz (cycle), {:.1} Hz (linear) at 100 km/h | G was reconstructed to give ≈ 270 Hz; the measured 250 Hz is a real wheel |",
        r100.map_or(f64::NAN, |r| r.freq_hz),
        r100.map_or(f64::NAN, |r| r.eig_freq_hz)
    );
    let _ = writeln!(
        s,
        "| polygon order | 18-gon observed | ≈ 19 at 100 km/h | {:.2} at 100 km/h | the observed wear integrates speeds; f/f_rot falls with speed |",
        r100.map_or(f64::NAN, |r| r.polygon_order)
    );
    let _ = writeln!(
        s,
        "| toe-in window | about 0.2x° to 0.41° | ≈ 0.21–0.41° | {}° | agrees |",
        fr(&toe.unstable_ranges(Wheel::Follower), "toe_deg")
    );
    let _ = writeln!(
        s,
        "| load threshold | above about 351x N | ≈ 3280 N | vibration at {} N | see (2) |",
        fr(&load.unstable_ranges(Wheel::Follower), "load_n")
    );
    let _ = writeln!(
        s,
        "| pressure threshold | below about 33x kPa | ≈ 342 kPa | vibration at {} kPa | see (2) |",
        fr(&pres.unstable_ranges(Wheel::Follower), "pressure_kpa")
    );
    let e = |pt: &str, w: &str| rec(pt, w).map_or(f64::NAN, |r| r.energy_per_cycle_j);
    let _ = writeln!(
        s,
        "| driving vs follower | driving: narrower ranges, lower oscillation energy | `paper`: almost identical; `combined`: far more stable | energy per cycle at 100 km/h: follower {:.3e} J, driving {:.3e} J (`paper`); driving under `combined`: {} | see (3) |",
        e("fig9_10_speed100", "follower"),
        e("fig9_10_speed100", "driving"),
        rec("fig21_speed100_combined", "driving").map_or("?", |r| r.class)
    );
    let _ = writeln!(
        s,
        "\n## Table 3 from the engine: where self-excited vibration occurs\n"
    );
    let _ = writeln!(s, "Intervals of each parameter (others at their defaults, {} km/h) where the equilibrium is unstable, bounded by the Hopf points that `polywear bifurcation` locates to 1e-6 relative within the swept ranges.\n", base.speed_kmh);
    let _ = writeln!(s, "| parameter | follower (`paper`) | driving (`paper`) | follower (`combined`) | driving (`combined`) |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for (axis, from, to) in AXES {
        let unit = crate::params::spec(axis).map_or("", |x| x.unit);
        let cell = |v: Variant, w: Wheel| {
            fmt_ranges(&find(sweeps, axis, v).unstable_ranges(w), unit, (from, to))
        };
        let _ = writeln!(
            s,
            "| {axis} (swept {from}–{to}) | {} | {} | {} | {} |",
            cell(Variant::Paper, Wheel::Follower),
            cell(Variant::Paper, Wheel::Driving),
            cell(Variant::Combined, Wheel::Follower),
            cell(Variant::Combined, Wheel::Driving)
        );
    }
    let _ = writeln!(s, "\nThe paper's Table 3 as legible: follower load > 351x N and pressure < 33x kPa; driving wheel load > 3 followed by lost digits, pressure < a value whose only legible digit is 7; the speed and toe-in cells are illegible.\n");
    let _ = writeln!(s, "## Why the numbers differ\n");
    let _ = writeln!(s, "1. **Onset speed.** With MODEL.md's decoded and reconstructed parameters the lower Hopf point lies at {:.1} km/h, not the paper's ≈ 80 km/h. The paper's own figures are mutually consistent only up to the lost digits: its simulation at 100 km/h vibrates and at 70 km/h does not, and both hold here. Several parameters (G, C, V_s, φ) were reconstructed from the paper's legible results; `polywear calibrate studies/paper_targets.toml` fits them to the legible targets and shows how far the model can move toward 80 km/h while keeping the frequency, toe, load and pressure targets.", sp.hopf.iter().find(|h| h.wheel == Wheel::Follower && h.destabilizing).map_or(f64::NAN, |h| h.value));
    let _ = writeln!(s, "2. **Load and pressure thresholds.** MODEL.md's reference model puts them at ≈ 3280 N and ≈ 342 kPa; polywear agrees with that model. The paper's 351x N and 33x kPa differ by a few per cent, again within what the reconstructed parameters leave open.");
    let _ = writeln!(s, "3. **Driving vs follower.** The paper reports a narrower vibration range and lower energy for the driving wheel. Under its own Eq. 19 (`paper` variant) both friction levels scale by the same factor, so the driving wheel's slip barely moves the boundary: polywear finds the two wheels almost identical, the driving wheel even marginally less stable. The `combined` variant, in which the longitudinal sliding speed enters the Stribeck curve, reproduces the paper's qualitative finding: the driving wheel is far more stable. The paper's conclusion needs a mechanism like `combined`'s; its Eq. 21 alone does not carry it.\n");
    let _ = writeln!(s, "## Figures\n");
    for f in files.iter().filter(|f| name(f).ends_with(".png")) {
        let _ = writeln!(
            s,
            "### {}\n\n![]({})\n",
            name(f).trim_end_matches(".png"),
            name(f)
        );
    }
    let _ = writeln!(s, "Tables: `bifurcation.parquet` (every sweep, both wheels and variants), `fig4_adhesion.csv`.");
    s
}
