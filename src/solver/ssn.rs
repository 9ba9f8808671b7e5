//! Algorithm SSN-C (Koko 2010, section 7): the semi-smooth Newton (primal-dual
//! active set) comparator for frictionless contact.
//!
//! (1) u^0 given (the paper: a vertical shift for a floating body,
//! `-ssn_initial_shift`); (2) active set `A^{k+1} = {lambda_hat + r(u_n^k - g) > 0}`;
//! (3) stop when `k >= 1` and `A^{k+1} = A^k`; (4) solve (7.1)
//! `(K + r B_A^T W B_A) u^{k+1} = f + B_A^T W (r g - lambda_hat)` and set
//! `lambda^{k+1} = lambda_hat + r(u_n^{k+1} - g)` on A, 0 elsewhere. With
//! `lambda_hat = 0` as in the paper. The matrix changes with the active set,
//! so it is re-assembled and factorized every iteration; its nonzero pattern
//! does not change, so the symbolic factorization is kept.

use super::surface::UbrState;
use super::ubr::UbrOutcome;
use super::Problem;
use crate::comm::allreduce_sum;
use crate::error::Error;
use crate::linalg::{linear_solver, without_zero_couplings};
use crate::mesh::distribute::LocalMesh;
use crate::options::LinearBackend;
use crate::petsc::{sys, Matrix, Vector};
use mpi::traits::*;

/// SSN-C settings.
#[derive(Clone, Debug)]
pub struct SsnControl {
    pub r: f64,
    pub max_it: usize,
    /// Initial displacement added to every node (empty: u^0 = 0).
    pub initial_shift: Vec<f64>,
    pub monitor: bool,
    /// The linear back-end (a KSP: SSN-C factorizes each iteration).
    pub linear: LinearBackend,
}

/// Runs SSN-C; the result lands in `state` (u, u_n, lambda as stresses, active set).
#[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
pub fn ssn_c<C: Communicator>(
    world: &C,
    problem: &Problem,
    mesh: &LocalMesh,
    state: &mut UbrState,
    ctl: &SsnControl,
    events: &crate::petsc::Events,
) -> Result<(UbrOutcome, String), Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    let nc = cs.len();
    let r = ctl.r;
    let root = world.rank() == 0;
    let lambda_hat = 0.0;
    // The matrix without the zeroed Dirichlet couplings (as UBR's direct
    // back-end factorizes it); the contact terms go to the nodes' own blocks.
    let base = without_zero_couplings(&problem.lin.matrix, d)?;
    let a = base.duplicate()?;
    let (ksp, description, iterative) = linear_solver(&a, mesh, &ctl.linear)?;
    let work = problem.lin.rhs0.duplicate()?;
    let rhs = problem.lin.rhs0.duplicate()?;
    let is_dir = &problem.dirichlet.fixed;
    // Dirichlet values at the owned dofs, for the lifting of the contact terms.
    let mut xd = vec![0.0; is_dir.len()];
    for &(i, v) in &problem.dirichlet.dofs {
        xd[i] = v;
    }
    // (1) u^0
    state.u.set(0.0)?;
    if !ctl.initial_shift.is_empty() {
        state.u.write(|u| {
            for (i, x) in u.iter_mut().enumerate() {
                *x = if is_dir[i] {
                    xd[i]
                } else {
                    ctl.initial_shift[i % d]
                };
            }
        })?;
    }
    let mut active = vec![false; nc];
    let mut next = vec![false; nc];
    let mut out = UbrOutcome::default();
    if root && ctl.monitor {
        println!("  SSN-C   it   active nodes   changed");
    }
    let mut k = 0;
    loop {
        // (2) the active set from u^k
        let changed = state.u.read(|u| {
            let mut changed = 0.0;
            for i in 0..nc {
                let (base, n) = (cs.node[i] * d, cs.n(i));
                let un: f64 = (0..d).map(|c| u[base + c] * n[c]).sum();
                next[i] = lambda_hat + r * (un - cs.g[i]) > 0.0;
                if next[i] != active[i] {
                    changed += 1.0;
                }
            }
            changed
        })?;
        let count = next.iter().filter(|&&x| x).count() as f64;
        let [changed, count] = allreduce_sum(world, [changed, count]);
        if root && ctl.monitor {
            println!(
                "  SSN-C {k:5}   {:12}   {:7}",
                count as usize, changed as usize
            );
        }
        crate::progress::tick(|| {
            format!(
                "SSN-C iteration {k}: {} active, {} changed",
                count as usize, changed as usize
            )
        });
        // (3) stop when the active set repeats
        if k >= 1 && changed == 0.0 {
            out.converged = true;
            break;
        }
        if k >= ctl.max_it {
            break;
        }
        std::mem::swap(&mut active, &mut next);
        // (4) K + r B_A^T W B_A, same pattern as K: numeric factorization only.
        {
            let _e = events.rhs.begin();
            active_system(problem, mesh, r, &active, &xd, &base, &a, &rhs)?;
        }
        ksp.set_operators(&a)?;
        let its = {
            let _e = events.solve.begin();
            ksp.solve(&rhs, &state.u)?
        };
        state.inner_iterations.push(its);
        if !iterative {
            check_direct_solve(&a, &state.u, &rhs, &work, k, count)?;
        }
        k += 1;
        out.iterations = k;
    }
    // lambda^{k} = lambda_hat + r(u_n - g) on A, 0 elsewhere; it is also -sigma_n(u).
    let _e = events.projection.begin();
    let counts = multipliers(problem, r, &active, state)?;
    let [contact] = allreduce_sum(world, [counts]);
    out.contact = contact as usize;
    out.criterion = 0.0;
    out.residual = 0.0;
    Ok((out, description))
}

/// Step (4): `K + r B_A^T W B_A` of the active set into `a` (from `base`,
/// the same pattern), and its right-hand side into `rhs`.
#[allow(clippy::too_many_arguments)]
fn active_system(
    problem: &Problem,
    mesh: &LocalMesh,
    r: f64,
    active: &[bool],
    xd: &[f64],
    base: &Matrix,
    a: &Matrix,
    rhs: &Vector,
) -> Result<(), Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    let nc = cs.len();
    let is_dir = &problem.dirichlet.fixed;
    let lambda_hat = 0.0;
    a.copy_from(base)?;
    let g0 = mesh.owned_start * d;
    let mut idx = Vec::with_capacity(d);
    let mut vals = Vec::with_capacity(d * d);
    for i in (0..nc).filter(|&i| active[i]) {
        let (base, n) = (cs.node[i] * d, cs.n(i));
        let rw = r * cs.w[i];
        idx.clear();
        vals.clear();
        for c in 0..d {
            // Dirichlet rows and columns stay eliminated.
            idx.push(if is_dir[base + c] {
                -1
            } else {
                (g0 + base + c) as sys::PetscInt
            });
        }
        for ci in 0..d {
            for cj in 0..d {
                vals.push(rw * n[ci] * n[cj]);
            }
        }
        a.add_values(&idx, &idx, &vals)?;
    }
    a.assemble()?;
    rhs.copy_from(&problem.lin.rhs0)?;
    rhs.write(|b| {
        for i in (0..nc).filter(|&i| active[i]) {
            let (base, n) = (cs.node[i] * d, cs.n(i));
            let w = cs.w[i];
            // r g - lambda_hat along n, lifted by the prescribed components.
            let lift: f64 = (0..d).map(|c| n[c] * xd[base + c]).sum();
            for c in 0..d {
                if !is_dir[base + c] {
                    b[base + c] += w * n[c] * (r * cs.g[i] - lambda_hat - r * lift);
                }
            }
        }
    })?;
    Ok(())
}

/// The multipliers `lambda = lambda_hat + r (u_n - g)` on the active set, 0
/// elsewhere, with u_n, u_t and the statuses, into `state`; returns this
/// rank's count in contact.
#[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
fn multipliers(
    problem: &Problem,
    r: f64,
    active: &[bool],
    state: &mut UbrState,
) -> Result<f64, Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    let nc = cs.len();
    let lambda_hat = 0.0;
    let surface = &mut state.surface;
    state.u.read(|u| {
        let mut contact = 0.0;
        for i in 0..nc {
            let (base, n) = (cs.node[i] * d, cs.n(i));
            let un: f64 = (0..d).map(|c| u[base + c] * n[c]).sum();
            surface.un[i] = un;
            for c in 0..d {
                surface.ut[i * d + c] = u[base + c] - un * n[c];
            }
            let l = if active[i] {
                lambda_hat + r * (un - cs.g[i])
            } else {
                0.0
            };
            surface.stress_n[i] = l;
            surface.lambda_n[i] = l;
            surface.in_contact[i] = active[i];
            if active[i] {
                contact += 1.0;
            }
        }
        contact
    })
}

/// A direct solve of a singular system (a body free to move that no
/// active node holds) does not always fail: its residual is checked
/// (`work`: scratch), at iteration k with `count` nodes active.
fn check_direct_solve(
    a: &Matrix,
    u: &Vector,
    rhs: &Vector,
    work: &Vector,
    k: usize,
    count: f64,
) -> Result<(), Error> {
    a.mult(u, work)?;
    work.axpy(-1.0, rhs)?;
    let (res, bn) = (work.norm2()?, rhs.norm2()?);
    if res.is_nan() || res > 1e-6 * bn.max(f64::MIN_POSITIVE) {
        let hint = if count == 0.0 {
            "; no contact node is active and the body is free to move: give an initial guess that touches (-ssn_initial_shift, the paper uses 0,-0.01)"
        } else {
            ""
        };
        return Err(Error::LinearSolver(format!(
            "SSN-C iteration {k}: the linear system is singular (relative residual {:.1e}){hint}",
            res / bn
        )));
    }
    Ok(())
}
