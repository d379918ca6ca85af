//! Cutting shapes at a picture's frame: plotters draws what lies outside its plot area on
//! the axes and margins, so a deposit picture clips its grains and force chains first.

/// A rectangle `[x_min, x_max, y_min, y_max]`.
pub type Frame = [f64; 4];

/// The part of the segment a-b inside the frame (Liang-Barsky), None when none is.
pub fn clip_segment(a: [f64; 2], b: [f64; 2], frame: Frame) -> Option<([f64; 2], [f64; 2])> {
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    // Each side as p t <= q.
    for (p, q) in [
        (-d[0], a[0] - frame[0]),
        (d[0], frame[1] - a[0]),
        (-d[1], a[1] - frame[2]),
        (d[1], frame[3] - a[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| [a[0] + t * d[0], a[1] + t * d[1]];
    Some((at(t0), at(t1)))
}

/// The part of a convex polygon inside the frame (Sutherland-Hodgman); empty when none is.
pub fn clip_polygon(polygon: &[[f64; 2]], frame: Frame) -> Vec<[f64; 2]> {
    // Each side: which coordinate, the bound, and whether inside is above it.
    let sides = [
        (0, frame[0], true),
        (0, frame[1], false),
        (1, frame[2], true),
        (1, frame[3], false),
    ];
    let mut points = polygon.to_vec();
    for (axis, bound, above) in sides {
        if points.is_empty() {
            break;
        }
        let inside = |p: &[f64; 2]| {
            if above {
                p[axis] >= bound
            } else {
                p[axis] <= bound
            }
        };
        let cross = |p: &[f64; 2], q: &[f64; 2]| {
            let t = (bound - p[axis]) / (q[axis] - p[axis]);
            [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
        };
        let mut kept = Vec::with_capacity(points.len() + 1);
        for k in 0..points.len() {
            let (p, q) = (points[k], points[(k + 1) % points.len()]);
            match (inside(&p), inside(&q)) {
                (true, true) => kept.push(q),
                (true, false) => kept.push(cross(&p, &q)),
                (false, true) => {
                    kept.push(cross(&p, &q));
                    kept.push(q);
                }
                (false, false) => {}
            }
        }
        points = kept;
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    const FRAME: Frame = [0.0, 10.0, 0.0, 5.0];

    fn area(p: &[[f64; 2]]) -> f64 {
        let n = p.len();
        0.5 * (0..n)
            .map(|k| p[k][0] * p[(k + 1) % n][1] - p[(k + 1) % n][0] * p[k][1])
            .sum::<f64>()
            .abs()
    }

    #[test]
    fn segments_are_cut_at_the_frame() {
        let (a, b) = clip_segment([-5.0, 2.0], [5.0, 2.0], FRAME).unwrap();
        assert_eq!((a, b), ([0.0, 2.0], [5.0, 2.0]));
        let inside = clip_segment([1.0, 1.0], [2.0, 3.0], FRAME).unwrap();
        assert_eq!(inside, ([1.0, 1.0], [2.0, 3.0]));
        // Wholly above, and a diagonal that passes by a corner.
        assert!(clip_segment([1.0, 6.0], [9.0, 7.0], FRAME).is_none());
        assert!(clip_segment([9.0, 7.0], [12.0, 4.0], FRAME).is_none());
    }

    #[test]
    fn a_square_across_a_corner_keeps_the_quarter_inside() {
        let square = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let cut = clip_polygon(&square, FRAME);
        assert!((area(&cut) - 1.0).abs() < 1e-12, "{cut:?}");
        assert!(cut.iter().all(|p| p[0] >= 0.0 && p[1] >= 0.0));
        // Inside: unchanged in area; outside: nothing.
        let inner = [[2.0, 2.0], [3.0, 2.0], [3.0, 3.0], [2.0, 3.0]];
        assert!((area(&clip_polygon(&inner, FRAME)) - 1.0).abs() < 1e-12);
        let outer = [[20.0, 2.0], [21.0, 2.0], [21.0, 3.0]];
        assert!(clip_polygon(&outer, FRAME).is_empty());
    }
}
