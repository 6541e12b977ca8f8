//! The files of an optimisation: `optimum.csv` (one row; with an `optimum.parquet` sidecar
//! carrying the metadata), `surface.parquet` (every setting evaluated), the picture of the
//! objective surface with the nominal tire's stability boundaries, and `report.md`, which says
//! in words where the optimum is, how flat it is, and whether it sits on the box's edge.

use polywear_core::wording::capitalise;
use std::path::{Path, PathBuf};

use super::optimize_figure;
use crate::plot::FigureFile;
use crate::plot::{FigureFormat, PlotError};
use polywear_core::wording::plain;
use polywear_study::optimize::{Problem, Solution};
use polywear_study::parquet_out::{write_csv, write_table, Column};

/// Why the files cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// A folder or file cannot be written.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A table cannot be written.
    #[error("{0}")]
    Write(#[from] polywear_study::parquet_out::WriteError),
    /// The picture cannot be drawn.
    #[error("{0}")]
    Figure(#[from] PlotError),
}

/// A probability or objective as people read it: 12.3%.
fn pct(x: f64) -> String {
    if x.is_finite() {
        format!("{:.1}%", 100.0 * x)
    } else {
        "–".into()
    }
}

/// The sentences of the result: the optimum with its interval, how flat it is, the edge.
pub fn summary(problem: &Problem, solution: &Solution) -> Vec<String> {
    let mut lines = Vec::new();
    let axes = &problem.axes;
    let Some(b) = solution.best else {
        lines.push(format!(
            "no setting of the {} evaluated meets the constraints ({})",
            solution.settings.len(),
            problem
                .constraints
                .iter()
                .map(|c| c.text.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ));
        return lines;
    };
    lines.push(optimum_line(problem, &solution.settings[b]));
    lines.push(flatness_line(problem, solution, b));
    // A box over which the objective does not move at all (over the tread's life at a workshop
    // toe-in, 0.0% everywhere) has no minimum: the best is the first of equals, and its edge
    // says nothing about what lies beyond the box.
    let flat = flat_value(solution, |s| Some(s.objective.value));
    if let Some(v) = flat {
        lines.push(format!(
            "the objective is {} at every setting of the box: no setting is better than another, so the optimum above only breaks a tie and its place (an edge or not) means nothing",
            pct(v)
        ));
    }
    for (k, side) in solution.on_edge().into_iter().filter(|_| flat.is_none()) {
        lines.push(edge_line(problem, &axes[k], k, side));
    }
    lines.extend(band_lines(problem, solution));
    if let Some(note) = &problem.band_note {
        lines.push(note.clone());
    }
    lines
}

/// The optimum in words: where it lies, its objective with the 95% interval (and the
/// calibration band where there is one), and over how many samples.
fn optimum_line(problem: &Problem, best: &polywear_study::optimize::Setting) -> String {
    let at: Vec<String> = problem
        .axes
        .iter()
        .zip(&best.values)
        .map(|(a, v)| format!("{} = {}", a.param, plain(*v, 4)))
        .collect();
    format!(
        "optimum: {}: {} {} (95% interval {} to {}{}) over {} samples",
        at.join(", "),
        problem.objective.text(),
        pct(best.objective.value),
        pct(best.objective.low),
        pct(best.objective.high),
        band_range(best).map_or(String::new(), |(lo, hi)| format!(
            "; calibration band {:.1}–{:.1}%",
            100.0 * lo,
            100.0 * hi
        )),
        best.objective.n
    )
}

/// How flat the objective is around the best setting `b`: the settings within its interval and
/// their span, those that cannot be told from it, and the objective's range over the box.
fn flatness_line(problem: &Problem, solution: &Solution, b: usize) -> String {
    let best = &solution.settings[b];
    let within = solution.within_best();
    let spans: Vec<String> = problem
        .axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let (lo, hi) = span(within.iter().map(|&i| solution.settings[i].values[k]));
            format!("{} {} to {}", a.param, plain(lo, 4), plain(hi, 4))
        })
        .collect();
    let worst = solution
        .settings
        .iter()
        .filter(|s| s.feasible)
        .map(|s| s.objective.value)
        .fold(f64::NEG_INFINITY, f64::max);
    // Paired on the same samples, a difference is far better resolved than either value.
    let indistinct = within
        .iter()
        .filter(|&&i| {
            let (_, lo, hi) = solution.vs_best[i];
            i != b && lo <= 0.0 && hi >= 0.0
        })
        .count();
    format!(
        "how flat: {} of {} settings lie within the best's interval (objective at most {}), spanning {}; {} of them cannot be told from the best (their paired difference's 95% interval holds 0); over the box the objective runs from {} to {}",
        within.len(),
        solution.settings.len(),
        pct(best.objective.high),
        spans.join(", "),
        indistinct,
        pct(best.objective.value),
        pct(worst)
    )
}

/// The optimum on the box's `side` edge of axis `a` (the `k`-th), in words, with the next step:
/// the widened box to search, or that the parameter's plausible limit is the answer.
fn edge_line(
    problem: &Problem,
    a: &polywear_study::optimize::Axis,
    k: usize,
    side: &str,
) -> String {
    let lower = side == "lower";
    let end = if lower { a.lo } else { a.hi };
    let next = match problem.widened(k, lower) {
        Some((lo, hi)) => format!(
            "next step: widen the box there, `--vary {}={}..{}` (the other --vary as they were)",
            a.param,
            plain(lo, 4),
            plain(hi, 4)
        ),
        None => format!(
            "the box already reaches {}'s plausible limit there, so that limit is the answer",
            a.param
        ),
    };
    format!(
        "the optimum sits on the box's {side} edge of {} ({}): the minimum may lie beyond the box; {next}",
        a.param,
        plain(end, 6)
    )
}

/// The value the objective takes at every feasible setting, where it takes one value only
/// (`of` reads a setting's objective; None where some setting differs or none is feasible).
fn flat_value(
    solution: &Solution,
    of: impl Fn(&polywear_study::optimize::Setting) -> Option<f64>,
) -> Option<f64> {
    let mut values = solution
        .settings
        .iter()
        .filter(|s| s.feasible)
        .map(|s| of(s).unwrap_or(f64::NAN));
    let first = values.next()?;
    (first.is_finite() && values.all(|v| v == first)).then_some(first)
}

/// The range of a setting's objective over the calibrated sets (None without a band, or where
/// no set gives it a value).
fn band_range(s: &polywear_study::optimize::Setting) -> Option<(f64, f64)> {
    let (lo, hi) = span(
        s.band
            .iter()
            .map(|e| e.objective.value)
            .filter(|v| v.is_finite()),
    );
    (lo <= hi).then_some((lo, hi))
}

/// The smallest and the largest of `values` ((+inf, −inf) for none).
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
        (l.min(v), h.max(v))
    })
}

/// What the calibrated sets do to the answer (MODEL.md#the-calibration-band): where the
/// optimum lies under each set, whether it moves, whether the run's optimum stays within each
/// set's best interval, and the box's edge in words where every set puts the optimum there.
fn band_lines(problem: &Problem, solution: &Solution) -> Vec<String> {
    let (Some(band), Some(b)) = (&problem.band, solution.best) else {
        return Vec::new();
    };
    let optima = solution.band_optima();
    if optima.is_empty() {
        return Vec::new();
    }
    let sets = optima.len();
    let found: Vec<usize> = optima.iter().flatten().copied().collect();
    let mut lines = Vec::new();
    let none = sets - found.len();
    let staying = found.iter().filter(|&&i| i == b).count();
    let places = optimum_places_under_sets(problem, solution, &found);
    let held = (0..sets)
        .filter(|&k| {
            let Some(o) = optima[k] else { return false };
            let at_run = &solution.settings[b].band[k];
            at_run.feasible && at_run.objective.value <= solution.settings[o].band[k].objective.high
        })
        .count();
    let moves = if staying == found.len() {
        format!("the optimum stays at {} under every set", places.join(", "))
    } else {
        format!(
            "the optimum moves with the constants: {} ({} of {} sets put it elsewhere than the run's constants do)",
            places.join(", "),
            found.len() - staying,
            found.len()
        )
    };
    lines.push(format!(
        "under each of the {sets} calibrated sets ({}), among the {} settings evaluated: {moves}; the run's optimum lies within the set's own best interval under {held} of {sets}{}",
        band.source,
        solution.settings.len(),
        if none > 0 {
            format!("; {none} sets leave no setting that meets the constraints")
        } else {
            String::new()
        }
    ));
    lines.extend(band_edge_line(problem, solution, &optima, &found));
    lines
}

/// Where the sets' optima (`found`, the settings they pick) lie along each axis: one value, or
/// the range they span.
fn optimum_places_under_sets(
    problem: &Problem,
    solution: &Solution,
    found: &[usize],
) -> Vec<String> {
    problem
        .axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let (lo, hi) = span(found.iter().map(|&i| solution.settings[i].values[k]));
            if lo == hi {
                format!("{} = {}", a.param, plain(lo, 4))
            } else {
                format!("{} from {} to {}", a.param, plain(lo, 4), plain(hi, 4))
            }
        })
        .collect()
}

/// The box's edge under the calibrated sets, in words: flat under every set, the edge every
/// set whose objective moves puts the optimum on, or how many sets put it on some edge (None
/// where none does). `optima` is each set's optimum, `found` those that exist.
fn band_edge_line(
    problem: &Problem,
    solution: &Solution,
    optima: &[Option<usize>],
    found: &[usize],
) -> Option<String> {
    let sets = optima.len();
    let none = sets - found.len();
    // The box's edge in words, where every set's optimum sits on it as the run's does. A set
    // whose objective is flat over the box has a tie for its optimum, not an edge: the edge is
    // named from the sets whose objective moves, and the flat ones are counted.
    let run_edges = solution.on_edge();
    let set_is_flat: Vec<bool> = (0..sets)
        .map(|k| {
            flat_value(solution, |s| {
                s.band
                    .get(k)
                    .filter(|e| e.feasible)
                    .map(|e| e.objective.value)
            })
            .is_some()
        })
        .collect();
    let flat_sets = set_is_flat.iter().filter(|&&f| f).count();
    let moving: Vec<usize> = (0..sets)
        .filter(|&k| !set_is_flat[k])
        .filter_map(|k| optima[k])
        .collect();
    let run_flat = flat_value(solution, |s| Some(s.objective.value)).is_some();
    let edges = if run_flat {
        moving.first().map_or(Vec::new(), |&i| solution.edges_of(i))
    } else {
        run_edges
    };
    if flat_sets == sets {
        Some(
            "under every calibrated set the objective is flat over the box too: no setting is better than another under any of them".into(),
        )
    } else if !edges.is_empty()
        && none == 0
        && moving.iter().all(|&i| solution.edges_of(i) == edges)
    {
        let words = box_edge_words(problem, &edges);
        let which = if flat_sets == 0 {
            "under every calibrated set".to_string()
        } else {
            format!(
                "under every calibrated set whose objective moves over the box ({} of {sets}; flat under the other {flat_sets})",
                sets - flat_sets
            )
        };
        Some(format!(
            "{which} the answer is the edge of the box: {}",
            words.join(", ")
        ))
    } else {
        let on_edge = found
            .iter()
            .filter(|&&i| !solution.edges_of(i).is_empty())
            .count();
        (on_edge > 0).then(|| {
            format!("{on_edge} of {sets} calibrated sets put the optimum on the box's edge")
        })
    }
}

/// The box's `edges` (axis, side) as the answer in words: "as little x as the box allows (lo)"
/// or "as much x as the box allows (hi)".
fn box_edge_words(problem: &Problem, edges: &[(usize, &'static str)]) -> Vec<String> {
    edges
        .iter()
        .map(|&(k, side)| {
            let a = &problem.axes[k];
            let (how, end) = if side == "lower" {
                ("little", a.lo)
            } else {
                ("much", a.hi)
            };
            format!("as {how} {} as the box allows ({})", a.param, plain(end, 6))
        })
        .collect()
}

/// Writes every file into `dir`; `metadata` (version, command, parameters, variant, study,
/// seed, objective) goes into every Parquet footer; `format` is the picture's.
pub fn write(
    problem: &Problem,
    solution: &Solution,
    dir: &Path,
    metadata: &[(String, String)],
    format: FigureFormat,
) -> Result<Vec<PathBuf>, OutputError> {
    polywear_study::safe_write::create_dir(dir).map_err(|e| OutputError::Io {
        path: dir.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut written = Vec::new();
    let optimum = optimum_columns(problem, solution);
    let csv = dir.join("optimum.csv");
    write_csv(&csv, &optimum)?;
    written.push(csv);
    let sidecar = dir.join("optimum.parquet");
    write_table(&sidecar, &optimum, metadata)?;
    written.push(sidecar);
    let surface = dir.join("surface.parquet");
    write_table(&surface, &surface_columns(problem, solution), metadata)?;
    written.push(surface);
    let band_file = dir.join(BAND_FILE);
    match band_columns(problem, solution) {
        Some(cols) => {
            write_table(&band_file, &cols, metadata)?;
            written.push(band_file);
        }
        // None of an earlier run's sets beside this run's files.
        None => {
            std::fs::remove_file(&band_file).ok();
        }
    }
    let picture = FigureFile::named(dir, "surface", format);
    let drawn = optimize_figure::draw(problem, solution, &picture)?;
    let text = page(problem, solution, drawn.then_some(picture.path.as_path()));
    if drawn {
        written.push(picture.path);
    } else {
        // No objective to draw (no verdict anywhere): no figure, and none of an earlier run.
        std::fs::remove_file(&picture.path).ok();
    }
    let report = dir.join("report.md");
    polywear_study::safe_write::write_file(&report, text.as_bytes()).map_err(|e| {
        OutputError::Io {
            path: report.clone(),
            message: e.to_string(),
        }
    })?;
    written.push(report);
    Ok(written)
}

/// `optimum.csv`: a column per varied parameter, `objective`, `objective_low`,
/// `objective_high` (NaN when no setting meets the constraints).
fn optimum_columns(problem: &Problem, solution: &Solution) -> Vec<Column> {
    let best = solution.best.map(|b| &solution.settings[b]);
    let mut cols: Vec<Column> = problem
        .axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let v = best.map_or(f64::NAN, |s| s.values[k]);
            Column::f64(a.param.name(), a.param.spec().unit, vec![v])
        })
        .collect();
    let e = best.map(|s| s.objective);
    for (name, v) in [
        ("objective", e.map(|e| e.value)),
        ("objective_low", e.map(|e| e.low)),
        ("objective_high", e.map(|e| e.high)),
    ] {
        cols.push(Column::f64(name, "-", vec![v.unwrap_or(f64::NAN)]));
    }
    cols
}

/// The optimum under each calibrated set, one row per set.
pub(crate) const BAND_FILE: &str = "calibration_band.parquet";

/// [`BAND_FILE`]'s columns: the set and its constants, its optimum (a column per varied
/// parameter, the objective with its interval, the box edges it sits on), and the objective at
/// the run's optimum under the set; None without a band.
fn band_columns(problem: &Problem, solution: &Solution) -> Option<Vec<Column>> {
    let band = problem.band.as_ref()?;
    let optima = solution.band_optima();
    if optima.len() != band.sets.sets.len() {
        return None;
    }
    let sets = &band.sets.sets;
    let s = &solution.settings;
    let at = |k: usize, get: &dyn Fn(usize) -> f64| optima[k].map_or(f64::NAN, get);
    let f = |name: &str, unit: &'static str, get: &dyn Fn(usize) -> f64| {
        Column::f64(name, unit, (0..sets.len()).map(get).collect())
    };
    let mut cols = vec![
        Column::str("set", sets.iter().map(|c| c.id.clone()).collect()),
        Column::i64(
            "nominal",
            "",
            sets.iter().map(|c| i64::from(c.nominal)).collect(),
        ),
        f("wear_share_straight", "-", &|k| sets[k].wear_share_straight),
        f("speed_spread_kmh", "km/h", &|k| sets[k].speed_spread_kmh),
        f("wear_rate_driven_factor", "-", &|k| {
            sets[k].wear_rate_driven_factor
        }),
        f("carcass_share", "-", &|k| sets[k].carcass_share),
        f("belt_mass_share", "-", &|k| sets[k].belt_mass_share),
    ];
    for (j, a) in problem.axes.iter().enumerate() {
        cols.push(f(a.param.name(), a.param.spec().unit, &|k| {
            at(k, &|i| s[i].values[j])
        }));
    }
    let objective = |k: usize, i: usize| s[i].band[k].objective;
    cols.extend([
        f("objective", "-", &|k| at(k, &|i| objective(k, i).value)),
        f("objective_low", "-", &|k| at(k, &|i| objective(k, i).low)),
        f("objective_high", "-", &|k| at(k, &|i| objective(k, i).high)),
        f("objective_at_run_optimum", "-", &|k| {
            solution.best.map_or(f64::NAN, |b| objective(k, b).value)
        }),
        Column::str(
            "on_edge",
            (0..sets.len())
                .map(|k| {
                    optima[k].map_or(String::new(), |i| {
                        solution
                            .edges_of(i)
                            .iter()
                            .map(|&(j, side)| format!("{} {side}", problem.axes[j].param))
                            .collect::<Vec<_>>()
                            .join(", ")
                    })
                })
                .collect(),
        ),
    ]);
    Some(cols)
}

/// `surface.parquet`: one row per setting evaluated, in order.
fn surface_columns(problem: &Problem, solution: &Solution) -> Vec<Column> {
    let s = &solution.settings;
    let mut cols: Vec<Column> = problem
        .axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let v = s.iter().map(|x| x.values[k]).collect();
            Column::f64(a.param.name(), a.param.spec().unit, v)
        })
        .collect();
    let f = |name: &str, g: &dyn Fn(usize) -> f64| {
        Column::f64(name, "-", (0..s.len()).map(g).collect())
    };
    let within = solution.within_best();
    cols.extend([
        f("objective", &|i| s[i].objective.value),
        f("objective_low", &|i| s[i].objective.low),
        f("objective_high", &|i| s[i].objective.high),
        Column::i64(
            "samples",
            "",
            s.iter().map(|x| x.objective.n as i64).collect(),
        ),
        Column::i64("level", "", s.iter().map(|x| x.level as i64).collect()),
        Column::i64(
            "feasible",
            "",
            s.iter().map(|x| i64::from(x.feasible)).collect(),
        ),
        Column::i64(
            "within_best_interval",
            "",
            (0..s.len())
                .map(|i| i64::from(within.contains(&i)))
                .collect(),
        ),
        f("difference_vs_best", &|i| solution.vs_best[i].0),
        f("difference_low", &|i| solution.vs_best[i].1),
        f("difference_high", &|i| solution.vs_best[i].2),
    ]);
    for (k, c) in problem.constraints.iter().enumerate() {
        let name = format!("constraint_{}_{}", c.term.name(), c.wheel.name());
        cols.push(f(&name, &|i| s[i].constrained[k].value));
    }
    cols
}

/// `report.md`: the question, the answer in words, the picture and the files.
fn page(problem: &Problem, solution: &Solution, picture: Option<&Path>) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(s, "# Optimum of study `{}`\n", problem.study.name);
    let _ = writeln!(
        s,
        "Minimised: **{}**{}, over {} samples of the study (seed {}, variant {}), every setting on \
         the same samples. A wheel counts for `vibration` when it settles on a limit cycle or is \
         bistable; for `wear` when a visible polygon appears within {} km.\n",
        problem.objective.text(),
        if problem.constraints.is_empty() {
            String::new()
        } else {
            format!(
                ", subject to {}",
                problem
                    .constraints
                    .iter()
                    .map(|c| format!("`{}`", c.text))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        },
        problem.samples,
        problem.seed,
        problem.variant,
        plain(problem.within_km, 9)
    );
    let _ = writeln!(s, "What a setting means:\n");
    for a in &problem.axes {
        let _ = writeln!(
            s,
            "- {}; searched from {} to {}",
            a.meaning(),
            plain(a.lo, 6),
            plain(a.hi, 6)
        );
    }
    let _ = writeln!(s, "\n## Result\n");
    for line in summary(problem, solution) {
        let _ = writeln!(s, "- {}.", capitalise(&line));
    }
    match picture.and_then(|p| p.file_name()) {
        Some(name) => {
            let _ = writeln!(s, "\n![]({})\n", name.to_string_lossy());
        }
        None => {
            let _ = writeln!(s, "\nNo figure: no setting has an objective to draw.\n");
        }
    }
    let _ = writeln!(
        s,
        "The search: a {}-point grid per axis, refined {} times (each halving the step) around \
         the best {} settings within the best's interval; {} settings evaluated. Files: \
         `optimum.csv` (and `optimum.parquet` with the metadata), `surface.parquet` (every \
         setting, with its paired difference from the best){}.",
        problem.search.grid,
        problem.search.levels,
        problem.search.keep,
        solution.settings.len(),
        match &problem.band {
            Some(b) => format!(
                ", `{BAND_FILE}` (the optimum under each of the {} calibrated sets of `{}`, \
                 found among the same settings: each setting's wear answer re-evaluated under \
                 every set on the same samples, in closed form)",
                b.sets.sets.len(),
                b.source
            ),
            None => String::new(),
        }
    );
    s
}
