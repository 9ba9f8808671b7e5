//! Hertz's analytic contact pressure (docs/DESIGN.md, "Reference"), and
//! where a candidate lies relative to the contact centre. The one copy of these
//! formulas: the reference comparison, `-tresca_bound hertz` and
//! `-plot_contact` all use them.

use std::f64::consts::PI;

use crate::options::HertzReference;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl HertzReference {
    /// The dimension of Hertz's formula: 2 for a cylinder (in 2D, or in 3D
    /// lying along `-reference_axis`: a line contact), 3 for a sphere.
    pub fn formula_dim(&self, dim: usize) -> usize {
        if self.axis.is_some() {
            2
        } else {
            dim
        }
    }

    /// Hertz's pressure, peak and half-width ([`pressure`]) at distance
    /// `x` from the contact centre or line.
    pub fn pressure(&self, dim: usize, e_star: f64, x: f64) -> (f64, f64, f64) {
        pressure(self.formula_dim(dim), self.force, self.radius, e_star, x)
    }

    /// The cylinder's axis across `n` (unit): the contact line's
    /// direction; None for a sphere, or where the axis lies within 25
    /// degrees of `n` (no line across it: the set-up refuses that where
    /// `-contact_direction` is given).
    pub fn line(&self, n: &[f64]) -> Option<Vec<f64>> {
        let a = self.axis.as_ref().filter(|a| a.len() == n.len())?;
        let an = dot(a, n);
        let across: Vec<f64> = a.iter().zip(n).map(|(x, y)| x - an * y).collect();
        let norm = dot(&across, &across).sqrt();
        (norm > 0.42).then(|| across.iter().map(|v| v / norm).collect())
    }

    /// Hertz's pressure at point `x` and its distance from the contact
    /// centre or line ([`HertzReference::distance`]), with the peak and
    /// the half-width: zero off the contact's side of the body, where `x`
    /// lies farther from the tangent plane at the centre than the
    /// half-width (the top of a whole disc or ball, whose projection falls
    /// in the zone; in the zone a surface of radius R departs from the
    /// plane by x^2 / 2R, far less).
    pub fn pressure_at(
        &self,
        dim: usize,
        e_star: f64,
        x: &[f64],
        center: &[f64],
        n: &[f64],
    ) -> (f64, f64, f64, f64) {
        let dist = self.distance(x, center, n);
        let (p, p0, b) = self.pressure(dim, e_star, dist);
        let p = if normal_offset(x, center, n).abs() > b {
            0.0
        } else {
            p
        };
        (p, p0, b, dist)
    }

    /// The distance of `x` orthogonal to `n` from the contact centre (a
    /// sphere), or from the contact line through it (a cylinder along
    /// the axis).
    pub fn distance(&self, x: &[f64], center: &[f64], n: &[f64]) -> f64 {
        let t = tangential_offset(x, center, n);
        let along = self.line(n).map_or(0.0, |a| dot(&t, &a));
        (dot(&t, &t) - along * along).max(0.0).sqrt()
    }
}

/// Hertz pressure at distance `x` from the centre, with the peak pressure
/// p0 and the half-width (b in 2D, a in 3D): a cylinder on a plane in 2D (F
/// per unit thickness), a sphere in 3D; `e_star` = E / (1 - nu^2).
pub fn pressure(dim: usize, force: f64, radius: f64, e_star: f64, x: f64) -> (f64, f64, f64) {
    if dim == 2 {
        // Cylinder on a plane: b = 2 sqrt(F R / (pi E*)), p = 2F/(pi b^2) sqrt(b^2 - x^2).
        let b = 2.0 * (force * radius / (PI * e_star)).sqrt();
        let p0 = 2.0 * force / (PI * b);
        let p = if x < b {
            2.0 * force / (PI * b * b) * (b * b - x * x).sqrt()
        } else {
            0.0
        };
        (p, p0, b)
    } else {
        // Sphere: a = (3FR/(4E*))^(1/3), p0 = 3F/(2 pi a^2).
        let a = (3.0 * force * radius / (4.0 * e_star)).cbrt();
        let p0 = 3.0 * force / (2.0 * PI * a * a);
        let p = if x < a {
            p0 * (1.0 - x * x / (a * a)).sqrt()
        } else {
            0.0
        };
        (p, p0, a)
    }
}

/// The contact centre: `given` (`-reference_center`), else the position of
/// the candidate with the smallest gap among `(gap, x)`.
pub fn center<'a>(
    given: Option<&[f64]>,
    dim: usize,
    candidates: impl Iterator<Item = (f64, &'a [f64])>,
) -> Vec<f64> {
    if let Some(c) = given {
        return c.to_vec();
    }
    candidates
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, x)| x[..dim].to_vec())
        .unwrap_or(vec![0.0; dim])
}

/// The component of `x - center` along `n`.
pub fn normal_offset(x: &[f64], center: &[f64], n: &[f64]) -> f64 {
    n.iter()
        .enumerate()
        .map(|(k, nk)| (x[k] - center[k]) * nk)
        .sum()
}

/// `x - center` without its component along `n`.
pub fn tangential_offset(x: &[f64], center: &[f64], n: &[f64]) -> Vec<f64> {
    let dx: Vec<f64> = n
        .iter()
        .enumerate()
        .map(|(k, _)| x[k] - center[k])
        .collect();
    let dn: f64 = dx.iter().zip(n).map(|(a, b)| a * b).sum();
    dx.iter().zip(n).map(|(a, b)| a - dn * b).collect()
}

/// Distance of `x` from `center` orthogonal to `n` (the Hertz radius).
pub fn distance(x: &[f64], center: &[f64], n: &[f64]) -> f64 {
    tangential_offset(x, center, n)
        .iter()
        .map(|v| v * v)
        .sum::<f64>()
        .sqrt()
}

/// 2D: the signed coordinate of `x` along the surface from `center`, along
/// the tangent t = (-n_y, n_x) (for n = (0,-1), t = (1,0): x grows).
pub fn coordinate_2d(x: &[f64], center: &[f64], n: &[f64]) -> f64 {
    let t = [-n[1], n[0]];
    (x[0] - center[0]) * t[0] + (x[1] - center[1]) * t[1]
}

/// The part of the whole contact a model cut by symmetry planes carries:
/// 1/2 for each axis across n along which the contact zone (`offsets`: the
/// tangential offsets from the centre of the candidates in contact) lies on
/// one side of the centre, spreading to the other. The axes: in 2D the
/// tangent (any symmetry line of the contact contains n), in 3D the
/// coordinate axes across n, or across a contact `line` (3D, unit, across
/// n) the direction n x line alone (a cut across the line leaves the load
/// per unit length).
pub fn symmetric_part(offsets: &[Vec<f64>], n: &[f64], line: Option<&[f64]>) -> f64 {
    let axes: Vec<Vec<f64>> = if n.len() == 2 {
        vec![vec![-n[1], n[0]]]
    } else if let Some(l) = line {
        vec![vec![
            n[1] * l[2] - n[2] * l[1],
            n[2] * l[0] - n[0] * l[2],
            n[0] * l[1] - n[1] * l[0],
        ]]
    } else {
        (0..n.len())
            .filter(|&k| n[k].abs() < 0.99)
            .map(|k| (0..n.len()).map(|c| f64::from(u8::from(c == k))).collect())
            .collect()
    };
    let size = offsets
        .iter()
        .flat_map(|o| o.iter().map(|v| v.abs()))
        .fold(0.0, f64::max);
    let eps = 1e-6 * size;
    let mut part = 1.0;
    for axis in &axes {
        let along = |o: &Vec<f64>| o.iter().zip(axis).map(|(a, b)| a * b).sum::<f64>();
        let lo = offsets.iter().map(along).fold(f64::INFINITY, f64::min);
        let hi = offsets.iter().map(along).fold(f64::NEG_INFINITY, f64::max);
        if hi - lo > eps && (lo >= -eps || hi <= eps) {
            part *= 0.5;
        }
    }
    part
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetric_part_counts_the_cut_axes() {
        let n2 = [0.0, -1.0];
        let one_side = [vec![0.0, 0.0], vec![0.1, 0.0], vec![0.2, 0.0]];
        let both = [vec![-0.1, 0.0], vec![0.0, 0.0], vec![0.2, 0.0]];
        assert_eq!(symmetric_part(&one_side, &n2, None), 0.5);
        assert_eq!(symmetric_part(&both, &n2, None), 1.0);
        // One node at the centre: nothing to tell.
        assert_eq!(symmetric_part(&[vec![0.0, 0.0]], &n2, None), 1.0);
        // A half model whose symmetry line is not a coordinate axis.
        let (c, sn) = (0.6f64, 0.8f64);
        let tilted: Vec<Vec<f64>> = [0.0, 0.1, 0.2]
            .iter()
            .map(|&a| vec![a * c, a * sn])
            .collect();
        assert_eq!(symmetric_part(&tilted, &[sn, -c], None), 0.5);
        let n3 = [0.0, 0.0, -1.0];
        let quarter = [
            vec![0.0, 0.0, 0.0],
            vec![0.1, 0.0, 0.0],
            vec![0.0, 0.1, 0.0],
            vec![0.1, 0.1, 0.0],
        ];
        let half = [
            vec![0.0, -0.1, 0.0],
            vec![0.1, 0.0, 0.0],
            vec![0.0, 0.1, 0.0],
        ];
        assert_eq!(symmetric_part(&quarter, &n3, None), 0.25);
        assert_eq!(symmetric_part(&half, &n3, None), 0.5);
        // A line contact along y cut at its end (a quarter model): the cut
        // across the line leaves the load per unit length whole.
        let y = [0.0, 1.0, 0.0];
        assert_eq!(symmetric_part(&quarter, &n3, Some(&y)), 0.5);
        let across_both = [vec![-0.1, 0.0, 0.0], vec![0.1, 0.3, 0.0]];
        assert_eq!(symmetric_part(&across_both, &n3, Some(&y)), 1.0);
    }

    #[test]
    fn line_contact_distances() {
        let reference = |axis: Option<Vec<f64>>| HertzReference {
            force: 1.0,
            radius: 1.0,
            center: None,
            axis,
        };
        let n = [0.0, 0.0, -1.0];
        let line = reference(Some(vec![0.0, 1.0, 0.0]));
        // From the line along y through the centre: only x counts.
        let x = [3.0, 40.0, 7.0];
        assert!((line.distance(&x, &[0.0, 0.0, 0.0], &n) - 3.0).abs() < 1e-15);
        assert!((reference(None).distance(&x, &[0.0; 3], &n) - 3.0f64.hypot(40.0)).abs() < 1e-12);
        // An axis given tilted out of the tangent plane: its part across n.
        let tilted = reference(Some(vec![0.0, 1.0, 1.0]));
        assert!((tilted.distance(&x, &[0.0; 3], &n) - 3.0).abs() < 1e-12);
        // Along n: no line.
        assert!(reference(Some(vec![0.0, 0.0, 1.0])).line(&n).is_none());
        assert_eq!(line.formula_dim(3), 2);
        assert_eq!(reference(None).formula_dim(3), 3);
    }

    #[test]
    fn hertz_2d_integrates_to_the_force() {
        // The integral of p over (-b, b) is F.
        let (f, r, e) = (1600.0, 8.0, 2000.0 / (1.0 - 0.09));
        let (_, _, b) = pressure(2, f, r, e, 0.0);
        let m = 200000;
        let h = 2.0 * b / m as f64;
        let total: f64 = (0..m)
            .map(|i| pressure(2, f, r, e, (-b + (i as f64 + 0.5) * h).abs()).0 * h)
            .sum();
        assert!((total - f).abs() < 1e-3 * f);
    }

    #[test]
    fn hertz_3d_integrates_to_the_force() {
        let (f, r, e) = (1000.0, 0.5, 1e6);
        let (_, _, a) = pressure(3, f, r, e, 0.0);
        let m = 100000;
        let h = a / m as f64;
        let total: f64 = (0..m)
            .map(|i| {
                let x = (i as f64 + 0.5) * h;
                pressure(3, f, r, e, x).0 * 2.0 * PI * x * h
            })
            .sum();
        assert!((total - f).abs() < 1e-3 * f);
    }

    #[test]
    fn distances_from_the_centre() {
        let n = [0.0, 0.0, -1.0];
        assert!((distance(&[3.0, 4.0, 7.0], &[0.0, 0.0, 0.0], &n) - 5.0).abs() < 1e-15);
        let n2 = [0.0, -1.0];
        assert_eq!(coordinate_2d(&[-2.0, 5.0], &[0.0, 0.0], &n2), -2.0);
        assert_eq!(coordinate_2d(&[2.0, 5.0], &[0.0, 0.0], &n2), 2.0);
        let pts = [[1.0, 2.0], [3.0, 4.0]];
        let c = center(
            None,
            2,
            [(0.5, &pts[0][..]), (0.1, &pts[1][..])].into_iter(),
        );
        assert_eq!(c, vec![3.0, 4.0]);
    }
}
