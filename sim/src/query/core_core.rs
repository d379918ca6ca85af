use smallvec::SmallVec;

use super::{Features, PlacedCore, SubContact};
use crate::math::Vec2;

/// Where a vertex meets the other core.
#[derive(Clone, Copy, Debug)]
enum Foot {
    Edge(usize),
    Vertex(usize),
}

/// One vertex-against-core finding: signed distance from the core and the unit normal that
/// points out of the core towards the vertex.
#[derive(Clone, Copy, Debug)]
struct Touch {
    foot: Foot,
    normal: Vec2,
    distance: f64,
    closest: Vec2,
}

/// All sub-contacts between two placed cores (SPEC §2): every vertex of one core against every
/// edge of the other, within r_i + r_j.
///
/// - A vertex whose projection falls inside an edge gives a vertex-edge sub-contact, so a face
///   against a face gives two, at the ends of the shared stretch.
/// - A vertex that projects outside both edges of the nearest vertex of the other core (a
///   corner against a corner) gives one vertex-vertex sub-contact, and only when each vertex
///   lies in the other's vertex region; otherwise a vertex-edge sub-contact covers it.
/// - A vertex that has entered the other core (overlap deeper than r_i + r_j) is pushed out
///   along the outward normal of one edge: the one it had last step, while it stays within
///   reach of it, so the normal does not flip as the vertex crosses the core's middle.
///
/// `previous` lists the features touching at the last step; it is read only for a vertex
/// found inside the other core, which is rare.
pub fn core_core_sub_contacts<I: Iterator<Item = Features>>(
    first: &PlacedCore,
    second: &PlacedCore,
    previous: impl Fn() -> I,
    out: &mut SmallVec<[SubContact; 4]>,
) {
    let cutoff = first.radius + second.radius;
    for k in 0..first.len() {
        let preferred = || {
            previous().find_map(|f| match f {
                Features::VertexEdge { vertex, edge } if vertex as usize == k => {
                    Some(edge as usize)
                }
                _ => None,
            })
        };
        vertex_against_core(first, k, second, cutoff, true, preferred, |touch| {
            let features = match touch.foot {
                Foot::Edge(e) => Features::VertexEdge {
                    vertex: k as u8,
                    edge: e as u8,
                },
                Foot::Vertex(m) => Features::VertexVertex {
                    first: k as u8,
                    second: m as u8,
                },
            };
            let p = first.vertices[k];
            out.push(SubContact {
                features,
                normal: touch.normal,
                overlap: cutoff - touch.distance,
                point: (p + touch.closest) / 2.0
                    + touch.normal * ((second.radius - first.radius) / 2.0),
            });
        });
    }
    for m in 0..second.len() {
        let preferred = || {
            previous().find_map(|f| match f {
                Features::EdgeVertex { edge, vertex } if vertex as usize == m => {
                    Some(edge as usize)
                }
                _ => None,
            })
        };
        vertex_against_core(second, m, first, cutoff, false, preferred, |touch| {
            let Foot::Edge(e) = touch.foot else { return };
            let p = second.vertices[m];
            out.push(SubContact {
                features: Features::EdgeVertex {
                    edge: e as u8,
                    vertex: m as u8,
                },
                normal: -touch.normal,
                overlap: cutoff - touch.distance,
                point: (p + touch.closest) / 2.0
                    + touch.normal * ((first.radius - second.radius) / 2.0),
            });
        });
    }
    count_corners_once(first, second, out);
}

/// The nearer end of edge `e` of `core` to the point whose projection is `along` from its
/// start.
fn nearer_end(core: &PlacedCore, e: usize, along: f64) -> usize {
    if along < core.lengths[e] / 2.0 {
        e
    } else if e + 1 == core.len() {
        0
    } else {
        e + 1
    }
}

/// Two faces that meet with their corners nearly level (squares stacked in a column): at that
/// end, corner a of one core projects inside the other's face and corner b of the other
/// inside the first's face, both within a window of (core gap x tilt), a fraction of a
/// micrometre. Counting both would double the force at that end; as the grains tremble across
/// the window a second sub-contact would appear and vanish at finite overlap, and pump energy
/// into a deposit at rest. The end is counted once, by the corner that lies deeper inside the
/// other's face: the two candidates hand over where they are equally deep, with the same
/// overlap to within gap x tilt^2.
#[inline]
fn count_corners_once(
    first: &PlacedCore,
    second: &PlacedCore,
    out: &mut SmallVec<[SubContact; 4]>,
) {
    if out.len() < 2 {
        return;
    }
    // Bit k set: drop out[k].
    let mut drop = 0u32;
    for a in 0..out.len().min(32) {
        let Features::VertexEdge { vertex: k, edge: e } = out[a].features else {
            continue;
        };
        let (k, e) = (k as usize, e as usize);
        let p = first.vertices[k];
        let along_p = (p - second.vertices[e]).dot(&second.directions[e]);
        let m_near = nearer_end(second, e, along_p);
        for b in 0..out.len().min(32) {
            let Features::EdgeVertex { edge: f, vertex: m } = out[b].features else {
                continue;
            };
            let (f, m) = (f as usize, m as usize);
            if m != m_near {
                continue;
            }
            let q = second.vertices[m];
            let along_q = (q - first.vertices[f]).dot(&first.directions[f]);
            if nearer_end(first, f, along_q) != k {
                continue;
            }
            let inset_p = along_p.min(second.lengths[e] - along_p);
            let inset_q = along_q.min(first.lengths[f] - along_q);
            drop |= if inset_p >= inset_q { 1 << b } else { 1 << a };
        }
    }
    if drop == 0 {
        return;
    }
    let mut index = 0;
    out.retain(|_| {
        let keep = drop & (1 << index) == 0;
        index += 1;
        keep
    });
}

/// The overlap the sub-contact `features` would have at the current placement, had it been
/// kept: the continuation of its own distance (a vertex's distance from an edge's line, or
/// from the other vertex). Used to account for the energy a sub-contact takes with it when
/// the feature rules switch it off at a finite overlap.
pub fn feature_overlap(first: &PlacedCore, second: &PlacedCore, features: Features) -> f64 {
    let cutoff = first.radius + second.radius;
    let vertex = |core: &PlacedCore, k: u8| core.vertices.get(k as usize).copied();
    let line_distance = |core: &PlacedCore, e: u8, p: Vec2| {
        let e = e as usize;
        (p - core.vertices[e]).dot(&core.normal(e))
    };
    let distance = match features {
        Features::VertexEdge { vertex: k, edge } => {
            vertex(first, k).map(|p| line_distance(second, edge, p))
        }
        Features::EdgeVertex { edge, vertex: m } => {
            vertex(second, m).map(|q| line_distance(first, edge, q))
        }
        Features::VertexVertex {
            first: k,
            second: m,
        } => vertex(first, k)
            .zip(vertex(second, m))
            .map(|(p, q)| (p - q).norm()),
        Features::VertexWall { .. } => None,
    };
    distance.map_or(0.0, |d| cutoff - d)
}

/// Vertex k of `owner` against `core`: calls `emit` for each touch within `cutoff`.
fn vertex_against_core(
    owner: &PlacedCore,
    k: usize,
    core: &PlacedCore,
    cutoff: f64,
    vertex_vertex: bool,
    preferred_edge: impl FnOnce() -> Option<usize>,
    mut emit: impl FnMut(Touch),
) {
    let p = owner.vertices[k];
    // Farther from the other core's centre than its farthest vertex plus the cutoff: no touch.
    let reach = core.arm + cutoff;
    if (p - core.centre).norm_squared() >= reach * reach {
        return;
    }
    let n = core.len();

    // Signed distance from each edge line. The distance to a convex core is at least the
    // largest of them, so one beyond the cutoff rules the vertex out: most vertices of a pair
    // face away from the other grain and stop here after an edge or two.
    // Kept for the second loop (most cores have few vertices).
    let mut signed = [0.0f64; 8];
    let mut nearest_edge = 0;
    let mut nearest_distance = f64::NEG_INFINITY;
    for e in 0..n {
        let s = (p - core.vertices[e]).dot(&core.normal(e));
        if s >= cutoff {
            return;
        }
        if e < signed.len() {
            signed[e] = s;
        }
        if s > nearest_distance {
            nearest_distance = s;
            nearest_edge = e;
        }
    }
    if nearest_distance <= 0.0 {
        // Inside the core: every edge line has the vertex on its inner side.
        let mut edge = nearest_edge;
        if let Some(e) = preferred_edge().filter(|&e| e < n) {
            if (p - core.vertices[e]).dot(&core.normal(e)) > nearest_distance - cutoff {
                edge = e;
            }
        }
        let normal = core.normal(edge);
        let distance = (p - core.vertices[edge]).dot(&normal);
        emit(Touch {
            foot: Foot::Edge(edge),
            normal,
            distance,
            closest: p - normal * distance,
        });
        return;
    }

    let (owner_in, owner_out) = (owner.directions[owner.previous(k)], owner.directions[k]);
    for e in 0..n {
        let a = core.vertices[e];
        let rel = p - a;
        let along = rel.dot(&core.directions[e]);
        if along > 0.0 && along < core.lengths[e] {
            let s = if e < signed.len() {
                signed[e]
            } else {
                rel.dot(&core.normal(e))
            };
            if s >= 0.0 {
                emit(Touch {
                    foot: Foot::Edge(e),
                    normal: core.normal(e),
                    distance: s,
                    closest: a + core.directions[e] * along,
                });
            }
        } else if along <= 0.0 && vertex_vertex {
            // p lies in the vertex region of a, and a in the vertex region of p.
            let core_in = core.directions[core.previous(e)];
            let mutual = rel.dot(&core_in) >= 0.0
                && (-rel).dot(&owner_out) <= 0.0
                && (-rel).dot(&owner_in) >= 0.0;
            let dist2 = rel.norm_squared();
            if mutual && dist2 < cutoff * cutoff {
                let distance = dist2.sqrt();
                let normal = if distance > 1e-9 * cutoff {
                    rel / distance
                } else {
                    (core.normal(core.previous(e)) + core.normal(e)).normalize()
                };
                emit(Touch {
                    foot: Foot::Vertex(e),
                    normal,
                    distance,
                    closest: a,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rotate;
    use crate::shape::Spheropolygon;

    struct Placed {
        vertices: Vec<Vec2>,
        directions: Vec<Vec2>,
        lengths: Vec<f64>,
        radius: f64,
        centre: Vec2,
        arm: f64,
    }

    impl Placed {
        fn new(shape: &Spheropolygon, centre: Vec2, angle: f64) -> Self {
            let (s, c) = angle.sin_cos();
            Self {
                vertices: shape
                    .vertices()
                    .iter()
                    .map(|v| centre + rotate(*v, c, s))
                    .collect(),
                directions: shape
                    .edge_directions()
                    .iter()
                    .map(|d| rotate(*d, c, s))
                    .collect(),
                lengths: shape.edge_lengths().to_vec(),
                radius: shape.radius(),
                centre,
                arm: shape.bounding_radius() - shape.radius(),
            }
        }
        fn core(&self) -> PlacedCore<'_> {
            PlacedCore {
                vertices: &self.vertices,
                directions: &self.directions,
                lengths: &self.lengths,
                radius: self.radius,
                centre: self.centre,
                arm: self.arm,
            }
        }
    }

    fn contacts(a: &Placed, b: &Placed) -> SmallVec<[SubContact; 4]> {
        let mut out = SmallVec::new();
        core_core_sub_contacts(&a.core(), &b.core(), std::iter::empty, &mut out);
        out
    }

    fn square() -> Spheropolygon {
        Spheropolygon::rounded_rectangle(1.0, 1.0, 0.1).unwrap()
    }

    #[test]
    fn stacked_faces_with_level_corners_count_each_end_once() {
        // A column of squares: the upper one tilted by 1e-3 rad and shifted across the window
        // (core gap x tilt = 0.8 x 1e-3) in which both corners at an end project inside the
        // other's face. Each end must give one sub-contact, and the total normal push
        // k * sum(overlap) must not jump as the shift crosses the window.
        let s = square();
        let bottom = Placed::new(&s, Vec2::new(0.0, 0.0), 0.0);
        let tilt = 1e-3;
        let mut previous: Option<f64> = None;
        for step in -40..=40 {
            let shift = step as f64 * 2.5e-5;
            let top = Placed::new(&s, Vec2::new(shift, 0.95), tilt);
            let c = contacts(&top, &bottom);
            assert_eq!(c.len(), 2, "shift {shift}: {c:?}");
            let push: f64 = c.iter().map(|sc| sc.overlap).sum();
            if let Some(p) = previous {
                // Between two shifts the overlaps change by tilt x 2.5e-5 at most, smoothly.
                assert!((push - p).abs() < 1e-7, "shift {shift}: {p} -> {push}");
            }
            previous = Some(push);
        }
    }

    #[test]
    fn face_on_face_gives_two_sub_contacts_at_the_ends_of_the_shared_stretch() {
        let s = square();
        // Upper square shifted right by 0.3: shared stretch of core x in [-0.1, 0.4].
        let top = Placed::new(&s, Vec2::new(0.3, 0.95), 0.0);
        let bottom = Placed::new(&s, Vec2::new(0.0, 0.0), 0.0);
        let c = contacts(&top, &bottom);
        assert_eq!(c.len(), 2, "{c:?}");
        let mut xs: Vec<f64> = c.iter().map(|s| s.point.x).collect();
        xs.sort_by(f64::total_cmp);
        assert!(
            (xs[0] + 0.1).abs() < 1e-12 && (xs[1] - 0.4).abs() < 1e-12,
            "{xs:?}"
        );
        for sc in &c {
            assert!((sc.normal - Vec2::new(0.0, 1.0)).norm() < 1e-12);
            assert!((sc.overlap - 0.05).abs() < 1e-12);
        }
    }

    #[test]
    fn aligned_stack_counts_each_corner_once() {
        let s = square();
        let top = Placed::new(&s, Vec2::new(0.0, 0.95), 0.0);
        let bottom = Placed::new(&s, Vec2::zeros(), 0.0);
        assert_eq!(contacts(&top, &bottom).len(), 2);
        // Nearly aligned: the corners sit 1e-13 apart sideways.
        let top = Placed::new(&s, Vec2::new(1e-13, 0.95), 0.0);
        assert_eq!(contacts(&top, &bottom).len(), 2);
        let top = Placed::new(&s, Vec2::new(-1e-13, 0.95), 0.0);
        assert_eq!(contacts(&top, &bottom).len(), 2);
    }

    #[test]
    fn corner_against_corner_counts_once_along_the_line_of_the_corners() {
        let s = square();
        let half_diagonal = 0.4 * 2f64.sqrt();
        for skew in [0.0, 0.1, -0.2] {
            // Corners pointing at each other along x, overlap 0.05.
            let gap = 0.2 - 0.05;
            let left = Placed::new(&s, Vec2::zeros(), std::f64::consts::FRAC_PI_4 + skew);
            let tip = left
                .vertices
                .iter()
                .copied()
                .max_by(|a, b| a.x.total_cmp(&b.x))
                .unwrap();
            let angle = std::f64::consts::FRAC_PI_4 - skew;
            let probe = Placed::new(&s, Vec2::zeros(), angle);
            let heel = probe
                .vertices
                .iter()
                .copied()
                .min_by(|a, b| a.x.total_cmp(&b.x))
                .unwrap();
            assert!(heel.norm() > half_diagonal - 1e-12);
            let right = Placed::new(&s, tip + Vec2::new(gap, 0.0) - heel, angle);
            let c = contacts(&right, &left);
            assert_eq!(c.len(), 1, "skew {skew}: {c:?}");
            assert!(matches!(c[0].features, Features::VertexVertex { .. }));
            assert!((c[0].overlap - 0.05).abs() < 1e-12);
            assert!((c[0].normal - Vec2::new(1.0, 0.0)).norm() < 1e-9);
        }
    }

    #[test]
    fn a_vertex_inside_the_other_core_is_pushed_out() {
        let s = square();
        let bottom = Placed::new(&s, Vec2::zeros(), 0.0);
        // A corner 0.25 below the top face of the bottom core: overlap 0.45 > r_i + r_j.
        let centre = Vec2::new(0.0, 0.4 - 0.25 + 0.4 * 2f64.sqrt());
        let top = Placed::new(&s, centre, std::f64::consts::FRAC_PI_4);
        // The tip is inside; the lower square's corners also touch the diamond's lower edges.
        for (a, b, up) in [(&top, &bottom, 1.0), (&bottom, &top, -1.0)] {
            let c = contacts(a, b);
            let deep: Vec<&SubContact> = c.iter().filter(|s| s.overlap > 0.4).collect();
            assert_eq!(deep.len(), 1, "{c:?}");
            assert!((deep[0].normal - Vec2::new(0.0, up)).norm() < 1e-12);
            assert!((deep[0].overlap - 0.45).abs() < 1e-12);
            // Every sub-contact pushes the upper grain up, none pulls.
            assert!(
                c.iter().all(|s| s.normal.y * up > 0.5 && s.overlap > 0.0),
                "{c:?}"
            );
        }
    }

    #[test]
    fn the_remembered_edge_keeps_a_deep_vertex_from_flipping() {
        let rod = Spheropolygon::rounded_rectangle(4.0, 1.0, 0.1).unwrap();
        let bottom = Placed::new(&rod, Vec2::zeros(), 0.0);
        // A corner 0.45 deep into a core 0.8 thick: nearer the bottom face than where it entered.
        let tip_depth = 0.45;
        let centre = Vec2::new(0.0, 0.4 - tip_depth + 0.4 * 2f64.sqrt());
        let top = Placed::new(&square(), centre, std::f64::consts::FRAC_PI_4);
        let mut out = SmallVec::new();
        let tip = top.vertices.iter().position(|v| v.y < 0.0).unwrap() as u8;
        let remembered = [Features::VertexEdge {
            vertex: tip,
            edge: 2,
        }];
        let of_tip = |c: &SmallVec<[SubContact; 4]>| {
            let hits: Vec<SubContact> = c
                .iter()
                .copied()
                .filter(
                    |s| matches!(s.features, Features::VertexEdge { vertex, .. } if vertex == tip),
                )
                .collect();
            assert_eq!(hits.len(), 1, "{c:?}");
            hits[0]
        };
        core_core_sub_contacts(
            &top.core(),
            &bottom.core(),
            || remembered.iter().copied(),
            &mut out,
        );
        let kept = of_tip(&out);
        assert!(kept.normal.y > 0.99, "{kept:?}");
        assert!((kept.overlap - (0.2 + tip_depth)).abs() < 1e-12);
        // Without memory the nearest face (the bottom one) would pull it through.
        let mut fresh = SmallVec::new();
        core_core_sub_contacts(&top.core(), &bottom.core(), std::iter::empty, &mut fresh);
        assert!(of_tip(&fresh).normal.y < -0.99);
    }
}
