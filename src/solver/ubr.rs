//! Algorithm UBR-C (Koko 2010, section 4.3): Uzawa block relaxation for
//! frictionless unilateral contact.
//!
//! Initialization: `phi^{-1} = 0`, `lambda^0 = 0`. Iteration k >= 0:
//! 1. solve (4.5): `(K + r B^T W B) u^k = f + B^T W (r phi^{k-1} - lambda^k)`
//!    with the matrix factorized once;
//! 2. project (4.15): `phi^k = u_n^k + [lambda^k - (lambda^k + r(u_n^k - g))^+] / r`;
//! 3. update (4.4): `lambda^{k+1} = lambda^k + rho (u_n^k - phi^k)`;
//!
//! until the relative change (4.16) is below eps_c and, as in section 7, the
//! constraint residual `||B u^k - phi^k||_{0,Gamma_c}` is below its tolerance.
//! Norms: lumped mass on Omega, nodal weights w_i on Gamma_c. Every stopping
//! decision is taken on globally reduced sums, so all ranks agree.

use super::{allreduce_sum, Problem};
use crate::contact::project_normal;
use crate::error::Error;
use crate::options::UbrSettings;
use crate::petsc::Vector;
use mpi::traits::*;

/// The state and outcome of a UBR run.
pub struct UbrResult {
    pub iterations: usize,
    pub converged: bool,
    /// Last value of the (4.16) quotient, and of the constraint residual.
    pub criterion: f64,
    pub residual: f64,
    /// Per owned candidate: normal displacement u_n^k; the contact pressure
    /// `lambda_n = -sigma_n(u^k) = lambda^k + r (u_n^k - phi^{k-1})` of (4.7),
    /// the normal stress in equilibrium with u^k, so that the contact force
    /// balances the load to round-off at any iteration (it differs from the
    /// multiplier `lambda^{k+1}` by `r (phi^k - phi^{k-1})`, which vanishes at
    /// convergence); the multiplier itself; the auxiliary phi^k; and whether
    /// the last projection found contact.
    pub un: Vec<f64>,
    pub lambda_n: Vec<f64>,
    pub lambda_next: Vec<f64>,
    pub phi_n: Vec<f64>,
    pub in_contact: Vec<bool>,
    /// Tangential displacement per candidate, `dim` components each.
    pub ut: Vec<f64>,
    pub solution: Vector,
    pub time_iterations: f64,
    /// Inner (KSP) iterations of each outer iteration.
    pub inner_iterations: Vec<usize>,
}

/// Runs UBR-C on `problem`.
pub fn ubr_c<C: Communicator>(
    world: &C,
    problem: &Problem,
    settings: &UbrSettings,
    events: &crate::Events,
) -> Result<UbrResult, Error> {
    let t0 = std::time::Instant::now();
    let d = problem.dim;
    let cs = &problem.contact;
    let nc = cs.len();
    let (r, rho) = (settings.r, settings.rho);
    let n = &cs.n;
    let root = world.rank() == 0;

    // Initialization: phi^{-1} = 0, lambda^0 = 0.
    let mut phi = vec![0.0; nc];
    let mut lambda = vec![0.0; nc];
    let mut stress = vec![0.0; nc];
    let mut un = vec![0.0; nc];
    let mut in_contact = vec![false; nc];
    let u = problem.rhs0.duplicate()?;
    u.set(0.0)?;
    let rhs = problem.rhs0.duplicate()?;
    let nloc = problem.is_dirichlet.len();
    let mut u_prev = vec![0.0; nloc];
    let mut inner = Vec::new();
    let mut converged = false;
    let mut criterion = f64::INFINITY;
    let mut residual = f64::INFINITY;
    let mut k = 0;
    if root && settings.monitor {
        println!("  UBR-C   it   rel. change (4.16)   ||Bu - phi||      contact nodes");
    }
    while k < settings.max_it {
        // Step 1: the elasticity subproblem (4.5); only the right-hand side changes.
        {
            let _e = events.rhs.begin();
            rhs.copy_from(&problem.rhs0)?;
            rhs.write(|b| {
                for i in 0..nc {
                    let s = cs.w[i] * (r * phi[i] - lambda[i]);
                    let base = cs.node[i] * d;
                    for c in 0..d {
                        if !problem.is_dirichlet[base + c] {
                            b[base + c] += s * n[c];
                        }
                    }
                }
            })?;
        }
        let its = {
            let _e = events.solve.begin();
            problem.ksp.solve(&rhs, &u)?
        };
        inner.push(its);
        // Steps 2 and 3: projection (4.15) and multiplier update (4.4), pointwise.
        let _e = events.projection.begin();
        let sums = u.read(|uv| {
            let mut s = [0.0f64; 6];
            // ||u^k - u^{k-1}||^2 and ||u^k||^2 with lumped mass
            for (j, m) in problem.lumped_mass.iter().enumerate() {
                for c in 0..d {
                    let x = uv[j * d + c];
                    let dx = x - u_prev[j * d + c];
                    s[0] += m * dx * dx;
                    s[1] += m * x * x;
                }
            }
            u_prev.copy_from_slice(uv);
            for i in 0..nc {
                let base = cs.node[i] * d;
                let uni: f64 = (0..d).map(|c| uv[base + c] * n[c]).sum();
                // -sigma_n(u^k) by (4.7): the contact stress in equilibrium with u^k.
                stress[i] = lambda[i] + r * (uni - phi[i]);
                let (phi_new, lambda_new, contact) =
                    project_normal(uni, lambda[i], cs.g[i], r, rho);
                let w = cs.w[i];
                s[2] += w * (phi_new - phi[i]).powi(2);
                s[3] += w * phi_new * phi_new;
                s[4] += w * (uni - phi_new).powi(2);
                s[5] += if contact { 1.0 } else { 0.0 };
                un[i] = uni;
                phi[i] = phi_new;
                lambda[i] = lambda_new;
                in_contact[i] = contact;
            }
            s
        })?;
        drop(_e);
        let [du2, u2, dphi2, phi2, res2, ncontact] = allreduce_sum(world, sums);
        criterion = if u2 + phi2 > 0.0 {
            ((du2 + dphi2) / (u2 + phi2)).sqrt()
        } else {
            0.0
        };
        residual = res2.sqrt();
        if root && settings.monitor {
            println!(
                "  UBR-C {:5}   {:.6e}         {:.6e}   {}",
                k, criterion, residual, ncontact as usize
            );
        }
        k += 1;
        if !criterion.is_finite() || !residual.is_finite() {
            return Err(Error::NotConverged(format!(
                "UBR-C produced a non-finite iterate at iteration {k}"
            )));
        }
        if k >= 2 && criterion < settings.rtol && residual < settings.residual_tol {
            converged = true;
            break;
        }
    }
    // Tangential displacement u_t = u - u_n n at each candidate.
    let ut = u.read(|uv| {
        let mut ut = vec![0.0; nc * d];
        for i in 0..nc {
            let base = cs.node[i] * d;
            for c in 0..d {
                ut[i * d + c] = uv[base + c] - un[i] * n[c];
            }
        }
        ut
    })?;
    Ok(UbrResult {
        iterations: k,
        converged,
        criterion,
        residual,
        un,
        lambda_n: stress,
        lambda_next: lambda,
        phi_n: phi,
        in_contact,
        ut,
        solution: u,
        time_iterations: t0.elapsed().as_secs_f64(),
        inner_iterations: inner,
    })
}
