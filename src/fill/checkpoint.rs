//! Checkpoints of a fill: the whole world (neighbour lists and contact histories included), the
//! feeder's place in its random stream and the fill loop's own state, so that a resumed run
//! writes the same files as an uninterrupted one.
//!
//! File layout: the line `facets checkpoint`, then in postcard (serde, little-endian, f64 as
//! its 8 bytes) a header (facets version, scene hash, seed) and the body. The header is read
//! first, so a checkpoint of another version or scene is refused with a message, not a decoding
//! error.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, bail};
use serde::{Deserialize, Serialize};
use sim::World;

use super::feeder::FeederState;
use super::run::FillState;
use super::silo::Silo;
use crate::io::write_atomic;
use crate::scene::Scene;

const MAGIC: &[u8] = b"facets checkpoint\n";

/// The name of the checkpoint in a run's folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Header {
    facets_version: String,
    scene_hash: u64,
    seed: u64,
}

/// The body as written, borrowing the world rather than copying it.
#[derive(Serialize)]
struct BodyRef<'a> {
    scene: &'a Scene,
    world: &'a World,
    feeder: FeederState,
    fill: &'a FillState,
}

/// The body as read; same fields in the same order as [`BodyRef`].
#[derive(Deserialize)]
struct BodyOwned {
    scene: Scene,
    world: World,
    feeder: FeederState,
    fill: FillState,
}

/// A fill stopped part-way, read from a checkpoint file.
pub struct Checkpoint {
    header: Header,
    scene: Scene,
    world: World,
    feeder: FeederState,
    fill: FillState,
}

impl std::fmt::Debug for Checkpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Checkpoint")
            .field("header", &self.header)
            .field("steps", &self.world.steps())
            .finish_non_exhaustive()
    }
}

/// FNV-1a (64 bits) of the scene as parsed, re-serialised, followed by the seed: the same for
/// the same scene whatever its file's comments, layout or defaults left out.
pub fn scene_hash(scene: &Scene, seed: u64) -> u64 {
    let mut bytes = postcard::to_stdvec(scene).expect("a scene always serialises");
    bytes.extend_from_slice(&seed.to_le_bytes());
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Writes the checkpoint of a fill atomically.
pub(crate) fn write_checkpoint(
    path: &Path,
    scene: &Scene,
    seed: u64,
    silo: &Silo,
    fill: &FillState,
) -> anyhow::Result<()> {
    let header = Header {
        facets_version: env!("CARGO_PKG_VERSION").to_string(),
        scene_hash: scene_hash(scene, seed),
        seed,
    };
    let body = BodyRef {
        scene,
        world: &silo.world,
        feeder: silo.feeder.state(),
        fill,
    };
    let header = postcard::to_stdvec(&header)?;
    let body = postcard::to_stdvec(&body)?;
    write_atomic(path, |w| {
        w.write_all(MAGIC)?;
        w.write_all(&header)?;
        w.write_all(&body)?;
        Ok(())
    })
    .with_context(|| format!("cannot write the checkpoint {}", path.display()))
}

impl Checkpoint {
    /// Reads a checkpoint; refuses a file that is not one, or one written by another version
    /// of facets (whose world may not continue with the same bits).
    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let bytes = std::fs::read(path)
            .with_context(|| format!("cannot read the checkpoint {}", path.display()))?;
        let Some(rest) = bytes.strip_prefix(MAGIC) else {
            bail!(
                "{} is not a facets checkpoint (it does not start with `facets checkpoint`)",
                path.display()
            );
        };
        let (header, rest): (Header, _) = postcard::take_from_bytes(rest)
            .with_context(|| format!("{}: the checkpoint's header is corrupt", path.display()))?;
        let version = env!("CARGO_PKG_VERSION");
        if header.facets_version != version {
            bail!(
                "{} was written by facets {}, this is facets {version}: a checkpoint resumes only with the version that wrote it",
                path.display(),
                header.facets_version
            );
        }
        let body: BodyOwned = postcard::from_bytes(rest).with_context(|| {
            format!(
                "{}: the checkpoint is truncated or corrupt, or was written by another build of facets {version} whose scene or world had other fields (the body's layout is not versioned between releases): rerun from the start",
                path.display()
            )
        })?;
        Ok(Self {
            header,
            scene: body.scene,
            world: body.world,
            feeder: body.feeder,
            fill: body.fill,
        })
    }

    /// The seed of the run the checkpoint belongs to.
    pub fn seed(&self) -> u64 {
        self.header.seed
    }

    /// The world as it stood (for diagnostics; a run continues it with `--resume`).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Simulated time (s) and steps done at the checkpoint.
    pub fn progress(&self) -> (f64, u64) {
        (self.world.time(), self.world.steps())
    }

    /// Refuses to continue the checkpoint as the run of another scene or seed, naming both
    /// and what differs.
    pub fn check_matches(&self, scene: &Scene, seed: u64) -> anyhow::Result<()> {
        let hash = scene_hash(scene, seed);
        if hash == self.header.scene_hash && seed == self.header.seed && *scene == self.scene {
            return Ok(());
        }
        let s = &self.scene;
        let mut differ: Vec<&str> = [
            ("[silo]", s.silo == scene.silo),
            ("[grains]", s.grains == scene.grains),
            ("[feed]", s.feed == scene.feed),
            ("[contact]", s.contact == scene.contact),
            ("[run]", s.run == scene.run),
            ("[output]", s.output == scene.output),
        ]
        .into_iter()
        .filter(|(_, same)| !same)
        .map(|(name, _)| name)
        .collect();
        if seed != self.header.seed {
            differ.push("the seed");
        }
        bail!(
            "the checkpoint belongs to seed {} of scene {:016x}, this run is seed {seed} of scene {hash:016x} (they differ in {}): resume with the scene and seed that wrote it",
            self.header.seed,
            self.header.scene_hash,
            differ.join(", ")
        )
    }

    /// Puts the checkpoint's world and feeder into a silo built from the same scene and seed,
    /// and returns the fill loop's state.
    pub(crate) fn restore(self, silo: &mut Silo) -> FillState {
        silo.world = self.world;
        silo.feeder.restore(&self.feeder);
        self.fill
    }
}
