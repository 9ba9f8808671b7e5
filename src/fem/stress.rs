//! Stresses of the displacement field, one per cell: constant on a P1
//! cell, at the centre of a Q1 cell (`xi = 0`). Computed only when an
//! output asks for them (`-vtk`).

use super::{element, grad_p1_2d, grad_p1_3d};

/// Cauchy stress (3x3, row-major) and von Mises stress of one cell, for an
/// isotropic material with Young's modulus `young`, Poisson's ratio `nu`.
/// `x` holds the cell's vertex coordinates and `u` its vertex displacements,
/// `dim` values each: `dim + 1` vertices (P1, constant stress) or `2^dim`
/// (Q1, the stress at the cell's centre). In 2D, plane strain has `sigma_zz = nu (sigma_xx + sigma_yy)`,
/// plane stress `sigma_zz = 0`.
pub fn cell_stress(
    dim: usize,
    x: &[f64],
    u: &[f64],
    young: f64,
    nu: f64,
    plane_stress: bool,
) -> ([f64; 9], f64) {
    // strain eps_ij = (du_i/dx_j + du_j/dx_i) / 2
    let mut grad = [[0.0; 3]; 3]; // grad[i][j] = du_i / dx_j
    let k = x.len() / dim;
    if k != dim + 1 {
        let g = element::centre_gradients(dim, x);
        for a in 0..k {
            for i in 0..dim {
                for j in 0..dim {
                    grad[i][j] += u[a * dim + i] * g[a * dim + j];
                }
            }
        }
    } else if dim == 2 {
        let (g, _) = grad_p1_2d(&[[x[0], x[1]], [x[2], x[3]], [x[4], x[5]]]);
        for (a, ga) in g.iter().enumerate() {
            for i in 0..2 {
                for j in 0..2 {
                    grad[i][j] += u[a * 2 + i] * ga[j];
                }
            }
        }
    } else {
        let p = |a: usize| [x[3 * a], x[3 * a + 1], x[3 * a + 2]];
        let (g, _) = grad_p1_3d(&[p(0), p(1), p(2), p(3)]);
        for (a, ga) in g.iter().enumerate() {
            for i in 0..3 {
                for j in 0..3 {
                    grad[i][j] += u[a * 3 + i] * ga[j];
                }
            }
        }
    }
    let mut eps = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            eps[i][j] = 0.5 * (grad[i][j] + grad[j][i]);
        }
    }
    let mu = young / (2.0 * (1.0 + nu));
    let lambda = if dim == 2 && plane_stress {
        young * nu / (1.0 - nu * nu)
    } else {
        young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    };
    let tr = eps[0][0] + eps[1][1] + if dim == 3 { eps[2][2] } else { 0.0 };
    let mut s = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            s[3 * i + j] = 2.0 * mu * eps[i][j] + if i == j { lambda * tr } else { 0.0 };
        }
    }
    if dim == 2 {
        s[8] = if plane_stress {
            0.0
        } else {
            nu * (s[0] + s[4])
        };
    }
    let (sxx, syy, szz) = (s[0], s[4], s[8]);
    let (sxy, syz, sxz) = (s[1], s[5], s[2]);
    let vm = (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2))
        + 3.0 * (sxy * sxy + syz * syz + sxz * sxz))
        .sqrt();
    (s, vm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_tension_3d() {
        // u = (eps x, -nu eps y, -nu eps z): uniaxial stress E eps along x.
        let (e, nu, eps) = (1000.0, 0.3, 1e-3);
        let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut u = [0.0; 12];
        for a in 0..4 {
            u[3 * a] = eps * x[3 * a];
            u[3 * a + 1] = -nu * eps * x[3 * a + 1];
            u[3 * a + 2] = -nu * eps * x[3 * a + 2];
        }
        let (s, vm) = cell_stress(3, &x, &u, e, nu, false);
        assert!((s[0] - e * eps).abs() < 1e-9);
        assert!(s[4].abs() < 1e-9 && s[8].abs() < 1e-9 && s[1].abs() < 1e-12);
        assert!((vm - e * eps).abs() < 1e-9);
    }

    #[test]
    fn q1_uniaxial_tension_at_the_centre() {
        // A distorted hexahedron and quadrilateral under a linear field: the
        // centre stress is the exact one.
        let (e, nu, eps) = (1000.0, 0.3, 1e-3);
        let mut x = Vec::new();
        for (a, c) in element::HEX_CORNERS.iter().enumerate() {
            let s = 0.05 * (a as f64) - 0.2;
            x.extend_from_slice(&[c[0] + s, 1.5 * c[1] - 0.5 * s, c[2] + 0.3 * s]);
        }
        let u: Vec<f64> = x
            .chunks(3)
            .flat_map(|p| [eps * p[0], -nu * eps * p[1], -nu * eps * p[2]])
            .collect();
        let (s, vm) = cell_stress(3, &x, &u, e, nu, false);
        assert!((s[0] - e * eps).abs() < 1e-9 && s[4].abs() < 1e-9 && s[8].abs() < 1e-9);
        assert!((vm - e * eps).abs() < 1e-9);
        let x = [0.0, 0.0, 2.0, 0.3, 1.7, 1.9, -0.2, 1.1];
        let u: Vec<f64> = x.chunks(2).flat_map(|p| [1e-3 * p[0], 0.0]).collect();
        let (s, _) = cell_stress(2, &x, &u, e, nu, true);
        assert!((s[0] - e / (1.0 - nu * nu) * 1e-3).abs() < 1e-9 && s[8] == 0.0);
    }

    #[test]
    fn plane_strain_out_of_plane_stress() {
        let (e, nu) = (200.0, 0.25);
        let x = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
        let u = [0.0, 0.0, 1e-3, 0.0, 0.0, 0.0]; // eps_xx = 1e-3
        let (s, _) = cell_stress(2, &x, &u, e, nu, false);
        assert!((s[8] - nu * (s[0] + s[4])).abs() < 1e-12);
        let (s, _) = cell_stress(2, &x, &u, e, nu, true);
        assert!((s[0] - e / (1.0 - nu * nu) * 1e-3).abs() < 1e-12 && s[8] == 0.0);
    }
}
