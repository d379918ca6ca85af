use serde::{Deserialize, Serialize};

use super::contacts::{Body, ContactRecord, Incidence, PairContact};
use super::energy::Energies;
use super::sleep::Dormancy;
use super::time_step::{critical_time_step, default_time_step};
use crate::broad_phase::VerletList;
use crate::dynamics::{ContactLaw, Grains, PlateFriction, Wall};
use crate::error::SimError;
use crate::math::Vec2;
use crate::query::{SubContact, core_core_sub_contacts, core_wall_sub_contacts};
use crate::shape::Spheropolygon;
use smallvec::SmallVec;

/// Engine settings that hold for a whole run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorldSettings {
    pub law: ContactLaw,
    /// Acceleration of gravity (m/s^2).
    pub gravity: Vec2,
    /// Time step (s). `None`: 1/400 of the binary collision of the lightest grains.
    pub time_step: Option<f64>,
    /// Verlet skin as a fraction of the smallest grain's bounding radius.
    pub skin_fraction: f64,
    /// Coulomb coefficient between a grain and a wall or fixed grain. `None`: the law's
    /// `friction`, as between two grains. Walls of another material than the grains (the
    /// experiment's steel walls against steel nuts, or a lined wall) have their own.
    pub wall_friction: Option<f64>,
    /// Friction of the plates in front of and behind a quasi-2D cell on every mobile grain;
    /// `None` for a truly two-dimensional system.
    pub plate_friction: Option<PlateFriction>,
}

impl Default for WorldSettings {
    fn default() -> Self {
        Self {
            law: ContactLaw::default(),
            gravity: Vec2::new(0.0, -10.0),
            time_step: None,
            skin_fraction: 0.2,
            wall_friction: None,
            plate_friction: None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ShapeId(pub usize);

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct GrainId(pub usize);

/// Position and velocity of one grain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GrainState {
    pub position: Vec2,
    pub angle: f64,
    pub velocity: Vec2,
    pub angular_velocity: f64,
}

impl GrainState {
    pub fn at_rest(position: Vec2, angle: f64) -> Self {
        Self {
            position,
            angle,
            velocity: Vec2::zeros(),
            angular_velocity: 0.0,
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct ShapeEntry {
    pub shape: Spheropolygon,
    pub mass: f64,
    pub inertia: f64,
}

/// Grains, walls and the contacts between them, advanced in time by [`World::step`].
///
/// Serialises whole (neighbour lists, contact histories, force buffers included), so a world
/// read back continues bit for bit as the one written would have.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct World {
    pub(crate) settings: WorldSettings,
    /// The contact law between a grain and a wall or fixed grain: the grains' law with the
    /// walls' friction.
    pub(crate) wall_law: ContactLaw,
    pub(crate) shapes: Vec<ShapeEntry>,
    pub(crate) grains: Grains,
    pub(crate) walls: Vec<Wall>,
    pub(crate) dt: f64,
    pub(crate) time: f64,
    pub(crate) steps: u64,
    /// Grains in the world (fixed ones too), summed over the steps: the work a run did,
    /// whatever its grain count at each step.
    pub(crate) grain_steps: u64,
    /// Slots per grain in the placed arrays: the most core vertices of any shape.
    pub(crate) stride: usize,
    pub(crate) placed_vertices: Vec<Vec2>,
    pub(crate) placed_directions: Vec<Vec2>,
    pub(crate) reach: Vec<f64>,
    /// Distance of the farthest core vertex from the centre.
    pub(crate) arm: Vec<f64>,
    pub(crate) mobile: Vec<bool>,
    /// How far any point of each grain may have moved since it was added (m, an upper bound,
    /// growing step by step): a pair found apart by a gap need not be looked at again until
    /// its two grains have together travelled that far.
    pub(crate) travel: Vec<f64>,
    /// Each grain's slip against the plates of a quasi-2D cell (m; the stretch of the plates'
    /// friction spring, zero without plate friction).
    pub(crate) plate_slip: Vec<Vec2>,
    pub(crate) skin: f64,
    pub(crate) verlet: VerletList,
    pub(crate) pair_contacts: Vec<PairContact>,
    pub(crate) wall_contacts: Vec<PairContact>,
    pub(crate) pair_push: Vec<[super::step::Push; 2]>,
    pub(crate) wall_push: Vec<super::step::Push>,
    /// The contact lists were re-indexed since the pushes were last written: the pushes of
    /// contacts at rest must be copied again.
    pub(crate) pushes_stale: bool,
    pub(crate) pair_incidence: Incidence,
    pub(crate) wall_incidence: Incidence,
    pub(crate) forces_ready: bool,
    /// Switching energy of pairs no longer in the Verlet list.
    pub(crate) switching_dropped: f64,
    pub(crate) dormancy: Dormancy,
    /// Rate (1/s) at which grains touching something lose their velocity (0: no drag).
    pub(crate) drag: f64,
    /// Smallest piece of a parallel pass given to one thread (`usize::MAX`: one thread).
    pub(crate) min_len: usize,
    /// A one-thread pool that runs steps with few awake grains without handing each pass to
    /// another thread (made when first needed; not saved: a world read back makes its own, and
    /// the results do not depend on the thread count).
    #[serde(skip)]
    pub(crate) serial_pool: Option<std::sync::Arc<rayon::ThreadPool>>,
}

impl World {
    pub fn new(settings: WorldSettings) -> Result<Self, SimError> {
        settings.law.validate()?;
        for (field, value) in [
            ("gravity", settings.gravity.x),
            ("gravity", settings.gravity.y),
        ] {
            if !value.is_finite() {
                return Err(SimError::BadParameter {
                    field,
                    value,
                    expected: "expected finite components (m/s^2)",
                });
            }
        }
        if let Some(dt) = settings.time_step {
            if !(dt.is_finite() && dt > 0.0) {
                return Err(SimError::BadParameter {
                    field: "time_step",
                    value: dt,
                    expected: "expected a positive time step in seconds",
                });
            }
        }
        if let Some(mu) = settings.wall_friction {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(SimError::BadParameter {
                    field: "wall_friction",
                    value: mu,
                    expected: "expected a finite number >= 0",
                });
            }
        }
        if let Some(plates) = &settings.plate_friction {
            plates.validate()?;
        }
        if !(settings.skin_fraction.is_finite() && settings.skin_fraction > 0.0) {
            return Err(SimError::BadParameter {
                field: "skin_fraction",
                value: settings.skin_fraction,
                expected: "expected a positive fraction of the grain's reach",
            });
        }
        let wall_law = ContactLaw {
            friction: settings.wall_friction.unwrap_or(settings.law.friction),
            ..settings.law
        };
        Ok(Self {
            settings,
            wall_law,
            shapes: Vec::new(),
            grains: Grains::default(),
            walls: Vec::new(),
            dt: settings.time_step.unwrap_or(f64::INFINITY),
            time: 0.0,
            steps: 0,
            grain_steps: 0,
            stride: 0,
            placed_vertices: Vec::new(),
            placed_directions: Vec::new(),
            reach: Vec::new(),
            arm: Vec::new(),
            mobile: Vec::new(),
            travel: Vec::new(),
            plate_slip: Vec::new(),
            skin: f64::INFINITY,
            verlet: VerletList::default(),
            pair_contacts: Vec::new(),
            wall_contacts: Vec::new(),
            pair_push: Vec::new(),
            wall_push: Vec::new(),
            pushes_stale: true,
            pair_incidence: Incidence::default(),
            wall_incidence: Incidence::default(),
            forces_ready: false,
            switching_dropped: 0.0,
            dormancy: Dormancy::default(),
            drag: 0.0,
            min_len: 1,
            serial_pool: None,
        })
    }

    /// Registers a grain outline with its areal density (kg/m^2). Refuses a set time step
    /// above the stability bound of this grain.
    pub fn add_shape(
        &mut self,
        shape: Spheropolygon,
        areal_density: f64,
    ) -> Result<ShapeId, SimError> {
        let (mass, inertia) = shape.mass_properties(areal_density)?;
        let critical =
            critical_time_step(&self.settings.law, mass, inertia, shape.bounding_radius());
        match self.settings.time_step {
            Some(dt) if dt > critical => return Err(SimError::TimeStepTooLarge { dt, critical }),
            Some(_) => {}
            None => self.dt = self.dt.min(default_time_step(&self.settings.law, mass)),
        }
        self.skin = self
            .skin
            .min(self.settings.skin_fraction * shape.bounding_radius());
        if shape.vertices().len() > self.stride {
            self.stride = shape.vertices().len();
            let slots = self.grains.len() * self.stride;
            self.placed_vertices.resize(slots, Vec2::zeros());
            self.placed_directions.resize(slots, Vec2::zeros());
        }
        self.shapes.push(ShapeEntry {
            shape,
            mass,
            inertia,
        });
        Ok(ShapeId(self.shapes.len() - 1))
    }

    /// Adds a mobile grain; its force starts as its weight until the next step finds contacts.
    pub fn add_grain(&mut self, shape: ShapeId, state: GrainState) -> Result<GrainId, SimError> {
        self.push_grain(shape, state, true)
    }

    /// Adds a grain that never moves (walls built of grains, obstacles).
    pub fn add_fixed_grain(
        &mut self,
        shape: ShapeId,
        position: Vec2,
        angle: f64,
    ) -> Result<GrainId, SimError> {
        self.push_grain(shape, GrainState::at_rest(position, angle), false)
    }

    fn push_grain(
        &mut self,
        shape: ShapeId,
        state: GrainState,
        mobile: bool,
    ) -> Result<GrainId, SimError> {
        let entry = self
            .shapes
            .get(shape.0)
            .ok_or(SimError::UnknownShape(shape.0))?;
        let values = [
            ("position", state.position.x),
            ("position", state.position.y),
            ("angle", state.angle),
            ("velocity", state.velocity.x),
            ("velocity", state.velocity.y),
            ("angular_velocity", state.angular_velocity),
        ];
        for (field, value) in values {
            if !value.is_finite() {
                return Err(SimError::BadParameter {
                    field,
                    value,
                    expected: "expected a finite number",
                });
            }
        }
        let g = &mut self.grains;
        g.shape.push(shape.0 as u32);
        g.position.push(state.position);
        g.angle.push(state.angle);
        g.rotation.push(unit(state.angle));
        g.mass.push(entry.mass);
        g.inertia.push(entry.inertia);
        if mobile {
            g.velocity.push(state.velocity);
            g.angular_velocity.push(state.angular_velocity);
            g.inverse_mass.push(1.0 / entry.mass);
            g.inverse_inertia.push(1.0 / entry.inertia);
            g.force.push(self.settings.gravity * entry.mass);
        } else {
            g.velocity.push(Vec2::zeros());
            g.angular_velocity.push(0.0);
            g.inverse_mass.push(0.0);
            g.inverse_inertia.push(0.0);
            g.force.push(Vec2::zeros());
        }
        g.torque.push(0.0);
        self.placed_vertices
            .extend(std::iter::repeat_n(Vec2::zeros(), self.stride));
        self.placed_directions
            .extend(std::iter::repeat_n(Vec2::zeros(), self.stride));
        self.reach.push(entry.shape.bounding_radius());
        self.arm
            .push(entry.shape.bounding_radius() - entry.shape.radius());
        self.mobile.push(mobile);
        self.travel.push(0.0);
        self.plate_slip.push(Vec2::zeros());
        self.dormancy.push(mobile, state.position, state.angle);
        let i = self.grains.len() - 1;
        self.place_core(i);
        Ok(GrainId(i))
    }

    pub fn add_wall(&mut self, wall: Wall) -> Result<usize, SimError> {
        let values = [wall.point.x, wall.point.y, wall.normal.x, wall.normal.y];
        if values.iter().any(|v| !v.is_finite()) || wall.normal.norm() == 0.0 {
            return Err(SimError::BadParameter {
                field: "wall",
                value: f64::NAN,
                expected: "expected a finite point and a non-zero normal",
            });
        }
        self.walls.push(wall);
        // Force the Verlet list to pick the new wall up.
        self.verlet = VerletList::default();
        Ok(self.walls.len() - 1)
    }

    pub fn settings(&self) -> &WorldSettings {
        &self.settings
    }

    pub fn set_gravity(&mut self, gravity: Vec2) {
        self.settings.gravity = gravity;
    }

    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// Changes the time step, refused above the stability bound of any grain shape.
    pub fn set_time_step(&mut self, dt: f64) -> Result<(), SimError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(SimError::BadParameter {
                field: "time_step",
                value: dt,
                expected: "expected a positive time step in seconds",
            });
        }
        let critical = self.critical_time_step();
        if dt > critical {
            return Err(SimError::TimeStepTooLarge { dt, critical });
        }
        self.dt = dt;
        Ok(())
    }

    /// Slows every grain that touches something at `rate` (1/s): its velocity and angular
    /// velocity decay as exp(-rate t) on top of what the forces do. Grains in free flight are
    /// not slowed. Zero (the default) turns it off.
    ///
    /// The contact law damps a pile's low modes hardly at all (a column rings for seconds at
    /// restitution 0.9); this drag brings a deposit to rest in a few tenths of a second
    /// without moving where it rests: the drag vanishes with the velocities.
    pub fn set_drag(&mut self, rate: f64) -> Result<(), SimError> {
        if !(rate.is_finite() && rate >= 0.0) {
            return Err(SimError::BadParameter {
                field: "drag",
                value: rate,
                expected: "expected a rate >= 0 in 1/s",
            });
        }
        self.drag = rate;
        Ok(())
    }

    pub fn drag(&self) -> f64 {
        self.drag
    }

    /// The smallest stability bound over the registered shapes (infinite with none).
    pub fn critical_time_step(&self) -> f64 {
        self.shapes
            .iter()
            .map(|s| {
                critical_time_step(
                    &self.settings.law,
                    s.mass,
                    s.inertia,
                    s.shape.bounding_radius(),
                )
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Bytes held by the world's arrays (grain state, placed cores, neighbour lists, contacts).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let g = &self.grains;
        let per_grain = g.position.capacity() * (3 * size_of::<Vec2>())
            + g.angle.capacity() * (8 * size_of::<f64>())
            + g.shape.capacity() * size_of::<u32>()
            + (self.reach.capacity() + self.arm.capacity() + self.travel.capacity())
                * size_of::<f64>()
            + self.mobile.capacity();
        let placed = (self.placed_vertices.capacity() + self.placed_directions.capacity())
            * size_of::<Vec2>();
        let lists = self.verlet.memory_bytes()
            + (self.pair_contacts.capacity() + self.wall_contacts.capacity())
                * size_of::<PairContact>()
            + self.pair_incidence.memory_bytes()
            + self.wall_incidence.memory_bytes();
        per_grain + placed + lists
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Grains in the world, summed over the steps. Over a run's wall time it gives the run's
    /// throughput in the engine benchmark's unit (grain-steps per second).
    pub fn grain_steps(&self) -> u64 {
        self.grain_steps
    }

    /// Grain pairs and grain-wall pairs in the Verlet lists.
    pub fn neighbour_pairs(&self) -> (usize, usize) {
        (self.verlet.pairs.len(), self.verlet.wall_pairs.len())
    }

    pub fn verlet_rebuilds(&self) -> u64 {
        self.verlet.rebuilds
    }

    pub fn len(&self) -> usize {
        self.grains.len()
    }

    pub fn is_empty(&self) -> bool {
        self.grains.is_empty()
    }

    pub fn grains(&self) -> &Grains {
        &self.grains
    }

    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    pub fn shape(&self, id: ShapeId) -> &Spheropolygon {
        &self.shapes[id.0].shape
    }

    pub fn shape_of(&self, grain: usize) -> ShapeId {
        ShapeId(self.grains.shape[grain] as usize)
    }

    pub fn grain(&self, i: usize) -> GrainState {
        let g = &self.grains;
        GrainState {
            position: g.position[i],
            angle: g.angle[i],
            velocity: g.velocity[i],
            angular_velocity: g.angular_velocity[i],
        }
    }

    /// Sets a grain's position and velocity (e.g. to place a grain at rest by hand).
    pub fn set_grain(&mut self, i: usize, state: GrainState) {
        let g = &mut self.grains;
        // A turn moves a vertex by at most twice its arm.
        self.travel[i] += (state.position - g.position[i]).norm() + 2.0 * self.arm[i];
        g.position[i] = state.position;
        g.angle[i] = state.angle;
        g.rotation[i] = unit(state.angle);
        if self.mobile[i] {
            g.velocity[i] = state.velocity;
            g.angular_velocity[i] = state.angular_velocity;
            // A grain moved by hand may now overlap sleeping ones: it and the list wake up.
            self.dormancy.awake[i] = true;
            self.dormancy.quiet_steps[i] = 0;
            self.dormancy.woken = true;
        }
        self.place_core(i);
    }

    /// Every sub-contact at the last force evaluation. Normals and contact points are found
    /// again by the narrow phase on the placed cores (the grains have not moved since).
    pub fn contacts(&self) -> impl Iterator<Item = ContactRecord> + '_ {
        let pairs = self
            .verlet
            .pairs
            .iter()
            .zip(&self.pair_contacts)
            .filter(|(_, c)| !c.subs.is_empty())
            .flat_map(move |([i, j], c)| {
                let (first, second) = (self.placed(*i as usize), self.placed(*j as usize));
                let mut found: SmallVec<[SubContact; 4]> = SmallVec::new();
                let previous = || c.subs.iter().map(|s| s.features);
                core_core_sub_contacts(&first, &second, previous, &mut found);
                records(
                    *i as usize,
                    Body::Grain(*j as usize),
                    c,
                    found,
                    &self.settings.law,
                )
            });
        let walls = self
            .verlet
            .wall_pairs
            .iter()
            .zip(&self.wall_contacts)
            .filter(|(_, c)| !c.subs.is_empty())
            .flat_map(move |([i, k], c)| {
                let mut found: SmallVec<[SubContact; 4]> = SmallVec::new();
                core_wall_sub_contacts(
                    &self.placed(*i as usize),
                    &self.walls[*k as usize],
                    &mut found,
                );
                records(
                    *i as usize,
                    Body::Wall(*k as usize),
                    c,
                    found,
                    &self.settings.law,
                )
            });
        pairs.chain(walls)
    }

    /// The contact law between grains `i` and `j`: a fixed grain is part of a wall.
    #[inline]
    pub(crate) fn law_between(&self, i: usize, j: usize) -> &ContactLaw {
        if self.mobile[i] && self.mobile[j] {
            &self.settings.law
        } else {
            &self.wall_law
        }
    }

    /// Total force the grains exert on the plates of a quasi-2D cell (zero without plate
    /// friction): what the plates' friction holds of the grains' weight.
    pub fn plate_load(&self) -> Vec2 {
        let Some(plates) = &self.settings.plate_friction else {
            return Vec2::zeros();
        };
        let g = &self.grains;
        let gravity = self.settings.gravity.norm();
        (0..g.len())
            .filter(|&i| self.mobile[i])
            .map(|i| {
                let (push, _) = plates.force(
                    &self.settings.law,
                    g.mass[i],
                    gravity,
                    g.velocity[i],
                    self.plate_slip[i],
                    0.0,
                );
                -push
            })
            .sum()
    }

    /// Total force the grains exert on wall `k`.
    pub fn wall_load(&self, k: usize) -> Vec2 {
        self.verlet
            .wall_pairs
            .iter()
            .zip(&self.wall_contacts)
            .filter(|(p, _)| p[1] as usize == k)
            .map(|(_, c)| -c.force)
            .sum()
    }

    pub fn energies(&self) -> Energies {
        let g = &self.grains;
        let mut e = Energies::default();
        for i in 0..g.len() {
            if self.mobile[i] {
                e.kinetic += 0.5 * g.mass[i] * g.velocity[i].norm_squared()
                    + 0.5 * g.inertia[i] * g.angular_velocity[i].powi(2);
                e.potential -= g.mass[i] * self.settings.gravity.dot(&g.position[i]);
            }
        }
        let law = &self.settings.law;
        e.switching = self.switching_dropped;
        for c in self.pair_contacts.iter().chain(&self.wall_contacts) {
            e.switching += c.switched;
            for s in &c.subs {
                e.elastic += s.elastic_energy(law);
            }
        }
        e
    }
}

/// The records of one pair's stored sub-contacts, with the normals and points of `found`.
fn records<'a>(
    first: usize,
    second: Body,
    contact: &'a PairContact,
    found: SmallVec<[SubContact; 4]>,
    law: &'a ContactLaw,
) -> impl Iterator<Item = ContactRecord> + 'a {
    contact.subs.iter().filter_map(move |s| {
        let geometry = found.iter().find(|f| f.features == s.features)?;
        // A corner sharing its zone with another carries -U grad(w) besides its weighted law
        // (PairContact::resolve): the force the grain feels, which the walls' loads and the
        // stress must see whole.
        let mut force = s.force(geometry.normal);
        if geometry.weight < 1.0 {
            force -= geometry.weight_gradient.position * law.elastic_energy(geometry.overlap, 0.0);
        }
        Some(ContactRecord {
            first,
            second,
            force,
            point: geometry.point,
            normal: geometry.normal,
            overlap: s.overlap,
            displacement: s.displacement,
        })
    })
}

/// (cos, sin) of an angle.
fn unit(angle: f64) -> (f64, f64) {
    let (sin, cos) = angle.sin_cos();
    (cos, sin)
}
