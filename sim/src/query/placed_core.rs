use crate::math::Vec2;

/// A core polygon placed in the world frame: what the contact queries read.
#[derive(Clone, Copy, Debug)]
pub struct PlacedCore<'a> {
    /// Vertices, counter-clockwise.
    pub vertices: &'a [Vec2],
    /// Unit direction of edge k (from vertex k to k + 1).
    pub directions: &'a [Vec2],
    pub lengths: &'a [f64],
    pub radius: f64,
    /// Centre of the grain and distance of its farthest core vertex from it.
    pub centre: Vec2,
    pub arm: f64,
}

impl PlacedCore<'_> {
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    #[inline]
    pub fn normal(&self, edge: usize) -> Vec2 {
        let d = self.directions[edge];
        Vec2::new(d.y, -d.x)
    }

    #[inline]
    pub fn previous(&self, k: usize) -> usize {
        if k == 0 { self.len() - 1 } else { k - 1 }
    }
}
