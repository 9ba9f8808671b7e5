//! Linear elasticity: element kernels (P1 here, Q1 in [`element`]), the
//! distributed stiffness matrix with exact preallocation, surface
//! tractions, lumped mass and Dirichlet data. Cells of any supported kind
//! may be mixed (triangles with quadrilaterals, tetrahedra with hexahedra).
//!
//! Global degrees of freedom are node-major: dof `dim * node + component`, with
//! the renumbered (rank-contiguous) global node numbers of `LocalMesh`.

pub mod element;
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

/// Measure of a facet given its vertex coordinates (point: 1, segment:
/// length, triangle: area, quadrilateral: area of its bilinear surface):
/// the sum of its nodal weights [`element::facet_weights`].
pub fn facet_measure(pts: &[&[f64]]) -> f64 {
    let mut w = Vec::with_capacity(4);
    element::facet_weights(pts, &mut w);
    w.iter().sum()
}

/// The neighbours of each owned node (the nodes it shares a cell with,
/// itself included), in compressed rows sorted by global number: the
/// neighbours of owned node a are `nbr[ptr[a]..ptr[a + 1]]` (local numbers).
fn node_adjacency(mesh: &LocalMesh) -> (Vec<usize>, Vec<u32>) {
    let nown = mesh.owned_count;
    let mut count = vec![1usize; nown]; // itself
    for cell in &mesh.cells {
        for &a in cell {
            if a < nown {
                count[a] += cell.len() - 1;
            }
        }
    }
    let mut ptr = vec![0usize; nown + 1];
    for a in 0..nown {
        ptr[a + 1] = ptr[a] + count[a];
    }
    let mut nbr = vec![0u32; ptr[nown]];
    let mut fill = ptr[..nown].to_vec();
    for a in 0..nown {
        nbr[fill[a]] = a as u32;
        fill[a] += 1;
    }
    for cell in &mesh.cells {
        for &a in cell {
            if a < nown {
                for &b in cell {
                    if b != a {
                        nbr[fill[a]] = b as u32;
                        fill[a] += 1;
                    }
                }
            }
        }
    }
    // Sort and deduplicate each row, compacting in place.
    let mut out = 0;
    let mut start = 0;
    for a in 0..nown {
        let end = ptr[a + 1];
        let row = &mut nbr[start..end];
        row.sort_unstable_by_key(|&b| mesh.node_global[b as usize]);
        let mut len = 0;
        for i in 0..row.len() {
            if i == 0 || row[i] != row[len - 1] {
                row[len] = row[i];
                len += 1;
            }
        }
        nbr.copy_within(start..start + len, out);
        start = end;
        ptr[a] = out;
        out += len;
        ptr[a + 1] = out;
    }
    nbr.truncate(out);
    (ptr, nbr)
}

/// The assembled elasticity data of this rank.
pub struct Elasticity {
    pub stiffness: Matrix,
    /// Lumped mass of each owned node (for the L2 norms of the stopping tests).
    pub lumped_mass: Vec<f64>,
}

/// Assembles K (only the rows this rank owns; no communication) and the lumped
/// mass. Extra owned diagonal 2x2/3x3 blocks can be added by `extra` before the
/// final assembly (the UBR term r B^T W B). The rows are built here in
/// compressed form (the cells taken in the order of their lowest vertex) and
/// handed to PETSc in one call; the arrays are freed before returning.
pub fn assemble_stiffness(
    comm: sys::MPI_Comm,
    mesh: &LocalMesh,
    settings: &Settings,
    extra: &[(usize, Vec<f64>)],
) -> Result<Elasticity, Error> {
    let d = mesh.dim;
    let nown = mesh.owned_count;
    let (nptr, nbr) = node_adjacency(mesh);
    // Dof row (a, ca) starts at d * (d * nptr[a] + ca * len(a)); its
    // columns are (b, cb) for b in the neighbours of a, cb in 0..d.
    let row_start = |a: usize, ca: usize| d * (d * nptr[a] + ca * (nptr[a + 1] - nptr[a]));
    let nnz = d * d * nptr[nown];
    let mut rowptr: Vec<sys::PetscInt> = Vec::with_capacity(nown * d + 1);
    let mut cols: Vec<sys::PetscInt> = Vec::with_capacity(nnz);
    for a in 0..nown {
        for _ca in 0..d {
            rowptr.push(cols.len() as sys::PetscInt);
            for &b in &nbr[nptr[a]..nptr[a + 1]] {
                let g = mesh.node_global[b as usize];
                for cb in 0..d {
                    cols.push((g * d + cb) as sys::PetscInt);
                }
            }
        }
    }
    rowptr.push(cols.len() as sys::PetscInt);
    let mut vals = vec![0.0; nnz];
    // Position of node b among the neighbours of the owned node a.
    let slot = |a: usize, b: usize| {
        nbr[nptr[a]..nptr[a + 1]]
            .iter()
            .position(|&x| x as usize == b)
            .expect("the vertices of a cell are neighbours")
    };
    let mut mass = vec![0.0; nown];
    let d2 = hooke_2d(settings.young, settings.nu, settings.plane_stress);
    let d3 = hooke_3d(settings.young, settings.nu);
    let lame = element::lame(settings.young, settings.nu, d, settings.plane_stress);
    let nloc_max = d * mesh.cells.max_nodes();
    let mut ke = vec![0.0; nloc_max * nloc_max];
    // Cells by their lowest vertex (counting sort): the rows each one adds
    // to are then swept in order, not at random (RCM-numbered nodes,
    // cells in file order; hertz_37473: 55 -> 40 ms).
    let ncells = mesh.cells.len();
    let lowest = |c: usize| *mesh.cells.get(c).iter().min().unwrap_or(&0);
    let mut start = vec![0usize; mesh.node_global.len() + 1];
    for c in 0..ncells {
        start[lowest(c) + 1] += 1;
    }
    for v in 0..mesh.node_global.len() {
        start[v + 1] += start[v];
    }
    let mut order = vec![0u32; ncells];
    for c in 0..ncells {
        let v = lowest(c);
        order[start[v]] = c as u32;
        start[v] += 1;
    }
    // The integral of each vertex's shape function over the cell.
    let mut lumped = [0.0; 8];
    for c in order.into_iter().map(|c| c as usize) {
        let cell = mesh.cells.get(c);
        let k = cell.len();
        let nloc = d * k;
        let measure = match (d, k) {
            (2, 3) => {
                let x = [0, 1, 2].map(|a| {
                    let p = mesh.x(cell[a]);
                    [p[0], p[1]]
                });
                let (m, area) = stiffness_2d(&x, &d2);
                for i in 0..6 {
                    for j in 0..6 {
                        ke[i * 6 + j] = m[(i, j)];
                    }
                }
                area
            }
            (3, 4) => {
                let x = [0, 1, 2, 3].map(|a| {
                    let p = mesh.x(cell[a]);
                    [p[0], p[1], p[2]]
                });
                let (m, vol) = stiffness_3d(&x, &d3);
                for i in 0..12 {
                    for j in 0..12 {
                        ke[i * 12 + j] = m[(i, j)];
                    }
                }
                vol
            }
            (2, 4) => {
                let x: [[f64; 2]; 4] = std::array::from_fn(|a| {
                    let p = mesh.x(cell[a]);
                    [p[0], p[1]]
                });
                ke[..64].fill(0.0);
                let mut l4 = [0.0; 4];
                let r = element::q1_stiffness(&x, element::quad_rule(), lame, &mut ke, &mut l4);
                lumped[..4].copy_from_slice(&l4);
                r.unwrap_or(f64::NAN)
            }
            (3, 8) => {
                let x: [[f64; 3]; 8] = std::array::from_fn(|a| {
                    let p = mesh.x(cell[a]);
                    [p[0], p[1], p[2]]
                });
                ke[..576].fill(0.0);
                let mut l8 = [0.0; 8];
                let r = element::q1_stiffness(&x, element::hex_rule(), lame, &mut ke, &mut l8);
                lumped.copy_from_slice(&l8);
                r.unwrap_or(f64::NAN)
            }
            _ => {
                return Err(Error::Internal(format!(
                    "cell {c} has {k} nodes in a {d}D mesh"
                )))
            }
        };
        if measure.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !measure.is_finite() {
            let tags: Vec<String> = cell.iter().map(|&v| mesh.node_tag[v].to_string()).collect();
            return bad(format!(
                "degenerate element {} (nodes {}): zero measure{}",
                c,
                tags.join(" "),
                if k == d + 1 {
                    ""
                } else {
                    ", or a Jacobian determinant that vanishes or changes sign"
                }
            ));
        }
        if k == d + 1 {
            // P1: a (d+1)-th of the measure to each vertex.
            lumped[..k].fill(measure / k as f64);
        }
        for (ia, &a) in cell.iter().enumerate() {
            if !mesh.is_owned(a) {
                continue;
            }
            mass[a] += lumped[ia];
            for (ib, &b) in cell.iter().enumerate() {
                let p = slot(a, b);
                for ca in 0..d {
                    let dst = row_start(a, ca) + p * d;
                    let src = (ia * d + ca) * nloc + ib * d;
                    for cb in 0..d {
                        vals[dst + cb] += ke[src + cb];
                    }
                }
            }
        }
    }
    for (local, block) in extra {
        let (a, p) = (*local, slot(*local, *local));
        for ca in 0..d {
            let dst = row_start(a, ca) + p * d;
            for cb in 0..d {
                vals[dst + cb] += block[ca * d + cb];
            }
        }
    }
    let mat = Matrix::new_aij_csr(comm, nown * d, d, &rowptr, &cols, &vals)?;
    Ok(Elasticity {
        stiffness: mat,
        lumped_mass: mass,
    })
}

/// The load vector's owned entries from the surface tractions (nodal
/// quadrature: vertex a of a facet gets `w_a t`, `w_a` from
/// [`element::facet_weights`]: |F|/m for a simplex facet of m vertices,
/// `int N_a dA` for a quadrilateral).
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
        let mut w = Vec::with_capacity(4);
        for e in &group.conn {
            let pts: Vec<&[f64]> = e.iter().map(|&v| mesh.x(v)).collect();
            element::facet_weights(&pts, &mut w);
            for (&v, &share) in e.iter().zip(&w) {
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
            for &v in group.conn.nodes() {
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
