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
//! until the stopping test holds ([`super::stopping`]: the paper's (4.16)/(5.6)
//! or, by default, a bound on the error of lambda).
//!
//! **The map on the contact surface.** Steps 2-3 read `lambda^k` and `u^k`
//! only through `z = lambda^k + r B u^k`: with rho = r, `(phi^k, lambda^{k+1})`
//! is the pointwise projection of z, and the next z is
//! `T(z) = lambda + r B K_r^{-1} (f + B^T W (r phi - lambda))` with
//! `(phi, lambda)` the projection of z. Plain UBR is `z <- T(z)`, exactly
//! the paper's iterates. With `-ubr_anderson M` (M > 0, the default 10) the
//! iteration is Anderson-accelerated on z ([`super::anderson`]); with M = 0
//! it is the paper's, arithmetic unchanged, with any step rho.
//!
//! The reported contact stresses are `-sigma(u^k)` on Gamma_c from (4.7):
//! `lambda^k + r (B u^k - phi^{k-1})`, the stresses in equilibrium with the
//! returned displacement (the contact force balances the load to round-off
//! at any iteration); they differ from `lambda^{k+1}` by the map's residual,
//! which the accuracy test bounds.
//!
//! Norms: lumped mass on Omega, nodal weights w_i on Gamma_c. Every stopping
//! decision is taken on globally reduced sums, so all ranks agree.

use super::anderson::Anderson;
use super::deferred::{Candidate, Deferred, Resolution};
use super::stopping::{paper_change, Accuracy, Progress, StopRule, STALL_ITS};
use super::surface::{Surface, UbrState};
use super::{mass_norms, Problem};
use crate::comm::{allreduce_max, allreduce_max_n, allreduce_sum};
use crate::contact::{project_normal, project_normal_z, project_tangential, project_tangential_z};
use crate::error::Error;
use mpi::collective::SystemOperation;
use mpi::traits::*;

/// A converged contact stress is compressive: tension above this fraction of
/// the largest stress means the augmentation springs r carry load, i.e. a
/// rigid motion of the body is free (it drifts away or slides off).
pub const TENSION_TOL: f64 = 1e-3;

/// Evaluations with nothing in contact, every candidate moving away from
/// the obstacle and the stresses not decaying, after which the body is
/// declared pulled off the obstacle (see [`ubr`]).
const DRIFT_ITS: usize = 100;

/// The tangential part of P is relative to `max |lambda_t|`, but at least
/// this fraction of `max |lambda_n|` (a friction force that is nil to
/// round-off has no relative accuracy).
const TANGENTIAL_FLOOR: f64 = 1e-6;

/// The inner tolerance factor is tightened tenfold at each rejected
/// Anderson step, down to this (iterative solvers).
const INNER_FACTOR_MIN: f64 = 1e-3;

/// Tolerances and caps of one UBR run.
#[derive(Clone, Copy, Debug)]
pub struct UbrControl {
    /// The multiplier step rho of (4.4) (None: rho = r).
    pub rho: Option<f64>,
    pub stop: StopRule,
    /// The paper's eps of (4.16)/(5.6), and the constraint-residual tolerance.
    pub rtol: f64,
    pub residual_tol: f64,
    /// Tolerance on the dual residual `r ||phi^k - phi^{k-1}|| / ||lambda^{k+1}||` (paper mode).
    pub dual_rtol: f64,
    /// Largest tensile contact stress accepted at convergence, relative to the
    /// largest stress ([`TENSION_TOL`]; CF-FP loosens it with eps_f^m).
    pub tension_tol: f64,
    /// The accuracy test's tolerance on lambda.
    pub lambda_rtol: f64,
    pub max_it: usize,
    pub monitor: bool,
    /// Inexact Uzawa: inner KSP rtol relative to the initial residual b - A u^{k-1}.
    pub inner_rtol_factor: f64,
    /// Anderson memory M (0: the paper's plain iteration).
    pub anderson: usize,
    /// A candidate displaced by more than this has drifted away: the body
    /// moves without bound (ten times the size of the bodies that contact
    /// alone holds, and their largest gap; infinite where none is).
    pub drift_limit: f64,
    /// The trial r0 of `-ubr_r auto` where the user's r is more than
    /// [`R_FAR`] times away from it (a likely cause of a failure).
    pub r_far: Option<f64>,
}

/// A user's r this many times above or below the trial r0 is far outside
/// the range `-ubr_r auto` chooses from (its estimates lie within a factor
/// of about 30 of r0 on every scene measured).
pub const R_FAR: f64 = 100.0;

/// Words on an r far from the trial r0.
fn r_far_words(r: f64, r0: f64) -> String {
    format!(
        "r = {r:.3e} (-ubr_r) is {:.1e} times the trial r0 = {r0:.3e} from which -ubr_r auto chooses (within a factor of about 30 of it): far outside the range where UBR converges in a reasonable number of iterations; use -ubr_r auto, or an r near r0",
        r / r0
    )
}

/// What one UBR run did.
#[derive(Clone, Debug, Default)]
pub struct UbrOutcome {
    pub iterations: usize,
    pub converged: bool,
    /// The paper's change (4.16)/(5.6) at the last iteration, and the
    /// constraint residual.
    pub criterion: f64,
    pub residual: f64,
    /// Dual residual `r ||phi^k - phi^{k-1}|| / ||lambda^{k+1}||`.
    pub dual: f64,
    /// Largest tensile contact stress `max (-lambda_n)^+` relative to the
    /// largest `|lambda_n|` (stresses of u^k): near 1 when the augmentation
    /// springs hold a body that nothing else holds.
    pub tension: f64,
    /// The accuracy test: residual P, amplification K, estimate P K.
    pub p: f64,
    pub k: f64,
    pub error_estimate: f64,
    /// Global counts from the last projection.
    pub contact: usize,
    pub stick: usize,
    pub slip: usize,
    /// Anderson: evaluations at an extrapolated point, and rejections.
    pub anderson_steps: usize,
    pub anderson_rejected: usize,
    /// Why the run stopped without converging (None: converged).
    pub failure: Option<String>,
}

/// The inner-product weights of z: w_i on every entry of candidate i.
fn z_weights(surface: &Surface) -> Vec<f64> {
    let (cs, d) = (surface.cs, surface.dim);
    let mut w = cs.w.clone();
    if surface.tangential {
        for &wi in &cs.w {
            w.extend(std::iter::repeat_n(wi, d));
        }
    }
    w
}

/// Sums reduced over the ranks after each projection.
#[derive(Clone, Copy, Default)]
struct Sums {
    du2: f64,
    u2: f64,
    dphi2: f64,
    phi2: f64,
    res2: f64,
    contact: f64,
    stick: f64,
    slip: f64,
    lam2: f64,
    /// `||T(z) - z||_W^2`
    f2: f64,
    /// Statuses changed since the previous evaluation.
    changes: f64,
    /// The contact nodes' part of `||u^k - u^{k-1}||^2` (condensed solves).
    dc2: f64,
}

impl Sums {
    fn to_array(self) -> [f64; 12] {
        [
            self.du2,
            self.u2,
            self.dphi2,
            self.phi2,
            self.res2,
            self.contact,
            self.stick,
            self.slip,
            self.lam2,
            self.f2,
            self.changes,
            self.dc2,
        ]
    }
    fn from_array(a: [f64; 12]) -> Sums {
        Sums {
            du2: a[0],
            u2: a[1],
            dphi2: a[2],
            phi2: a[3],
            res2: a[4],
            contact: a[5],
            stick: a[6],
            slip: a[7],
            lam2: a[8],
            f2: a[9],
            changes: a[10],
            dc2: a[11],
        }
    }
}

/// Maxima reduced over the ranks after each projection.
#[derive(Clone, Copy, Default)]
struct Maxima {
    /// Largest tensile stress, largest |stress_n|, largest |u_n|.
    tension: f64,
    stress: f64,
    un: f64,
    /// Accuracy test: largest residual `|stress - lambda|` (normal,
    /// tangential) and largest multiplier (normal, tangential).
    f_n: f64,
    f_t: f64,
    lam_n: f64,
    lam_t: f64,
    /// Largest change of u_n (negative: every candidate moved away).
    dun: f64,
    /// Largest displacement component of a candidate.
    umax: f64,
}

impl Maxima {
    fn to_array(self) -> [f64; 9] {
        [
            self.tension,
            self.stress,
            self.un,
            self.f_n,
            self.f_t,
            self.lam_n,
            self.lam_t,
            self.dun,
            self.umax,
        ]
    }
    fn from_array(a: [f64; 9]) -> Maxima {
        Maxima {
            tension: a[0],
            stress: a[1],
            un: a[2],
            f_n: a[3],
            f_t: a[4],
            lam_n: a[5],
            lam_t: a[6],
            dun: a[7],
            umax: a[8],
        }
    }
}

/// Runs UBR-C (`friction_bound` = None, the problem assembled without the
/// tangential term) or UBR-TF (`Some(s)`, one bound per candidate) from
/// `state` (the paper's initialization, or a previous run's iterate).
#[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
pub fn ubr<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    friction_bound: Option<&[f64]>,
    ctl: &UbrControl,
    events: &crate::petsc::Events,
) -> Result<UbrOutcome, Error> {
    let d = problem.dim;
    let Problem {
        contact: cs,
        lin,
        lumped_mass,
        dirichlet,
        tangential,
        ..
    } = problem;
    let surface = Surface {
        cs,
        dim: d,
        tangential: *tangential,
        dirichlet: &dirichlet.contact,
    };
    let nc = cs.len();
    let r = lin.r();
    let rho = ctl.rho.unwrap_or(r);
    let root = world.rank() == 0;
    let name = if friction_bound.is_some() {
        "UBR-TF"
    } else {
        "UBR-C"
    };
    assert_eq!(friction_bound.is_some(), surface.tangential);
    let paper = ctl.stop == StopRule::Paper;
    let nt = if surface.tangential { nc * d } else { 0 };
    let mut out = UbrOutcome {
        criterion: f64::NAN,
        residual: f64::INFINITY,
        // Unknown until an evaluation: null in the report.
        error_estimate: f64::NAN,
        p: f64::NAN,
        k: f64::NAN,
        ..Default::default()
    };
    if root && ctl.monitor {
        let test = if paper {
            "rel. change (4.16) ||Bu - phi||    "
        } else {
            "error estimate     residual P   K  "
        };
        if friction_bound.is_some() {
            println!("  {name}   it   {test} contact  stick   slip");
        } else {
            println!("  {name}   it   {test} contact");
        }
    }
    let mut aa = (ctl.anderson > 0).then(|| Anderson::new(ctl.anderson, z_weights(&surface)));
    // Anderson: the point whose projection is the current (phi, lambda)
    // (None before the first evaluation, which starts from the state).
    let mut z_in: Option<Vec<f64>> = None;
    let mut z_out = vec![0.0; nc + nt];
    let mut next = vec![0.0; nc + nt];
    let mut c = vec![0.0; nc * d];
    let mut c_prev = vec![0.0; nc * d];
    let mut uc = vec![0.0; nc * d];
    let mut uc_prev = vec![0.0; nc * d];
    let mut acc = Accuracy::new(ctl.lambda_rtol);
    let mut progress = Progress::default();
    // The paper's test on the condensed back-end: candidates decided later.
    // Their decision leaves the whole displacement of the chosen one in u.
    let mut deferred = (paper && lin.is_condensed()).then(|| Deferred::new(lumped_mass.len() * d));
    // u^{k-1} of a full solve, for the change (4.16)/(5.6).
    let mut u_prev = vec![0.0; lumped_mass.len() * d];
    state.u.read(|u| u_prev.copy_from_slice(u))?;
    // Evaluations in a row with nothing in contact, everything moving away
    // and the stresses not decaying; the stress scale at the first of them.
    let mut drifting = 0usize;
    let mut drift_stress = 0.0f64;
    let cold = std::mem::replace(&mut state.cold, false);
    let was_condensed = lin.is_condensed();
    let mut last = Sums::default();
    // A zero bound everywhere (a frictionless solve through UBR-TF).
    let no_friction = friction_bound
        .is_some_and(|b| allreduce_max(world, b.iter().fold(0.0, |a: f64, &x| a.max(x))) == 0.0);
    let mut inner_factor = ctl.inner_rtol_factor;
    let mut k = 0;
    while k < ctl.max_it {
        std::mem::swap(&mut c, &mut c_prev);
        std::mem::swap(&mut uc, &mut uc_prev);
        let st = &mut state.surface;
        // Step 1: the elasticity subproblem (4.5)/(5.3); only the right-hand
        // side changes, by c = B^T W (r phi^{k-1} - lambda^k) on the contact nodes.
        {
            let _e = events.rhs.begin();
            surface.load(
                |i| r * st.phi_n[i] - st.lambda_n[i],
                |i, cc| r * st.phi_t[i * d + cc] - st.lambda_t[i * d + cc],
                &mut c,
            );
        }
        if lin.iterative && lin.adaptive_inner {
            // Inexact Uzawa: each solve starts from u^{k-1} and reduces the
            // residual b - A u^{k-1} (the change this iteration brings) by
            // the factor.
            lin.set_inner_rtol(inner_factor)?;
        }
        let its = {
            let _e = events.solve.begin();
            lin.solve(&surface, &c, &mut uc, &state.u)?
        };
        state.inner_iterations.push(its);
        let mut sums = Sums::default();
        let mut ext = Maxima {
            dun: f64::NEG_INFINITY,
            ..Default::default()
        };
        // The paper's change of u: a full solve knows it now; a condensed
        // one, its part at the contact nodes (the candidates decide the rest).
        if lin.is_condensed() {
            for (i, &v) in cs.node.iter().enumerate() {
                let m = lumped_mass[v];
                for cc in 0..d {
                    sums.dc2 += m * (uc[i * d + cc] - uc_prev[i * d + cc]).powi(2);
                }
            }
        } else {
            state.u.read(|u| {
                (sums.du2, sums.u2) = mass_norms(lumped_mass, d, u, &u_prev);
                u_prev.copy_from_slice(u);
            })?;
        }
        // Steps 2 and 3: projections (4.15), (5.5) and the multiplier update
        // (4.4), pointwise.
        let e = events.projection.begin();
        let st = &mut state.surface;
        for i in 0..nc {
            let w = cs.w[i];
            let uni = surface.normal(&uc, i);
            // -sigma_n(u^k) by (4.7), before the update
            let stress = st.lambda_n[i] + r * (uni - st.phi_n[i]);
            st.stress_n[i] = stress;
            ext.tension = ext.tension.max(-stress);
            ext.stress = ext.stress.max(stress.abs());
            ext.un = ext.un.max(uni.abs());
            for cc in 0..d {
                ext.umax = ext.umax.max(uc[i * d + cc].abs());
            }
            ext.dun = ext.dun.max(uni - st.un[i]);
            let f = stress - st.lambda_n[i];
            ext.f_n = ext.f_n.max(f.abs());
            sums.f2 += w * f * f;
            z_out[i] = st.lambda_n[i] + r * uni;
            let (phi_new, lambda_new, contact) =
                project_normal(uni, st.lambda_n[i], cs.g[i], r, rho);
            ext.lam_n = ext.lam_n.max(st.lambda_n[i].abs()).max(lambda_new.abs());
            sums.dphi2 += w * (phi_new - st.phi_n[i]).powi(2);
            sums.phi2 += w * phi_new * phi_new;
            sums.res2 += w * (uni - phi_new).powi(2);
            sums.lam2 += w * lambda_new * lambda_new;
            st.un[i] = uni;
            st.phi_n[i] = phi_new;
            st.lambda_n[i] = lambda_new;
            if contact != st.in_contact[i] {
                sums.changes += 1.0;
            }
            st.in_contact[i] = contact;
            let mut ut = [0.0; 3];
            surface.tangential_part(&uc, i, uni, &mut ut);
            st.ut[i * d..(i + 1) * d].copy_from_slice(&ut[..d]);
            if let Some(bound) = friction_bound {
                let t = i * d..(i + 1) * d;
                let mut ft = 0.0;
                let mut lt = 0.0f64;
                for cc in 0..d {
                    let stress = st.lambda_t[i * d + cc] + r * (ut[cc] - st.phi_t[i * d + cc]);
                    st.stress_t[i * d + cc] = stress;
                    let f = stress - st.lambda_t[i * d + cc];
                    ft += f * f;
                    lt += st.lambda_t[i * d + cc].powi(2);
                    z_out[nc + i * d + cc] = st.lambda_t[i * d + cc] + r * ut[cc];
                }
                sums.f2 += w * ft;
                ext.f_t = ext.f_t.max(ft.sqrt());
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
                for cc in 0..d {
                    let old = st.phi_t[i * d + cc];
                    sums.dphi2 += w * (phi_t[cc] - old).powi(2);
                    sums.phi2 += w * phi_t[cc] * phi_t[cc];
                    sums.res2 += w * (ut[cc] - phi_t[cc]).powi(2);
                }
                let ln = lam_t[..d].iter().map(|v| v * v).sum::<f64>();
                ext.lam_t = ext.lam_t.max(lt.sqrt()).max(ln.sqrt());
                st.phi_t[t.clone()].copy_from_slice(&phi_t[..d]);
                st.lambda_t[t].copy_from_slice(&lam_t[..d]);
                sums.lam2 += w * ln;
                if slip != st.slip[i] && contact {
                    sums.changes += 1.0;
                }
                st.slip[i] = slip;
                if contact {
                    if slip {
                        sums.slip += 1.0;
                    } else {
                        sums.stick += 1.0;
                    }
                }
            }
            if contact {
                sums.contact += 1.0;
            }
        }
        drop(e);
        let ext = Maxima::from_array(allreduce_max_n(world, ext.to_array()));
        let sums = Sums::from_array(allreduce_sum(world, sums.to_array()));
        last = sums;
        out.tension = if ext.stress > 0.0 {
            ext.tension / ext.stress
        } else {
            0.0
        };
        state.peak_stress = state.peak_stress.max(ext.stress);
        if cold && k == 0 {
            state.stress_scale = ext.stress;
        }
        // The dual residual r ||phi^k - phi^{k-1}||, relative to ||lambda^{k+1}||:
        // the gap between the multiplier and the stress of u^k (4.7).
        out.dual = if sums.lam2 > 0.0 {
            r * (sums.dphi2 / sums.lam2).sqrt()
        } else {
            0.0
        };
        out.criterion = if lin.is_condensed() {
            f64::NAN // decided with the candidates
        } else {
            paper_change(sums.du2, sums.dphi2, sums.u2, sums.phi2)
        };
        out.residual = sums.res2.sqrt();
        out.contact = sums.contact as usize;
        out.stick = sums.stick as usize;
        out.slip = sums.slip as usize;
        // The accuracy test's residual P: the map's residual |stress - lambda|
        // (which also bounds the change of lambda by one plain step), normal
        // and tangential parts each relative to their multiplier's max norm;
        // with nothing in contact, relative to the stress of the first
        // evaluation (the load's scale).
        let scale_n = if ext.lam_n > 0.0 {
            ext.lam_n
        } else {
            state.stress_scale
        };
        let p_n = if ext.f_n == 0.0 {
            0.0
        } else {
            ext.f_n / scale_n
        };
        let p_t = if ext.f_t == 0.0 {
            0.0
        } else if no_friction {
            ext.f_t / scale_n // s = 0: lambda_t = 0, its stress relative to the pressure
        } else {
            ext.f_t / ext.lam_t.max(TANGENTIAL_FLOOR * scale_n)
        };
        let p = p_n.max(p_t);
        // Anderson: the next point (the first evaluation only starts it).
        let mut amplification = None;
        if let Some(aa) = aa.as_mut() {
            if let Some(zi) = z_in.as_mut() {
                let step = aa.step(
                    |s, rcv| world.all_reduce_into(s, rcv, SystemOperation::sum()),
                    zi,
                    &z_out,
                    sums.f2.sqrt(),
                    &mut next,
                );
                amplification = step.amplification;
                if step.rejected && inner_factor > INNER_FACTOR_MIN {
                    // The inexact solves' errors spoil the secant pairs
                    // (tube2d_tresca with CG+GAMG: 81 rejections and 1759
                    // iterations at 0.1; at 0.01 none and 115): solve the
                    // rest more accurately.
                    inner_factor = (inner_factor * 0.1).max(INNER_FACTOR_MIN);
                }
                std::mem::swap(zi, &mut next);
            } else {
                z_in = Some(z_out.clone());
            }
            out.anderson_steps = aa.steps;
            out.anderson_rejected = aa.rejected;
        }
        let est = acc.record(
            p,
            sums.changes as usize,
            aa.is_some().then_some(amplification),
        );
        out.p = acc.residual;
        out.k = acc.amplification;
        out.error_estimate = est;
        state.history.push([
            out.criterion,
            out.residual,
            if paper { f64::NAN } else { est },
        ]);
        if root && ctl.monitor {
            let inner = if lin.iterative {
                format!("   inner its {its}")
            } else {
                String::new()
            };
            let test = if paper {
                format!("{:.6e}       {:.6e}", out.criterion, out.residual)
            } else {
                format!("{:.3e}   {:.3e}   {:.1e}", est, p, out.k)
            };
            if friction_bound.is_some() {
                println!(
                    "  {name} {:5}   {test}   {:7} {:6} {:6}{inner}",
                    k, out.contact, out.stick, out.slip
                );
            } else {
                println!("  {name} {:5}   {test}   {}{inner}", k, out.contact);
            }
        } else {
            crate::progress::tick(|| {
                let test = if paper {
                    format!(
                        "rel. change (4.16) {:.2e} (target {:.0e})",
                        out.criterion, ctl.rtol
                    )
                } else if est.is_finite() {
                    format!("estimated error {est:.2e} (target {:.0e})", ctl.lambda_rtol)
                } else {
                    format!("error not yet estimated (target {:.0e})", ctl.lambda_rtol)
                };
                format!(
                    "{name} iteration {k}: {test}, {} nodes in contact",
                    out.contact
                )
            });
        }
        k += 1;
        out.iterations = k;
        if !out.residual.is_finite() || !p.is_finite() {
            return Err(Error::NotConverged(format!(
                "{name} produced a non-finite iterate at iteration {k}"
            )));
        }
        // A body that nothing but the contact holds along n, pulled away:
        // nothing touches, every candidate moves away from the obstacle,
        // and the stresses (then the iteration's lag r (u_n^k - u_n^{k-1}))
        // stay instead of dying out.
        if sums.contact == 0.0 && ext.dun < 0.0 && ext.stress > 0.0 {
            if drifting == 0 {
                drift_stress = ext.stress;
            }
            drifting += 1;
            if ext.stress < 0.999 * drift_stress {
                drifting = 0;
            }
        } else {
            drifting = 0;
        }
        if drifting >= DRIFT_ITS {
            return Err(Error::IllPosed(format!(
                "nothing holds the body along the contact direction: no node touches the obstacle and the body moves away from it by the same step every iteration ({DRIFT_ITS} iterations of {name}), so the loads pull it off the obstacle; check the signs of the loads, the contact direction (-contact_direction points from the body toward the obstacle) and the obstacle's position"
            )));
        }
        // Any body that contact alone holds, moving without bound: no
        // contact state holds the loads (a Tresca bound too small for the
        // tangential load, a pressure that friction cannot use).
        if ext.umax > ctl.drift_limit {
            if let Some(r0) = ctl.r_far {
                return Err(Error::NotConverged(format!(
                    "{name}: the iterates move without bound (a contact node has moved {:.3e} after {k} iterations): {}",
                    ext.umax,
                    r_far_words(r, r0)
                )));
            }
            let what = if sums.contact == 0.0 {
                "no node touches the obstacle".to_string()
            } else if friction_bound.is_some() && sums.stick == 0.0 && !no_friction {
                format!(
                    "every one of the {} contact nodes slips: friction cannot hold the tangential load with the pressures this body develops, and the body slides",
                    sums.contact
                )
            } else {
                format!("{} nodes touch the obstacle", sums.contact)
            };
            return Err(Error::NotConverged(format!(
                "{name}: the body moves without bound: after {k} iterations a contact node has moved {:.3e}, ten times the size and gap of the bodies that only contact holds ({:.3e}); {what}; no contact state found holds the loads (lower the loads, raise the friction, or add a Dirichlet condition; where another method finds an answer, the iteration is at fault: try -ubr_anderson 0)",
                ext.umax,
                ctl.drift_limit / 10.0
            )));
        }
        let stalled = progress.record(p, sums.changes as usize);
        // Held-body tests: where nodes touch, the stress of u^k must not turn
        // tensile; where none does, an open node's stress is the lag
        // r (u_n^k - u_n^{k-1}), which dies out with the iteration when the
        // body is held: the stresses must then have decayed by eps (or to
        // round-off), their sign being noise. The dual residual, relative to
        // a multiplier that is itself noise, means nothing there.
        let (held, dual_ok) = if sums.contact > 0.0 {
            (out.tension < ctl.tension_tol, out.dual < ctl.dual_rtol)
        } else {
            let decayed =
                ext.stress <= ctl.rtol * state.peak_stress || ext.stress <= 1e-13 * r * ext.un;
            (decayed, true)
        };
        let last = k >= ctl.max_it || stalled;
        if !paper {
            if k >= 2 && acc.satisfied() {
                out.converged = true;
                break;
            }
        } else if let Some(def) = deferred.as_mut() {
            // The change (4.16)/(5.6) needs the whole displacement: decided
            // for the evaluations where it is the last test open (unless it
            // surely fails), a batch at a time, going back to the first that
            // passes, and for the last.
            let others_ok = k >= 2 && out.residual < ctl.residual_tol && dual_ok && held;
            let decide = if others_ok || last {
                def.offer(
                    Candidate {
                        iteration: k,
                        evaluation: state.history.len(),
                        inner_len: state.inner_iterations.len(),
                        others_ok,
                        dphi2: sums.dphi2,
                        phi2: sums.phi2,
                        dc2: sums.dc2,
                        c: c.clone(),
                        c_prev: c_prev.clone(),
                        uc: uc.clone(),
                        uc_prev: uc_prev.clone(),
                        snap: state.surface.clone(),
                        peak_stress: state.peak_stress,
                        change: f64::NAN,
                    },
                    ctl.rtol,
                    last,
                )
            } else {
                false
            };
            if decide {
                let found = {
                    let _e = events.solve.begin();
                    def.decide(world, lin, &surface, lumped_mass, &state.u, ctl.rtol)?
                };
                if let Resolution::Inconsistent(why) = &found {
                    if root {
                        eprintln!("warning: {name}: {why} Going on without condensation.");
                    }
                    lin.uncondense();
                    // u^{k-1} and u^k by full solves, for this iteration's change.
                    let mut scratch = vec![0.0; nc * d];
                    lin.solve(&surface, &c_prev, &mut scratch, &state.u)?;
                    state.u.read(|u| u_prev.copy_from_slice(u))?;
                    lin.solve(&surface, &c, &mut scratch, &state.u)?;
                    let (du2, u2) = state.u.read(|u| {
                        let s = mass_norms(lumped_mass, d, u, &u_prev);
                        u_prev.copy_from_slice(u);
                        s
                    })?;
                    let [du2, u2] = allreduce_sum(world, [du2, u2]);
                    out.criterion = paper_change(du2, sums.dphi2, u2, sums.phi2);
                    def.pending.clear();
                    deferred = None;
                    if others_ok && out.criterion < ctl.rtol {
                        out.converged = true;
                        break;
                    }
                } else {
                    for cand in &def.pending {
                        state.history[cand.evaluation - 1][0] = cand.change;
                    }
                    if let Resolution::Converged(i) = found {
                        let cand = def.pending.swap_remove(i);
                        state.history.truncate(cand.evaluation);
                        state.inner_iterations.truncate(cand.inner_len);
                        state.surface = cand.snap;
                        state.peak_stress = cand.peak_stress;
                        out.iterations = cand.iteration;
                        out.criterion = cand.change;
                        out.converged = true;
                        break; // u is the candidate's
                    }
                    out.criterion = def.pending.last().map_or(f64::NAN, |c| c.change);
                    def.pending.clear();
                }
            }
        } else {
            let others_ok = k >= 2 && out.residual < ctl.residual_tol && dual_ok && held;
            if others_ok && out.criterion < ctl.rtol {
                out.converged = true;
                break;
            }
        }
        if stalled {
            break;
        }
        if let Some(zi) = z_in.as_ref().filter(|_| aa.is_some()) {
            // The next (phi, lambda): the projection of the new z (rho = r).
            let st = &mut state.surface;
            for i in 0..nc {
                let (phi, lambda, _) = project_normal_z(zi[i], cs.g[i], r);
                st.phi_n[i] = phi;
                st.lambda_n[i] = lambda;
                if let Some(bound) = friction_bound {
                    let t = i * d..(i + 1) * d;
                    project_tangential_z(
                        &zi[nc + i * d..nc + (i + 1) * d],
                        bound[i],
                        r,
                        &mut st.phi_t[t.clone()],
                        &mut st.lambda_t[t],
                    );
                }
            }
        }
    }
    // The whole displacement of the last evaluation: a condensed run knows
    // it at the contact nodes only (the paper's candidates leave theirs).
    if lin.is_condensed() && !paper {
        // The paper's change (4.16)/(5.6) is reported in every mode: u^{k-1}
        // and u^k from one solve with two right-hand sides.
        // (From u_C alone: the equilibrium check of the answer then tests
        // the Schur solves too.)
        let x = lin.displacements(&surface, &[(&c_prev, &uc_prev), (&c, &uc)], true)?;
        let nloc = u_prev.len();
        let (du2, u2) = x.read(|xx| {
            state
                .u
                .write(|u| u.copy_from_slice(&xx[nloc..2 * nloc]))
                .map(|_| mass_norms(lumped_mass, d, &xx[nloc..], &xx[..nloc]))
        })??;
        let [du2, u2] = allreduce_sum(world, [du2, u2]);
        out.criterion = paper_change(du2, last.dphi2, u2, last.phi2);
    }
    if was_condensed {
        // A condensed solve knew u at the Schur components only: u_t of the
        // candidates from the whole displacement now known.
        let st = &mut state.surface;
        state.u.read(|u| {
            for (i, &v) in cs.node.iter().enumerate() {
                let un = surface.normal(&u[v * d..(v + 1) * d], 0);
                let mut ut = [0.0; 3];
                surface.tangential_part(&u[v * d..(v + 1) * d], 0, un, &mut ut);
                st.ut[i * d..(i + 1) * d].copy_from_slice(&ut[..d]);
            }
        })?;
    }
    if !out.converged {
        out.failure = Some(if progress.since >= STALL_ITS {
            let friction = friction_bound.is_some() && !no_friction;
            stalled(name, ctl, &out, r, &acc, &progress, friction)
        } else {
            failure(name, ctl, &out, r, &acc)
        });
    }
    if root && ctl.monitor && aa.is_some() {
        println!(
            "  {name}: Anderson: {} of {} evaluations at extrapolated points, {} rejected by the safeguard",
            out.anderson_steps, out.iterations, out.anderson_rejected
        );
    }
    Ok(out)
}

/// The message of a run stopped because it made no progress: what it
/// stalled at, and the likely cause.
fn stalled(
    name: &str,
    ctl: &UbrControl,
    out: &UbrOutcome,
    r: f64,
    acc: &Accuracy,
    progress: &Progress,
    friction: bool,
) -> String {
    let its = out.iterations;
    let target = if ctl.stop == StopRule::Paper {
        format!(
            "relative change (4.16) {:.3e} (target -ubr_rtol {:.1e})",
            out.criterion, ctl.rtol
        )
    } else {
        format!(
            "error estimate of lambda {:.3e} (target -ubr_lambda_rtol {:.1e} / 4)",
            acc.estimate, ctl.lambda_rtol
        )
    };
    let cause = if friction && out.contact > 0 && out.stick == 0 {
        format!(
            "every one of the {} contact nodes slips: the bound s cannot hold the tangential load, and the body slides (with Coulomb friction: friction cannot hold the loads with the pressures this body develops; lower the tangential load or raise -friction_coefficient)",
            out.contact
        )
    } else if let Some(r0) = ctl.r_far {
        r_far_words(r, r0)
    } else if out.contact == 0 {
        "no node touches the obstacle at the last iterations although the loads push the body along a motion that only the contact holds: the iterates do not reach a contact state that holds them (no contact reached); check the obstacle's position and the loads, or try -ubr_anderson 0".to_string()
    } else if progress.changes >= progress.since / 10 {
        format!(
            "contact statuses changed {} times in those iterations: the contact set cycles between states, as when the contact zone is a few nodes or a point smaller than a cell; refine the mesh where the body touches, or loosen -ubr_lambda_rtol",
            progress.changes
        )
    } else {
        format!(
            "{} nodes touch the obstacle and the contact set has settled, yet the residual stays flat at r = {r:.3e}; try -ubr_anderson 0 or another r",
            out.contact
        )
    };
    format!(
        "{name} stalled: its best residual has not fallen by 3% in the last {} iterations (best {:.3e}), stopped after {its} of -ubr_max_it {}; {target}; {cause}",
        progress.since, progress.best, ctl.max_it
    )
}

/// The message of a run stopped by the iteration cap: the failing test,
/// its value and target, and what to try.
fn failure(name: &str, ctl: &UbrControl, out: &UbrOutcome, r: f64, acc: &Accuracy) -> String {
    let its = out.iterations;
    if its == 0 {
        return format!(
            "{name} ran no iteration (-ubr_max_it {}): the answer is its start (no contact stress); give -ubr_max_it at least 1 (default 10000)",
            ctl.max_it
        );
    }
    if ctl.stop == StopRule::Paper {
        return format!(
            "{name} stopped after {its} iterations (-ubr_max_it): relative change (4.16) {:.3e} (target -ubr_rtol {:.1e}), constraint residual {:.3e} (target -ubr_residual_tol {:.1e}); try more iterations, -ubr_anderson 10, or the default stopping test (-ubr_stop accuracy)",
            out.criterion, ctl.rtol, out.residual, ctl.residual_tol
        );
    }
    if acc.statuses_unsettled() {
        return format!(
            "{name} stopped after {its} iterations (-ubr_max_it): the error estimate {:.3e} meets its target ({:.1e}) but contact statuses still change every iteration (a node switching between open and contact, or stick and slip); try -ubr_max_it larger or a finer mesh near the edge of the contact zone",
            out.error_estimate,
            0.25 * ctl.lambda_rtol
        );
    }
    format!(
        "{name} stopped after {its} iterations (-ubr_max_it): the error estimate of lambda is {:.3e} (residual {:.3e} x amplification {:.3e}), the target -ubr_lambda_rtol {:.1e} / 4; r = {r:.6e}; try -ubr_max_it larger, a looser -ubr_lambda_rtol, or another r (-ubr_r auto chooses it)",
        out.error_estimate, out.p, out.k, ctl.lambda_rtol
    )
}
