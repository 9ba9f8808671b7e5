//! The linear back-ends of UBR: their one job is to apply `K_r^{-1}`, where
//! `K_r = K + r B^T W B` is factorized (or preconditioned) once.
//!
//! Every UBR solve (4.5)/(5.3) has the right-hand side `f + B^T W v`, whose
//! contact part `c = B^T W v` lives on the contact nodes alone. A back-end
//! returns `u_C`, the displacement at the contact nodes, for `rhs0 + C c`:
//! - **full**: a sparse solve of the whole system (any KSP/PC from the
//!   options; the whole displacement comes with it);
//! - **condensed** (one rank, MUMPS): `u_C = y0 + S^{-1} c`, where S is the
//!   Schur complement of `K_r` on the contact unknowns, returned by MUMPS with
//!   the one numeric factorization, and `y0` is `u_C` for `rhs0`. The whole
//!   displacement costs one sparse solve, at the end.
//!
//! Changing r. `K_r' = K_r + (r' - r) B^T W B` differs from `K_r` only in the
//! contact blocks, so its Schur complement is `S + (r' - r) M` (M: the
//! contact blocks, [`Surface::apply_contact_block`]): the condensed back-end
//! changes r with a dense refactorization of S alone, and gets the whole
//! displacement from the factorization of `K_r` by moving the difference to
//! the right-hand side, `K_r u = rhs0 + C (c - (r' - r) M u_C)`, exact since
//! `u_C` is known. The full back-end updates the contact blocks of the
//! matrix and refactorizes (a direct solver: numeric factorization only, the
//! pattern is the same) or keeps its preconditioner (an iterative one: the
//! multigrid hierarchy of `K_r` serves `K_r'`, no second set-up).

use super::surface::Surface;
use crate::error::Error;
use crate::petsc::{sys, DenseColumns, DenseSpd, Ksp, Matrix, SchurSolver, Vector};

/// The condensed back-end's data.
pub struct Condensed {
    /// PETSc's factorization of S at the assembled r (the full solves use it too).
    schur: SchurSolver,
    /// S at the assembled r, unfactored (column-major).
    s0: Vec<f64>,
    /// S at the current r, when it differs from the assembled one.
    shifted: Option<DenseSpd>,
    /// `u_C` for `rhs0` at the assembled r, and at the current r.
    y0_assembled: Vec<f64>,
    y0: Vec<f64>,
}

/// `K_r^{-1}` for UBR, with the bookkeeping of r and of the solves.
pub struct LinearSolver {
    pub ksp: Ksp,
    /// `K + r_a B^T W B` with Dirichlet rows and columns eliminated (r_a: the
    /// assembled r).
    pub matrix: Matrix,
    /// Right-hand side without contact terms, at the current r.
    pub rhs0: Vector,
    pub iterative: bool,
    /// Inexact solves: the inner tolerance follows the outer iteration.
    pub adaptive_inner: bool,
    pub description: String,
    r_assembled: f64,
    r: f64,
    condensed: Option<Condensed>,
    /// Dirichlet values at the contact unknowns (0 elsewhere).
    xd_c: Vec<f64>,
    /// Owned Dirichlet dofs and values: an iterative solve meets them only
    /// to its tolerance, so they are set exactly after it (their rows and
    /// columns are decoupled, so this changes nothing else).
    dirichlet: Vec<(usize, f64)>,
    rhs: Vector,
    /// Linear solves so far (full, condensed, and the r estimation's).
    pub solves: usize,
    /// Inner tolerance last set on an iterative solver.
    rtol: f64,
}

impl LinearSolver {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ksp: Ksp,
        matrix: Matrix,
        rhs0: Vector,
        iterative: bool,
        adaptive_inner: bool,
        description: String,
        r: f64,
        xd_c: Vec<f64>,
        dirichlet: Vec<(usize, f64)>,
    ) -> Result<LinearSolver, Error> {
        let rhs = rhs0.duplicate()?;
        Ok(LinearSolver {
            ksp,
            matrix,
            rhs0,
            iterative,
            adaptive_inner,
            description,
            r_assembled: r,
            r,
            condensed: None,
            xd_c,
            dirichlet,
            rhs,
            solves: 0,
            rtol: f64::NAN,
        })
    }

    /// The r of the iteration (the matrix's, or the one the condensed
    /// back-end shifted to).
    pub fn r(&self) -> f64 {
        self.r
    }

    /// The r of the assembled matrix (that `matrix` holds).
    pub fn r_assembled(&self) -> f64 {
        self.r_assembled
    }

    pub fn condensed_unknowns(&self) -> usize {
        self.condensed.as_ref().map_or(0, |c| c.y0.len())
    }

    pub fn is_condensed(&self) -> bool {
        self.condensed.is_some()
    }

    /// Turns the condensed back-end on, from the factorization that
    /// [`Ksp::request_schur`] asked for: takes a copy of S, factorizes it, and
    /// solves for `y0` (one full solve), whose contact part is `u_C` of rhs0.
    pub fn condense(&mut self, surface: &Surface, u: &Vector) -> Result<(), Error> {
        let m = surface.len() * surface.dim;
        let s0 = self.ksp.schur_copy(m)?;
        let schur = self.ksp.schur(m)?;
        self.ksp.solve(&self.rhs0, u)?;
        self.solves += 1;
        let mut y0 = vec![0.0; m];
        extract(surface, u, &mut y0)?;
        self.condensed = Some(Condensed {
            schur,
            s0,
            shifted: None,
            y0_assembled: y0.clone(),
            y0,
        });
        self.description
            .push_str(&format!(", condensed on the {m} contact unknowns"));
        Ok(())
    }

    /// Back to full solves (the condensed and full solves disagreed).
    pub fn uncondense(&mut self) {
        self.condensed = None;
    }

    /// Inexact solves: the relative tolerance of the next inner solves.
    pub fn set_inner_rtol(&mut self, rtol: f64) -> Result<(), Error> {
        if self.iterative && self.adaptive_inner && rtol != self.rtol {
            self.ksp.set_rtol(rtol)?;
            self.rtol = rtol;
        }
        Ok(())
    }

    /// `u_C` for the right-hand side `rhs0 + C c` into `uc`; a full solve
    /// also leaves the whole displacement in `u` (which an iterative solver
    /// starts from). Returns the inner iteration count.
    pub fn solve(
        &mut self,
        surface: &Surface,
        c: &[f64],
        uc: &mut [f64],
        u: &Vector,
    ) -> Result<usize, Error> {
        self.solves += 1;
        if let Some(cd) = &self.condensed {
            match &cd.shifted {
                Some(s) => s.solve(c, uc)?,
                None => cd.schur.solve(c, uc)?,
            }
            for (x, y) in uc.iter_mut().zip(&cd.y0) {
                *x += y;
            }
            return Ok(0);
        }
        self.rhs.copy_from(&self.rhs0)?;
        scatter_add(surface, c, &self.rhs)?;
        let its = self.ksp.solve(&self.rhs, u)?;
        self.exact_dirichlet(u, 1.0)?;
        extract(surface, u, uc)?;
        Ok(its)
    }

    /// Iterative solves: the Dirichlet values exactly (`scale` 0: zero data).
    fn exact_dirichlet(&self, u: &Vector, scale: f64) -> Result<(), Error> {
        if !self.iterative {
            return Ok(());
        }
        u.write(|u| {
            for &(i, v) in &self.dirichlet {
                u[i] = scale * v;
            }
        })
    }

    /// `u_C` for `C c` alone (no load, zero Dirichlet data): the operator
    /// `C^T K_r^{-1} C` of the r estimation. `work` is a vector of the
    /// system's layout; an iterative solver starts from zero.
    pub fn solve_homogeneous(
        &mut self,
        surface: &Surface,
        c: &[f64],
        uc: &mut [f64],
        work: &Vector,
    ) -> Result<usize, Error> {
        self.solves += 1;
        if let Some(cd) = &self.condensed {
            match &cd.shifted {
                Some(s) => s.solve(c, uc)?,
                None => cd.schur.solve(c, uc)?,
            }
            return Ok(0);
        }
        self.rhs.set(0.0)?;
        scatter_add(surface, c, &self.rhs)?;
        work.set(0.0)?;
        let its = self.ksp.solve(&self.rhs, work)?;
        self.exact_dirichlet(work, 0.0)?;
        extract(surface, work, uc)?;
        Ok(its)
    }

    /// The whole displacement `u` for the contact load `c` whose contact
    /// displacement `uc` a solve returned: already in `u` after a full
    /// solve; one sparse solve after condensed ones.
    pub fn displacement(
        &mut self,
        surface: &Surface,
        c: &[f64],
        uc: &[f64],
        u: &Vector,
    ) -> Result<(), Error> {
        if self.condensed.is_none() {
            return Ok(());
        }
        let cc = self.corrected(surface, c, uc);
        self.rhs.copy_from(&self.rhs0)?;
        scatter_add(surface, &cc, &self.rhs)?;
        self.solves += 1;
        self.ksp.solve(&self.rhs, u)?;
        self.exact_dirichlet(u, 1.0)
    }

    /// The whole displacements for several contact loads at once (one pass
    /// over the factors): column j of the result for `cols[j] = (c, uc)`.
    pub fn displacements(
        &mut self,
        surface: &Surface,
        cols: &[(&[f64], &[f64])],
    ) -> Result<DenseColumns, Error> {
        let n = self.rhs0.local_size()?;
        let comm = crate::petsc::comm_world();
        let b = DenseColumns::new(comm, n, cols.len())?;
        let x = DenseColumns::new(comm, n, cols.len())?;
        let loads: Vec<Vec<f64>> = cols
            .iter()
            .map(|(c, uc)| self.corrected(surface, c, uc))
            .collect();
        let (d, cs) = (surface.dim, surface.cs);
        self.rhs0.read(|r0| {
            b.write(|bb| {
                for (j, c) in loads.iter().enumerate() {
                    let col = &mut bb[j * n..(j + 1) * n];
                    col.copy_from_slice(r0);
                    for (i, &v) in cs.node.iter().enumerate() {
                        for k in 0..d {
                            col[v * d + k] += c[i * d + k];
                        }
                    }
                }
            })
        })??;
        self.solves += cols.len();
        self.ksp.mat_solve(&b, &x)?;
        Ok(x)
    }

    /// `c - (r - r_a) M u_C`: the contact load that gives, with the
    /// assembled matrix, the solution at the current r.
    fn corrected(&self, surface: &Surface, c: &[f64], uc: &[f64]) -> Vec<f64> {
        let delta = self.r - self.r_assembled;
        if delta == 0.0 {
            return c.to_vec();
        }
        let mut m = vec![0.0; c.len()];
        surface.apply_contact_block(uc, &mut m);
        c.iter().zip(&m).map(|(a, b)| a - delta * b).collect()
    }

    /// Changes r to `r_new`: see the module documentation.
    pub fn set_r(&mut self, surface: &Surface, r_new: f64, mesh_start: usize) -> Result<(), Error> {
        if r_new == self.r {
            return Ok(());
        }
        let d = surface.dim;
        let m = surface.len() * d;
        if let Some(cd) = &mut self.condensed {
            let delta = r_new - self.r_assembled;
            // S_r' = S_r_a + delta M (M on the unknowns without Dirichlet data).
            let mut s = cd.s0.clone();
            let mut e = vec![0.0; m];
            let mut col = vec![0.0; m];
            for j in 0..m {
                e[j] = 1.0;
                surface.apply_contact_block(&e, &mut col);
                e[j] = 0.0;
                for i in 0..m {
                    if !surface.dirichlet[j] {
                        s[j * m + i] += delta * col[i];
                    }
                }
            }
            // y0 at r': S_r' y0' = S_r_a y0 - delta M_FD x_D.
            let mut b = vec![0.0; m];
            for j in 0..m {
                let y = cd.y0_assembled[j];
                if y != 0.0 {
                    for (bi, sij) in b.iter_mut().zip(&cd.s0[j * m..(j + 1) * m]) {
                        *bi += sij * y;
                    }
                }
            }
            surface.apply_contact_block(&self.xd_c, &mut col);
            for i in 0..m {
                b[i] -= delta * col[i];
            }
            let shifted = DenseSpd::factor(m, &s)?;
            shifted.solve(&b, &mut cd.y0)?;
            cd.shifted = Some(shifted);
            self.r = r_new;
            return Ok(());
        }
        // Full: the matrix's contact blocks and the lifted load change.
        let delta = r_new - self.r;
        let cs = surface.cs;
        let mut idx = Vec::with_capacity(d);
        let mut col = vec![0.0; m];
        for (i, &v) in cs.node.iter().enumerate() {
            idx.clear();
            for c in 0..d {
                // Dirichlet rows and columns stay eliminated.
                idx.push(if surface.dirichlet[i * d + c] {
                    -1
                } else {
                    ((mesh_start + v) * d + c) as sys::PetscInt
                });
            }
            let vals = super::contact_block(d, &cs.n, delta * cs.w[i], surface.tangential);
            self.matrix.add_values(&idx, &idx, &vals)?;
        }
        self.matrix.assemble()?;
        surface.apply_contact_block(&self.xd_c, &mut col);
        col.iter_mut().for_each(|x| *x *= -delta);
        scatter_add(surface, &col, &self.rhs0)?;
        if self.iterative {
            self.ksp.set_reuse_preconditioner(true)?;
        }
        self.ksp.set_operators(&self.matrix)?;
        if !self.iterative {
            self.ksp.set_up()?; // the numeric factorization at r'
        }
        self.r = r_new;
        self.r_assembled = r_new;
        Ok(())
    }
}

/// `b += C c`: the contact-node values into a vector of the system.
fn scatter_add(surface: &Surface, c: &[f64], b: &Vector) -> Result<(), Error> {
    let d = surface.dim;
    b.write(|b| {
        for (i, &v) in surface.cs.node.iter().enumerate() {
            for k in 0..d {
                b[v * d + k] += c[i * d + k];
            }
        }
    })
}

/// `u_C = C^T u`.
fn extract(surface: &Surface, u: &Vector, uc: &mut [f64]) -> Result<(), Error> {
    let d = surface.dim;
    u.read(|u| {
        for (i, &v) in surface.cs.node.iter().enumerate() {
            uc[i * d..(i + 1) * d].copy_from_slice(&u[v * d..(v + 1) * d]);
        }
    })
}
