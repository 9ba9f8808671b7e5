//! The PETSc SNES VI comparator (`-contact_algorithm snesvi`): the frictionless
//! contact problem as a bound-constrained linear complementarity problem,
//! `K u - f` with `u.n <= g` at the candidates as a variable bound, solved by
//! PETSc's reduced-space active-set Newton method `vinewtonrsls` (full steps
//! by default, `-snes_linesearch_type basic`; every SNES option applies). The
//! contact direction must be a coordinate axis, so that the constraint is a
//! bound on one component. The contact pressure is the constraint reaction
//! `lambda = -(K u - f).n / w`.

use super::surface::UbrState;
use super::ubr::UbrOutcome;
use super::Problem;
use crate::comm::allreduce_sum;
use crate::error::{bad, Error};
use crate::linalg::without_zero_couplings;
use crate::petsc::{options, Snes};
use mpi::traits::*;

/// Bounds above and below every value (PETSc's SNES_VI_INF is 1e20).
const FREE: f64 = 1e20;

pub fn snes_vi<C: Communicator>(
    world: &C,
    problem: &Problem,
    state: &mut UbrState,
    initial_shift: &[f64],
) -> Result<UbrOutcome, Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    let nc = cs.len();
    let Some(axis) = cs
        .common_normal()
        .and_then(|n| (0..d).find(|&c| n[c].abs() == 1.0))
    else {
        return bad("-contact_algorithm snesvi needs one contact normal along a coordinate axis for every candidate (the bound u.n <= g must bound one component): use -contact_normal fixed with an axis -contact_direction");
    };
    let n = &cs.direction;
    let sign = n[axis];
    options::set_default("-snes_linesearch_type", "basic")?;
    let lower = problem.lin.rhs0.duplicate()?;
    let upper = problem.lin.rhs0.duplicate()?;
    lower.set(-FREE)?;
    upper.set(FREE)?;
    let is_dir = &problem.dirichlet.fixed;
    lower.write(|lo| {
        upper.write(|up| {
            for i in 0..nc {
                let dof = cs.node[i] * d + axis;
                if is_dir[dof] {
                    continue;
                }
                // u.n = sign * u_axis <= g
                if sign > 0.0 {
                    up[dof] = cs.g[i];
                } else {
                    lo[dof] = -cs.g[i];
                }
            }
        })
    })??;
    // Initial guess: the shift (projected onto the bounds), Dirichlet values kept.
    let mut xd = vec![0.0; is_dir.len()];
    for &(i, v) in &problem.dirichlet.dofs {
        xd[i] = v;
    }
    state.u.write(|u| {
        lower.read(|lo| {
            upper.read(|up| {
                for (i, x) in u.iter_mut().enumerate() {
                    let v = if is_dir[i] {
                        xd[i]
                    } else if initial_shift.is_empty() {
                        0.0
                    } else {
                        initial_shift[i % d]
                    };
                    *x = v.clamp(lo[i], up[i]);
                }
            })
        })
    })???;
    let matrix = without_zero_couplings(&problem.lin.matrix, d)?;
    let snes = Snes::new_vi(&matrix, &problem.lin.rhs0, &lower, &upper)?;
    let (its, lits, failure) = snes.solve(&state.u)?;
    state.inner_iterations.push(lits);
    // The reaction: K u - f = -B^T W lambda.
    let f = problem.lin.rhs0.duplicate()?;
    problem.lin.matrix.mult(&state.u, &f)?;
    f.axpy(-1.0, &problem.lin.rhs0)?;
    let contact = state.u.read(|u| {
        f.read(|fv| {
            let mut contact = 0.0;
            for i in 0..nc {
                let base = cs.node[i] * d;
                let un: f64 = (0..d).map(|c| u[base + c] * n[c]).sum();
                state.surface.un[i] = un;
                for c in 0..d {
                    state.surface.ut[i * d + c] = u[base + c] - un * n[c];
                }
                let fn_: f64 = (0..d).map(|c| fv[base + c] * n[c]).sum();
                let l = -fn_ / cs.w[i];
                state.surface.stress_n[i] = l;
                state.surface.lambda_n[i] = l;
                state.surface.in_contact[i] =
                    un >= cs.g[i] - 1e-12 * cs.g[i].abs().max(1e-12) && l > 0.0;
                if state.surface.in_contact[i] {
                    contact += 1.0;
                }
            }
            contact
        })
    })??;
    let [contact] = allreduce_sum(world, [contact]);
    Ok(UbrOutcome {
        iterations: its,
        converged: failure.is_none(),
        failure,
        contact: contact as usize,
        ..Default::default()
    })
}
