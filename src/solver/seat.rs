//! The rigid approach: a body that only the contact holds along some rigid
//! motion, and that starts away from the obstacle (a gap) or tilted onto
//! part of it, is first moved rigidly onto the obstacle, and UBR starts
//! from there.
//!
//! **Why.** Along a rigid motion m that no Dirichlet condition restrains,
//! K m = 0 and only the augmentation springs `r B^T W B` hold the body in
//! `K_r`. While no candidate touches, the projection (4.15) resets the
//! springs to where the body is (`phi = u_n`), so each UBR iteration moves
//! the body by the same `F / (r sum w)` along m: the map on the contact
//! surface has the eigenvalue 1 there (`r S_r -> 1` on the deflated modes of
//! [`super::penalty`]), and no acceleration shortens a translation. A steel
//! block 0.1 mm above the floor falls about 1e-10 m an iteration and needs
//! a million of them; a body resting on one corner turns as slowly. The
//! paper's scenes start touching (section 7: the cylinder's lowest point
//! lies on the foundation), where the question does not arise.
//!
//! **What.** The rigid part of the problem is small: with the motions'
//! coefficients a (k of them, a few per body), the rigid body on the
//! augmentation springs minimizes the convex piecewise quadratic
//!
//! `Pi(a) = -b.a + r/2 sum_i w_i [ ((A a)_i - g_i)^+^2 + |(T a)_i|^2 ]`,
//!
//! with `b_j = f . m_j` the load's work on each motion, `(A a)_i` the
//! normal and `(T a)_i` the tangential displacement of candidate i (the
//! tangential springs only where the matrix has them, with friction). Its
//! minimizer rests on the obstacle with the rigid body's contact pressures
//! `r ((A a)_i - g_i)^+`, which balance the load on every such motion. It is
//! found by a semi-smooth Newton method with an exact line search (k
//! unknowns, reductions over the ranks only). UBR then starts from
//! `phi^{-1} = A a`, `lambda^0 = r (A a - g)^+`: its first solve gives the
//! rigid placement plus the elastic response to a balanced load.
//!
//! **When.** The paper's initialization (`phi^{-1} = lambda^0 = 0`) is kept
//! when it already holds the body: when the contact set of its first
//! step's rigid part (the load on the springs of every candidate,
//! `a_0 = H^{-1} b`) restrains every such motion. Otherwise (a gap, a body on
//! a corner) the approach runs. So the paper's Hertz scene and every scene
//! that starts touching keep the paper's iterates.

use super::Problem;
use crate::comm::{allreduce_max_n, allreduce_sum, allreduce_sum_vec};
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::wellposed::Restraint;
use mpi::traits::*;
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Newton steps at most.
const MAX_NEWTON: usize = 100;
/// Line-search evaluations at most per step.
const MAX_SEARCH: usize = 200;
/// A motion is restrained by a contact set when its eigenvalue of the
/// set's Hessian is above this fraction of the largest eigenvalue of the
/// Hessian with every candidate touching.
const HELD_TOL: f64 = 1e-9;
/// Newton stops at this gradient, relative to the load's work |b|; a start
/// further than `ACCEPT_TOL` from the rigid minimizer is not used.
const GRAD_TOL: f64 = 1e-10;
const ACCEPT_TOL: f64 = 1e-6;
/// The line search stops on a bracket this narrow (relative), or a slope
/// this small against the initial one.
const SEARCH_TOL: f64 = 1e-12;

/// The start of UBR after the rigid approach, per owned candidate.
#[derive(Clone, Debug)]
pub struct Seat {
    /// `phi^{-1} = (A a)_i`, `lambda^0 = r ((A a)_i - g_i)^+`.
    pub phi_n: Vec<f64>,
    pub lambda_n: Vec<f64>,
    /// The rigid motion's largest displacement of a candidate along n, and
    /// the number of candidates its rigid body touches (for the summary).
    pub approach: f64,
    pub touching: usize,
}

/// The rigid rows of the owned candidates: `A_i` (k values) and, with the
/// tangential springs, `T_i` (d x k, component-major), and the load's work.
struct Rigid {
    k: usize,
    d: usize,
    tangential: bool,
    a: Vec<f64>,
    t: Vec<f64>,
    w: Vec<f64>,
    g: Vec<f64>,
    r: f64,
    b: DVector<f64>,
}

impl Rigid {
    fn new<C: Communicator>(
        world: &C,
        mesh: &LocalMesh,
        restraint: &Restraint,
        problem: &Problem,
        load: &[f64],
    ) -> Rigid {
        let modes = &restraint.contact_held;
        let bodies = &restraint.bodies;
        let k = modes.len();
        let d = problem.dim;
        let cs = &problem.contact;
        let tangential = problem.tangential;
        let nc = cs.len();
        let mut a = vec![0.0; nc * k];
        let mut t = vec![0.0; if tangential { nc * k * d } else { 0 }];
        for (i, &v) in cs.node.iter().enumerate() {
            let x = mesh.x(v);
            for (j, m) in modes.iter().enumerate() {
                if bodies.node_body[v] != m.body {
                    continue;
                }
                let u = bodies.displacement(m, x);
                let n = cs.n(i);
                let un: f64 = (0..d).map(|c| u[c] * n[c]).sum();
                a[i * k + j] = un;
                if tangential {
                    for c in 0..d {
                        t[(i * d + c) * k + j] = u[c] - un * n[c];
                    }
                }
            }
        }
        // b_j = f . m_j over the owned nodes.
        let mut b = vec![0.0; k];
        for v in 0..mesh.owned_count {
            let x = mesh.x(v);
            for (j, m) in modes.iter().enumerate() {
                if bodies.node_body[v] != m.body {
                    continue;
                }
                let u = bodies.displacement(m, x);
                b[j] += (0..d).map(|c| load[v * d + c] * u[c]).sum::<f64>();
            }
        }
        let b = DVector::from_vec(allreduce_sum_vec(world, &b));
        Rigid {
            k,
            d,
            tangential,
            a,
            t,
            w: cs.w.clone(),
            g: cs.g.clone(),
            r: problem.r(),
            b,
        }
    }

    fn row(&self, i: usize) -> &[f64] {
        &self.a[i * self.k..(i + 1) * self.k]
    }

    fn dot(row: &[f64], x: &DVector<f64>) -> f64 {
        row.iter().zip(x.iter()).map(|(p, q)| p * q).sum()
    }

    /// The gradient and the Hessian of Pi at `x` (the Hessian of the
    /// candidates with `(A x)_i > g_i`, or of all with `all`), reduced.
    fn derivatives<C: Communicator>(
        &self,
        world: &C,
        x: &DVector<f64>,
        all: bool,
    ) -> (DVector<f64>, DMatrix<f64>) {
        let (k, d) = (self.k, self.d);
        // [gradient (k), Hessian (k x k)]
        let mut buf = vec![0.0; k + k * k];
        for i in 0..self.w.len() {
            let rw = self.r * self.w[i];
            let row = self.row(i);
            let s = Self::dot(row, x) - self.g[i];
            if s > 0.0 || all {
                for p in 0..k {
                    if s > 0.0 {
                        buf[p] += rw * s * row[p];
                    }
                    for q in 0..k {
                        buf[k + p * k + q] += rw * row[p] * row[q];
                    }
                }
            }
            if self.tangential {
                for c in 0..d {
                    let tr = &self.t[(i * d + c) * k..(i * d + c + 1) * k];
                    let tx = Self::dot(tr, x);
                    for p in 0..k {
                        buf[p] += rw * tx * tr[p];
                        for q in 0..k {
                            buf[k + p * k + q] += rw * tr[p] * tr[q];
                        }
                    }
                }
            }
        }
        let buf = allreduce_sum_vec(world, &buf);
        let grad = DVector::from_column_slice(&buf[..k]) - &self.b;
        let hess = DMatrix::from_row_slice(k, k, &buf[k..]);
        (grad, hess)
    }

    /// `dPi(x + s p) / ds`, reduced.
    fn slope<C: Communicator>(&self, world: &C, x: &DVector<f64>, p: &DVector<f64>, s: f64) -> f64 {
        let (k, d) = (self.k, self.d);
        let y = x + p * s;
        let mut acc = 0.0;
        for i in 0..self.w.len() {
            let rw = self.r * self.w[i];
            let row = self.row(i);
            let over = Self::dot(row, &y) - self.g[i];
            if over > 0.0 {
                acc += rw * over * Self::dot(row, p);
            }
            if self.tangential {
                for c in 0..d {
                    let tr = &self.t[(i * d + c) * k..(i * d + c + 1) * k];
                    acc += rw * Self::dot(tr, &y) * Self::dot(tr, p);
                }
            }
        }
        allreduce_sum_vec(world, &[acc])[0] - self.b.dot(p)
    }
}

/// Whether the Hessian `h` restrains every motion, against `full`'s scale.
fn restrains(h: &DMatrix<f64>, full_max: f64) -> bool {
    let eig = SymmetricEigen::new(h.clone());
    eig.eigenvalues.iter().all(|&l| l > HELD_TOL * full_max)
}

/// The exact line search of the rigid approach from `x` along `p` (`s0`:
/// the slope at 0, negative): the step where the slope, non-decreasing
/// and piecewise linear, vanishes; None when it never does (unbounded).
fn line_search<C: Communicator>(
    world: &C,
    rigid: &Rigid,
    x: &DVector<f64>,
    p: &DVector<f64>,
    s0: f64,
) -> Option<f64> {
    // Bracket the zero of the (non-decreasing, piecewise linear) slope.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let (mut f_lo, mut f_hi) = (s0, rigid.slope(world, x, p, hi));
    let mut n = 0;
    while f_hi < 0.0 && n < MAX_SEARCH {
        lo = hi;
        f_lo = f_hi;
        hi *= 4.0;
        f_hi = rigid.slope(world, x, p, hi);
        n += 1;
    }
    if f_hi < 0.0 {
        return None;
    }
    // The secant point of the bracket (exact once no kink is left in
    // it), or its middle (geometric where it spans decades) when the
    // secant does not halve it.
    let mut s = hi;
    while n < MAX_SEARCH && hi - lo > SEARCH_TOL * hi {
        let secant = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        let middle = if lo > 0.0 && hi > 16.0 * lo {
            (lo * hi).sqrt()
        } else {
            0.5 * (lo + hi)
        };
        let width = hi - lo;
        let f_sec = rigid.slope(world, x, p, secant);
        n += 1;
        s = secant;
        if f_sec.abs() <= SEARCH_TOL * s0.abs() {
            break;
        }
        if f_sec < 0.0 {
            (lo, f_lo) = (secant, f_sec);
        } else {
            (hi, f_hi) = (secant, f_sec);
        }
        if hi - lo > 0.5 * width && middle > lo && middle < hi {
            let f_mid = rigid.slope(world, x, p, middle);
            n += 1;
            s = middle;
            if f_mid < 0.0 {
                (lo, f_lo) = (middle, f_mid);
            } else {
                (hi, f_hi) = (middle, f_mid);
            }
        }
    }
    Some(s)
}

/// The rigid approach (see the module documentation): None when the
/// paper's initialization holds the body already, when no rigid motion is
/// held by contact alone, or when the rigid problem has no minimizer (the
/// loads pull the body away: the checks of the scene and of the answer
/// name that).
pub fn approach<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    restraint: &Restraint,
    problem: &Problem,
) -> Result<Option<Seat>, Error> {
    if restraint.contact_held.is_empty() {
        return Ok(None);
    }
    let load = problem.load.read(|f| f.to_vec())?;
    let rigid = Rigid::new(world, mesh, restraint, problem, &load);
    let k = rigid.k;
    let zero = DVector::<f64>::zeros(k);
    let (_, full) = rigid.derivatives(world, &zero, true);
    let full_max = SymmetricEigen::new(full.clone())
        .eigenvalues
        .iter()
        .fold(0.0f64, |m, &l| m.max(l));
    if full_max <= 0.0 {
        return Ok(None);
    }
    let Some(full_inv) = full.clone().try_inverse() else {
        return Ok(None);
    };
    // The paper's first step: the load on the springs of every candidate.
    let a0 = &full_inv * &rigid.b;
    let (_, h0) = rigid.derivatives(world, &a0, false);
    if restrains(&h0, full_max) {
        return Ok(None);
    }
    // Semi-smooth Newton on Pi with an exact line search; the Hessian of
    // the touching candidates is regularized by a trace of the full one,
    // so that where nothing touches the step is along H^{-1} (-grad),
    // stretched until the line search meets the obstacle.
    let eps = 1e-10;
    let mut x = zero;
    let scale = rigid.b.norm().max(f64::MIN_POSITIVE);
    for _ in 0..MAX_NEWTON {
        let (grad, h) = rigid.derivatives(world, &x, false);
        let gn = grad.norm();
        // A start needs no more; round-off (r w (A x - g) against b) sets
        // a floor near 1e-11 of the load.
        if gn <= GRAD_TOL * scale {
            break;
        }
        let m = &h + &full * eps;
        let Some(p) = m.cholesky().map(|c| -c.solve(&grad)) else {
            break;
        };
        let s0 = grad.dot(&p);
        if s0 >= 0.0 {
            break;
        }
        let Some(s) = line_search(world, &rigid, &x, &p, s0) else {
            return Ok(None); // unbounded: the loads pull the body away
        };
        let step = &p * s;
        x += &step;
        if step.norm() <= 1e-14 * x.norm() {
            break; // no progress left at this precision
        }
    }
    let (grad, _) = rigid.derivatives(world, &x, false);
    if grad.norm() > ACCEPT_TOL * scale {
        return Ok(None);
    }
    let nc = rigid.w.len();
    let mut phi_n = vec![0.0; nc];
    let mut lambda_n = vec![0.0; nc];
    let (mut approach, mut touching) = (0.0f64, 0.0);
    for i in 0..nc {
        let an = Rigid::dot(rigid.row(i), &x);
        phi_n[i] = an;
        let over = an - rigid.g[i];
        if over > 0.0 {
            lambda_n[i] = rigid.r * over;
            touching += 1.0;
        }
        approach = approach.max(an.abs());
    }
    let [approach] = allreduce_max_n(world, [approach]);
    let [touching] = allreduce_sum(world, [touching]);
    Ok(Some(Seat {
        phi_n,
        lambda_n,
        approach,
        touching: touching as usize,
    }))
}
