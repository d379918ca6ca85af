//! The grains' VTK file (issue 56): an XML unstructured grid of polygon cells that other tools
//! read, in mm, one cell a grain, with the deposit table's folded orientation.

use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

use facets::deposit::read_deposit_csv;
use facets::fill::{FLOOR, GRAINS_VTK, LEFT_WALL, Silo, deposit_of, fill, write_vtk};
use facets::scene::parse_scene;
use sim::{GrainState, Vec2};

/// VTK's cell type of a polygon.
const VTK_POLYGON: f64 = 7.0;

/// The arrays of a `.vtu` file written in ASCII, by name, with their number of components.
struct Vtu {
    points: usize,
    cells: usize,
    arrays: HashMap<String, (usize, Vec<f64>)>,
}

/// The value of attribute `name` in the tag `tag` (its text between `<` and `>`).
fn attribute<'a>(tag: &'a str, name: &str) -> &'a str {
    let start = tag
        .find(&format!(" {name}=\""))
        .unwrap_or_else(|| panic!("no attribute {name} in <{tag}>"))
        + name.len()
        + 3;
    let end = start + tag[start..].find('"').unwrap();
    &tag[start..end]
}

fn read_vtu(path: &Path) -> Vtu {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.starts_with("<?xml"), "not an XML file");
    let root = &text[text.find("<VTKFile").unwrap()..];
    let root = &root[..root.find('>').unwrap()];
    assert_eq!(attribute(root, "type"), "UnstructuredGrid");
    let piece = &text[text.find("<Piece").unwrap()..];
    let piece = &piece[..piece.find('>').unwrap()];
    let count = |name| attribute(piece, name).parse::<usize>().unwrap();
    let mut arrays = HashMap::new();
    let mut rest = text.as_str();
    while let Some(start) = rest.find("<DataArray") {
        rest = &rest[start..];
        let header_end = rest.find('>').unwrap();
        let header = &rest[..header_end];
        assert_eq!(attribute(header, "format"), "ascii");
        let body_end = rest.find("</DataArray>").unwrap();
        let values = rest[header_end + 1..body_end]
            .split_whitespace()
            .map(|v| v.parse::<f64>().unwrap())
            .collect();
        let components = attribute(header, "NumberOfComponents").parse().unwrap();
        arrays.insert(attribute(header, "Name").to_string(), (components, values));
        rest = &rest[body_end..];
    }
    Vtu {
        points: count("NumberOfPoints"),
        cells: count("NumberOfCells"),
        arrays,
    }
}

impl Vtu {
    fn array(&self, name: &str, components: usize) -> &[f64] {
        let (c, values) = self
            .arrays
            .get(name)
            .unwrap_or_else(|| panic!("no array {name}"));
        assert_eq!(*c, components, "{name}: components");
        values
    }

    /// Checks the grid's structure; returns each cell's points (x, y in mm).
    fn polygons(&self) -> Vec<Vec<[f64; 2]>> {
        let points = self.array("Points", 3);
        assert_eq!(points.len(), 3 * self.points);
        assert!(points.chunks(3).all(|p| p[2] == 0.0), "a point off z = 0");
        let connectivity = self.array("connectivity", 1);
        let offsets = self.array("offsets", 1);
        let types = self.array("types", 1);
        assert_eq!((offsets.len(), types.len()), (self.cells, self.cells));
        assert!(types.iter().all(|&t| t == VTK_POLYGON));
        assert_eq!(*offsets.last().unwrap() as usize, connectivity.len());
        let mut used = vec![false; self.points];
        let mut start = 0;
        let mut polygons = Vec::new();
        for &end in offsets {
            let end = end as usize;
            assert!(end >= start + 3, "a polygon of fewer than 3 points");
            polygons.push(
                connectivity[start..end]
                    .iter()
                    .map(|&k| {
                        let k = k as usize;
                        assert!(k < self.points, "point {k} of {}", self.points);
                        used[k] = true;
                        [points[3 * k], points[3 * k + 1]]
                    })
                    .collect(),
            );
            start = end;
        }
        assert!(used.iter().all(|&u| u), "a point no cell uses");
        for (name, (components, values)) in &self.arrays {
            if !["Points", "connectivity", "offsets", "types"].contains(&name.as_str()) {
                assert_eq!(values.len(), components * self.cells, "cell data {name}");
            }
        }
        polygons
    }
}

/// The outline's centre and its half extents along the axes at `theta` (mm).
fn centre_and_half_extents(polygon: &[[f64; 2]], theta: f64) -> ([f64; 2], [f64; 2]) {
    let n = polygon.len() as f64;
    let centre = [
        polygon.iter().map(|p| p[0]).sum::<f64>() / n,
        polygon.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let (s, c) = theta.sin_cos();
    let mut half = [0.0f64; 2];
    for p in polygon {
        let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
        half[0] = half[0].max((c * dx + s * dy).abs());
        half[1] = half[1].max((-s * dx + c * dy).abs());
    }
    (centre, half)
}

/// A silo of `kind` with flat walls, no grain poured.
fn empty_silo(kind: &str) -> Silo {
    let text = format!(
        "[silo]\nwidth_mm = 96\nwalls = \"flat\"\n[grains]\nkind = \"{kind}\"\ncount = 10\n[feed]\nphi0 = 0.1\n"
    );
    Silo::new(&parse_scene(&text, "vtk.toml").unwrap(), 1).unwrap()
}

#[test]
fn a_placed_grain_is_written_in_mm_with_the_tables_folded_orientation() {
    // (kind, L, D in mm, angle the engine holds, angle folded by the outline's symmetry)
    for (kind, [length, width], angle, folded) in [
        ("square", [6.9, 6.9], 2.0, 2.0 - FRAC_PI_2),
        ("square", [6.9, 6.9], -0.3, FRAC_PI_2 - 0.3),
        ("rod53", [4.9, 3.0], 2.0, 2.0),
        ("rod53", [4.9, 3.0], -0.5, PI - 0.5),
    ] {
        let mut silo = empty_silo(kind);
        let at = [0.05, 0.03];
        silo.world
            .add_grain(
                silo.shape,
                GrainState {
                    position: Vec2::new(at[0], at[1]),
                    angle,
                    velocity: Vec2::new(0.1, -0.2),
                    angular_velocity: 0.0,
                },
            )
            .unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("one.vtu");
        write_vtk(&path, &silo, length * 1e-3, width * 1e-3).unwrap();
        let vtu = read_vtu(&path);
        let polygons = vtu.polygons();
        assert_eq!((vtu.cells, polygons.len()), (1, 1));
        let theta = vtu.array("theta_rad", 1)[0];
        assert!(
            (theta - folded).abs() < 1e-12,
            "{kind} at {angle} rad: theta_rad {theta}, expected {folded}"
        );
        let table = deposit_of(&silo, length * 1e-3, width * 1e-3);
        assert!((theta - table.grains[0].theta).abs() < 1e-12);
        let (centre, half) = centre_and_half_extents(&polygons[0], theta);
        for (got, want, what) in [
            (centre[0], 50.0, "centre x"),
            (centre[1], 30.0, "centre y"),
            (2.0 * half[0], length, "length"),
            (2.0 * half[1], width, "width"),
        ] {
            assert!(
                (got - want).abs() < 1e-9,
                "{kind}: {what} {got} mm, expected {want} mm"
            );
        }
        assert_eq!(vtu.array("velocity_mm_s", 3), [100.0, -200.0, 0.0]);
        assert_eq!(vtu.array("grain", 1), [0.0]);
        assert_eq!(vtu.array("fixed", 1), [0.0]);
        assert_eq!(vtu.array("length_mm", 1), [length]);
        assert_eq!(vtu.array("width_mm", 1), [width]);
    }
}

/// 40 squares in a 96 mm silo of rough walls, stopped 20 ms after the last one: every grain
/// of the run's file, wall grains included, against the deposit table.
#[test]
fn a_runs_file_holds_every_grain_as_the_deposit_table_does() {
    let scene = parse_scene(
        r#"
[silo]
width_mm = 96
height_mm = 300

[grains]
kind = "square"
count = 40

[feed]
phi0 = 0.1

[run]
time_step_s = 4e-6
max_relaxation_time_s = 0.02
"#,
        "vtk.toml",
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let record = fill(&scene, 5, dir.path(), &mut |_| {}).unwrap();
    let deposit = read_deposit_csv(&dir.path().join("deposit.csv")).unwrap();
    let vtu = read_vtu(&dir.path().join(GRAINS_VTK));
    let polygons = vtu.polygons();
    let walls = record.wall_grains;
    assert!(walls > 0, "rough walls are built of fixed grains");
    assert_eq!(vtu.cells, walls + deposit.grains.len());
    let (ids, fixed) = (vtu.array("grain", 1), vtu.array("fixed", 1));
    let theta = vtu.array("theta_rad", 1);
    // The wall grains come first, each named by its wall as the contact table does.
    let silo = Silo::new(&scene, 5).unwrap();
    for (k, &wall) in silo.wall_of.iter().enumerate() {
        let expected = match wall {
            LEFT_WALL => -1.0,
            FLOOR => -3.0,
            _ => -2.0,
        };
        assert_eq!((ids[k], fixed[k]), (expected, 1.0), "wall grain {k}");
    }
    for (row, g) in deposit.grains.iter().enumerate() {
        let k = walls + row;
        assert_eq!((ids[k], fixed[k]), (row as f64, 0.0), "cell {k}");
        // The table prints theta to 1e-6 rad and positions to 1e-4 mm.
        assert!(
            (theta[k] - g.theta).abs() < 1e-6 && (0.0..FRAC_PI_2).contains(&theta[k]),
            "row {row}: theta_rad {} in the VTK file, {} in the table",
            theta[k],
            g.theta
        );
        let (centre, half) = centre_and_half_extents(&polygons[k], theta[k]);
        assert!(
            (centre[0] - g.x * 1e3).abs() < 1e-4 && (centre[1] - g.y * 1e3).abs() < 1e-4,
            "row {row}: centre ({}, {}) mm in the VTK file, ({}, {}) mm in the table",
            centre[0],
            centre[1],
            g.x * 1e3,
            g.y * 1e3
        );
        for h in half {
            assert!(
                (2.0 * h - 6.9).abs() < 1e-6,
                "row {row}: side {} mm",
                2.0 * h
            );
        }
    }
}
