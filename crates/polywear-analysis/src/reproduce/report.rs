//! `report.md` of a [`Reproduction`]: each of the paper's results beside polywear's, section by
//! section, from the result alone (no string lookups, no splicing).

use std::fmt::Write as _;
use std::path::PathBuf;

use super::{PaperPoint, Reproduction, AXES};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::{ParamId, Params};

/// The paper's Table 3 as legible (MODEL.md#targets): (axis, follower, driving).
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

/// The report: the sections in order, the charts' section (`charts_md`) before the list of the
/// figures among `files`.
pub(super) fn report(r: &Reproduction, charts_md: &str, files: &[PathBuf]) -> String {
    let mut s = String::new();
    intro(&mut s);
    follower_results(&mut s, r);
    table3(&mut s, r);
    driving_against_follower(&mut s, r);
    paired_section(&mut s, r);
    why_not_literal(&mut s, r);
    let _ = writeln!(s, "{charts_md}");
    figures(&mut s, files);
    s
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

fn intro(s: &mut String) {
    let _ = writeln!(
        s,
        "# Zuo, Duan & Li (2014) reproduced with polywear {}\n",
        polywear_study::provenance::POLYWEAR_VERSION
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
}

fn follower_results(s: &mut String, r: &Reproduction) {
    let d = Variant::DEFAULT;
    let f = Wheel::Follower;
    let sp = r.sweep(ParamId::SpeedKmh, d);
    let fr = |x: &[(f64, f64)], axis: ParamId| fmt_ranges(x, "", bounds(axis));
    let _ = writeln!(s, "## The paper's results beside polywear's (follower)\n");
    let _ = writeln!(
        s,
        "| result | paper (legible) | polywear, follower | comment |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    let r100 = r.record(PaperPoint::Speed100, f);
    let r70 = r.record(PaperPoint::Speed70, f);
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
}

fn table3(s: &mut String, r: &Reproduction) {
    let d = Variant::DEFAULT;
    let base = &r.request.base;
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
            fmt_ranges(&r.sweep(axis, v).unstable_ranges(w), unit, (from, to))
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
}

fn driving_against_follower(s: &mut String, r: &Reproduction) {
    let d = Variant::DEFAULT;
    let f = Wheel::Follower;
    let _ = writeln!(s, "\n## Figs. 18 and 19: driving against follower\n");
    let _ = writeln!(
        s,
        "At 100 km/h (defaults otherwise), each wheel's limit cycle:\n"
    );
    let _ = writeln!(s, "| variant | wheel | class | amplitude of y [m] | amplitude of v [m/s] | frequency [Hz] | energy per cycle [J] |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for (pt, variant) in [
        (PaperPoint::Speed100, d),
        (PaperPoint::Speed100Paper, Variant::Paper),
        (PaperPoint::Speed100Combined, Variant::Combined),
    ] {
        for w in Wheel::BOTH {
            if let Some(row) = r.record(pt, w) {
                let _ = writeln!(
                    s,
                    "| `{variant}` | {w} | {} | {:.4e} | {:.4e} | {:.2} | {:.4e} |",
                    row.class, row.amp_y_m, row.amp_v_mps, row.freq_hz, row.energy_per_cycle_j
                );
            }
        }
    }
    let amp = |pt: PaperPoint, w: Wheel| r.record(pt, w).map_or(f64::NAN, |r| r.amp_y_m);
    let _ = writeln!(
        s,
        "\nUnder `{d}` the driving wheel's amplitude at 100 km/h is {:.0}% of the follower's (the paper: lower oscillation energy). `fig18_amplitude_vs_speed` draws the amplitude against speed for the follower and each variant's driving wheel; `fig9_10_speed100` and `fig19_speed150` show both wheels' time histories.",
        100.0 * amp(PaperPoint::Speed100, Wheel::Driving) / amp(PaperPoint::Speed100, f)
    );
}

fn paired_section(s: &mut String, r: &Reproduction) {
    let _ = writeln!(
        s,
        "\n## Which wheel vibrates more often: the default study, paired\n"
    );
    let n = r.paired.first().map_or(0, |r| r.pairs);
    let _ = writeln!(s, "The same {n} samples of the built-in default study (`studies/default.toml`: speed, toe-in, load, pressure and tire-structure uncertainty), both wheels of each, under each variant. Samples where a wheel failed or lost traction are left out of this table.\n");
    let _ = writeln!(s, "| variant | samples | P(follower vibrates) | P(driving vibrates) | both | follower only | driving only |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for row in &r.paired {
        let _ = writeln!(
            s,
            "| `{}` | {} | {:.2}% | {:.2}% | {} | {} | {} |",
            row.variant,
            row.pairs,
            100.0 * row.p_follower(),
            100.0 * row.p_driving(),
            row.both,
            row.only_follower,
            row.only_driving
        );
    }
}

fn why_not_literal(s: &mut String, r: &Reproduction) {
    let d = Variant::DEFAULT;
    let f = Wheel::Follower;
    let base = &r.request.base;
    let hopf = |v: Variant, w: Wheel| {
        r.sweep(ParamId::SpeedKmh, v)
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
        r.record(PaperPoint::Speed100Paper, f),
        r.record(PaperPoint::Speed100Paper, Wheel::Driving),
    ) {
        (Some(a), Some(b)) => (a.f_m, b.f_m, b.slip_ratio, b.q),
        _ => (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
    };
    let p100 = Params {
        speed_kmh: 100.0,
        ..*base
    };
    let (v, alpha) = (p100.speed_mps(), p100.toe_rad());
    let v_sx_full =
        polywear_core::model::longitudinal_sliding_mps(Variant::Combined, v, alpha, slip, q);
    let v_sx_share =
        polywear_core::model::longitudinal_sliding_mps(Variant::SlidingShare, v, alpha, slip, q);
    let _ = writeln!(s, "- In Eq. 19 the driving wheel's slip ratio S enters F_m and F_s through the same factor q(3−2q)(1+S)tan α / r(S). At 100 km/h both friction levels move together by {:+.2}%, and in this regime *lower* friction levels destabilise, so the driving wheel comes out marginally less stable than the follower (onset {:.2} km/h against {:.2} km/h), vibrates slightly more often, and there are samples where only the driving wheel vibrates and none where only the follower does.", 100.0 * (fm_d / fm_f - 1.0), hopf(Variant::Paper, Wheel::Driving), hopf(d, f));
    let _ = writeln!(s, "- Eq. 21 lets only the lateral sliding speed w reach the Stribeck curve. A driving wheel also slides lengthwise, and a Stribeck curve is a function of the total sliding speed: that is the missing mechanism. Taking the full longitudinal sliding speed V cos α S/(1+S) (`combined`, a 2-D LuGre law) is too strong: {v_sx_full:.4} m/s at 100 km/h against U = V sin α = {:.4} m/s and V_s = {} m/s, it pushes the driving wheel past the Stribeck drop and makes it stable everywhere.", v * alpha.sin(), base.v_s);
    let share = r.paired.iter().find(|x| x.variant == Variant::SlidingShare);
    let _ = writeln!(s, "- `sliding_share` assumes what the brush model itself says: only the sliding share q of the contact length slides; the adhesion zone moves with the road. The patch-mean longitudinal sliding speed is therefore q·V cos α S/(1+S) ({v_sx_share:.4} m/s at 100 km/h, q = {q:.4}). With it the driving wheel's vibration ranges lie inside the follower's on every axis (Table 3 above), its amplitude is lower, it vibrates in {:.1}% of the default-study samples against the follower's {:.1}%, and {} samples vibrate on the driving wheel alone: the paper's Table 3 and conclusion.", share.map_or(f64::NAN, |x| 100.0 * x.p_driving()), share.map_or(f64::NAN, |x| 100.0 * x.p_follower()), share.map_or(0, |x| x.only_driving));
    let _ = writeln!(s, "- The shipped constants G, C and α2 (reconstructed, MODEL.md#constants; α2's digits were all lost) are fitted to both wheels' legible Table 3 results under `sliding_share` (`polywear calibrate studies/paper_targets.toml`), with the decoded constants kept at values their legible digits allow. The reference constants R0 (MODEL.md#r0-and-the-shipped-defaults) remain available as `--params studies/params_r0.toml`. `studies/decoding.toml` checks that the conclusion does not hang on one reading of the lost digits.\n");
}

fn figures(s: &mut String, files: &[PathBuf]) {
    let name = |f: &PathBuf| {
        f.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let _ = writeln!(s, "## Figures\n");
    let is_figure = |f: &PathBuf| crate::plot::FigureFormat::of_path(f).is_some();
    for f in files.iter().filter(|f| is_figure(f)) {
        let stem = f
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let _ = writeln!(s, "### {stem}\n\n![]({})\n", name(f));
    }
    let _ = writeln!(s, "Tables: `bifurcation.parquet` (every sweep, both wheels, all three variants), `fig4_adhesion.csv`.");
}
