//! Tire geometry and the tread block (MODEL.md#step-1-deflection to #step-3-tread-block; paper
//! Eqs. 13, 14, 16).

use crate::params::Params;

/// The tire–road contact patch under load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPatch {
    /// Maximum radial deflection δ (Eq. 14).
    pub deflection_m: f64,
    /// Contact length a (Eq. 13).
    pub length_m: f64,
    /// Contact width b (Eq. 13).
    pub width_m: f64,
}

/// No contact patch: the deflection is so large that the contact length is undefined.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("contact patch undefined: xi*deflection = {xi_deflection_m:.4} m reaches the tire diameter 2*r_b = {diameter_m:.4} m")]
pub struct FlatTire {
    /// ξδ \[m\].
    pub xi_deflection_m: f64,
    /// 2 r_B \[m\].
    pub diameter_m: f64,
}

/// Contact patch from load and pressure (steps 1–2). Fails when the deflection is so large that
/// the contact length is undefined (ξδ ≥ 2 r_B): the tire would be flat.
pub fn contact_patch(p: &Params) -> Result<ContactPatch, FlatTire> {
    let alpha1 = 1.0 / (2.0 * std::f64::consts::PI * (p.r_b * p.r_w).sqrt());
    let t = alpha1 * p.load_n / (2.0 * p.pressure_pa());
    let deflection_m = t + (t * t + p.alpha2 * p.load_n).sqrt();
    let xd = p.xi * deflection_m;
    let chord_sq = 2.0 * p.r_b * xd - xd * xd;
    if chord_sq.is_nan() || chord_sq <= 0.0 {
        return Err(FlatTire {
            xi_deflection_m: xd,
            diameter_m: 2.0 * p.r_b,
        });
    }
    Ok(ContactPatch {
        deflection_m,
        length_m: 2.0 * chord_sq.sqrt(),
        width_m: p.b0 * (1.0 - (-p.psi * deflection_m).exp()),
    })
}

/// Lateral stiffness and mass of the tread block in the contact patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreadBlock {
    /// K_s, which is also the LuGre bristle stiffness σ0 (step 3).
    pub stiffness_n_per_m: f64,
    /// m = ρ a b h.
    pub mass_kg: f64,
}

/// Tread block shear stiffness with the bending correction of Eq. 16 (reconstructed form).
pub(crate) fn tread_block(p: &Params, patch: &ContactPatch) -> TreadBlock {
    TreadBlock {
        stiffness_n_per_m: block_stiffness_n_per_m(p, patch, p.tread_height),
        mass_kg: p.rho * patch.length_m * patch.width_m * p.tread_height,
    }
}

/// Eq. 16 for a block of height `height_m`: K = G b β (1 − 6/(6 + π²β²)), β = a/h.
fn block_stiffness_n_per_m(p: &Params, patch: &ContactPatch, height_m: f64) -> f64 {
    let beta = patch.length_m / height_m;
    let pi2 = std::f64::consts::PI * std::f64::consts::PI;
    p.g_mod * patch.width_m * beta * (1.0 - 6.0 / (6.0 + pi2 * beta * beta))
}

/// The tread block of a worn tyre whose tread is `height_m` high (MODEL.md#the-ageing-tread),
/// `p.tread_height` being the new tyre's h₀. The new tyre's contact lateral compliance 1/K_s0
/// (Eq. 16 at h₀, the paper's) is the carcass and belt's share c = `carcass_share` in series
/// with the tread block's 1 − c; only the block's part follows the height, as Eq. 16 does:
/// 1/K_s(h) = c/K_s0 + (1 − c)/K_t(h), K_t(h) being Eq. 16 at h, so K_s(h₀) = K_s0. Of the mode's
/// mass m₀ = ρ a b h₀ the share μ_b = `belt_mass_share` is belt and carcass, which does not wear,
/// and the rest the tread rubber that is left: m = m₀ (μ_b + (1 − μ_b) h/h₀). At h = h₀ this is
/// the new tyre's tread block exactly, whatever the shares, and with c = 0 and μ_b = 0 it is
/// Eq. 16 at h exactly (the tread alone).
pub(crate) fn worn_tread_block(p: &Params, patch: &ContactPatch, height_m: f64) -> TreadBlock {
    if height_m == p.tread_height {
        return tread_block(p, patch);
    }
    let block = block_stiffness_n_per_m(p, patch, height_m);
    let c = p.carcass_share;
    let stiffness_n_per_m = if c == 0.0 {
        block
    } else {
        let new = block_stiffness_n_per_m(p, patch, p.tread_height);
        1.0 / (c / new + (1.0 - c) / block)
    };
    // The belt and carcass's share of the mode's mass moves with the tread and does not wear.
    let mu = p.belt_mass_share;
    let mass_height_m = if mu == 0.0 {
        height_m
    } else {
        mu * p.tread_height + (1.0 - mu) * height_m
    };
    TreadBlock {
        stiffness_n_per_m,
        mass_kg: p.rho * patch.length_m * patch.width_m * mass_height_m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(p: &Params) -> ContactPatch {
        contact_patch(p).unwrap()
    }

    #[test]
    fn the_new_tyre_is_the_papers_tread_block_bit_for_bit() {
        for c in [0.0, 0.3, 0.5, 0.7, 1.0] {
            for mu in [0.0, 0.2, 0.5, 0.7, 1.0] {
                let p = Params {
                    carcass_share: c,
                    belt_mass_share: mu,
                    ..Params::default()
                };
                let a = patch(&p);
                assert_eq!(
                    worn_tread_block(&p, &a, p.tread_height),
                    tread_block(&p, &a)
                );
            }
        }
    }

    #[test]
    fn the_belt_s_share_of_the_mass_does_not_wear() {
        let h = 0.0086;
        for mu in [0.0, 0.3, 0.7, 1.0] {
            let p = Params {
                belt_mass_share: mu,
                ..Params::default()
            };
            let a = patch(&p);
            let (m0, worn) = (tread_block(&p, &a).mass_kg, worn_tread_block(&p, &a, h));
            let want = mu + (1.0 - mu) * h / p.tread_height;
            assert!((worn.mass_kg / m0 - want).abs() < 1e-14, "{mu}");
            // The stiffness is the carcass's and the block's, whatever the mass.
            let none = worn_tread_block(
                &Params {
                    belt_mass_share: 0.0,
                    ..p
                },
                &a,
                h,
            );
            assert_eq!(worn.stiffness_n_per_m, none.stiffness_n_per_m);
        }
    }

    #[test]
    fn no_carcass_share_is_the_block_alone_at_the_worn_height() {
        let p = Params {
            carcass_share: 0.0,
            belt_mass_share: 0.0,
            ..Params::default()
        };
        let a = patch(&p);
        let h = 0.0086;
        let at_h = Params {
            tread_height: h,
            ..p
        };
        assert_eq!(worn_tread_block(&p, &a, h), tread_block(&at_h, &a));
    }

    #[test]
    fn the_carcass_is_in_series_with_the_worn_block() {
        let p = Params {
            belt_mass_share: 0.0,
            ..Params::default()
        };
        let a = patch(&p);
        let h = 0.0086;
        let k0 = tread_block(&p, &a).stiffness_n_per_m;
        let kt = tread_block(
            &Params {
                tread_height: h,
                ..p
            },
            &a,
        )
        .stiffness_n_per_m;
        let worn = worn_tread_block(&p, &a, h);
        let c = p.carcass_share;
        let want = 1.0 / (c / k0 + (1.0 - c) / kt);
        assert!((worn.stiffness_n_per_m / want - 1.0).abs() < 1e-14);
        // Stiffer than new, softer than the block alone; the mass is the rubber left.
        assert!(k0 < worn.stiffness_n_per_m && worn.stiffness_n_per_m < kt);
        let m0 = tread_block(&p, &a).mass_kg;
        assert!((worn.mass_kg / m0 - h / p.tread_height).abs() < 1e-14);
        // A carcass that takes all the compliance keeps K_s0.
        let rigid = worn_tread_block(
            &Params {
                carcass_share: 1.0,
                ..p
            },
            &a,
            h,
        );
        assert!((rigid.stiffness_n_per_m / k0 - 1.0).abs() < 1e-14);
    }
}
