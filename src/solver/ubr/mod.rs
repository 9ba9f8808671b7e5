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

mod measures;
mod messages;
pub use messages::names_far_r;
mod run;

use super::mass_norms;
use super::stopping::{paper_change, StopRule};
use super::surface::{Surface, UbrState};
use super::Problem;
use crate::comm::allreduce_sum;
use crate::error::Error;
use crate::linalg::linear::LinearSolver;
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
    /// What of the whole displacement a condensed run computes at its end.
    pub displacement: Whole,
    /// A condensed run (accuracy test) leaves its whole displacement to the
    /// caller ([`UbrOutcome::pending`], [`complete`]), which knows only
    /// after the run whether it is wanted: CF-FP's Tresca solves, of which
    /// the last alone gives the answer (each full solve cost as much as
    /// the rest of the solve on hertz_37473).
    pub defer_whole: bool,
    /// Anderson's iterates that drift or stall go back to the plain
    /// iteration (false: the run fails, and its caller has a cheaper way
    /// on: CF-FP's halving of the step of its bound).
    pub retreat: bool,
}

/// The whole displacement at the end of a condensed run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Whole {
    /// None: `u` keeps its last value (the steps of a load history whose
    /// displacement nothing reads).
    No,
    /// u^k alone (one column; the paper's change (4.16) is not computed).
    Only,
    /// u^{k-1} and u^k (two columns): u and the paper's change.
    WithChange,
}

/// A user's r this many times above or below the trial r0 is far outside
/// the range `-ubr_r auto` chooses from (its estimates lie within a factor
/// of about 30 of r0 on every scene measured).
pub const R_FAR: f64 = 100.0;

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
    /// Runs whose Anderson iterates drifted or stalled, and went on plain
    /// (0 or 1; CF-FP's outcome: over all its Tresca solves).
    pub anderson_retreats: usize,
    /// Of those, runs whose plain iteration drifted or stalled too and
    /// started again from the run's start (0 or 1 per run).
    pub plain_restarts: usize,
    /// Why the run stopped without converging (None: converged).
    pub failure: Option<String>,
    /// Stopped at round-off (the accuracy test, its residual flat at 1e-12
    /// or less): as accurate as double precision gives, its estimate above
    /// the target.
    pub roundoff: bool,
    /// Stopped because its best residual made no progress for
    /// `STALL_ITS` iterations (not at round-off).
    pub stalled: bool,
    /// A run of [`UbrControl::defer_whole`]: what its whole displacement is
    /// made from (None: made already, or nothing to make).
    pub pending: Option<Pending>,
}

impl UbrOutcome {
    /// Adds this run's Anderson retreats and plain restarts to `to` (the
    /// counts over CF-FP's Tresca solves).
    pub fn count_retreats(&self, to: &mut [usize; 2]) {
        to[0] += self.anderson_retreats;
        to[1] += self.plain_restarts;
    }
}

/// The contact parts of a condensed run's last two right-hand sides and
/// their solutions `u_C`, and the norms of phi the paper's change is
/// relative to: its whole displacement (u^{k-1} and u^k) from one solve.
#[derive(Clone, Debug, Default)]
pub struct Pending {
    pub c_prev: Vec<f64>,
    pub uc_prev: Vec<f64>,
    pub c: Vec<f64>,
    pub uc: Vec<f64>,
    pub dphi2: f64,
    pub phi2: f64,
}

/// The whole displacement of a condensed run from its contact values
/// (`paper`: the paper's test, whose deferred candidates left it in u
/// already): u^k (`Whole::Only`), or u^{k-1} and u^k from one solve with two
/// right-hand sides and the paper's change (4.16)/(5.6), returned
/// (`Whole::WithChange`).
#[allow(clippy::too_many_arguments)]
pub(super) fn whole_displacement<C: Communicator>(
    world: &C,
    lin: &mut LinearSolver,
    surface: &Surface,
    lumped_mass: &[f64],
    state: &mut UbrState,
    p: &Pending,
    mode: Whole,
    paper: bool,
) -> Result<Option<f64>, Error> {
    let d = surface.dim;
    let mut criterion = None;
    let condensed = lin.is_condensed();
    if condensed && !paper && mode == Whole::Only {
        // u^k alone (a step of a load history with outputs).
        let x = lin.displacements(surface, &[(&p.c, &p.uc)], true)?;
        let u = &state.u;
        x.read(|xx| u.write(|u| u.copy_from_slice(xx)))??;
    } else if condensed && !paper && mode == Whole::WithChange {
        // The paper's change (4.16)/(5.6) is reported in every mode: u^{k-1}
        // and u^k from one solve with two right-hand sides.
        // (From u_C alone: the equilibrium check of the answer then tests
        // the Schur solves too.)
        let x = lin.displacements(surface, &[(&p.c_prev, &p.uc_prev), (&p.c, &p.uc)], true)?;
        let u = &state.u;
        let nloc = u.local_size()?;
        let (du2, u2) = x.read(|xx| {
            u.write(|u| u.copy_from_slice(&xx[nloc..2 * nloc]))
                .map(|_| mass_norms(lumped_mass, d, &xx[nloc..], &xx[..nloc]))
        })??;
        let [du2, u2] = allreduce_sum(world, [du2, u2]);
        criterion = Some(paper_change(du2, p.dphi2, u2, p.phi2));
    }
    Ok(criterion)
}

/// What a UBR run works on: the linear solver, the contact surface and
/// the lumped mass of `problem`.
fn parts(problem: &mut Problem) -> (&mut LinearSolver, Surface<'_>, &[f64]) {
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
    (lin, surface, lumped_mass)
}

/// Makes the whole displacement a run of [`UbrControl::defer_whole`] left
/// pending, as `mode` says (nothing for `Whole::No`), right after the run
/// (the factorization and r it solved with); sets its paper's change.
pub fn complete<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    out: &mut UbrOutcome,
    mode: Whole,
) -> Result<(), Error> {
    let Some(p) = out.pending.take() else {
        return Ok(());
    };
    let (lin, surface, lumped_mass) = parts(problem);
    let criterion = whole_displacement(world, lin, &surface, lumped_mass, state, &p, mode, false)?;
    if let Some(c) = criterion {
        out.criterion = c;
    }
    if mode != Whole::No && !lin.condenses_every_component() {
        tangential_from_whole(&surface, state)?;
    }
    Ok(())
}

/// A condensed solve knew u at the Schur components only: u_t of the
/// candidates from the whole displacement now known. (Where the Schur
/// components are all of them, u_t is the last evaluation's already:
/// recomputed, it would differ by round-off, and a history's next step,
/// which measures slip from it, would depend on whether a step's outputs
/// were asked for.)
fn tangential_from_whole(surface: &Surface, state: &mut UbrState) -> Result<(), Error> {
    let d = surface.dim;
    let st = &mut state.surface;
    state.u.read(|u| {
        for (i, &v) in surface.cs.node.iter().enumerate() {
            // (The node's own normal n_i: its u is candidate i's.)
            let (uv, n) = (&u[v * d..(v + 1) * d], surface.cs.n(i));
            let un: f64 = (0..d).map(|c| uv[c] * n[c]).sum();
            for c in 0..d {
                st.ut[i * d + c] = uv[c] - un * n[c];
            }
        }
    })
}

/// Runs UBR-C (`friction_bound` = None, the problem assembled without the
/// tangential term) or UBR-TF (`Some(s)`, one bound per candidate) from
/// `state` (the paper's initialization, or a previous run's iterate).
pub fn ubr<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    friction_bound: Option<&[f64]>,
    ctl: &UbrControl,
    events: &crate::petsc::Events,
) -> Result<UbrOutcome, Error> {
    let (lin, surface, lumped_mass) = parts(problem);
    run::Run::new(
        world,
        lin,
        surface,
        lumped_mass,
        state,
        friction_bound,
        ctl,
        events,
    )?
    .run()
}
