//! The per-wheel work budget: at most so many RHS evaluations and so much wall time
//! for one wheel's verdict. A wheel that needs more becomes a `failed` row whose reason starts
//! with `budget exceeded (`, so one pathological point cannot stall a whole study.

use std::cell::Cell;
use std::time::Instant;

/// Limits on the work spent on one wheel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelBudget {
    /// Right-hand-side evaluations (variational evaluations count as one). Deterministic: the
    /// same wheel hits it or not on every machine.
    pub max_rhs_evals: u64,
    /// Wall-clock seconds: a safety net far above any normal wheel (which takes milliseconds);
    /// unlike the evaluation count it depends on the machine and its load.
    pub max_wheel_seconds: f64,
}

impl WheelBudget {
    /// Accepted range of `max_rhs_evals`.
    pub const RHS_EVALS_RANGE: (u64, u64) = (100, 1_000_000_000_000);
    /// Accepted range of `max_wheel_seconds`.
    pub const SECONDS_RANGE: (f64, f64) = (1e-3, 86_400.0);

    /// Checks both limits against their accepted ranges; the error names the key as the
    /// study file spells it.
    pub fn check(&self) -> Result<(), BudgetError> {
        let (lo, hi) = Self::RHS_EVALS_RANGE;
        if !(lo..=hi).contains(&self.max_rhs_evals) {
            return Err(BudgetError::RhsEvals(self.max_rhs_evals));
        }
        let (lo, hi) = Self::SECONDS_RANGE;
        let s = self.max_wheel_seconds;
        if !(s.is_finite() && (lo..=hi).contains(&s)) {
            return Err(BudgetError::WheelSeconds(s));
        }
        Ok(())
    }
}

/// A budget limit outside its accepted range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BudgetError {
    /// `max_rhs_evals` outside [`WheelBudget::RHS_EVALS_RANGE`].
    #[error("`max_rhs_evals` {}", self.refusal())]
    RhsEvals(u64),
    /// `max_wheel_seconds` outside [`WheelBudget::SECONDS_RANGE`].
    #[error("`max_wheel_seconds` {}", self.refusal())]
    WheelSeconds(f64),
}

impl BudgetError {
    /// The key as a study file spells it (the command line maps it to its flag).
    pub fn key(&self) -> &'static str {
        match self {
            BudgetError::RhsEvals(_) => "max_rhs_evals",
            BudgetError::WheelSeconds(_) => "max_wheel_seconds",
        }
    }

    /// The refusal after the key's name: "= value is outside the accepted range \[lo, hi\]".
    pub fn refusal(&self) -> String {
        match self {
            BudgetError::RhsEvals(n) => {
                let (lo, hi) = WheelBudget::RHS_EVALS_RANGE;
                format!("= {n} is outside the accepted range [{lo}, {hi}]")
            }
            BudgetError::WheelSeconds(s) => {
                let (lo, hi) = WheelBudget::SECONDS_RANGE;
                format!("= {s} is outside the accepted range [{lo}, {hi}] s")
            }
        }
    }
}

impl Default for WheelBudget {
    /// 20 million evaluations (about 2 s of one core; a limit cycle takes about a thousand, the
    /// slowest envelope fallback of 60 simulated seconds about 2 million) and 60 s of wall time.
    fn default() -> Self {
        WheelBudget {
            max_rhs_evals: 20_000_000,
            max_wheel_seconds: 60.0,
        }
    }
}

/// Counts the work of one wheel against its budget. Integrations take their step limit from
/// [`Meter::max_steps`] and poll [`Meter::out_of_time`] from their step callbacks.
pub struct Meter {
    budget: WheelBudget,
    start: Instant,
    used: Cell<u64>,
    polls: Cell<u32>,
    timed_out: Cell<bool>,
}

impl Meter {
    /// A meter that starts counting now.
    pub fn new(budget: WheelBudget) -> Self {
        Meter {
            budget,
            start: Instant::now(),
            used: Cell::new(0),
            polls: Cell::new(0),
            timed_out: Cell::new(false),
        }
    }

    /// Adds the evaluations of a finished (or failed) integration.
    pub fn charge(&self, rhs_evals: usize) {
        self.used.set(self.used.get() + rhs_evals as u64);
    }

    /// Evaluations spent so far.
    pub fn used(&self) -> u64 {
        self.used.get()
    }

    /// The step limit for the next integration: `cap`, or less where the evaluations left
    /// run out first at `evals_per_step` per step (6 for DOPRI5, 15 for DOP853).
    pub fn max_steps(&self, cap: usize, evals_per_step: usize) -> usize {
        let left = self.budget.max_rhs_evals.saturating_sub(self.used.get());
        cap.min((left / evals_per_step.max(1) as u64) as usize + 1)
    }

    /// Whether the wall-time limit has passed (the clock is read every 64th call).
    pub fn out_of_time(&self) -> bool {
        if self.timed_out.get() {
            return true;
        }
        let n = self.polls.get().wrapping_add(1);
        self.polls.set(n);
        if n % 64 == 1 && self.start.elapsed().as_secs_f64() > self.budget.max_wheel_seconds {
            self.timed_out.set(true);
        }
        self.timed_out.get()
    }

    /// The meter's wall-clock limit, to carry into work that holds no meter: the wear stage's
    /// walks over the tread's life, which read no RHS and may run on other threads.
    pub fn deadline(&self) -> Deadline {
        Deadline {
            start: self.start,
            max_seconds: self.budget.max_wheel_seconds,
        }
    }

    /// `Some(reason)` once either limit is exceeded.
    pub fn exceeded(&self) -> Option<String> {
        let b = &self.budget;
        if self.timed_out.get() || self.start.elapsed().as_secs_f64() > b.max_wheel_seconds {
            return Some(format!(
                "budget exceeded (max_wheel_seconds = {} s; {:.3} s and {} RHS evaluations spent)",
                b.max_wheel_seconds,
                self.start.elapsed().as_secs_f64(),
                self.used.get()
            ));
        }
        // An integration stopped by its step limit has used up all that was left, or all but
        // less than one step (6 evaluations) and its start.
        if self.used.get() + 7 >= b.max_rhs_evals {
            return Some(format!(
                "budget exceeded (max_rhs_evals = {}; {} RHS evaluations spent)",
                b.max_rhs_evals,
                self.used.get()
            ));
        }
        None
    }
}

/// A wheel's wall-clock limit ([`Meter::deadline`]): the same `max_wheel_seconds`, counted from
/// the same start, for work that runs no integration (the wear stage's walks over the tread's
/// life, the calibration band's sets), so that no wheel outlasts its budget silently.
#[derive(Debug, Clone, Copy)]
pub struct Deadline {
    start: Instant,
    max_seconds: f64,
}

impl Deadline {
    /// A deadline that never passes (probes and tests that time nothing).
    pub fn never() -> Self {
        Deadline {
            start: Instant::now(),
            max_seconds: f64::INFINITY,
        }
    }

    /// Whether the limit has passed.
    pub fn passed(&self) -> bool {
        self.start.elapsed().as_secs_f64() > self.max_seconds
    }

    /// The reason a wheel's wear figures are missing once it has: as [`Meter::exceeded`] says
    /// it, naming the stage.
    pub fn reason(&self) -> String {
        format!(
            "budget exceeded (max_wheel_seconds = {} s; {:.3} s spent, in the wear stage)",
            self.max_seconds,
            self.start.elapsed().as_secs_f64()
        )
    }
}

/// Every deadline is equal to every other: when a wheel's work must end is not part of what
/// the work is (a wheel's growth compared with another's compares its physics).
impl PartialEq for Deadline {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}
