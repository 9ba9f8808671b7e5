//! Algorithms UBR-C (Koko 2010, section 4.3) and UBR-TF (section 5): Uzawa
//! block relaxation for frictionless contact and for Tresca friction.
//!
//! Initialization: `phi^{-1} = 0`, `lambda^0 = 0`. Iteration k >= 0:
//! 1. solve (4.5) / (5.3): `(K + r B^T W B) u^k = f + B^T W (r phi^{k-1} - lambda^k)`
//!    with the matrix factorized once (B = B_n, or (B_n, B_t) with friction);
//! 2. project: (4.15) `phi_c^k = u_n^k + [lambda_c^k - (lambda_c^k + r(u_n^k - g))^+] / r`,
//!    and with friction (5.5) `phi_f^k = (|q| - s)/(r|q|) q` if `|q| > s`, else 0,
//!    where `q = lambda_f^k + r u_t^k`;
//! 3. update (4.4): `lambda^{k+1} = lambda^k + rho (B u^k - phi^k)`;
//!
//! until the relative change (4.16) / (5.6) is below eps and, as in section 7,
//! the constraint residual `||B u^k - phi^k||_{0,Gamma_c}` is below its
//! tolerance; and (our addition) the dual residual
//! `r ||phi^k - phi^{k-1}|| / ||lambda^{k+1}||` is below `-ubr_dual_rtol`
//! (default 10 eps), which the paper's test misses for large r. Norms: lumped mass on Omega, nodal weights w_i on Gamma_c. Every
//! stopping decision is taken on globally reduced sums, so all ranks agree.
//!
//! The reported contact stresses are `-sigma(u^k)` on Gamma_c from (4.7):
//! `lambda^k + r (B u^k - phi^{k-1})`, the stresses in equilibrium with the
//! returned displacement, so that the contact force balances the load to
//! round-off at any iteration; they differ from `lambda^{k+1}` by
//! `r (phi^k - phi^{k-1})`, which vanishes at convergence.

use super::{allreduce_sum, Problem};
use crate::contact::{project_normal, project_tangential};
use crate::error::Error;
use crate::petsc::Vector;
use mpi::traits::*;

/// A converged contact stress is compressive: tension above this fraction of
/// the largest stress means the augmentation springs r carry load, i.e. a
/// rigid motion of the body is free (it drifts away or slides off).
pub const TENSION_TOL: f64 = 1e-3;

/// The iterate of a UBR run, kept between runs for warm starts (CF-FP).
pub struct UbrState {
    pub dim: usize,
    /// Auxiliary variables phi^k: normal per candidate, tangential `dim` per candidate.
    pub phi_n: Vec<f64>,
    pub phi_t: Vec<f64>,
    /// Multipliers lambda^{k+1} (the algorithm's).
    pub lambda_n: Vec<f64>,
    pub lambda_t: Vec<f64>,
    /// Contact stresses -sigma(u^k) of (4.7) (what is reported).
    pub stress_n: Vec<f64>,
    pub stress_t: Vec<f64>,
    /// u_n^k and u_t^k at the candidates.
    pub un: Vec<f64>,
    pub ut: Vec<f64>,
    /// Status from the last projection.
    pub in_contact: Vec<bool>,
    pub slip: Vec<bool>,
    pub u: Vector,
    u_prev: Vec<f64>,
    rhs: Vector,
    /// Inner (KSP) iterations of every outer iteration so far.
    pub inner_iterations: Vec<usize>,
    /// (4.16)/(5.6) change and constraint residual of every outer iteration so far.
    pub history: Vec<[f64; 2]>,
    /// The largest contact stress seen since the cold start (the scale of
    /// the held-body test when nothing touches; kept across warm starts).
    pub peak_stress: f64,
}

impl UbrState {
    /// The paper's initialization: phi^{-1} = 0, lambda^0 = 0, u = 0.
    pub fn new(problem: &Problem) -> Result<UbrState, Error> {
        let d = problem.dim;
        let nc = problem.contact.len();
        let u = problem.rhs0.duplicate()?;
        u.set(0.0)?;
        Ok(UbrState {
            dim: d,
            phi_n: vec![0.0; nc],
            phi_t: vec![0.0; nc * d],
            lambda_n: vec![0.0; nc],
            lambda_t: vec![0.0; nc * d],
            stress_n: vec![0.0; nc],
            stress_t: vec![0.0; nc * d],
            un: vec![0.0; nc],
            ut: vec![0.0; nc * d],
            in_contact: vec![false; nc],
            slip: vec![false; nc],
            rhs: problem.rhs0.duplicate()?,
            u,
            u_prev: vec![0.0; problem.is_dirichlet.len()],
            inner_iterations: Vec::new(),
            history: Vec::new(),
            peak_stress: 0.0,
        })
    }

    /// The right-hand side work vector (for other algorithms sharing the state).
    pub fn rhs_mut(&mut self) -> &mut Vector {
        &mut self.rhs
    }
    pub fn rhs_ref(&self) -> &Vector {
        &self.rhs
    }

    /// Back to the paper's initialization (a cold start).
    pub fn reset(&mut self) -> Result<(), Error> {
        for v in [
            &mut self.phi_n,
            &mut self.phi_t,
            &mut self.lambda_n,
            &mut self.lambda_t,
            &mut self.stress_n,
            &mut self.stress_t,
            &mut self.un,
            &mut self.ut,
            &mut self.u_prev,
        ] {
            v.iter_mut().for_each(|x| *x = 0.0);
        }
        self.peak_stress = 0.0;
        self.u.set(0.0)
    }
}

/// Tolerances and caps of one UBR run.
#[derive(Clone, Copy, Debug)]
pub struct UbrControl {
    pub r: f64,
    pub rho: f64,
    pub rtol: f64,
    pub residual_tol: f64,
    pub max_it: usize,
    pub monitor: bool,
    /// Inexact Uzawa: inner KSP rtol relative to the initial residual b - A u^{k-1}.
    pub inner_rtol_factor: f64,
    /// Tolerance on the dual residual `r ||phi^k - phi^{k-1}|| / ||lambda^{k+1}||`.
    pub dual_rtol: f64,
    /// Largest tensile contact stress accepted at convergence, relative to the
    /// largest stress ([`TENSION_TOL`]; CF-FP loosens it with eps_f^m).
    pub tension_tol: f64,
}

/// What one UBR run did.
#[derive(Clone, Copy, Debug, Default)]
pub struct UbrOutcome {
    pub iterations: usize,
    pub converged: bool,
    /// Last value of the (4.16)/(5.6) quotient, and of the constraint residual.
    pub criterion: f64,
    pub residual: f64,
    /// Dual residual `r ||phi^k - phi^{k-1}|| / ||lambda^{k+1}||`.
    pub dual: f64,
    /// Largest tensile contact stress `max (-lambda_n)^+` relative to the
    /// largest `|lambda_n|` (stresses of u^k): near 1 when the augmentation
    /// springs hold a body that nothing else holds.
    pub tension: f64,
    /// Global counts from the last projection.
    pub contact: usize,
    pub stick: usize,
    pub slip: usize,
}

/// Runs UBR-C (`friction_bound` = None, the problem assembled without the
/// tangential term) or UBR-TF (`Some(s)`, one bound per candidate) from `state`.
#[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
pub fn ubr<C: Communicator>(
    world: &C,
    problem: &Problem,
    state: &mut UbrState,
    friction_bound: Option<&[f64]>,
    ctl: &UbrControl,
    events: &crate::Events,
) -> Result<UbrOutcome, Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    let nc = cs.len();
    let (r, rho) = (ctl.r, ctl.rho);
    let n = &cs.n;
    let root = world.rank() == 0;
    let name = if friction_bound.is_some() {
        "UBR-TF"
    } else {
        "UBR-C"
    };
    assert_eq!(friction_bound.is_some(), problem.tangential);
    let mut out = UbrOutcome {
        criterion: f64::INFINITY,
        residual: f64::INFINITY,
        ..Default::default()
    };
    if root && ctl.monitor {
        if friction_bound.is_some() {
            println!("  {name}   it   rel. change (5.6)   ||Bu - phi||      contact  stick   slip");
        } else {
            println!("  {name}   it   rel. change (4.16)  ||Bu - phi||      contact");
        }
    }
    let mut k = 0;
    while k < ctl.max_it {
        // Step 1: the elasticity subproblem (4.5)/(5.3); only the right-hand side changes.
        {
            let _e = events.rhs.begin();
            state.rhs.copy_from(&problem.rhs0)?;
            let (phi_n, lambda_n, phi_t, lambda_t) =
                (&state.phi_n, &state.lambda_n, &state.phi_t, &state.lambda_t);
            state.rhs.write(|b| {
                for i in 0..nc {
                    let w = cs.w[i];
                    let sn = w * (r * phi_n[i] - lambda_n[i]);
                    let base = cs.node[i] * d;
                    for c in 0..d {
                        if !problem.is_dirichlet[base + c] {
                            let mut v = sn * n[c];
                            if problem.tangential {
                                v += w * (r * phi_t[i * d + c] - lambda_t[i * d + c]);
                            }
                            b[base + c] += v;
                        }
                    }
                }
            })?;
        }
        if problem.adaptive_inner && k == 0 {
            // Inexact Uzawa: each solve starts from u^{k-1} and reduces the
            // residual b - A u^{k-1}, i.e. the change this iteration brings,
            // by the factor below (-ksp_converged_use_initial_residual_norm):
            // loose in absolute terms early, tight at the end as the changes
            // shrink with (4.16).
            problem.ksp.set_rtol(ctl.inner_rtol_factor)?;
        }
        let its = {
            let _e = events.solve.begin();
            problem.ksp.solve(&state.rhs, &state.u)?
        };
        state.inner_iterations.push(its);
        // Steps 2 and 3: projections (4.15), (5.5) and the multiplier update (4.4), pointwise.
        let e = events.projection.begin();
        let st = &mut *state;
        let sums = st.u.read(|uv| {
            let mut s = [0.0f64; 9];
            // max tension, max |stress|, max |u_n|
            let mut ext = [0.0f64; 3];
            // ||u^k - u^{k-1}||^2 and ||u^k||^2 with lumped mass
            for (j, m) in problem.lumped_mass.iter().enumerate() {
                for c in 0..d {
                    let x = uv[j * d + c];
                    let dx = x - st.u_prev[j * d + c];
                    s[0] += m * dx * dx;
                    s[1] += m * x * x;
                }
            }
            st.u_prev.copy_from_slice(uv);
            for i in 0..nc {
                let base = cs.node[i] * d;
                let w = cs.w[i];
                let uni: f64 = (0..d).map(|c| uv[base + c] * n[c]).sum();
                // -sigma_n(u^k) by (4.7), before the update
                st.stress_n[i] = st.lambda_n[i] + r * (uni - st.phi_n[i]);
                ext[0] = ext[0].max(-st.stress_n[i]);
                ext[1] = ext[1].max(st.stress_n[i].abs());
                ext[2] = ext[2].max(uni.abs());
                let (phi_new, lambda_new, contact) =
                    project_normal(uni, st.lambda_n[i], cs.g[i], r, rho);
                s[2] += w * (phi_new - st.phi_n[i]).powi(2);
                s[3] += w * phi_new * phi_new;
                s[4] += w * (uni - phi_new).powi(2);
                st.un[i] = uni;
                st.phi_n[i] = phi_new;
                st.lambda_n[i] = lambda_new;
                s[8] += w * lambda_new * lambda_new;
                st.in_contact[i] = contact;
                let mut ut = [0.0; 3];
                for c in 0..d {
                    ut[c] = uv[base + c] - uni * n[c];
                    st.ut[i * d + c] = ut[c];
                }
                if let Some(bound) = friction_bound {
                    let t = i * d..(i + 1) * d;
                    for c in 0..d {
                        st.stress_t[i * d + c] =
                            st.lambda_t[i * d + c] + r * (ut[c] - st.phi_t[i * d + c]);
                    }
                    let mut phi_t = [0.0; 3];
                    let mut lam_t = [0.0; 3];
                    let slip = project_tangential(
                        &ut[..d],
                        &st.lambda_t[t.clone()],
                        bound[i],
                        r,
                        rho,
                        &mut phi_t[..d],
                        &mut lam_t[..d],
                    );
                    for c in 0..d {
                        let old = st.phi_t[i * d + c];
                        s[2] += w * (phi_t[c] - old).powi(2);
                        s[3] += w * phi_t[c] * phi_t[c];
                        s[4] += w * (ut[c] - phi_t[c]).powi(2);
                    }
                    st.phi_t[t.clone()].copy_from_slice(&phi_t[..d]);
                    st.lambda_t[t].copy_from_slice(&lam_t[..d]);
                    s[8] += w * lam_t[..d].iter().map(|v| v * v).sum::<f64>();
                    st.slip[i] = slip;
                    if contact {
                        if slip {
                            s[7] += 1.0;
                        } else {
                            s[6] += 1.0;
                        }
                    }
                }
                if contact {
                    s[5] += 1.0;
                }
            }
            (s, ext)
        })?;
        drop(e);
        let (sums, ext) = sums;
        let [tension, largest, un_max] = super::allreduce_max_n(world, ext);
        out.tension = if largest > 0.0 {
            tension / largest
        } else {
            0.0
        };
        state.peak_stress = state.peak_stress.max(largest);
        let [du2, u2, dphi2, phi2, res2, ncontact, nstick, nslip, lam2] =
            allreduce_sum(world, sums);
        // The dual residual r ||phi^k - phi^{k-1}||, relative to ||lambda^{k+1}||:
        // the gap between the multiplier and the stress of u^k (4.7).
        out.dual = if lam2 > 0.0 {
            r * (dphi2 / lam2).sqrt()
        } else {
            0.0
        };
        out.criterion = if u2 + phi2 > 0.0 {
            ((du2 + dphi2) / (u2 + phi2)).sqrt()
        } else {
            0.0
        };
        out.residual = res2.sqrt();
        state.history.push([out.criterion, out.residual]);
        out.contact = ncontact as usize;
        out.stick = nstick as usize;
        out.slip = nslip as usize;
        if root && ctl.monitor {
            let inner = if problem.iterative {
                format!("   inner its {its}")
            } else {
                String::new()
            };
            if friction_bound.is_some() {
                println!(
                    "  {name} {:5}   {:.6e}         {:.6e}   {:7} {:6} {:6}{inner}",
                    k, out.criterion, out.residual, out.contact, out.stick, out.slip
                );
            } else {
                println!(
                    "  {name} {:5}   {:.6e}         {:.6e}   {}{inner}  dual {:.3e}",
                    k, out.criterion, out.residual, out.contact, out.dual
                );
            }
        }
        k += 1;
        out.iterations = k;
        if !out.criterion.is_finite() || !out.residual.is_finite() {
            return Err(Error::NotConverged(format!(
                "{name} produced a non-finite iterate at iteration {k}"
            )));
        }
        // The paper's tests (4.16)/(5.6) and the constraint residual, plus the
        // dual residual: for a large r the change (4.16) stalls while the
        // multipliers are still far from converged (sublinear regime, section
        // 7.1.1); the dual residual, the gap between lambda^{k+1} and the
        // stress of u^k, does not.
        // A body that only the augmentation springs hold: where nodes touch,
        // the stress of u^k turns tensile; where none does, an open node's
        // stress is the lag r (u_n^k - u_n^{k-1}), which dies out with the
        // iteration when the body is held and stays (carrying the load) when
        // it drifts: then the stresses must have decayed by eps (or to
        // round-off), their sign being noise. Likewise the dual residual,
        // relative to a multiplier that is itself noise, means nothing there.
        let (held, dual_ok) = if ncontact > 0.0 {
            (out.tension < ctl.tension_tol, out.dual < ctl.dual_rtol)
        } else {
            let decayed = largest <= ctl.rtol * state.peak_stress || largest <= 1e-13 * r * un_max;
            (decayed, true)
        };
        if k >= 2 && out.criterion < ctl.rtol && out.residual < ctl.residual_tol && dual_ok && held
        {
            out.converged = true;
            break;
        }
    }
    Ok(out)
}
