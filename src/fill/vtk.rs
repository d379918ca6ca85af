//! Legacy VTK (ASCII POLYDATA) of the grains: each grain's rounded outline as one polygon, with
//! cell data velocity, orientation, contact force and whether the grain is fixed, for ParaView.

use std::io::Write;
use std::path::Path;

use sim::{Body, Vec2, World};

use crate::io::write_atomic;

/// Points per rounded corner of an outline.
const ARC_POINTS: usize = 4;

/// Writes the grains of `world` (metres, as the engine holds them) atomically.
pub fn write_vtk(path: &Path, world: &World) -> anyhow::Result<()> {
    let n = world.len();
    let mut force = vec![0.0; n];
    for c in world.contacts() {
        let f = c.force.norm();
        force[c.first] += f;
        if let Body::Grain(j) = c.second {
            force[j] += f;
        }
    }
    let outlines: Vec<Vec<Vec2>> = (0..n).map(|i| outline(world, i)).collect();
    let points: usize = outlines.iter().map(Vec::len).sum();
    write_atomic(path, |w| {
        writeln!(w, "# vtk DataFile Version 3.0")?;
        writeln!(w, "facets silo deposit: grain outlines (m)")?;
        writeln!(w, "ASCII")?;
        writeln!(w, "DATASET POLYDATA")?;
        writeln!(w, "POINTS {points} double")?;
        for p in outlines.iter().flatten() {
            writeln!(w, "{:e} {:e} 0", p.x, p.y)?;
        }
        writeln!(w, "POLYGONS {n} {}", n + points)?;
        let mut next = 0;
        for o in &outlines {
            write!(w, "{}", o.len())?;
            for k in next..next + o.len() {
                write!(w, " {k}")?;
            }
            writeln!(w)?;
            next += o.len();
        }
        writeln!(w, "CELL_DATA {n}")?;
        writeln!(w, "VECTORS velocity_m_s double")?;
        for i in 0..n {
            let v = world.grain(i).velocity;
            writeln!(w, "{:e} {:e} 0", v.x, v.y)?;
        }
        writeln!(w, "SCALARS orientation_rad double 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for i in 0..n {
            writeln!(
                w,
                "{:e}",
                world.grain(i).angle.rem_euclid(std::f64::consts::PI)
            )?;
        }
        writeln!(w, "SCALARS contact_force_N double 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for f in &force {
            writeln!(w, "{f:e}")?;
        }
        // 1 for the fixed grains walls are built of, to hide them or colour them apart.
        writeln!(w, "SCALARS fixed int 1")?;
        writeln!(w, "LOOKUP_TABLE default")?;
        for m in &world.grains().inverse_mass {
            writeln!(w, "{}", u8::from(*m == 0.0))?;
        }
        Ok(())
    })
}

/// The rounded outline of grain i, counter-clockwise: each core vertex swept by an arc from
/// the normal of the edge before it to the normal of the edge after it.
fn outline(world: &World, i: usize) -> Vec<Vec2> {
    let shape = world.shape(world.shape_of(i));
    let g = world.grain(i);
    let (sin, cos) = g.angle.sin_cos();
    let rotate = |v: Vec2| Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y);
    let vertices = shape.vertices();
    let m = vertices.len();
    let normal_angle = |k: usize| {
        let d = shape.edge_directions()[k];
        d.x.atan2(-d.y)
    };
    let mut out = Vec::with_capacity(m * ARC_POINTS);
    for (k, vertex) in vertices.iter().enumerate() {
        let before = normal_angle((k + m - 1) % m);
        let mut after = normal_angle(k);
        if after < before {
            after += std::f64::consts::TAU;
        }
        for s in 0..ARC_POINTS {
            let a = before + (after - before) * s as f64 / (ARC_POINTS - 1) as f64;
            let p = vertex + Vec2::new(a.cos(), a.sin()) * shape.radius();
            out.push(g.position + rotate(p));
        }
    }
    out
}
