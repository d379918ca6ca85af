//! The sample tables in data-samples/deposits/ are what the builders make, and they read back
//! whole: a built static deposit with balanced contacts (simulation side) and a jittered lattice
//! standing in for a detected photograph (experiment side).
//! `FACETS_WRITE_SAMPLES=1 cargo test --release --test samples` rewrites them.

use std::path::{Path, PathBuf};

use facets::deposit::{
    DepositMeta, FrameMm, LoadOptions, Partner, Source, SquareStack, jittered_lattice,
    load_realisation, write_contacts_csv, write_deposit_csv, write_meta_json,
};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data-samples/deposits")
}

pub fn stack() -> SquareStack {
    SquareStack {
        columns: 24,
        rows: 14,
        ..SquareStack::default()
    }
}

fn write_samples() {
    let d = dir();
    std::fs::create_dir_all(&d).unwrap();
    let (deposit, contacts, meta) = stack().build(0.1);
    write_deposit_csv(&d.join("stack.csv"), &deposit).unwrap();
    write_contacts_csv(&d.join("stack.contacts.csv"), &contacts).unwrap();
    write_meta_json(&d.join("stack.meta.json"), &meta).unwrap();
    let frame = [0.0, 0.258, 0.290, 0.410];
    let photo = jittered_lattice(550, 6.9e-3, 6.9e-3, frame, 0.05, 0.4, 7);
    write_deposit_csv(&d.join("photo.csv"), &photo).unwrap();
    let meta = DepositMeta {
        silo_width_mm: 258.0,
        phi0: 0.1,
        frame_mm: Some(FrameMm {
            x_min: 0.0,
            x_max: 258.0,
            y_min: 290.0,
            y_max: 410.0,
        }),
        areal_density_kg_m2: None,
        gravity_m_s2: None,
        source: Source::Experiment,
    };
    write_meta_json(&d.join("photo.meta.json"), &meta).unwrap();
}

#[test]
fn samples_read_back_and_the_built_deposit_is_balanced() {
    if std::env::var_os("FACETS_WRITE_SAMPLES").is_some() {
        write_samples();
    }
    let real = load_realisation(&dir().join("stack.csv"), &LoadOptions::default()).unwrap();
    let contacts = real
        .contacts
        .as_ref()
        .expect("stack.contacts.csv is found beside it");
    let (built, built_contacts, _) = stack().build(0.1);
    assert_eq!(real.deposit.grains.len(), built.grains.len());
    assert_eq!(contacts.len(), built_contacts.len());
    assert_eq!(real.meta.source, Source::Simulation);
    // Force balance after the round trip through the files (forces written in full precision).
    let masses = real.masses();
    let g = real.meta.gravity();
    let mut net: Vec<[f64; 2]> = masses.iter().map(|m| [0.0, -m * g]).collect();
    for c in contacts {
        net[c.i][0] += c.force[0];
        net[c.i][1] += c.force[1];
        if let Partner::Grain(j) = c.partner {
            net[j][0] -= c.force[0];
            net[j][1] -= c.force[1];
        }
    }
    let weight = masses[0] * g;
    for f in net {
        assert!(
            f[0].abs() < 1e-9 * weight && f[1].abs() < 1e-9 * weight,
            "{f:?}"
        );
    }
    let photo = load_realisation(&dir().join("photo.csv"), &LoadOptions::default()).unwrap();
    assert_eq!(photo.deposit.grains.len(), 550);
    assert!(photo.contacts.is_none());
}
