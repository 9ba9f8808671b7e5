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
//!
//! Anderson acceleration (our addition, `-ubr_anderson M`, off by default).
//! One iteration is a fixed-point map `z -> T(z)` on the contact-surface
//! variables `z = (phi^{k-1}, lambda^k)` alone (u^k is a function of z), and T
//! is piecewise affine and contracts slowly (about 0.995 per iteration at the
//! paper's r = 0.11E). We accelerate it with safeguarded type-II Anderson
//! acceleration (H. F. Walker, P. Ni, "Anderson acceleration for fixed-point
//! iterations", SIAM J. Numer. Anal. 49 (2011) 1715-1735; the safeguard of
//! J. Zhang, B. O'Donoghue, S. Boyd, "Globally convergent type-I Anderson
//! acceleration for nonsmooth fixed-point iterations", SIAM J. Optim. 30
//! (2020) 3170-3197, as SCS 2.x applies it to its ADMM map): with
//! `f_j = T(z_j) - z_j`, the last M differences `dF`, `dG` of f and T(z),
//! `gamma = argmin ||f_k - dF gamma||_W` and `z_{k+1} = T(z_k) - dG gamma`.
//! The norm W is the Gamma_c norm of phi plus that of lambda / r (both
//! displacements), so the Gram matrix `dF^T W dF` is a sum of local dot
//! products reduced by one allreduce per iteration; every rank solves the
//! same small regularized system and gets the same coefficients. Safeguard:
//! an extrapolated point is kept only if its residual `||f||` is below that
//! of the last accepted point; otherwise the iteration goes back to the plain
//! step T(z) of that point and the memory is cleared. The stopping tests are
//! evaluated, unchanged, on every evaluation of T. M = 0 runs the paper's
//! iteration exactly. Measured (hertz_37473, one rank, rtol 1e-8): 604 plain
//! iterations, 107 / 82 / 59 with M = 5 / 10 / 20; restarting the memory when
//! the contact set changes gave 97 / 88 / 69, no consistent gain, so the
//! memory is only cleared by the safeguard.

use super::{allreduce_sum, Problem};
use crate::contact::{project_normal, project_tangential};
use crate::error::Error;
use crate::petsc::{DenseColumns, Vector};
use mpi::collective::SystemOperation;
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
    /// Evaluations of the UBR map so far, and the one whose whole
    /// displacement `u_prev` is (a condensed iteration only computes u at the
    /// contact nodes; 0: the initial u = 0).
    evaluations: usize,
    u_prev_of: usize,
    /// Contact part `B^T W (r phi - lambda)` of the right-hand side of this
    /// evaluation and of the previous one, and u at the contact nodes
    /// (candidate i, component c at `i * dim + c`).
    c: Vec<f64>,
    c_prev: Vec<f64>,
    uc: Vec<f64>,
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
            evaluations: 0,
            u_prev_of: 0,
            c: vec![0.0; nc * d],
            c_prev: vec![0.0; nc * d],
            uc: vec![0.0; nc * d],
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

    /// With `u` the whole displacement of this evaluation: the local sums of
    /// `||u^k - u^{k-1}||^2` and `||u^k||^2` (lumped mass), then `u^{k-1} = u^k`;
    /// with `extract`, also u at the contact nodes.
    fn update_full_norms(&mut self, problem: &Problem, extract: bool) -> Result<(f64, f64), Error> {
        let d = self.dim;
        let (u_prev, uc) = (&mut self.u_prev, &mut self.uc);
        let sums = self.u.read(|uv| {
            let (du2, u2) = mass_norms(problem, uv, u_prev);
            u_prev.copy_from_slice(uv);
            if extract {
                for (i, &v) in problem.contact.node.iter().enumerate() {
                    uc[i * d..(i + 1) * d].copy_from_slice(&uv[v * d..(v + 1) * d]);
                }
            }
            (du2, u2)
        })?;
        self.u_prev_of = self.evaluations;
        Ok(sums)
    }

    /// Back to the paper's initialization (a cold start).
    pub fn reset(&mut self) -> Result<(), Error> {
        self.u_prev.iter_mut().for_each(|x| *x = 0.0);
        for v in self.arrays_mut() {
            v.iter_mut().for_each(|x| *x = 0.0);
        }
        self.evaluations = 0;
        self.u_prev_of = 0;
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
    /// Anderson memory M (0: the paper's plain iteration).
    pub anderson: usize,
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
    /// Anderson: evaluations at an extrapolated point, and how many of them
    /// the safeguard rejected.
    pub anderson_steps: usize,
    pub anderson_rejected: usize,
}

/// Safeguard factor: an extrapolated point is kept while its fixed-point
/// residual is at most this times that of the last accepted point.
const ANDERSON_SAFEGUARD: f64 = 1.0;
/// Tikhonov regularization of the Gram matrix, relative to its largest diagonal entry.
const ANDERSON_REGULARIZATION: f64 = 1e-10;
/// Extrapolation coefficients larger than this are not trusted (a reset instead).
const ANDERSON_MAX_WEIGHT: f64 = 1e8;

/// The memory of the Anderson acceleration, allocated once per UBR run.
struct Anderson {
    mem: usize,
    nc: usize,
    d: usize,
    tangential: bool,
    /// Inner-product weights of z: w_i on phi, w_i / r^2 on lambda.
    wz: Vec<f64>,
    /// Input z of the current evaluation, and T(z).
    z: Vec<f64>,
    g: Vec<f64>,
    /// f = T(z) - z and T(z) of the last accepted evaluation.
    f_prev: Vec<f64>,
    g_prev: Vec<f64>,
    have_prev: bool,
    /// Columns of dF and dG (a ring of `mem` columns, `count` filled, `next` to overwrite).
    df: Vec<f64>,
    dg: Vec<f64>,
    count: usize,
    next: usize,
    gram: Vec<f64>,
    gamma: Vec<f64>,
    send: Vec<f64>,
    recv: Vec<f64>,
    /// Whether the current z is an extrapolated point.
    extrapolated: bool,
    /// ||f|| of the last accepted evaluation.
    ref_norm: f64,
}

impl Anderson {
    fn new(mem: usize, problem: &Problem, r: f64) -> Anderson {
        let cs = &problem.contact;
        let (nc, d) = (cs.len(), problem.dim);
        let tangential = problem.tangential;
        let per = if tangential { 1 + d } else { 1 };
        let nz = 2 * nc * per;
        let mut wz = vec![0.0; nz];
        for i in 0..nc {
            wz[i] = cs.w[i];
            wz[nc * per + i] = cs.w[i] / (r * r);
            if tangential {
                for c in 0..d {
                    wz[nc + i * d + c] = cs.w[i];
                    wz[nc * per + nc + i * d + c] = cs.w[i] / (r * r);
                }
            }
        }
        let nred = mem * (mem + 1) / 2 + mem;
        Anderson {
            mem,
            nc,
            d,
            tangential,
            wz,
            z: vec![0.0; nz],
            g: vec![0.0; nz],
            f_prev: vec![0.0; nz],
            g_prev: vec![0.0; nz],
            have_prev: false,
            df: vec![0.0; nz * mem],
            dg: vec![0.0; nz * mem],
            count: 0,
            next: 0,
            gram: vec![0.0; mem * mem],
            gamma: vec![0.0; mem],
            send: vec![0.0; nred],
            recv: vec![0.0; nred],
            extrapolated: false,
            ref_norm: f64::INFINITY,
        }
    }

    /// z = (phi_n, phi_t, lambda_n, lambda_t) of the state into `out`.
    fn gather(&self, st: &UbrState, out: &mut [f64]) {
        let (nc, nt) = (self.nc, if self.tangential { self.nc * self.d } else { 0 });
        out[..nc].copy_from_slice(&st.phi_n);
        out[nc..nc + nt].copy_from_slice(&st.phi_t[..nt]);
        out[nc + nt..2 * nc + nt].copy_from_slice(&st.lambda_n);
        out[2 * nc + nt..].copy_from_slice(&st.lambda_t[..nt]);
    }

    fn scatter(&self, z: &[f64], st: &mut UbrState) {
        let (nc, nt) = (self.nc, if self.tangential { self.nc * self.d } else { 0 });
        st.phi_n.copy_from_slice(&z[..nc]);
        st.phi_t[..nt].copy_from_slice(&z[nc..nc + nt]);
        st.lambda_n.copy_from_slice(&z[nc + nt..2 * nc + nt]);
        st.lambda_t[..nt].copy_from_slice(&z[2 * nc + nt..]);
    }

    fn reset(&mut self) {
        self.count = 0;
        self.next = 0;
    }

    /// After an evaluation `T(z)` (in `st`) whose residual is `fnorm`: the next z,
    /// written into `st`. Returns whether the evaluation was rejected.
    fn step<C: Communicator>(&mut self, world: &C, st: &mut UbrState, fnorm: f64) -> bool {
        let nz = self.z.len();
        let worse = fnorm.is_nan() || fnorm > ANDERSON_SAFEGUARD * self.ref_norm;
        if self.extrapolated && worse {
            // Worse than the last accepted point: back to its plain step.
            self.reset();
            self.extrapolated = false;
            let g_prev = std::mem::take(&mut self.g_prev);
            self.scatter(&g_prev, st);
            self.g_prev = g_prev;
            return true;
        }
        let mut g = std::mem::take(&mut self.g);
        self.gather(st, &mut g);
        // f = g - z, stored in z (z is not needed any more)
        for (zi, gi) in self.z.iter_mut().zip(&g) {
            *zi = gi - *zi;
        }
        if self.have_prev {
            let col = self.next * nz..(self.next + 1) * nz;
            for (j, x) in col.clone().enumerate() {
                self.df[x] = self.z[j] - self.f_prev[j];
                self.dg[x] = g[j] - self.g_prev[j];
            }
            self.next = (self.next + 1) % self.mem;
            self.count = (self.count + 1).min(self.mem);
        }
        self.f_prev.copy_from_slice(&self.z);
        self.g_prev.copy_from_slice(&g);
        self.have_prev = true;
        self.ref_norm = fnorm;
        self.g = g;
        let m = self.count;
        self.extrapolated = false;
        if m == 0 || fnorm == 0.0 {
            return false; // the plain step: the state holds T(z)
        }
        // Gram matrix dF^T W dF (upper triangle) and dF^T W f: one reduction.
        let mut p = 0;
        for a in 0..m {
            let ca = &self.df[a * nz..(a + 1) * nz];
            for b in a..m {
                let cb = &self.df[b * nz..(b + 1) * nz];
                self.send[p] = (0..nz).map(|j| self.wz[j] * ca[j] * cb[j]).sum();
                p += 1;
            }
            self.send[p] = (0..nz).map(|j| self.wz[j] * ca[j] * self.f_prev[j]).sum();
            p += 1;
        }
        world.all_reduce_into(&self.send[..p], &mut self.recv[..p], SystemOperation::sum());
        let mut p = 0;
        let mut diag_max = 0.0f64;
        for a in 0..m {
            for b in a..m {
                self.gram[a * m + b] = self.recv[p];
                self.gram[b * m + a] = self.recv[p];
                p += 1;
            }
            self.gamma[a] = self.recv[p];
            p += 1;
            diag_max = diag_max.max(self.gram[a * m + a]);
        }
        let reg = ANDERSON_REGULARIZATION * diag_max + f64::MIN_POSITIVE;
        for a in 0..m {
            self.gram[a * m + a] += reg;
        }
        let ok = cholesky_solve(&mut self.gram[..m * m], &mut self.gamma[..m], m)
            && self.gamma[..m]
                .iter()
                .all(|x| x.is_finite() && x.abs() <= ANDERSON_MAX_WEIGHT);
        if !ok {
            self.reset();
            return false;
        }
        // z_{k+1} = T(z_k) - dG gamma
        self.z.copy_from_slice(&self.g);
        for a in 0..m {
            let ga = self.gamma[a];
            let ca = &self.dg[a * nz..(a + 1) * nz];
            for (zj, cj) in self.z.iter_mut().zip(ca) {
                *zj -= ga * cj;
            }
        }
        let z = std::mem::take(&mut self.z);
        self.scatter(&z, st);
        self.z = z;
        self.extrapolated = true;
        false
    }
}

/// Solves `a x = b` in place (a: m x m symmetric positive definite, row-major,
/// overwritten by its Cholesky factor; b overwritten by x). False if a pivot
/// is not positive.
fn cholesky_solve(a: &mut [f64], b: &mut [f64], m: usize) -> bool {
    for j in 0..m {
        let mut dj = a[j * m + j];
        for k in 0..j {
            dj -= a[j * m + k] * a[j * m + k];
        }
        if dj.is_nan() || dj <= 0.0 {
            return false;
        }
        let dj = dj.sqrt();
        a[j * m + j] = dj;
        for i in j + 1..m {
            let mut v = a[i * m + j];
            for k in 0..j {
                v -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = v / dj;
        }
    }
    for i in 0..m {
        let mut v = b[i];
        for k in 0..i {
            v -= a[i * m + k] * b[k];
        }
        b[i] = v / a[i * m + i];
    }
    for i in (0..m).rev() {
        let mut v = b[i];
        for k in i + 1..m {
            v -= a[k * m + i] * b[k];
        }
        b[i] = v / a[i * m + i];
    }
    true
}

/// The local sums of `||u - u_prev||^2` and `||u||^2` with the lumped mass.
fn mass_norms(problem: &Problem, u: &[f64], u_prev: &[f64]) -> (f64, f64) {
    let d = problem.dim;
    let (mut du2, mut u2) = (0.0, 0.0);
    for (j, m) in problem.lumped_mass.iter().enumerate() {
        for c in 0..d {
            let x = u[j * d + c];
            let dx = x - u_prev[j * d + c];
            du2 += m * dx * dx;
            u2 += m * x * x;
        }
    }
    (du2, u2)
}

/// Solves (4.5)/(5.3) for the whole displacement: `state.u` from the
/// right-hand side `rhs0 + c`. Returns the inner iteration count.
fn full_solve(problem: &Problem, state: &mut UbrState) -> Result<usize, Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    state.rhs.copy_from(&problem.rhs0)?;
    let c = &state.c;
    state.rhs.write(|b| {
        for (i, &v) in cs.node.iter().enumerate() {
            for k in 0..d {
                b[v * d + k] += c[i * d + k];
            }
        }
    })?;
    problem.ksp.solve(&state.rhs, &state.u)
}

/// The contact-surface part of the state after one evaluation: enough to
/// go back to a condensed iteration whose stopping test is decided later.
struct Snapshot {
    arrays: [Vec<f64>; 11],
    in_contact: Vec<bool>,
    slip: Vec<bool>,
    evaluations: usize,
    peak_stress: f64,
}

/// Positions in [`UbrState::arrays_mut`] (and [`Snapshot`]) of c, c_prev, uc.
const IDX_C: usize = 8;
const IDX_C_PREV: usize = 9;
const IDX_UC: usize = 10;

impl UbrState {
    /// The per-candidate arrays of the state.
    fn arrays_mut(&mut self) -> [&mut Vec<f64>; 11] {
        [
            &mut self.phi_n,
            &mut self.phi_t,
            &mut self.lambda_n,
            &mut self.lambda_t,
            &mut self.stress_n,
            &mut self.stress_t,
            &mut self.un,
            &mut self.ut,
            &mut self.c,
            &mut self.c_prev,
            &mut self.uc,
        ]
    }

    fn snapshot(&mut self) -> Snapshot {
        Snapshot {
            arrays: self.arrays_mut().map(|v| v.clone()),
            in_contact: self.in_contact.clone(),
            slip: self.slip.clone(),
            evaluations: self.evaluations,
            peak_stress: self.peak_stress,
        }
    }

    fn restore(&mut self, snap: Snapshot) {
        for (v, saved) in self.arrays_mut().into_iter().zip(snap.arrays) {
            *v = saved;
        }
        self.in_contact = snap.in_contact;
        self.slip = snap.slip;
        self.evaluations = snap.evaluations;
        self.peak_stress = snap.peak_stress;
    }
}

/// A condensed evaluation whose stopping tests, but for the change
/// (4.16)/(5.6), are decided (`others_ok`), or the last one of the run.
struct Candidate {
    /// Its position in `state.history`, and the length of
    /// `state.inner_iterations` after it.
    index: usize,
    inner_len: usize,
    others_ok: bool,
    /// `||phi^k - phi^{k-1}||^2` and `||phi^k||^2` (global sums), and the
    /// part of `||u^k - u^{k-1}||^2` at the contact nodes.
    dphi2: f64,
    phi2: f64,
    dc2: f64,
    out: UbrOutcome,
    snap: Snapshot,
}

/// When to decide the pending candidates. A solve with many right-hand sides
/// costs about 35 ms plus 7 ms per column here (hertz_37473: MUMPS walks its
/// tree once per call), so the candidates are decided together, once the
/// newest one is predicted to pass; the condensed iterations past the first
/// converged candidate are cheap and undone.
///
/// What is learnt from decided candidates: `||u||^2` of the last one, and
/// the largest ratio seen of `||u^k - u^{k-1}||^2` to its part at the
/// contact nodes (60-130 on the Hertz meshes, erratic with Anderson).
/// - A candidate whose change (4.16)/(5.6), counting only the contact nodes'
///   part of the change of u and with `||u||^2` taken 10% larger than last
///   seen, is still at least eps fails for sure: it is not solved.
/// - The newest pending candidate triggers the solve when its change
///   predicted with the largest ratio is below eps; the first one
///   (nothing learnt yet) triggers it at once; 16 pending ones, or the last
///   evaluation of the run, trigger it too.
///
/// Every candidate not surely failing is decided, so the iteration stops
/// where the uncondensed one does, unless `||u||^2` grows by more than 10%
/// over the iterations whose other tests already pass.
struct Calibration {
    u2: Option<f64>,
    ratio: f64,
}
const U2_MARGIN: f64 = 1.1;
const MAX_PENDING: usize = 16;

impl Calibration {
    /// The squared change (4.16)/(5.6) of `cand` with the contact part of
    /// `||u^k - u^{k-1}||^2` scaled by `ratio` (1: a lower bound) and the
    /// last `||u||^2` by `u2_scale`; None while nothing is learnt.
    fn change2(&self, cand: &Candidate, ratio: f64, u2_scale: f64) -> Option<f64> {
        let u2 = self.u2? * u2_scale + cand.phi2;
        Some(if u2 > 0.0 {
            (ratio * cand.dc2 + cand.dphi2) / u2
        } else {
            0.0
        })
    }
    fn surely_fails(&self, cand: &Candidate, rtol: f64) -> bool {
        self.change2(cand, 1.0, U2_MARGIN)
            .is_some_and(|c2| c2 >= rtol * rtol)
    }
    fn predicted_to_pass(&self, cand: &Candidate, rtol: f64) -> bool {
        self.change2(cand, self.ratio.max(1.0), 1.0)
            .is_none_or(|c2| c2 < rtol * rtol)
    }
}

/// Decides the pending condensed candidates: the whole displacement of each
/// (and of its predecessor, unless known) from one solve with many
/// right-hand sides, checked against the condensed values at the contact
/// nodes, then the change (4.16)/(5.6) of each in turn. Unless the two
/// disagree, `state.u` and `u_prev` are then the displacement of the first
/// candidate that passes every test, else of the last candidate.
fn resolve<C: Communicator>(
    world: &C,
    problem: &Problem,
    state: &mut UbrState,
    pending: &mut [Candidate],
    rtol: f64,
    cal: &mut Calibration,
) -> Result<Resolution, Error> {
    let d = problem.dim;
    let cs = &problem.contact;
    let n = state.u_prev.len();
    // Columns: for each candidate, its predecessor's displacement (None:
    // u_prev) and its own.
    let mut rhs: Vec<&[f64]> = Vec::new();
    let mut prev_col = Vec::with_capacity(pending.len());
    let mut own_col: Vec<usize> = Vec::with_capacity(pending.len());
    for (i, cand) in pending.iter().enumerate() {
        let e = cand.snap.evaluations;
        let prev = if e == state.u_prev_of + 1 {
            None
        } else if i > 0 && pending[i - 1].snap.evaluations + 1 == e {
            Some(own_col[i - 1])
        } else {
            rhs.push(&cand.snap.arrays[IDX_C_PREV]);
            Some(rhs.len() - 1)
        };
        prev_col.push(prev);
        rhs.push(&cand.snap.arrays[IDX_C]);
        own_col.push(rhs.len() - 1);
    }
    let comm = crate::petsc::comm_world();
    let b = DenseColumns::new(comm, n, rhs.len())?;
    let x = DenseColumns::new(comm, n, rhs.len())?;
    problem.rhs0.read(|r0| {
        b.write(|bb| {
            for (j, c) in rhs.iter().enumerate() {
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
    problem.ksp.mat_solve(&b, &x)?;
    let mut found = None;
    let mut chosen = pending.len() - 1;
    let inconsistent = x.read(|xx| -> Result<Option<String>, Error> {
        for (i, cand) in pending.iter_mut().enumerate() {
            let u = &xx[own_col[i] * n..(own_col[i] + 1) * n];
            let up = match prev_col[i] {
                None => &state.u_prev[..],
                Some(j) => &xx[j * n..(j + 1) * n],
            };
            let uc = &cand.snap.arrays[IDX_UC];
            let (mut diff, mut scale) = (0.0f64, 0.0f64);
            for (l, &v) in cs.node.iter().enumerate() {
                for k in 0..d {
                    diff = diff.max((u[v * d + k] - uc[l * d + k]).abs());
                    scale = scale.max(u[v * d + k].abs());
                }
            }
            if diff.is_nan() || diff > 1e-6 * scale {
                return Ok(Some(format!(
                    "the condensed solve differs from the full one by {diff:.3e} at the \
                     contact nodes (displacements up to {scale:.3e}): is the body held?"
                )));
            }
            let (du2, u2) = mass_norms(problem, u, up);
            let [du2, u2] = allreduce_sum(world, [du2, u2]);
            cal.u2 = Some(u2);
            if cand.dc2 > 0.0 {
                cal.ratio = cal.ratio.max(du2 / cand.dc2);
            }
            cand.out.criterion = if u2 + cand.phi2 > 0.0 {
                ((du2 + cand.dphi2) / (u2 + cand.phi2)).sqrt()
            } else {
                0.0
            };
            if !cand.out.criterion.is_finite() {
                return Err(Error::NotConverged(format!(
                    "UBR produced a non-finite iterate at iteration {}",
                    cand.out.iterations
                )));
            }
            if cand.others_ok && cand.out.criterion < rtol {
                found = Some(i);
                chosen = i;
                break;
            }
        }
        let u = &xx[own_col[chosen] * n..(own_col[chosen] + 1) * n];
        state.u_prev.copy_from_slice(u);
        Ok(None)
    })??;
    if let Some(why) = inconsistent {
        return Ok(Resolution::Inconsistent(why));
    }
    state.u_prev_of = pending[chosen].snap.evaluations;
    let u_prev = &state.u_prev;
    state.u.write(|u| u.copy_from_slice(u_prev))?;
    Ok(match found {
        Some(i) => Resolution::Converged(i),
        None => Resolution::Open,
    })
}

/// What deciding a batch of candidates found.
enum Resolution {
    /// The candidate at this position passes every test.
    Converged(usize),
    /// None does.
    Open,
    /// The condensed and the full solves disagree (a matrix singular or
    /// nearly so, e.g. a body that nothing holds): the run goes on without
    /// condensation.
    Inconsistent(String),
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
    let mut aa = (ctl.anderson > 0).then(|| Anderson::new(ctl.anderson, problem, r));
    let mut condensed = problem.condensed.as_ref();
    let mut pending: Vec<Candidate> = Vec::new();
    let mut cal = Calibration {
        u2: None,
        ratio: 0.0,
    };
    let mut uc_old = vec![0.0; state.uc.len()];
    let mut k = 0;
    while k < ctl.max_it {
        if let Some(aa) = aa.as_mut() {
            let mut z = std::mem::take(&mut aa.z);
            aa.gather(state, &mut z);
            aa.z = z;
            if aa.extrapolated {
                out.anderson_steps += 1;
            }
        }
        // Step 1: the elasticity subproblem (4.5)/(5.3); only the right-hand
        // side changes, by c = B^T W (r phi^{k-1} - lambda^k) on the contact nodes.
        std::mem::swap(&mut state.c, &mut state.c_prev);
        state.evaluations += 1;
        {
            let _e = events.rhs.begin();
            for i in 0..nc {
                let w = cs.w[i];
                let sn = w * (r * state.phi_n[i] - state.lambda_n[i]);
                let base = cs.node[i] * d;
                for c in 0..d {
                    state.c[i * d + c] = if problem.is_dirichlet[base + c] {
                        0.0
                    } else if problem.tangential {
                        sn * n[c] + w * (r * state.phi_t[i * d + c] - state.lambda_t[i * d + c])
                    } else {
                        sn * n[c]
                    };
                }
            }
        }
        if problem.adaptive_inner && k == 0 {
            // Inexact Uzawa: each solve starts from u^{k-1} and reduces the
            // residual b - A u^{k-1}, i.e. the change this iteration brings,
            // by the factor below (-ksp_converged_use_initial_residual_norm):
            // loose in absolute terms early, tight at the end as the changes
            // shrink with (4.16).
            problem.ksp.set_rtol(ctl.inner_rtol_factor)?;
        }
        // ||u^k - u^{k-1}||^2 and ||u^k||^2 with lumped mass (local sums), when known.
        let mut du_u = None;
        // The part of ||u^k - u^{k-1}||^2 at the contact nodes (condensed).
        let mut dc2 = 0.0;
        let its = if let Some(cd) = condensed {
            let _e = events.solve.begin();
            uc_old.copy_from_slice(&state.uc);
            cd.schur.solve(&state.c, &mut state.uc)?;
            for (x, y) in state.uc.iter_mut().zip(&cd.y0) {
                *x += y;
            }
            for (i, &v) in cs.node.iter().enumerate() {
                let m = problem.lumped_mass[v];
                for c in 0..d {
                    dc2 += m * (state.uc[i * d + c] - uc_old[i * d + c]).powi(2);
                }
            }
            0
        } else {
            let its = {
                let _e = events.solve.begin();
                full_solve(problem, state)?
            };
            du_u = Some(state.update_full_norms(problem, true)?);
            its
        };
        state.inner_iterations.push(its);
        // Steps 2 and 3: projections (4.15), (5.5) and the multiplier update (4.4), pointwise.
        let e = events.projection.begin();
        let st = &mut *state;
        let sums = {
            let uv = &st.uc;
            // [9]: ||lambda^{k+1} - lambda^k||^2 (the Anderson residual)
            let mut s = [0.0f64; 10];
            // max tension, max |stress|, max |u_n|
            let mut ext = [0.0f64; 3];
            if let Some((du2, u2)) = du_u {
                s[0] = du2;
                s[1] = u2;
            }
            for i in 0..nc {
                let base = i * d;
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
                s[8] += w * lambda_new * lambda_new;
                s[9] += w * (lambda_new - st.lambda_n[i]).powi(2);
                st.un[i] = uni;
                st.phi_n[i] = phi_new;
                st.lambda_n[i] = lambda_new;
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
                    for c in 0..d {
                        s[9] += w * (lam_t[c] - st.lambda_t[i * d + c]).powi(2);
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
        };
        drop(e);
        let (sums, ext) = sums;
        let [tension, largest, un_max] = super::allreduce_max_n(world, ext);
        out.tension = if largest > 0.0 {
            tension / largest
        } else {
            0.0
        };
        state.peak_stress = state.peak_stress.max(largest);
        let [du2, u2, dphi2, phi2, res2, ncontact, nstick, nslip, lam2, dlam2] =
            allreduce_sum(world, sums);
        // The dual residual r ||phi^k - phi^{k-1}||, relative to ||lambda^{k+1}||:
        // the gap between the multiplier and the stress of u^k (4.7).
        out.dual = if lam2 > 0.0 {
            r * (dphi2 / lam2).sqrt()
        } else {
            0.0
        };
        // (4.16)/(5.6): the relative change of (u, phi); after a condensed
        // solve, known only once the candidate is decided.
        out.criterion = if du_u.is_none() {
            f64::NAN
        } else if u2 + phi2 > 0.0 {
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
        if (du_u.is_some() && !out.criterion.is_finite()) || !out.residual.is_finite() {
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
        let others_ok = k >= 2 && out.residual < ctl.residual_tol && dual_ok && held;
        if condensed.is_some() {
            // The change (4.16)/(5.6) needs the whole displacement: decided
            // for the evaluations where it is the last test open (unless it
            // surely fails, see `Calibration`), a batch at a time, going back
            // to the first that passes (so the iterations stop where the
            // uncondensed ones do), and for the last.
            let last = k >= ctl.max_it;
            let mut decide = last && !pending.is_empty();
            if others_ok || last {
                let cand = Candidate {
                    index: state.history.len() - 1,
                    inner_len: state.inner_iterations.len(),
                    others_ok,
                    dphi2,
                    phi2,
                    dc2,
                    out,
                    snap: state.snapshot(),
                };
                if last || !cal.surely_fails(&cand, ctl.rtol) {
                    decide |= last
                        || pending.len() + 1 >= MAX_PENDING
                        || cal.predicted_to_pass(&cand, ctl.rtol);
                    pending.push(cand);
                }
            }
            if decide {
                let found = {
                    let _e = events.solve.begin();
                    resolve(world, problem, state, &mut pending, ctl.rtol, &mut cal)?
                };
                if let Resolution::Inconsistent(why) = &found {
                    if root {
                        eprintln!("warning: {name}: {why} Going on without condensation.");
                    }
                    condensed = None;
                    // u^{k-1} and u^k by full solves, for this iteration's change.
                    std::mem::swap(&mut state.c, &mut state.c_prev);
                    let solved = full_solve(problem, state);
                    std::mem::swap(&mut state.c, &mut state.c_prev);
                    solved?;
                    state.u.read(|u| state.u_prev.copy_from_slice(u))?;
                    full_solve(problem, state)?;
                    let (du2, u2) = state.update_full_norms(problem, false)?;
                    let [du2, u2] = allreduce_sum(world, [du2, u2]);
                    let change = if u2 + phi2 > 0.0 {
                        ((du2 + dphi2) / (u2 + phi2)).sqrt()
                    } else {
                        0.0
                    };
                    if let Some(c) = pending.last_mut() {
                        c.out.criterion = change;
                    }
                }
                for cand in &pending {
                    state.history[cand.index][0] = cand.out.criterion;
                }
                if let Resolution::Converged(i) = found {
                    let cand = pending.swap_remove(i);
                    state.history.truncate(cand.index + 1);
                    state.inner_iterations.truncate(cand.inner_len);
                    state.restore(cand.snap);
                    out = cand.out;
                    out.converged = true;
                    break;
                }
                out.criterion = pending.last().map_or(f64::NAN, |c| c.out.criterion);
                pending.clear();
            }
        } else if others_ok && out.criterion < ctl.rtol {
            out.converged = true;
            break;
        }
        if let Some(aa) = aa.as_mut() {
            // The fixed-point residual ||T(z) - z|| in the norm of phi and lambda / r.
            let fnorm = (dphi2 + dlam2 / (r * r)).sqrt();
            if aa.step(world, state, fnorm) {
                out.anderson_rejected += 1;
            }
        }
    }
    if root && ctl.monitor && aa.is_some() {
        println!(
            "  {name}: Anderson: {} of {} evaluations at extrapolated points, {} rejected by the safeguard",
            out.anderson_steps, out.iterations, out.anderson_rejected
        );
    }
    Ok(out)
}
