//! Flags and checks every command shares: whole numbers in a range, threads, output files and
//! their extensions and the per-wheel budget.

use std::path::Path;

use clap::Args;
use strum::VariantNames as _;

use super::{CliError, CliResult};
use polywear_analysis::plot::{FigureFile, FigureFormat};
use polywear_core::classify::WheelBudget;

/// Accepted range of `--threads`, the same in every command.
pub(crate) const THREADS_MAX: usize = 1024;

/// Parses a whole number for `flag` within [lo, hi]; anything else (negative, fractional, not a
/// number, out of range) is refused with the accepted range. Use with
/// `allow_negative_numbers = true`, so that `-5` reaches this message instead of clap's
/// "unexpected argument".
pub(crate) fn whole_in<T: TryFrom<u64>>(
    flag: &'static str,
    lo: u64,
    hi: u64,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        whole_number(s)
            .filter(|v| (lo..=hi).contains(v))
            .and_then(|v| T::try_from(v).ok())
            .ok_or_else(|| format!("{flag} `{s}` must be a whole number in [{lo}, {hi}]"))
    }
}

/// A whole number as people type one: `20000`, `2e4`, `20_000` or `2.0e4` (a count written as
/// a number is the same count); None for a fraction, a sign, or what is no number.
fn whole_number(s: &str) -> Option<u64> {
    let t = s.trim().replace('_', "");
    if let Ok(v) = t.parse::<u64>() {
        return Some(v);
    }
    let x: f64 = t.parse().ok()?;
    // Below 2^53 every whole f64 is exact, so a count read this way is the count typed.
    (x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < 9_007_199_254_740_992.0)
        .then_some(x as u64)
}

/// A count given as a number (so `1e9` is accepted) checked for `flag`: a whole number within
/// [lo, hi], else refused with the accepted range, powers of ten written short (`1e12`).
pub(crate) fn whole_count(flag: &str, n: f64, (lo, hi): (u64, u64)) -> CliResult<u64> {
    if n.fract() == 0.0 && n >= lo as f64 && n <= hi as f64 {
        return Ok(n as u64);
    }
    let short = |v: u64| {
        let digits = v.to_string();
        match digits.trim_end_matches('0') {
            "1" if v >= 1_000_000 => format!("1e{}", digits.len() - 1),
            _ => digits,
        }
    };
    Err(CliError(format!(
        "{flag} = {n} must be a whole number in [{}, {}]",
        short(lo),
        short(hi)
    )))
}

/// Parses `--threads`: a whole number in [1, THREADS_MAX].
pub(crate) fn parse_threads(s: &str) -> Result<usize, String> {
    whole_in("--threads", 1, THREADS_MAX as u64)(s)
}

/// Prepares an output file before any work starts: a missing folder is created (as every
/// command does with its output paths), a directory given as the file is refused.
pub(crate) fn check_out_file(path: &Path, flag: &str) -> CliResult {
    if path.is_dir() {
        return Err(CliError(format!(
            "{flag} {}: is a directory; accepted: a file name",
            path.display()
        )));
    }
    let parent = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(dir) = parent {
        polywear_study::safe_write::create_dir(dir).map_err(|e| {
            CliError(format!(
                "{flag} {}: cannot create the folder {}: {e}",
                path.display(),
                dir.display()
            ))
        })?;
    }
    Ok(())
}

/// The worker pool of `--threads` (None: all cores).
pub(crate) fn thread_pool(threads: Option<usize>) -> CliResult<rayon::ThreadPool> {
    if let Some(t) = threads {
        if !(1..=THREADS_MAX).contains(&t) {
            return Err(CliError(format!(
                "--threads = {t} is outside its accepted range [1, {THREADS_MAX}]"
            )));
        }
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError(format!("cannot start threads: {e}")))
}

/// A figure file named in full (`--plot FILE`): its format is its extension, refused with the
/// accepted ones before any work starts.
pub(crate) fn figure_file(path: &Path, flag: &str) -> CliResult<FigureFile> {
    let format = FigureFormat::of_path(path)
        .ok_or_else(|| extension_refusal(path, flag, FigureFormat::VARIANTS))?;
    Ok(FigureFile {
        path: path.to_path_buf(),
        format,
    })
}

/// Refuses output paths whose extension we cannot write, before any work starts.
pub(crate) fn check_extension(path: &Path, accepted: &[&str], flag: &str) -> CliResult {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if accepted.contains(&ext) {
        Ok(())
    } else {
        Err(extension_refusal(path, flag, accepted))
    }
}

/// The refusal of `path`'s extension, naming the flag and the accepted ones.
fn extension_refusal(path: &Path, flag: &str, accepted: &[&str]) -> CliError {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    CliError(format!(
        "{flag} {}: unsupported file type `.{ext}`; accepted: {}",
        path.display(),
        accepted
            .iter()
            .map(|e| format!(".{e}"))
            .collect::<Vec<_>>()
            .join(", ")
    ))
}

/// The per-wheel work budget flags, shared by every command that classifies.
#[derive(Debug, Args, Clone, Default)]
pub(crate) struct BudgetArgs {
    /// Most RHS evaluations one wheel may take; a wheel that needs more becomes a `failed` row
    /// with reason `budget exceeded (...)`. Accepted [100, 1e12]; default: the study's
    /// `max_rhs_evals`, else 20000000 (a limit cycle takes about a thousand)
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub(crate) max_rhs_evals: Option<f64>,
    /// Most wall-clock seconds one wheel may take (a safety net; normal wheels take
    /// milliseconds). Accepted [0.001, 86400]; default: the study's `max_wheel_seconds`, else 60
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub(crate) max_wheel_seconds: Option<f64>,
}

impl BudgetArgs {
    /// `base` (defaults or the study's) with the flags given applied, checked.
    pub(crate) fn apply(&self, base: WheelBudget) -> CliResult<WheelBudget> {
        let mut b = base;
        if let Some(n) = self.max_rhs_evals {
            b.max_rhs_evals = whole_count("--max-rhs-evals", n, WheelBudget::RHS_EVALS_RANGE)?;
        }
        if let Some(s) = self.max_wheel_seconds {
            b.max_wheel_seconds = s;
        }
        b.check()
            .map_err(|e| CliError(format!("--{} {}", e.key().replace('_', "-"), e.refusal())))?;
        Ok(b)
    }
}
