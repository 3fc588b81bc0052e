//! The time left, as the progress bar shows it.
//!
//! A render is a sequence of passes whose shares of the progress bar are fixed guesses (the
//! photon pass's 10 %, the camera pass's 35 %, …), so extrapolating the whole bar's fraction,
//! as a generic progress bar does, is wrong by the factor those guesses are off: the bar sat at
//! "0 % ETA 12m" through a photon pass of a few seconds. Two estimates are exact instead, or
//! become exact as a pass goes on:
//!
//! * under a time budget `T`, the render ends at `T`: the time left is `T − elapsed`;
//! * otherwise, within a pass, work is done at a steady rate (light paths, pixel rows, splat
//!   batches of equal size), so the pass's time left is `t · (1 − f) / f` after `t` seconds in
//!   the pass at fraction `f` of its work. It is shown once the pass has run [`MIN_SECONDS`]
//!   and done [`MIN_FRACTION`] of its work, and is labelled as the pass's, not the render's.
//!
//! A pass starts where the previous one's last report was (passes follow each other), so the
//! time before a pass's first report counts toward it.

use std::time::Duration;

/// A pass's time left is not extrapolated from less than this much of its time (s)…
pub const MIN_SECONDS: f64 = 0.25;
/// …or of its work (the first waves of a pass may include its set-up).
pub const MIN_FRACTION: f64 = 0.005;

/// What the bar says about the time left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeLeft {
    /// Not yet known (the pass has just started).
    Unknown,
    /// Time left in the current pass (s).
    Pass(f64),
    /// Time left in the whole render under its time budget (s).
    Render(f64),
}

impl std::fmt::Display for TimeLeft {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            TimeLeft::Unknown => Ok(()),
            TimeLeft::Pass(s) => write!(f, "{} left in this pass", duration(s)),
            TimeLeft::Render(s) => write!(f, "ETA {}", duration(s)),
        }
    }
}

/// `s` seconds as "7s", "2m05s" or "1h02m".
pub(crate) fn duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, s / 60 % 60),
    }
}

/// Follows the passes of one render from its progress reports.
#[derive(Clone, Debug)]
pub struct EtaClock {
    /// The render's time budget (s), if any.
    budget: Option<f64>,
    pass: &'static str,
    /// When the current pass started, and the time of the last report (s since the render
    /// started).
    pass_start: f64,
    last: f64,
}

impl EtaClock {
    /// A clock for a render with the time budget `budget`.
    pub fn new(budget: Option<Duration>) -> Self {
        Self {
            budget: budget.map(|d| d.as_secs_f64()),
            pass: "",
            pass_start: 0.0,
            last: 0.0,
        }
    }

    /// A report at `now` seconds after the render started: the pass `pass` has done the
    /// fraction `done` of its work. Returns the time left.
    pub fn update(&mut self, now: f64, pass: &'static str, done: f64) -> TimeLeft {
        if pass != self.pass {
            self.pass = pass;
            self.pass_start = self.last;
        }
        self.last = now;
        if let Some(t) = self.budget {
            return TimeLeft::Render((t - now).max(0.0));
        }
        let t = now - self.pass_start;
        if t < MIN_SECONDS || done < MIN_FRACTION {
            return TimeLeft::Unknown;
        }
        TimeLeft::Pass(t * (1.0 - done.min(1.0)) / done)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_steady_pass_is_predicted_exactly_from_its_first_second() {
        // A pass of 20 s after one of 3 s; reports every 0.1 s at a steady rate.
        let mut c = EtaClock::new(None);
        for i in 1..=30 {
            c.update(0.1 * i as f64, "tracing photons", i as f64 / 30.0);
        }
        for i in 1..=200 {
            let now = 3.0 + 0.1 * i as f64;
            let left = c.update(now, "camera pass", i as f64 / 200.0);
            let truth = 23.0 - now;
            match left {
                TimeLeft::Pass(s) => assert!((s - truth).abs() < 1e-9, "{s} vs {truth}"),
                TimeLeft::Unknown => assert!(now - 3.0 < MIN_SECONDS, "unknown at {now}"),
                TimeLeft::Render(_) => panic!("no budget"),
            }
        }
    }

    #[test]
    fn the_first_report_of_a_pass_counts_the_time_since_the_previous_one() {
        // The photon pass reports first after 2 s (its first wave) at 10 %: 18 s are left, not
        // 0 (as if it had started at its first report) nor the whole bar's extrapolation.
        let mut c = EtaClock::new(None);
        assert_eq!(c.update(2.0, "tracing photons", 0.1), TimeLeft::Pass(18.0));
    }

    #[test]
    fn a_new_pass_is_unknown_until_it_has_run_a_little() {
        let mut c = EtaClock::new(None);
        c.update(5.0, "tracing photons", 1.0);
        assert_eq!(c.update(5.1, "camera pass", 0.2), TimeLeft::Unknown);
        assert_eq!(c.update(6.0, "camera pass", 0.002), TimeLeft::Unknown);
        assert_eq!(c.update(7.0, "camera pass", 0.5), TimeLeft::Pass(2.0));
    }

    #[test]
    fn under_a_budget_the_time_left_is_the_budget_left() {
        let mut c = EtaClock::new(Some(Duration::from_secs(10)));
        assert_eq!(
            c.update(0.01, "tracing photons", 0.0),
            TimeLeft::Render(9.99)
        );
        assert_eq!(c.update(4.0, "camera pass", 0.9), TimeLeft::Render(6.0));
        assert_eq!(c.update(11.0, "camera pass", 1.0), TimeLeft::Render(0.0));
    }

    #[test]
    fn durations_read_as_minutes_and_hours() {
        assert_eq!(TimeLeft::Render(7.4).to_string(), "ETA 7s");
        assert_eq!(TimeLeft::Pass(125.0).to_string(), "2m05s left in this pass");
        assert_eq!(TimeLeft::Render(3720.0).to_string(), "ETA 1h02m");
        assert_eq!(TimeLeft::Unknown.to_string(), "");
    }
}
