use serde::{Deserialize, Serialize};
use smallvec::SmallVec;

use crate::dynamics::ContactLaw;
use crate::math::{Vec2, cross, cross_scalar, perp};
use crate::query::{Features, NearVertices, SubContact};

/// The other body of a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Body {
    Grain(usize),
    Wall(usize),
}

/// A sub-contact as it stood at the last force evaluation, with its tangential history.
///
/// Its normal and point are not kept: every step streams all contacts through the cache, so
/// each byte here costs time in a large deposit. [`World::contacts`](super::World::contacts)
/// finds them again from the placed cores, which have not moved since.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubContactState {
    pub features: Features,
    /// The sub-contact's share of the law's force (see [`SubContact::weight`]); single
    /// precision fills the padding after `features`, and only the energy accounts read it.
    pub weight: f32,
    /// Accumulated tangential displacement xi (m), along perp(normal).
    pub displacement: f64,
    pub overlap: f64,
    /// Normal and tangential force, weighted.
    pub normal_force: f64,
    pub tangential_force: f64,
}

impl SubContactState {
    /// Elastic energy stored in the sub-contact, weighted like its force.
    pub fn elastic_energy(&self, law: &ContactLaw) -> f64 {
        f64::from(self.weight) * law.elastic_energy(self.overlap, self.displacement)
    }

    /// Force on the first body, given the sub-contact's unit normal.
    pub fn force(&self, normal: Vec2) -> Vec2 {
        normal * self.normal_force + perp(normal) * self.tangential_force
    }
}

/// Everything between two bodies (a grain pair, or a grain and a wall): its sub-contacts and
/// their summed force and torques.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairContact {
    pub subs: SmallVec<[SubContactState; 2]>,
    /// Force on the first body (the second gets the opposite).
    pub force: Vec2,
    pub torque_first: f64,
    pub torque_second: f64,
    /// Elastic energy this pair's sub-contacts brought in by appearing, less what they took
    /// away by vanishing, since the pair was created (J). See [`super::Energies::switching`].
    pub switched: f64,
    /// While the two grains' `travel` sums to less than this, the pair cannot touch (no
    /// sub-contacts: their travel when it was found apart, plus how far apart it was), or only
    /// its `near` vertices can (0: look at every vertex every step).
    pub apart_until: f64,
    /// The vertices that may touch while `apart_until` holds, for a pair in touch
    /// ([`NearVertices::NONE`]: not known, look at every vertex).
    pub near: NearVertices,
}

/// One sub-contact as seen from outside: who, where, how hard.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactRecord {
    pub first: usize,
    pub second: Body,
    /// Force on the first body from the second (N).
    pub force: Vec2,
    pub point: Vec2,
    /// Unit normal from the second body to the first.
    pub normal: Vec2,
    pub overlap: f64,
    /// Tangential spring displacement xi (m).
    pub displacement: f64,
}

/// Kinematics of one body as the contact law needs it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Kinematics {
    pub position: Vec2,
    pub velocity: Vec2,
    pub angular_velocity: f64,
    pub inverse_mass: f64,
}

impl Kinematics {
    pub const STATIC: Self = Self {
        position: Vec2::new(0.0, 0.0),
        velocity: Vec2::new(0.0, 0.0),
        angular_velocity: 0.0,
        inverse_mass: 0.0,
    };
}

impl PairContact {
    /// Drops every sub-contact; `would_be_overlap` gives the overlap each would have now.
    pub(crate) fn clear(&mut self, law: &ContactLaw, would_be_overlap: impl Fn(Features) -> f64) {
        for old in &self.subs {
            self.switched -= f64::from(old.weight)
                * law.elastic_energy(would_be_overlap(old.features), old.displacement);
        }
        self.subs.clear();
        self.force = Vec2::zeros();
        self.torque_first = 0.0;
        self.torque_second = 0.0;
    }

    /// Applies the contact law to the sub-contacts found this step, carrying each one's
    /// tangential history over from the last step when the same features touched.
    pub(crate) fn resolve(
        &mut self,
        found: &[SubContact],
        first: &Kinematics,
        second: &Kinematics,
        law: &ContactLaw,
        dt: f64,
        would_be_overlap: impl Fn(Features) -> f64,
    ) {
        // A pair's sub-contacts are usually those of a step ago, in the same order: each is
        // looked for at its own place first.
        for (n, old) in self.subs.iter().enumerate() {
            let kept = found.get(n).is_some_and(|f| f.features == old.features)
                || found.iter().any(|f| f.features == old.features);
            if !kept {
                self.switched -= f64::from(old.weight)
                    * law.elastic_energy(would_be_overlap(old.features), old.displacement);
            }
        }
        let reduced_mass = 1.0 / (first.inverse_mass + second.inverse_mass);
        // The new states are written in place over the old ones while the features match
        // place by place (a sub-contact's features are unique within its pair, so an old
        // state matched at its own place is the one a search would find, and no later one
        // needs it). From the first mismatch on, the remaining histories are read aside.
        let mut histories: SmallVec<[(Features, f64); 4]> = SmallVec::new();
        let mut in_place = true;
        let (mut force, mut torque_first, mut torque_second) = (Vec2::zeros(), 0.0, 0.0);
        for (n, sc) in found.iter().enumerate() {
            debug_assert!(found[..n].iter().all(|f| f.features != sc.features));
            let history = match self.subs.get(n) {
                Some(old) if in_place && old.features == sc.features => Some(old.displacement),
                _ => {
                    if in_place {
                        in_place = false;
                        histories.extend(
                            self.subs[n.min(self.subs.len())..]
                                .iter()
                                .map(|s| (s.features, s.displacement)),
                        );
                        self.subs.truncate(n);
                    }
                    histories
                        .iter()
                        .find(|(features, _)| *features == sc.features)
                        .map(|(_, displacement)| *displacement)
                }
            };
            let arm_first = sc.point - first.position;
            let arm_second = sc.point - second.position;
            let relative = first.velocity + cross_scalar(first.angular_velocity, arm_first)
                - second.velocity
                - cross_scalar(second.angular_velocity, arm_second);
            let tangent = perp(sc.normal);
            let normal_velocity = relative.dot(&sc.normal);
            // A sub-contact that was already overlapping a step ago was switched in by the
            // feature rules, not by the grains coming into touch.
            if history.is_none() && sc.overlap + normal_velocity * dt > 0.0 {
                self.switched += sc.weight * law.elastic_energy(sc.overlap, 0.0);
            }
            let f = law.force(
                sc.overlap,
                normal_velocity,
                relative.dot(&tangent),
                reduced_mass,
                history.unwrap_or(0.0),
                dt,
            );
            let (normal_force, tangential_force) = (sc.weight * f.normal, sc.weight * f.tangential);
            let on_first = sc.normal * normal_force + tangent * tangential_force;
            force += on_first;
            torque_first += cross(arm_first, on_first);
            torque_second -= cross(arm_second, on_first);
            if sc.weight < 1.0 {
                // The weighted energy w U is a potential only with -U grad(w) besides.
                let energy = law.elastic_energy(sc.overlap, 0.0);
                let g = &sc.weight_gradient;
                force -= g.position * energy;
                torque_first -= g.angle_first * energy;
                torque_second -= g.angle_second * energy;
            }
            let state = SubContactState {
                features: sc.features,
                weight: sc.weight as f32,
                displacement: f.displacement,
                overlap: sc.overlap,
                normal_force,
                tangential_force,
            };
            if in_place {
                self.subs[n] = state;
            } else {
                self.subs.push(state);
            }
        }
        // Old sub-contacts past the last one found (matched in place up to there).
        self.subs.truncate(found.len());
        self.force = force;
        self.torque_first = torque_first;
        self.torque_second = torque_second;
    }
}

/// Moves the histories of pairs that survive a Verlet rebuild to their new slots, and
/// returns them with the switching energy of the pairs dropped; both pair lists are sorted.
/// The lists usually agree up to some pair: the grains that moved are the top of a deposit,
/// its latest grains, whose pairs sort last. The contacts before it stay where they are and
/// only the rest are moved.
pub(crate) fn carry_over<K: Ord + Copy>(
    old_keys: &[K],
    mut old: Vec<PairContact>,
    new_keys: &[K],
) -> (Vec<PairContact>, f64) {
    let same = old_keys
        .iter()
        .zip(new_keys)
        .take_while(|(a, b)| a == b)
        .count();
    let mut rest = old.split_off(same);
    let (old_keys, new_keys) = (&old_keys[same..], &new_keys[same..]);
    let mut carried = old;
    carried.reserve(new_keys.len());
    let mut dropped = 0.0;
    let mut k = 0;
    for key in new_keys {
        while k < old_keys.len() && old_keys[k] < *key {
            dropped += rest[k].switched;
            k += 1;
        }
        if k < old_keys.len() && old_keys[k] == *key {
            carried.push(std::mem::take(&mut rest[k]));
            k += 1;
        } else {
            carried.push(PairContact::default());
        }
    }
    for contact in &rest[k..] {
        dropped += contact.switched;
    }
    (carried, dropped)
}

/// For each grain, the contacts it takes part in, in a fixed order, so forces are summed the
/// same way whatever the thread count.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Incidence {
    start: Vec<u32>,
    /// (contact index, true when the grain is the first body).
    entries: Vec<(u32, bool)>,
}

impl Incidence {
    /// `pairs` of grains, or with `second_is_grain` false, (grain, wall) pairs.
    pub fn build(grains: usize, pairs: &[[u32; 2]], second_is_grain: bool) -> Self {
        let mut count = vec![0u32; grains + 1];
        for [i, j] in pairs {
            count[*i as usize + 1] += 1;
            if second_is_grain {
                count[*j as usize + 1] += 1;
            }
        }
        for g in 0..grains {
            count[g + 1] += count[g];
        }
        let mut fill = count.clone();
        let mut entries = vec![(0, false); count[grains] as usize];
        for (k, [i, j]) in pairs.iter().enumerate() {
            let sides = if second_is_grain { 2 } else { 1 };
            for &(g, first) in [(*i, true), (*j, false)].iter().take(sides) {
                let slot = &mut fill[g as usize];
                entries[*slot as usize] = (k as u32, first);
                *slot += 1;
            }
        }
        Self {
            start: count,
            entries,
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.start.capacity() * 4 + self.entries.capacity() * 8
    }

    /// Number of grains it was built for.
    pub fn grains(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    pub fn of(&self, grain: usize) -> &[(u32, bool)] {
        &self.entries[self.start[grain] as usize..self.start[grain + 1] as usize]
    }
}
