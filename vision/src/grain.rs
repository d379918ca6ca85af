/// The outline family of the grains in a photograph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GrainShape {
    /// A square nut seen face-on: side length and the diameter of its threaded hole (metres).
    Square { side: f64, hole_diameter: f64 },
    /// A cylinder seen from the side: a length x width rectangle (metres), length >= width.
    Rod { length: f64, width: f64 },
}

impl GrainShape {
    /// Long side (the side, for squares).
    pub fn length(&self) -> f64 {
        match *self {
            GrainShape::Square { side, .. } => side,
            GrainShape::Rod { length, .. } => length,
        }
    }

    /// Short side D (the side, for squares).
    pub fn width(&self) -> f64 {
        match *self {
            GrainShape::Square { side, .. } => side,
            GrainShape::Rod { width, .. } => width,
        }
    }

    /// The rotation after which the outline looks the same: pi/2 for squares, pi for rods.
    pub fn symmetry_period(&self) -> f64 {
        match self {
            GrainShape::Square { .. } => std::f64::consts::FRAC_PI_2,
            GrainShape::Rod { .. } => std::f64::consts::PI,
        }
    }
}

/// One grain placed in a frame (metres, radians counter-clockwise from +x).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrainOutline {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
    pub shape: GrainShape,
}

/// The region of the deposit a photograph covers, and its scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Width and height of the region (metres).
    pub width: f64,
    pub height: f64,
    /// Pixels per metre.
    pub scale: f64,
}

impl Frame {
    pub fn columns(&self) -> u32 {
        (self.width * self.scale).round() as u32
    }

    pub fn rows(&self) -> u32 {
        (self.height * self.scale).round() as u32
    }

    /// Pixel coordinates (column, row as continuous values, row 0 at the top) of a frame point.
    pub fn to_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        (x * self.scale, self.rows() as f64 - y * self.scale)
    }

    /// Frame point of continuous pixel coordinates.
    pub fn to_frame(&self, column: f64, row: f64) -> (f64, f64) {
        (column / self.scale, (self.rows() as f64 - row) / self.scale)
    }
}
