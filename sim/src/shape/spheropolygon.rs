use serde::{Deserialize, Serialize};

use super::mass_properties::{RoundedMoments, outward_normal};
use crate::error::ShapeError;
use crate::math::{Vec2, cross};

/// A convex spheropolygon: the Minkowski sum of a convex core polygon and a disk of radius r.
///
/// The core vertices are stored counter-clockwise in the body frame, with the origin at the
/// centroid of the rounded outline. Edge k runs from vertex k to vertex k + 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spheropolygon {
    vertices: Vec<Vec2>,
    /// Unit direction of each edge in the body frame.
    edge_directions: Vec<Vec2>,
    edge_lengths: Vec<f64>,
    radius: f64,
    area: f64,
    polar_moment: f64,
    bounding_radius: f64,
}

fn finite(field: &'static str, value: f64) -> Result<f64, ShapeError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ShapeError::NotFinite { field, value })
    }
}

impl Spheropolygon {
    /// Builds the shape from core vertices (counter-clockwise, convex) and the rounding radius.
    /// The vertices are re-centred on the centroid of the rounded outline.
    pub fn new(vertices: Vec<Vec2>, radius: f64) -> Result<Self, ShapeError> {
        finite("radius", radius)?;
        if radius <= 0.0 {
            return Err(ShapeError::NonPositiveRadius(radius));
        }
        for v in &vertices {
            finite("vertices", v.x)?;
            finite("vertices", v.y)?;
        }
        let n = vertices.len();
        if n < 3 {
            return Err(ShapeError::TooFewVertices(n));
        }
        if n > super::MAX_VERTICES {
            return Err(ShapeError::TooManyVertices(n));
        }
        let scale = vertices.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for k in 0..n {
            let a = vertices[(k + n - 1) % n];
            let b = vertices[k];
            let c = vertices[(k + 1) % n];
            let turn = cross(b - a, c - b);
            // Collinear or reflex vertices break the vertex-region logic of the narrow phase.
            if turn <= 1e-12 * scale * scale {
                return Err(ShapeError::NotConvex { vertex: k, turn });
            }
        }
        let moments = RoundedMoments::of(&vertices, radius);
        let centroid = moments.centroid();
        let vertices: Vec<Vec2> = vertices.iter().map(|v| v - centroid).collect();
        let edges: Vec<Vec2> = (0..n)
            .map(|k| vertices[(k + 1) % n] - vertices[k])
            .collect();
        let bounding_radius = vertices.iter().map(|v| v.norm()).fold(0.0, f64::max) + radius;
        Ok(Self {
            edge_directions: edges.iter().map(|e| e.normalize()).collect(),
            edge_lengths: edges.iter().map(|e| e.norm()).collect(),
            vertices,
            radius,
            area: moments.area,
            polar_moment: moments.polar_moment_about_centroid(),
            bounding_radius,
        })
    }

    /// The outline of a length x width rectangle with corners rounded by `radius`:
    /// a (length - 2r) x (width - 2r) core swept by a disk of radius r. Long axis along x.
    pub fn rounded_rectangle(length: f64, width: f64, radius: f64) -> Result<Self, ShapeError> {
        finite("length", length)?;
        finite("width", width)?;
        finite("radius", radius)?;
        if radius <= 0.0 {
            return Err(ShapeError::NonPositiveRadius(radius));
        }
        if length < width {
            return Err(ShapeError::LengthBelowWidth { length, width });
        }
        if width <= 2.0 * radius {
            return Err(ShapeError::WidthNotAboveRounding { width, radius });
        }
        let (a, b) = (length / 2.0 - radius, width / 2.0 - radius);
        Self::new(
            vec![
                Vec2::new(-a, -b),
                Vec2::new(a, -b),
                Vec2::new(a, b),
                Vec2::new(-a, b),
            ],
            radius,
        )
    }

    pub fn vertices(&self) -> &[Vec2] {
        &self.vertices
    }

    pub fn edge_directions(&self) -> &[Vec2] {
        &self.edge_directions
    }

    pub fn edge_lengths(&self) -> &[f64] {
        &self.edge_lengths
    }

    /// Outward unit normal of edge k in the body frame.
    pub fn edge_normal(&self, k: usize) -> Vec2 {
        let n = self.vertices.len();
        outward_normal(self.vertices[k], self.vertices[(k + 1) % n])
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Area of the rounded outline.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Integral of |x|^2 over the rounded outline, about its centroid.
    pub fn polar_moment(&self) -> f64 {
        self.polar_moment
    }

    /// Radius of the smallest disk about the centroid that holds the rounded outline.
    pub fn bounding_radius(&self) -> f64 {
        self.bounding_radius
    }

    /// Mass and moment of inertia of a uniform plate of this outline.
    pub fn mass_properties(&self, areal_density: f64) -> Result<(f64, f64), ShapeError> {
        finite("areal_density", areal_density)?;
        if areal_density <= 0.0 {
            return Err(ShapeError::NonPositiveDensity(areal_density));
        }
        Ok((areal_density * self.area, areal_density * self.polar_moment))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::mass_properties::steiner_area;
    use std::f64::consts::PI;

    #[test]
    fn rounded_rectangle_area_and_inertia_match_direct_integration() {
        let (l, d, r) = (8.9e-3, 3e-3, 0.15e-3);
        let s = Spheropolygon::rounded_rectangle(l, d, r).unwrap();
        let exact_area = l * d - (4.0 - PI) * r * r;
        assert!((s.area() - exact_area).abs() < 1e-15);
        let core = (l - 2.0 * r) * (d - 2.0 * r);
        let perimeter = 2.0 * (l - 2.0 * r + d - 2.0 * r);
        assert!((s.area() - steiner_area(core, perimeter, r)).abs() < 1e-15);
        // Midpoint-rule integration of |x|^2 over the outline on a fine grid.
        let n = 2000;
        let (hx, hy) = (l / n as f64, d / n as f64);
        let (a, b) = (l / 2.0 - r, d / 2.0 - r);
        let mut j = 0.0;
        for ix in 0..n {
            for iy in 0..n {
                let x = -l / 2.0 + (ix as f64 + 0.5) * hx;
                let y = -d / 2.0 + (iy as f64 + 0.5) * hy;
                let (ex, ey) = ((x.abs() - a).max(0.0), (y.abs() - b).max(0.0));
                if ex * ex + ey * ey <= r * r {
                    j += (x * x + y * y) * hx * hy;
                }
            }
        }
        assert!(
            (s.polar_moment() - j).abs() / j < 1e-4,
            "{} vs {j}",
            s.polar_moment()
        );
    }

    #[test]
    fn nut_mass_matches_spec() {
        let s = Spheropolygon::rounded_rectangle(6.9e-3, 6.9e-3, 0.35e-3).unwrap();
        let (m, _) = s.mass_properties(20.3).unwrap();
        assert!((m - 0.97e-3).abs() < 0.01e-3, "nut mass {m}");
    }

    #[test]
    fn triangle_is_recentred_on_its_centroid() {
        let s = Spheropolygon::new(
            vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(3.0, 0.0),
                Vec2::new(0.0, 3.0),
            ],
            0.1,
        )
        .unwrap();
        let m = RoundedMoments::of(s.vertices(), s.radius());
        assert!(m.first_moment.norm() < 1e-12);
    }

    #[test]
    fn bad_outlines_name_the_field() {
        let msg = |e: ShapeError| e.to_string();
        assert!(
            msg(Spheropolygon::rounded_rectangle(5.0, 3.0, 0.0).unwrap_err()).contains("radius")
        );
        assert!(
            msg(Spheropolygon::rounded_rectangle(5.0, 3.0, -1.0).unwrap_err()).contains("radius")
        );
        assert!(
            msg(Spheropolygon::rounded_rectangle(2.0, 3.0, 0.1).unwrap_err()).contains("`length`")
        );
        assert!(
            msg(Spheropolygon::rounded_rectangle(5.0, 3.0, 1.5).unwrap_err()).contains("`width`")
        );
        assert!(
            msg(Spheropolygon::rounded_rectangle(f64::NAN, 3.0, 0.1).unwrap_err())
                .contains("`length`")
        );
        let square = |v: Vec<(f64, f64)>| {
            Spheropolygon::new(v.into_iter().map(|(x, y)| Vec2::new(x, y)).collect(), 0.1)
        };
        let clockwise = square(vec![(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)]);
        assert!(msg(clockwise.unwrap_err()).contains("`vertices`"));
        let dart = square(vec![(0.0, 0.0), (2.0, 0.0), (0.5, 0.5), (0.0, 2.0)]);
        assert!(matches!(dart, Err(ShapeError::NotConvex { vertex: 2, .. })));
        assert!(msg(square(vec![(0.0, 0.0), (1.0, 0.0)]).unwrap_err()).contains("`vertices`"));
        let s = Spheropolygon::rounded_rectangle(5.0, 3.0, 0.1).unwrap();
        assert!(msg(s.mass_properties(0.0).unwrap_err()).contains("areal_density"));
    }
}
