//! Flags shared by the commands that evaluate operating points, and the error type of the CLI.

use std::path::Path;

use clap::builder::TypedValueParser as _;
use clap::{Args, ValueEnum};
use strum::VariantNames as _;

use polywear_analysis::plot::{FigureFile, FigureFormat};
use polywear_core::classify::WheelBudget;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::{ParamError, ParamId, Params};
use polywear_study::param_sources::{Refusal, Typed};

/// An error that ends the program: printed as `error: …`, exit code 2.
#[derive(Debug)]
pub struct CliError(pub String);

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl From<Refusal> for CliError {
    fn from(e: Refusal) -> Self {
        CliError(e.0)
    }
}

impl From<ParamError> for CliError {
    fn from(e: ParamError) -> Self {
        CliError(e.to_string())
    }
}

impl From<polywear_study::parquet_out::WriteError> for CliError {
    fn from(e: polywear_study::parquet_out::WriteError) -> Self {
        let text = e.to_string();
        let hint = if text.contains("read-only") || text.contains("full disk") {
            "; choose another folder with the command's --out"
        } else {
            ""
        };
        CliError(format!("cannot write output: {text}{hint}"))
    }
}

pub type CliResult<T = ()> = Result<T, CliError>;

/// The text of an input file (a regular file within `limit`, see `polywear_study::safe_read`), refused
/// as `{prefix}FILE: why` (`prefix` names the flag, e.g. `"--params "`, or is empty).
pub fn read_input(
    path: &Path,
    prefix: &str,
    limit: polywear_study::safe_read::Limit,
) -> CliResult<String> {
    polywear_study::safe_read::read_text(path, limit).map_err(|e| CliError(format!("{prefix}{e}")))
}

/// The operating point and any other model parameter.
#[derive(Debug, Args, Clone)]
pub struct PointArgs {
    #[arg(long, value_name = "KMH", allow_hyphen_values = true, help = flag_help(ParamId::SpeedKmh))]
    pub speed: Option<f64>,
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, help = flag_help(ParamId::ToeDeg))]
    pub toe: Option<f64>,
    /// Toe-in in mm at the rim's edge across rim_diameter_mm (default 381 mm, a 15-inch rim;
    /// `--set rim_diameter_mm=406.4` for 16 inch), converted to the per-wheel angle
    /// atan(mm / D_rim)
    #[arg(long = "toe-mm", value_name = "MM", allow_hyphen_values = true,
          conflicts_with_all = ["toe", "toe_total"])]
    pub toe_mm: Option<f64>,
    /// Toe-in as the axle's total toe (both wheels) [deg], converted to the per-wheel angle
    /// (half of it)
    #[arg(
        long = "toe-total",
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "toe"
    )]
    pub toe_total: Option<f64>,
    #[arg(long, value_name = "N", allow_hyphen_values = true, help = flag_help(ParamId::LoadN))]
    pub load: Option<f64>,
    #[arg(long, value_name = "KPA", allow_hyphen_values = true, help = flag_help(ParamId::PressureKpa))]
    pub pressure: Option<f64>,
    /// Any model parameter by name, e.g. `--set g_mod=0.9e6` (repeatable; `polywear params`
    /// lists names, units, defaults and ranges)
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_assignment)]
    pub set: Vec<(String, f64)>,
    /// Parameter file (TOML `[params]` table, e.g. from `polywear calibrate`); --set and the
    /// operating-point flags replace its values, each replacement said in a note
    #[arg(long, value_name = "FILE")]
    pub params: Option<std::path::PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway; without it a
    /// likely unit mix-up (pressure 2.4: bar, not kPa) is refused before any work
    #[arg(long)]
    pub accept_implausible: bool,
    /// Friction variant (differs for the driving wheel only): `sliding_share` (default; 2-D LuGre
    /// with the patch-mean longitudinal sliding speed, reproduces the paper's driving-wheel
    /// results), `paper` (the paper's literal Eq. 21, w_t = |w|) or `combined` (2-D LuGre with
    /// the full longitudinal sliding speed)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub variant: VariantArg,
}

#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum VariantArg {
    Paper,
    Combined,
    #[value(name = "sliding_share", alias = "sliding-share")]
    SlidingShare,
}

impl From<VariantArg> for Variant {
    fn from(v: VariantArg) -> Self {
        match v {
            VariantArg::Paper => Variant::Paper,
            VariantArg::Combined => Variant::Combined,
            VariantArg::SlidingShare => Variant::SlidingShare,
        }
    }
}

/// `--format`'s parser: the library's figure formats by name (`png`, `svg`), listed in help
/// and in the refusal of any other name.
pub fn figure_formats() -> impl clap::builder::TypedValueParser<Value = FigureFormat> {
    clap::builder::PossibleValuesParser::new(FigureFormat::VARIANTS.iter().copied()).map(|name| {
        name.parse::<FigureFormat>()
            .expect("a possible value is a format")
    })
}

#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum WheelArg {
    Follower,
    Driving,
    Both,
}

impl WheelArg {
    pub fn wheels(self) -> Vec<Wheel> {
        match self {
            WheelArg::Follower => vec![Wheel::Follower],
            WheelArg::Driving => vec![Wheel::Driving],
            WheelArg::Both => Wheel::BOTH.to_vec(),
        }
    }
}

/// The help of an operating-point flag, from the parameter table: what it is, its unit, its
/// accepted range and its default, e.g. "Vehicle speed [km/h], accepted (0, 400] [default: 100]".
fn flag_help(id: ParamId) -> String {
    let s = id.spec();
    format!(
        "{} [{}], accepted {} [default: {}]",
        s.description.trim_end_matches('.'),
        s.unit,
        s.range_text(),
        polywear_core::wording::plain(s.default, 6)
    )
}

pub fn parse_assignment(s: &str) -> Result<(String, f64), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=VALUE, got `{s}`"))?;
    let name = name.trim();
    let value: f64 = value.trim().parse().map_err(|_| match setting(name) {
        Some((flag, accepted, commands)) => format!(
            "`{name}` is a setting, not a parameter (--set takes numbers): {commands} take it as {flag} {} (accepted: {})",
            value.trim(),
            accepted.join(", ")
        ),
        None => format!("value of `{name}` is not a number: `{}`", value.trim()),
    })?;
    Ok((name.to_string(), value))
}

/// A setting's flag, accepted names and the commands that take it, for a study key that is no
/// parameter (`wear_zone`).
fn setting(name: &str) -> Option<(&'static str, &'static [&'static str], &'static str)> {
    use polywear_core::wear::{WearPower, WearZone, SHIPPED_LEVEL};
    use strum::VariantNames;
    const WEAR: &str = "explore, cycle and wear";
    match name {
        "wear_zone" => Some(("--wear-zone", WearZone::VARIANTS, WEAR)),
        "wear_power" => Some(("--wear-power", WearPower::VARIANTS, WEAR)),
        "wear_estimate" => Some((
            "--wear-estimate (retired: one answer is given)",
            &[SHIPPED_LEVEL],
            "explore and cycle",
        )),
        "variant" | "variants" => Some((
            "--variant",
            polywear_core::model::Variant::VARIANTS,
            "simulate, cycle, wear, chart, classify and bifurcation",
        )),
        _ => None,
    }
}

pub use polywear_study::param_sources::{
    param_file, refuse_file_overlap, refuse_reserved_names, ParamSources as Resolved,
};

impl PointArgs {
    /// Defaults, then `--params`, then `--set` and the four named flags; everything validated
    /// before work starts (see [`PointArgs::resolve`]).
    pub fn params(&self) -> CliResult<Params> {
        self.resolve().map(|r| r.params)
    }

    /// The parameters with their sources ([`Resolved::resolve`]: the one-place rule), the
    /// notes printed on stderr.
    pub fn resolve(&self) -> CliResult<Resolved> {
        use polywear_core::params::toe::ToeInput;
        let plain = |x: f64| polywear_core::wording::plain(x, 12);
        let rim = polywear_study::toe_input::rim_diameter_mm(
            self.params.as_deref(),
            &self.set,
            self.accept_implausible,
        )?;
        let toe = |typed_as: String, input: ToeInput, x: f64| -> CliResult<Typed> {
            let (value, by) = polywear_study::toe_input::typed_toe(
                &typed_as,
                input,
                x,
                rim,
                self.accept_implausible,
            )?;
            let id = ParamId::ToeDeg;
            Ok(Typed { id, by, value })
        };
        let mut typed = Vec::new();
        for (name, value) in &self.set {
            if let Some(input) = ToeInput::parse(name) {
                typed.push(toe(
                    format!("--set {name}={}", plain(*value)),
                    input,
                    *value,
                )?);
                continue;
            }
            let id: ParamId = name
                .parse()
                .map_err(|e: ParamError| CliError(format!("--set {name}={value}: {e}")))?;
            let by = format!("--set {name}={}", plain(*value));
            typed.push(Typed {
                id,
                by,
                value: *value,
            });
        }
        for (input, value) in [
            (ToeInput::Mm, self.toe_mm),
            (ToeInput::TotalDeg, self.toe_total),
        ] {
            if let Some(x) = value {
                typed.push(toe(format!("{} {}", input.flag(), plain(x)), input, x)?);
            }
        }
        for (flag, id, value) in [
            ("--speed", ParamId::SpeedKmh, self.speed),
            ("--toe", ParamId::ToeDeg, self.toe),
            ("--load", ParamId::LoadN, self.load),
            ("--pressure", ParamId::PressureKpa, self.pressure),
        ] {
            if let Some(value) = value {
                let by = format!("{flag} {}", polywear_core::wording::plain(value, 12));
                typed.push(Typed { id, by, value });
            }
        }
        let (resolved, notes) =
            Resolved::resolve(self.params.as_deref(), typed, self.accept_implausible)?;
        for note in notes {
            eprintln!("{note}");
        }
        Ok(resolved)
    }
}

/// The defaults, with the `--params` file applied when one is given (see [`param_file`]).
pub fn base_params(path: Option<&Path>, accept_implausible: bool) -> CliResult<Params> {
    Ok(param_file(path, accept_implausible).map(|(p, _)| p)?)
}

/// A parameter the command itself varies (a sweep, a chart's axis): typed too it is refused;
/// a `--params` file's value is replaced, and a note says so.
pub fn sweep_owns(id: ParamId, owner: &str, resolved: &Resolved) -> CliResult {
    if let Some(note) = resolved.owned_by(id, owner)? {
        eprintln!("{note}");
    }
    Ok(())
}

/// Accepted range of `--threads`, the same in every command.
pub const THREADS_MAX: usize = 1024;

/// Parses a whole number for `flag` within [lo, hi]; anything else (negative, fractional, not a
/// number, out of range) is refused with the accepted range. Use with
/// `allow_negative_numbers = true`, so that `-5` reaches this message instead of clap's
/// "unexpected argument".
pub fn whole_in<T: TryFrom<u64>>(
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
pub fn whole_count(flag: &str, n: f64, (lo, hi): (u64, u64)) -> CliResult<u64> {
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
pub fn parse_threads(s: &str) -> Result<usize, String> {
    whole_in("--threads", 1, THREADS_MAX as u64)(s)
}

/// Prepares an output file before any work starts: a missing folder is created (as every
/// command does with its output paths), a directory given as the file is refused.
pub fn check_out_file(path: &Path, flag: &str) -> CliResult {
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
pub fn thread_pool(threads: Option<usize>) -> CliResult<rayon::ThreadPool> {
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
pub fn figure_file(path: &Path, flag: &str) -> CliResult<FigureFile> {
    let format = FigureFormat::of_path(path)
        .ok_or_else(|| extension_refusal(path, flag, FigureFormat::VARIANTS))?;
    Ok(FigureFile {
        path: path.to_path_buf(),
        format,
    })
}

/// Refuses output paths whose extension we cannot write, before any work starts.
pub fn check_extension(path: &Path, accepted: &[&str], flag: &str) -> CliResult {
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

pub use polywear_study::provenance::run_metadata as base_metadata;

/// The per-wheel work budget flags, shared by every command that classifies.
#[derive(Debug, Args, Clone, Default)]
pub struct BudgetArgs {
    /// Most RHS evaluations one wheel may take; a wheel that needs more becomes a `failed` row
    /// with reason `budget exceeded (...)`. Accepted [100, 1e12]; default: the study's
    /// `max_rhs_evals`, else 20000000 (a limit cycle takes about a thousand)
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub max_rhs_evals: Option<f64>,
    /// Most wall-clock seconds one wheel may take (a safety net; normal wheels take
    /// milliseconds). Accepted [0.001, 86400]; default: the study's `max_wheel_seconds`, else 60
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub max_wheel_seconds: Option<f64>,
}

impl BudgetArgs {
    /// `base` (defaults or the study's) with the flags given applied, checked.
    pub fn apply(&self, base: WheelBudget) -> CliResult<WheelBudget> {
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

/// The calibration band `--calibration-band` asks for: the shipped sets when absent, none for
/// `off`, else the file's (refused here, before any work, when it cannot be read or is not a
/// file of calibrated sets). Returns the sets and where they come from.
pub fn calibration_band(
    asked: Option<&str>,
) -> CliResult<Option<(polywear_study::calibration_band::CalibrationBand, String)>> {
    use polywear_study::calibration_band::{CalibrationBand, SHIPPED_NAME};
    match asked {
        Some("off") => Ok(None),
        None => Ok(Some((CalibrationBand::shipped(), SHIPPED_NAME.to_string()))),
        Some(file) => {
            let text = read_input(
                std::path::Path::new(file),
                "--calibration-band ",
                polywear_study::safe_read::Limit::Text,
            )?;
            let band = CalibrationBand::parse(&text, file)
                .map_err(|e| CliError(format!("--calibration-band {e}")))?;
            Ok(Some((band, file.to_string())))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::whole_count;

    #[test]
    fn a_count_flag_takes_a_count_written_as_a_number() {
        let band = super::whole_in::<u64>("--band-samples", 100, 1_000_000);
        for typed in ["20000", "2e4", "20_000", "2.0e4", " 2E4 "] {
            assert_eq!(band(typed), Ok(20_000), "{typed}");
        }
        for bad in ["150.5", "-2e4", "2e7", "1e400", "nan", "lots", "2e-1"] {
            let e = band(bad).unwrap_err();
            assert_eq!(
                e,
                format!("--band-samples `{bad}` must be a whole number in [100, 1000000]")
            );
        }
    }

    #[test]
    fn whole_count_takes_whole_numbers_in_range_and_names_the_flag_otherwise() {
        assert_eq!(
            whole_count("--n", 1e9, (100, 1_000_000_000_000)).unwrap(),
            1_000_000_000
        );
        assert_eq!(whole_count("--n", 100.0, (100, 1_000)).unwrap(), 100);
        for bad in [99.0, 2.5e12, 1e9 + 0.5, f64::NAN, -1.0] {
            let e = whole_count("--n", bad, (100, 1_000_000_000_000))
                .unwrap_err()
                .0;
            assert!(e.starts_with("--n = "), "{e}");
            assert!(e.ends_with("must be a whole number in [100, 1e12]"), "{e}");
        }
        let e = whole_count("--n", 1.0, (1_000_000, 3_000_000))
            .unwrap_err()
            .0;
        assert!(e.ends_with("[1e6, 3000000]"), "{e}");
    }
}
