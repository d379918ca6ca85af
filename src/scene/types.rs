use serde::{Deserialize, Serialize};
use sim::ContactLaw;

use crate::grains::{DEFAULT_ROUNDING, GrainKind};

const MM: f64 = 1e-3;

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(default)]
    pub silo: SiloSection,
    pub grains: GrainSection,
    pub feed: FeedSection,
    #[serde(default)]
    pub contact: ContactSection,
    #[serde(default)]
    pub run: RunSection,
    #[serde(default)]
    pub plates: PlatesSection,
    #[serde(default)]
    pub model: ModelSection,
    #[serde(default)]
    pub output: OutputSection,
}

/// `[silo]`: the box the grains fill.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SiloSection {
    /// Distance between the side walls (mm); the paper's simulations use 256 mm.
    pub width_mm: f64,
    /// Height of the side walls (mm); a deposit reaching above it is reported as overflowing.
    pub height_mm: f64,
    /// How the floor and side walls are built: "rough" (the default: fixed grains of the
    /// scene's shape at random orientations, set back by random depths up to `roughness_mm`,
    /// walls of fixed particles as the study's), "flat" (half-planes with the grains' contact
    /// law) or "grains" (fixed grains of the scene's shape laid edge to edge: flat faces).
    /// A flat wall holds a grain by friction alone, a rough one also by the slopes of its
    /// grains' faces: the deposit's load on the walls depends on it (docs/model.md).
    pub walls: WallKind,
    /// "rough" walls only: the largest depth by which a wall grain is set back behind the
    /// wall's line (mm, >= 0). Default: the grain's width D. Zero still leaves the unevenness
    /// of grains at random orientations (their corners).
    pub roughness_mm: Option<f64>,
}

impl Default for SiloSection {
    fn default() -> Self {
        Self {
            width_mm: 256.0,
            height_mm: 750.0,
            walls: WallKind::Rough,
            roughness_mm: None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WallKind {
    /// Floor and side walls are half-planes.
    Flat,
    /// Floor and side walls are rows of fixed grains of the scene's shape, long side along the
    /// wall, their inner faces on the silo's outline (x = 0, x = W, y = 0).
    Grains,
    /// Floor and side walls are fixed grains of the scene's shape at random orientations, set
    /// back behind the silo's outline by random depths up to `roughness_mm`.
    Rough,
}

/// `[grains]`: one kind of grain, with optional overrides of the kind's outline and density.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrainSection {
    /// "square" (6.9 x 6.9 mm nut), "rod53" (4.9 x 3 mm) or "rod3" (8.9 x 3 mm).
    pub kind: GrainKind,
    /// Number of grains poured.
    pub count: usize,
    /// Outline length L, the long side (mm). Default: the kind's.
    #[serde(default)]
    pub length_mm: Option<f64>,
    /// Outline width D, the short side (mm). Default: the kind's.
    #[serde(default)]
    pub width_mm: Option<f64>,
    /// Rounding radius as a fraction of the width D (dimensionless). Default 0.05.
    #[serde(default)]
    pub rounding_fraction: Option<f64>,
    /// Mass per outline area (kg/m^2). Default: nuts 20.3, rods 18.5 (docs/model.md §2).
    #[serde(default)]
    pub areal_density_kg_m2: Option<f64>,
}

impl GrainSection {
    pub fn grain_kind(&self) -> GrainKind {
        self.kind
    }

    /// Length L (m).
    pub fn length(&self) -> f64 {
        self.length_mm
            .map_or_else(|| self.grain_kind().length(), |v| v * MM)
    }

    /// Width D (m).
    pub fn width(&self) -> f64 {
        self.width_mm
            .map_or_else(|| self.grain_kind().width(), |v| v * MM)
    }

    pub fn rounding(&self) -> f64 {
        self.rounding_fraction.unwrap_or(DEFAULT_ROUNDING)
    }

    pub fn areal_density(&self) -> f64 {
        self.areal_density_kg_m2
            .unwrap_or_else(|| self.grain_kind().areal_density())
    }
}

/// `[feed]`: the rain of grains.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeedSection {
    /// Volume (area) fraction of the falling rain (dimensionless, 0 < phi0 < 1).
    pub phi0: f64,
    /// Downward speed of the inserted grains (m/s). Default 3.5, the speed measured where the
    /// deposit forms.
    #[serde(default = "default_speed")]
    pub speed_m_s: f64,
    /// "surface": the insertion band follows the free surface at `gap_mm` (no long fall is
    /// simulated); "fixed": the band stays at `fixed_height_mm`.
    #[serde(default)]
    pub insertion: Insertion,
    /// Gap between the free surface (the top of the highest settled grain) and the bottom of
    /// the insertion band (mm), "surface" insertion only. Default 20.
    #[serde(default = "default_gap")]
    pub gap_mm: f64,
    /// Height of the insertion band's bottom above the floor (mm), "fixed" insertion only.
    /// Default: the silo height less the band height.
    #[serde(default)]
    pub fixed_height_mm: Option<f64>,
    /// Height of the insertion band (mm). Default: four bounding diameters of the grain.
    #[serde(default)]
    pub band_height_mm: Option<f64>,
    /// Spread of the inserted grains' velocity, as a fraction of `speed_m_s`: each component gets
    /// an independent uniform kick in [-s, s] x speed. Default 0 (all fall straight down at the
    /// inflow speed). Grains leaving a hopper collide on their way down and arrive scattered.
    #[serde(default)]
    pub speed_spread: f64,
    /// Largest spin of the inserted grains (rad/s): each spins at a uniform rate in
    /// [-spin, spin]. Default 0.
    #[serde(default)]
    pub spin_rad_s: f64,
}

fn default_speed() -> f64 {
    3.5
}

fn default_gap() -> f64 {
    20.0
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Insertion {
    #[default]
    Surface,
    Fixed,
}

/// `[contact]`: the contact law of docs/model.md §2 and gravity. Defaults are the paper's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSection {
    /// k_N (N/m).
    #[serde(rename = "normal_stiffness_N_m")]
    pub normal_stiffness: f64,
    /// k_T (N/m).
    #[serde(rename = "tangential_stiffness_N_m")]
    pub tangential_stiffness: f64,
    /// gamma_N (1/s).
    #[serde(rename = "normal_damping_1_s")]
    pub normal_damping: f64,
    /// gamma_T (1/s).
    #[serde(rename = "tangential_damping_1_s")]
    pub tangential_damping: f64,
    /// Coulomb friction coefficient mu (dimensionless) between grains, and between grains and
    /// walls unless `wall_friction` is given.
    pub friction: f64,
    /// Coulomb friction coefficient between a grain and the floor or a side wall, flat or built
    /// of fixed grains (dimensionless). Default: `friction`.
    pub wall_friction: Option<f64>,
    /// Acceleration of gravity (m/s^2), pointing down.
    pub gravity_m_s2: f64,
}

impl Default for ContactSection {
    fn default() -> Self {
        let law = ContactLaw::default();
        Self {
            normal_stiffness: law.normal_stiffness,
            tangential_stiffness: law.tangential_stiffness,
            normal_damping: law.normal_damping,
            tangential_damping: law.tangential_damping,
            friction: law.friction,
            wall_friction: None,
            gravity_m_s2: 10.0,
        }
    }
}

impl ContactSection {
    pub fn law(&self) -> ContactLaw {
        ContactLaw {
            normal_stiffness: self.normal_stiffness,
            tangential_stiffness: self.tangential_stiffness,
            normal_damping: self.normal_damping,
            tangential_damping: self.tangential_damping,
            friction: self.friction,
        }
    }
}

/// `[plates]`: friction of the glass plates in front of and behind the experiment's
/// quasi-2D cell on every grain sliding between them. Off by default: the study's simulations
/// are two-dimensional.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlatesSection {
    /// "none", "coulomb" (dry friction: `friction` times a normal load of `load_fraction` of
    /// the grain's weight, with the contact law's tangential spring and damper, so it also
    /// holds a grain at rest) or "viscous" (a force -`drag_per_s` m v).
    pub law: PlateLaw,
    /// Coulomb coefficient between a grain and the plates (dimensionless), "coulomb" only.
    pub friction: Option<f64>,
    /// Normal load pressing a grain on the plates as a fraction of its weight
    /// (dimensionless), "coulomb" only: a grain tilted between the plates or wedged by its
    /// neighbours presses on them; nothing in a 2D model sets how hard.
    pub load_fraction: Option<f64>,
    /// Rate of the viscous law (1/s), "viscous" only.
    pub drag_per_s: Option<f64>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlateLaw {
    #[default]
    None,
    Coulomb,
    Viscous,
}

impl PlatesSection {
    /// The engine's plate friction (`None` for "none"); the scene must have been validated.
    pub fn friction_model(&self) -> Option<sim::PlateFriction> {
        match self.law {
            PlateLaw::None => None,
            PlateLaw::Coulomb => Some(sim::PlateFriction::Coulomb {
                coefficient: self.friction.unwrap_or(0.0),
                load_fraction: self.load_fraction.unwrap_or(0.0),
            }),
            PlateLaw::Viscous => Some(sim::PlateFriction::Viscous {
                rate: self.drag_per_s.unwrap_or(0.0),
            }),
        }
    }
}

/// `[run]`: seed, time step and when to stop.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunSection {
    /// Seed of the feeder's random positions and orientations (`--seed` overrides it).
    pub seed: u64,
    /// Time step (s). Default: none, and `[model] steps_per_collision` sets it (t_c / 10).
    pub time_step_s: Option<f64>,
    /// The deposit is relaxed when its mean kinetic energy is below this fraction of the mean
    /// elastic energy in the contacts (dimensionless). Default 1e-4 (docs/model.md §2).
    pub relaxation_ratio: f64,
    /// The window of the means above (s of simulated time), checks every `check_interval_s`:
    /// a deposit oscillating as a whole passes through turning points where its kinetic energy
    /// is small but its forces are out of balance; one check there would stop it too early.
    pub relaxation_hold_s: f64,
    /// Relaxed also needs the floor and walls to carry the grains' weight to within this
    /// fraction (dimensionless): a deposit oscillating as a whole meets the energy criterion
    /// at small sizes while its net force is still out of balance. Default 0.005.
    pub load_balance: f64,
    /// Simulated time allowed for relaxation after the last grain is in (s); a deposit still
    /// moving then is written and reported as not relaxed.
    pub max_relaxation_time_s: f64,
    /// Interval between two relaxation checks (s of simulated time).
    pub check_interval_s: f64,
}

impl Default for RunSection {
    fn default() -> Self {
        Self {
            seed: 1,
            time_step_s: None,
            relaxation_ratio: 1e-4,
            relaxation_hold_s: 0.05,
            load_balance: 0.005,
            max_relaxation_time_s: 10.0,
            check_interval_s: 1e-3,
        }
    }
}

/// `[model]`: what the run may leave out to go faster. Each switch is measured against the
/// paper-faithful settings (dt = 1e-6 s, every grain integrated every step) by
/// `facets bench fill`; the defaults are the fastest settings within two standard errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModelSection {
    /// Time step as steps per binary collision of two grains (dimensionless): dt = t_c / n,
    /// t_c = 0.69 ms for the nuts. Ignored when `[run] time_step_s` is set. The paper's 1e-6 s
    /// is n = 690 for nuts. Default 10 (dt = 69 us for nuts, 0.16 of the stability
    /// bound t_c / 1.57): with the late relaxation drag, on the reference scenes of
    /// `facets bench fill` it is 40-79 x faster than the paper's step (1.2 x fewer steps than
    /// n = 12), with every observable within 2 standard errors of the paper-faithful ensemble
    /// (largest: 1.75, the pressure profile of squares at phi0 = 0.25) and the packing
    /// fraction's shift pooled over the scenes -1.36 (n = 12: -0.54; n = 8: -2.07, refused).
    pub steps_per_collision: f64,
    /// Grains at rest stop being integrated until a neighbour disturbs them. Off by default:
    /// during a fill the deposit rings (restitution 0.9), so by speed hardly a grain falls
    /// asleep, and by drift (`sleep_drift_mm`) the bench's 150-grain deposits are too shallow
    /// to leave anything out: `facets bench fill` measured no gain either way.
    pub sleep: bool,
    /// A grain may sleep when its centre and corners move slower than this (m/s) ...
    pub sleep_speed_m_s: f64,
    /// ... with its net force below this fraction of its weight (dimensionless; 1 excludes
    /// only grains in free flight: a deposit under a rain of grains rings, and its grains are
    /// rarely in balance) ...
    pub sleep_force_fraction: f64,
    /// ... and its centre and corners within this distance of where they stood when the
    /// stretch began (mm) ...
    pub sleep_drift_mm: f64,
    /// ... for this long (s). `inf` turns any of the three criteria off.
    pub sleep_quiet_time_s: f64,
    /// A sleeping grain wakes when its net force has changed by this fraction of its weight.
    pub wake_force_fraction: f64,
    /// After the last grain is in, wake every grain and relax with all of them integrated
    /// (true), or let the deposit finish relaxing with sleep on (false).
    pub wake_to_relax: bool,
    /// After the last grain is in, grains touching something lose their velocity at this rate
    /// (1/s) on top of the contact law's damping (0: none), from when `relaxation_drag_below`
    /// says. The contact law hardly damps a deposit's low modes, so a pile creeps and rings
    /// for a second (rods: kinetic/elastic takes 0.7 s to go from 1e-3 to the 1e-4 that ends
    /// the run). Default 200 (kinetic energy falls as exp(-400 t) once it starts).
    pub relaxation_drag_per_s: f64,
    /// The drag starts once the mean kinetic energy (over `[run] relaxation_hold_s`) has
    /// fallen below this fraction of the elastic energy (dimensionless; `inf`: as soon as the
    /// last grain is in). Default 1e-2: the last grains have landed, and the drag only cuts
    /// the deposit's ringing and creep. `facets bench fill` measured the packing fraction,
    /// f(theta), g(r) and the pressure profile of the reference scenes unchanged by it
    /// (settings `n10-earlydrag` (1e-2) and `n10-latedrag` (1e-3) against `n10`: every
    /// deviation equal to the second decimal), and every run relaxed within the bench's 1 s.
    /// Started at once (`inf`) the drag also slows the last grains' landing: the rods'
    /// packing fraction moved by 2.53 standard errors.
    pub relaxation_drag_below: f64,
}

impl Default for ModelSection {
    fn default() -> Self {
        let s = sim::SleepSettings::default();
        Self {
            steps_per_collision: 10.0,
            sleep: false,
            sleep_speed_m_s: s.speed,
            sleep_force_fraction: s.force_fraction,
            sleep_drift_mm: s.drift * 1e3,
            sleep_quiet_time_s: s.quiet_time,
            wake_force_fraction: s.wake_fraction,
            wake_to_relax: true,
            relaxation_drag_per_s: 200.0,
            relaxation_drag_below: 1e-2,
        }
    }
}

impl ModelSection {
    pub fn sleep_settings(&self) -> Option<sim::SleepSettings> {
        self.sleep.then(|| sim::SleepSettings {
            speed: self.sleep_speed_m_s,
            force_fraction: self.sleep_force_fraction,
            drift: self.sleep_drift_mm * 1e-3,
            quiet_time: self.sleep_quiet_time_s,
            wake_fraction: self.wake_force_fraction,
            ..sim::SleepSettings::default()
        })
    }
}

/// `[output]`: what is written besides the deposit, contacts, sidecar, VTK and run record.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSection {
    /// Write a VTK snapshot of the grains every this many steps (none by default).
    pub snapshot_every_steps: Option<u64>,
    /// The frame the analysis reads (sidecar `frame_mm`): "region-e" (the photographed heights
    /// 290-410 mm), "whole" (the whole deposit), or "auto" (region E when the deposit reaches
    /// above it, else the whole deposit).
    pub frame: FrameChoice,
    /// Write `checkpoint.bin` in the run's folder every this many seconds of simulated time
    /// (none by default; Ctrl-C writes one anyway). `facets sim SCENE --resume FILE` continues
    /// it with the same result as an uninterrupted run.
    pub checkpoint_every_s: Option<f64>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrameChoice {
    #[default]
    Auto,
    Whole,
    RegionE,
}
