//! The figures' layout, read back from SVG renderings and from what the drawing code returns:
//! the stability chart says where it was drawn and names every region it shades, a risk map's
//! colour bar reads with its own label, tick labels never run together, and in a drive
//! cycle's picture the driving wheel's markers leave the follower's showing.

use crate::common::fresh_dir;
use crate::common::svg::{circles, rects, texts, SvgText};

use polywear::analysis::bins::Bins;
use polywear::analysis::conditional::BinStat;
use polywear::analysis::counts::ClassCounts;
use polywear::analysis::risk_map::RiskMap;
use polywear::classify::Class;
use polywear::model::{Variant, Wheel};
use polywear::params::{ParamId, Params};
use polywear_analysis::figures::chart::draw;
use polywear_analysis::plot::cycle::{cycle_figure, WheelTrace};
use polywear_analysis::plot::{FigureFile, FigureFormat};
use polywear_core::continuation::trace::HopfCurves;
use polywear_core::continuation::ParamBox;
use polywear_study::chart::{ChartRequest, WheelCurves};

fn counts(vibrating: u64, stable: u64) -> ClassCounts {
    let mut c = ClassCounts::default();
    c.add(Class::LimitCycle, vibrating);
    c.add(Class::Stable, stable);
    c
}

fn no_curves(wheel: Wheel) -> WheelCurves {
    WheelCurves {
        wheel,
        curves: HopfCurves {
            curves: vec![],
            special: vec![],
        },
    }
}

#[test]
fn the_chart_says_where_it_was_drawn_and_names_the_overlap() {
    let dir = fresh_dir("fig-chart");
    std::fs::create_dir_all(&dir).unwrap();
    let req = ChartRequest::new(
        Params::default(),
        Variant::SlidingShare,
        Wheel::BOTH.to_vec(),
        (ParamId::LoadN, ParamId::PressureKpa),
        ParamBox {
            lo: [2500.0, 180.0],
            hi: [6500.0, 320.0],
        },
    )
    .unwrap();
    let n = polywear_analysis::figures::chart::SHADE_CELLS;
    // The follower unstable in the left half, the driving wheel in the left quarter: both
    // there.
    let grid =
        |upto: usize| -> Vec<Option<bool>> { (0..n * n).map(|k| Some(k % n < upto)).collect() };
    let grids = [grid(n / 2), grid(n / 4)];
    let charts = [no_curves(Wheel::Follower), no_curves(Wheel::Driving)];
    let file = FigureFile::named(&dir, "chart", FigureFormat::Svg);
    let path = file.path.clone();
    let layout = draw(&file, &req, &charts, &grids, None).unwrap();
    let p = Params::default();
    let speed = format!("speed {} km/h", p.speed_kmh);
    let toe = format!("toe-in {} deg", p.toe_deg);
    assert!(
        layout.title.contains(&speed) && layout.title.contains(&toe),
        "{}",
        layout.title
    );
    assert!(
        layout
            .legend
            .iter()
            .any(|l| l.starts_with("both wheels unstable")),
        "{:?}",
        layout.legend
    );
    let nominal = format!(
        "nominal operating point (load {} N, pressure {} kPa)",
        p.load_n, p.pressure_kpa
    );
    assert!(layout.legend.contains(&nominal), "{:?}", layout.legend);
    // What the layout says is what the picture shows.
    let svg = std::fs::read_to_string(&path).unwrap();
    let shown: Vec<String> = texts(&svg).into_iter().map(|t| t.text).collect();
    for words in std::iter::once(&layout.title).chain(&layout.legend) {
        assert!(shown.contains(words), "{words} not in the SVG");
    }
    // Without an overlap there is no such entry.
    let layout = draw(&file, &req, &charts, &[grid(n / 2), grid(0)], None).unwrap();
    assert!(!layout.legend.iter().any(|l| l.starts_with("both wheels")));
    std::fs::remove_dir_all(&dir).ok();
}

fn small_map(x: ParamId, xr: (f64, f64), y: ParamId, yr: (f64, f64)) -> RiskMap {
    let (nx, ny) = (3, 3);
    let grid = |k: u64| -> Vec<Vec<ClassCounts>> {
        (0..nx)
            .map(|i| (0..ny).map(|j| counts(k * (i + j) as u64, 40)).collect())
            .collect()
    };
    RiskMap {
        variant: Variant::SlidingShare,
        x,
        y,
        x_bins: Bins::equal_width(xr.0, xr.1, nx),
        y_bins: Bins::equal_width(yr.0, yr.1, ny),
        cells: vec![(Wheel::Follower, grid(10)), (Wheel::Driving, grid(5))],
        nominal: None,
    }
}

fn label(p: ParamId) -> String {
    polywear::params::axis_label(p.name(), p.spec().unit)
}

#[test]
fn a_colour_bar_reads_with_its_own_label() {
    let dir = fresh_dir("fig-colourbar");
    std::fs::create_dir_all(&dir).unwrap();
    let file = FigureFile::named(&dir, "map", FigureFormat::Svg);
    let path = file.path.clone();
    let map = small_map(
        ParamId::SpeedKmh,
        (60.0, 200.0),
        ParamId::ToeDeg,
        (0.0, 0.5),
    );
    polywear::render::figures::risk_map(&file, &map, &label, 30, Default::default()).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    let rotated: Vec<SvgText> = texts(&svg).into_iter().filter(|t| t.rotated).collect();
    let bar_labels = ["Risk of vibration [%]", "Difference [percentage points]"];
    // A colour bar: a column of at least 50 rectangles of one x and width.
    let mut columns: std::collections::BTreeMap<(i64, i64), usize> = Default::default();
    for r in rects(&svg) {
        *columns
            .entry((r.x.round() as i64, r.width.round() as i64))
            .or_default() += 1;
    }
    let bars: Vec<(f64, f64)> = columns
        .into_iter()
        .filter(|(_, n)| *n >= 50)
        .map(|((x, w), _)| (x as f64, (x + w) as f64))
        .collect();
    assert_eq!(bars.len(), 3, "one colour bar per panel");
    for (left, right) in bars {
        let distance = |t: &SvgText| {
            if t.x < left {
                left - t.x
            } else if t.x > right {
                t.x - right
            } else {
                0.0
            }
        };
        let nearest = rotated
            .iter()
            .min_by(|a, b| distance(a).total_cmp(&distance(b)))
            .unwrap();
        assert!(
            bar_labels.contains(&nearest.text.as_str()),
            "the label nearest the bar at x = {left}..{right} is {:?}",
            nearest.text
        );
        // And any other panel's axis label stands well apart from the bar's own.
        for other in rotated
            .iter()
            .filter(|t| !bar_labels.contains(&t.text.as_str()))
        {
            assert!(
                (other.x - nearest.x).abs() >= 40.0,
                "{:?} at x = {} stands against {:?} at x = {}",
                other.text,
                other.x,
                nearest.text,
                nearest.x
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The unrotated texts along one line (the same y), left to right.
fn tick_rows(svg: &str) -> Vec<Vec<SvgText>> {
    let mut rows: std::collections::BTreeMap<i64, Vec<SvgText>> = Default::default();
    for t in texts(svg)
        .into_iter()
        .filter(|t| !t.rotated && t.anchor == "middle")
    {
        rows.entry(t.y.round() as i64).or_default().push(t);
    }
    rows.into_values()
        .map(|mut r| {
            r.sort_by(|a, b| a.x.total_cmp(&b.x));
            r
        })
        .collect()
}

fn assert_no_tick_labels_touch(svg: &str, what: &str) {
    let mut checked = 0;
    for row in tick_rows(svg) {
        for w in row.windows(2) {
            let (a, b) = (w[0].x_extent(), w[1].x_extent());
            assert!(
                a.1 <= b.0,
                "{what}: {:?} and {:?} run together ({a:?}, {b:?})",
                w[0].text,
                w[1].text
            );
            checked += 1;
        }
    }
    assert!(checked > 5, "{what}: only {checked} neighbouring labels");
}

#[test]
fn scientific_tick_labels_never_run_together() {
    let dir = fresh_dir("fig-ticks");
    std::fs::create_dir_all(&dir).unwrap();
    // C = 3.05e7 .. 3.95e7: round ticks every 0.1e7, each label six characters wide.
    let (lo, hi) = (3.05e7, 3.95e7);
    let map = small_map(ParamId::CBrush, (lo, hi), ParamId::GMod, (7.5e5, 9.5e5));
    let file = FigureFile::named(&dir, "map", FigureFormat::Svg);
    let path = file.path.clone();
    polywear::render::figures::risk_map(&file, &map, &label, 30, Default::default()).unwrap();
    assert_no_tick_labels_touch(&std::fs::read_to_string(&path).unwrap(), "risk map");
    let axes = [
        ParamId::CBrush,
        ParamId::GMod,
        ParamId::Rho,
        ParamId::TreadHeight,
        ParamId::SpeedKmh,
    ];
    let bins: Vec<BinStat> = axes
        .iter()
        .flat_map(|&axis| {
            let spec = axis.spec();
            let (a, b) = if axis == ParamId::CBrush {
                (lo, hi)
            } else {
                (spec.min.max(1e-3), spec.min.max(1e-3) * 1.5)
            };
            (0..20).flat_map(move |i| {
                let (l, h) = (
                    a + (b - a) * i as f64 / 20.0,
                    a + (b - a) * (i + 1) as f64 / 20.0,
                );
                Wheel::BOTH.map(|wheel| BinStat {
                    variant: Variant::SlidingShare,
                    wheel,
                    axis,
                    lo: l,
                    hi: h,
                    mid: 0.5 * (l + h),
                    counts: counts(i, 40),
                })
            })
        })
        .collect();
    let file = FigureFile::named(&dir, "conditional", FigureFormat::Svg);
    let path = file.path.clone();
    polywear::render::figures::conditional(&file, Variant::SlidingShare, &axes, &label, &bins, 30)
        .unwrap();
    assert_no_tick_labels_touch(&std::fs::read_to_string(&path).unwrap(), "conditional");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_driving_wheels_markers_leave_the_followers_showing() {
    let dir = fresh_dir("fig-cycle");
    std::fs::create_dir_all(&dir).unwrap();
    let n = 200;
    let time_s: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let speed_kmh: Vec<f64> = (0..n).map(|i| 60.0 + 0.3 * i as f64).collect();
    // The driving wheel vibrates only where the follower does, at the same polygon order.
    let follower: Vec<bool> = (0..n).map(|i| i >= 50).collect();
    let driving: Vec<bool> = (0..n).map(|i| i >= 120).collect();
    let order = |v: &[bool]| v.iter().map(|&b| if b { 18.0 } else { f64::NAN }).collect();
    let wheels = [
        WheelTrace {
            label: "follower",
            polygon_order: order(&follower),
            vibrates: follower,
        },
        WheelTrace {
            label: "driving",
            polygon_order: order(&driving),
            vibrates: driving,
        },
    ];
    let file = FigureFile::named(&dir, "cycle", FigureFormat::Svg);
    let path = file.path.clone();
    cycle_figure(&file, "test cycle", &time_s, &speed_kmh, &wheels).unwrap();
    let drawn = circles(&std::fs::read_to_string(&path).unwrap());
    let mut overlaps = 0;
    for (k, later) in drawn.iter().enumerate() {
        for earlier in &drawn[..k] {
            let same_place =
                (earlier.cx - later.cx).abs() < 0.5 && (earlier.cy - later.cy).abs() < 0.5;
            if same_place && earlier.fill != later.fill {
                overlaps += 1;
                assert!(
                    later.r < earlier.r,
                    "a marker of radius {} ({}) covers one of radius {} ({}) at ({}, {})",
                    later.r,
                    later.fill,
                    earlier.r,
                    earlier.fill,
                    later.cx,
                    later.cy
                );
            }
        }
    }
    assert!(
        overlaps >= 80,
        "both wheels marked at the same steps: {overlaps}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
