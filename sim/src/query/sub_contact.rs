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
}
