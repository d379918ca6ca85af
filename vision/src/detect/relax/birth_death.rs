//! Death and birth: a grain whose removal lowers the objective is removed (a duplicate, or a
//! grain fitted over field), and a grain fitted into a patch of dark area no outline covers is
//! added when it lowers the objective (a grain the acceptance missed, or one a removal or a
//! jump left room for).

use std::f64::consts::FRAC_PI_2;

use super::super::model::Pose;
use super::super::plane::Bordered;
use super::moves::Geometry;
use super::objective::Canvas;

/// A patch of unexplained dark area smaller than this fraction of a grain's area is left: a
/// sliver along outlines fitted a pixel off, or dust.
const LEAST_PATCH: f64 = 0.3;
/// Angles tried for a grain born in a patch, besides the patch's own axis and the axis at
/// right angles to it: a patch cut by its neighbours shows a grain's axis poorly.
const BIRTH_ANGLES: usize = 8;

/// The grains (indices into `poses`, alive and among those `asked`) whose removal lowers the
/// objective, removed one at a time in order.
pub fn deaths(
    canvas: &mut Canvas,
    poses: &[Pose],
    alive: &mut [bool],
    asked: &[bool],
) -> Vec<usize> {
    let mut died = Vec::new();
    for (g, p) in poses.iter().enumerate() {
        if alive[g] && asked.get(g) == Some(&true) && canvas.change(&[*p], &[]) < 0.0 {
            canvas.apply(&[*p], &[]);
            alive[g] = false;
            died.push(g);
        }
    }
    died
}

/// A 4-connected patch of unexplained dark pixels: its centroid and axis.
struct Patch {
    centre: (f64, f64),
    axis: f64,
}

/// The patches of dark area no outline covers, of at least `least` pixels, the frame's edge
/// not cutting them.
fn patches(canvas: &Canvas, least: usize) -> Vec<Patch> {
    let (w, h) = (canvas.width(), canvas.height());
    let mut seen = vec![false; w * h];
    let mut found = Vec::new();
    let mut stack = Vec::new();
    for start in 0..w * h {
        if seen[start] || !canvas.unexplained(start % w, start / w) {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let (mut n, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0usize, 0.0, 0.0, 0.0, 0.0, 0.0);
        let mut on_edge = false;
        while let Some(i) = stack.pop() {
            let (c, r) = (i % w, i / w);
            on_edge |= c == 0 || r == 0 || c + 1 == w || r + 1 == h;
            let (x, y) = (c as f64 + 0.5, r as f64 + 0.5);
            n += 1;
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
            sxy += x * y;
            let mut visit = |j: usize| {
                if !seen[j] && canvas.unexplained(j % w, j / w) {
                    seen[j] = true;
                    stack.push(j);
                }
            };
            if c > 0 {
                visit(i - 1);
            }
            if c + 1 < w {
                visit(i + 1);
            }
            if r > 0 {
                visit(i - w);
            }
            if r + 1 < h {
                visit(i + w);
            }
        }
        // A patch the frame's edge cuts may as well be the field darkening toward the edge
        // as a grain: the whole outline of neither is seen (a bare lab photograph's corner
        // gave a nut there).
        if n < least || on_edge {
            continue;
        }
        let k = n as f64;
        let (mx, my) = (sx / k, sy / k);
        let (vxx, vyy, vxy) = (sxx / k - mx * mx, syy / k - my * my, sxy / k - mx * my);
        // The long axis of the patch, as a pose angle (rows down: phi = -atan2(dy, dx)).
        let axis = -0.5 * (2.0 * vxy).atan2(vxx - vyy);
        found.push(Patch {
            centre: (mx, my),
            axis,
        });
    }
    found
}

/// Grains fitted into the patches of unexplained dark area, each added when it lowers the
/// objective and passes the acceptance's test (`accepted`, on the darkness no other grain
/// explains); returns the poses added, with their agreement.
pub fn births(
    canvas: &mut Canvas,
    geometry: &Geometry,
    accepted: impl Fn(Pose, &Bordered) -> Option<f64>,
) -> Vec<(Pose, f64)> {
    let least = (LEAST_PATCH * geometry.length * geometry.width) as usize;
    let mut born = Vec::new();
    let found = patches(canvas, least.max(1));
    if found.is_empty() {
        return born;
    }
    let mut free = Bordered::new(&canvas.free());
    for patch in found {
        let (x, y) = patch.centre;
        let mut angles = vec![patch.axis, patch.axis + FRAC_PI_2];
        angles.extend(
            (0..BIRTH_ANGLES).map(|k| k as f64 * std::f64::consts::PI / BIRTH_ANGLES as f64),
        );
        let mut best: Option<(Pose, f64)> = None;
        for phi in angles {
            let q = Pose { x, y, phi };
            let raw = canvas.change(&[], &[q]);
            canvas.apply(&[], &[q]);
            let (q, e) = geometry.polish(canvas, q, 2.0);
            canvas.apply(&[q], &[]);
            if raw + e < 0.0 && best.is_none_or(|b| raw + e < b.1) {
                best = Some((q, raw + e));
            }
        }
        if let Some((q, _)) = best
            && let Some(agreement) = accepted(q, &free)
        {
            canvas.apply(&[], &[q]);
            canvas.paint_free(q, &mut free);
            born.push((q, agreement));
        }
    }
    born
}
