//! The wear stage's two readings as flags, shared by `explore`, `cycle` and `wear`: where the
//! friction power wears the tread, and which power (MODEL.md#step-11-wear-zone,
//! MODEL.md#the-driving-wheels-slip-power).
use clap::Args;
use polywear_core::wear::{WearPower, WearSettings, WearZone};

/// `--wear-zone` and `--wear-power`.
#[derive(Debug, Clone, Default, Args)]
pub(crate) struct WearReadingArgs {
    /// Where the friction power wears the tread (MODEL.md#step-11-wear-zone): trailing (the
    /// default), whole_patch or whole_patch_uniform; a study can say `wear_zone = "..."`
    #[arg(long, value_name = "ZONE", value_parser = |s: &str| s.parse::<WearZone>().map_err(|e| e.to_string()))]
    pub(crate) wear_zone: Option<WearZone>,
    /// Which friction power wears it (MODEL.md#the-driving-wheels-slip-power): with_slip (the
    /// default: the driving wheel's longitudinal slip power too, and its position's faster even
    /// wear) or lateral_only; a study can say `wear_power = "..."`
    #[arg(long, value_name = "POWER", value_parser = |s: &str| s.parse::<WearPower>().map_err(|e| e.to_string()))]
    pub(crate) wear_power: Option<WearPower>,
    /// Retired: every sample carries one wear answer, over the tread's life with each speed's
    /// print saturated. `tread_life_saturated` is accepted (it changes nothing); `new_tire` and
    /// `tread_life` are refused, naming what replaced them
    #[arg(long, value_name = "LEVEL", hide = true, value_parser = parse_retired_level)]
    pub(crate) wear_estimate: Option<String>,
}

/// `--wear-estimate`: the one answer, accepted; a retired one, refused with what replaced it.
fn parse_retired_level(s: &str) -> Result<String, String> {
    use polywear_core::wear::{retired_level, SHIPPED_LEVEL};
    if s == SHIPPED_LEVEL {
        return Ok(s.to_string());
    }
    Err(retired_level(s).unwrap_or_else(|| {
        format!("no such wear answer; the one answer is `{SHIPPED_LEVEL}`, and the flag may be left out")
    }))
}

impl WearReadingArgs {
    /// The settings asked for, the defaults where a flag is not given.
    pub(crate) fn settings(&self) -> WearSettings {
        WearSettings {
            zone: self.wear_zone.unwrap_or_default(),
            power: self.wear_power.unwrap_or_default(),
        }
    }
}
