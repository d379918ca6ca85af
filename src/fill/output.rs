use std::io::Write;
use std::path::Path;

use anyhow::Context;
use sim::{Body, World};

use super::record::RunRecord;
use super::silo::{FLOOR, LEFT_WALL, RIGHT_WALL, Silo};
use super::vtk::{GRAINS_VTK, write_vtk};
use crate::deposit::{
    AnalysedArea, Contact, Deposit, DepositMeta, FrameMm, Grain, Partner, Source, Wall,
    write_contacts_csv, write_deposit_csv, write_meta_json,
};
use crate::io::write_atomic;
use crate::scene::FrameChoice;

/// Heights of the photographed region "E" (docs/model.md §1), mm.
const REGION_E_MM: [f64; 2] = [290.0, 410.0];

/// Refuses an output folder that cannot be created or written, before anything is simulated.
pub fn check_writable(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create the output folder {}", dir.display()))?;
    let probe = dir.join(".facets-write-test");
    write_atomic(&probe, |w| Ok(w.write_all(b"ok")?))
        .with_context(|| format!("the output folder {} is not writable", dir.display()))?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}

/// The poured grains of a silo as a deposit table (x from the left wall, y from the floor,
/// theta folded by the outline's symmetry); fixed wall grains are not part of it.
pub fn deposit_of(silo: &Silo, length: f64, width: f64) -> Deposit {
    let grains = silo
        .deposit_grains()
        .map(|i| pose_of(&silo.world, i, length, width))
        .collect();
    Deposit { grains }
}

/// Grain i of `world` (outline `length` x `width`) as a deposit row: centre and theta folded by
/// the outline's symmetry, as the deposit table and the VTK file write it.
pub(crate) fn pose_of(world: &World, i: usize, length: f64, width: f64) -> Grain {
    let g = world.grain(i);
    Grain::placed(g.position.x, g.position.y, g.angle, length, width).folded()
}

/// One row per sub-contact, the force on the first grain; each touching pair appears once. A
/// contact with a fixed wall grain is one with its wall, the force on the deposit grain.
fn contacts_of(silo: &Silo) -> Vec<Contact> {
    silo.world
        .contacts()
        .map(|c| {
            let (i, other, force) = silo.deposit_side(&c);
            Contact {
                i,
                partner: match other {
                    Body::Grain(j) => Partner::Grain(j),
                    Body::Wall(k) => Partner::Wall(deposit_wall(k)),
                },
                force: [force.x, force.y],
                point: [c.point.x, c.point.y],
            }
        })
        .collect()
}

/// The deposit's name of the silo's wall k (FLOOR, LEFT_WALL or RIGHT_WALL).
pub(crate) fn deposit_wall(k: usize) -> Wall {
    match k {
        LEFT_WALL => Wall::Left,
        RIGHT_WALL => Wall::Right,
        FLOOR => Wall::Floor,
        k => unreachable!("the silo has three walls, not {k}"),
    }
}

/// The frame the analysis reads: region E, or the whole deposit (mm).
pub fn frame_of(choice: FrameChoice, silo_width: f64, top: f64) -> FrameMm {
    let whole = FrameMm {
        x_min: 0.0,
        x_max: silo_width * 1e3,
        y_min: 0.0,
        y_max: top * 1e3,
    };
    let region_e = FrameMm {
        y_min: REGION_E_MM[0],
        y_max: REGION_E_MM[1],
        ..whole
    };
    match choice {
        FrameChoice::Whole => whole,
        FrameChoice::RegionE => region_e,
        FrameChoice::Auto if top * 1e3 > REGION_E_MM[1] => region_e,
        FrameChoice::Auto => whole,
    }
}

/// Writes deposit, contacts, sidecar, VTK and run record, each atomically.
pub(crate) fn write_outputs(out: &Path, silo: &Silo, record: &mut RunRecord) -> anyhow::Result<()> {
    let world = &silo.world;
    let scene = &record.scene;
    let deposit = deposit_of(silo, scene.grains.length(), scene.grains.width());
    let top = silo
        .deposit_grains()
        .map(|i| world.grain(i).position.y + silo.reach)
        .fold(0.0, f64::max);
    let frame = frame_of(scene.output.frame, silo.width, top);
    record.frame_mm = Some(frame);
    record.deposit_height_mm = top * 1e3;
    record.overflow = top > silo.height;
    record.packing_fraction = AnalysedArea::new(
        [
            frame.x_min * 1e-3,
            frame.x_max * 1e-3,
            frame.y_min * 1e-3,
            frame.y_max * 1e-3,
        ],
        silo.width,
    )
    .map_or(f64::NAN, |a| a.packing_fraction(&deposit));

    let table = out.join("deposit.csv");
    write_deposit_csv(&table, &deposit)?;
    write_contacts_csv(&crate::deposit::contacts_path(&table), &contacts_of(silo))?;
    let meta = DepositMeta {
        silo_width_mm: silo.width * 1e3,
        phi0: scene.feed.phi0,
        frame_mm: Some(frame),
        areal_density_kg_m2: Some(scene.grains.areal_density()),
        gravity_m_s2: Some(scene.contact.gravity_m_s2),
        source: Source::Simulation,
    };
    write_meta_json(&crate::deposit::meta_path(&table), &meta)?;
    write_vtk(
        &out.join(GRAINS_VTK),
        silo,
        scene.grains.length(),
        scene.grains.width(),
    )?;
    write_atomic(&out.join("run.json"), |w| {
        serde_json::to_writer_pretty(&mut *w, record)?;
        Ok(())
    })
}
