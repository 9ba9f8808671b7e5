//! P1 linear elasticity: element kernels, the distributed stiffness matrix with
//! exact preallocation, surface tractions, lumped mass and Dirichlet data.
//!
//! Global degrees of freedom are node-major: dof `dim * node + component`, with
//! the renumbered (rank-contiguous) global node numbers of `LocalMesh`.

pub mod stress;

use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use crate::options::{DirichletBc, Settings, TractionBc};
use crate::petsc::{sys, Matrix};
use nalgebra::{SMatrix, SVector};

/// Isotropic Hooke law in Voigt notation (engineering shear strains).
pub fn hooke_2d(young: f64, nu: f64, plane_stress: bool) -> SMatrix<f64, 3, 3> {
    let (c11, c12, c33) = if plane_stress {
        let c = young / (1.0 - nu * nu);
        (c, c * nu, c * (1.0 - nu) / 2.0)
    } else {
        let c = young / ((1.0 + nu) * (1.0 - 2.0 * nu));
        (c * (1.0 - nu), c * nu, c * (1.0 - 2.0 * nu) / 2.0)
    };
    SMatrix::<f64, 3, 3>::new(c11, c12, 0.0, c12, c11, 0.0, 0.0, 0.0, c33)
}

pub fn hooke_3d(young: f64, nu: f64) -> SMatrix<f64, 6, 6> {
    let c = young / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let (a, b, g) = (c * (1.0 - nu), c * nu, young / (2.0 * (1.0 + nu)));
    let mut d = SMatrix::<f64, 6, 6>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            d[(i, j)] = if i == j { a } else { b };
        }
        d[(i + 3, i + 3)] = g;
    }
    d
}

/// Gradients of the P1 basis functions of a triangle and its area (> 0 unless degenerate).
pub fn grad_p1_2d(x: &[[f64; 2]; 3]) -> ([[f64; 2]; 3], f64) {
    let det = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]);
    let inv = 1.0 / det;
    let g = [
        [(x[1][1] - x[2][1]) * inv, (x[2][0] - x[1][0]) * inv],
        [(x[2][1] - x[0][1]) * inv, (x[0][0] - x[2][0]) * inv],
        [(x[0][1] - x[1][1]) * inv, (x[1][0] - x[0][0]) * inv],
    ];
    (g, 0.5 * det.abs())
}

/// Gradients of the P1 basis functions of a tetrahedron and its volume.
pub fn grad_p1_3d(x: &[[f64; 3]; 4]) -> ([[f64; 3]; 4], f64) {
    let j = SMatrix::<f64, 3, 3>::from_fn(|r, c| x[c + 1][r] - x[0][r]);
    let det = j.determinant();
    let jinv_t = j.try_inverse().unwrap_or_else(SMatrix::zeros).transpose();
    let mut g = [[0.0; 3]; 4];
    for (a, ga) in g.iter_mut().enumerate().skip(1) {
        let e = SVector::<f64, 3>::from_fn(|r, _| if r == a - 1 { 1.0 } else { 0.0 });
        let v = jinv_t * e;
        *ga = [v[0], v[1], v[2]];
    }
    let g0 = [0, 1, 2].map(|k| -(g[1][k] + g[2][k] + g[3][k]));
    g[0] = g0;
    (g, det.abs() / 6.0)
}

/// Element stiffness of a triangle (6x6, dofs node-major).
pub fn stiffness_2d(x: &[[f64; 2]; 3], d: &SMatrix<f64, 3, 3>) -> (SMatrix<f64, 6, 6>, f64) {
    let (g, area) = grad_p1_2d(x);
    let mut b = SMatrix::<f64, 3, 6>::zeros();
    for a in 0..3 {
        b[(0, 2 * a)] = g[a][0];
        b[(1, 2 * a + 1)] = g[a][1];
        b[(2, 2 * a)] = g[a][1];
        b[(2, 2 * a + 1)] = g[a][0];
    }
    (b.transpose() * d * b * area, area)
}

/// Element stiffness of a tetrahedron (12x12, dofs node-major).
pub fn stiffness_3d(x: &[[f64; 3]; 4], d: &SMatrix<f64, 6, 6>) -> (SMatrix<f64, 12, 12>, f64) {
    let (g, vol) = grad_p1_3d(x);
    let mut b = SMatrix::<f64, 6, 12>::zeros();
    for a in 0..4 {
        let (gx, gy, gz) = (g[a][0], g[a][1], g[a][2]);
        b[(0, 3 * a)] = gx;
        b[(1, 3 * a + 1)] = gy;
        b[(2, 3 * a + 2)] = gz;
        b[(3, 3 * a + 1)] = gz;
        b[(3, 3 * a + 2)] = gy;
        b[(4, 3 * a)] = gz;
        b[(4, 3 * a + 2)] = gx;
        b[(5, 3 * a)] = gy;
        b[(5, 3 * a + 1)] = gx;
    }
    (b.transpose() * d * b * vol, vol)
}

/// Measure of a simplex facet given its vertex coordinates (point: 1, segment: length, triangle: area).
pub fn facet_measure(pts: &[&[f64]]) -> f64 {
    match pts.len() {
        1 => 1.0,
        2 => pts[0]
            .iter()
            .zip(pts[1])
            .map(|(a, b)| (b - a) * (b - a))
            .sum::<f64>()
            .sqrt(),
        3 => {
            let mut u = [0.0; 3];
            let mut v = [0.0; 3];
            for k in 0..pts[0].len() {
                u[k] = pts[1][k] - pts[0][k];
                v[k] = pts[2][k] - pts[0][k];
            }
            let c = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
        }
        _ => 0.0,
    }
}

/// Exact preallocation of the owned rows: per dof row, the number of nonzero
/// columns in the diagonal block (owned columns) and outside it.
pub fn preallocation(mesh: &LocalMesh) -> (Vec<sys::PetscInt>, Vec<sys::PetscInt>) {
    let d = mesh.dim;
    let k = d + 1;
    let nown = mesh.owned_count;
    let mut adj: Vec<Vec<u32>> = vec![Vec::new(); nown];
    for cell in mesh.cells.chunks(k) {
        for &a in cell {
            if a < nown {
                for &b in cell {
                    adj[a].push(b as u32);
                }
            }
        }
    }
    let mut d_nnz = Vec::with_capacity(nown * d);
    let mut o_nnz = Vec::with_capacity(nown * d);
    for list in &mut adj {
        if list.is_empty() {
            list.push(0); // an isolated owned node still has its diagonal
        }
        list.sort_unstable();
        list.dedup();
        let inside = list.iter().filter(|&&b| (b as usize) < nown).count();
        let outside = list.len() - inside;
        for _ in 0..d {
            d_nnz.push((inside.max(1) * d) as sys::PetscInt);
            o_nnz.push((outside * d) as sys::PetscInt);
        }
    }
    (d_nnz, o_nnz)
}

/// The assembled elasticity data of this rank.
pub struct Elasticity {
    pub stiffness: Matrix,
    /// Lumped mass of each owned node (for the L2 norms of the stopping tests).
    pub lumped_mass: Vec<f64>,
}

/// Assembles K (only the rows this rank owns; no communication) and the lumped
/// mass. Extra owned diagonal 2x2/3x3 blocks can be added by `extra` before the
/// final assembly (the UBR term r B^T W B).
pub fn assemble_stiffness(
    comm: sys::MPI_Comm,
    mesh: &LocalMesh,
    settings: &Settings,
    extra: &[(usize, Vec<f64>)],
) -> Result<Elasticity, Error> {
    let d = mesh.dim;
    let k = d + 1;
    let (d_nnz, o_nnz) = preallocation(mesh);
    let mat = Matrix::new_aij(comm, mesh.owned_count * d, d, &d_nnz, &o_nnz)?;
    let mut mass = vec![0.0; mesh.owned_count];
    let nloc = d * k;
    let mut rows = vec![0 as sys::PetscInt; nloc];
    let mut cols = vec![0 as sys::PetscInt; nloc];
    let mut vals = vec![0.0; nloc * nloc];
    let d2 = hooke_2d(settings.young, settings.nu, settings.plane_stress);
    let d3 = hooke_3d(settings.young, settings.nu);
    for (c, cell) in mesh.cells.chunks(k).enumerate() {
        let measure;
        if d == 2 {
            let x = [0, 1, 2].map(|a| {
                let p = mesh.x(cell[a]);
                [p[0], p[1]]
            });
            let (ke, area) = stiffness_2d(&x, &d2);
            measure = area;
            for i in 0..6 {
                for j in 0..6 {
                    vals[i * 6 + j] = ke[(i, j)];
                }
            }
        } else {
            let x = [0, 1, 2, 3].map(|a| {
                let p = mesh.x(cell[a]);
                [p[0], p[1], p[2]]
            });
            let (ke, vol) = stiffness_3d(&x, &d3);
            measure = vol;
            for i in 0..12 {
                for j in 0..12 {
                    vals[i * 12 + j] = ke[(i, j)];
                }
            }
        }
        if measure.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !measure.is_finite() {
            let tags: Vec<String> = cell.iter().map(|&v| mesh.node_tag[v].to_string()).collect();
            return bad(format!(
                "degenerate element {} (nodes {}): zero measure",
                c,
                tags.join(" ")
            ));
        }
        for (a, &v) in cell.iter().enumerate() {
            let g = mesh.node_global[v];
            for comp in 0..d {
                cols[a * d + comp] = (g * d + comp) as sys::PetscInt;
                rows[a * d + comp] = if mesh.is_owned(v) {
                    (g * d + comp) as sys::PetscInt
                } else {
                    -1
                };
            }
            if mesh.is_owned(v) {
                mass[v] += measure / k as f64;
            }
        }
        mat.add_values(&rows, &cols, &vals)?;
    }
    for (local, block) in extra {
        let g = mesh.node_global[*local];
        let idx: Vec<sys::PetscInt> = (0..d).map(|c| (g * d + c) as sys::PetscInt).collect();
        mat.add_values(&idx, &idx, block)?;
    }
    mat.assemble()?;
    Ok(Elasticity {
        stiffness: mat,
        lumped_mass: mass,
    })
}

/// The load vector's owned entries from the surface tractions (nodal quadrature:
/// a facet of measure |F| with m vertices gives |F|/m * t to each vertex).
pub fn traction_load(mesh: &LocalMesh, tractions: &[TractionBc]) -> Result<Vec<f64>, Error> {
    let d = mesh.dim;
    let mut f = vec![0.0; mesh.owned_count * d];
    for t in tractions {
        let Some(group) = mesh.group(&t.group) else {
            return bad(format!(
                "option -traction_{}: the mesh has no physical group '{}' (it has: {})",
                t.group,
                t.group,
                mesh.group_names()
            ));
        };
        if t.traction.len() != d {
            return bad(format!(
                "option -traction_{}: {} components given, the mesh is {}D",
                t.group,
                t.traction.len(),
                d
            ));
        }
        if group.dim + 1 != d {
            return bad(format!(
                "option -traction_{}: group '{}' has dimension {}, a traction needs a boundary of dimension {}",
                t.group,
                t.group,
                group.dim,
                d - 1
            ));
        }
        let m = group.nodes_per_element();
        for e in group.conn.chunks(m) {
            let pts: Vec<&[f64]> = e.iter().map(|&v| mesh.x(v)).collect();
            let share = facet_measure(&pts) / m as f64;
            for &v in e {
                if mesh.is_owned(v) {
                    for c in 0..d {
                        f[v * d + c] += share * t.traction[c];
                    }
                }
            }
        }
    }
    Ok(f)
}

/// Owned Dirichlet dofs: (local dof index among owned dofs, value), sorted, unique.
pub fn dirichlet_dofs(mesh: &LocalMesh, bcs: &[DirichletBc]) -> Result<Vec<(usize, f64)>, Error> {
    let d = mesh.dim;
    let mut out = Vec::new();
    for bc in bcs {
        let Some(group) = mesh.group(&bc.group) else {
            return bad(format!(
                "option -dirichlet_{}: the mesh has no physical group '{}' (it has: {})",
                bc.group,
                bc.group,
                mesh.group_names()
            ));
        };
        for &(comp, value) in &bc.comps {
            if comp >= d {
                return bad(format!(
                    "option -dirichlet_{}: component u{} does not exist in {}D",
                    bc.group,
                    ["x", "y", "z"][comp],
                    d
                ));
            }
            for &v in &group.conn {
                if mesh.is_owned(v) {
                    out.push((v * d + comp, value));
                }
            }
        }
    }
    out.sort_by_key(|a| a.0);
    out.dedup_by(|a, b| a.0 == b.0);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_motions_are_in_the_kernel_2d() {
        let x = [[0.0, 0.0], [1.3, 0.2], [0.4, 0.9]];
        let (k, area) = stiffness_2d(&x, &hooke_2d(200.0, 0.3, false));
        assert!((area - 0.5 * (1.3 * 0.9 - 0.4 * 0.2)).abs() < 1e-14);
        let rot = SVector::<f64, 6>::from_fn(|i, _| {
            let a = i / 2;
            if i % 2 == 0 {
                -x[a][1]
            } else {
                x[a][0]
            }
        });
        let tx = SVector::<f64, 6>::from_fn(|i, _| if i % 2 == 0 { 1.0 } else { 0.0 });
        assert!((k * rot).norm() < 1e-10 * k.norm());
        assert!((k * tx).norm() < 1e-10 * k.norm());
        assert!((k - k.transpose()).norm() < 1e-12 * k.norm());
    }

    #[test]
    fn uniform_strain_energy_3d() {
        // u = (eps x, 0, 0): energy density 1/2 eps^2 (lambda + 2 mu) times volume.
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let (e, nu) = (1000.0, 0.25);
        let (k, vol) = stiffness_3d(&x, &hooke_3d(e, nu));
        assert!((vol - 1.0 / 6.0).abs() < 1e-14);
        let eps = 1e-3;
        let u =
            SVector::<f64, 12>::from_fn(|i, _| if i % 3 == 0 { eps * x[i / 3][0] } else { 0.0 });
        let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        let expect = 0.5 * eps * eps * (lam + 2.0 * mu) * vol;
        let got = 0.5 * (u.transpose() * k * u)[(0, 0)];
        assert!((got - expect).abs() < 1e-12 * expect.abs().max(1.0));
    }
}
