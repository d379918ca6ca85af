use super::{Deposit, Grain};

/// Grains whose centre is closer than this to a side wall are not analysed (walls align them;
/// docs/model.md §1).
pub const WALL_MARGIN: f64 = 0.040;

/// The analysed area: the frame less 40 mm at each side wall (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnalysedArea {
    pub x_min: f64,
    pub x_max: f64,
    pub y_min: f64,
    pub y_max: f64,
}

impl AnalysedArea {
    /// `frame` = [x_min, x_max, y_min, y_max] in the silo's frame (x = 0 at the left wall).
    pub fn new(frame: [f64; 4], silo_width: f64) -> anyhow::Result<Self> {
        let area = AnalysedArea {
            x_min: frame[0].max(WALL_MARGIN),
            x_max: frame[1].min(silo_width - WALL_MARGIN),
            y_min: frame[2],
            y_max: frame[3],
        };
        if !(area.x_max > area.x_min && area.y_max > area.y_min) {
            anyhow::bail!(
                "the analysed area is empty: frame x {:.1}..{:.1} mm, y {:.1}..{:.1} mm, silo width {:.1} mm less {:.0} mm at each wall",
                frame[0] * 1e3,
                frame[1] * 1e3,
                frame[2] * 1e3,
                frame[3] * 1e3,
                silo_width * 1e3,
                WALL_MARGIN * 1e3
            );
        }
        Ok(area)
    }

    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x_min && x <= self.x_max && y >= self.y_min && y <= self.y_max
    }

    /// Distance from an inside point to the nearest border (negative outside).
    pub fn depth_inside(&self, x: f64, y: f64) -> f64 {
        (x - self.x_min)
            .min(self.x_max - x)
            .min(y - self.y_min)
            .min(self.y_max - y)
    }

    pub fn area(&self) -> f64 {
        (self.x_max - self.x_min) * (self.y_max - self.y_min)
    }

    /// The grains whose centre lies in the area.
    pub fn grains<'a>(&'a self, deposit: &'a Deposit) -> impl Iterator<Item = &'a Grain> + 'a {
        deposit.grains.iter().filter(|g| self.contains(g.x, g.y))
    }

    /// Packing fraction: the part of each grain's outline (its L x D rectangle) that lies in
    /// the area, summed, over the area. Counting grains whole by their centre instead makes
    /// the count jump by a row of grains as the border moves across one: an error of order
    /// perimeter x D / area, +-3 % in region E of an ordered deposit of nuts.
    pub fn packing_fraction(&self, deposit: &Deposit) -> f64 {
        let covered: f64 = deposit.grains.iter().map(|g| self.covered_by(g)).sum();
        covered / self.area()
    }

    /// Area of the grain's L x D rectangle inside the area.
    fn covered_by(&self, g: &Grain) -> f64 {
        let reach = 0.5 * g.length.hypot(g.width);
        if g.x + reach < self.x_min
            || g.x - reach > self.x_max
            || g.y + reach < self.y_min
            || g.y - reach > self.y_max
        {
            return 0.0;
        }
        let (sin, cos) = g.theta.sin_cos();
        let (a, b) = (0.5 * g.length, 0.5 * g.width);
        let corner = |u: f64, v: f64| [g.x + u * cos - v * sin, g.y + u * sin + v * cos];
        let mut polygon = vec![corner(-a, -b), corner(a, -b), corner(a, b), corner(-a, b)];
        // Sutherland-Hodgman against the four sides: (axis, bound, keep the side below it).
        for (axis, bound, below) in [
            (0, self.x_min, false),
            (0, self.x_max, true),
            (1, self.y_min, false),
            (1, self.y_max, true),
        ] {
            let inside = |p: &[f64; 2]| (p[axis] <= bound) == below || p[axis] == bound;
            let mut clipped = Vec::with_capacity(polygon.len() + 1);
            for k in 0..polygon.len() {
                let (p, q) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                if inside(&p) {
                    clipped.push(p);
                }
                if inside(&p) != inside(&q) {
                    let t = (bound - p[axis]) / (q[axis] - p[axis]);
                    clipped.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
                }
            }
            polygon = clipped;
            if polygon.is_empty() {
                return 0.0;
            }
        }
        let twice: f64 = (0..polygon.len())
            .map(|k| {
                let (p, q) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                p[0] * q[1] - q[0] * p[1]
            })
            .sum();
        0.5 * twice.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tiling_of_squares_fills_the_area_whatever_its_border_cuts() {
        // Squares of side D tiling the plane, the lattice turned and shifted: every point of
        // the area is covered once, so the fraction is 1 however the border cuts the rows
        // (counting grains whole by their centre gives 0.9-1.1 here).
        let d = 6.9e-3;
        let area = AnalysedArea::new([0.0, 0.256, 0.29, 0.41], 0.256).unwrap();
        for (turn, shift) in [
            (0.0, 0.0),
            (0.0, 0.4),
            (0.3, 0.17),
            (0.785, 0.5),
            (1.2, 0.9),
        ] {
            let (sin, cos) = f64::sin_cos(turn);
            let mut grains = Vec::new();
            for i in -60..60 {
                for j in -60..60 {
                    let (u, v) = ((i as f64 + shift) * d, (j as f64 + shift) * d);
                    let (x, y) = (0.128 + u * cos - v * sin, 0.35 + u * sin + v * cos);
                    grains.push(Grain::placed(x, y, turn, d, d));
                }
            }
            let deposit = Deposit { grains };
            let phi = area.packing_fraction(&deposit);
            assert!(
                (phi - 1.0).abs() < 1e-9,
                "turn {turn}, shift {shift}: {phi}"
            );
        }
    }

    #[test]
    fn a_rod_across_the_border_counts_the_part_inside() {
        // A rod 8.9 x 3 mm lying across the left border of the analysed area (x = 40 mm), a
        // third of its length inside, and one turned upright across the top border.
        let area = AnalysedArea::new([0.0, 0.256, 0.29, 0.41], 0.256).unwrap();
        let (l, w) = (8.9e-3, 3e-3);
        let across = Grain::placed(0.040 - l / 6.0, 0.35, 0.0, l, w);
        assert!((area.covered_by(&across) - l * w / 3.0).abs() < 1e-12 * l * w);
        let upright = Grain::placed(0.1, 0.41 - 1e-3, std::f64::consts::FRAC_PI_2, l, w);
        assert!((area.covered_by(&upright) - (l / 2.0 + 1e-3) * w).abs() < 1e-12 * l * w);
        let outside = Grain::placed(0.1, 0.2, 0.3, l, w);
        assert_eq!(area.covered_by(&outside), 0.0);
    }
}
