//! A list of model taps and the weighted bilinear sum over them, the detector's inner loop
//! (nearly all of its time goes into this sum).
//!
//! The taps are stored as columns (u, v, w) padded with weightless taps at the centre to a
//! multiple of [`LANES`], and summed in `LANES` interleaved partial sums combined in a fixed
//! order. With AVX2 the lanes are one vector (four gathers per eight taps instead of 32 scalar
//! loads and their index arithmetic); without it a scalar loop does the same operations in the
//! same order, so a score does not depend on the processor, nor on anything but its inputs.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{__m256, __m256d, __m256i, __m512, __m512i};

use super::plane::Bordered;
#[cfg(test)]
use super::plane::Plane;

/// Taps summed side by side: one AVX2 vector of f32.
pub const LANES: usize = 8;

/// Taps in the grain's frame (u along the long axis, v across) and their weights.
#[derive(Clone, Debug, Default)]
pub struct Taps {
    u: Vec<f32>,
    v: Vec<f32>,
    w: Vec<f32>,
    /// Taps before padding.
    len: usize,
    /// Sum of the weights (what the weighted sum is normalised with when every tap is inside).
    weight: f32,
    /// Largest |u| and |v| of any tap: bounds where a rotated tap can fall.
    reach_u: f32,
    reach_v: f32,
}

/// Rotation and translation of the taps: a tap (u, v) samples at
/// (x + u cos + v sin, y - u sin + v cos), as in [`super::model::Pose`].
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    pub x: f32,
    pub y: f32,
    pub sin: f32,
    pub cos: f32,
}

impl Placement {
    /// Where tap (u, v) samples.
    #[inline]
    fn apply(self, u: f32, v: f32) -> (f32, f32) {
        (
            self.x + u * self.cos + v * self.sin,
            self.y - u * self.sin + v * self.cos,
        )
    }
}

/// A weighted tap sum and its derivatives with respect to the placement: the bilinear
/// interpolation's own slopes at each tap, so one pass over the taps gives the refinement
/// its gradient (d/dphi through each tap's lever arm about the placement's origin).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Slopes {
    /// Sum of weight x max(value, floor), as [`Taps::sum`] gives it.
    pub sum: f32,
    /// Sum of the weights of the taps inside the plane.
    pub weight: f32,
    /// Derivatives of `sum` along x, y (pixels) and the angle (radians).
    pub dx: f32,
    pub dy: f32,
    pub dphi: f32,
}

impl Taps {
    pub fn push(&mut self, u: f32, v: f32, w: f32) {
        // Padding is only ever appended by `seal`.
        debug_assert_eq!(self.u.len(), self.len);
        self.u.push(u);
        self.v.push(v);
        self.w.push(w);
        self.len += 1;
        self.weight += w;
        self.reach_u = self.reach_u.max(u.abs());
        self.reach_v = self.reach_v.max(v.abs());
    }

    /// Pads to whole lanes; call once, after the last `push`.
    pub fn seal(&mut self) {
        while !self.u.len().is_multiple_of(LANES) {
            self.u.push(0.0);
            self.v.push(0.0);
            self.w.push(0.0);
        }
    }

    /// Farthest any tap lies from the placement's origin, whatever its angle (pixels).
    pub fn reach(&self) -> f32 {
        self.reach_u.hypot(self.reach_v)
    }

    /// Whether every tap of a placement samples at least one pixel inside the plane's edge, so
    /// that its four bilinear neighbours exist.
    pub fn inside(&self, at: Placement, plane: &Bordered) -> bool {
        let (s, c) = (at.sin.abs(), at.cos.abs());
        let ex = c * self.reach_u + s * self.reach_v + 1.0;
        let ey = s * self.reach_u + c * self.reach_v + 1.0;
        at.x - ex >= 1.0
            && at.y - ey >= 1.0
            && at.x + ex + 1.0 < plane.width as f32
            && at.y + ey + 1.0 < plane.height as f32
    }

    /// Sums of weight x max(value, floor) and of the weights over the taps that fall inside
    /// the plane (values bilinear, pixel centres at integer + 0.5).
    pub fn sum(&self, at: Placement, plane: &Bordered, floor: f32) -> (f32, f32) {
        if self.len == 0 {
            return (0.0, 0.0);
        }
        if !self.inside(at, plane) {
            return self.sum_near_edge(at, plane, floor);
        }
        let mut lanes = [0.0f32; LANES];
        self.accumulate_inside(at, plane, floor, &mut lanes, 0..self.u.len());
        (combine(lanes), self.weight)
    }

    /// [`Taps::sum`] and its derivatives with respect to the placement. Where a tap's value
    /// is below `floor` it counts as the floor, which does not move: no slope.
    pub fn sum_with_slopes(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        if self.len == 0 {
            return Slopes::default();
        }
        if !self.inside(at, plane) {
            return self.slopes_near_edge(at, plane, floor);
        }
        #[cfg(target_arch = "x86_64")]
        if has_avx512() {
            // SAFETY: AVX-512 F and DQ are present and the placement inside the plane.
            return unsafe { self.slopes_inside_avx512(at, plane, floor) };
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: AVX2 is present and the placement inside the plane.
            return unsafe { self.slopes_inside_avx2(at, plane, floor) };
        }
        self.slopes_inside_scalar(at, plane, floor)
    }

    /// The slope sums one tap at a time, in the AVX2 path's operations and order.
    fn slopes_inside_scalar(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        let mut lanes = SlopeLanes::default();
        for k in 0..self.u.len() {
            let (u, v, w) = (self.u[k], self.v[k], self.w[k]);
            let (x, y) = at.apply(u, v);
            let ([a, b, d, e], (tx, ty)) = corners_inside(plane, x, y);
            let (value, gx, gy) = blend_slopes(a, b, d, e, tx, ty);
            lanes.add(k % LANES, w, (value, gx, gy), (x - at.x, y - at.y), floor);
        }
        lanes.slopes(Some(self.weight))
    }

    /// # Safety
    /// AVX2 must be present and the placement inside the plane ([`Taps::inside`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn slopes_inside_avx2(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        let mut acc = SlopeLanesX8::new(at, floor);
        // SAFETY: as the caller's.
        unsafe { self.slopes_inside_avx2_from(at, plane, &mut acc, 0) };
        acc.slopes(Some(self.weight))
    }

    /// The slope sums of taps `start..` (whole lanes) added to `acc`.
    ///
    /// # Safety
    /// As [`Taps::slopes_inside_avx2`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn slopes_inside_avx2_from(
        &self,
        at: Placement,
        plane: &Bordered,
        acc: &mut SlopeLanesX8,
        start: usize,
    ) {
        use std::arch::x86_64::*;
        let width = plane.stride as i32;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let at = PlacementX8::new(at);
        let half = _mm256_set1_ps(0.5);
        let stride = _mm256_set1_epi32(width);
        for k in (start..self.u.len()).step_by(LANES) {
            // SAFETY: k is a whole lane of the padded columns (`seal`).
            let (x, y, w) = unsafe { at.taps(self, k) };
            let (fx, fy) = (_mm256_sub_ps(x, half), _mm256_sub_ps(y, half));
            let (c, r) = (_mm256_cvttps_epi32(fx), _mm256_cvttps_epi32(fy));
            let tx = _mm256_sub_ps(fx, _mm256_cvtepi32_ps(c));
            let ty = _mm256_sub_ps(fy, _mm256_cvtepi32_ps(r));
            let i = _mm256_add_epi32(_mm256_mullo_epi32(r, stride), c);
            // SAFETY: `inside` keeps (c, r) and (c + 1, r + 1) in the plane.
            let (value, gx, gy) = unsafe { gather_bilinear_slopes(data, below, i, tx, ty) };
            acc.add(w, value, gx, gy, x, y);
        }
    }

    /// [`Taps::slopes_inside_avx2`] sixteen taps at a time: the same operations on each tap,
    /// and each group of eight added to the eight lanes in tap order, so the sums agree to
    /// the bit.
    ///
    /// # Safety
    /// AVX-512 F and DQ must be present and the placement inside the plane
    /// ([`Taps::inside`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx2")]
    unsafe fn slopes_inside_avx512(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        use std::arch::x86_64::*;
        let width = plane.stride as i32;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let mut acc = SlopeLanesX8::new(at, floor);
        let at16 = PlacementX16::new(at);
        let half = _mm512_set1_ps(0.5);
        let stride = _mm512_set1_epi32(width);
        let floor16 = _mm512_set1_ps(floor);
        let n = self.u.len();
        let mut k = 0;
        while k + 2 * LANES <= n {
            // SAFETY: k + 16 taps lie inside the padded columns.
            let (x, y, w) = unsafe { at16.taps(self, k) };
            let (fx, fy) = (_mm512_sub_ps(x, half), _mm512_sub_ps(y, half));
            let (c, r) = (_mm512_cvttps_epi32(fx), _mm512_cvttps_epi32(fy));
            let tx = _mm512_sub_ps(fx, _mm512_cvtepi32_ps(c));
            let ty = _mm512_sub_ps(fy, _mm512_cvtepi32_ps(r));
            let i = _mm512_add_epi32(_mm512_mullo_epi32(r, stride), c);
            // SAFETY: `inside` keeps (c, r) and (c + 1, r + 1) in the plane.
            let (value, gx, gy) = unsafe { gather_bilinear_slopes_x16(data, below, i, tx, ty) };
            add_slopes_x16(&mut acc, &at16, floor16, w, (value, gx, gy), (x, y));
            k += 2 * LANES;
        }
        // SAFETY: as this function's.
        unsafe { self.slopes_inside_avx2_from(at, plane, &mut acc, k) };
        acc.slopes(Some(self.weight))
    }

    /// The slope sums of a placement near or beyond the edge: taps outside count for
    /// nothing, neighbours beyond the edge are clamped onto it (as [`Taps::sum`] does).
    fn slopes_near_edge(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        #[cfg(target_arch = "x86_64")]
        if has_avx512() {
            // SAFETY: AVX-512 F and DQ are present.
            return unsafe { self.slopes_near_edge_avx512(at, plane, floor) };
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: AVX2 is present.
            return unsafe { self.slopes_near_edge_avx2(at, plane, floor) };
        }
        self.slopes_near_edge_scalar(at, plane, floor)
    }

    /// [`Taps::slopes_near_edge`] one tap at a time, in the AVX2 path's operations and order.
    fn slopes_near_edge_scalar(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        let mut lanes = SlopeLanes::default();
        for (k, ((&u, &v), &w)) in self.u.iter().zip(&self.v).zip(&self.w).enumerate() {
            let (x, y) = at.apply(u, v);
            let seen = x >= 0.0 && y >= 0.0 && x < plane.width as f32 && y < plane.height as f32;
            let w = if seen { w } else { 0.0 };
            let ([a, b, d, e], (tx, ty)) = corners_bordered(plane, x, y);
            let (value, gx, gy) = blend_slopes(a, b, d, e, tx, ty);
            lanes.add(k % LANES, w, (value, gx, gy), (x - at.x, y - at.y), floor);
        }
        lanes.slopes(None)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn slopes_near_edge_avx2(&self, at: Placement, plane: &Bordered, floor: f32) -> Slopes {
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let mut acc = SlopeLanesX8::new(at, floor);
        let at = PlacementX8::new(at);
        let edge = EdgeX8::new(plane);
        for k in (0..self.u.len()).step_by(LANES) {
            // SAFETY: k is a whole lane of the padded columns (`seal`).
            let (x, y, w) = unsafe { at.taps(self, k) };
            let (w, i, tx, ty) = edge.lookup(x, y, w);
            // SAFETY: every index is clamped into the bordered plane.
            let (value, gx, gy) = unsafe { gather_bilinear_slopes(data, below, i, tx, ty) };
            acc.add(w, value, gx, gy, x, y);
        }
        acc.slopes(None)
    }

    /// [`Taps::slopes_near_edge_avx2`] sixteen taps at a time, each group of eight added to
    /// the lanes in tap order (the same sums to the bit).
    ///
    /// # Safety
    /// AVX-512 F and DQ must be present.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx2")]
    unsafe fn slopes_near_edge_avx512(
        &self,
        at: Placement,
        plane: &Bordered,
        floor: f32,
    ) -> Slopes {
        use std::arch::x86_64::*;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let mut acc = SlopeLanesX8::new(at, floor);
        let at16 = PlacementX16::new(at);
        let at8 = PlacementX8::new(at);
        let edge = EdgeX16::new(plane);
        let edge8 = EdgeX8::new(plane);
        let floor16 = _mm512_set1_ps(floor);
        let n = self.u.len();
        let mut k = 0;
        while k + 2 * LANES <= n {
            // SAFETY: k + 16 taps lie inside the padded columns.
            let (x, y, w) = unsafe { at16.taps(self, k) };
            let (w, i, tx, ty) = edge.lookup(x, y, w);
            // SAFETY: every index is clamped into the bordered plane.
            let (value, gx, gy) = unsafe { gather_bilinear_slopes_x16(data, below, i, tx, ty) };
            add_slopes_x16(&mut acc, &at16, floor16, w, (value, gx, gy), (x, y));
            k += 2 * LANES;
        }
        if k < n {
            // SAFETY: k is the last whole lane of the padded columns.
            let (x, y, w) = unsafe { at8.taps(self, k) };
            let (w, i, tx, ty) = edge8.lookup(x, y, w);
            // SAFETY: every index is clamped into the bordered plane.
            let (value, gx, gy) = unsafe { gather_bilinear_slopes(data, below, i, tx, ty) };
            acc.add(w, value, gx, gy, x, y);
        }
        acc.slopes(None)
    }

    /// Padded taps (a whole number of lanes).
    pub fn padded_len(&self) -> usize {
        self.u.len()
    }

    /// Sum of the weights.
    pub fn weight(&self) -> f32 {
        self.weight
    }

    /// Sum of the weights of `taps` (a range of whole lanes).
    pub fn weight_of(&self, taps: std::ops::Range<usize>) -> f32 {
        self.w[taps].iter().sum()
    }

    /// Adds taps `taps` (a range of whole lanes) of an inside placement (see [`Taps::inside`])
    /// to the lanes' partial sums: summing a list range after range gives the same lanes, to
    /// the bit, as summing it at once, and [`Taps::lanes_total`] the sum [`Taps::sum`] gives.
    pub fn accumulate_inside(
        &self,
        at: Placement,
        plane: &Bordered,
        floor: f32,
        lanes: &mut [f32; LANES],
        taps: std::ops::Range<usize>,
    ) {
        assert!(
            taps.start.is_multiple_of(LANES)
                && taps.end.is_multiple_of(LANES)
                && taps.end <= self.u.len(),
            "tap ranges are whole lanes of the padded columns"
        );
        assert!(
            plane.data.len() <= i32::MAX as usize,
            "plane too large for 32-bit tap indices"
        );
        debug_assert!(self.inside(at, plane));
        #[cfg(target_arch = "x86_64")]
        if taps.len() >= WIDE_ENOUGH && has_avx512() {
            // SAFETY: AVX-512 F and DQ are present, the range is whole lanes of the columns,
            // and the caller keeps every bilinear neighbour in the plane (`inside`).
            unsafe { self.accumulate_inside_avx512(at, plane, floor, lanes, taps) };
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: AVX2 is present, the range is whole lanes of the columns, and the caller
            // keeps every bilinear neighbour in the plane (`inside`).
            unsafe { self.accumulate_inside_avx2(at, plane, floor, lanes, taps) };
            return;
        }
        self.accumulate_inside_scalar(at, plane, floor, lanes, taps);
    }

    /// The lanes' partial sums combined (in the fixed order every path uses).
    pub fn lanes_total(lanes: [f32; LANES]) -> f32 {
        combine(lanes)
    }

    /// The lane-interleaved sum, one tap at a time (the AVX2 path's operations, in its order).
    fn accumulate_inside_scalar(
        &self,
        at: Placement,
        plane: &Bordered,
        floor: f32,
        lanes: &mut [f32; LANES],
        taps: std::ops::Range<usize>,
    ) {
        for k in taps {
            let (u, v, w) = (self.u[k], self.v[k], self.w[k]);
            let (x, y) = at.apply(u, v);
            let ([a, b, d, e], (tx, ty)) = corners_inside(plane, x, y);
            lanes[k % LANES] += w * blend(a, b, d, e, tx, ty).max(floor);
        }
    }

    #[cfg(test)]
    fn sum_inside_scalar(&self, at: Placement, plane: &Bordered, floor: f32) -> f32 {
        let mut lanes = [0.0f32; LANES];
        self.accumulate_inside_scalar(at, plane, floor, &mut lanes, 0..self.u.len());
        combine(lanes)
    }

    #[cfg(all(test, target_arch = "x86_64"))]
    unsafe fn sum_inside_avx2(&self, at: Placement, plane: &Bordered, floor: f32) -> f32 {
        let mut lanes = [0.0f32; LANES];
        // SAFETY: the caller checks AVX2 and `inside`.
        unsafe { self.accumulate_inside_avx2(at, plane, floor, &mut lanes, 0..self.u.len()) };
        combine(lanes)
    }

    /// # Safety
    /// AVX2 must be present, `taps` whole lanes of the padded columns, and the placement
    /// inside the plane ([`Taps::inside`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn accumulate_inside_avx2(
        &self,
        at: Placement,
        plane: &Bordered,
        floor: f32,
        lanes: &mut [f32; LANES],
        taps: std::ops::Range<usize>,
    ) {
        use std::arch::x86_64::*;
        let width = plane.stride as i32;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let at = PlacementX8::new(at);
        let half = _mm256_set1_ps(0.5);
        let floor = _mm256_set1_ps(floor);
        let stride = _mm256_set1_epi32(width);
        // SAFETY: `lanes` holds exactly one vector.
        let mut acc = unsafe { _mm256_loadu_ps(lanes.as_ptr()) };
        for k in taps.step_by(LANES) {
            // SAFETY: k is a whole lane of the padded columns (`seal`, and the caller).
            let (x, y, w) = unsafe { at.taps(self, k) };
            let (fx, fy) = (_mm256_sub_ps(x, half), _mm256_sub_ps(y, half));
            let (c, r) = (_mm256_cvttps_epi32(fx), _mm256_cvttps_epi32(fy));
            let tx = _mm256_sub_ps(fx, _mm256_cvtepi32_ps(c));
            let ty = _mm256_sub_ps(fy, _mm256_cvtepi32_ps(r));
            let i = _mm256_add_epi32(_mm256_mullo_epi32(r, stride), c);
            // SAFETY: `inside` keeps (c, r) and (c + 1, r + 1) in the plane.
            let value = unsafe { gather_bilinear(data, below, i, tx, ty) };
            // max(value, floor) as in f32::max for the non-NaN values a plane holds.
            acc = _mm256_add_ps(acc, _mm256_mul_ps(w, _mm256_max_ps(value, floor)));
        }
        // SAFETY: `lanes` holds exactly one vector.
        unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), acc) };
    }

    /// [`Taps::accumulate_inside_avx2`] sixteen taps at a time: the same operations on each
    /// tap, and each group of eight added to the lanes in tap order, so the lanes agree to
    /// the bit.
    ///
    /// # Safety
    /// AVX-512 F and DQ must be present, `taps` whole lanes of the padded columns, and the
    /// placement inside the plane ([`Taps::inside`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx2")]
    unsafe fn accumulate_inside_avx512(
        &self,
        at: Placement,
        plane: &Bordered,
        floor: f32,
        lanes: &mut [f32; LANES],
        taps: std::ops::Range<usize>,
    ) {
        use std::arch::x86_64::*;
        let width = plane.stride as i32;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let at16 = PlacementX16::new(at);
        let half = _mm512_set1_ps(0.5);
        let floor16 = _mm512_set1_ps(floor);
        let stride = _mm512_set1_epi32(width);
        // SAFETY: `lanes` holds exactly one vector.
        let mut acc = unsafe { _mm256_loadu_ps(lanes.as_ptr()) };
        let mut k = taps.start;
        while k + 2 * LANES <= taps.end {
            // SAFETY: k + 16 taps lie inside the range, whole lanes of the padded columns.
            let (x, y, w) = unsafe { at16.taps(self, k) };
            let (fx, fy) = (_mm512_sub_ps(x, half), _mm512_sub_ps(y, half));
            let (c, r) = (_mm512_cvttps_epi32(fx), _mm512_cvttps_epi32(fy));
            let tx = _mm512_sub_ps(fx, _mm512_cvtepi32_ps(c));
            let ty = _mm512_sub_ps(fy, _mm512_cvtepi32_ps(r));
            let i = _mm512_add_epi32(_mm512_mullo_epi32(r, stride), c);
            // SAFETY: `inside` keeps (c, r) and (c + 1, r + 1) in the plane.
            let (a, b, d, e) = unsafe { gather_corners_x16(data, below, i) };
            let value = blend_x16(a, b, d, e, tx, ty);
            let terms = _mm512_mul_ps(w, _mm512_max_ps(value, floor16));
            acc = _mm256_add_ps(acc, _mm512_castps512_ps256(terms));
            acc = _mm256_add_ps(acc, _mm512_extractf32x8_ps::<1>(terms));
            k += 2 * LANES;
        }
        // SAFETY: `lanes` holds exactly one vector.
        unsafe { _mm256_storeu_ps(lanes.as_mut_ptr(), acc) };
        if k < taps.end {
            // SAFETY: as this function's; AVX2 comes with AVX-512.
            unsafe { self.accumulate_inside_avx2(at, plane, floor, lanes, k..taps.end) };
        }
    }

    /// Taps near or beyond the edge (a sixth of the poses on a full-width frame): taps
    /// outside the plane count for nothing, neighbours beyond the edge are clamped onto it.
    fn sum_near_edge(&self, at: Placement, plane: &Bordered, floor: f32) -> (f32, f32) {
        #[cfg(target_arch = "x86_64")]
        if self.u.len() >= WIDE_ENOUGH && has_avx512() {
            // SAFETY: AVX-512 F and DQ are present.
            return unsafe { self.sum_near_edge_avx512(at, plane, floor) };
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: AVX2 is present.
            return unsafe { self.sum_near_edge_avx2(at, plane, floor) };
        }
        self.sum_near_edge_scalar(at, plane, floor)
    }

    fn sum_near_edge_scalar(&self, at: Placement, plane: &Bordered, floor: f32) -> (f32, f32) {
        let (mut sums, mut weights) = ([0.0f32; LANES], [0.0f32; LANES]);
        for (k, ((&u, &v), &w)) in self.u.iter().zip(&self.v).zip(&self.w).enumerate() {
            let (x, y) = at.apply(u, v);
            let seen = x >= 0.0 && y >= 0.0 && x < plane.width as f32 && y < plane.height as f32;
            let w = if seen { w } else { 0.0 };
            sums[k % LANES] += w * bilinear_bordered(plane, x, y).max(floor);
            weights[k % LANES] += w;
        }
        (combine(sums), combine(weights))
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sum_near_edge_avx2(&self, at: Placement, plane: &Bordered, floor: f32) -> (f32, f32) {
        use std::arch::x86_64::*;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let at = PlacementX8::new(at);
        let edge = EdgeX8::new(plane);
        let floor = _mm256_set1_ps(floor);
        let (mut acc, mut acc_w) = (_mm256_setzero_ps(), _mm256_setzero_ps());
        for k in (0..self.u.len()).step_by(LANES) {
            // SAFETY: k is a whole lane of the padded columns (`seal`).
            let (x, y, w) = unsafe { at.taps(self, k) };
            let (w, i, tx, ty) = edge.lookup(x, y, w);
            // SAFETY: every index is clamped into the bordered plane.
            let value = unsafe { gather_bilinear(data, below, i, tx, ty) };
            acc = _mm256_add_ps(acc, _mm256_mul_ps(w, _mm256_max_ps(value, floor)));
            acc_w = _mm256_add_ps(acc_w, w);
        }
        let (mut sums, mut weights) = ([0.0f32; LANES], [0.0f32; LANES]);
        // SAFETY: each array holds exactly one vector.
        unsafe {
            _mm256_storeu_ps(sums.as_mut_ptr(), acc);
            _mm256_storeu_ps(weights.as_mut_ptr(), acc_w);
        }
        (combine(sums), combine(weights))
    }
}

impl Taps {
    /// [`Taps::sum_near_edge_avx2`] sixteen taps at a time, each group of eight added to the
    /// lanes in tap order (the same sums to the bit).
    ///
    /// # Safety
    /// AVX-512 F and DQ must be present.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512dq,avx2")]
    unsafe fn sum_near_edge_avx512(
        &self,
        at: Placement,
        plane: &Bordered,
        floor: f32,
    ) -> (f32, f32) {
        use std::arch::x86_64::*;
        // SAFETY: pixel (0, 0) of the plane and the row below it lie inside the border.
        let data = unsafe { plane.data.as_ptr().add(plane.stride + 1) };
        let below = unsafe { data.add(plane.stride) };
        let at16 = PlacementX16::new(at);
        let at8 = PlacementX8::new(at);
        let edge = EdgeX16::new(plane);
        let edge8 = EdgeX8::new(plane);
        let floor16 = _mm512_set1_ps(floor);
        let (mut acc, mut acc_w) = (_mm256_setzero_ps(), _mm256_setzero_ps());
        let n = self.u.len();
        let mut k = 0;
        while k + 2 * LANES <= n {
            // SAFETY: k + 16 taps lie inside the padded columns.
            let (x, y, w) = unsafe { at16.taps(self, k) };
            let (w, i, tx, ty) = edge.lookup(x, y, w);
            // SAFETY: every index is clamped into the bordered plane.
            let (a, b, d, e) = unsafe { gather_corners_x16(data, below, i) };
            let value = blend_x16(a, b, d, e, tx, ty);
            let terms = _mm512_mul_ps(w, _mm512_max_ps(value, floor16));
            acc = _mm256_add_ps(acc, _mm512_castps512_ps256(terms));
            acc = _mm256_add_ps(acc, _mm512_extractf32x8_ps::<1>(terms));
            acc_w = _mm256_add_ps(acc_w, _mm512_castps512_ps256(w));
            acc_w = _mm256_add_ps(acc_w, _mm512_extractf32x8_ps::<1>(w));
            k += 2 * LANES;
        }
        if k < n {
            // SAFETY: k is the last whole lane of the padded columns.
            let (x, y, w) = unsafe { at8.taps(self, k) };
            let (w, i, tx, ty) = edge8.lookup(x, y, w);
            // SAFETY: every index is clamped into the bordered plane.
            let value = unsafe { gather_bilinear(data, below, i, tx, ty) };
            acc = _mm256_add_ps(
                acc,
                _mm256_mul_ps(w, _mm256_max_ps(value, _mm256_set1_ps(floor))),
            );
            acc_w = _mm256_add_ps(acc_w, w);
        }
        let (mut sums, mut weights) = ([0.0f32; LANES], [0.0f32; LANES]);
        // SAFETY: each array holds exactly one vector.
        unsafe {
            _mm256_storeu_ps(sums.as_mut_ptr(), acc);
            _mm256_storeu_ps(weights.as_mut_ptr(), acc_w);
        }
        (combine(sums), combine(weights))
    }
}

/// [`EdgeX8`] on sixteen lanes.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct EdgeX16 {
    width: __m512,
    height: __m512,
    stride: __m512i,
    last_column: __m512i,
    last_row: __m512i,
}

#[cfg(target_arch = "x86_64")]
impl EdgeX16 {
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn new(plane: &Bordered) -> Self {
        use std::arch::x86_64::*;
        Self {
            width: _mm512_set1_ps(plane.width as f32),
            height: _mm512_set1_ps(plane.height as f32),
            stride: _mm512_set1_epi32(plane.stride as i32),
            last_column: _mm512_set1_epi32(plane.width as i32 - 1),
            last_row: _mm512_set1_epi32(plane.height as i32 - 1),
        }
    }

    /// [`EdgeX8::lookup`], the same operations: a floor is a rounding towards minus
    /// infinity, and a weight not seen is zeroed (+0, as the mask's `and` gives).
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn lookup(self, x: __m512, y: __m512, w: __m512) -> (__m512, __m512i, __m512, __m512) {
        use std::arch::x86_64::*;
        let zero = _mm512_setzero_ps();
        let half = _mm512_set1_ps(0.5);
        let seen = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(x, zero)
            & _mm512_cmp_ps_mask::<_CMP_GE_OQ>(y, zero)
            & _mm512_cmp_ps_mask::<_CMP_LT_OQ>(x, self.width)
            & _mm512_cmp_ps_mask::<_CMP_LT_OQ>(y, self.height);
        let w = _mm512_maskz_mov_ps(seen, w);
        let (fx, fy) = (_mm512_sub_ps(x, half), _mm512_sub_ps(y, half));
        const DOWN: i32 = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
        let (cf, rf) = (
            _mm512_roundscale_ps::<DOWN>(fx),
            _mm512_roundscale_ps::<DOWN>(fy),
        );
        let (tx, ty) = (_mm512_sub_ps(fx, cf), _mm512_sub_ps(fy, rf));
        let border = _mm512_set1_epi32(-1);
        let clamp = |i: __m512i, last: __m512i| _mm512_min_epi32(_mm512_max_epi32(i, border), last);
        let c = clamp(_mm512_cvttps_epi32(cf), self.last_column);
        let r = clamp(_mm512_cvttps_epi32(rf), self.last_row);
        (
            w,
            _mm512_add_epi32(_mm512_mullo_epi32(r, self.stride), c),
            tx,
            ty,
        )
    }
}

/// [`blend_x8`] on sixteen lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn blend_x16(a: __m512, b: __m512, d: __m512, e: __m512, tx: __m512, ty: __m512) -> __m512 {
    use std::arch::x86_64::*;
    let top = _mm512_add_ps(a, _mm512_mul_ps(tx, _mm512_sub_ps(b, a)));
    let bottom = _mm512_add_ps(d, _mm512_mul_ps(tx, _mm512_sub_ps(e, d)));
    _mm512_add_ps(top, _mm512_mul_ps(ty, _mm512_sub_ps(bottom, top)))
}

/// [`gather_bilinear_slopes`] for sixteen taps.
///
/// # Safety
/// As [`gather_bilinear`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn gather_bilinear_slopes_x16(
    data: *const f32,
    below: *const f32,
    i: __m512i,
    tx: __m512,
    ty: __m512,
) -> (__m512, __m512, __m512) {
    use std::arch::x86_64::*;
    // SAFETY: as the caller's.
    let (a, b, d, e) = unsafe { gather_corners_x16(data, below, i) };
    let (upper, lower) = (_mm512_sub_ps(b, a), _mm512_sub_ps(e, d));
    let top = _mm512_add_ps(a, _mm512_mul_ps(tx, upper));
    let bottom = _mm512_add_ps(d, _mm512_mul_ps(tx, lower));
    let gy = _mm512_sub_ps(bottom, top);
    let value = _mm512_add_ps(top, _mm512_mul_ps(ty, gy));
    let gx = _mm512_add_ps(upper, _mm512_mul_ps(ty, _mm512_sub_ps(lower, upper)));
    (value, gx, gy)
}

/// [`SlopeLanesX8::add`]'s terms for sixteen taps, added to its lanes eight at a time in
/// tap order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx2")]
#[inline]
fn add_slopes_x16(
    acc: &mut SlopeLanesX8,
    at: &PlacementX16,
    floor: __m512,
    w: __m512,
    (value, gx, gy): (__m512, __m512, __m512),
    (x, y): (__m512, __m512),
) {
    use std::arch::x86_64::*;
    let sum = _mm512_mul_ps(w, _mm512_max_ps(value, floor));
    let wm = _mm512_maskz_mov_ps(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(value, floor), w);
    let (wx, wy) = (_mm512_mul_ps(wm, gx), _mm512_mul_ps(wm, gy));
    let lever = _mm512_sub_ps(
        _mm512_mul_ps(wx, _mm512_sub_ps(y, at.y)),
        _mm512_mul_ps(wy, _mm512_sub_ps(x, at.x)),
    );
    for (slot, terms) in [(0, sum), (4, w), (1, wx), (2, wy), (3, lever)] {
        let a = &mut acc.acc[slot];
        *a = _mm256_add_ps(*a, _mm512_castps512_ps256(terms));
        *a = _mm256_add_ps(*a, _mm512_extractf32x8_ps::<1>(terms));
    }
}

/// A [`Placement`] broadcast to eight lanes.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct PlacementX8 {
    x: __m256,
    y: __m256,
    sin: __m256,
    cos: __m256,
}

#[cfg(target_arch = "x86_64")]
impl PlacementX8 {
    #[target_feature(enable = "avx2")]
    #[inline]
    fn new(at: Placement) -> Self {
        use std::arch::x86_64::*;
        Self {
            x: _mm256_set1_ps(at.x),
            y: _mm256_set1_ps(at.y),
            sin: _mm256_set1_ps(at.sin),
            cos: _mm256_set1_ps(at.cos),
        }
    }

    /// Where taps k to k + 7 sample ([`Placement::apply`], the same operations), and their
    /// weights.
    ///
    /// # Safety
    /// k + 8 must not exceed the padded columns' length.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn taps(self, taps: &Taps, k: usize) -> (__m256, __m256, __m256) {
        use std::arch::x86_64::*;
        // SAFETY: the caller keeps the eight loads inside the columns.
        let (u, v, w) = unsafe {
            (
                _mm256_loadu_ps(taps.u.as_ptr().add(k)),
                _mm256_loadu_ps(taps.v.as_ptr().add(k)),
                _mm256_loadu_ps(taps.w.as_ptr().add(k)),
            )
        };
        let x = _mm256_add_ps(
            _mm256_add_ps(self.x, _mm256_mul_ps(u, self.cos)),
            _mm256_mul_ps(v, self.sin),
        );
        let y = _mm256_add_ps(
            _mm256_sub_ps(self.y, _mm256_mul_ps(u, self.sin)),
            _mm256_mul_ps(v, self.cos),
        );
        (x, y, w)
    }
}

/// A [`Placement`] broadcast to sixteen lanes.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct PlacementX16 {
    x: __m512,
    y: __m512,
    sin: __m512,
    cos: __m512,
}

#[cfg(target_arch = "x86_64")]
impl PlacementX16 {
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn new(at: Placement) -> Self {
        use std::arch::x86_64::*;
        Self {
            x: _mm512_set1_ps(at.x),
            y: _mm512_set1_ps(at.y),
            sin: _mm512_set1_ps(at.sin),
            cos: _mm512_set1_ps(at.cos),
        }
    }

    /// [`PlacementX8::taps`] for taps k to k + 15.
    ///
    /// # Safety
    /// k + 16 must not exceed the padded columns' length.
    #[target_feature(enable = "avx512f")]
    #[inline]
    unsafe fn taps(self, taps: &Taps, k: usize) -> (__m512, __m512, __m512) {
        use std::arch::x86_64::*;
        // SAFETY: the caller keeps the sixteen loads inside the columns.
        let (u, v, w) = unsafe {
            (
                _mm512_loadu_ps(taps.u.as_ptr().add(k)),
                _mm512_loadu_ps(taps.v.as_ptr().add(k)),
                _mm512_loadu_ps(taps.w.as_ptr().add(k)),
            )
        };
        let x = _mm512_add_ps(
            _mm512_add_ps(self.x, _mm512_mul_ps(u, self.cos)),
            _mm512_mul_ps(v, self.sin),
        );
        let y = _mm512_add_ps(
            _mm512_sub_ps(self.y, _mm512_mul_ps(u, self.sin)),
            _mm512_mul_ps(v, self.cos),
        );
        (x, y, w)
    }
}

/// Fewest taps summed sixteen at a time: the coarse search's blocks hold one to three groups
/// of eight, too few to repay the sixteen-tap paths.
const WIDE_ENOUGH: usize = 4 * LANES;

/// Whether the sixteen-tap paths can run (checked once; the answer is cached).
#[cfg(target_arch = "x86_64")]
fn has_avx512() -> bool {
    std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("avx512dq")
}

/// [`gather_corners`] for sixteen taps: each pair of neighbours one 64-bit element, eight
/// per gather, then the lefts and rights picked out in tap order.
///
/// # Safety
/// As [`gather_bilinear`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
unsafe fn gather_corners_x16(
    data: *const f32,
    below: *const f32,
    i: __m512i,
) -> (__m512, __m512, __m512, __m512) {
    use std::arch::x86_64::*;
    let (first, last) = (_mm512_castsi512_si256(i), _mm512_extracti64x4_epi64::<1>(i));
    // SAFETY: the caller keeps every index's pair of pixels in both rows.
    let (top_lo, top_hi, bottom_lo, bottom_hi) = unsafe {
        (
            _mm512_i32gather_pd::<4>(first, data as *const f64),
            _mm512_i32gather_pd::<4>(last, data as *const f64),
            _mm512_i32gather_pd::<4>(first, below as *const f64),
            _mm512_i32gather_pd::<4>(last, below as *const f64),
        )
    };
    let lefts = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
    let rights = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
    let pick = |low: std::arch::x86_64::__m512d, high, which| {
        _mm512_permutex2var_ps(_mm512_castpd_ps(low), which, _mm512_castpd_ps(high))
    };
    (
        pick(top_lo, top_hi, lefts),
        pick(top_lo, top_hi, rights),
        pick(bottom_lo, bottom_hi, lefts),
        pick(bottom_lo, bottom_hi, rights),
    )
}

/// The slope passes' five sums, lane by lane: score, its slopes in x, y and the angle, and
/// the weight of the taps seen.
#[derive(Default)]
struct SlopeLanes {
    lanes: [[f32; LANES]; 5],
}

impl SlopeLanes {
    /// One tap in `lane`: weight w, darkness and its slopes, offset from the grain's centre.
    fn add(
        &mut self,
        lane: usize,
        w: f32,
        (value, gx, gy): (f32, f32, f32),
        (dx, dy): (f32, f32),
        floor: f32,
    ) {
        let l = &mut self.lanes;
        l[0][lane] += w * value.max(floor);
        l[4][lane] += w;
        // Where the darkness is floored the score does not move with the pose.
        if value > floor {
            let (wx, wy) = (w * gx, w * gy);
            l[1][lane] += wx;
            l[2][lane] += wy;
            l[3][lane] += wx * dy - wy * dx;
        }
    }

    /// The sums, with `weight` when the caller knows it (every tap seen).
    fn slopes(&self, weight: Option<f32>) -> Slopes {
        let l = &self.lanes;
        Slopes {
            sum: combine(l[0]),
            weight: weight.unwrap_or_else(|| combine(l[4])),
            dx: combine(l[1]),
            dy: combine(l[2]),
            dphi: combine(l[3]),
        }
    }
}

/// [`SlopeLanes`] on eight lanes, the same operations.
#[cfg(target_arch = "x86_64")]
struct SlopeLanesX8 {
    acc: [__m256; 5],
    floor: __m256,
    x: __m256,
    y: __m256,
}

#[cfg(target_arch = "x86_64")]
impl SlopeLanesX8 {
    #[target_feature(enable = "avx2")]
    #[inline]
    fn new(at: Placement, floor: f32) -> Self {
        use std::arch::x86_64::*;
        Self {
            acc: [_mm256_setzero_ps(); 5],
            floor: _mm256_set1_ps(floor),
            x: _mm256_set1_ps(at.x),
            y: _mm256_set1_ps(at.y),
        }
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    fn add(&mut self, w: __m256, value: __m256, gx: __m256, gy: __m256, x: __m256, y: __m256) {
        use std::arch::x86_64::*;
        let acc = &mut self.acc;
        acc[0] = _mm256_add_ps(acc[0], _mm256_mul_ps(w, _mm256_max_ps(value, self.floor)));
        acc[4] = _mm256_add_ps(acc[4], w);
        let w = _mm256_and_ps(w, _mm256_cmp_ps::<_CMP_GT_OQ>(value, self.floor));
        let (wx, wy) = (_mm256_mul_ps(w, gx), _mm256_mul_ps(w, gy));
        acc[1] = _mm256_add_ps(acc[1], wx);
        acc[2] = _mm256_add_ps(acc[2], wy);
        let lever = _mm256_sub_ps(
            _mm256_mul_ps(wx, _mm256_sub_ps(y, self.y)),
            _mm256_mul_ps(wy, _mm256_sub_ps(x, self.x)),
        );
        acc[3] = _mm256_add_ps(acc[3], lever);
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    fn slopes(&self, weight: Option<f32>) -> Slopes {
        use std::arch::x86_64::*;
        let mut lanes = SlopeLanes::default();
        for (l, a) in lanes.lanes.iter_mut().zip(self.acc) {
            // SAFETY: each array holds exactly one vector.
            unsafe { _mm256_storeu_ps(l.as_mut_ptr(), a) };
        }
        lanes.slopes(weight)
    }
}

/// What the near-edge paths need to look eight taps up in a [`Bordered`] plane.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct EdgeX8 {
    width: __m256,
    height: __m256,
    stride: __m256i,
    last_column: __m256i,
    last_row: __m256i,
}

#[cfg(target_arch = "x86_64")]
impl EdgeX8 {
    #[target_feature(enable = "avx2")]
    #[inline]
    fn new(plane: &Bordered) -> Self {
        use std::arch::x86_64::*;
        Self {
            width: _mm256_set1_ps(plane.width as f32),
            height: _mm256_set1_ps(plane.height as f32),
            stride: _mm256_set1_epi32(plane.stride as i32),
            last_column: _mm256_set1_epi32(plane.width as i32 - 1),
            last_row: _mm256_set1_epi32(plane.height as i32 - 1),
        }
    }

    /// For taps at (x, y) with weights w: the weights with taps off the plane zeroed, the
    /// index of each tap's top-left pixel clamped onto the border, and the bilinear
    /// fractions. Clamped onto the border, a pixel and its right neighbour read what clamping
    /// each onto the plane would.
    #[target_feature(enable = "avx2")]
    #[inline]
    fn lookup(self, x: __m256, y: __m256, w: __m256) -> (__m256, __m256i, __m256, __m256) {
        use std::arch::x86_64::*;
        let zero = _mm256_setzero_ps();
        let half = _mm256_set1_ps(0.5);
        let seen = _mm256_and_ps(
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(x, zero),
                _mm256_cmp_ps::<_CMP_GE_OQ>(y, zero),
            ),
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_LT_OQ>(x, self.width),
                _mm256_cmp_ps::<_CMP_LT_OQ>(y, self.height),
            ),
        );
        let w = _mm256_and_ps(w, seen);
        let (fx, fy) = (_mm256_sub_ps(x, half), _mm256_sub_ps(y, half));
        let (cf, rf) = (_mm256_floor_ps(fx), _mm256_floor_ps(fy));
        let (tx, ty) = (_mm256_sub_ps(fx, cf), _mm256_sub_ps(fy, rf));
        let border = _mm256_set1_epi32(-1);
        let clamp = |i: __m256i, last: __m256i| _mm256_min_epi32(_mm256_max_epi32(i, border), last);
        let c = clamp(_mm256_cvttps_epi32(cf), self.last_column);
        let r = clamp(_mm256_cvttps_epi32(rf), self.last_row);
        (
            w,
            _mm256_add_epi32(_mm256_mullo_epi32(r, self.stride), c),
            tx,
            ty,
        )
    }
}

/// [`blend`] on eight lanes, the same operations.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn blend_x8(a: __m256, b: __m256, d: __m256, e: __m256, tx: __m256, ty: __m256) -> __m256 {
    use std::arch::x86_64::*;
    let top = _mm256_add_ps(a, _mm256_mul_ps(tx, _mm256_sub_ps(b, a)));
    let bottom = _mm256_add_ps(d, _mm256_mul_ps(tx, _mm256_sub_ps(e, d)));
    _mm256_add_ps(top, _mm256_mul_ps(ty, _mm256_sub_ps(bottom, top)))
}

/// Bilinear values of eight taps whose top-left pixels are at indices `i` of the rows from
/// `data` and `below` (one row further), at fractions `tx`, `ty`. Each tap's two horizontal
/// neighbours are adjacent: one 64-bit gather element reads both, halving the gathered
/// elements.
///
/// # Safety
/// Every pixel `i` and `i + 1` of both rows must lie inside the allocation.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn gather_bilinear(
    data: *const f32,
    below: *const f32,
    i: __m256i,
    tx: __m256,
    ty: __m256,
) -> __m256 {
    // SAFETY: as the caller's.
    let (a, b, d, e) = unsafe { gather_corners(data, below, i) };
    blend_x8(a, b, d, e, tx, ty)
}

/// [`gather_bilinear`] with the blend's slopes along x and y ([`blend_slopes`]).
///
/// # Safety
/// As [`gather_bilinear`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn gather_bilinear_slopes(
    data: *const f32,
    below: *const f32,
    i: __m256i,
    tx: __m256,
    ty: __m256,
) -> (__m256, __m256, __m256) {
    use std::arch::x86_64::*;
    // SAFETY: as the caller's.
    let (a, b, d, e) = unsafe { gather_corners(data, below, i) };
    let (upper, lower) = (_mm256_sub_ps(b, a), _mm256_sub_ps(e, d));
    let top = _mm256_add_ps(a, _mm256_mul_ps(tx, upper));
    let bottom = _mm256_add_ps(d, _mm256_mul_ps(tx, lower));
    let gy = _mm256_sub_ps(bottom, top);
    let value = _mm256_add_ps(top, _mm256_mul_ps(ty, gy));
    let gx = _mm256_add_ps(upper, _mm256_mul_ps(ty, _mm256_sub_ps(lower, upper)));
    (value, gx, gy)
}

/// The four pixels around each of eight taps: top left and right (a, b) from `data`, bottom
/// left and right (d, e) from `below`, each pair read as one 64-bit element.
///
/// # Safety
/// As [`gather_bilinear`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn gather_corners(
    data: *const f32,
    below: *const f32,
    i: __m256i,
) -> (__m256, __m256, __m256, __m256) {
    use std::arch::x86_64::*;
    // Taps 0 1 4 5 gathered first and 2 3 6 7 second: the in-lane shuffles of `split_pairs`
    // then leave them in tap order, with no cross-lane permute of the four results.
    let i = _mm256_permutevar8x32_epi32(i, _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7));
    let (first, last) = (_mm256_castsi256_si128(i), _mm256_extracti128_si256::<1>(i));
    // SAFETY: the caller keeps every index's pair of pixels in both rows.
    let (top_lo, top_hi, bottom_lo, bottom_hi) = unsafe {
        (
            _mm256_i32gather_pd::<4>(data as *const f64, first),
            _mm256_i32gather_pd::<4>(data as *const f64, last),
            _mm256_i32gather_pd::<4>(below as *const f64, first),
            _mm256_i32gather_pd::<4>(below as *const f64, last),
        )
    };
    let (a, b) = split_pairs(top_lo, top_hi);
    let (d, e) = split_pairs(bottom_lo, bottom_hi);
    (a, b, d, e)
}

/// Pairs (left, right neighbour) of taps 0 1 4 5 (`low`) and 2 3 6 7 (`high`) as two vectors
/// in tap order: the lefts and the rights.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn split_pairs(low: __m256d, high: __m256d) -> (__m256, __m256) {
    use std::arch::x86_64::*;
    let (low, high) = (_mm256_castpd_ps(low), _mm256_castpd_ps(high));
    // Within each 128-bit half: the lefts (or rights) of low's two taps, then high's two.
    let left = _mm256_shuffle_ps::<0b10_00_10_00>(low, high);
    let right = _mm256_shuffle_ps::<0b11_01_11_01>(low, high);
    (left, right)
}

/// The lanes' partial sums, combined pairwise in a fixed order.
#[inline]
fn combine(l: [f32; LANES]) -> f32 {
    ((l[0] + l[4]) + (l[1] + l[5])) + ((l[2] + l[6]) + (l[3] + l[7]))
}

/// Bilinear value at continuous pixel coordinates, neighbours clamped onto the plane (read
/// clamped onto its border, as the vector path does).
#[inline]
fn bilinear_bordered(p: &Bordered, x: f32, y: f32) -> f32 {
    let ([a, b, d, e], (tx, ty)) = corners_bordered(p, x, y);
    blend(a, b, d, e, tx, ty)
}

/// The four pixels around (x, y), neighbours beyond the edge clamped onto the border, and
/// the bilinear fractions.
fn corners_bordered(p: &Bordered, x: f32, y: f32) -> ([f32; 4], (f32, f32)) {
    let (fx, fy) = (x - 0.5, y - 0.5);
    let (cf, rf) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - cf, fy - rf);
    let c = (cf as i32).clamp(-1, p.width as i32 - 1);
    let r = (rf as i32).clamp(-1, p.height as i32 - 1);
    let i = (r + 1) as usize * p.stride + (c + 1) as usize;
    (corners_at(p, i), (tx, ty))
}

/// The four pixels around (x, y) of a placement inside the plane ([`Taps::inside`]), where
/// truncation is the floor, and the bilinear fractions.
fn corners_inside(p: &Bordered, x: f32, y: f32) -> ([f32; 4], (f32, f32)) {
    let (fx, fy) = (x - 0.5, y - 0.5);
    let (c, r) = (fx as i32, fy as i32);
    let (tx, ty) = (fx - c as f32, fy - r as f32);
    let i = (r as usize + 1) * p.stride + c as usize + 1;
    (corners_at(p, i), (tx, ty))
}

/// Pixel i of the bordered data, its right neighbour, and the two below them.
fn corners_at(p: &Bordered, i: usize) -> [f32; 4] {
    [
        p.data[i],
        p.data[i + 1],
        p.data[i + p.stride],
        p.data[i + p.stride + 1],
    ]
}

/// Bilinear value at continuous pixel coordinates, neighbours clamped onto the plane.
#[cfg(test)]
fn bilinear_clamped(p: &Plane, x: f32, y: f32) -> f32 {
    let (fx, fy) = (x - 0.5, y - 0.5);
    let (cf, rf) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - cf, fy - rf);
    let (c, r) = (cf as i32, rf as i32);
    let (last_c, last_r) = (p.width as i32 - 1, p.height as i32 - 1);
    let (c0, c1) = (
        c.clamp(0, last_c) as usize,
        c.saturating_add(1).clamp(0, last_c) as usize,
    );
    let (r0, r1) = (
        r.clamp(0, last_r) as usize * p.width,
        r.saturating_add(1).clamp(0, last_r) as usize * p.width,
    );
    let (a, b) = (p.data[r0 + c0], p.data[r0 + c1]);
    let (d, e) = (p.data[r1 + c0], p.data[r1 + c1]);
    blend(a, b, d, e, tx, ty)
}

/// [`blend`] and its slopes along x and y (the fractions move one for one with the tap).
#[inline]
fn blend_slopes(a: f32, b: f32, d: f32, e: f32, tx: f32, ty: f32) -> (f32, f32, f32) {
    let (upper, lower) = (b - a, e - d);
    let top = a + tx * upper;
    let bottom = d + tx * lower;
    let gy = bottom - top;
    (top + ty * gy, upper + ty * (lower - upper), gy)
}

/// Bilinear blend of a pixel's four neighbours (a b on top, d e below) at fractions (tx, ty).
#[inline]
fn blend(a: f32, b: f32, d: f32, e: f32, tx: f32, ty: f32) -> f32 {
    let top = a + tx * (b - a);
    let bottom = d + tx * (e - d);
    top + ty * (bottom - top)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect::testing::Lcg;

    fn noise_plane(width: usize, height: usize) -> Plane {
        let mut rng = Lcg(0x9e37_79b9_7f4a_7c15);
        let data = (0..width * height).map(|_| rng.unit_f32()).collect();
        Plane {
            width,
            height,
            data,
        }
    }

    fn some_taps() -> Taps {
        let mut taps = Taps::default();
        for k in 0..37 {
            let (u, v) = ((k % 9) as f32 * 1.7 - 6.0, (k / 9) as f32 * 1.3 - 2.5);
            taps.push(u, v, 0.25 + (k % 5) as f32 * 0.3 - 0.6);
        }
        taps.seal();
        taps
    }

    /// The vector paths (eight and sixteen taps at a time) and the scalar path give the same
    /// sums to the bit, so scores do not depend on the processor; they agree with a plain
    /// sum of bilinear values.
    #[test]
    fn paths_agree() {
        let raw = noise_plane(64, 48);
        let plane = Bordered::new(&raw);
        let taps = some_taps();
        for k in 0..50 {
            let phi = k as f32 * 0.37;
            let at = Placement {
                x: 20.0 + (k % 7) as f32 * 3.1,
                y: 18.0 + (k % 5) as f32 * 2.3,
                sin: phi.sin(),
                cos: phi.cos(),
            };
            assert!(taps.inside(at, &plane));
            let scalar = taps.sum_inside_scalar(at, &plane, 0.3);
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                let vector = unsafe { taps.sum_inside_avx2(at, &plane, 0.3) };
                assert_eq!(scalar.to_bits(), vector.to_bits());
            }
            #[cfg(target_arch = "x86_64")]
            if has_avx512() {
                let mut lanes = [0.0f32; LANES];
                let all = 0..taps.padded_len();
                unsafe { taps.accumulate_inside_avx512(at, &plane, 0.3, &mut lanes, all) };
                assert_eq!(scalar.to_bits(), combine(lanes).to_bits());
                let wide = unsafe { taps.slopes_inside_avx512(at, &plane, 0.3) };
                assert_eq!(wide, taps.slopes_inside_scalar(at, &plane, 0.3));
            }
            let (plain, n) = taps.sum_near_edge_scalar(at, &plane, 0.3);
            assert!((plain - scalar).abs() < 1e-4 * (1.0 + plain.abs()));
            assert!((n - taps.weight).abs() < 1e-5);
        }
    }

    /// Summing the taps range by range gives the lanes summing them at once gives.
    #[test]
    fn ranges_add_up_to_the_whole() {
        let raw = noise_plane(64, 48);
        let plane = Bordered::new(&raw);
        let taps = some_taps();
        let at = Placement {
            x: 30.0,
            y: 24.0,
            sin: 0.6f32.sin(),
            cos: 0.6f32.cos(),
        };
        let (whole, _) = taps.sum(at, &plane, 0.2);
        let mut lanes = [0.0f32; LANES];
        let n = taps.padded_len();
        for k in (0..n).step_by(LANES) {
            taps.accumulate_inside(at, &plane, 0.2, &mut lanes, k..k + LANES);
        }
        assert_eq!(Taps::lanes_total(lanes).to_bits(), whole.to_bits());
    }

    /// Near the edge, too, both paths give the same sums to the bit, and these are the plain
    /// sums over the taps that fall inside the plane.
    #[test]
    fn edge_paths_agree() {
        let raw = noise_plane(40, 30);
        let plane = Bordered::new(&raw);
        let taps = some_taps();
        for k in 0..60 {
            let phi = k as f32 * 0.29;
            let at = Placement {
                x: -3.0 + (k % 11) as f32 * 4.6,
                y: -2.0 + (k % 7) as f32 * 5.1,
                sin: phi.sin(),
                cos: phi.cos(),
            };
            let (s, n) = taps.sum_near_edge_scalar(at, &plane, 0.3);
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                let (vs, vn) = unsafe { taps.sum_near_edge_avx2(at, &plane, 0.3) };
                assert_eq!((s.to_bits(), n.to_bits()), (vs.to_bits(), vn.to_bits()));
            }
            #[cfg(target_arch = "x86_64")]
            if has_avx512() {
                let (vs, vn) = unsafe { taps.sum_near_edge_avx512(at, &plane, 0.3) };
                assert_eq!((s.to_bits(), n.to_bits()), (vs.to_bits(), vn.to_bits()));
                let wide = unsafe { taps.slopes_near_edge_avx512(at, &plane, 0.3) };
                assert_eq!(wide, taps.slopes_near_edge_scalar(at, &plane, 0.3));
            }
            let (mut plain, mut plain_n) = (0.0f32, 0.0f32);
            for t in 0..taps.len {
                let (x, y) = at.apply(taps.u[t], taps.v[t]);
                if x >= 0.0 && y >= 0.0 && x < 40.0 && y < 30.0 {
                    plain += taps.w[t] * bilinear_clamped(&raw, x, y).max(0.3);
                    plain_n += taps.w[t];
                }
            }
            assert!((plain - s).abs() < 1e-4 * (1.0 + plain.abs()));
            assert!((plain_n - n).abs() < 1e-4);
        }
    }

    /// The slope sums: the vector and scalar paths agree to the bit (inside and near the
    /// edge), their sums are what `sum` gives, and their slopes are the derivatives of the sum
    /// (central differences over a step small against a pixel, so that no tap crosses a
    /// pixel boundary's kink in most lanes: a loose tolerance covers those that do).
    #[test]
    fn slopes_are_the_derivatives_of_the_sum() {
        let raw = noise_plane(64, 48);
        let plane = Bordered::new(&raw);
        let taps = some_taps();
        let mut edge_poses = 0;
        for k in 0..60 {
            let phi = k as f32 * 0.41;
            let near_edge = k % 3 == 0;
            let at = Placement {
                // Off the pixel grid, so that no tap sits on a kink of the bilinear blend.
                x: if near_edge { 2.137 } else { 20.137 } + (k % 7) as f32 * 3.1,
                y: if near_edge { 1.291 } else { 18.291 } + (k % 5) as f32 * 2.3,
                sin: phi.sin(),
                cos: phi.cos(),
            };
            let floor = if k % 2 == 0 { 0.0 } else { 0.4 };
            let slopes = taps.sum_with_slopes(at, &plane, floor);
            let (sum, weight) = taps.sum(at, &plane, floor);
            let scalar = if !taps.inside(at, &plane) {
                edge_poses += 1;
                taps.slopes_near_edge_scalar(at, &plane, floor)
            } else {
                taps.slopes_inside_scalar(at, &plane, floor)
            };
            assert_eq!(slopes, scalar);
            assert_eq!(
                (slopes.sum.to_bits(), slopes.weight.to_bits()),
                (sum.to_bits(), weight.to_bits())
            );
            let h = 1e-4f32;
            let shifted = |dx: f32, dy: f32, dphi: f32| {
                let p = phi + dphi;
                let at = Placement {
                    x: at.x + dx,
                    y: at.y + dy,
                    sin: p.sin(),
                    cos: p.cos(),
                };
                taps.sum(at, &plane, floor)
            };
            let ends = [
                (shifted(h, 0.0, 0.0), shifted(-h, 0.0, 0.0)),
                (shifted(0.0, h, 0.0), shifted(0.0, -h, 0.0)),
                (shifted(0.0, 0.0, h), shifted(0.0, 0.0, -h)),
            ];
            let numeric = ends.map(|(p, m)| f64::from(p.0 - m.0) / (2.0 * f64::from(h)));
            let analytic = [slopes.dx, slopes.dy, slopes.dphi].map(f64::from);
            for ((n, a), (p, m)) in numeric.iter().zip(analytic).zip(ends) {
                // A tap entering or leaving the photograph is a step, not a slope.
                if p.1 != weight || m.1 != weight {
                    continue;
                }
                assert!(
                    (n - a).abs() < 0.05 * (1.0 + a.abs()),
                    "pose {k}: numeric {numeric:?}, analytic {analytic:?}"
                );
            }
        }
        assert!(edge_poses >= 10, "{edge_poses} poses near the edge");
    }

    /// Near the edge only the taps inside the plane count, with their weights.
    #[test]
    fn taps_outside_are_skipped() {
        let plane = Bordered::new(&Plane::new(10, 10, 1.0));
        let mut taps = Taps::default();
        taps.push(0.0, 0.0, 1.0);
        taps.push(-20.0, 0.0, 2.0);
        taps.seal();
        let at = Placement {
            x: 5.0,
            y: 5.0,
            sin: 0.0,
            cos: 1.0,
        };
        assert!(!taps.inside(at, &plane));
        assert_eq!(taps.sum(at, &plane, 0.0), (1.0, 1.0));
    }
}
