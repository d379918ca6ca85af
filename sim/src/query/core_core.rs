use smallvec::SmallVec;

use super::near_vertices::{
    Members, NEAR_WITHIN, NearVertices, RECHECK_AFTER, Verdict, edge_clearance,
};
use super::{Features, PlacedCore, SubContact, WeightGradient};
use crate::math::{Vec2, cross, perp};

/// Where a vertex meets the other core.
#[derive(Clone, Copy, Debug)]
enum Foot {
    Edge(usize),
    Vertex(usize),
}

/// How a vertex found inside the other core came in, from the sub-contact it had a step ago.
#[derive(Clone, Copy, Debug)]
enum Entry {
    /// Through the inside of this edge.
    Edge(usize),
    /// Past this corner.
    Corner(usize),
}

/// A vertex within this fraction of r_i + r_j of the other core counts as inside it.
const INSIDE: f64 = 1e-3;

/// One vertex-against-core finding: signed distance from the core and the unit normal that
/// points out of the core towards the vertex.
#[derive(Clone, Copy, Debug)]
struct Touch {
    foot: Foot,
    normal: Vec2,
    distance: f64,
    closest: Vec2,
}

/// All sub-contacts between two placed cores (docs/model.md §2): every vertex of one core against every
/// edge of the other, within r_i + r_j.
///
/// - A vertex whose projection falls inside an edge gives a vertex-edge sub-contact, so a face
///   against a face gives two, at the ends of the shared stretch.
/// - A vertex that projects outside both edges of the nearest vertex of the other core (a
///   corner against a corner) gives one vertex-vertex sub-contact, and only when each vertex
///   lies in the other's vertex region; otherwise a vertex-edge sub-contact covers it.
/// - A vertex that has entered the other core (overlap deeper than r_i + r_j), or lies on its
///   outline, is pushed out along the outward normal of the edge it came in through, so the
///   normal does not flip as it crosses the core's middle: the edge of its own sub-contact a
///   step ago; or, when it came in past a corner (its own vertex-vertex sub-contact, or that
///   corner against an edge ending at this vertex: two corners meeting, counted once), the
///   edge of that corner it lies deeper behind. Only a vertex with no history takes the
///   nearest edge.
///
/// `previous` lists the features touching at the last step; it is read only for a vertex
/// found inside the other core, which is rare.
pub fn core_core_sub_contacts<I: Iterator<Item = Features>>(
    first: &PlacedCore,
    second: &PlacedCore,
    previous: impl Fn() -> I,
    out: &mut SmallVec<[SubContact; 4]>,
) {
    sub_contacts_of(
        first,
        second,
        NearVertices::ALL,
        previous,
        out,
        |_, _, _| {},
    );
}

/// The sub-contacts of [`core_core_sub_contacts`], and the vertices that came near the other
/// core with how much longer the others stay out of its reach (see [`NearVertices`]).
pub fn core_core_sub_contacts_and_near<I: Iterator<Item = Features>>(
    first: &PlacedCore,
    second: &PlacedCore,
    previous: impl Fn() -> I,
    out: &mut SmallVec<[SubContact; 4]>,
) -> (NearVertices, f64) {
    let cutoff = first.radius + second.radius;
    let mut near = NearVertices::NONE;
    let mut clearance = RECHECK_AFTER * cutoff;
    sub_contacts_of(
        first,
        second,
        NearVertices::ALL,
        previous,
        out,
        |of_first, k, verdict| {
            let core = if of_first { second } else { first };
            let margin = verdict.clearance(core, cutoff);
            if margin < NEAR_WITHIN * cutoff {
                near.insert(of_first, k);
            } else {
                clearance = clearance.min(margin);
            }
        },
    );
    // The edges the near vertices may touch: the others are certified out of their reach
    // like the vertices far from the other core.
    for (of_first, owner, core) in [(true, first, second), (false, second, first)] {
        for e in 0..core.len() {
            let a = core.vertices[e];
            let margin = near
                .members(of_first, owner.len())
                .map(|k| {
                    let rel = owner.vertices[k] - a;
                    edge_clearance(core, cutoff, rel.dot(&core.normal(e)), rel.norm())
                })
                .fold(f64::INFINITY, f64::min);
            if margin < NEAR_WITHIN * cutoff {
                near.insert_edge(of_first, e);
            } else {
                clearance = clearance.min(margin);
            }
        }
    }
    (near, clearance)
}

/// The sub-contacts of [`core_core_sub_contacts`] when only the `near` vertices can touch
/// (the others are certified out of reach, [`NearVertices`]): the same sub-contacts, in the
/// same order, from the same arithmetic.
pub fn near_vertex_sub_contacts<I: Iterator<Item = Features>>(
    first: &PlacedCore,
    second: &PlacedCore,
    near: NearVertices,
    previous: impl Fn() -> I,
    out: &mut SmallVec<[SubContact; 4]>,
) {
    sub_contacts_of(first, second, near, previous, out, |_, _, _| {});
}

/// Sub-contacts of the vertices in `among`; `verdict` hears how each vertex looked at ended
/// (true for a vertex of the first core).
#[inline(always)]
fn sub_contacts_of<I: Iterator<Item = Features>>(
    first: &PlacedCore,
    second: &PlacedCore,
    among: NearVertices,
    previous: impl Fn() -> I,
    out: &mut SmallVec<[SubContact; 4]>,
    mut verdict: impl FnMut(bool, usize, Verdict),
) {
    let cutoff = first.radius + second.radius;
    // The sub-contacts are built inline (`#[inline(always)]` on the closures below): called
    // from three places, the compiler left them out of line, a call and a copy of the touch
    // for every sub-contact.
    let edges = among.edges_against(true, second.len());
    for k in among.members(true, first.len()) {
        let preferred = || entry(first, k, second, &previous);
        let seen = vertex_against_core(
            first,
            k,
            second,
            edges,
            cutoff,
            true,
            preferred,
            #[inline(always)]
            |touch| {
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
                    weight: 1.0,
                    weight_gradient: WeightGradient::ZERO,
                });
            },
        );
        verdict(true, k, seen);
    }
    let edges = among.edges_against(false, first.len());
    for m in among.members(false, second.len()) {
        let preferred = || entry(second, m, first, || previous().map(Features::mirrored));
        let seen = vertex_against_core(
            second,
            m,
            first,
            edges,
            cutoff,
            false,
            preferred,
            #[inline(always)]
            |touch| {
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
                    weight: 1.0,
                    weight_gradient: WeightGradient::ZERO,
                });
            },
        );
        verdict(false, m, seen);
    }
    share_close_corners(first, second, out);
}

/// The vertex after `k` of `core`.
fn next(core: &PlacedCore, k: usize) -> usize {
    if k + 1 == core.len() { 0 } else { k + 1 }
}

/// How vertex k of `owner`, found inside the `other` core, came in, read from the features
/// that touched a step ago (`previous`, with `owner` as the first core): its own sub-contact,
/// or else the other grain's corner against an edge of `owner` ending at k (two corners that
/// met, counted once as that corner's), if that corner is near k. An edge has two ends: two
/// rods side by side touch with a corner of one near one end of the other's face, and the far
/// end of that face may be the vertex that comes in, through the face, nowhere near that
/// corner; pushed out past the corner's other edge, the far end of the rod, it would be
/// given an overlap of nearly a rod length.
fn entry<J: Iterator<Item = Features>>(
    owner: &PlacedCore,
    k: usize,
    other: &PlacedCore,
    previous: impl Fn() -> J,
) -> Option<Entry> {
    let own = previous().find_map(|f| match f {
        Features::VertexEdge { vertex, edge } if vertex as usize == k => {
            Some(Entry::Edge(edge as usize))
        }
        Features::VertexVertex { first, second } if first as usize == k => {
            Some(Entry::Corner(second as usize))
        }
        _ => None,
    });
    // Corners that met a step ago are within the cutoff of each other, and the sharing zone
    // along the face; a step moves them by a fraction of the cutoff more.
    let near = CORNERS_MET * (owner.radius + other.radius);
    let p = owner.vertices[k];
    own.or_else(|| {
        previous().find_map(|f| match f {
            Features::EdgeVertex { edge, vertex }
                if ends(owner, edge, k)
                    && other
                        .vertices
                        .get(vertex as usize)
                        .is_some_and(|q| (p - q).norm() < near) =>
            {
                Some(Entry::Corner(vertex as usize))
            }
            _ => None,
        })
    })
}

/// Two corners closer than this many times r_i + r_j met (see [`entry`]).
const CORNERS_MET: f64 = 4.0;

/// Whether vertex `k` of `core` is an end of its edge `edge`.
fn ends(core: &PlacedCore, edge: u8, k: usize) -> bool {
    let edge = edge as usize;
    edge < core.len() && (k == edge || k == next(core, edge))
}

/// Corner p of one core inside a face of the other, near that face's corner q, while q lies
/// inside a face of the first near p. The two sub-contacts stand for one contact zone when
/// the corners are close, and must not switch at a finite overlap as the grains tremble,
/// which would pump energy into a deposit at rest. Two cases:
///
/// - Level corners (squares stacked in a column): p and q at the same end of the shared
///   stretch, both inside within a window of about (core gap x tilt). Counting both would
///   double the force at that end.
/// - The two ends of a short shared stretch: as it shrinks to nothing the face-on-face pair
///   becomes one corner-on-corner sub-contact, and counting both to the last would halve the
///   force there at a stroke.
///
/// Both are handled by one weighting of the insets x of p and y of q (how far each lies inside
/// the other's face, from the other's corner), with a(t) a smooth step from 0 at t = 0 to 1 at
/// t = l, l the mean rounding radius (the width of a rounded contact zone, within a factor of a
/// few): w_p = a(x) + (1 - a(x)) (1 - a(y)) x / (x + y), and w_q likewise. Apart (x, y >= l)
/// both count in full; as p reaches the end of the face (x -> 0) its weight falls to zero
/// where its sub-contact ends; as both reach the ends, the weights add up to the one
/// corner-on-corner sub-contact that takes over. The force is continuous throughout, and the
/// weights' gradients make it conservative.
#[inline]
fn share_close_corners(
    first: &PlacedCore,
    second: &PlacedCore,
    out: &mut SmallVec<[SubContact; 4]>,
) {
    if out.len() < 2 {
        return;
    }
    let zone = (first.radius + second.radius) / 2.0;
    let mut shared = false;
    for a in 0..out.len() {
        let Features::VertexEdge { vertex: k, edge: e } = out[a].features else {
            continue;
        };
        let (k, e) = (k as usize, e as usize);
        for b in 0..out.len() {
            let Features::EdgeVertex { edge: f, vertex: m } = out[b].features else {
                continue;
            };
            let (f, m) = (f as usize, m as usize);
            let q_ends_e = m == e || m == next(second, e);
            let p_ends_f = k == f || k == next(first, f);
            if !(q_ends_e && p_ends_f) {
                continue;
            }
            let (p, q) = (first.vertices[k], second.vertices[m]);
            let (de, df) = (second.directions[e], first.directions[f]);
            let (along_e, along_f) = ((p - q).dot(&de), (q - p).dot(&df));
            let (x, y) = (along_e.abs(), along_f.abs());
            if x >= zone && y >= zone {
                continue;
            }
            // x = |(p - q) . d_e| and y = |(q - p) . d_f| as the bodies move: p and d_f turn
            // with the first, q and d_e with the second.
            let (arm_p, arm_q) = (p - first.centre, q - second.centre);
            let grad_x = WeightGradient {
                position: de,
                angle_first: cross(arm_p, de),
                angle_second: (p - q).dot(&perp(de)) - cross(arm_q, de),
            }
            .scaled(along_e.signum());
            let grad_y = WeightGradient {
                position: -df,
                angle_first: (q - p).dot(&perp(df)) - cross(arm_p, df),
                angle_second: cross(arm_q, df),
            }
            .scaled(along_f.signum());
            let shares = Shares::of(x, y, zone);
            shared = true;
            for (index, share, by_x, by_y) in [
                (a, shares.first, shares.first_by_x, shares.first_by_y),
                (b, shares.second, shares.second_by_x, shares.second_by_y),
            ] {
                let sc = &mut out[index];
                let share_gradient = grad_x.combine(by_x, grad_y, by_y);
                sc.weight_gradient = sc.weight_gradient.combine(share, share_gradient, sc.weight);
                sc.weight *= share;
            }
        }
    }
    // Only a shared weight can have fallen to zero.
    if shared {
        out.retain(|sc| sc.weight > 0.0);
    }
}

/// The two weights of [`share_close_corners`] and their derivatives by the insets x and y.
struct Shares {
    first: f64,
    first_by_x: f64,
    first_by_y: f64,
    second: f64,
    second_by_x: f64,
    second_by_y: f64,
}

impl Shares {
    fn of(x: f64, y: f64, zone: f64) -> Self {
        // Smooth step 3 s^2 - 2 s^3 and its derivative.
        let step = |t: f64| {
            let s = (t / zone).min(1.0);
            (s * s * (3.0 - 2.0 * s), 6.0 * s * (1.0 - s) / zone)
        };
        let ((ax, dax), (ay, day)) = (step(x), step(y));
        let sum = x + y;
        if sum <= 0.0 {
            return Self {
                first: 0.5,
                first_by_x: 0.0,
                first_by_y: 0.0,
                second: 0.5,
                second_by_x: 0.0,
                second_by_y: 0.0,
            };
        }
        // w_p = a_x + g x / S, w_q = a_y + g y / S, with g = (1 - a_x)(1 - a_y), S = x + y.
        let g = (1.0 - ax) * (1.0 - ay);
        let (g_by_x, g_by_y) = (-dax * (1.0 - ay), -(1.0 - ax) * day);
        let (fx, fy) = (x / sum, y / sum);
        let s2 = sum * sum;
        Self {
            first: ax + g * fx,
            first_by_x: dax + g_by_x * fx + g * y / s2,
            first_by_y: g_by_y * fx - g * x / s2,
            second: ay + g * fy,
            second_by_x: g_by_x * fy - g * y / s2,
            second_by_y: day + g_by_y * fy + g * x / s2,
        }
    }
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

/// Vertex k of `owner` against `core`: calls `emit` for each touch within `cutoff`, and
/// tells how it ended. Only the core's `edges` are looked at, the others being certified to
/// give nothing (see [`NearVertices`]), except for a vertex that may lie inside the core,
/// whose nearest edge is looked for among all.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn vertex_against_core(
    owner: &PlacedCore,
    k: usize,
    core: &PlacedCore,
    edges: Members,
    cutoff: f64,
    vertex_vertex: bool,
    preferred_entry: impl FnOnce() -> Option<Entry>,
    mut emit: impl FnMut(Touch),
) -> Verdict {
    let p = owner.vertices[k];
    // Farther from the other core's centre than its farthest vertex plus the cutoff: no touch.
    let reach = core.arm + cutoff;
    let centre_squared = (p - core.centre).norm_squared();
    if centre_squared >= reach * reach {
        return Verdict::Beyond { centre_squared };
    }
    // The core's arrays cut to its length once: indexing them by an edge below then needs
    // no bounds check.
    let n = core.len();
    let (vertices, directions, lengths) =
        (core.vertices, &core.directions[..n], &core.lengths[..n]);
    let normal = |e: usize| {
        let d = directions[e];
        Vec2::new(d.y, -d.x)
    };
    let previous = |e: usize| if e == 0 { n - 1 } else { e - 1 };

    // Signed distance from each edge line. The distance to a convex core is at least the
    // largest of them, so one beyond the cutoff rules the vertex out: most vertices of a pair
    // face away from the other grain and stop here after an edge or two.
    // Kept for the second loop (most cores have few vertices).
    let mut signed = [0.0f64; 8];
    // The nearest edge line (the largest signed distance), or the signed distance from the
    // first line found beyond the cutoff.
    let edge_lines = |edges: Members, signed: &mut [f64; 8]| {
        let mut nearest_edge = 0;
        let mut nearest_distance = f64::NEG_INFINITY;
        for e in edges {
            let s = (p - vertices[e]).dot(&normal(e));
            if s >= cutoff {
                return Err(s);
            }
            if e < signed.len() {
                signed[e] = s;
            }
            if s > nearest_distance {
                nearest_distance = s;
                nearest_edge = e;
            }
        }
        Ok((nearest_edge, nearest_distance))
    };
    let (mut nearest_edge, mut nearest_distance) = match edge_lines(edges, &mut signed) {
        Ok(nearest) => nearest,
        Err(signed) => return Verdict::BehindEdge { signed },
    };
    // The edges left out have the vertex on the inner side of their lines: a vertex outside
    // the core by the edges looked at is outside it, nearest one of them; one that may lie
    // inside has its nearest edge looked for among all.
    if nearest_distance <= INSIDE * cutoff && !edges.is_all() {
        (nearest_edge, nearest_distance) = match edge_lines(Members::of(u8::MAX, n), &mut signed) {
            Ok(nearest) => nearest,
            Err(signed) => return Verdict::BehindEdge { signed },
        };
    }
    if nearest_distance <= INSIDE * cutoff {
        // Inside the core (every edge line has the vertex on its inner side), or on its
        // outline: a corner that came in past the end of a face of equal width (rods meeting
        // end-on) glides along the lines of the sides, and pushed out through a side it would
        // be squeezed from both and held there.
        let distance_to = |e: usize| (p - vertices[e]).dot(&normal(e));
        let edge = match preferred_entry() {
            Some(Entry::Edge(e)) if e < n => e,
            // In from a corner: through whichever of its two edges it lies deeper behind.
            Some(Entry::Corner(m)) if m < n => {
                let before = previous(m);
                if distance_to(before) < distance_to(m) {
                    before
                } else {
                    m
                }
            }
            _ => nearest_edge,
        };
        let normal = normal(edge);
        let distance = distance_to(edge);
        emit(Touch {
            foot: Foot::Edge(edge),
            normal,
            distance,
            closest: p - normal * distance,
        });
        return Verdict::Near;
    }

    let (owner_in, owner_out) = (owner.directions[owner.previous(k)], owner.directions[k]);
    for e in edges {
        let a = vertices[e];
        let rel = p - a;
        let along = rel.dot(&directions[e]);
        if along > 0.0 && along < lengths[e] {
            let s = if e < signed.len() {
                signed[e]
            } else {
                rel.dot(&normal(e))
            };
            if s >= 0.0 {
                emit(Touch {
                    foot: Foot::Edge(e),
                    normal: normal(e),
                    distance: s,
                    closest: a + directions[e] * along,
                });
            }
        } else if along <= 0.0 && vertex_vertex {
            // p lies in the vertex region of a, and a in the vertex region of p.
            let core_in = directions[previous(e)];
            let mutual = rel.dot(&core_in) >= 0.0
                && (-rel).dot(&owner_out) <= 0.0
                && (-rel).dot(&owner_in) >= 0.0;
            let dist2 = rel.norm_squared();
            if mutual && dist2 < cutoff * cutoff {
                let distance = dist2.sqrt();
                let normal = if distance > 1e-9 * cutoff {
                    rel / distance
                } else {
                    (normal(previous(e)) + normal(e)).normalize()
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
    Verdict::Near
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

    #[test]
    fn near_vertices_find_every_sub_contact_while_the_grains_travel_less_than_the_clearance() {
        // Pairs of squares and rods placed at random in and near touch, then moved by random
        // steps (slides, and turns that sweep the far ends of the edge lines) as long as their
        // summed travel stays below the clearance: the near vertices alone must give what all
        // of them give, bit for bit.
        let shapes = [
            square(),
            Spheropolygon::rounded_rectangle(4.0, 1.0, 0.1).unwrap(),
        ];
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut checked, mut skipped, mut skipped_edges, mut expired) = (0, 0, 0, 0);
        for trial in 0..2000 {
            let (a, b) = (&shapes[trial % 2], &shapes[(trial / 2) % 2]);
            let reach = a.bounding_radius() + b.bounding_radius();
            let direction = uniform() * std::f64::consts::TAU;
            let distance = reach * (0.4 + 0.65 * uniform());
            let mut placement = [
                (Vec2::zeros(), uniform() * std::f64::consts::TAU),
                (
                    Vec2::new(direction.cos(), direction.sin()) * distance,
                    uniform() * std::f64::consts::TAU,
                ),
            ];
            let place = |p: &[(Vec2, f64); 2]| {
                (
                    Placed::new(a, p[0].0, p[0].1),
                    Placed::new(b, p[1].0, p[1].1),
                )
            };
            let (first, second) = place(&placement);
            let mut out = SmallVec::new();
            let (near, clearance) = core_core_sub_contacts_and_near(
                &first.core(),
                &second.core(),
                std::iter::empty,
                &mut out,
            );
            let arms = [first.arm, second.arm];
            let mut travelled = 0.0;
            loop {
                // Steps of up to a third of the clearance, each a slide (towards the other
                // grain, or anywhere) or a turn.
                let towards = placement[1].0 - placement[0].0;
                for (k, (centre, angle)) in placement.iter_mut().enumerate() {
                    let size = clearance / 3.0 * uniform();
                    let draw = uniform();
                    if draw < 0.4 {
                        let sign = if k == 0 { 1.0 } else { -1.0 };
                        *centre += towards.normalize() * (sign * size);
                    } else if draw < 0.6 {
                        let heading = uniform() * std::f64::consts::TAU;
                        *centre += Vec2::new(heading.cos(), heading.sin()) * size;
                    } else {
                        let turn = size / arms[k] * if uniform() < 0.5 { -1.0 } else { 1.0 };
                        *angle += turn;
                    }
                    travelled += size * (1.0 + 1e-9) + 1e-15;
                }
                if travelled >= clearance {
                    expired += 1;
                    break;
                }
                let (first, second) = place(&placement);
                let (mut all, mut some) = (SmallVec::new(), SmallVec::new());
                core_core_sub_contacts(&first.core(), &second.core(), std::iter::empty, &mut all);
                near_vertex_sub_contacts(
                    &first.core(),
                    &second.core(),
                    near,
                    std::iter::empty,
                    &mut some,
                );
                assert_eq!(all, some, "trial {trial}, {near:?}, clearance {clearance}");
                checked += 1;
                skipped += 8 - (near.first.count_ones() + near.second.count_ones()) as usize;
                skipped_edges +=
                    8 - (near.first_edges.count_ones() + near.second_edges.count_ones()) as usize;
            }
        }
        // The check saw many steps, vertices and edges left out, and the clearance run out.
        assert!(
            checked > 1000
                && skipped > 4 * checked
                && skipped_edges > 2 * checked
                && expired == 2000,
            "{checked} steps, {skipped} vertices and {skipped_edges} edges left out"
        );
    }

    fn square() -> Spheropolygon {
        Spheropolygon::rounded_rectangle(1.0, 1.0, 0.1).unwrap()
    }

    /// Sum of the weights and the weighted normal push k * sum(weight x overlap) / k.
    fn weighted(c: &[SubContact]) -> (f64, f64) {
        (
            c.iter().map(|sc| sc.weight).sum(),
            c.iter().map(|sc| sc.weight * sc.overlap).sum(),
        )
    }

    #[test]
    fn stacked_faces_with_level_corners_share_each_end() {
        // A column of squares: the upper one tilted by 1e-3 rad and shifted across the window
        // (core gap x tilt = 0.15 x 1e-3, six shifts) in which both corners at an end project
        // inside the other's face. Each end must carry one sub-contact's worth of weight, and the total
        // normal push must not jump as the shift crosses the window.
        let s = square();
        let bottom = Placed::new(&s, Vec2::new(0.0, 0.0), 0.0);
        let tilt = 1e-3;
        let mut previous: Option<f64> = None;
        let mut shared = 0;
        for step in -40..=40 {
            let shift = step as f64 * 2.5e-5;
            let top = Placed::new(&s, Vec2::new(shift, 0.95), tilt);
            let c = contacts(&top, &bottom);
            let (weight, push) = weighted(&c);
            // Two corners sharing an end weigh 1 + a(x) a(y) together, with insets x, y of a
            // few 1e-5 against the ramp of 0.1.
            assert!((weight - 2.0).abs() < 1e-6, "shift {shift}: {c:?}");
            shared += usize::from(c.len() > 2);
            if let Some(p) = previous {
                // Between two shifts the overlaps change by tilt x 2.5e-5 at most, smoothly.
                assert!((push - p).abs() < 1e-7, "shift {shift}: {p} -> {push}");
            }
            previous = Some(push);
        }
        assert!(
            shared >= 5,
            "the window was crossed in {shared} shifts only"
        );
    }

    #[test]
    fn level_corners_hand_over_continuously_in_force_and_torque() {
        // Finer shifts across the window of one end: the force on the upper square and its
        // torque about the centre change by no more than the shift's own effect.
        let s = square();
        let bottom = Placed::new(&s, Vec2::new(0.0, 0.0), 0.0);
        let tilt = 2e-2;
        let load = |shift: f64| {
            let top = Placed::new(&s, Vec2::new(shift, 0.95), tilt);
            let c = contacts(&top, &bottom);
            let force: Vec2 = c.iter().map(|sc| sc.normal * sc.weight * sc.overlap).sum();
            let torque: f64 = c
                .iter()
                .map(|sc| {
                    crate::math::cross(sc.point - top.centre, sc.normal * sc.weight * sc.overlap)
                })
                .sum();
            (force, torque)
        };
        // The window at the right end spans shifts of about gap x tilt = 0.016.
        let h = 2e-4;
        let mut last = load(-0.03);
        for step in 1..=300 {
            let now = load(-0.03 + step as f64 * h);
            assert!(
                (now.0 - last.0).norm() < 1e-4 && (now.1 - last.1).abs() < 1e-4,
                "step {step}: {last:?} -> {now:?}"
            );
            last = now;
        }
    }

    #[test]
    fn the_weight_gradient_matches_finite_differences() {
        // Close corners at both kinds of pair (level corners, and the ends of a short shared
        // stretch), with some tilt so that every term of the gradient matters.
        let s = square();
        let bottom_at = |angle: f64| Placed::new(&s, Vec2::new(0.0, 0.0), angle);
        for (shift, tilt) in [(0.014, -0.03), (0.75, 0.05), (0.72, -0.04)] {
            let top_at =
                |dx: Vec2, angle: f64| Placed::new(&s, Vec2::new(shift, 0.95) + dx, tilt + angle);
            let weights = |top: &Placed, bottom: &Placed| -> Vec<(Features, f64)> {
                contacts(top, bottom)
                    .iter()
                    .map(|sc| (sc.features, sc.weight))
                    .collect()
            };
            let found = contacts(&top_at(Vec2::zeros(), 0.0), &bottom_at(0.0));
            let shared: Vec<&SubContact> = found.iter().filter(|sc| sc.weight < 1.0).collect();
            assert!(!shared.is_empty(), "shift {shift}: {found:?}");
            let h = 1e-7;
            let derivative =
                |features: Features, plus: (Placed, Placed), minus: (Placed, Placed)| {
                    let at = |w: Vec<(Features, f64)>| {
                        w.iter()
                            .find(|(f, _)| *f == features)
                            .map_or(0.0, |(_, w)| *w)
                    };
                    (at(weights(&plus.0, &plus.1)) - at(weights(&minus.0, &minus.1))) / (2.0 * h)
                };
            for sc in shared {
                let g = sc.weight_gradient;
                let numeric = [
                    derivative(
                        sc.features,
                        (top_at(Vec2::new(h, 0.0), 0.0), bottom_at(0.0)),
                        (top_at(Vec2::new(-h, 0.0), 0.0), bottom_at(0.0)),
                    ),
                    derivative(
                        sc.features,
                        (top_at(Vec2::new(0.0, h), 0.0), bottom_at(0.0)),
                        (top_at(Vec2::new(0.0, -h), 0.0), bottom_at(0.0)),
                    ),
                    derivative(
                        sc.features,
                        (top_at(Vec2::zeros(), h), bottom_at(0.0)),
                        (top_at(Vec2::zeros(), -h), bottom_at(0.0)),
                    ),
                    derivative(
                        sc.features,
                        (top_at(Vec2::zeros(), 0.0), bottom_at(h)),
                        (top_at(Vec2::zeros(), 0.0), bottom_at(-h)),
                    ),
                ];
                let analytic = [g.position.x, g.position.y, g.angle_first, g.angle_second];
                for (n, a) in numeric.iter().zip(analytic) {
                    assert!(
                        (n - a).abs() < 1e-5 * (1.0 + a.abs()),
                        "shift {shift}, {:?}: numeric {numeric:?}, analytic {analytic:?}",
                        sc.features
                    );
                }
            }
        }
    }

    #[test]
    fn a_short_shared_stretch_counts_both_ends_in_full() {
        // Faces overlapping over 0.15 of their 0.8 core length (more than the 0.1 rounding
        // radius), slightly tilted either way: each end of the stretch counts in full.
        let s = square();
        let bottom = Placed::new(&s, Vec2::zeros(), 0.0);
        for tilt in [-1e-3, 0.0, 1e-3] {
            let top = Placed::new(&s, Vec2::new(0.65, 0.95), tilt);
            let c = contacts(&top, &bottom);
            assert_eq!(c.len(), 2, "tilt {tilt}: {c:?}");
            assert!(c.iter().all(|sc| sc.weight == 1.0), "tilt {tilt}: {c:?}");
        }
    }

    #[test]
    fn a_shrinking_shared_stretch_becomes_one_corner_contact_continuously() {
        // The upper square slides off the lower one: two sub-contacts at the ends of the
        // shared stretch, then one corner against a corner, then none. The normal push must
        // go from two overlaps' worth to one without a jump.
        let s = square();
        let bottom = Placed::new(&s, Vec2::zeros(), 0.0);
        for tilt in [-1e-3, 0.0, 1e-3] {
            let mut last: Option<f64> = None;
            for step in 0..4000 {
                let shift = 0.6 + step as f64 * 1e-4;
                let top = Placed::new(&s, Vec2::new(shift, 0.95), tilt);
                let (_, push) = weighted(&contacts(&top, &bottom));
                if step == 0 {
                    assert!((push - 0.1).abs() < 1e-3, "{push}");
                }
                if let Some(p) = last {
                    // Over the ramp (the 0.1 rounding radius) the push falls by 0.05 as
                    // a smooth step: at most 1.5e-4 per step. A switch from two
                    // sub-contacts to one would jump by 0.05.
                    assert!(
                        (push - p).abs() < 3e-4,
                        "tilt {tilt}, shift {shift}: {p} -> {push}"
                    );
                }
                last = Some(push);
            }
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

    #[test]
    fn the_far_end_of_a_face_entering_side_by_side_is_pushed_out_through_the_face() {
        // Two rods side by side, the upper one shifted 0.3 along the axis, cores 0.01 deep
        // into each other. A step ago the upper rod's left corner touched the lower one's top
        // face, which ends at the lower rod's right corner: that corner, now inside the upper
        // core through its bottom face, 3.5 from the remembered corner, must be pushed out
        // through that face, not past the upper rod's far end (an overlap of 3.4).
        let rod = Spheropolygon::rounded_rectangle(4.0, 1.0, 0.1).unwrap();
        let lower = Placed::new(&rod, Vec2::zeros(), 0.0);
        let upper = Placed::new(&rod, Vec2::new(0.3, 0.8 - 0.01), 0.0);
        // Vertices counter-clockwise from the lower left: the lower rod's top face is edge 2,
        // from its corner 2 (right) to 3 (left); the upper rod's lower left corner is 0.
        assert!(lower.vertices[2].x > 0.0 && lower.vertices[2].y > 0.0);
        assert!(upper.vertices[0].x < 0.0 && upper.vertices[0].y < upper.centre.y);
        let remembered = [Features::EdgeVertex { edge: 2, vertex: 0 }];
        let mut out = SmallVec::new();
        core_core_sub_contacts(
            &lower.core(),
            &upper.core(),
            || remembered.iter().copied(),
            &mut out,
        );
        let corner = out
            .iter()
            .find(|s| matches!(s.features, Features::VertexEdge { vertex: 2, .. }))
            .unwrap_or_else(|| panic!("{out:?}"));
        assert!(corner.normal.y < -0.99, "{corner:?}");
        assert!((corner.overlap - (0.2 + 0.01)).abs() < 1e-12, "{corner:?}");
        // Every sub-contact pushes the lower rod down, by a shallow overlap.
        assert!(
            out.iter().all(|s| s.normal.y < -0.99 && s.overlap < 0.25),
            "{out:?}"
        );
    }
}
