//! Two elastic bodies on the same fixed operator: the change of unknowns
//! that keeps every contact row node-local ([`crate::contact::mortar`]).
//!
//! At a pair's slave node k the unknown becomes the relative displacement
//! `v_k = u_k - Q_k sum_j P_kj u_j` (`Q_k = n_k n_k^T` frictionless: the
//! normal component alone, so a Dirichlet condition on a tangential
//! component stays one; `Q_k = I` with friction, whose slip is relative
//! too); every other unknown is kept. With `u = T v` the problem on v has
//! the stiffness `T^T K T` (symmetric positive definite as K is: T is
//! unit triangular) and the load `T^T f`, and the constraint of node k is
//! `n_k . v_k <= g_k`, the form of a rigid obstacle: UBR's blocks, the
//! condensation, the choice of r and every projection carry over. The
//! multiplier is the slave's contact pressure; the master receives its
//! mortar share through `T^T`. Components of a slave node that carry a
//! Dirichlet condition are not changed (their row of `Q_k` is zero).

use crate::contact::ContactSet;
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::petsc::{self, sys, Matrix, Vector};

/// `u = T v`, for the contact pairs of a scene.
pub struct Transform {
    t: Matrix,
}

impl Transform {
    /// T for the candidates' mortar rows (None without a contact pair);
    /// `dirichlet`: this rank's Dirichlet dofs (local, owned);
    /// `tangential`: the whole relative displacement (friction).
    pub fn build<C: mpi::traits::Communicator>(
        world: &C,
        mesh: &LocalMesh,
        cs: &ContactSet,
        dirichlet: &[(usize, f64)],
        tangential: bool,
    ) -> Result<Option<Transform>, Error> {
        let any = crate::comm::allreduce_count(world, usize::from(cs.has_pairs()));
        if any == 0 {
            return Ok(None);
        }
        let d = mesh.dim;
        let nown = mesh.owned_count * d;
        let fixed: std::collections::HashSet<usize> = dirichlet.iter().map(|&(i, _)| i).collect();
        let mut candidate = vec![usize::MAX; mesh.owned_count];
        for (i, &v) in cs.node.iter().enumerate() {
            if cs.pair[i] != usize::MAX {
                candidate[v] = i;
            }
        }
        let first = mesh.owned_start * d;
        let mut rowptr: Vec<sys::PetscInt> = Vec::with_capacity(nown + 1);
        let (mut cols, mut vals): (Vec<sys::PetscInt>, Vec<f64>) = (Vec::new(), Vec::new());
        rowptr.push(0);
        let mut row: Vec<(usize, f64)> = Vec::new();
        for (v, &i) in candidate.iter().enumerate() {
            for c in 0..d {
                let dof = v * d + c;
                row.clear();
                row.push((first + dof, 1.0));
                if i != usize::MAX && !fixed.contains(&dof) {
                    let n = cs.n(i);
                    for &(j, p) in &cs.mortar[i] {
                        for e in 0..d {
                            let q = if tangential {
                                f64::from(u8::from(c == e))
                            } else {
                                n[c] * n[e]
                            };
                            if q != 0.0 {
                                row.push((j * d + e, p * q));
                            }
                        }
                    }
                }
                row.sort_unstable_by_key(|&(col, _)| col);
                let start = cols.len();
                for &(col, val) in row.iter() {
                    if cols.len() > start && cols[cols.len() - 1] as usize == col {
                        *vals.last_mut().expect("a column") += val;
                    } else {
                        cols.push(col as sys::PetscInt);
                        vals.push(val);
                    }
                }
                rowptr.push(cols.len() as sys::PetscInt);
            }
        }
        let t = Matrix::new_aij_csr(petsc::comm_world(), nown, 1, rowptr, cols, vals)?;
        Ok(Some(Transform { t }))
    }

    /// `T^T K T`.
    pub fn stiffness(&self, k: &Matrix) -> Result<Matrix, Error> {
        k.ptap(&self.t)
    }

    /// `T^T f` into a new vector.
    pub fn load(&self, f: &Vector) -> Result<Vector, Error> {
        let out = f.duplicate()?;
        self.t.mult_transpose(f, &out)?;
        Ok(out)
    }

    /// `T^T f` of this rank's owned values `f` (`d` per node).
    pub fn transpose_apply(&self, f: &[f64], d: usize) -> Result<Vec<f64>, Error> {
        let x = Vector::new(petsc::comm_world(), f.len(), d)?;
        x.write(|v| v.copy_from_slice(f))?;
        let y = x.duplicate()?;
        self.t.mult_transpose(&x, &y)?;
        y.read(|v| v.to_vec())
    }

    /// The traction that the pairs' slaves put on the master nodes: the
    /// magnitude of the mortar share `T^T F - F` of the slave forces `F`
    /// (`f_slave`, this rank's owned dofs), over the node's weight on the
    /// master surfaces (`int N_j`); by node tag, from every rank.
    pub fn master_traction<C: mpi::traits::Communicator>(
        &self,
        world: &C,
        mesh: &LocalMesh,
        f_slave: &[f64],
        masters: &[&str],
    ) -> Result<Vec<(u64, f64)>, Error> {
        let d = mesh.dim;
        let share = self.transpose_apply(f_slave, d)?;
        let mut weight = vec![0.0; mesh.owned_count];
        let mut seen = std::collections::HashSet::new();
        let mut w = Vec::with_capacity(4);
        for g in masters.iter().filter_map(|name| mesh.group(name)) {
            for e in &g.conn {
                let mut key = e.to_vec();
                key.sort_unstable();
                if !seen.insert(key) {
                    continue;
                }
                let pts: Vec<&[f64]> = e.iter().map(|&v| mesh.x(v)).collect();
                crate::element::facet_weights(&pts, &mut w);
                for (&v, &wv) in e.iter().zip(&w) {
                    if mesh.is_owned(v) {
                        weight[v] += wv;
                    }
                }
            }
        }
        let mut mine = Vec::new();
        for (v, &wv) in weight.iter().enumerate().filter(|(_, &wv)| wv > 0.0) {
            let f: f64 = (0..d)
                .map(|c| (share[v * d + c] - f_slave[v * d + c]).powi(2))
                .sum::<f64>()
                .sqrt();
            mine.extend([mesh.node_tag[v] as f64, f / wv]);
        }
        let all = crate::comm::Layout::new(world, mine.len()).all_gather(world, &mine);
        Ok(all.chunks(2).map(|p| (p[0] as u64, p[1])).collect())
    }

    /// `u = T v` into a new vector.
    pub fn displacement(&self, v: &Vector) -> Result<Vector, Error> {
        let out = v.duplicate()?;
        self.t.mult(v, &out)?;
        Ok(out)
    }
}
