use rayon::prelude::*;
use smallvec::SmallVec;

use super::contacts::{Incidence, Kinematics, PairContact, carry_over};
use super::sleep::Dormancy;
use super::world::World;
use crate::broad_phase::moved_past_half_skin;
use crate::dynamics::ContactLaw;
use crate::error::SimError;
use crate::math::{Vec2, rotate};
use crate::query::{
    Features, NearVertices, PlacedCore, SubContact, core_core_separation, core_core_sub_contacts,
    core_core_sub_contacts_and_near, core_wall_sub_contacts, feature_overlap,
    near_vertex_sub_contacts, wall_feature_overlap,
};

impl World {
    /// Advances the world by one time step (velocity Verlet; the contact damping sees the
    /// half-step velocities):
    /// 1. half kick and drift, 2. broad phase, 3. narrow phase and contact forces,
    /// 4. second half kick.
    ///
    /// With sleep on, the sleepers a neighbour disturbed wake before the second half kick, and
    /// the awake grains then count how long they have been quiet.
    ///
    /// Every stage is a parallel map over grains or pairs whose results do not depend on how
    /// the work is split, and forces are gathered per grain in a fixed order: the outcome is
    /// bit-identical whatever the number of threads.
    pub fn step(&mut self) -> Result<(), SimError> {
        self.prime()?;
        let dt = self.dt;
        let stale = self.kick_drift_place(dt);
        let sleep_due = self.sleep_check_due();
        if sleep_due {
            self.fall_asleep();
        }
        if stale || sleep_due || self.dormancy.woken {
            self.rebuild_neighbours()?;
        }
        // The gather ends the step grain by grain: wakes, second half kick, quiet count.
        self.compute_forces(Some(dt / 2.0));
        self.time += dt;
        self.steps += 1;
        self.grain_steps += self.grains.len() as u64;
        Ok(())
    }

    /// Evaluates contacts and forces at the current state, once, before the first step (the
    /// step does it by itself; call it to read contacts before stepping).
    pub fn prime(&mut self) -> Result<(), SimError> {
        if !self.dt.is_finite() {
            return Err(SimError::BadParameter {
                field: "time_step",
                value: self.dt,
                expected: "no grain shape was added, so there is no time step",
            });
        }
        if !self.forces_ready {
            self.place_cores();
            self.rebuild_neighbours()?;
            self.compute_forces(None);
            self.forces_ready = true;
        }
        Ok(())
    }

    /// Runs `steps` steps. While few grains are awake the steps run on one thread of a pool
    /// of their own: a pass over a few grains takes less time than waking a second thread.
    pub fn run(&mut self, steps: u64) -> Result<(), SimError> {
        let mut done = 0;
        while done < steps {
            self.prime()?;
            let serial = self.min_len == usize::MAX;
            // Run until the mode changes (checked every few steps; the answer is the same).
            let batch = (steps - done).min(64);
            if serial {
                let pool = self.serial_pool()?;
                pool.install(|| (0..batch).try_for_each(|_| self.step()))?;
            } else {
                // From outside the pool every parallel pass would be injected and the caller
                // put to sleep and woken again (two futex calls, three passes a step): the
                // batch runs on one of the pool's workers instead, whose passes are joins.
                rayon::scope(|_| (0..batch).try_for_each(|_| self.step()))?;
            }
            done += batch;
        }
        Ok(())
    }

    fn serial_pool(&mut self) -> Result<std::sync::Arc<rayon::ThreadPool>, SimError> {
        if self.serial_pool.is_none() {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .map_err(|e| SimError::ThreadPool(e.to_string()))?;
            self.serial_pool = Some(std::sync::Arc::new(pool));
        }
        Ok(self.serial_pool.clone().expect("made above"))
    }

    /// The drag's velocity factor over `time` (exactly 1 without drag).
    fn drag_decay(&self, time: f64) -> f64 {
        (-self.drag * time).exp()
    }

    /// One pass over the grains: first half kick, drift, the cores placed at the new
    /// positions, and whether some vertex has moved half the Verlet skin since the last
    /// rebuild (a vertex moves at most |dx| + arm |dtheta|).
    fn kick_drift_place(&mut self, dt: f64) -> bool {
        let (stride, skin) = (self.stride, self.skin);
        if self.grains.is_empty() {
            return false;
        }
        let (reference, reference_angles) = self.verlet.reference();
        let fresh = reference.len() == self.grains.len();
        let decay = self.drag_decay(dt / 2.0);
        let gravity = self.settings.gravity;
        let (shapes, arm, awake) = (&self.shapes, &self.arm, &self.dormancy.awake);
        let g = &mut self.grains;
        let (force, torque, mass, inverse_mass, inverse_inertia, shape) = (
            &g.force,
            &g.torque,
            &g.mass,
            &g.inverse_mass,
            &g.inverse_inertia,
            &g.shape,
        );
        // Blocks of grains, each a plain loop: handing the pass grain by grain through the
        // eight zipped arrays cost more than the kick and drift themselves.
        (
            g.position.par_chunks_mut(BLOCK),
            g.angle.par_chunks_mut(BLOCK),
            g.rotation.par_chunks_mut(BLOCK),
            g.velocity.par_chunks_mut(BLOCK),
            g.angular_velocity.par_chunks_mut(BLOCK),
            self.placed_vertices.par_chunks_mut(BLOCK * stride),
            self.placed_directions.par_chunks_mut(BLOCK * stride),
            self.travel.par_chunks_mut(BLOCK),
        )
            .into_par_iter()
            .with_min_len(self.min_len)
            .enumerate()
            .map(
                |(block, (xs, thetas, rotations, vs, ws, vertices, directions, travels))| {
                    let mut stale = false;
                    for k in 0..xs.len() {
                        let i = block * BLOCK + k;
                        // Fixed and sleeping grains stay where they are, cores placed.
                        if !awake[i] {
                            stale |= !fresh;
                            continue;
                        }
                        let (x, theta, v, w) = (&mut xs[k], &mut thetas[k], &mut vs[k], &mut ws[k]);
                        let d = drag_factor(decay, force[i], torque[i], gravity * mass[i]);
                        *v = *v * d + force[i] * (inverse_mass[i] * dt / 2.0);
                        *w = *w * d + torque[i] * inverse_inertia[i] * dt / 2.0;
                        *x += *v * dt;
                        let turn = *w * dt;
                        // A vertex moves at most |dx| + arm |turn|; the slack covers the
                        // rounding of the position and of the turned (cos, sin), far below a
                        // nanometre a step.
                        travels[k] += (v.norm() * dt + arm[i] * turn.abs()) * (1.0 + 1e-9) + 1e-15;
                        *theta += turn;
                        rotations[k] = rotate_by(rotations[k], turn);
                        let (cos, sin) = rotations[k];
                        let outline = &shapes[shape[i] as usize].shape;
                        let slots = k * stride..(k + 1) * stride;
                        let (vertices, directions) =
                            (&mut vertices[slots.clone()], &mut directions[slots]);
                        for (k, v) in outline.vertices().iter().enumerate() {
                            vertices[k] = *x + rotate(*v, cos, sin);
                            directions[k] = rotate(outline.edge_directions()[k], cos, sin);
                        }
                        stale |= !fresh
                            || moved_past_half_skin(
                                *x - reference[i],
                                *theta - reference_angles[i],
                                arm[i],
                                skin,
                            );
                    }
                    stale
                },
            )
            .reduce(|| false, |a, b| a || b)
    }

    /// Broad phase: rebuilds the Verlet lists from the current, placed, cores.
    fn rebuild_neighbours(&mut self) -> Result<(), SimError> {
        let g = &self.grains;
        if let Some(i) = (0..g.len()).find(|&i| {
            !(g.position[i].x.is_finite()
                && g.position[i].y.is_finite()
                && g.velocity[i].x.is_finite()
                && g.velocity[i].y.is_finite()
                && g.angle[i].is_finite()
                && g.angular_velocity[i].is_finite())
        }) {
            return Err(SimError::Diverged {
                grain: i,
                time: self.time,
            });
        }
        let mut verlet = std::mem::take(&mut self.verlet);
        let half_skin = self.skin / 2.0;
        let old = {
            let this = &*self;
            // Outlines within the skin (and j's margin): sub-contacts of grown cores.
            let near = |i: usize, j: usize, margin: f64| {
                let (mut a, mut b) = (this.placed(i), this.placed(j));
                a.radius += half_skin;
                b.radius += half_skin + margin;
                let mut found: SmallVec<[SubContact; 4]> = SmallVec::new();
                core_core_sub_contacts(&a, &b, std::iter::empty, &mut found);
                !found.is_empty()
            };
            let g = &this.grains;
            verlet.update(
                &g.position,
                &g.angle,
                &this.reach,
                &this.arm,
                &this.mobile,
                &this.walls,
                this.skin,
                near,
            )
        };
        self.verlet = verlet;
        self.dormancy.woken = false;
        let n = self.grains.len();
        // Unchanged lists (most updates while grains fall alone) keep their contacts in place.
        for (old, new, contacts, incidence, second_is_grain) in [
            (
                &old.pairs,
                &self.verlet.pairs,
                &mut self.pair_contacts,
                &mut self.pair_incidence,
                true,
            ),
            (
                &old.wall_pairs,
                &self.verlet.wall_pairs,
                &mut self.wall_contacts,
                &mut self.wall_incidence,
                false,
            ),
        ] {
            if let Some(dropped) =
                refresh_contacts(old, new, contacts, incidence, n, second_is_grain)
            {
                self.switching_dropped += dropped;
                self.pushes_stale = true;
            }
        }
        self.find_watched();
        // Splitting a pass over threads costs microseconds: not worth it for a few grains.
        let awake = self.dormancy.awake.iter().filter(|a| **a).count();
        self.min_len = if awake < SERIAL_BELOW { usize::MAX } else { 1 };
        Ok(())
    }

    /// World-frame vertices and edge directions of every core.
    fn place_cores(&mut self) {
        if self.grains.is_empty() {
            return;
        }
        let (shapes, g) = (&self.shapes, &self.grains);
        self.placed_vertices
            .par_chunks_mut(self.stride)
            .zip(self.placed_directions.par_chunks_mut(self.stride))
            .enumerate()
            .for_each(|(i, (vertices, directions))| {
                let outline = &shapes[g.shape[i] as usize].shape;
                let (cos, sin) = g.rotation[i];
                for (k, v) in outline.vertices().iter().enumerate() {
                    vertices[k] = g.position[i] + rotate(*v, cos, sin);
                    directions[k] = rotate(outline.edge_directions()[k], cos, sin);
                }
            });
    }

    /// Places one grain's core (a grain added or moved by hand; the step places the others).
    pub(crate) fn place_core(&mut self, i: usize) {
        let outline = &self.shapes[self.grains.shape[i] as usize].shape;
        let (cos, sin) = self.grains.rotation[i];
        let slots = i * self.stride..(i + 1) * self.stride;
        let vertices = &mut self.placed_vertices[slots.clone()];
        let directions = &mut self.placed_directions[slots];
        for (k, v) in outline.vertices().iter().enumerate() {
            vertices[k] = self.grains.position[i] + rotate(*v, cos, sin);
            directions[k] = rotate(outline.edge_directions()[k], cos, sin);
        }
    }

    // Called twice per pair and step: left out of line it costs a call and its bounds checks.
    #[inline(always)]
    pub(crate) fn placed(&self, i: usize) -> PlacedCore<'_> {
        let shape = &self.shapes[self.grains.shape[i] as usize].shape;
        let a = i * self.stride;
        let b = a + shape.vertices().len();
        PlacedCore {
            vertices: &self.placed_vertices[a..b],
            directions: &self.placed_directions[a..b],
            lengths: shape.edge_lengths(),
            radius: shape.radius(),
            centre: self.grains.position[i],
            arm: self.arm[i],
        }
    }

    #[inline]
    fn kinematics(&self, i: usize) -> Kinematics {
        let g = &self.grains;
        Kinematics {
            position: g.position[i],
            velocity: g.velocity[i],
            angular_velocity: g.angular_velocity[i],
            inverse_mass: g.inverse_mass[i],
        }
    }

    /// Narrow phase and contact law for every pair and wall contact, then the sum per grain;
    /// with `kick` (s), also the end of the step for each grain once its force is known: a
    /// watched sleeper wakes if disturbed, an awake grain takes the half kick v += a kick and
    /// counts its quiet steps.
    fn compute_forces(&mut self, kick: Option<f64>) {
        let mut pair_contacts = std::mem::take(&mut self.pair_contacts);
        let mut wall_contacts = std::mem::take(&mut self.wall_contacts);
        // The gather below reads only these compact copies of each contact's push: they fit
        // in cache where the contacts with their histories do not.
        let mut pair_push = std::mem::take(&mut self.pair_push);
        let mut wall_push = std::mem::take(&mut self.wall_push);
        pair_push.resize(pair_contacts.len(), Push::APART);
        wall_push.resize(wall_contacts.len(), Push::default());
        {
            let this = &*self;
            let (awake, travel) = (&this.dormancy.awake, &this.travel);
            // A contact at rest keeps its push: copied again only when the lists moved it.
            let stale = this.pushes_stale;
            // Pairs and walls side by side: one wait for both instead of one each.
            let pairs = || {
                pair_contacts
                    .par_iter_mut()
                    .zip(pair_push.par_iter_mut())
                    .zip(&this.verlet.pairs)
                    .with_min_len(this.min_len)
                    .for_each(|((contact, push), &[i, j])| {
                        let (i, j) = (i as usize, j as usize);
                        if !(awake[i] || awake[j]) {
                            // Both at rest: the contact keeps the force it had.
                            if stale {
                                *push = Push::pair(contact);
                            }
                            return;
                        }
                        // Found apart by more than the two grains have travelled since: the
                        // narrow phase would find nothing (a third of a dense deposit's pairs).
                        let travelled = travel[i] + travel[j];
                        if contact.subs.is_empty() && travelled < contact.apart_until {
                            // Its push is already nothing, unless the lists moved it.
                            if stale {
                                *push = Push::APART;
                            }
                            return;
                        }
                        let (first, second) = (this.placed(i), this.placed(j));
                        let would_be = |f: Features| feature_overlap(&first, &second, f);
                        let reach = this.reach[i] + this.reach[j];
                        let g = &this.grains;
                        let centres = (g.position[i] - g.position[j]).norm_squared();
                        let law = this.law_between(i, j);
                        if centres >= reach * reach {
                            contact.clear(law, would_be);
                            contact.apart_until = apart_until(travelled, centres.sqrt() - reach);
                            *push = Push::APART;
                            return;
                        }
                        let mut found: SmallVec<[SubContact; 4]> = SmallVec::new();
                        let previous = || contact.subs.iter().map(|s| s.features);
                        // Only the vertices that came near can touch until the grains have
                        // travelled the others' clearance: the same sub-contacts, found sooner.
                        let certified = travelled < contact.apart_until;
                        let near = if certified && contact.near != NearVertices::NONE {
                            near_vertex_sub_contacts(
                                &first,
                                &second,
                                contact.near,
                                previous,
                                &mut found,
                            );
                            None
                        } else {
                            Some(core_core_sub_contacts_and_near(
                                &first, &second, previous, &mut found,
                            ))
                        };
                        let kinematics = (this.kinematics(i), this.kinematics(j));
                        resolve(contact, &found, kinematics, law, this.dt, would_be);
                        if found.is_empty() {
                            let cutoff = first.radius + second.radius;
                            let gap = core_core_separation(&first, &second) - cutoff;
                            contact.apart_until = apart_until(travelled, gap);
                            contact.near = NearVertices::NONE;
                        } else if let Some((near, clearance)) = near {
                            contact.apart_until = travelled + clearance;
                            contact.near = near;
                        }
                        *push = Push::pair(contact);
                    });
            };
            let walls = || {
                wall_contacts
                    .par_iter_mut()
                    .zip(wall_push.par_iter_mut())
                    .zip(&this.verlet.wall_pairs)
                    .with_min_len(this.min_len)
                    .for_each(|((contact, push), &[i, k])| {
                        let (i, k) = (i as usize, k as usize);
                        if !awake[i] {
                            if stale {
                                *push = Push::on_first(contact);
                            }
                            return;
                        }
                        let (core, wall) = (this.placed(i), &this.walls[k]);
                        let mut found: SmallVec<[SubContact; 4]> = SmallVec::new();
                        core_wall_sub_contacts(&core, wall, &mut found);
                        let kinematics = (this.kinematics(i), Kinematics::STATIC);
                        resolve(contact, &found, kinematics, &this.wall_law, this.dt, |f| {
                            wall_feature_overlap(&core, wall, f)
                        });
                        *push = Push::on_first(contact);
                    });
            };
            rayon::join(pairs, walls);
        }
        let gravity = self.settings.gravity;
        let (law, plates) = (&self.settings.law, self.settings.plate_friction);
        // The plates' spring stretches over a whole step; priming only reads it.
        let plate_dt = if kick.is_some() { self.dt } else { 0.0 };
        let (pairs, walls, mobile) = (&self.pair_incidence, &self.wall_incidence, &self.mobile);
        let arm = &self.arm;
        let decay = self.drag_decay(kick.unwrap_or(0.0));
        let crate::dynamics::Grains {
            position,
            angle,
            force,
            torque,
            mass,
            velocity,
            angular_velocity,
            inverse_mass,
            inverse_inertia,
            ..
        } = &mut self.grains;
        let Dormancy {
            settings: sleep,
            awake,
            watched,
            quiet_steps,
            anchor,
            asleep_load,
            ..
        } = &mut self.dormancy;
        let sleep = *sleep;
        let gravity_norm = gravity.norm();
        // The end of the step for grain i, given its slots.
        #[allow(clippy::type_complexity)]
        let grain_end = |i: usize,
                         (force, torque, v, w, awake, watched, quiet_steps, anchor, slip): (
            &mut Vec2,
            &mut f64,
            &mut Vec2,
            &mut f64,
            &mut bool,
            &mut bool,
            &mut u32,
            &mut (Vec2, f64),
            &mut Vec2,
        )| {
            // A sleeping grain's forces change only through awake neighbours.
            if mobile[i] && !(*awake || *watched) {
                return false;
            }
            let mut f = Vec2::zeros();
            let mut t = 0.0;
            if mobile[i] {
                f = gravity * mass[i];
                for &(k, first) in pairs.of(i) {
                    let c = &pair_push[k as usize][usize::from(!first)];
                    f += c.force;
                    t += c.torque;
                }
                for &(k, _) in walls.of(i) {
                    let c = &wall_push[k as usize];
                    f += c.force;
                    t += c.torque;
                }
                if let Some(plates) = &plates {
                    let (push, stretch) =
                        plates.force(law, mass[i], gravity_norm, *v, *slip, plate_dt);
                    f += push;
                    *slip = stretch;
                }
            }
            *force = f;
            *torque = t;
            let Some(kick) = kick else {
                return false;
            };
            // The rest of the step, grain by grain, now that its force is known: a watched
            // sleeper disturbed wakes, the awake grains take the second half kick, and
            // count how long they have been quiet.
            let weight = mass[i] * gravity_norm;
            let here = (position[i], angle[i]);
            let mut woke = false;
            if let Some(s) = &sleep {
                if *watched && s.disturbed(f, t, asleep_load[i], weight, arm[i]) {
                    (*awake, *watched, *quiet_steps, *anchor) = (true, false, 0, here);
                    woke = true;
                }
            }
            if *awake {
                let d = drag_factor(decay, f, t, gravity * mass[i]);
                *v = *v * d + f * (inverse_mass[i] * kick);
                *w = *w * d + t * inverse_inertia[i] * kick;
                if let Some(s) = &sleep {
                    if s.quiet(*v, *w, f, t, weight, arm[i], here, *anchor) {
                        *quiet_steps = quiet_steps.saturating_add(1);
                    } else {
                        (*quiet_steps, *anchor) = (0, here);
                    }
                }
            }
            woke
        };
        // Blocks of grains, each a plain loop (see `kick_drift_place`).
        let woke = (
            force.par_chunks_mut(BLOCK),
            torque.par_chunks_mut(BLOCK),
            velocity.par_chunks_mut(BLOCK),
            angular_velocity.par_chunks_mut(BLOCK),
            awake.par_chunks_mut(BLOCK),
            watched.par_chunks_mut(BLOCK),
            quiet_steps.par_chunks_mut(BLOCK),
            anchor.par_chunks_mut(BLOCK),
            self.plate_slip.par_chunks_mut(BLOCK),
        )
            .into_par_iter()
            .with_min_len(self.min_len)
            .enumerate()
            .map(
                |(block, (fs, ts, vs, ws, awakes, watcheds, quiets, anchors, slips))| {
                    let mut woke = false;
                    for k in 0..fs.len() {
                        let slots = (
                            &mut fs[k],
                            &mut ts[k],
                            &mut vs[k],
                            &mut ws[k],
                            &mut awakes[k],
                            &mut watcheds[k],
                            &mut quiets[k],
                            &mut anchors[k],
                            &mut slips[k],
                        );
                        woke |= grain_end(block * BLOCK + k, slots);
                    }
                    woke
                },
            )
            .reduce(|| false, |a, b| a || b);
        self.dormancy.woken |= woke;
        self.pair_contacts = pair_contacts;
        self.wall_contacts = wall_contacts;
        self.pair_push = pair_push;
        self.wall_push = wall_push;
        self.pushes_stale = false;
    }
}

/// Carries the contacts of one pair list over to its new version and rebuilds its incidence,
/// unless neither the list nor the grain count changed (`None`); returns the switching energy
/// of the pairs dropped.
fn refresh_contacts(
    old: &[[u32; 2]],
    new: &[[u32; 2]],
    contacts: &mut Vec<PairContact>,
    incidence: &mut Incidence,
    grains: usize,
    second_is_grain: bool,
) -> Option<f64> {
    if old == new && incidence.grains() == grains {
        return None;
    }
    let (carried, dropped) = carry_over(old, std::mem::take(contacts), new);
    *contacts = carried;
    *incidence = Incidence::build(grains, new, second_is_grain);
    Some(dropped)
}

/// `apart_until` of a pair found `gap` apart when its grains had `travelled` together: a hair
/// less than the gap further (the narrow phase rounds at about 1e-17 m); 0, look again next
/// step, for a pair that touches or nearly does.
#[inline]
fn apart_until(travelled: f64, gap: f64) -> f64 {
    let margin = gap * (1.0 - 1e-9) - 1e-12;
    if margin > 0.0 {
        travelled + margin
    } else {
        0.0
    }
}

/// Grains a pass over the grains hands to a thread at a time.
const BLOCK: usize = 64;

/// Below this many awake grains a step runs on one thread.
const SERIAL_BELOW: usize = 256;

/// What a contact does to one of its bodies this step. The gather only adds: the second
/// body's force is kept negated (x - y and x + (-y) are the same number), so summing a
/// grain's pushes needs no branch on which body it is.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Push {
    force: Vec2,
    torque: f64,
}

impl Push {
    /// The pushes of a pair that does not touch: those of a zero force.
    const APART: [Self; 2] = [
        Self {
            force: Vec2::new(0.0, 0.0),
            torque: 0.0,
        },
        Self {
            force: Vec2::new(-0.0, -0.0),
            torque: 0.0,
        },
    ];

    /// On the first and on the second body.
    fn pair(contact: &PairContact) -> [Self; 2] {
        [
            Self::on_first(contact),
            Self {
                force: -contact.force,
                torque: contact.torque_second,
            },
        ]
    }

    fn on_first(contact: &PairContact) -> Self {
        Self {
            force: contact.force,
            torque: contact.torque_first,
        }
    }
}

fn resolve(
    contact: &mut PairContact,
    found: &[SubContact],
    (first, second): (Kinematics, Kinematics),
    law: &ContactLaw,
    dt: f64,
    would_be_overlap: impl Fn(Features) -> f64,
) {
    if found.is_empty() {
        contact.clear(law, would_be_overlap);
    } else {
        contact.resolve(found, &first, &second, law, dt, would_be_overlap);
    }
}

/// (cos, sin) of an angle turned further by `turn` (rad). A step turns a grain by 1e-2 rad
/// at most in practice: there a Taylor series to the seventh order is exact to rounding and
/// cheaper than sin_cos; larger turns use sin_cos.
#[inline]
fn rotate_by((cos, sin): (f64, f64), turn: f64) -> (f64, f64) {
    let (s, c) = if turn.abs() < 1e-2 {
        let t2 = turn * turn;
        (
            turn * (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0))),
            1.0 - t2 / 2.0 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0)),
        )
    } else {
        turn.sin_cos()
    };
    (cos * c - sin * s, sin * c + cos * s)
}

/// The drag's factor for a grain: `decay` when something touches it, 1 in free flight (only
/// gravity acts: the gathered force is exactly its weight and there is no torque) and without
/// drag (checked first: that is every step of a fill but its relaxation).
#[inline]
fn drag_factor(decay: f64, force: Vec2, torque: f64, weight: Vec2) -> f64 {
    if decay == 1.0 || (force == weight && torque == 0.0) {
        1.0
    } else {
        decay
    }
}

#[cfg(test)]
mod tests {
    use super::rotate_by;

    #[test]
    fn small_turns_match_sin_cos() {
        let mut r = (1.0, 0.0);
        let mut angle = 0.0;
        for k in 0..100_000 {
            let turn = 1e-3 * ((k % 17) as f64 - 8.0) / 8.0 + 2e-4;
            r = rotate_by(r, turn);
            angle += turn;
        }
        let (s, c) = f64::sin_cos(angle);
        assert!(
            (r.0 - c).abs() < 1e-11 && (r.1 - s).abs() < 1e-11,
            "{r:?} vs {c}, {s}"
        );
        let big = rotate_by((1.0, 0.0), 0.5);
        assert!((big.0 - 0.5f64.cos()).abs() < 1e-15);
    }
}
