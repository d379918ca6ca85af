//! The benchmark's seeds split once and for all into a tuning set and a held-out set: a
//! detector is tuned on the first, and its figures are reported on the second, which it was
//! never run on while being tuned.
//!
//! Seeds are numbered within their set from 1: tuning seed k is the absolute seed k (the seeds
//! earlier versions of the bench used), held-out seed k is 1 000 000 + k. An absolute seed
//! draws the photograph's look, the packing, and the deposit's window.

/// A set of seeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Split {
    /// Seeds 1 to 999 999: for tuning the detector.
    Tuning,
    /// Seeds 1 000 001 to 1 999 999: for the figures reported.
    HeldOut,
}

/// Seeds in each set.
pub const SEEDS_PER_SPLIT: u64 = 999_999;

impl Split {
    pub const ALL: [Split; 2] = [Split::Tuning, Split::HeldOut];

    /// The name the command line and the tables use.
    pub fn name(self) -> &'static str {
        match self {
            Split::Tuning => "tuning",
            Split::HeldOut => "held-out",
        }
    }

    /// The absolute seed of the set's seed `number` (1 to [`SEEDS_PER_SPLIT`]).
    pub fn seed(self, number: u64) -> Result<u64, String> {
        if !(1..=SEEDS_PER_SPLIT).contains(&number) {
            return Err(format!(
                "--seed {number}: seeds are numbered within their split from 1 to {SEEDS_PER_SPLIT}"
            ));
        }
        Ok(match self {
            Split::Tuning => number,
            Split::HeldOut => 1_000_000 + number,
        })
    }

    /// The absolute seeds of the set.
    pub fn seeds(self) -> std::ops::RangeInclusive<u64> {
        let first = self.seed(1).unwrap_or_default();
        first..=first + SEEDS_PER_SPLIT - 1
    }
}

impl std::str::FromStr for Split {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Split::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown split `{s}`: expected tuning or held-out"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tuning_and_held_out_seeds_are_disjoint() {
        let (t, h) = (Split::Tuning.seeds(), Split::HeldOut.seeds());
        assert!(t.end() < h.start() || h.end() < t.start(), "{t:?} {h:?}");
        for number in [1, 2, 500, SEEDS_PER_SPLIT] {
            let (a, b) = (
                Split::Tuning.seed(number).unwrap(),
                Split::HeldOut.seed(number).unwrap(),
            );
            assert!(t.contains(&a) && h.contains(&b) && a != b);
        }
        assert_eq!(Split::Tuning.seed(1), Ok(1));
        for bad in [0, SEEDS_PER_SPLIT + 1] {
            let e = Split::HeldOut.seed(bad).unwrap_err();
            assert!(e.contains("--seed") && e.contains(&bad.to_string()), "{e}");
        }
        assert_eq!("held-out".parse::<Split>(), Ok(Split::HeldOut));
        assert!(
            "test"
                .parse::<Split>()
                .unwrap_err()
                .contains("tuning or held-out")
        );
    }
}
