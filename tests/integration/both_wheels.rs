//! The shipped defaults answer the driving-vs-follower question as the paper does.
//! Hopf points of both wheels in the paper's bands (MODEL.md#targets and #variants), every
//! driving range inside the follower's, the default study's paired comparison, and the literal
//! equations' reversed answer kept visible.

use crate::common::polywear;
use polywear::classify::ClassifierOptions;
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::{ParamId, Params};
use polywear_analysis::reproduce::paired_comparison;
use polywear_study::bifurcation::{linspace, sweep};

/// Unstable interval of `axis` for a wheel, from a sweep of the shipped defaults.
fn window(p: &Params, axis: ParamId, from: f64, to: f64, wheel: Wheel) -> (f64, f64) {
    let sw = sweep(
        p,
        axis,
        &linspace(from, to, 61),
        Variant::DEFAULT,
        &ClassifierOptions::default(),
    );
    let r = sw.unstable_ranges(wheel);
    assert_eq!(r.len(), 1, "{axis} {wheel}: {r:?}");
    r[0]
}

fn inside(x: f64, (lo, hi): (f64, f64), what: &str) {
    assert!(
        lo <= x && x <= hi,
        "{what} = {x} outside the band [{lo}, {hi}]"
    );
}

#[test]
fn default_variant_is_sliding_share() {
    assert_eq!(Variant::DEFAULT, Variant::SlidingShare);
    let study = polywear::study::Study::parse(polywear::study::DEFAULT_STUDY).unwrap();
    assert_eq!(study.variants, vec![Variant::SlidingShare]);
}

#[test]
fn shipped_defaults_put_both_wheels_in_the_papers_bands() {
    let p = Params::default();
    let (f, d) = (Wheel::Follower, Wheel::Driving);
    let fs = window(&p, ParamId::SpeedKmh, 40.0, 260.0, f);
    let ds = window(&p, ParamId::SpeedKmh, 40.0, 260.0, d);
    inside(fs.0, (72.0, 95.0), "follower speed onset");
    inside(fs.1, (142.0, 210.0), "follower speed end");
    let ft = window(&p, ParamId::ToeDeg, 0.05, 1.0, f);
    let dt = window(&p, ParamId::ToeDeg, 0.05, 1.0, d);
    inside(ft.1, (0.37, 0.45), "follower toe end");
    inside(dt.1, (0.315, 0.385), "driving toe end");
    let fl = window(&p, ParamId::LoadN, 2000.0, 7000.0, f);
    let dl = window(&p, ParamId::LoadN, 2000.0, 7000.0, d);
    inside(fl.0, (3160.0, 3870.0), "follower load threshold");
    inside(dl.0, (3450.0, 4230.0), "driving load threshold");
    let fp = window(&p, ParamId::PressureKpa, 150.0, 450.0, f);
    let dp = window(&p, ParamId::PressureKpa, 150.0, 450.0, d);
    inside(fp.1, (300.0, 368.0), "follower pressure threshold");
    inside(dp.1, (205.0, 300.0), "driving pressure threshold");
    let freq = WheelModel::build(&p, f, Variant::DEFAULT)
        .unwrap()
        .ode
        .linear_stability()
        .eig_freq_hz;
    inside(freq, (257.0, 284.0), "follower frequency at 100 km/h");
    // Every driving range inside the follower's.
    for (what, fw, dw) in [
        ("speed", fs, ds),
        ("toe", ft, dt),
        ("load", fl, dl),
        ("pressure", fp, dp),
    ] {
        assert!(
            fw.0 <= dw.0 && dw.1 <= fw.1,
            "{what}: driving {dw:?} not inside follower {fw:?}"
        );
    }
}

#[test]
fn the_default_study_finds_the_driving_wheel_less_exposed() {
    let rows = paired_comparison(&Params::default(), 600).unwrap();
    let row = |v| rows.iter().find(|r| r.variant == v).unwrap();
    let s = row(Variant::SlidingShare);
    assert!(s.pairs >= 590, "{s:?}");
    assert!(
        s.p_driving() < 0.75 * s.p_follower() && s.p_follower() > 0.2,
        "{s:?}"
    );
    assert!(s.only_driving * 200 <= s.pairs, "{s:?}");
    // The literal equations reverse the answer: say so, and keep it visible.
    let p = row(Variant::Paper);
    assert!(p.only_driving > p.only_follower, "{p:?}");
    assert!(p.p_driving() >= p.p_follower(), "{p:?}");
    // The follower does not depend on the variant.
    assert_eq!(s.follower_vibrating(), p.follower_vibrating());
    assert_eq!(row(Variant::Combined).driving_vibrating(), 0);
}

#[test]
fn r0_parameter_file_holds_model_md_constants() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/params_r0.toml"),
    )
    .unwrap();
    let p = polywear::study::apply_param_file(&Params::default(), &text).unwrap();
    assert_eq!(p, Params::r0());
    // MODEL.md#r0-and-the-shipped-defaults.
    let r0 = Params::r0();
    assert_eq!(
        (r0.g_mod, r0.c_brush, r0.alpha2, r0.v_s, r0.phi, r0.c_s, r0.sigma1),
        (0.8645e6, 3.6e7, 4.0e-8, 0.126, 0.94, 18.0, 10.0)
    );
    assert_ne!(Params::default(), r0);
}

#[test]
fn every_variant_is_accepted_by_name_everywhere() {
    for v in Variant::ALL {
        assert_eq!(v.as_str().parse::<Variant>().unwrap(), v);
    }
    let e = "magic".parse::<Variant>().unwrap_err().to_string();
    assert!(e.contains("sliding_share"), "{e}");
}

#[test]
fn decoding_study_draws_each_decoded_constant_over_its_lost_digit_readings() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/decoding.toml"),
    )
    .unwrap();
    let study = polywear::study::Study::parse(&text).unwrap();
    let names: Vec<&str> = study.drawn.iter().map(|d| d.param.name()).collect();
    for n in [
        "phi",
        "v_s",
        "sigma1",
        "c_s",
        "speed_kmh",
        "toe_deg",
        "load_n",
        "pressure_kpa",
    ] {
        assert!(names.contains(&n), "{n} not drawn: {names:?}");
    }
    // Each shipped default of those constants is one of its readings.
    let sampler = study.sampler(study.seed, 2000);
    let mut seen = std::collections::BTreeSet::new();
    for i in 0..2000 {
        let (p, _) = sampler.sample(i);
        seen.insert(((p.phi * 100.0).round() as i64, (p.c_s).round() as i64));
    }
    assert_eq!(seen.len(), 16, "all phi x c_s readings drawn: {seen:?}");
    assert!(seen.contains(&(90, 14)));
}

#[test]
fn the_conclusion_holds_for_every_lost_digit_decoding() {
    // The shipped decoding study through explore and analyze; the driving wheel
    // must be less exposed than the follower in every decoding with enough samples.
    let dir = std::env::temp_dir().join(format!("polywear-decoding-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/decoding.toml");
    let out = dir.to_str().unwrap();
    let (code, _, stderr) = polywear(&[
        "explore",
        study,
        "--quiet",
        "--no-report",
        "--samples",
        "10240",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = polywear(&["analyze", "--min-count", "15", out]);
    assert_eq!(code, 0, "{stderr}");
    let line = stdout
        .lines()
        .find(|l| l.contains("lost digits: driving less exposed in"))
        .unwrap_or_else(|| panic!("no lost-digits line in\n{stdout}"));
    // "... in N of M decodings (...); K with too few samples"
    let nums: Vec<u64> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|t| t.parse().ok())
        .collect();
    let (n, m) = (nums[0], nums[1]);
    assert!(m >= 200 && n == m, "{line}");
    std::fs::remove_dir_all(&dir).ok();
}
