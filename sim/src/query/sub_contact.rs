use serde::{Deserialize, Serialize};

use crate::math::Vec2;

/// Which features of the two grains touch. Together with the pair of grains this is the key
/// under which a sub-contact's tangential history is kept from step to step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Features {
    /// A vertex of the first core against the inside of an edge of the second.
    VertexEdge { vertex: u8, edge: u8 },
    /// The inside of an edge of the first core against a vertex of the second.
    EdgeVertex { edge: u8, vertex: u8 },
    /// A vertex of each core, each in the other's vertex region: a corner against a corner,
    /// counted once.
    VertexVertex { first: u8, second: u8 },
    /// A vertex of the core against a wall.
    VertexWall { vertex: u8 },
}

impl Features {
    /// The same features with the two cores' roles swapped.
    pub fn mirrored(self) -> Self {
        match self {
            Self::VertexEdge { vertex, edge } => Self::EdgeVertex { edge, vertex },
            Self::EdgeVertex { edge, vertex } => Self::VertexEdge { vertex, edge },
            Self::VertexVertex { first, second } => Self::VertexVertex {
                first: second,
                second: first,
            },
            wall @ Self::VertexWall { .. } => wall,
        }
    }
}

/// One point of contact between two spheropolygons (or a spheropolygon and a wall).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubContact {
    pub features: Features,
    /// Unit normal pointing from the second body towards the first.
    pub normal: Vec2,
    /// r_i + r_j minus the signed distance between the cores; above r_i + r_j when a vertex
    /// has entered the other core.
    pub overlap: f64,
    /// Contact point: the middle of the overlap along the normal.
    pub point: Vec2,
    /// Share of the contact law's force this sub-contact carries: 1, except for two corners
    /// close to each other, which share one contact zone (see
    /// [`core_core_sub_contacts`](super::core_core_sub_contacts)).
    pub weight: f64,
    /// How the weight changes as the bodies move. The weighted elastic energy w U is a
    /// potential only if its force includes -U grad(w) besides w times the law's force.
    pub weight_gradient: WeightGradient,
}

/// Derivatives of a sub-contact's weight with respect to the placement of the two bodies. The
/// weight depends only on their relative placement, so moving the second body by dX changes
/// it by -position . dX.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WeightGradient {
    /// With respect to the first body's position (1/m).
    pub position: Vec2,
    /// With respect to the first body's angle (1/rad).
    pub angle_first: f64,
    /// With respect to the second body's angle (1/rad).
    pub angle_second: f64,
}

impl WeightGradient {
    pub const ZERO: Self = Self {
        position: Vec2::new(0.0, 0.0),
        angle_first: 0.0,
        angle_second: 0.0,
    };

    pub fn scaled(self, a: f64) -> Self {
        self.combine(a, Self::ZERO, 0.0)
    }

    /// `self * a + other * b`.
    pub fn combine(self, a: f64, other: Self, b: f64) -> Self {
        Self {
            position: self.position * a + other.position * b,
            angle_first: self.angle_first * a + other.angle_first * b,
            angle_second: self.angle_second * a + other.angle_second * b,
        }
    }
}
