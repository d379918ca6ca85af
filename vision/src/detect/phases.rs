//! Where a detection's wall time goes, step by step of the pipeline ([`Report::phases`]): the
//! figure a change for speed is measured by, and what the benchmark prints beside its table.
//!
//! [`Report::phases`]: super::Report::phases

use std::time::{Duration, Instant};

/// Wall time of each step of the detector, in the order the steps were first reached; a step
/// reached again (each round's fits, each tile) adds to its time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Phases(Vec<(&'static str, Duration)>);

impl Phases {
    /// The steps and their times, in the order first reached.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, Duration)> + '_ {
        self.0.iter().copied()
    }

    /// The time of every step together.
    pub fn total(&self) -> Duration {
        self.0.iter().map(|&(_, d)| d).sum()
    }

    /// Adds `time` to step `name`, a new step after the others when it was not reached yet.
    pub fn add(&mut self, name: &'static str, time: Duration) {
        match self.0.iter_mut().find(|(n, _)| *n == name) {
            Some((_, d)) => *d += time,
            None => self.0.push((name, time)),
        }
    }

    /// Adds every step of `other` (another tile's, another photograph's).
    pub fn add_all(&mut self, other: &Phases) {
        for (name, time) in other.iter() {
            self.add(name, time);
        }
    }
}

/// A stopwatch that charges the time since its last lap to the step named.
pub(crate) struct Laps<'p> {
    phases: &'p mut Phases,
    last: Instant,
}

impl<'p> Laps<'p> {
    /// Started now.
    pub(crate) fn new(phases: &'p mut Phases) -> Self {
        Laps {
            phases,
            last: Instant::now(),
        }
    }

    /// Charges the time since the last lap (or the start) to `name`.
    pub(crate) fn lap(&mut self, name: &'static str) {
        let now = Instant::now();
        self.phases.add(name, now - self.last);
        self.last = now;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step reached again adds to its time and keeps its place; another photograph's steps
    /// add to the same names, new ones after.
    #[test]
    fn steps_reached_again_add_up_in_the_order_first_reached() {
        let ms = Duration::from_millis;
        let mut p = Phases::default();
        p.add("fits", ms(3));
        p.add("acceptance", ms(1));
        p.add("fits", ms(2));
        let mut q = Phases::default();
        q.add("settle", ms(4));
        q.add("fits", ms(5));
        p.add_all(&q);
        let steps: Vec<_> = p.iter().collect();
        assert_eq!(
            steps,
            [("fits", ms(10)), ("acceptance", ms(1)), ("settle", ms(4))]
        );
        assert_eq!(p.total(), ms(15));
    }

    /// Laps charge the time between them, and nothing is lost between laps: their sum is the
    /// time from the start to the last lap.
    #[test]
    fn laps_charge_the_time_between_them() {
        let mut phases = Phases::default();
        let start = Instant::now();
        let mut laps = Laps::new(&mut phases);
        std::thread::sleep(Duration::from_millis(20));
        laps.lap("first");
        laps.lap("second");
        std::thread::sleep(Duration::from_millis(10));
        laps.lap("first");
        let whole = start.elapsed();
        let first = phases.iter().find(|s| s.0 == "first").unwrap().1;
        assert!(first >= Duration::from_millis(30), "{first:?}");
        assert!(phases.total() <= whole, "{:?} > {whole:?}", phases.total());
        assert_eq!(phases.iter().count(), 2);
    }
}
