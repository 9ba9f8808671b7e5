//! Linear elasticity: element kernels (P1 here, Q1 in [`element`]), the
//! distributed stiffness matrix with exact preallocation, surface
//! tractions, lumped mass and Dirichlet data. Cells of any supported kind
//! may be mixed (triangles with quadrilaterals, tetrahedra with hexahedra).
//!
//! Global degrees of freedom are node-major: dof `dim * node + component`, with
//! the renumbered (rank-contiguous) global node numbers of `LocalMesh`.

pub mod deformation;
pub use crate::element;
pub use crate::element::{hooke_2d, hooke_3d};
pub mod loads;
pub mod material;
pub mod stress;

use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use crate::options::{DirichletBc, Settings, TractionBc};
use crate::petsc::{sys, Matrix};
use nalgebra::{SMatrix, SVector};

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

/// The stiffness of an isotropic P1 tetrahedron (Lamé's `lame`) into `ke`
/// (12x12, row-major, dofs node-major), returns its volume: block (a, b) is
/// `vol (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I)`, g the shape
/// function gradients; what [`stiffness_3d`]'s `B^T D B` gives for Hooke's
/// isotropic D, without the 6x12 products (the general path of mixed meshes).
pub fn stiffness_p1_3d_into(x: &[[f64; 3]; 4], (lambda, mu): (f64, f64), ke: &mut [f64]) -> f64 {
    let (g, vol) = grad_p1_3d(x);
    let (lv, mv) = (lambda * vol, mu * vol);
    for a in 0..4 {
        for b in 0..4 {
            let k = p1_block(&g[a], &g[b], lv, mv);
            for (i, ki) in k.iter().enumerate() {
                let at = (3 * a + i) * 12 + 3 * b;
                ke[at..at + 3].copy_from_slice(ki);
            }
        }
    }
    vol
}

/// Block (a, b) of an isotropic P1 tetrahedron's stiffness from the shape
/// function gradients `ga`, `gb` and `lv = lambda vol`, `mv = mu vol`:
/// `lv ga gb^T + mv gb ga^T + mv (ga . gb) I` (row i, column j).
#[inline]
fn p1_block(ga: &[f64; 3], gb: &[f64; 3], lv: f64, mv: f64) -> [[f64; 3]; 3] {
    let dot = mv * (ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]);
    let mut k = [[0.0; 3]; 3];
    for (i, ki) in k.iter_mut().enumerate() {
        for (j, kij) in ki.iter_mut().enumerate() {
            *kij = lv * ga[i] * gb[j] + mv * ga[j] * gb[i];
        }
        ki[i] += dot;
    }
    k
}

/// Measure of a facet given its vertex coordinates (point: 1, segment:
/// length, triangle: area, quadrilateral: area of its bilinear surface):
/// the sum of its nodal weights [`element::facet_weights`].
pub fn facet_measure(pts: &[&[f64]]) -> f64 {
    let mut w = Vec::with_capacity(4);
    element::facet_weights(pts, &mut w);
    w.iter().sum()
}

/// Compressed rows of the owned nodes' neighbours ([`node_adjacency`]):
/// made once, for the assembly and for METIS' graph.
pub(crate) type Adjacency = (Vec<usize>, Vec<u32>);

/// The neighbours of each owned node (the nodes it shares a cell with,
/// itself included), in compressed rows sorted by global number: the
/// neighbours of owned node a are `nbr[ptr[a]..ptr[a + 1]]` (local numbers).
pub(crate) fn node_adjacency(mesh: &LocalMesh) -> Adjacency {
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
    // Deduplicate each row (a mark per node: the last row that saw it),
    // then sort the few left by global number, compacting in place.
    let mut mark = vec![u32::MAX; mesh.node_global.len()];
    let mut out = 0;
    let mut start = 0;
    for a in 0..nown {
        let end = ptr[a + 1];
        let mut len = 0;
        for i in start..end {
            let b = nbr[i];
            if mark[b as usize] != a as u32 {
                mark[b as usize] = a as u32;
                nbr[out + len] = b;
                len += 1;
            }
        }
        nbr[out..out + len].sort_unstable_by_key(|&b| mesh.node_global[b as usize]);
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

/// The material matrices of the element kernels, once per use: one per
/// material of the mesh ([`material`]), each cell taking its own.
pub struct Kernels {
    /// Hooke's matrix (2D) and Lamé's constants of each material.
    each: Vec<(SMatrix<f64, 3, 3>, (f64, f64))>,
}

impl Kernels {
    pub fn new(settings: &Settings, mesh: &LocalMesh) -> Kernels {
        let ps = settings.plane_stress;
        let each = material::list(mesh, settings)
            .iter()
            .map(|m| {
                (
                    hooke_2d(m.young, m.nu, ps),
                    element::lame(m.young, m.nu, mesh.dim, ps),
                )
            })
            .collect();
        Kernels { each }
    }

    /// Hooke's matrix (2D) of local cell `c`'s material.
    #[inline]
    fn d2(&self, mesh: &LocalMesh, c: usize) -> &SMatrix<f64, 3, 3> {
        &self.each[mesh.materials.index(c)].0
    }

    /// Lamé's `(lambda, mu)` of local cell `c`'s material.
    #[inline]
    pub fn lame(&self, mesh: &LocalMesh, c: usize) -> (f64, f64) {
        self.each[mesh.materials.index(c)].1
    }
}

/// The stiffness of local cell `c` into `ke` (`(d k)^2` values, row-major,
/// dofs node-major) and, for a Q1 cell, `int N_a dx` of its vertices into
/// `lumped`; returns its measure (NaN for a folded Q1 cell).
pub fn cell_stiffness(
    mesh: &LocalMesh,
    c: usize,
    kernels: &Kernels,
    ke: &mut [f64],
    lumped: &mut [f64; 8],
) -> Result<f64, Error> {
    let d = mesh.dim;
    let cell = mesh.cells.get(c);
    let k = cell.len();
    Ok(match (d, k) {
        (2, 3) => {
            let x = [0, 1, 2].map(|a| {
                let p = mesh.x(cell[a]);
                [p[0], p[1]]
            });
            let (m, area) = stiffness_2d(&x, kernels.d2(mesh, c));
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
            stiffness_p1_3d_into(&x, kernels.lame(mesh, c), ke)
        }
        (2, 4) => {
            let x: [[f64; 2]; 4] = std::array::from_fn(|a| {
                let p = mesh.x(cell[a]);
                [p[0], p[1]]
            });
            ke[..64].fill(0.0);
            let mut l4 = [0.0; 4];
            let lame = kernels.lame(mesh, c);
            let r = element::q1_stiffness(&x, element::quad_rule(), lame, ke, &mut l4);
            lumped[..4].copy_from_slice(&l4);
            r.unwrap_or(f64::NAN)
        }
        (3, 5 | 6 | 8) => {
            // Hexahedra; prisms and pyramids as degenerate ones.
            let mut x = [[0.0; 3]; 8];
            for (xa, &v) in x.iter_mut().zip(cell) {
                let p = mesh.x(v);
                *xa = [p[0], p[1], p[2]];
            }
            element::hex_family_stiffness(&x[..k], kernels.lame(mesh, c), ke, lumped)
                .unwrap_or(f64::NAN)
        }
        _ => {
            return Err(Error::Internal(format!(
                "cell {c} has {k} nodes in a {d}D mesh"
            )))
        }
    })
}

/// Assembles K (only the rows this rank owns; no communication) and the lumped
/// mass. Extra owned diagonal 2x2/3x3 blocks can be added by `extra` before the
/// final assembly (the UBR term r B^T W B). The rows are built here in
/// compressed form (the cells taken in the order of their lowest vertex) and
/// handed to PETSc in one call ([`Matrix::new_aij_csr`]), which keeps them
/// as the matrix's own storage until the matrix is destroyed (on several
/// ranks split into the owned and the other columns): they are not copied
/// entry by entry, and not freed here.
pub fn assemble_stiffness(
    comm: sys::MPI_Comm,
    mesh: &LocalMesh,
    adjacency: &Adjacency,
    settings: &Settings,
    extra: &[(usize, Vec<f64>)],
) -> Result<Elasticity, Error> {
    let d = mesh.dim;
    let nown = mesh.owned_count;
    let (rowptr, cols) = csr_pattern(mesh, adjacency);
    let mut vals = vec![0.0; cols.len()];
    let mut mass = vec![0.0; nown];
    if d == 3 && mesh.cells.max_nodes() == 4 {
        add_tetrahedra(mesh, adjacency, settings, &mut vals, &mut mass)?;
    } else {
        add_cells(mesh, adjacency, settings, &mut vals, &mut mass)?;
    }
    for (local, block) in extra {
        let (a, p) = (*local, slot(adjacency, *local, *local));
        for ca in 0..d {
            let dst = row_start(adjacency, d, a, ca) + p * d;
            for cb in 0..d {
                vals[dst + cb] += block[ca * d + cb];
            }
        }
    }
    let mat = Matrix::new_aij_csr(comm, nown * d, d, rowptr, cols, vals)?;
    Ok(Elasticity {
        stiffness: mat,
        lumped_mass: mass,
    })
}

/// Where dof row (a, ca) starts: at d * (d * nptr[a] + ca * len(a)); its
/// columns are (b, cb) for b in the neighbours of a, cb in 0..d.
fn row_start((nptr, _): &Adjacency, d: usize, a: usize, ca: usize) -> usize {
    d * (d * nptr[a] + ca * (nptr[a + 1] - nptr[a]))
}

/// Position of node b among the neighbours of the owned node a.
fn slot((nptr, nbr): &Adjacency, a: usize, b: usize) -> usize {
    nbr[nptr[a]..nptr[a + 1]]
        .iter()
        .position(|&x| x as usize == b)
        .expect("the vertices of a cell are neighbours")
}

/// The compressed rows of the owned dofs: row pointers and global columns.
fn csr_pattern(
    mesh: &LocalMesh,
    (nptr, nbr): &Adjacency,
) -> (Vec<sys::PetscInt>, Vec<sys::PetscInt>) {
    let d = mesh.dim;
    let nown = mesh.owned_count;
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
    (rowptr, cols)
}

/// The error of cell c of zero (or negative) measure.
fn degenerate(mesh: &LocalMesh, c: usize) -> Error {
    let cell = mesh.cells.get(c);
    let k = cell.len();
    let tags: Vec<String> = cell.iter().map(|&v| mesh.node_tag[v].to_string()).collect();
    Error::BadInput(format!(
        "degenerate element {} (nodes {}): zero measure{}",
        c,
        tags.join(" "),
        if k == mesh.dim + 1 {
            ""
        } else {
            ", or a Jacobian determinant that vanishes or changes sign"
        }
    ))
}

/// K and the lumped mass of a mesh of tetrahedra alone, into `vals` and
/// `mass`.
fn add_tetrahedra(
    mesh: &LocalMesh,
    (nptr, nbr): &Adjacency,
    settings: &Settings,
    vals: &mut [f64],
    mass: &mut [f64],
) -> Result<(), Error> {
    let d = mesh.dim;
    let nown = mesh.owned_count;
    // Tetrahedra alone: row by row. For each owned node a, a marker
    // gives every neighbour's slot at once, and the cells around a add
    // their block row (a, .) in closed form (see stiffness_p1_3d_into)
    // to a's rows, which stay in cache: no search for a slot, no
    // scattered writes (block3d_17887: assembly phase 0.100 -> 0.079 s).
    // Each cell with its own material's Lamé constants.
    let kernels = Kernels::new(settings, mesh);
    let nlocal = mesh.node_global.len();
    let ncells = mesh.cells.len();
    // The cells around each owned node.
    let mut around_ptr = vec![0usize; nown + 1];
    for c in 0..ncells {
        for &a in mesh.cells.get(c) {
            if a < nown {
                around_ptr[a + 1] += 1;
            }
        }
    }
    for a in 0..nown {
        around_ptr[a + 1] += around_ptr[a];
    }
    let mut fill = around_ptr[..nown].to_vec();
    let mut around = vec![0u32; around_ptr[nown]];
    for c in 0..ncells {
        for &a in mesh.cells.get(c) {
            if a < nown {
                around[fill[a]] = c as u32;
                fill[a] += 1;
            }
        }
    }
    drop(fill);
    let mut marker = vec![0u32; nlocal];
    for a in 0..nown {
        let nb = &nbr[nptr[a]..nptr[a + 1]];
        for (p, &b) in nb.iter().enumerate() {
            marker[b as usize] = p as u32;
        }
        let len = nb.len();
        let rows = &mut vals[d * d * nptr[a]..d * d * nptr[a + 1]];
        for &c in &around[around_ptr[a]..around_ptr[a + 1]] {
            let c = c as usize;
            let cell = mesh.cells.get(c);
            let x = [0, 1, 2, 3].map(|v| {
                let p = mesh.x(cell[v]);
                [p[0], p[1], p[2]]
            });
            let (g, vol) = grad_p1_3d(&x);
            if vol.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !vol.is_finite() {
                return Err(degenerate(mesh, c));
            }
            mass[a] += 0.25 * vol;
            let ia = cell.iter().position(|&v| v == a).expect("a is a vertex");
            let ga = g[ia];
            let (lambda, mu) = kernels.lame(mesh, c);
            let (lv, mv) = (lambda * vol, mu * vol);
            for (ib, &b) in cell.iter().enumerate() {
                let k = p1_block(&ga, &g[ib], lv, mv);
                let p = marker[b] as usize;
                for (i, ki) in k.iter().enumerate() {
                    let row = &mut rows[i * 3 * len + 3 * p..i * 3 * len + 3 * p + 3];
                    for (r, kij) in row.iter_mut().zip(ki) {
                        *r += kij;
                    }
                }
            }
        }
    }
    Ok(())
}

/// K and the lumped mass of any mesh, cell by cell, into `vals` and `mass`.
fn add_cells(
    mesh: &LocalMesh,
    adjacency: &Adjacency,
    settings: &Settings,
    vals: &mut [f64],
    mass: &mut [f64],
) -> Result<(), Error> {
    let d = mesh.dim;
    let kernels = Kernels::new(settings, mesh);
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
        let measure = cell_stiffness(mesh, c, &kernels, &mut ke, &mut lumped)?;
        if measure.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || !measure.is_finite() {
            return Err(degenerate(mesh, c));
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
                let p = slot(adjacency, a, b);
                for ca in 0..d {
                    let dst = row_start(adjacency, d, a, ca) + p * d;
                    let src = (ia * d + ca) * nloc + ib * d;
                    for cb in 0..d {
                        vals[dst + cb] += ke[src + cb];
                    }
                }
            }
        }
    }
    Ok(())
}

/// The load vector's owned entries from the surface tractions (nodal
/// quadrature: vertex a of a facet gets `w_a t`, `w_a` from
/// [`element::facet_weights`]: |F|/m for a simplex facet of m vertices,
/// `int N_a dA` for a quadrilateral).
pub fn traction_load(mesh: &LocalMesh, tractions: &[TractionBc]) -> Result<Vec<f64>, Error> {
    let d = mesh.dim;
    let mut f = vec![0.0; mesh.owned_count * d];
    for t in tractions {
        let option = format!("-traction_{}", t.group);
        let group = mesh.group_for(&option, &t.group, d - 1..=d - 1, "a traction")?;
        if t.traction.len() != d {
            return bad(format!(
                "option {option}: {} components given, the mesh is {}D",
                t.traction.len(),
                d
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
        let option = format!("-dirichlet_{}", bc.group);
        let group = mesh.group_for(&option, &bc.group, 0..=d - 1, "a Dirichlet condition")?;
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

    /// The closed form of the P1 tetrahedron equals `B^T D B` on a skewed
    /// cell.
    #[test]
    fn closed_form_tetrahedron() {
        let x = [
            [0.1, -0.2, 0.05],
            [1.3, 0.1, -0.2],
            [0.2, 0.9, 0.3],
            [-0.1, 0.4, 1.1],
        ];
        let (e, nu) = (2.1e5, 0.45);
        let (k, vol) = stiffness_3d(&x, &hooke_3d(e, nu));
        let mut ke = [0.0; 144];
        let v = stiffness_p1_3d_into(&x, element::lame(e, nu, 3, false), &mut ke);
        assert!((v - vol).abs() < 1e-14 * vol);
        let scale = k.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..12 {
            for j in 0..12 {
                assert!(
                    (ke[i * 12 + j] - k[(i, j)]).abs() < 1e-13 * scale,
                    "({i}, {j}): {} against {}",
                    ke[i * 12 + j],
                    k[(i, j)]
                );
            }
        }
    }
}

#[cfg(test)]
mod patch_tests;
