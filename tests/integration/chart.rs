//! Stability charts against brute force: every reported point is a Hopf point of the model, no
//! crossing of a fine eigenvalue grid is missed, l1 agrees with a finite-difference l1, and the
//! command refuses bad input before work.

use crate::common;
use nalgebra::{Complex, DMatrix, DVector};
use parquet::file::reader::{FileReader, SerializedFileReader};

use polywear::model::TreadSystem;
use polywear::model::{Variant, Wheel, WheelModel};
use polywear::params::{ParamId, Params};
use polywear_core::continuation::hopf::{analyse, HopfData};
use polywear_core::continuation::trace::TraceOptions;
use polywear_core::continuation::{CVector, OdeWithJacobian, ParamBox};
use polywear_study::chart::{ChartRequest, WheelCurves, RE_LAMBDA_BOUND};

fn request(x: &str, xr: (f64, f64), y: &str, yr: (f64, f64)) -> ChartRequest {
    ChartRequest::new(
        Params::default(),
        Variant::SlidingShare,
        Wheel::BOTH.to_vec(),
        (x.parse().unwrap(), y.parse().unwrap()),
        ParamBox {
            lo: [xr.0, yr.0],
            hi: [xr.1, yr.1],
        },
    )
    .unwrap()
}

fn speed_toe() -> ChartRequest {
    request("speed_kmh", (60.0, 250.0), "toe_deg", (0.05, 0.6))
}

/// Every point: the model's own eigenvalues there hold a pair ±iω with |Re λ| ≤ bound·ω.
fn assert_on_curve(req: &ChartRequest, charts: &[WheelCurves]) -> usize {
    let mut n = 0;
    for c in charts {
        let fam = req.family(c.wheel);
        for curve in &c.curves.curves {
            for d in &curve.points {
                let m = WheelModel::build(&fam.params(d.p), c.wheel, req.variant).unwrap();
                let ev = m.ode.eigenvalues();
                let pair = ev
                    .iter()
                    .filter(|e| e.im > 0.0)
                    .min_by(|a, b| a.re.abs().total_cmp(&b.re.abs()))
                    .expect("a complex pair");
                assert!(
                    pair.re.abs() <= RE_LAMBDA_BOUND * pair.im,
                    "{} at {:?}: Re λ = {:e}, Im λ = {}",
                    c.wheel,
                    d.p,
                    pair.re,
                    pair.im
                );
                assert!((pair.im - d.omega).abs() <= 1e-7 * d.omega);
                n += 1;
            }
        }
    }
    n
}

/// Box-relative distance from s to the polylines of `c`.
fn distance_to_curves(req: &ChartRequest, c: &WheelCurves, s: [f64; 2]) -> f64 {
    let mut best = f64::INFINITY;
    for curve in &c.curves.curves {
        let pts: Vec<[f64; 2]> = curve
            .points
            .iter()
            .map(|d| req.bounds.to_unit(d.p))
            .collect();
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let t = if len2 > 0.0 {
                (((s[0] - a[0]) * d[0] + (s[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            best = best.min((s[0] - a[0] - t * d[0]).hypot(s[1] - a[1] - t * d[1]));
        }
    }
    best
}

/// Every sign change of max Re λ between neighbouring nodes of an n×n grid lies on a curve.
fn assert_grid_crossings_found(req: &ChartRequest, charts: &[WheelCurves], n: usize) -> usize {
    let mut crossings = 0;
    for c in charts {
        let grid = req.stability_grid(c.wheel, n, n);
        let centre =
            |i: usize, j: usize| [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
        for j in 0..n {
            for i in 0..n {
                let here = grid[j * n + i];
                for (ii, jj) in [(i + 1, j), (i, j + 1)] {
                    if ii >= n || jj >= n {
                        continue;
                    }
                    let there = grid[jj * n + ii];
                    if let (Some(a), Some(b)) = (here, there) {
                        if a != b {
                            crossings += 1;
                            let (p, q) = (centre(i, j), centre(ii, jj));
                            let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                            let d = distance_to_curves(req, c, mid);
                            assert!(
                                d <= 0.6 / n as f64,
                                "{}: stability changes between grid nodes {p:?} and {q:?} \
                                 but the nearest curve is {d} away",
                                c.wheel
                            );
                        }
                    }
                }
            }
        }
    }
    crossings
}

#[test]
fn speed_toe_chart_is_on_the_curve_and_complete() {
    let req = speed_toe();
    let charts = req.trace(&TraceOptions::default());
    let points = assert_on_curve(&req, &charts);
    assert!(points > 100, "{points} points");
    let crossings = assert_grid_crossings_found(&req, &charts, 200);
    assert!(crossings > 100, "{crossings} grid crossings");
    // The driving wheel's unstable region is a closed island in this plane.
    let driving = charts.iter().find(|c| c.wheel == Wheel::Driving).unwrap();
    assert!(
        driving.curves.curves.iter().any(|c| c.closed),
        "{:?}",
        driving.curves.special
    );
}

#[test]
fn load_pressure_chart_is_on_the_curve_and_complete() {
    let req = request("load_n", (2500.0, 6500.0), "pressure_kpa", (180.0, 400.0));
    let charts = req.trace(&TraceOptions::default());
    assert!(assert_on_curve(&req, &charts) > 50);
    assert!(assert_grid_crossings_found(&req, &charts, 200) > 50);
}

#[test]
fn structure_parameter_chart_under_the_paper_variant() {
    let mut req = request("speed_kmh", (60.0, 250.0), "g_mod", (0.6e6, 1.1e6));
    req.variant = Variant::Paper;
    let charts = req.trace(&TraceOptions::default());
    assert!(assert_on_curve(&req, &charts) > 50);
    assert_grid_crossings_found(&req, &charts, 120);
}

/// B and C by central differences of the model's own Jacobian (no jets), for an l1 computed
/// without the exact derivatives.
struct Differenced(TreadSystem);

impl Differenced {
    /// D²A[u, v] for real u, v, by differences of A (step per state from `h`).
    fn d2a(&self, x: &DVector<f64>, u: &DVector<f64>, v: &DVector<f64>) -> DMatrix<f64> {
        let e = 1e-4;
        let j = |a: f64, b: f64| self.0.jacobian(&(x + u * (a * e) + v * (b * e)));
        (j(1.0, 1.0) - j(1.0, -1.0) - j(-1.0, 1.0) + j(-1.0, -1.0)) / (4.0 * e * e)
    }
}

fn split(c: &CVector) -> (DVector<f64>, DVector<f64>) {
    (c.map(|z| z.re), c.map(|z| z.im))
}

fn times(m: &DMatrix<f64>, v: &CVector) -> CVector {
    m.map(|a| Complex::new(a, 0.0)) * v
}

impl OdeWithJacobian for Differenced {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&self, x: &DVector<f64>) -> DVector<f64> {
        self.0.rhs(x)
    }
    fn jacobian(&self, x: &DVector<f64>) -> DMatrix<f64> {
        self.0.jacobian(x)
    }
    fn second(&self, x: &DVector<f64>, u: &CVector, v: &CVector) -> CVector {
        let e = 1e-6;
        let (ur, ui) = split(u);
        let da = |d: &DVector<f64>| {
            (self.0.jacobian(&(x + d * e)) - self.0.jacobian(&(x - d * e))) / (2.0 * e)
        };
        times(&da(&ur), v) + times(&da(&ui), v) * Complex::new(0.0, 1.0)
    }
    fn third(&self, x: &DVector<f64>, u: &CVector, v: &CVector, w: &CVector) -> CVector {
        let (ur, ui) = split(u);
        let (vr, vi) = split(v);
        let i = Complex::new(0.0, 1.0);
        times(&self.d2a(x, &ur, &vr), w) - times(&self.d2a(x, &ui, &vi), w)
            + (times(&self.d2a(x, &ur, &vi), w) + times(&self.d2a(x, &ui, &vr), w)) * i
    }
    fn equilibrium_guess(&self) -> DVector<f64> {
        self.0.equilibrium_guess()
    }
}

#[test]
fn l1_agrees_with_an_l1_from_differenced_derivatives() {
    let req = speed_toe();
    let charts = req.trace(&TraceOptions::default());
    let mut checked = 0;
    for c in &charts {
        let fam = req.family(c.wheel);
        for curve in &c.curves.curves {
            for d in curve.points.iter().step_by(17) {
                let m = WheelModel::build(&fam.params(d.p), c.wheel, req.variant).unwrap();
                let x = DVector::from_vec(d.x.clone());
                let fd: HopfData = analyse(&Differenced(TreadSystem(m.ode)), &x, d.p).unwrap();
                assert!(
                    (fd.l1 - d.l1).abs() <= 1e-3 * d.l1.abs(),
                    "{} at {:?}: l1 {} vs differenced {}",
                    c.wheel,
                    d.p,
                    d.l1,
                    fd.l1
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 10);
}

fn dir(name: &str) -> std::path::PathBuf {
    let d = common::fresh_dir(&format!("chart-{name}"));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn refused(args: &[&str], needles: &[&str]) {
    let (code, _, stderr) = common::polywear(args);
    assert_eq!(code, 2, "{args:?}: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "{args:?}: stderr lacks `{n}`: {stderr}");
    }
}

#[test]
fn bad_chart_requests_are_refused_before_work() {
    let d = dir("bad");
    let out = d.join("c.parquet");
    let out = out.to_str().unwrap();
    let base = |x: &str, xf: &str, xt: &str, y: &str, yf: &str, yt: &str| -> Vec<String> {
        [
            "chart", "--x", x, "--x-from", xf, "--x-to", xt, "--y", y, "--y-from", yf, "--y-to",
            yt, "--out", out,
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let check = |v: Vec<String>, needles: &[&str]| {
        let args: Vec<&str> = v.iter().map(|s| s.as_str()).collect();
        refused(&args, needles);
    };
    check(
        base("nope", "1", "2", "toe_deg", "0.1", "0.5"),
        &["--x", "unknown parameter `nope`"],
    );
    check(
        base("speed_kmh", "60", "200", "speed_kmh", "80", "90"),
        &["--x and --y", "speed_kmh"],
    );
    check(
        base("speed_kmh", "200", "60", "toe_deg", "0.1", "0.5"),
        &["--x-from", "--x-to", "(0, 400]"],
    );
    check(
        base("speed_kmh", "60", "200", "toe_deg", "0.3", "0.3"),
        &["--y-from", "empty or inverted"],
    );
    check(
        base("speed_kmh", "60", "500", "toe_deg", "0.1", "0.5"),
        &["--x-to", "(0, 400]"],
    );
    check(
        base("speed_kmh", "60", "200", "toe_deg", "-0.1", "0.5"),
        &["--y-from", "(0, 10]"],
    );
    check(
        base("mu_s", "0.5", "0.9", "toe_deg", "0.1", "0.5"),
        &["corner", "mu_s"],
    );
    let mut v = base("speed_kmh", "60", "200", "toe_deg", "0.1", "0.5");
    v.extend(["--wheel".to_string(), "left".to_string()]);
    check(v, &["left", "front", "rear"]);
    assert!(
        std::fs::read_dir(&d).unwrap().next().is_none(),
        "nothing written"
    );
}

fn columns(path: &std::path::Path) -> (Vec<String>, i64, Vec<String>) {
    let r = SerializedFileReader::new(std::fs::File::open(path).unwrap()).unwrap();
    let meta = r.metadata().file_metadata();
    let names = meta
        .schema_descr()
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let keys = meta
        .key_value_metadata()
        .map(|kv| kv.iter().map(|k| k.key.clone()).collect())
        .unwrap_or_default();
    (names, meta.num_rows(), keys)
}

#[test]
fn chart_command_writes_tables_and_picture() {
    let d = dir("run");
    let out = d.join("speed_toe.parquet");
    let (code, stdout, stderr) = common::polywear(&[
        "chart",
        "--x",
        "speed_kmh",
        "--x-from",
        "60",
        "--x-to",
        "250",
        "--y",
        "toe_deg",
        "--y-from",
        "0.05",
        "--y-to",
        "0.6",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("follower") && stdout.contains("driving"),
        "{stdout}"
    );
    let (names, rows, keys) = columns(&out);
    assert_eq!(
        &names[..8],
        [
            "wheel",
            "variant",
            "curve",
            "speed_kmh",
            "toe_deg",
            "freq_hz",
            "l1",
            "criticality"
        ]
    );
    assert!(rows > 100);
    for k in [
        "polywear_version",
        "params",
        "variant",
        "chart_x",
        "chart_y",
    ] {
        assert!(keys.iter().any(|x| x == k), "metadata lacks {k}: {keys:?}");
    }
    let csv = std::fs::read_to_string(d.join("speed_toe.csv")).unwrap();
    assert_eq!(csv.lines().count() as i64, rows + 1);
    assert!(csv.contains("supercritical"));
    let (sp_names, sp_rows, _) = columns(&d.join("speed_toe_special.parquet"));
    assert!(sp_names.contains(&"kind".to_string()) && sp_rows > 0);
    assert!(std::fs::metadata(d.join("speed_toe.png")).unwrap().len() > 10_000);
}

#[test]
fn empty_box_gives_an_empty_table_and_exit_0() {
    let d = dir("empty");
    let out = d.join("calm.parquet");
    let (code, stdout, stderr) = common::polywear(&[
        "chart",
        "--x",
        "speed_kmh",
        "--x-from",
        "20",
        "--x-to",
        "40",
        "--y",
        "toe_deg",
        "--y-from",
        "0.05",
        "--y-to",
        "0.1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("0 Hopf curve"), "{stdout}");
    let (_, rows, _) = columns(&out);
    assert_eq!(rows, 0);
    assert!(d.join("calm.png").exists() && d.join("calm.csv").exists());
}

#[test]
fn bifurcation_hopf_points_carry_the_charts_l1() {
    use polywear::classify::ClassifierOptions;
    use polywear_study::bifurcation::{linspace, sweep};
    let base = Params::default();
    let sw = sweep(
        &base,
        ParamId::SpeedKmh,
        &linspace(60.0, 250.0, 20),
        Variant::SlidingShare,
        &ClassifierOptions::default(),
    );
    assert_eq!(sw.hopf.len(), 4, "{:?}", sw.hopf);
    // The chart's curve ends on the edge toe = 0.3 of a box above it are the same Hopf points.
    let req = request("speed_kmh", (60.0, 250.0), "toe_deg", (0.3, 0.5));
    let charts = req.trace(&TraceOptions::default());
    for h in &sw.hopf {
        let c = charts.iter().find(|c| c.wheel == h.wheel).unwrap();
        let end = c
            .curves
            .special
            .iter()
            .filter(|s| (s.p[1] - 0.3).abs() < 1e-12)
            .min_by(|a, b| {
                (a.p[0] - h.value)
                    .abs()
                    .total_cmp(&(b.p[0] - h.value).abs())
            })
            .unwrap();
        assert!(
            (end.p[0] - h.value).abs() < 1e-4 * h.value,
            "{h:?} vs {end:?}"
        );
        assert!(
            (end.l1 - h.l1).abs() < 1e-3 * h.l1.abs(),
            "{h:?} vs {end:?}"
        );
        assert!(h.l1 < 0.0);
    }
}

#[test]
fn structure_samples_draw_the_boundary_band() {
    let d = dir("band");
    let out = d.join("b.parquet");
    let study = concat!(env!("CARGO_MANIFEST_DIR"), "/studies/default.toml");
    let (code, stdout, stderr) = common::polywear(&[
        "chart",
        "--x",
        "load_n",
        "--x-from",
        "2500",
        "--x-to",
        "6500",
        "--y",
        "pressure_kpa",
        "--y-from",
        "180",
        "--y-to",
        "400",
        "--study",
        study,
        "--structure-samples",
        "12",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("12 structures") && stdout.contains("g_mod"),
        "{stdout}"
    );
    let (names, rows, keys) = columns(&d.join("b_band.parquet"));
    assert_eq!(
        names,
        [
            "wheel",
            "variant",
            "load_n",
            "pressure_kpa",
            "unstable_share"
        ]
    );
    assert_eq!(rows, 2 * 100 * 100);
    assert!(keys.iter().any(|k| k == "structure_samples"));
    let csv = std::fs::read_to_string(d.join("b_band.csv")).unwrap();
    let shares: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(shares.iter().all(|s| (0.0..=1.0).contains(s)));
    assert!(
        shares.iter().any(|s| *s > 0.05 && *s < 0.95),
        "a band exists"
    );
    // Without --study, or with too few structures: refused.
    refused(
        &[
            "chart",
            "--x",
            "load_n",
            "--x-from",
            "2500",
            "--x-to",
            "6500",
            "--y",
            "pressure_kpa",
            "--y-from",
            "180",
            "--y-to",
            "400",
            "--structure-samples",
            "12",
            "--out",
            out.to_str().unwrap(),
        ],
        &["--study"],
    );
    refused(
        &[
            "chart",
            "--x",
            "load_n",
            "--x-from",
            "2500",
            "--x-to",
            "6500",
            "--y",
            "pressure_kpa",
            "--y-from",
            "180",
            "--y-to",
            "400",
            "--study",
            study,
            "--structure-samples",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
        &["--structure-samples", "[2, 10000]"],
    );
}

#[test]
fn every_pair_of_operating_axes_in_every_variant() {
    let axes = [
        ("speed_kmh", (40.0, 300.0)),
        ("toe_deg", (0.02, 0.8)),
        ("load_n", (2000.0, 8000.0)),
        ("pressure_kpa", (150.0, 450.0)),
    ];
    for variant in Variant::ALL {
        for i in 0..4 {
            for j in i + 1..4 {
                let mut req = request(axes[i].0, axes[i].1, axes[j].0, axes[j].1);
                req.variant = variant;
                let charts = req.trace(&TraceOptions::default());
                assert_on_curve(&req, &charts);
                let n = assert_grid_crossings_found(&req, &charts, 100);
                eprintln!(
                    "{variant} {} x {}: {n} crossings, {} curves",
                    axes[i].0,
                    axes[j].0,
                    charts.iter().map(|c| c.curves.curves.len()).sum::<usize>()
                );
            }
        }
    }
}

#[test]
fn analyze_overlay_traces_the_nominal_tire_at_the_study_median() {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/studies/default.toml"))
            .unwrap();
    let study = polywear::study::Study::parse(&text).unwrap();
    let curves = polywear_study::chart::nominal_curves(
        &study,
        Variant::SlidingShare,
        "speed_kmh",
        "toe_deg",
        &[60.0, 130.0, 200.0],
        &[0.02, 0.4, 0.8],
    )
    .unwrap();
    assert_eq!(curves.len(), 2);
    // The nominal tire: every drawn parameter off the axes at its median (u = 0.5).
    let fam_base = {
        let mut p = study.base;
        for d in study
            .drawn
            .iter()
            .filter(|d| !["speed_kmh", "toe_deg"].contains(&d.param.name()))
        {
            p[d.param] = d.dist.quantile(0.5);
        }
        assert!((p.load_n - 4000.0).abs() < 100.0 && (p.g_mod - 0.8557e6).abs() < 1.0);
        p
    };
    for c in &curves {
        assert!(!c.curves.curves.is_empty());
        for d in c.curves.curves.iter().flat_map(|k| &k.points) {
            let mut p = fam_base;
            p.speed_kmh = d.p[0];
            p.toe_deg = d.p[1];
            let re = WheelModel::build(&p, c.wheel, Variant::SlidingShare)
                .unwrap()
                .ode
                .linear_stability();
            assert!(
                re.eig_re_max.abs() < 1e-6 * re.leading.im.abs(),
                "{:?}",
                d.p
            );
        }
    }
    assert!(polywear_study::chart::nominal_curves(
        &study,
        Variant::Paper,
        "nope",
        "toe_deg",
        &[1.0, 2.0],
        &[0.1, 0.2]
    )
    .is_none());
}

/// Whole parameter ranges, an edge where the driving wheel stops transmitting the drive (its
/// curves end there as `stopped`), a friction and a vehicle parameter as axes.
#[test]
fn extreme_boxes_and_the_no_traction_edge() {
    let boxes = [
        ("speed_kmh", (150.0, 400.0), "load_n", (300.0, 3000.0)),
        ("speed_kmh", (1.0, 400.0), "toe_deg", (0.001, 10.0)),
        ("load_n", (100.0, 50000.0), "pressure_kpa", (10.0, 2000.0)),
        ("toe_deg", (0.001, 2.0), "mu_s", (0.1, 0.75)),
        ("speed_kmh", (20.0, 400.0), "c_d", (0.0, 5.0)),
    ];
    for variant in Variant::ALL {
        for (x, xr, y, yr) in boxes {
            let mut req = request(x, xr, y, yr);
            req.variant = variant;
            let charts = req.trace(&TraceOptions::default());
            assert_on_curve(&req, &charts);
            assert_grid_crossings_found(&req, &charts, 150);
        }
    }
}
