//! One order's closed loop (MODEL.md#growth-of-an-order, MODEL.md#growth-of-a-vibrating-wheel):
//! what its growth takes from the wheel alone, what it takes from the speed spread, and the loop
//! as a function of the tread's mean transfer; and the sets of fitted constants grouped by spread.

use super::*;

/// One order's closed loop as a function of the tread's transfer Ḡ it sees: affine in Ḡ (the
/// linear loop, MODEL.md#growth-of-an-order), and over the share of the spread in the
/// tongue, the locked print instead (MODEL.md#growth-of-a-vibrating-wheel).
#[derive(Debug, Clone, Copy)]
pub(super) struct OrderLoop {
    /// β with no transfer through the tread: −w′κ(1 − |H_w|²) − λ_other − the slip power's
    /// part \[1/m\].
    pub(super) base_per_m: f64,
    /// β's part through the tread is Re(Ḡ · this): −w′ conj(H_w) e_n \[1/m\].
    pub(super) through_per_m: Complex64,
    /// The locked print's growth, less λ_other and the slip power's part \[1/m\].
    pub(super) locked_per_m: f64,
}

impl OrderLoop {
    /// β's regenerative part, the one through the tread, for the transfer `g` \[1/m\].
    pub(super) fn through_tread_per_m(&self, g: Complex64) -> f64 {
        (g * self.through_per_m).re
    }

    /// β of the linear loop for the transfer `g` \[1/m\].
    pub(super) fn linear_per_m(&self, g: Complex64) -> f64 {
        self.base_per_m + self.through_tread_per_m(g)
    }

    /// β for the transfer's normal mean over the spread `mean`, a share `locked_share` of the
    /// spread inside the tongue, over which the transfer's uniform mean is `over_tongue`
    /// \[1/m\]. Inside the tongue the order grows by the locked print instead of the linear
    /// loop: over the share of the spread there, the loop's own mean over the band (uniform,
    /// the spread's density taken as flat across it) is replaced; with no spread
    /// (`over_tongue` none), the whole.
    pub(super) fn growth_per_m(
        &self,
        mean: Complex64,
        locked_share: f64,
        over_tongue: Option<Complex64>,
    ) -> f64 {
        let beta = self.linear_per_m(mean);
        if locked_share > NEGLIGIBLE_LOCKED_SHARE {
            let in_band = over_tongue.map_or(beta, |g| self.linear_per_m(g));
            beta + locked_share * (self.locked_per_m - in_band)
        } else {
            beta
        }
    }
}

/// The part of one order's growth that depends on the wheel alone.
#[derive(Debug, Clone)]
pub(super) struct OrderFixed {
    pub(super) order: u32,
    /// H_w(n), the wear zone's transfer.
    pub(super) zone: Complex64,
    /// e_n, the forcing per unit radius.
    pub(super) forcing: Complex64,
    /// The tongue's centre and half-width \[m/s\].
    pub(super) lock_speed_mps: f64,
    pub(super) lock_mps: f64,
    /// The forcing's uniform mean over the tongue, once a spread reaches into it.
    pub(super) over_tongue: std::cell::OnceCell<Complex64>,
}

/// The part of one order's growth that does not depend on φ_s or k_d: the order's zone transfer
/// and forcing, and what the speed spread gives it ([`WheelGrowth::answers_with`] keeps it per
/// spread).
#[derive(Debug, Clone, Copy)]
pub(super) struct SpreadTerms {
    pub(super) order: u32,
    /// H_w(n), the wear zone's transfer.
    pub(super) zone: Complex64,
    /// e_n, the forcing per unit radius.
    pub(super) forcing: Complex64,
    /// Ḡ, the forcing's transfer averaged over the normal spread.
    pub(super) mean: Complex64,
    /// Half-width of the tongue \[m/s\].
    pub(super) lock_mps: f64,
    /// The share of the spread inside it.
    pub(super) locked_share: f64,
    /// The transfer's uniform mean over the tongue, where the spread reaches into it.
    pub(super) over_tongue: Option<Complex64>,
}

/// `answer(what, c)` for every set `c` of `sets`, in order, where `what` is `for_spread(σ_V)`
/// \[m/s\] taken once per distinct speed spread among the sets (the calibration band's sets
/// share a few spreads).
pub(crate) fn per_spread<T, A>(
    sets: &[FittedConstants],
    mut for_spread: impl FnMut(f64) -> T,
    mut answer: impl FnMut(&T, &FittedConstants) -> A,
) -> Vec<A> {
    let mut by_spread: Vec<(u64, T)> = Vec::new();
    sets.iter()
        .map(|c| {
            let spread_mps = c.speed_spread_kmh / 3.6;
            let key = spread_mps.to_bits();
            let k = match by_spread.iter().position(|(b, _)| *b == key) {
                Some(k) => k,
                None => {
                    by_spread.push((key, for_spread(spread_mps)));
                    by_spread.len() - 1
                }
            };
            answer(&by_spread[k].1, c)
        })
        .collect()
}
