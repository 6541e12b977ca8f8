//! Flags shared by the commands that evaluate operating points, and the error type of the CLI.

use std::path::Path;

use clap::builder::TypedValueParser as _;
use clap::{Args, ValueEnum};
use strum::VariantNames as _;

use polywear_analysis::plot::FigureFormat;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::axle::Drivetrain;
use polywear_core::params::{ParamError, ParamId, Params};
use polywear_study::param_sources::{Refusal, Typed};

/// An error that ends the program: printed as `error: …`, exit code 2.
#[derive(Debug)]
pub(crate) struct CliError(pub String);

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl From<Refusal> for CliError {
    fn from(e: Refusal) -> Self {
        CliError(e.to_string())
    }
}

impl From<polywear_study::calibration_band::BandFileError> for CliError {
    fn from(e: polywear_study::calibration_band::BandFileError) -> Self {
        CliError(e.to_string())
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

pub(crate) type CliResult<T = ()> = Result<T, CliError>;

/// The text of an input file (a regular file within `limit`, see `polywear_study::safe_read`), refused
/// as `{prefix}FILE: why` (`prefix` names the flag, e.g. `"--params "`, or is empty).
pub(crate) fn read_input(
    path: &Path,
    prefix: &str,
    limit: polywear_study::safe_read::Limit,
) -> CliResult<String> {
    polywear_study::safe_read::read_text(path, limit).map_err(|e| CliError(format!("{prefix}{e}")))
}

/// The operating point and any other model parameter.
#[derive(Debug, Args, Clone)]
pub(crate) struct PointArgs {
    #[arg(long, value_name = "KMH", allow_hyphen_values = true, help = flag_help(ParamId::SpeedKmh))]
    pub(crate) speed: Option<f64>,
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, help = flag_help(ParamId::ToeDeg))]
    pub(crate) toe: Option<f64>,
    /// Toe-in in mm at the rim's edge across rim_diameter_mm (default 381 mm, a 15-inch rim;
    /// `--set rim_diameter_mm=406.4` for 16 inch), converted to the per-wheel angle
    /// atan(mm / D_rim)
    #[arg(long = "toe-mm", value_name = "MM", allow_hyphen_values = true,
          conflicts_with_all = ["toe", "toe_total"])]
    pub(crate) toe_mm: Option<f64>,
    /// Toe-in as the axle's total toe (both wheels) [deg], converted to the per-wheel angle
    /// (half of it)
    #[arg(
        long = "toe-total",
        value_name = "DEG",
        allow_hyphen_values = true,
        conflicts_with = "toe"
    )]
    pub(crate) toe_total: Option<f64>,
    #[arg(long, value_name = "N", allow_hyphen_values = true, help = flag_help(ParamId::LoadN))]
    pub(crate) load: Option<f64>,
    #[arg(long, value_name = "KPA", allow_hyphen_values = true, help = flag_help(ParamId::PressureKpa))]
    pub(crate) pressure: Option<f64>,
    /// Any model parameter by name, e.g. `--set g_mod=0.9e6` (repeatable; `polywear params`
    /// lists names, units, defaults and ranges)
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_assignment)]
    pub(crate) set: Vec<(String, f64)>,
    /// Parameter file (TOML `[params]` table, e.g. from `polywear calibrate`); --set and the
    /// operating-point flags replace its values, each replacement said in a note
    #[arg(long, value_name = "FILE")]
    pub(crate) params: Option<std::path::PathBuf>,
    /// Run values outside their plausible ranges (`polywear params`) anyway; without it a
    /// likely unit mix-up (pressure 2.4: bar, not kPa) is refused before any work
    #[arg(long)]
    pub(crate) accept_implausible: bool,
    /// Friction variant (differs for the driving wheel only): `sliding_share` (default; 2-D LuGre
    /// with the patch-mean longitudinal sliding speed, reproduces the paper's driving-wheel
    /// results), `paper` (the paper's literal Eq. 21, w_t = |w|) or `combined` (2-D LuGre with
    /// the full longitudinal sliding speed)
    #[arg(long, value_enum, default_value_t = VariantArg::SlidingShare)]
    pub(crate) variant: VariantArg,
    /// Which axle the engine drives: `fwd` (default; the driving wheel is a front wheel, the
    /// follower a rear one) or `rwd`. Each wheel reads its own axle's toe-in, load and pressure
    /// (`--set toe_rear_deg=0.4`; an axle without its own value takes the shared one)
    #[arg(long, value_name = "fwd|rwd", value_parser = drivetrains())]
    pub(crate) drivetrain: Option<Drivetrain>,
}

#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub(crate) enum VariantArg {
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
pub(crate) fn figure_formats() -> impl clap::builder::TypedValueParser<Value = FigureFormat> {
    clap::builder::PossibleValuesParser::new(FigureFormat::VARIANTS.iter().copied()).map(|name| {
        name.parse::<FigureFormat>()
            .expect("a possible value is a format")
    })
}

/// `--drivetrain`'s parser: the drivetrains by name (`fwd`, `rwd`), listed in help and in the
/// refusal of any other name.
pub(crate) fn drivetrains() -> impl clap::builder::TypedValueParser<Value = Drivetrain> {
    clap::builder::PossibleValuesParser::new(Drivetrain::VARIANTS.iter().copied()).map(|name| {
        name.parse::<Drivetrain>()
            .expect("a possible value is a drivetrain")
    })
}

#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub(crate) enum WheelArg {
    Follower,
    Driving,
    // The wheel on the front or rear axle under the drivetrain (`--drivetrain`); plain
    // comments, since a documented value would turn `--help` into its long form.
    Front,
    Rear,
    Both,
}

impl WheelArg {
    /// The wheels asked for, a front or rear one being the drivetrain's wheel on that axle.
    pub(crate) fn wheels(self, drivetrain: Drivetrain) -> Vec<Wheel> {
        use polywear_core::params::axle::Axle;
        match self {
            WheelArg::Follower => vec![Wheel::Follower],
            WheelArg::Driving => vec![Wheel::Driving],
            WheelArg::Front => vec![drivetrain.wheel_on(Axle::Front)],
            WheelArg::Rear => vec![drivetrain.wheel_on(Axle::Rear)],
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

pub(crate) fn parse_assignment(s: &str) -> Result<(String, f64), String> {
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

pub(crate) use polywear_study::param_sources::{param_file, ParamSources as Resolved};

impl PointArgs {
    /// Defaults, then `--params`, then `--set` and the four named flags; everything validated
    /// before work starts (see [`PointArgs::resolve`]).
    pub(crate) fn params(&self) -> CliResult<Params> {
        self.resolve().map(|r| r.params)
    }

    /// The parameters with their sources ([`Resolved::resolve`]: the one-place rule), the
    /// notes printed on stderr.
    pub(crate) fn resolve(&self) -> CliResult<Resolved> {
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
            let id = input.target();
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
            (ToeInput::MM, self.toe_mm),
            (ToeInput::TOTAL_DEG, self.toe_total),
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
        let (mut resolved, notes) =
            Resolved::resolve(self.params.as_deref(), typed, self.accept_implausible)?;
        if let Some(d) = self.drivetrain {
            resolved.params.drivetrain = d;
        }
        for note in notes {
            eprintln!("{note}");
        }
        Ok(resolved)
    }
}

/// The defaults, with the `--params` file applied when one is given (see [`param_file`]).
pub(crate) fn base_params(path: Option<&Path>, accept_implausible: bool) -> CliResult<Params> {
    Ok(param_file(path, accept_implausible).map(|(p, _)| p)?)
}

/// A parameter the command itself varies (a sweep, a chart's axis): typed too it is refused;
/// a `--params` file's value is replaced, and a note says so.
pub(crate) fn sweep_owns(id: ParamId, owner: &str, resolved: &Resolved) -> CliResult {
    if let Some(note) = resolved.owned_by(id, owner)? {
        eprintln!("{note}");
    }
    Ok(())
}

pub(crate) use polywear_study::provenance::run_metadata as base_metadata;

mod flags;
pub(crate) use flags::*;

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
