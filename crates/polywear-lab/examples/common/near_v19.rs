//! The default point's follower at its V_19 (φ_s = 1, no spread), shared by the examples that
//! force its cycle by one order-19 harmonic (`locked_print`, `orbit_tongue`).
use polywear::classify::budget::Meter;
use polywear::classify::ClassifierOptions;
use polywear::evaluate::{solve_wheel, WearStage, WheelSolution};
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear_core::wear::{WearSettings, WheelGrowth};

/// The order forced.
pub const ORDER: u32 = 19;
/// The friction variant.
pub const VARIANT: Variant = Variant::SlidingShare;

/// The radii R \[µm\] given on the command line.
pub fn radii_um() -> Vec<f64> {
    std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("a radius in µm"))
        .collect()
}

/// The default point's parameters at `speed_kmh`, φ_s = 1 and no spread.
pub fn at(speed_kmh: f64) -> Params {
    Params {
        speed_kmh,
        wear_share_straight: 1.0,
        speed_spread_kmh: 0.0,
        ..Params::default()
    }
}

/// The follower near V_19: its growth and solution at the speed V ν/19 of 100 km/h's ν, and
/// V_19 refined once more from that speed's ν \[km/h\].
pub struct NearV19 {
    pub growth: WheelGrowth,
    pub wheel: WheelSolution,
    pub centre_kmh: f64,
}

impl NearV19 {
    pub fn new() -> Self {
        let opts = ClassifierOptions::default();
        let growth_at = |p: &Params| {
            let stage = WearStage::for_run(p, VARIANT, WearSettings::default(), &opts).unwrap();
            let w = solve_wheel(*p, VARIANT, Wheel::Follower, &opts);
            let g = WheelGrowth::new(&stage.problem(p, &w), &Meter::new(opts.budget)).unwrap();
            (w, g)
        };
        let (_, g100) = growth_at(&at(100.0));
        let p0 = at(100.0 * g100.nu() / ORDER as f64);
        let (wheel, growth) = growth_at(&p0);
        let centre_kmh = p0.speed_kmh * growth.nu() / ORDER as f64;
        NearV19 {
            growth,
            wheel,
            centre_kmh,
        }
    }

    /// The free cycle's state on its section (z, y, v), where forced runs start.
    pub fn free_start(&self) -> [f64; 3] {
        let v = &self.wheel.verdict;
        let m = self.wheel.model.as_ref().unwrap();
        [v.section_z_m, m.ode.equilibrium()[1], v.section_v_mps]
    }
}
