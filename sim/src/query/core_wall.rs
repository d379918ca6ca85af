use smallvec::SmallVec;

use super::{Features, PlacedCore, SubContact, WeightGradient};
use crate::dynamics::Wall;

/// Sub-contacts of a placed core against a flat wall: one per vertex closer to the wall than
/// the rounding radius. A wall is one-sided, so a vertex that has crossed it is still pushed
/// back along the wall's normal, however deep.
pub fn core_wall_sub_contacts(core: &PlacedCore, wall: &Wall, out: &mut SmallVec<[SubContact; 4]>) {
    let r = core.radius;
    for (k, p) in core.vertices.iter().enumerate() {
        let s = (p - wall.point).dot(&wall.normal);
        if s < r {
            out.push(SubContact {
                features: Features::VertexWall { vertex: k as u8 },
                normal: wall.normal,
                overlap: r - s,
                point: p - wall.normal * ((r + s) / 2.0),
                weight: 1.0,
                weight_gradient: WeightGradient::ZERO,
            });
        }
    }
}

/// The overlap a vertex-wall sub-contact would have at the current placement.
pub fn wall_feature_overlap(core: &PlacedCore, wall: &Wall, features: Features) -> f64 {
    match features {
        Features::VertexWall { vertex } => core
            .vertices
            .get(vertex as usize)
            .map_or(0.0, |p| core.radius - wall.distance(*p)),
        _ => 0.0,
    }
}
