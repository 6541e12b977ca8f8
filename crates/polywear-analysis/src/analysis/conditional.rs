//! Where the risk lives along each axis: P(outcome | parameter in bin), per variant and wheel
//! (`crate::analysis::outcome::answer` counts the bins).

use std::collections::BTreeMap;

use super::bins::Bins;
use super::counts::{ClassCounts, RiskCounts};
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;

/// Probability in one bin of one axis. The vibration analysis counts rows per class
/// ([`ClassCounts`], the default); the wear analysis counts wheels within a distance
/// ([`crate::analysis::counts::WithinCounts`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BinStat<C = ClassCounts> {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The drawn parameter binned.
    pub axis: ParamId,
    /// Lower edge of the bin (the level itself for levels).
    pub lo: f64,
    /// Upper edge of the bin (the level itself for levels).
    pub hi: f64,
    /// Middle of the bin, where the figure plots it.
    pub mid: f64,
    /// What the bin counts.
    pub counts: C,
}

/// Every bin of `bins` for every (variant, wheel) of `groups` (variant, wheel, bin index of a
/// [`GroupKey::Bin`](crate::analysis::rows::GroupKey::Bin) key, counts), in variant, wheel and bin order, empty bins included; a bin
/// index outside `bins` is left out.
pub(crate) fn bins_of_groups<'a, C: RiskCounts + 'a>(
    groups: impl IntoIterator<Item = (Variant, Wheel, i64, &'a C)>,
    axis: ParamId,
    bins: &Bins,
) -> Vec<BinStat<C>> {
    let mut map: BTreeMap<(Variant, Wheel), Vec<C>> = BTreeMap::new();
    for (variant, wheel, bin, counts) in groups {
        let per_bin = map
            .entry((variant, wheel))
            .or_insert_with(|| vec![C::default(); bins.count()]);
        if let Some(c) = usize::try_from(bin).ok().and_then(|i| per_bin.get_mut(i)) {
            c.merge(counts);
        }
    }
    let mut out = Vec::new();
    for ((variant, wheel), per_bin) in map {
        for (i, counts) in per_bin.into_iter().enumerate() {
            let (lo, hi, mid) = bins.range(i);
            out.push(BinStat {
                variant,
                wheel,
                axis,
                lo,
                hi,
                mid,
                counts,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::counts::WithinCounts;
    use polywear_core::classify::Class;

    #[test]
    fn every_bin_of_every_group_in_order_empty_ones_included_whatever_they_count() {
        let bins = Bins::equal_width(0.0, 3.0, 3);
        let w = WithinCounts {
            within: 1,
            known: 2,
            unknown: 0,
            w_within: 1,
            w_known: 2,
            w2_known: 2,
        };
        let groups = [
            (Variant::SlidingShare, Wheel::Follower, 1, &w),
            (Variant::Paper, Wheel::Driving, 2, &w),
            (Variant::Paper, Wheel::Driving, 2, &w),
            (Variant::Paper, Wheel::Driving, 3, &w),
            (Variant::Paper, Wheel::Driving, -1, &w),
        ];
        let out = bins_of_groups(groups, ParamId::SpeedKmh, &bins);
        let keys: Vec<(Variant, Wheel, f64)> =
            out.iter().map(|b| (b.variant, b.wheel, b.mid)).collect();
        assert_eq!(
            keys,
            [
                (Variant::Paper, Wheel::Driving, 0.5),
                (Variant::Paper, Wheel::Driving, 1.5),
                (Variant::Paper, Wheel::Driving, 2.5),
                (Variant::SlidingShare, Wheel::Follower, 0.5),
                (Variant::SlidingShare, Wheel::Follower, 1.5),
                (Variant::SlidingShare, Wheel::Follower, 2.5),
            ]
        );
        let known: Vec<u64> = out.iter().map(|b| b.counts.known).collect();
        assert_eq!(
            known,
            [0, 0, 4, 0, 2, 0],
            "bins outside the axis are left out"
        );
        let mut c = ClassCounts::default();
        c.add(Class::Bistable, 1);
        c.add(Class::Stable, 3);
        let out = bins_of_groups(
            [(Variant::Paper, Wheel::Follower, 0, &c)],
            ParamId::ToeDeg,
            &bins,
        );
        assert_eq!((out.len(), out[0].counts.p()), (3, 0.25));
    }
}
