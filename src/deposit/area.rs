use super::{Deposit, Grain};

/// Grains whose centre is closer than this to a side wall are not analysed (walls align them;
/// SPEC §1).
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

    /// Packing fraction: outline areas of the grains centred in the area over the area (grains
    /// cut by the border count whole; the error is of order perimeter * D / area).
    pub fn packing_fraction(&self, deposit: &Deposit) -> f64 {
        let covered: f64 = self.grains(deposit).map(|g| g.length * g.width).sum();
        covered / self.area()
    }
}
