//! The linear back-ends of UBR: their one job is to apply `K_r^{-1}`, where
//! `K_r = K + r B^T W B` is factorized (or preconditioned) once.
//!
//! Every UBR solve (4.5)/(5.3) has the right-hand side `f + B^T W v`, whose
//! contact part `c = B^T W v` lives on the contact nodes alone. A back-end
//! returns `u_C`, the displacement at the contact nodes, for `rhs0 + C c`:
//! - **full**: a sparse solve of the whole system, by PETSc's KSP (any
//!   KSP/PC from the options) or by MUMPS directly ([`super::direct`]); the
//!   whole displacement comes with it;
//! - **condensed** (MUMPS directly, any number of ranks): `u_C = y0 + S^{-1} c`,
//!   where S is the Schur complement of `K_r` on the contact unknowns,
//!   returned by MUMPS with the one numeric factorization (on the host), and
//!   `y0` is `u_C` for `rhs0`. The whole displacement costs one sparse
//!   solve, at the end.
//!
//! Changing r. `K_r' = K_r + (r' - r) B^T W B` differs from `K_r` only in the
//! contact blocks, so its Schur complement is `S + (r' - r) M` (M: the
//! contact blocks, [`Surface::apply_contact_block`]): the condensed back-end
//! changes r with a dense refactorization of S alone, and gets the whole
//! displacement from the factorization of `K_r` by moving the difference to
//! the right-hand side, `K_r u = rhs0 + C (c - (r' - r) M u_C)`, exact since
//! `u_C` is known. A full back-end updates the contact blocks of the matrix
//! and refactorizes (a direct solver: numeric factorization only, the
//! pattern is the same) or keeps its preconditioner (an iterative one: the
//! multigrid hierarchy of `K_r` serves `K_r'`, no second set-up).

use super::direct::Direct;
use crate::contact::surface::{contact_block, Surface};
use crate::error::Error;
use crate::petsc::{sys, DenseColumns, Ksp, Matrix, Vector};
use mpi::topology::SimpleCommunicator;

/// What solves with `K_r`.
pub enum Engine {
    /// PETSc's KSP, any solver from the options.
    Ksp(Ksp),
    /// MUMPS driven directly (METIS ordering, Schur complement on any rank count).
    Direct(Box<Direct>),
}

/// `K_r^{-1}` for UBR, with the bookkeeping of r and of the solves.
pub struct LinearSolver {
    engine: Engine,
    world: SimpleCommunicator,
    /// `K + r_a B^T W B` with Dirichlet rows and columns eliminated (r_a: the
    /// assembled r).
    pub matrix: Matrix,
    /// An iterative solver's operator for products, the same matrix in
    /// symmetric block storage (`-ubr_sbaij`); the preconditioner is built
    /// from `matrix`.
    operator: Option<Matrix>,
    /// Right-hand side without contact terms, at the current r.
    pub rhs0: Vector,
    pub iterative: bool,
    /// Inexact solves: the inner tolerance follows the outer iteration.
    pub adaptive_inner: bool,
    pub description: String,
    r_assembled: f64,
    r: f64,
    /// The r at which `rhs0` was made (the assembly's): a full back-end
    /// that changed r adds the difference's Dirichlet part to a new load.
    r_original: f64,
    /// Condensed: `u_C` of `rhs0` (this rank's candidates, the Schur
    /// components) at the assembled r and at the current r.
    y0: Option<(Vec<f64>, Vec<f64>)>,
    /// The components of each candidate in the Schur complement (the normal
    /// axis alone, frictionless along an axis; else all): a condensed solve
    /// knows u only there (the other components of `u_C` are set to 0).
    comps: Vec<usize>,
    dim: usize,
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
    /// Work space of the direct solves of every iteration (the picked
    /// Schur components, and the solution or a whole right-hand side).
    scratch: (Vec<f64>, Vec<f64>),
    /// What the run's warnings should say of the solver (the application
    /// takes them).
    pub warnings: Vec<String>,
    /// Consecutive UBR solves an iterative solver ended before its first
    /// iteration ([`IDLE_SOLVES`]).
    idle: usize,
}

/// UBR solves in a row that an iterative solver may end before its first
/// iteration (its tolerances met by the start, the previous displacement)
/// before the run stops: the displacement no longer follows the contact
/// stresses. A `-ksp_atol` above the residuals of the run's units did it
/// (`-ksp_atol 1e10` on a 3D pair of blocks: every solve ended at 0
/// iterations, UBR ran to -ubr_max_it, 10,000, its relative residual
/// falling as 1/k while the stresses grew without bound). The program's
/// own tolerances (relative to each solve's start) meet it only where a
/// start is exact, when UBR has converged.
const IDLE_SOLVES: usize = 20;

/// The Schur components `comps` of each candidate of `v` (`dim` values
/// each) into `out`.
fn pick_into(dim: usize, comps: &[usize], v: &[f64], out: &mut Vec<f64>) {
    out.clear();
    out.extend(
        v.chunks_exact(dim)
            .flat_map(|x| comps.iter().map(move |&c| x[c])),
    );
}

/// Writes the Schur components `x` into `uc` (`dim` values per candidate;
/// the others 0).
fn place(dim: usize, comps: &[usize], x: &[f64], uc: &mut [f64]) {
    let nk = comps.len();
    uc.iter_mut().for_each(|v| *v = 0.0);
    for (i, xi) in x.chunks_exact(nk).enumerate() {
        for (k, &c) in comps.iter().enumerate() {
            uc[i * dim + c] = xi[k];
        }
    }
}

impl LinearSolver {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        engine: Engine,
        matrix: Matrix,
        operator: Option<Matrix>,
        rhs0: Vector,
        iterative: bool,
        adaptive_inner: bool,
        description: String,
        r: f64,
        xd_c: Vec<f64>,
        dirichlet: Vec<(usize, f64)>,
        dim: usize,
    ) -> Result<LinearSolver, Error> {
        let rhs = rhs0.duplicate()?;
        Ok(LinearSolver {
            engine,
            world: SimpleCommunicator::world(),
            matrix,
            operator,
            rhs0,
            iterative,
            adaptive_inner,
            description,
            r_assembled: r,
            r,
            r_original: r,
            y0: None,
            comps: Vec::new(),
            dim,
            xd_c,
            dirichlet,
            rhs,
            solves: 0,
            rtol: f64::NAN,
            scratch: (Vec::new(), Vec::new()),
            warnings: Vec::new(),
            idle: 0,
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
        match &self.engine {
            Engine::Direct(d) if self.y0.is_some() => d.schur_size(),
            _ => 0,
        }
    }

    pub fn is_condensed(&self) -> bool {
        self.y0.is_some()
    }

    /// Condensed on every component of each candidate: its solves know the
    /// whole `u` of the candidates (the tangential part too).
    pub fn condenses_every_component(&self) -> bool {
        self.is_condensed() && self.comps.len() == self.dim
    }

    /// Why the one factorization failed, when it did (the direct back-end
    /// keeps such a failure, the same on every rank: the problem is set up,
    /// every solve returns it, and the run reports it with its outputs).
    pub fn failure(&self) -> Option<Error> {
        match &self.engine {
            Engine::Direct(d) => d.failure().cloned(),
            Engine::Ksp(_) => None,
        }
    }

    /// Turns the condensed solves on (a direct engine factorized with the
    /// Schur complement on the components `comps` of the candidates): `y0`,
    /// the Schur components of `u_C` for rhs0, from one condensation and a
    /// dense solve (no expansion). Nothing to do after a failed
    /// factorization ([`LinearSolver::failure`]).
    pub fn condense(&mut self, surface: &Surface, comps: &[usize]) -> Result<(), Error> {
        if self.failure().is_some() {
            return Ok(());
        }
        let m = match &self.engine {
            Engine::Direct(d) if d.is_condensed() => d.schur_size(),
            _ => {
                return Err(Error::Internal(
                    "condensation needs the Schur complement".into(),
                ))
            }
        };
        self.solves += 1;
        let b = self.rhs0.read(|b| b.to_vec())?;
        let mut y0 = vec![0.0; surface.len() * comps.len()];
        if let Engine::Direct(d) = &mut self.engine {
            // Two columns kept for the two final displacements
            // ([`LinearSolver::displacements`] with `expand`).
            d.solve_contact_part(&self.world, &b, &mut y0, 2)?;
        }
        self.comps = comps.to_vec();
        self.y0 = Some((y0.clone(), y0));
        let layout = match &self.engine {
            Engine::Direct(d) if d.schur_distributed() => {
                " (the Schur complement from MUMPS distributed over the ranks, factorized and solved there by ScaLAPACK)"
            }
            _ => "",
        };
        self.description
            .push_str(&format!(", condensed on the {m} contact unknowns{layout}"));
        Ok(())
    }

    /// The Schur components of the candidates, when condensed.
    pub fn schur_comps(&self) -> Option<&[usize]> {
        self.y0.as_ref().map(|_| &self.comps[..])
    }

    /// Back to full solves (the condensed and full solves disagreed).
    pub fn uncondense(&mut self) {
        self.y0 = None;
    }

    /// Inexact solves: the relative tolerance of the next inner solves.
    pub fn set_inner_rtol(&mut self, rtol: f64) -> Result<(), Error> {
        if let Engine::Ksp(ksp) = &self.engine {
            if self.iterative && self.adaptive_inner && rtol != self.rtol {
                ksp.set_rtol(rtol)?;
                self.rtol = rtol;
            }
        }
        Ok(())
    }

    /// One full solve `K_r u = b`, b the work vector `rhs` (`true`) or
    /// `rhs0` (u: the initial guess of an iterative solver); returns the
    /// inner iteration count.
    fn full_solve(&mut self, from_rhs: bool, u: &Vector) -> Result<usize, Error> {
        self.solves += 1;
        let b = if from_rhs { &self.rhs } else { &self.rhs0 };
        match &mut self.engine {
            Engine::Ksp(ksp) => {
                let its = ksp.solve(b, u)?;
                if self.iterative {
                    u.write(|u| {
                        for &(i, v) in &self.dirichlet {
                            u[i] = v;
                        }
                    })?;
                }
                Ok(its)
            }
            Engine::Direct(d) => {
                let x = &mut self.scratch.1;
                b.read(|b| {
                    x.clear();
                    x.extend_from_slice(b);
                })?;
                d.solve_full(&self.world, x, 1)?;
                u.write(|u| u.copy_from_slice(x))?;
                Ok(0)
            }
        }
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
        if let (Some((_, y0)), Engine::Direct(d)) = (&self.y0, &mut self.engine) {
            self.solves += 1;
            let (picked, x) = &mut self.scratch;
            pick_into(self.dim, &self.comps, c, picked);
            x.resize(y0.len(), 0.0);
            d.solve_schur(&self.world, picked, x)?;
            for (xi, y) in x.iter_mut().zip(y0) {
                *xi += y;
            }
            place(self.dim, &self.comps, x, uc);
            return Ok(0);
        }
        self.rhs.copy_from(&self.rhs0)?;
        scatter_add(surface, c, &self.rhs)?;
        let its = self.full_solve(true, u)?;
        if self.iterative {
            self.idle = if its == 0 { self.idle + 1 } else { 0 };
            if self.idle >= IDLE_SOLVES {
                return Err(Error::NotConverged(format!(
                    "the iterative solver ended each of the last {IDLE_SOLVES} solves before its first iteration: its tolerances (-ksp_atol, -ksp_rtol) are met where each starts, so the displacement no longer follows the contact stresses; lower -ksp_atol below the residuals of the model's units, or leave the tolerances to the program (each solve reduces its starting residual by -ubr_inner_rtol_factor)"
                )));
            }
        }
        extract(surface, u, uc)?;
        Ok(its)
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
        if let (Some((_, y0)), Engine::Direct(d)) = (&self.y0, &mut self.engine) {
            self.solves += 1;
            let (picked, x) = &mut self.scratch;
            pick_into(self.dim, &self.comps, c, picked);
            x.resize(y0.len(), 0.0);
            d.solve_schur(&self.world, picked, x)?;
            place(self.dim, &self.comps, x, uc);
            return Ok(0);
        }
        self.rhs.set(0.0)?;
        scatter_add(surface, c, &self.rhs)?;
        work.set(0.0)?;
        let its = self.full_solve(true, work)?;
        if self.iterative {
            work.write(|u| {
                for &(i, _) in &self.dirichlet {
                    u[i] = 0.0;
                }
            })?;
        }
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
        if self.y0.is_none() {
            return Ok(());
        }
        let cc = self.corrected(surface, c, uc);
        self.rhs.copy_from(&self.rhs0)?;
        scatter_add(surface, &cc, &self.rhs)?;
        self.full_solve(true, u)?;
        Ok(())
    }

    /// The whole displacements for several contact loads at once (one pass
    /// over the factors): column j of the result for `cols[j] = (c, uc)`.
    /// `expand`, when condensed: from `uc` at the Schur components, by the
    /// backward pass alone over the forward elimination of `rhs0` that
    /// [`LinearSolver::condense`] left (the contact loads act on the Schur
    /// unknowns alone), if no other sparse solve came between (else as
    /// without). The columns then meet their equations at the Schur
    /// unknowns only as well as `uc` does; without, `u_C` of the result is
    /// the sparse solve's own (what the deferred test compares with `uc`).
    pub fn displacements(
        &mut self,
        surface: &Surface,
        cols: &[(&[f64], &[f64])],
        expand: bool,
    ) -> Result<DenseColumns, Error> {
        let n = self.rhs0.local_size()?;
        let comm = crate::petsc::comm_world();
        let x = DenseColumns::new(comm, n, cols.len())?;
        if let (true, true, Engine::Direct(dd)) = (expand, self.y0.is_some(), &mut self.engine) {
            let mut xs = Vec::new();
            let mut picked = Vec::new();
            for (_, uc) in cols {
                pick_into(self.dim, &self.comps, uc, &mut picked);
                xs.extend_from_slice(&picked);
            }
            let mut all = vec![0.0; n * cols.len()];
            if dd.expand(&self.world, &xs, cols.len(), &mut all)? {
                self.solves += cols.len();
                x.write(|xx| xx.copy_from_slice(&all))?;
                return Ok(x);
            }
        }
        let b = DenseColumns::new(comm, n, cols.len())?;
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
        match &mut self.engine {
            Engine::Ksp(ksp) => ksp.mat_solve(&b, &x)?,
            Engine::Direct(dd) => {
                let mut all = b.read(|bb| bb.to_vec())?;
                dd.solve_full(&self.world, &mut all, cols.len())?;
                x.write(|xx| xx.copy_from_slice(&all))?;
            }
        }
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

    /// Condensed, S already shifted to the current r: y0 at r from `y0a`
    /// (at the assembled r), `S_r y0 = S_r_a y0a - (r - r_a) M_FD x_D`.
    fn y0_shifted(&mut self, surface: &Surface, y0a: &[f64]) -> Result<Vec<f64>, Error> {
        let d = surface.dim;
        let delta = self.r - self.r_assembled;
        let Engine::Direct(dd) = &mut self.engine else {
            return Err(Error::Internal("condensed without MUMPS".into()));
        };
        let mut b = vec![0.0; y0a.len()];
        dd.apply_schur(&self.world, y0a, &mut b);
        let mut col = vec![0.0; surface.len() * d];
        surface.apply_contact_block(&self.xd_c, &mut col);
        let col: Vec<f64> = col
            .chunks_exact(d)
            .flat_map(|x| self.comps.iter().map(move |&c| x[c]))
            .collect();
        for (bi, ci) in b.iter_mut().zip(&col) {
            *bi -= delta * ci;
        }
        let mut y0 = vec![0.0; b.len()];
        dd.solve_schur(&self.world, &b, &mut y0)?;
        Ok(y0)
    }

    /// Condensed: the Schur components of `u_C` for the right-hand side
    /// `rhs` at the assembled r (one solve with the factors); None when not
    /// condensed.
    pub fn contact_part(
        &mut self,
        surface: &Surface,
        rhs: &[f64],
    ) -> Result<Option<Vec<f64>>, Error> {
        if self.y0.is_none() || self.failure().is_some() {
            return Ok(None);
        }
        self.solves += 1;
        let mut y = vec![0.0; surface.len() * self.comps.len()];
        if let Engine::Direct(d) = &mut self.engine {
            d.solve_contact_part(&self.world, rhs, &mut y, 1)?;
        }
        Ok(Some(y))
    }

    /// A new load on the same factorization (a step of a load history):
    /// `rhs0` (made at the assembly's r), the Dirichlet values at the
    /// contact unknowns `xd_c` and the owned Dirichlet dofs and values;
    /// condensed, `y0` at the assembled r given as `y0a` (a combination of
    /// [`LinearSolver::contact_part`]s), else from one solve with the
    /// factors; that solve is made anyway where `keep` columns of the whole
    /// displacement are wanted (it prepares their expansion), a given `y0a`
    /// still kept; then a dense solve where r moved.
    pub fn set_load(
        &mut self,
        surface: &Surface,
        rhs0: &[f64],
        xd_c: Vec<f64>,
        dirichlet: Vec<(usize, f64)>,
        y0a: Option<Vec<f64>>,
        keep: usize,
    ) -> Result<(), Error> {
        self.rhs0.write(|b| b.copy_from_slice(rhs0))?;
        self.xd_c = xd_c;
        self.dirichlet = dirichlet;
        let delta = self.r_assembled - self.r_original;
        if delta != 0.0 {
            // A full back-end at r' = r_assembled: the lifted load's
            // Dirichlet part at the contact blocks, as `set_r` moved it.
            let mut col = vec![0.0; surface.len() * surface.dim];
            surface.apply_contact_block(&self.xd_c, &mut col);
            col.iter_mut().for_each(|x| *x *= -delta);
            scatter_add(surface, &col, &self.rhs0)?;
        }
        if self.y0.is_none() || self.failure().is_some() {
            return Ok(());
        }
        let y0a = match y0a {
            Some(y) if keep == 0 => y,
            given => {
                // The solve prepares the expansion of the `keep` columns;
                // a given y0 (a combination of responses) is kept.
                self.solves += 1;
                let mut y = vec![0.0; surface.len() * self.comps.len()];
                if let Engine::Direct(d) = &mut self.engine {
                    d.solve_contact_part(&self.world, rhs0, &mut y, keep)?;
                }
                given.unwrap_or(y)
            }
        };
        let y0 = if self.r == self.r_assembled {
            y0a.clone()
        } else {
            self.y0_shifted(surface, &y0a)?
        };
        self.y0 = Some((y0a, y0));
        Ok(())
    }

    /// Changes r to `r_new`: see the module documentation.
    pub fn set_r(&mut self, surface: &Surface, r_new: f64, mesh_start: usize) -> Result<(), Error> {
        if r_new == self.r {
            return Ok(());
        }
        let d = surface.dim;
        let m = surface.len() * d;
        let cs = surface.cs;
        if let (Some((y0a, _)), Engine::Direct(dd)) = (&self.y0, &mut self.engine) {
            let delta = r_new - self.r_assembled;
            // S_r' = S_r_a + delta M (M on the Schur components without
            // Dirichlet data).
            let nk = self.comps.len();
            let mut blocks = Vec::with_capacity(surface.len() * nk * nk);
            for (i, &w) in cs.w.iter().enumerate() {
                let b = contact_block(d, cs.n(i), w, surface.tangential);
                for &a in &self.comps {
                    for &c in &self.comps {
                        let keep = !surface.dirichlet[i * d + a] && !surface.dirichlet[i * d + c];
                        blocks.push(if keep { b[a * d + c] } else { 0.0 });
                    }
                }
            }
            dd.shift_schur(&self.world, delta, &blocks, nk)?;
            let y0a = y0a.clone();
            self.r = r_new;
            let y0 = self.y0_shifted(surface, &y0a)?;
            self.y0.as_mut().expect("condensed").1 = y0;
            return Ok(());
        }
        // Full: the matrix's contact blocks and the lifted load change.
        let delta = r_new - self.r;
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
            let vals = contact_block(d, cs.n(i), delta * cs.w[i], surface.tangential);
            self.matrix.add_values(&idx, &idx, &vals)?;
            if let Some(op) = &self.operator {
                // A node's block is a diagonal block, stored whole.
                op.add_values(&idx, &idx, &vals)?;
            }
        }
        self.matrix.assemble()?;
        if let Some(op) = &self.operator {
            op.assemble()?;
        }
        surface.apply_contact_block(&self.xd_c, &mut col);
        col.iter_mut().for_each(|x| *x *= -delta);
        scatter_add(surface, &col, &self.rhs0)?;
        match &mut self.engine {
            Engine::Ksp(ksp) => {
                if self.iterative {
                    ksp.set_reuse_preconditioner(true)?;
                }
                match &self.operator {
                    Some(op) => ksp.set_operators_split(op, &self.matrix)?,
                    None => ksp.set_operators(&self.matrix)?,
                }
                if !self.iterative {
                    ksp.set_up()?; // the numeric factorization at r'
                }
            }
            Engine::Direct(dd) => dd.refactorize(&self.world, &self.matrix)?,
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
