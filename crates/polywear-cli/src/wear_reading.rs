//! The wear stage's two readings as flags, shared by `explore`, `cycle` and `wear`: where the
//! friction power wears the tread, and which power (MODEL.md#step-11-wear-zone,
//! MODEL.md#the-driving-wheels-slip-power).
use clap::Args;
use polywear_core::wear::{EstimateLevel, WearPower, WearSettings, WearZone};

/// `--wear-zone` and `--wear-power`.
#[derive(Debug, Clone, Default, Args)]
pub struct WearReadingArgs {
    /// Where the friction power wears the tread (MODEL.md#step-11-wear-zone): trailing (the
    /// default), whole_patch or whole_patch_uniform; a study can say `wear_zone = "..."`
    #[arg(long, value_name = "ZONE", value_parser = |s: &str| s.parse::<WearZone>().map_err(|e| e.to_string()))]
    pub wear_zone: Option<WearZone>,
    /// Which friction power wears it (MODEL.md#the-driving-wheels-slip-power): with_slip (the
    /// default: the driving wheel's longitudinal slip power too, and its position's faster even
    /// wear) or lateral_only; a study can say `wear_power = "..."`
    #[arg(long, value_name = "POWER", value_parser = |s: &str| s.parse::<WearPower>().map_err(|e| e.to_string()))]
    pub wear_power: Option<WearPower>,
}

impl WearReadingArgs {
    /// The settings asked for, the defaults where a flag is not given.
    pub fn settings(&self) -> WearSettings {
        WearSettings {
            zone: self.wear_zone.unwrap_or_default(),
            power: self.wear_power.unwrap_or_default(),
            // `cycle` and `wear` answer as the new tire (`wear --estimate` prints the answer
            // over the tread's life beside it); explore's `--wear-estimate` chooses.
            estimate: EstimateLevel::NewTire,
        }
    }
}
