//! The loop's accepted steps (MODEL.md#the-long-term-loop): the length of the next step, how
//! finely a lock edge must be placed, and what is kept of each accepted step (the history, the
//! profiles, the first visible polygon, the tread worn out).

use super::*;

/// The step to take from `state` \[m\]: `step_m`, bracketed by a lock `edge` ahead, no further
/// than the run's `total_m`, and (at the last step's `wear_rate_m_per_m`) no further than where
/// the usable tread `usable_m` runs out.
pub(super) fn step_to_take_m(
    step_m: f64,
    state: &RunState,
    total_m: f64,
    usable_m: f64,
    wear_rate_m_per_m: f64,
    edge: &mut Option<(f64, f64)>,
) -> f64 {
    let this_m = bracketed_step_m(step_m, state.distance_m, edge).min(total_m - state.distance_m);
    if wear_rate_m_per_m > 0.0 {
        // The tyre's last step ends where its usable tread runs out (1% and 1 m past at the
        // last step's rate, so that it does).
        let to_out_m = (usable_m - state.worn_m) / wear_rate_m_per_m;
        return this_m.min(1.01 * to_out_m + 1.0);
    }
    this_m
}

/// The next step's length \[m\] after an accepted step whose history is `point` and whose
/// legs wore at `rate` \[m/m\], and the step's mean wear rate \[m/m\].
pub(super) fn step_after(
    point: &HistoryPoint,
    rate: &[f64],
    settings: &LoopSettings,
) -> (f64, f64) {
    let mean = rate.iter().sum::<f64>() / rate.len() as f64;
    let spread = rate.iter().fold(0.0f64, |m, r| m.max((r - mean).abs()));
    let step_m = next_step_m(
        (settings.min_step_km, settings.max_step_km),
        (
            &point.depths_m,
            &point.depth_rate_m_per_m,
            &point.growth_per_m,
        ),
        spread,
    );
    (step_m, mean)
}

/// What the loop keeps of its accepted steps: the history, the profiles (distance \[km\],
/// depths), the first visible polygon, where the tread wore out, and the steps taken and redone.
pub(super) struct LoopRecord {
    pub(super) history: Vec<HistoryPoint>,
    pub(super) profiles: Vec<(f64, Vec<f64>)>,
    pub(super) visible: Option<(u32, f64)>,
    pub(super) worn_out_km: Option<f64>,
    pub(super) steps: usize,
    pub(super) redone: usize,
}

impl LoopRecord {
    /// The record of a run that starts at `state`, its history `start`.
    pub(super) fn new(start: HistoryPoint, state: &RunState) -> Self {
        LoopRecord {
            history: vec![start],
            profiles: vec![(0.0, state.profile.depth_m.clone())],
            visible: None,
            worn_out_km: None,
            steps: 0,
            redone: 0,
        }
    }

    /// Records the step of `this_m` metres from `before` to `after` (`point` its history):
    /// a polygon first visible in it, the tread worn out in it (a polygon visible only later
    /// in the step comes after the tyre's end), and its profile.
    pub(super) fn accept(
        &mut self,
        point: HistoryPoint,
        before: &RunState,
        after: &mut RunState,
        this_m: f64,
        p: &Params,
    ) {
        self.steps += 1;
        let usable_m = p.usable_wear_m();
        let prev_depths = self.history.last().expect("the start").depths_m.clone();
        if self.visible.is_none() {
            let visible_m = p.visible_depth_mm * 1e-3;
            self.visible = crossing(&prev_depths, &point.depths_m, visible_m, before, this_m);
        }
        if after.worn_m >= usable_m {
            let worn_out_km = worn_out_at_km(before, after, usable_m);
            self.worn_out_km = Some(worn_out_km);
            // A polygon that would be visible only later in this step comes after the tyre's
            // end: the tyre is worn out before it.
            if matches!(self.visible, Some((_, km)) if km > worn_out_km) {
                self.visible = None;
            }
        }
        self.history.push(point);
        after.history_len = self.history.len();
        self.profiles
            .push((after.distance_m / 1e3, after.profile.depth_m.clone()));
    }
}

/// Where in the step from `before` to `after` the worn depth reached `usable_m` \[km\] (linear
/// within the step: the even wear's rate moves little over one).
pub(super) fn worn_out_at_km(before: &RunState, after: &RunState, usable_m: f64) -> f64 {
    let (w0, w1) = (before.worn_m, after.worn_m);
    let share = if w1 > w0 {
        ((usable_m - w0) / (w1 - w0)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    (before.distance_m + share * (after.distance_m - before.distance_m)) / 1e3
}

/// The first order whose depth crossed `visible_m` in a step of `step_m` from `before`, and
/// where (exponential interpolation between the depths at the step's ends) \[km\].
pub(super) fn crossing(
    prev: &[f64],
    now: &[f64],
    visible_m: f64,
    before: &RunState,
    step_m: f64,
) -> Option<(u32, f64)> {
    let (n, (d0, d1)) = prev
        .iter()
        .zip(now)
        .enumerate()
        .filter(|(_, (_, d1))| **d1 >= visible_m)
        .max_by(|a, b| (a.1 .1).total_cmp(b.1 .1))?;
    let share = if *d0 > 0.0 && d1 > d0 && *d0 < visible_m {
        (visible_m / d0).ln() / (d1 / d0).ln()
    } else {
        1.0
    };
    Some(((n + 1) as u32, (before.distance_m + share * step_m) / 1e3))
}
