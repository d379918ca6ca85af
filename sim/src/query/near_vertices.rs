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
/// the first core), and the edges of the other core they may touch (bit e of
/// `second_edges`: edge e of the second core, for the first's near vertices). Vertices and
/// edges past the eighth always count as near.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NearVertices {
    pub first: u8,
    pub second: u8,
    pub second_edges: u8,
    pub first_edges: u8,
}

impl NearVertices {
    pub const NONE: Self = Self {
        first: 0,
        second: 0,
        second_edges: 0,
        first_edges: 0,
    };
    pub const ALL: Self = Self {
        first: u8::MAX,
        second: u8::MAX,
        second_edges: u8::MAX,
        first_edges: u8::MAX,
    };

    /// The near vertices of a core of `len` vertices (the first core's with `of_first`), in
    /// increasing order: the narrow phase steps from one to the next without looking at the
    /// others.
    #[inline(always)]
    pub fn members(self, of_first: bool, len: usize) -> Members {
        Members::of(if of_first { self.first } else { self.second }, len)
    }

    /// The edges of the other core (of `len` edges) that the near vertices of the first core
    /// (with `of_first`) or of the second may touch, in increasing order.
    #[inline(always)]
    pub fn edges_against(self, of_first: bool, len: usize) -> Members {
        Members::of(
            if of_first {
                self.second_edges
            } else {
                self.first_edges
            },
            len,
        )
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

    /// Counts edge e of the other core as one the first core's near vertices (with
    /// `of_first`) or the second's may touch.
    pub fn insert_edge(&mut self, of_first: bool, e: usize) {
        if e < 8 {
            let bits = if of_first {
                &mut self.second_edges
            } else {
                &mut self.first_edges
            };
            *bits |= 1 << e;
        }
    }
}

/// The vertices of [`NearVertices::members`]: the set bits, then every vertex past the
/// eighth.
#[derive(Clone, Copy, Debug)]
pub struct Members {
    bits: u8,
    past_eighth: usize,
    len: usize,
}

impl Members {
    /// Bit k of `bits` for k below `len` and 8, then every index from 8 to `len`.
    #[inline(always)]
    pub fn of(bits: u8, len: usize) -> Self {
        let within = if len >= 8 { u8::MAX } else { (1u8 << len) - 1 };
        Self {
            bits: bits & within,
            past_eighth: 8,
            len,
        }
    }

    /// Whether every index below `len` is a member.
    #[inline(always)]
    pub fn is_all(&self) -> bool {
        let within = if self.len >= 8 {
            u8::MAX
        } else {
            (1u8 << self.len) - 1
        };
        self.bits == within
    }
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
        with_rounding_margin(gap)
    }
}

/// How much further two grains may travel together before vertex p, looked at every step,
/// can give a sub-contact against edge e of `core` (from vertex a with outward normal n),
/// given its signed distance s = (p - a) . n from the edge line and its distance |p - a|
/// from the edge's first vertex: the edge gives a vertex-edge sub-contact only with s >= 0,
/// and a vertex-vertex one only with |p - a| < cutoff.
///
/// - s rises by at most (3 + cutoff / arm) times the travel (as in [`Verdict::clearance`],
///   where p must be within reach of the core's centre to touch at all);
/// - |p - a| falls by at most the travel.
pub fn edge_clearance(core: &PlacedCore, cutoff: f64, signed: f64, distance: f64) -> f64 {
    let behind = -signed / (3.0 + cutoff / core.arm);
    with_rounding_margin(behind.min(distance - cutoff))
}

/// A hair less than `gap`, 0 when it is not positive (the narrow phase rounds at about
/// 1e-17 m).
fn with_rounding_margin(gap: f64) -> f64 {
    (gap * (1.0 - 1e-9) - 1e-12).max(0.0)
}
