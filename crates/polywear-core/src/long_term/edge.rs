//! Lock edges in the long-term loop (MODEL.md#the-long-term-loop): a step after which a speed's
//! lock flag, or the order it is locked to, changed is redone shorter, so that a tongue is
//! neither jumped over nor entered or left far from where the road would. How short is set by
//! what the lock prints: the edge is placed until misplacing it by a step would change the
//! locked order's depth by less than `EDGE_DEPTH_SHARE` of it (and never finer than Δs_min).
//! A lock at a seed-deep profile that prints slowly (a small φ_s) is placed in a step or two;
//! one that deepens its order fast is bisected down to Δs_min as before.

use super::profile::{harmonics_of, Profile};

/// The lock signature of a step: per speed, locked and to which order (−1 when not locked).
pub(crate) type Signature = Vec<(bool, i64)>;

/// A lock edge is resolved until a step's misplacement of it changes the locked order's depth
/// by less than this share of that depth.
pub(crate) const EDGE_DEPTH_SHARE: f64 = 0.1;

/// The lock signature that a step must not change without being redone: per speed, the lock
/// flag and, where locked, the order it is locked to. (An unlocked ρ drifts on with the tread
/// height and the growing profile; its nearest order changing is not an event to resolve.)
pub(crate) fn signature(rho: &[f64], locked: &[bool]) -> Signature {
    rho.iter()
        .zip(locked)
        .map(|(r, l)| (*l, if *l { r.round() as i64 } else { -1 }))
        .collect()
}

/// What the two steps on either side of a signature change measured.
pub(crate) struct EdgeSides<'a> {
    /// Each speed's share of the distance.
    pub shares: &'a [f64],
    /// The signature before and after the change.
    pub signatures: [&'a Signature; 2],
    /// Each speed's wear rate per cell \[m/m\] before and after.
    pub rates_m_per_m: [Vec<&'a [f64]>; 2],
    /// The profile at the change.
    pub profile: &'a Profile,
    /// The depth below which an order counts as seed-deep, 2R⁰ \[m\].
    pub seed_depth_m: f64,
}

impl EdgeSides<'_> {
    /// The step length \[m\] to which the change must be resolved: for every speed whose
    /// signature changed and each side where it is locked to order n, ε·D_n/(share·dD_n/ds),
    /// dD_n/ds that speed's print on order n (D_n at least the seed's depth); the smallest of
    /// them, at least `min_step_m`. Infinite (or beyond any run) where the lock prints nothing.
    pub fn resolution_m(&self, min_step_m: f64) -> f64 {
        let mut finest = f64::INFINITY;
        for (i, share) in self.shares.iter().enumerate() {
            let [before, after] = self.signatures;
            if before[i] == after[i] {
                continue;
            }
            for side in 0..2 {
                let (locked, order) = self.signatures[side][i];
                if !locked || order < 1 {
                    continue;
                }
                let n = order as usize;
                let print = share * order_rate_m_per_m(self.rates_m_per_m[side][i], n);
                let depth = self.profile.depths_m(n)[n - 1].max(self.seed_depth_m);
                if print > 0.0 {
                    finest = finest.min(EDGE_DEPTH_SHARE * depth / print);
                }
            }
        }
        finest.max(min_step_m)
    }
}

/// |dD_n/ds| \[m/m\] of a wear rate per cell: twice the order-n harmonic of its radius change.
fn order_rate_m_per_m(rate_m_per_m: &[f64], order: usize) -> f64 {
    let mean = rate_m_per_m.iter().sum::<f64>() / rate_m_per_m.len() as f64;
    let radius_rate: Vec<f64> = rate_m_per_m.iter().map(|r| -(r - mean)).collect();
    2.0 * harmonics_of(&radius_rate, order)[order - 1].norm()
}

/// The length of a step from `distance_m` whose rule gives `step_m`: short of where a window
/// saw the signature change (`edge`: that distance and the resolution it needs, cleared once
/// passed), at most half the way there and never under the resolution, so that the redone steps
/// close in on the change as a bisection does instead of stepping over it again at the rule's
/// length.
pub(crate) fn bracketed_step_m(step_m: f64, distance_m: f64, edge: &mut Option<(f64, f64)>) -> f64 {
    match *edge {
        Some((e, resolution_m)) if distance_m < e * (1.0 - 1e-12) => {
            step_m.min((0.5 * (e - distance_m)).max(resolution_m))
        }
        _ => {
            *edge = None;
            step_m
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Short of the distance where a change was seen, a step goes at most half the way there
    /// (never under the resolution); once there, the rule's step again and the edge forgotten.
    #[test]
    fn steps_close_in_on_a_change_as_a_bisection() {
        let mut edge = Some((1000.0, 20.0));
        assert_eq!(bracketed_step_m(500.0, 600.0, &mut edge), 200.0);
        assert_eq!(bracketed_step_m(100.0, 600.0, &mut edge), 100.0);
        assert_eq!(bracketed_step_m(500.0, 990.0, &mut edge), 20.0);
        assert_eq!(edge, Some((1000.0, 20.0)));
        assert_eq!(bracketed_step_m(500.0, 1000.0, &mut edge), 500.0);
        assert_eq!(edge, None);
        assert_eq!(bracketed_step_m(500.0, 600.0, &mut edge), 500.0);
    }

    /// A speed that locks to order 19 and prints dD/ds on it: the edge is resolved to
    /// ε D/(share dD/ds), at least Δs_min; a speed whose signature did not change, or a lock that
    /// prints nothing, asks for nothing.
    #[test]
    fn the_resolution_follows_the_print_of_the_lock() {
        let cells = 1024;
        let theta = |i: usize| (i as f64 + 0.5) * std::f64::consts::TAU / cells as f64;
        // Depth 0.2 mm of order 19, and a print of 1e-9 m/m peak to valley on it.
        let depth: Vec<f64> = (0..cells)
            .map(|i| -0.1e-3 * (19.0 * theta(i)).cos())
            .collect();
        let rate: Vec<f64> = (0..cells)
            .map(|i| 1e-8 - 0.5e-9 * (19.0 * theta(i)).cos())
            .collect();
        let flat = vec![1e-8; cells];
        let profile = Profile { depth_m: depth };
        let (unlocked, locked): (Signature, Signature) = (
            vec![(false, -1), (false, -1)],
            vec![(false, -1), (true, 19)],
        );
        let resolution = |after: &[f64], min_step_m: f64| {
            EdgeSides {
                shares: &[0.5, 0.5],
                signatures: [&unlocked, &locked],
                rates_m_per_m: [vec![&flat, &flat], vec![&flat, after]],
                profile: &profile,
                seed_depth_m: 4e-6,
            }
            .resolution_m(min_step_m)
        };
        // 0.1 × 0.2 mm / (0.5 × 1e-9) = 40 km.
        let r = resolution(&rate, 1.0);
        assert!((r / 40e3 - 1.0).abs() < 1e-6, "{r}");
        assert_eq!(resolution(&rate, 50e3), 50e3);
        let none = resolution(&flat, 20e3);
        assert!(none > 1e9, "{none}");
    }
}
