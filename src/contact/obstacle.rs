//! The rigid obstacle, the gap along the contact direction n, and the gap
//! and normal from a node's closest point (docs/DESIGN.md,
//! "Discretization": the gap).

pub use crate::options::Obstacle;

impl Obstacle {
    /// A point of the obstacle: the plane's point, the ball's centre.
    pub fn anchor(&self) -> &[f64] {
        match self {
            Obstacle::Plane { point } => point,
            Obstacle::Ball { center, .. }
            | Obstacle::HalfBall { center, .. }
            | Obstacle::Cylinder { center, .. } => center,
            // (A surface has no one point: callers take the candidate
            // with the smallest gap.)
            Obstacle::Mesh { .. } => &[],
        }
    }
}

/// Gap from `x` along `n` to the obstacle, or `None` when the line `x + t n`
/// misses it (ball only; docs/DESIGN.md: candidate only if it meets the
/// sphere at two points and t2 > 0, then g = t1). A half-ball on its floor
/// is the union of the ball and the half-space beyond the plane through the
/// centre: the line enters the ball first where it meets it (t1 <= the
/// plane's t), and the floor elsewhere, so every node is a candidate.
pub fn gap(x: &[f64], n: &[f64], obstacle: &Obstacle) -> Option<f64> {
    let along = |p: &[f64]| -> f64 { p.iter().zip(x).zip(n).map(|((p, x), n)| (p - x) * n).sum() };
    // Where the line enters: t1 of the meeting points t1 < t2, t2 > 0.
    let entry = |(t1, t2): (f64, f64)| (t2 > 0.0).then_some(t1);
    match obstacle {
        Obstacle::Plane { point } => Some(along(point)),
        Obstacle::Ball { center, radius } => meets(x, n, center, &[], *radius).and_then(entry),
        Obstacle::HalfBall { center, radius } => Some(
            meets(x, n, center, &[], *radius)
                .and_then(entry)
                .unwrap_or_else(|| along(center)),
        ),
        Obstacle::Cylinder {
            center,
            axis,
            radius,
        } => meets(x, n, center, axis, *radius).and_then(entry),
        // (Refused by the options: a surface's gaps are closest-point ones,
        // [`crate::contact::mesh_obstacle`].)
        Obstacle::Mesh { .. } => None,
    }
}

/// `v` without its component along the unit `axis` (empty axis: `v`).
fn off_axis(v: &[f64], axis: &[f64]) -> Vec<f64> {
    let along: f64 = v.iter().zip(axis).map(|(a, b)| a * b).sum();
    let mut out = v.to_vec();
    for (o, a) in out.iter_mut().zip(axis) {
        *o -= along * a;
    }
    out
}

/// The signed distance from `x` to the obstacle along the direction to its
/// closest point, and the unit normal from `x` toward that point
/// (`direction`: the floor's normal of a half-ball, the plane's n). `None`
/// for a node on a ball's centre or a cylinder's axis, where no direction
/// is the closest.
pub fn closest(x: &[f64], direction: &[f64], obstacle: &Obstacle) -> Option<(f64, Vec<f64>)> {
    let radial = |center: &[f64], axis: &[f64], radius: f64| {
        let (dist, dc) = from_axis(x, center, axis);
        (dist > 0.0).then(|| (dist - radius, dc.iter().map(|v| -v / dist).collect()))
    };
    match obstacle {
        Obstacle::Plane { .. } => Some((gap(x, direction, obstacle)?, direction.to_vec())),
        Obstacle::Ball { center, radius } => radial(center, &[], *radius),
        Obstacle::Cylinder {
            center,
            axis,
            radius,
        } => radial(center, axis, *radius),
        Obstacle::HalfBall { center, radius } => {
            // The solid is the ball and the half-space beyond the floor:
            // the nearer of the two (the ball on a tie).
            let floor: f64 = (0..x.len())
                .map(|c| (center[c] - x[c]) * direction[c])
                .sum();
            match radial(center, &[], *radius) {
                Some((g, n)) if g <= floor => Some((g, n)),
                _ => Some((floor, direction.to_vec())),
            }
        }
        // (Read into a [`crate::contact::mesh_obstacle::MeshObstacle`] by
        // the contact set, which asks it.)
        Obstacle::Mesh { .. } => None,
    }
}

/// The distance of `x` from a centre (empty `axis`) or from the axis
/// through it, and the offset `x - center` without its part along the axis.
fn from_axis(x: &[f64], center: &[f64], axis: &[f64]) -> (f64, Vec<f64>) {
    let dc: Vec<f64> = x.iter().zip(center).map(|(x, c)| x - c).collect();
    let dc = off_axis(&dc, axis);
    (dc.iter().map(|v| v * v).sum::<f64>().sqrt(), dc)
}

/// Where the line `x + t n` (unit `n`) meets the sphere of `radius` about
/// `center` (empty `axis`), or the cylinder about the axis through it: the
/// parameters `t1 < t2`; `None` when it misses (or runs along the axis).
fn meets(x: &[f64], n: &[f64], center: &[f64], axis: &[f64], radius: f64) -> Option<(f64, f64)> {
    // The line and the centre seen in the plane orthogonal to the axis,
    // where the cylinder is a disc: n's part there, of length len.
    let (np, len) = if axis.is_empty() {
        (n.to_vec(), 1.0)
    } else {
        let np = off_axis(n, axis);
        let len = np.iter().map(|v| v * v).sum::<f64>().sqrt();
        if len < 1e-12 {
            return None;
        }
        (np.iter().map(|v| v / len).collect(), len)
    };
    // |dc + t np|^2 = R^2: t^2 + 2 t dc.np + |dc|^2 - R^2 = 0.
    let (_, dc) = from_axis(x, center, axis);
    let b = dc.iter().zip(&np).map(|(a, b)| a * b).sum::<f64>();
    let c = dc.iter().map(|a| a * a).sum::<f64>() - radius * radius;
    let disc = b * b - c;
    if disc <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    Some(((-b - s) / len, (-b + s) / len))
}

/// Whether `x` lies inside a ball or a cylinder (None for the other
/// obstacles, which have no inside a body could fill).
pub fn inside_round(x: &[f64], obstacle: &Obstacle) -> Option<bool> {
    let (center, axis, radius) = round(obstacle)?;
    Some(from_axis(x, center, axis).0 < radius)
}

/// Whether the obstacle is a ball or a cylinder (it has an inside a body
/// could fill: [`inside_round`]).
pub fn is_round(obstacle: &Obstacle) -> bool {
    round(obstacle).is_some()
}

/// A ball's or a cylinder's centre, axis (empty for a ball) and radius.
fn round(obstacle: &Obstacle) -> Option<(&[f64], &[f64], f64)> {
    match obstacle {
        Obstacle::Ball { center, radius } => Some((center, &[], *radius)),
        Obstacle::Cylinder {
            center,
            axis,
            radius,
        } => Some((center, axis, *radius)),
        _ => None,
    }
}

/// [`closest`] for the cavity a ball or a cylinder bounds (a socket, a
/// bore: the rigid solid is outside it, the body inside): the gap
/// `radius - distance` from the centre (or the axis) and the unit normal
/// from `x` away from it, toward the wall. `None` on the centre (or the
/// axis), where no direction is the closest, and for the other obstacles.
pub fn cavity_closest(x: &[f64], obstacle: &Obstacle) -> Option<(f64, Vec<f64>)> {
    let (center, axis, radius) = round(obstacle)?;
    let (dist, dc) = from_axis(x, center, axis);
    (dist > 0.0).then(|| (radius - dist, dc.iter().map(|v| v / dist).collect()))
}

/// [`gap`] for the cavity of [`cavity_closest`]: from `x` along `n` to
/// where the line leaves the ball (or the cylinder), `t2` of the two
/// meeting points (negative when both lie behind: `x` beyond the wall);
/// `None` when the line misses it.
pub fn cavity_gap(x: &[f64], n: &[f64], obstacle: &Obstacle) -> Option<f64> {
    let (center, axis, radius) = round(obstacle)?;
    meets(x, n, center, axis, radius).map(|(_, t2)| t2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cavity_gaps_and_normals() {
        let ball = Obstacle::Ball {
            center: vec![0.0, 1.0],
            radius: 1.0,
        };
        // 0.25 below the centre: the wall below is 0.75 away, downward.
        let (g, n) = cavity_closest(&[0.0, 0.75], &ball).unwrap();
        assert!(
            (g - 0.75).abs() < 1e-15 && n == vec![0.0, -1.0],
            "{g} {n:?}"
        );
        assert_eq!(cavity_gap(&[0.0, 0.75], &[0.0, -1.0], &ball), Some(0.75));
        // Along a slanted n from the centre: the radius.
        let s = 0.5f64.sqrt();
        let t = cavity_gap(&[0.0, 1.0], &[s, -s], &ball).unwrap();
        assert!((t - 1.0).abs() < 1e-15, "{t}");
        // Beyond the wall (in the solid): a negative gap, a penetration.
        let (g, _) = cavity_closest(&[0.0, -0.1], &ball).unwrap();
        assert!((g + 0.1).abs() < 1e-15, "{g}");
        assert!(cavity_closest(&[0.0, 1.0], &ball).is_none());
        assert_eq!(inside_round(&[0.0, 0.75], &ball), Some(true));
        assert_eq!(inside_round(&[0.0, -0.1], &ball), Some(false));
        // A 3D cylinder along z: the axis direction does not count.
        let cyl = Obstacle::Cylinder {
            center: vec![0.0, 0.0, 0.0],
            axis: vec![0.0, 0.0, 1.0],
            radius: 2.0,
        };
        let (g, n) = cavity_closest(&[0.5, 0.0, 7.0], &cyl).unwrap();
        assert!(
            (g - 1.5).abs() < 1e-15 && n == vec![1.0, 0.0, 0.0],
            "{g} {n:?}"
        );
        let t = cavity_gap(&[0.5, 0.0, 7.0], &[s, 0.0, -s], &cyl).unwrap();
        assert!((t - 1.5 / s).abs() < 1e-12, "{t}");
        assert_eq!(inside_round(&[0.5, 0.0, 70.0], &cyl), Some(true));
        let plane = Obstacle::Plane {
            point: vec![0.0, 0.0],
        };
        assert!(inside_round(&[0.0, 0.0], &plane).is_none());
    }

    #[test]
    fn ball_gap() {
        let ball = Obstacle::Ball {
            center: vec![0.0, -1.0],
            radius: 0.5,
        };
        // Straight above the top of the circle (y=-0.5) by 0.5.
        let g = gap(&[0.0, 0.0], &[0.0, -1.0], &ball).unwrap();
        assert!((g - 0.5).abs() < 1e-14);
        assert!(gap(&[0.6, 0.0], &[0.0, -1.0], &ball).is_none());
        // Below the ball's centre line but t2 < 0: moving away from it.
        assert!(gap(&[0.0, -2.0], &[0.0, -1.0], &ball).is_none());
        let plane = Obstacle::Plane {
            point: vec![0.0, 0.0],
        };
        assert!((gap(&[3.0, 0.25], &[0.0, -1.0], &plane).unwrap() - 0.25).abs() < 1e-15);
    }

    #[test]
    fn closest_gaps_and_normals() {
        let ball = Obstacle::Ball {
            center: vec![0.0, -1.0],
            radius: 0.5,
        };
        // Beside the ball: radial gap and normal.
        let (g, n) = closest(&[1.0, -1.0], &[], &ball).unwrap();
        assert!((g - 0.5).abs() < 1e-15 && (n[0] + 1.0).abs() < 1e-15 && n[1] == 0.0);
        assert!(closest(&[0.0, -1.0], &[], &ball).is_none());
        // A 3D cylinder along z through (0, 0, 0), radius 1: radial to the axis.
        let cyl = Obstacle::Cylinder {
            center: vec![0.0, 0.0, 0.0],
            axis: vec![0.0, 0.0, 1.0],
            radius: 1.0,
        };
        let (g, n) = closest(&[0.0, 3.0, 7.0], &[], &cyl).unwrap();
        assert!((g - 2.0).abs() < 1e-15 && n == vec![0.0, -1.0, 0.0]);
        // Fixed direction on the cylinder: the line along -y meets it at y = 1.
        let g = gap(&[0.5, 3.0, 7.0], &[0.0, -1.0, 0.0], &cyl).unwrap();
        assert!((g - (3.0 - 0.75f64.sqrt())).abs() < 1e-14);
        // Along the axis the line never meets the surface.
        assert!(gap(&[0.0, 3.0, 7.0], &[0.0, 0.0, -1.0], &cyl).is_none());
        // Half-ball: the floor where it is nearer than the ball.
        let hb = Obstacle::HalfBall {
            center: vec![0.0, 0.0, -1.0],
            radius: 0.5,
        };
        let down = [0.0, 0.0, -1.0];
        let (g, n) = closest(&[2.0, 0.0, -0.5], &down, &hb).unwrap();
        assert!((g - 0.5).abs() < 1e-15 && n == down.to_vec());
        let (g, _) = closest(&[0.0, 0.0, -0.25], &down, &hb).unwrap();
        assert!((g - 0.25).abs() < 1e-15);
    }

    #[test]
    fn half_ball_gap() {
        // The paper's 3D obstacle: centre (-0.3, 0, -1), radius 0.5, n = -z.
        let hb = Obstacle::HalfBall {
            center: vec![-0.3, 0.0, -1.0],
            radius: 0.5,
        };
        let n = [0.0, 0.0, -1.0];
        // Above the pole: the same gap as the ball (touching at z = -0.5).
        assert!(gap(&[-0.3, 0.0, -0.5], &n, &hb).unwrap().abs() < 1e-15);
        let x = [-0.1, 0.2, -0.5];
        let ball = Obstacle::Ball {
            center: vec![-0.3, 0.0, -1.0],
            radius: 0.5,
        };
        assert_eq!(gap(&x, &n, &hb), gap(&x, &n, &ball));
        // Beside the ball: the floor z = -1, 0.5 below the bottom face,
        // where the ball alone has no candidate.
        assert!(gap(&[0.5, 0.9, -0.5], &n, &ball).is_none());
        assert!((gap(&[0.5, 0.9, -0.5], &n, &hb).unwrap() - 0.5).abs() < 1e-15);
        // Over the ball the entry is never beyond the floor.
        for i in 0..=20 {
            let x = [-0.8 + 0.05 * i as f64, 0.1, -0.5];
            assert!(gap(&x, &n, &hb).unwrap() <= 0.5 + 1e-15);
        }
    }
}
