//! Which vertices of a touching pair can touch at the next steps: the others are certified
//! out of the other core's reach while the two grains travel less than a bound, and the
//! narrow phase skips them (exact: a skipped vertex is one that would have given nothing).

use serde::{Deserialize, Serialize};

use super::PlacedCore;

/// A vertex certified out for less than this many r_i + r_j counts as near, and is looked at
/// every step.
pub const NEAR_WITHIN: f64 = 0.5;

/// A pair whose vertices are all near is looked at in full again after its grains have
/// travelled this many r_i + r_j (to let the set shrink).
pub const RECHECK_AFTER: f64 = 1.0;

/// The vertices of two cores that may touch the other core (bit k of `first`: vertex k of
/// the first core). Vertices past the eighth always count as near.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NearVertices {
    pub first: u8,
    pub second: u8,
}

impl NearVertices {
    pub const NONE: Self = Self {
        first: 0,
        second: 0,
    };
    pub const ALL: Self = Self {
        first: u8::MAX,
        second: u8::MAX,
    };

    /// The near vertices of a core of `len` vertices (the first core's with `of_first`), in
    /// increasing order: the narrow phase steps from one to the next without looking at the
    /// others.
    #[inline(always)]
    pub fn members(self, of_first: bool, len: usize) -> Members {
        let bits = if of_first { self.first } else { self.second };
        let within = if len >= 8 { u8::MAX } else { (1u8 << len) - 1 };
        Members {
            bits: bits & within,
            past_eighth: 8,
            len,
        }
    }

    pub fn insert(&mut self, of_first: bool, k: usize) {
        if k < 8 {
            let bits = if of_first {
                &mut self.first
            } else {
                &mut self.second
            };
            *bits |= 1 << k;
        }
    }
}

/// The vertices of [`NearVertices::members`]: the set bits, then every vertex past the
/// eighth.
pub struct Members {
    bits: u8,
    past_eighth: usize,
    len: usize,
}

impl Iterator for Members {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.bits != 0 {
            let k = self.bits.trailing_zeros() as usize;
            self.bits &= self.bits - 1;
            Some(k)
        } else if self.past_eighth < self.len {
            self.past_eighth += 1;
            Some(self.past_eighth - 1)
        } else {
            None
        }
    }
}

/// How the narrow phase ended for one vertex p against the other core.
#[derive(Clone, Copy, Debug)]
pub enum Verdict {
    /// p lies beyond the core's reach (arm + cutoff) from its centre: |p - c|^2.
    Beyond { centre_squared: f64 },
    /// p lies beyond the cutoff from the line of an edge: its signed distance s.
    BehindEdge { signed: f64 },
    /// p came near the core and was looked at in full.
    Near,
}

impl Verdict {
    /// How much further the two grains may travel together (the sum of their `travel`, each
    /// an upper bound on how far any point of its core has moved) before vertex p can give a
    /// sub-contact against `core`: 0 when it came near.
    ///
    /// - Beyond: the vertex gives nothing while |p - c| >= arm + cutoff, and |p - c| shrinks
    ///   by at most what p and the centre c travel.
    /// - Behind the edge from vertex a with outward normal n: nothing while
    ///   s = (p - a) . n >= cutoff. When the grains move, the change of s is
    ///   (dp - da) . n' + (p - a) . (n' - n), primes for the new placement: the first term
    ///   is at most what p and a travel; n turns by at most the core's travel over its arm;
    ///   and where the second term matters, p is within reach of c at the new placement, so
    ///   |p - a| <= arm + cutoff + arm. s thus falls by at most (3 + cutoff / arm) times the
    ///   travel of the two grains.
    ///
    /// The margin left for rounding is that of the pairs found apart: far above the 1e-17 m
    /// the narrow phase rounds at.
    pub fn clearance(self, core: &PlacedCore, cutoff: f64) -> f64 {
        let gap = match self {
            Verdict::Beyond { centre_squared } => centre_squared.sqrt() - (core.arm + cutoff),
            Verdict::BehindEdge { signed } => (signed - cutoff) / (3.0 + cutoff / core.arm),
            Verdict::Near => return 0.0,
        };
        (gap * (1.0 - 1e-9) - 1e-12).max(0.0)
    }
}
