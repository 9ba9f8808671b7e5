//! The contact set: candidate nodes of Gamma_c owned by this rank, their
//! nodal weights `w_i`, gaps `g_i` along the fixed direction `n`, and the
//! pointwise projections of the paper, (4.15) and (5.5).

use crate::error::{bad, Error};
use crate::fem::element::facet_weights;
use crate::mesh::distribute::LocalMesh;
use crate::options::{ContactSettings, Obstacle};

/// Candidates owned by this rank.
#[derive(Clone, Debug, Default)]
pub struct ContactSet {
    pub dim: usize,
    /// Unit contact direction n.
    pub n: Vec<f64>,
    /// Local node index (an owned node) of each candidate.
    pub node: Vec<usize>,
    /// Nodal weight w_i (trapezoidal quadrature on Gamma_c).
    pub w: Vec<f64>,
    /// Gap g_i along n (negative: initial penetration).
    pub g: Vec<f64>,
}

impl ContactSet {
    pub fn len(&self) -> usize {
        self.node.len()
    }
    pub fn is_empty(&self) -> bool {
        self.node.is_empty()
    }

    /// Builds the owned candidates of `settings.surface`. The caller checks the
    /// global candidate count (a surface with no candidate is bad input).
    pub fn build(mesh: &LocalMesh, settings: &ContactSettings) -> Result<ContactSet, Error> {
        let d = mesh.dim;
        let Some(group) = mesh.group(&settings.surface) else {
            return bad(format!(
                "option -contact_surface: the mesh has no physical group '{}' (it has: {})",
                settings.surface,
                mesh.group_names()
            ));
        };
        if settings.direction.len() != d {
            return bad(format!(
                "option -contact_direction: {} components given, the mesh is {}D",
                settings.direction.len(),
                d
            ));
        }
        if group.dim + 1 != d {
            return bad(format!(
                "option -contact_surface: group '{}' has dimension {}, a contact surface needs dimension {}",
                settings.surface,
                group.dim,
                d - 1
            ));
        }
        match &settings.obstacle {
            Obstacle::Plane { point } if point.len() != d => {
                return bad(format!(
                    "option -obstacle_point: {} components given, the mesh is {}D",
                    point.len(),
                    d
                ))
            }
            Obstacle::Ball { center, .. } | Obstacle::HalfBall { center, .. }
                if center.len() != d =>
            {
                return bad(format!(
                    "option -obstacle_center: {} components given, the mesh is {}D",
                    center.len(),
                    d
                ))
            }
            _ => {}
        }
        let n = &settings.direction;
        // Weights of every owned node of the surface.
        let mut weight = vec![0.0; mesh.owned_count];
        let mut on_surface = vec![false; mesh.owned_count];
        // w_i: sum over the facets of the surface touching node i of the
        // facet's nodal weight (measure / vertices for a simplex facet;
        // int N_i dA for a quadrilateral, a quarter of a parallelogram;
        // `element::facet_weights`).
        let mut share = Vec::with_capacity(4);
        for e in &group.conn {
            let pts: Vec<&[f64]> = e.iter().map(|&v| mesh.x(v)).collect();
            facet_weights(&pts, &mut share);
            for (&v, &w) in e.iter().zip(&share) {
                if mesh.is_owned(v) {
                    weight[v] += w;
                    on_surface[v] = true;
                }
            }
        }
        let mut set = ContactSet {
            dim: d,
            n: n.clone(),
            ..Default::default()
        };
        for v in 0..mesh.owned_count {
            if !on_surface[v] {
                continue;
            }
            if let Some(g) = gap(mesh.x(v), n, &settings.obstacle) {
                set.node.push(v);
                set.w.push(weight[v]);
                set.g.push(g);
            }
        }
        Ok(set)
    }
}

/// Gap from `x` along `n` to the obstacle, or `None` when the line `x + t n`
/// misses it (ball only; DESIGN.md: candidate only if it meets the sphere at
/// two points and t2 > 0, then g = t1). A half-ball on its floor is the union
/// of the ball and the half-space beyond the plane through the centre: the
/// line enters the ball first where it meets it (t1 <= the plane's t), and
/// the floor elsewhere, so every node is a candidate.
pub fn gap(x: &[f64], n: &[f64], obstacle: &Obstacle) -> Option<f64> {
    let along = |p: &[f64]| -> f64 { p.iter().zip(x).zip(n).map(|((p, x), n)| (p - x) * n).sum() };
    match obstacle {
        Obstacle::Plane { point } => Some(along(point)),
        Obstacle::Ball { center, radius } => ball_entry(x, n, center, *radius),
        Obstacle::HalfBall { center, radius } => {
            Some(ball_entry(x, n, center, *radius).unwrap_or_else(|| along(center)))
        }
    }
}

/// Where the line `x + t n` enters the ball: `t1` when it meets the sphere at
/// `t1 < t2` with `t2 > 0`, else `None`.
fn ball_entry(x: &[f64], n: &[f64], center: &[f64], radius: f64) -> Option<f64> {
    // |x + t n - c|^2 = R^2, |n| = 1: t^2 + 2 t (x-c).n + |x-c|^2 - R^2 = 0.
    let dc: Vec<f64> = x.iter().zip(center).map(|(x, c)| x - c).collect();
    let b = dc.iter().zip(n).map(|(a, b)| a * b).sum::<f64>();
    let c = dc.iter().map(|a| a * a).sum::<f64>() - radius * radius;
    let disc = b * b - c;
    if disc <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let (t1, t2) = (-b - s, -b + s);
    (t2 > 0.0).then_some(t1)
}

/// The contact projection (4.15) with the multiplier update (4.4) at one node:
/// returns `(phi, lambda_next, in_contact)` for normal displacement `un`,
/// multiplier `lambda`, gap `g`, augmentation `r` and step `rho`.
#[inline]
pub fn project_normal(un: f64, lambda: f64, g: f64, r: f64, rho: f64) -> (f64, f64, bool) {
    let gamma = (lambda + r * (un - g)).max(0.0); // (4.14)
    let phi = un + (lambda - gamma) / r; // (4.15)
                                         // (4.4): lambda + rho (un - phi) = lambda + (rho / r)(gamma - lambda); the
                                         // second form gives gamma exactly (so lambda >= 0 exactly) when rho = r.
    let lambda_next = lambda + (rho / r) * (gamma - lambda);
    (phi, lambda_next, gamma > 0.0)
}

/// The friction projection (5.5) with the multiplier update at one node, for
/// tangential displacement `ut`, multiplier `lambda` (both `dim` components,
/// tangent to n) and bound `s`: writes `phi` and `lambda_next`; returns
/// whether the node slips (the first branch of (5.5), `|lambda + r ut| > s`).
#[inline]
pub fn project_tangential(
    ut: &[f64],
    lambda: &[f64],
    s: f64,
    r: f64,
    rho: f64,
    phi: &mut [f64],
    lambda_next: &mut [f64],
) -> bool {
    let d = ut.len();
    let mut q = [0.0; 3];
    for c in 0..d {
        q[c] = lambda[c] + r * ut[c];
    }
    let norm = q[..d].iter().map(|v| v * v).sum::<f64>().sqrt();
    let slip = norm > s;
    // lambda + rho (ut - phi) = lambda + (rho / r)(target - lambda), with
    // target = q s/|q| (slip) or q (stick): |lambda_next| <= s when rho = r.
    let (phi_factor, target_factor) = if slip {
        ((norm - s) / (r * norm), s / norm)
    } else {
        (0.0, 1.0)
    };
    for c in 0..d {
        phi[c] = phi_factor * q[c];
        lambda_next[c] = lambda[c] + (rho / r) * (target_factor * q[c] - lambda[c]);
    }
    slip
}

/// The projection (4.14)-(4.15) with the update (4.4) at rho = r, written on
/// `z = lambda + r u_n` (the only combination of lambda and u_n it reads):
/// returns `(phi, lambda_next, in_contact)` with
/// `lambda_next = (z - r g)^+` and `phi = (z - lambda_next) / r`.
#[inline]
pub fn project_normal_z(z: f64, g: f64, r: f64) -> (f64, f64, bool) {
    let gamma = (z - r * g).max(0.0);
    ((z - gamma) / r, gamma, gamma > 0.0)
}

/// The projection (5.5) with the update at rho = r, on
/// `z = lambda_t + r u_t`: `lambda_next` is z projected onto the ball of
/// radius s, `phi = (z - lambda_next) / r`. Returns whether the node slips.
#[inline]
pub fn project_tangential_z(
    z: &[f64],
    s: f64,
    r: f64,
    phi: &mut [f64],
    lambda_next: &mut [f64],
) -> bool {
    let norm = z.iter().map(|v| v * v).sum::<f64>().sqrt();
    let slip = norm > s;
    let factor = if slip { s / norm } else { 1.0 };
    for c in 0..z.len() {
        lambda_next[c] = factor * z[c];
        phi[c] = (z[c] - lambda_next[c]) / r;
    }
    slip
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The z forms agree with the paper's forms at rho = r.
    #[test]
    fn z_forms_match_the_paper_forms() {
        let r = 2.5;
        for &(un, lam, g) in &[
            (0.5, 0.0, 0.2),
            (-1.0, 2.0, 0.0),
            (0.1, 10.0, 0.3),
            (0.3, 0.1, -0.2),
        ] {
            let (p1, l1, c1) = project_normal(un, lam, g, r, r);
            let (p2, l2, c2) = project_normal_z(lam + r * un, g, r);
            assert!((p1 - p2).abs() < 1e-12 && (l1 - l2).abs() < 1e-12 && c1 == c2);
        }
        let (ut, lt) = ([0.3, -0.4], [0.2, 0.1]);
        for s in [0.0, 0.5, 10.0] {
            let (mut p1, mut l1, mut p2, mut l2) = ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
            let a = project_tangential(&ut, &lt, s, r, r, &mut p1, &mut l1);
            let z = [lt[0] + r * ut[0], lt[1] + r * ut[1]];
            let b = project_tangential_z(&z, s, r, &mut p2, &mut l2);
            assert_eq!(a, b);
            for c in 0..2 {
                assert!((p1[c] - p2[c]).abs() < 1e-12 && (l1[c] - l2[c]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn projection_is_feasible_and_idempotent() {
        let r = 3.0;
        for &(un, lam, g) in &[
            (0.5, 0.0, 0.2),
            (-1.0, 2.0, 0.0),
            (0.1, 10.0, 0.3),
            (0.0, 0.0, 0.0),
        ] {
            let (phi, lnext, _) = project_normal(un, lam, g, r, r);
            assert!(phi <= g + 1e-15, "phi {phi} > g {g}");
            assert!(lnext >= 0.0);
            // With rho = r the update is lambda+ = (lambda + r(un - g))^+.
            assert!((lnext - (lam + r * (un - g)).max(0.0)).abs() < 1e-12);
            // Projecting phi itself with the next multiplier is a fixed point.
            let (phi2, l2, _) = project_normal(phi, lnext, g, r, r);
            if lnext > 0.0 {
                assert!((phi2 - g).abs() < 1e-12 && (l2 - lnext).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn large_r_limit_is_the_obstacle_projection() {
        let (phi, _, _) = project_normal(0.5, 0.0, 0.2, 1e12, 1e12);
        assert!((phi - 0.2).abs() < 1e-9);
        let (phi, _, c) = project_normal(0.1, 0.0, 0.2, 1e12, 1e12);
        assert!((phi - 0.1).abs() < 1e-9 && !c);
    }

    #[test]
    fn friction_projection_bounds_and_limits() {
        let r = 2.0;
        let mut phi = [0.0; 2];
        let mut lam = [0.0; 2];
        // Slip: |lambda+| = s, phi along q.
        let slip = project_tangential(&[1.0, 0.5], &[0.3, -0.1], 0.7, r, r, &mut phi, &mut lam);
        assert!(slip);
        let nl = (lam[0] * lam[0] + lam[1] * lam[1]).sqrt();
        assert!((nl - 0.7).abs() < 1e-14);
        let q = [0.3 + 2.0, -0.1 + 1.0];
        assert!((phi[0] * q[1] - phi[1] * q[0]).abs() < 1e-14 && phi[0] * q[0] > 0.0);
        // Stick: phi = 0, lambda+ = lambda + r ut.
        let slip = project_tangential(&[0.01, 0.0], &[0.1, 0.0], 5.0, r, r, &mut phi, &mut lam);
        assert!(!slip && phi == [0.0, 0.0] && (lam[0] - 0.12).abs() < 1e-15);
        // s = 0: frictionless, lambda+ = 0, phi = ut + lambda/r.
        project_tangential(&[0.4, -0.2], &[0.2, 0.0], 0.0, r, r, &mut phi, &mut lam);
        assert!(lam.iter().all(|v| v.abs() < 1e-15));
        assert!((phi[0] - 0.5).abs() < 1e-15 && (phi[1] + 0.2).abs() < 1e-15);
        // Idempotence: projecting the fixed point again changes nothing.
        let (ut, l0) = ([0.3, 0.4], [0.6, 0.0]);
        let mut p1 = [0.0; 2];
        let mut l1 = [0.0; 2];
        project_tangential(&ut, &l0, 0.5, r, r, &mut p1, &mut l1);
        let mut p2 = [0.0; 2];
        let mut l2 = [0.0; 2];
        project_tangential(&p1, &l1, 0.5, r, r, &mut p2, &mut l2);
        assert!((p2[0] - p1[0]).abs() < 1e-14 && (l2[1] - l1[1]).abs() < 1e-14);
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
