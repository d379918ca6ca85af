//! The grains as a VTK XML unstructured grid (`.vtu`, ASCII), which ParaView, VTK, pyvista and
//! meshio read: each grain's rounded outline one polygon cell (VTK_POLYGON), in mm in the
//! deposit table's coordinates (x from the left wall, y from the floor, z = 0), fixed wall
//! grains included. Cell data, one value a grain:
//! - `grain`: the grain's row in deposit.csv counted from 0 (the `i`, `j` of the contact table);
//!   for a fixed wall grain its wall as the contact table names it (-1 left, -2 right, -3 floor);
//! - `fixed`: 1 for the fixed grains walls are built of, to hide them or colour them apart;
//! - `theta_rad`: orientation folded by the outline's symmetry exactly as deposit.csv's
//!   (into [0, pi/2) for squares, [0, pi) for rods);
//! - `length_mm`, `width_mm`: the outline, as deposit.csv's;
//! - `velocity_mm_s`: the centre's velocity (x, y, 0);
//! - `contact_force_N`: the sum of the magnitudes of the contact forces on the grain.

use std::io::Write;
use std::path::Path;

use sim::{Body, Vec2, World};

use super::output::{deposit_wall, pose_of};
use super::silo::Silo;
use crate::io::write_atomic;

/// The run folder's VTK file.
pub const GRAINS_VTK: &str = "grains.vtu";

/// Points per rounded corner of an outline.
const ARC_POINTS: usize = 4;

/// VTK's cell type of a polygon.
const VTK_POLYGON: u8 = 7;

const MM_PER_M: f64 = 1e3;

/// Writes the grains of `silo` (outline `length` x `width`, m) atomically.
pub fn write_vtk(path: &Path, silo: &Silo, length: f64, width: f64) -> anyhow::Result<()> {
    let world = &silo.world;
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
    let first_poured = silo.wall_of.len();
    let id = |i: usize| match silo.wall_of.get(i) {
        Some(&wall) => deposit_wall(wall).code(),
        None => (i - first_poured) as i64,
    };
    let poses: Vec<_> = (0..n).map(|i| pose_of(world, i, length, width)).collect();
    let fixed = &world.grains().inverse_mass;
    write_atomic(path, |w| {
        writeln!(w, r#"<?xml version="1.0"?>"#)?;
        writeln!(
            w,
            r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
        )?;
        writeln!(
            w,
            "<!-- facets silo deposit: grain outlines, lengths in mm -->"
        )?;
        writeln!(w, "<UnstructuredGrid>")?;
        writeln!(
            w,
            r#"<Piece NumberOfPoints="{points}" NumberOfCells="{n}">"#
        )?;
        writeln!(w, "<Points>")?;
        data_array(
            w,
            ("Float64", "Points", 3),
            outlines
                .iter()
                .flatten()
                .map(|p| format!("{:e} {:e} 0", p.x * MM_PER_M, p.y * MM_PER_M)),
        )?;
        writeln!(w, "</Points>")?;
        writeln!(w, "<Cells>")?;
        data_array(
            w,
            ("Int64", "connectivity", 1),
            (0..points).map(|k| k.to_string()),
        )?;
        data_array(
            w,
            ("Int64", "offsets", 1),
            outlines.iter().scan(0, |end, o| {
                *end += o.len();
                Some(end.to_string())
            }),
        )?;
        data_array(
            w,
            ("UInt8", "types", 1),
            (0..n).map(|_| VTK_POLYGON.to_string()),
        )?;
        writeln!(w, "</Cells>")?;
        writeln!(
            w,
            r#"<CellData Scalars="theta_rad" Vectors="velocity_mm_s">"#
        )?;
        data_array(w, ("Int64", "grain", 1), (0..n).map(|i| id(i).to_string()))?;
        data_array(
            w,
            ("UInt8", "fixed", 1),
            fixed.iter().map(|m| u8::from(*m == 0.0).to_string()),
        )?;
        data_array(
            w,
            ("Float64", "theta_rad", 1),
            poses.iter().map(|g| format!("{:e}", g.theta)),
        )?;
        data_array(
            w,
            ("Float64", "length_mm", 1),
            poses.iter().map(|g| format!("{:e}", g.length * MM_PER_M)),
        )?;
        data_array(
            w,
            ("Float64", "width_mm", 1),
            poses.iter().map(|g| format!("{:e}", g.width * MM_PER_M)),
        )?;
        data_array(
            w,
            ("Float64", "velocity_mm_s", 3),
            (0..n).map(|i| {
                let v = world.grain(i).velocity * MM_PER_M;
                format!("{:e} {:e} 0", v.x, v.y)
            }),
        )?;
        data_array(
            w,
            ("Float64", "contact_force_N", 1),
            force.iter().map(|f| format!("{f:e}")),
        )?;
        writeln!(w, "</CellData>")?;
        writeln!(w, "</Piece>")?;
        writeln!(w, "</UnstructuredGrid>")?;
        writeln!(w, "</VTKFile>")?;
        Ok(())
    })
}

/// One ASCII `DataArray` of (type, name, components), a value (all its components) a line.
fn data_array(
    w: &mut dyn Write,
    (kind, name, components): (&str, &str, usize),
    values: impl Iterator<Item = String>,
) -> std::io::Result<()> {
    writeln!(
        w,
        r#"<DataArray type="{kind}" Name="{name}" NumberOfComponents="{components}" format="ascii">"#
    )?;
    for v in values {
        writeln!(w, "{v}")?;
    }
    writeln!(w, "</DataArray>")
}

/// The rounded outline of grain i, counter-clockwise: each core vertex swept by an arc of the
/// rounding radius from the outward normal of the edge before it to that of the edge after it.
fn outline(world: &World, i: usize) -> Vec<Vec2> {
    let shape = world.shape(world.shape_of(i));
    let g = world.grain(i);
    let (sin, cos) = g.angle.sin_cos();
    let rotate = |v: Vec2| Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y);
    let vertices = shape.vertices();
    let m = vertices.len();
    let normal_angle = |k: usize| {
        let n = shape.edge_normal(k);
        n.y.atan2(n.x)
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
