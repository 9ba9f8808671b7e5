//! The choice of the augmentation parameter r (`-ubr_r auto`, the default).
//!
//! UBR's convergence depends on r through the spectrum of the contact
//! compliance `S_0 = W^{1/2} B K^{-1} B^T W^{1/2}` (over the candidate rows):
//! with eigenvalues sigma, the iteration's modes contract like
//! `|1 - r sigma| / (1 + r sigma)`-type factors, balanced when
//! `r = 1 / sqrt(sigma_min sigma_max)`. That is the rule: it depends on the
//! compliance of the body, not only on its material. Measured against a
//! sweep of r/E (`bench/run --steps 7`, bench/README.md, "Iterations against
//! r/E", 2026-11-23): the automatic r gives the sweep's best iteration count
//! on hertz_1692 (27 against 27) and one fewer on block3d_739 (17 against
//! 18 at the best grid point).
//!
//! The extreme sigma come from about 20 Lanczos steps on
//! `S_{r0} = W^{1/2} B K_{r0}^{-1} B^T W^{1/2}` with the first factorization
//! at a trial r0 (one solve per step; dense solves on the condensed
//! back-end), through `sigma = tau / (1 - r0 tau)` (Woodbury: `S_r = S_0 (I +
//! r S_0)^{-1}`). The rigid motions that only contact holds (a floating body,
//! like the paper's Hertz body: K is singular on them) are exact eigenvectors
//! of `S_{r0}` with tau = 1/r0 (sigma = infinity): they are deflated.
//!
//! The trial r0 is `M / sqrt(h L)`, M the P-wave modulus (the stiffness of
//! a constrained column), h the candidates' spacing and L the extent of the
//! contact surface: the geometric mean of the compliances of the finest
//! (h / M) and the smoothest (L / M) surface loads. The condensed back-end
//! then moves to the estimate exactly (a dense refactorization of the Schur
//! complement only); a full back-end refactorizes only when the estimate is
//! outside [r0/3, 3 r0] (Anderson's good-r window is wider than that: within
//! 25% of its best count over a factor 5-6 of r), and an iterative one keeps
//! its multigrid preconditioner.

use super::surface::Surface;
use super::Problem;
use crate::comm::{allreduce_count, allreduce_max, allreduce_sum, allreduce_sum_vec};
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::wellposed::Restraint;
use mpi::traits::*;
use nalgebra::{DMatrix, SymmetricEigen};

/// Lanczos steps at most, and at least before the estimate may be final.
const MAX_STEPS: usize = 20;
const MIN_STEPS: usize = 6;
/// Steps after which a full back-end may stop on a rough estimate.
const ROUGH_STEPS: usize = 4;
/// The estimate is final when it moved by less than this twice in a row.
const SETTLED: f64 = 0.02;
/// A full back-end refactorizes when the estimate is this far from r0.
pub const WINDOW: f64 = 3.0;
/// Where friction alone holds a rigid motion (no Dirichlet condition and
/// no contact along n restrains it: [`Restraint::friction_held`]), r is
/// the spectral estimate divided by this. The rule balances the modes of
/// the compliance; such a motion is none of them (K does not see it, and
/// the estimate deflates it), and only the sticking nodes hold it, at a
/// stiffness of r. Measured at fixed multiples of the estimate (1 rank,
/// 2026-11-29, `bench/friction_held/run.sh`: failures and iterations summed
/// over each grid): the Hertz quarter free along x and rolling, Tresca (21
/// scenes): 6 failed and 39683 iterations at 1x, 2 and 16327 at 1/3, 1 and
/// 5427 at 1/10; the same, Coulomb (36): 2 and 63713 Tresca iterations, 0
/// and 25566, 0 and 16685; the quarter held by uy = 0 only, Coulomb (30, 4
/// failing at every r: loads beyond what friction holds): 16154, 12061,
/// 17097. A third is never far from the best; a tenth loses on the last.
/// A round-nosed 2D block and a 3D dome on a tilted plane, Coulomb: 279/261,
/// 308/287, 217/130, 178/126 iterations at 1x/0.3. Bodies held by Dirichlet
/// conditions keep the estimate (block3d Coulomb: 68 iterations at 1x, 97
/// at 0.3).
pub const FRICTION_HELD: f64 = 3.0;

/// Where r came from, for the summary and the report (`r_source`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    Auto,
    Option,
}

/// The outcome of the choice.
#[derive(Clone, Debug)]
pub struct Choice {
    pub r: f64,
    pub source: Source,
    /// The trial r0 of the first factorization (auto), the spectral
    /// estimate, and the extreme eigenvalues of `S_0` found.
    pub r0: f64,
    pub estimate: f64,
    pub sigma_min: f64,
    pub sigma_max: f64,
    /// Lanczos steps (one linear solve each), and whether the matrix was
    /// refactorized for the new r.
    pub steps: usize,
    pub refactorized: bool,
    /// The estimate divided by [`FRICTION_HELD`]: friction alone holds a
    /// rigid motion.
    pub friction_held: bool,
}

/// The P-wave modulus: the stiffness of the material in a constrained
/// column (plane strain and 3D), or its plane-stress counterpart.
pub fn p_wave_modulus(young: f64, nu: f64, dim: usize, plane_stress: bool) -> f64 {
    if dim == 2 && plane_stress {
        young / (1.0 - nu * nu)
    } else {
        young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }
}

/// The trial r0 (see the module documentation).
pub fn trial<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    cs: &crate::contact::ContactSet,
    modulus: f64,
) -> f64 {
    let d = mesh.dim;
    let [wsum, count] = allreduce_sum(world, [cs.w.iter().sum::<f64>(), cs.len() as f64]);
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut lo = [f64::NEG_INFINITY; 3];
    for &v in &cs.node {
        for (c, &x) in mesh.x(v).iter().enumerate() {
            hi[c] = hi[c].max(x);
            lo[c] = lo[c].max(-x);
        }
    }
    let mut l2 = 0.0;
    for c in 0..d {
        let (h, l) = (allreduce_max(world, hi[c]), -allreduce_max(world, lo[c]));
        l2 += (h - l).powi(2);
    }
    let mean_w = if count > 0.0 { wsum / count } else { 1.0 };
    let h = if d == 2 { mean_w } else { mean_w.sqrt() };
    let l = l2.sqrt().max(h);
    modulus / (h * l).sqrt()
}

/// The entries of the Lanczos vectors: per candidate its normal row
/// (frictionless) or its components (friction), those without Dirichlet
/// data; `sqrt(w)` of each.
struct Space {
    tangential: bool,
    d: usize,
    /// Per entry: used (not all-Dirichlet).
    active: Vec<bool>,
    sqrt_w: Vec<f64>,
}

impl Space {
    fn new(surface: &Surface) -> Space {
        let (cs, d) = (surface.cs, surface.dim);
        let nc = cs.len();
        let mut active = Vec::new();
        let mut sqrt_w = Vec::new();
        for i in 0..nc {
            let sw = cs.w[i].sqrt();
            if surface.tangential {
                for c in 0..d {
                    active.push(!surface.dirichlet[i * d + c]);
                    sqrt_w.push(sw);
                }
            } else {
                let free = (0..d).any(|c| !surface.dirichlet[i * d + c] && cs.n(i)[c] != 0.0);
                active.push(free);
                sqrt_w.push(sw);
            }
        }
        Space {
            tangential: surface.tangential,
            d,
            active,
            sqrt_w,
        }
    }

    fn len(&self) -> usize {
        self.active.len()
    }

    /// `c = B^T W^{1/2} x` at the contact nodes (zero on Dirichlet components).
    fn load(&self, surface: &Surface, x: &[f64], c: &mut [f64]) {
        let d = self.d;
        for (j, v) in c.iter_mut().enumerate() {
            *v = if surface.dirichlet[j] {
                0.0
            } else if self.tangential {
                self.sqrt_w[j] * x[j]
            } else {
                let i = j / d;
                self.sqrt_w[i] * x[i] * surface.cs.n(i)[j % d]
            };
        }
    }

    /// `y = W^{1/2} B u_C`.
    fn gather(&self, surface: &Surface, uc: &[f64], y: &mut [f64]) {
        for j in 0..self.len() {
            y[j] = if !self.active[j] {
                0.0
            } else if self.tangential {
                self.sqrt_w[j] * uc[j]
            } else {
                self.sqrt_w[j] * surface.normal(uc, j)
            };
        }
    }
}

fn dot<C: Communicator>(world: &C, a: &[f64], b: &[f64]) -> f64 {
    allreduce_sum(world, [a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>()])[0]
}

/// `x -= sum (q.x) q` over `basis` (orthonormal), twice (full reorthogonalization).
fn orthogonalize<C: Communicator>(world: &C, basis: &[Vec<f64>], x: &mut [f64]) {
    for _ in 0..2 {
        if basis.is_empty() {
            return;
        }
        let local: Vec<f64> = basis
            .iter()
            .map(|q| q.iter().zip(x.iter()).map(|(a, b)| a * b).sum())
            .collect();
        let coef = allreduce_sum_vec(world, &local);
        for (q, a) in basis.iter().zip(coef) {
            for (xi, qi) in x.iter_mut().zip(q) {
                *xi -= a * qi;
            }
        }
    }
}

/// A deterministic start vector, the same whatever the rank count: a hash
/// of the node's tag in the mesh file and of the component.
fn start_vector(mesh: &LocalMesh, surface: &Surface, space: &Space) -> Vec<f64> {
    let per = if space.tangential { space.d } else { 1 };
    (0..space.len())
        .map(|j| {
            if !space.active[j] {
                return 0.0;
            }
            let tag = mesh.node_tag[surface.cs.node[j / per]];
            let mut h = tag
                .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                .wrapping_add((j % per) as u64 * 0xBF58_476D_1CE4_E5B9);
            h ^= h >> 31;
            h = h.wrapping_mul(0x94D0_49BB_1331_11EB);
            h ^= h >> 29;
            0.5 + (h >> 11) as f64 / (1u64 << 53) as f64 // in [0.5, 1.5)
        })
        .collect()
}

/// The rigid motions only contact holds, on the Lanczos space of `space`,
/// orthonormal: exact eigenvectors of the compliance, deflated.
fn deflation<C: Communicator>(
    world: &C,
    restraint: &Restraint,
    mesh: &LocalMesh,
    surface: &Surface,
    space: &Space,
) -> Vec<Vec<f64>> {
    let (nc, d) = (surface.len(), surface.dim);
    let mut deflate: Vec<Vec<f64>> = Vec::new();
    for m in &restraint.contact_held {
        let mut x = vec![0.0; space.len()];
        for i in 0..nc {
            let v = surface.cs.node[i];
            let u = restraint.bodies.displacement(m, mesh.x(v));
            if space.tangential {
                for c in 0..d {
                    if space.active[i * d + c] {
                        x[i * d + c] = space.sqrt_w[i * d + c] * u[c];
                    }
                }
            } else if space.active[i] {
                x[i] = space.sqrt_w[i] * (0..d).map(|c| u[c] * surface.cs.n(i)[c]).sum::<f64>();
            }
        }
        orthogonalize(world, &deflate, &mut x);
        let nx = dot(world, &x, &x).sqrt();
        if nx > 0.0 {
            x.iter_mut().for_each(|v| *v /= nx);
            deflate.push(x);
        }
    }
    deflate
}

/// The eigenvalues sigma of `S_0` from the Ritz values tau of the Lanczos
/// tridiagonal matrix (`alpha`, `beta`) of `S_{r0}`: `sigma = tau / (1 - r0
/// tau)`, those that map.
fn ritz_sigmas(alpha: &[f64], beta: &[f64], r0: f64) -> Vec<f64> {
    let m = alpha.len();
    let mut t = DMatrix::<f64>::zeros(m, m);
    for i in 0..m {
        t[(i, i)] = alpha[i];
        if i + 1 < m {
            t[(i, i + 1)] = beta[i];
            t[(i + 1, i)] = beta[i];
        }
    }
    let eig = SymmetricEigen::new(t);
    eig.eigenvalues
        .iter()
        .filter(|&&tau| tau > 0.0 && r0 * tau < 1.0 - 1e-6)
        .map(|&tau| tau / (1.0 - r0 * tau))
        .collect()
}

/// The extreme eigenvalues of `S_0` from Lanczos on `S_{r0}`; returns
/// (sigma_min, sigma_max, steps), or None when the space is too small.
pub fn spectrum<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    restraint: &Restraint,
    mesh: &LocalMesh,
    monitor: bool,
) -> Result<Option<(f64, f64, usize)>, Error> {
    let r0 = problem.r();
    let decide_only = !problem.lin.is_condensed();
    let d = problem.dim;
    let work = problem.lin.rhs0.duplicate()?;
    let Problem {
        contact,
        dirichlet,
        tangential,
        lin,
        ..
    } = problem;
    let surface = Surface {
        cs: contact,
        dim: d,
        tangential: *tangential,
        dirichlet: &dirichlet.contact,
    };
    let space = Space::new(&surface);
    let nc = surface.len();
    // The rigid motions only contact holds: exact eigenvectors, deflated.
    let deflate = deflation(world, restraint, mesh, &surface, &space);
    let active = allreduce_count(world, space.active.iter().filter(|&&a| a).count());
    let dim = active.saturating_sub(deflate.len());
    if dim < 2 {
        return Ok(None);
    }
    if lin.iterative && lin.adaptive_inner {
        // The Lanczos vectors' solves start from zero; the iterative path
        // only decides whether to move r (the preconditioner is kept either
        // way), for which the extreme Ritz values of inexact products (CG to
        // 1e-2) are close enough, at a few CG steps each.
        lin.set_inner_rtol(1e-2)?;
    }
    let steps_max = MAX_STEPS.min(dim);
    let mut q = start_vector(mesh, &surface, &space);
    orthogonalize(world, &deflate, &mut q);
    let nq = dot(world, &q, &q).sqrt();
    q.iter_mut().for_each(|v| *v /= nq);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let (mut alpha, mut beta) = (Vec::new(), Vec::<f64>::new());
    let mut c = vec![0.0; nc * d];
    let mut uc = vec![0.0; nc * d];
    let mut w = vec![0.0; space.len()];
    let mut last: Option<f64> = None;
    let mut extremes: Option<(f64, f64)> = None;
    let mut settled = 0;
    let mut result = None;
    for step in 0..steps_max {
        space.load(&surface, &q, &mut c);
        lin.solve_homogeneous(&surface, &c, &mut uc, &work)?;
        space.gather(&surface, &uc, &mut w);
        let a = dot(world, &q, &w);
        alpha.push(a);
        basis.push(q.clone());
        orthogonalize(world, &deflate, &mut w);
        orthogonalize(world, &basis, &mut w);
        let b = dot(world, &w, &w).sqrt();
        // Ritz values of the tridiagonal matrix so far.
        let sigmas = ritz_sigmas(&alpha, &beta, r0);
        if let (Some(lo), Some(hi)) = (
            sigmas.iter().copied().reduce(f64::min),
            sigmas.iter().copied().reduce(f64::max),
        ) {
            let r = 1.0 / (lo * hi).sqrt();
            if let Some(prev) = last {
                settled = if (r - prev).abs() <= SETTLED * r {
                    settled + 1
                } else {
                    0
                };
            }
            crate::progress::tick(|| format!("r choice: Lanczos step {}, r = {r:.4e}", step + 1));
            if monitor && world.rank() == 0 {
                println!(
                    "  r choice  Lanczos step {:2}: sigma in [{lo:.4e}, {hi:.4e}], r = {r:.4e} (trial {r0:.4e})",
                    step + 1
                );
            }
            // A full back-end only decides whether to refactorize: an estimate
            // settled to 10% and 30% away from the window's edges decides it.
            // Settled means both extremes, not r alone: a smallest sigma still
            // falling and a largest still rising move r in opposite ways (a
            // nearly incompressible body, nu 0.49: r moved 6.5% from step 3
            // to 4, at 3.6e4, while sigma_max rose 39%; 20 steps gave 9.5e3).
            let ratio = (r / r0).ln().abs();
            let clear = (ratio - WINDOW.ln()).abs() > 1.3f64.ln();
            let near = |a: f64, b: f64| (a - b).abs() <= 0.1 * a;
            let rough = extremes.is_some_and(|(plo, phi)| near(lo, plo) && near(hi, phi));
            extremes = Some((lo, hi));
            last = Some(r);
            result = Some((lo, hi, step + 1));
            if step + 1 >= MIN_STEPS && settled >= 2 {
                break;
            }
            if decide_only && clear && rough && step + 1 >= ROUGH_STEPS {
                break;
            }
        }
        if b.is_nan() || b <= 1e-12 * a.abs() {
            break; // an invariant subspace: the spectrum is found
        }
        beta.push(b);
        q = w.iter().map(|v| v / b).collect();
    }
    Ok(result)
}

/// Chooses r: the user's value, or the automatic one (see the module
/// documentation), moving the back-end to it where that is worth it.
pub fn choose<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    restraint: &Restraint,
    mesh: &LocalMesh,
    auto: bool,
    monitor: bool,
) -> Result<Choice, Error> {
    let r0 = problem.r();
    let mut choice = Choice {
        r: r0,
        source: if auto { Source::Auto } else { Source::Option },
        r0,
        estimate: f64::NAN,
        sigma_min: f64::NAN,
        sigma_max: f64::NAN,
        steps: 0,
        refactorized: false,
        friction_held: false,
    };
    if !auto {
        return Ok(choice);
    }
    let Some((lo, hi, steps)) = spectrum(world, problem, restraint, mesh, monitor)? else {
        return Ok(choice);
    };
    let spectral = 1.0 / (lo * hi).sqrt();
    choice.estimate = spectral;
    choice.friction_held = problem.tangential && restraint.friction_held.is_some();
    let estimate = match choice.friction_held {
        true => spectral / FRICTION_HELD,
        false => spectral,
    };
    choice.sigma_min = lo;
    choice.sigma_max = hi;
    choice.steps = steps;
    let condensed = problem.lin.is_condensed();
    let outside = estimate > WINDOW * r0 || estimate < r0 / WINDOW;
    if condensed || outside {
        let start = problem.owned_start;
        let surface = Surface {
            cs: &problem.contact,
            dim: problem.dim,
            tangential: problem.tangential,
            dirichlet: &problem.dirichlet.contact,
        };
        problem.lin.set_r(&surface, estimate, start)?;
        choice.r = estimate;
        choice.refactorized = !condensed && !problem.lin.iterative;
    }
    Ok(choice)
}
