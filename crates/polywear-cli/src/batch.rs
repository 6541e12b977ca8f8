//! What a long run says and hears: a progress line every few seconds for batch logs (stderr not
//! a terminal, e.g. a Slurm job), and SIGINT/SIGTERM turned into a clean stop.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::common::{CliError, CliResult};
use polywear_core::wording::{duration_text, plain};

/// Progress lines on stderr: `progress: 1216 of 6000 samples (20.3%), 412 samples/s, ETA 12 s`.
pub(crate) struct ProgressLog {
    total: u64,
    /// What is counted, plural: `samples`, `steps`.
    unit: &'static str,
    every: Duration,
    start: Instant,
    done: AtomicU64,
    next: Mutex<Instant>,
}

impl ProgressLog {
    pub(crate) fn new(total: u64, unit: &'static str, every: Duration) -> ProgressLog {
        let start = Instant::now();
        ProgressLog {
            total,
            unit,
            every,
            start,
            done: AtomicU64::new(0),
            next: Mutex::new(start + every),
        }
    }

    /// Counts `n` more; prints a line when the interval has passed (one worker prints,
    /// the others do not wait for it).
    pub(crate) fn add(&self, n: u64) {
        let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
        let now = Instant::now();
        let Ok(mut next) = self.next.try_lock() else {
            return;
        };
        if now < *next {
            return;
        }
        *next = now + self.every;
        eprintln!("{}", self.line(done, now - self.start));
    }

    fn line(&self, done: u64, elapsed: Duration) -> String {
        let rate = done as f64 / elapsed.as_secs_f64().max(1e-9);
        let eta = if rate > 0.0 {
            duration_text((self.total.saturating_sub(done)) as f64 / rate)
        } else {
            "unknown".into()
        };
        let unit = self.unit;
        format!(
            "progress: {done} of {} {unit} ({}%), {} {unit}/s, ETA {eta}",
            self.total,
            plain(100.0 * done as f64 / self.total.max(1) as f64, 3),
            plain(rate, 3)
        )
    }
}

/// Progress of a long run counted in `unit`s: a bar with rate and ETA on a terminal, a
/// [`ProgressLog`] line every `every` in a log (stderr not a terminal), nothing when quiet.
pub(crate) struct Progress {
    bar: ProgressBar,
    log: Option<ProgressLog>,
}

impl Progress {
    pub(crate) fn new(quiet: bool, total: u64, unit: &'static str, every: Duration) -> Progress {
        let log = (!quiet && !std::io::stderr().is_terminal())
            .then(|| ProgressLog::new(total, unit, every));
        let bar = styled_bar(quiet || log.is_some(), total, "", unit, unit);
        Progress { bar, log }
    }

    /// Counts `n` more (from any thread).
    pub(crate) fn add(&self, n: u64) {
        self.bar.inc(n);
        if let Some(log) = &self.log {
            log.add(n);
        }
    }

    /// Clears the bar before the results are printed.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// A bar on stderr (hidden when `hidden`) of `total` things `counted`, with their rate in
/// `rate_unit`/s and the ETA; `head` goes before the bar (`"{msg} "` for a message).
pub(crate) fn styled_bar(
    hidden: bool,
    total: u64,
    head: &str,
    counted: &str,
    rate_unit: &'static str,
) -> ProgressBar {
    let bar = if hidden {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr())
    };
    let template = format!(
        "{{spinner}} [{{elapsed_precise}}] {head}{{wide_bar}} {{pos}}/{{len}} {counted}  {{rate}}  ETA {{eta}}"
    );
    let rate = move |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
        let _ = write!(w, "{:.0} {rate_unit}/s", s.per_sec());
    };
    let style = ProgressStyle::with_template(&template).expect("valid template");
    bar.set_style(style.with_key("rate", rate));
    bar
}

/// SIGINT and SIGTERM while a run is in progress: the first sets a flag the workers read (no new
/// chunk starts, see `RunPlan::run_until`); a second one, or any after [`Interrupt::disarm`],
/// ends the program at once with 128 + the signal number, as the default action would.
pub(crate) struct Interrupt {
    signal: Arc<AtomicUsize>,
    armed: Arc<AtomicBool>,
}

impl Interrupt {
    pub(crate) fn install() -> CliResult<Interrupt> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let signal = Arc::new(AtomicUsize::new(0));
        let armed = Arc::new(AtomicBool::new(false));
        for sig in [SIGINT, SIGTERM] {
            let e = |e: std::io::Error| CliError(format!("cannot handle signal {sig}: {e}"));
            // In this order: a signal that finds `armed` set ends the program; the first one
            // records itself and arms.
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&armed))
                .map_err(e)?;
            signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize).map_err(e)?;
            signal_hook::flag::register(sig, Arc::clone(&armed)).map_err(e)?;
        }
        Ok(Interrupt { signal, armed })
    }

    /// The signal that asked the run to stop, if one did.
    pub(crate) fn signal(&self) -> Option<i32> {
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            s => Some(s as i32),
        }
    }

    /// From now on a signal ends the program at once.
    pub(crate) fn disarm(&self) {
        self.armed.store(true, Ordering::SeqCst);
    }
}

/// For a command that cannot stop midway and resume (optimize's search): the first SIGINT or
/// SIGTERM prints "COMMAND: stopped by SIGNAL; WORDS" and ends the program with 128 + the signal
/// number, as the default action would, but not without a word. A watcher thread reads the flag
/// the handler sets (a handler itself must not print).
pub(crate) fn say_and_exit_on_signal(command: &'static str, words: String) -> CliResult {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let signal = Arc::new(AtomicUsize::new(0));
    for sig in [SIGINT, SIGTERM] {
        signal_hook::flag::register_usize(sig, Arc::clone(&signal), sig as usize)
            .map_err(|e| CliError(format!("cannot handle signal {sig}: {e}")))?;
    }
    std::thread::spawn(move || loop {
        std::thread::sleep(std::time::Duration::from_millis(20));
        let sig = signal.load(Ordering::SeqCst) as i32;
        if sig != 0 {
            eprintln!("\n{command}: stopped by {}; {words}", signal_name(sig));
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// `SIGINT (Ctrl-C)` or `SIGTERM`.
pub(crate) fn signal_name(sig: i32) -> &'static str {
    match sig {
        signal_hook::consts::SIGINT => "SIGINT (Ctrl-C)",
        signal_hook::consts::SIGTERM => "SIGTERM",
        _ => "a signal",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_lines() {
        let log = ProgressLog::new(6000, "samples", Duration::from_secs(5));
        assert_eq!(
            log.line(1500, Duration::from_secs(3)),
            "progress: 1500 of 6000 samples (25%), 500 samples/s, ETA 9 s"
        );
        let log = ProgressLog::new(1800, "steps", Duration::from_secs(5));
        assert_eq!(
            log.line(900, Duration::from_secs(3)),
            "progress: 900 of 1800 steps (50%), 300 steps/s, ETA 3 s"
        );
    }
}
