//! The contact surface: the operators B and B^T W of the contact set, and
//! the iterate that lives on it.
//!
//! Unknowns at the contact nodes are stored candidate by candidate: `u_C`
//! has component c of candidate i at `i * dim + c`. `B u = (u_n, u_t)` with
//! `u_n = u.n` and `u_t = u - u_n n` (2.1); `B^T W (v_n, v_t)` is the nodal
//! force `w_i (v_n n + v_t)` (nodal quadrature of `(v, B u)_{Gamma_c}`),
//! zero on the components that carry a Dirichlet condition (their rows are
//! eliminated from the linear system).

use super::seat::Seat;
use super::Problem;
use crate::contact::ContactSet;
use crate::error::Error;
use crate::petsc::Vector;

/// B and B^T W of the candidates owned by this rank.
pub struct Surface<'a> {
    pub cs: &'a ContactSet,
    pub dim: usize,
    /// Whether the tangential part is in play (friction).
    pub tangential: bool,
    /// Per contact unknown (`i * dim + c`): a Dirichlet component.
    pub dirichlet: &'a [bool],
}

impl Surface<'_> {
    pub fn len(&self) -> usize {
        self.cs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cs.is_empty()
    }

    /// `u_n` of candidate i from `u_C`.
    #[inline]
    pub fn normal(&self, uc: &[f64], i: usize) -> f64 {
        let d = self.dim;
        let n = &self.cs.n;
        (0..d).map(|c| uc[i * d + c] * n[c]).sum()
    }

    /// `u_t` of candidate i from `u_C`, given its `u_n`.
    #[inline]
    pub fn tangential_part(&self, uc: &[f64], i: usize, un: f64, out: &mut [f64]) {
        let d = self.dim;
        for c in 0..d {
            out[c] = uc[i * d + c] - un * self.cs.n[c];
        }
    }

    /// The contact load `B^T W (v_n, v_t)` at the contact nodes, where
    /// candidate i has `v_n = vn(i)` and (with friction) `v_t = vt(i, c)`.
    pub fn load(
        &self,
        vn: impl Fn(usize) -> f64,
        vt: impl Fn(usize, usize) -> f64,
        out: &mut [f64],
    ) {
        let d = self.dim;
        let n = &self.cs.n;
        for i in 0..self.len() {
            let w = self.cs.w[i];
            let sn = w * vn(i);
            for c in 0..d {
                out[i * d + c] = if self.dirichlet[i * d + c] {
                    0.0
                } else if self.tangential {
                    sn * n[c] + w * vt(i, c)
                } else {
                    sn * n[c]
                };
            }
        }
    }

    /// The contact block `M_i` of `B^T W B` at candidate i (`w n n^T`, or
    /// `w I` with friction), applied to `u_C` and kept on the components
    /// without a Dirichlet condition: `out = M u_C` there.
    pub fn apply_contact_block(&self, uc: &[f64], out: &mut [f64]) {
        let d = self.dim;
        for i in 0..self.len() {
            let w = self.cs.w[i];
            let un = self.normal(uc, i);
            for c in 0..d {
                out[i * d + c] = if self.dirichlet[i * d + c] {
                    0.0
                } else if self.tangential {
                    w * uc[i * d + c]
                } else {
                    w * un * self.cs.n[c]
                };
            }
        }
    }
}

/// The UBR iterate on the contact surface (and the whole displacement),
/// kept between runs for warm starts (CF-FP) and read by the report.
/// Per candidate: normal values at `i`, tangential vectors (global
/// components, tangent to n) at `i * dim..(i + 1) * dim`.
#[derive(Clone)]
pub struct SurfaceState {
    /// Auxiliary variables phi (after the last projection).
    pub phi_n: Vec<f64>,
    pub phi_t: Vec<f64>,
    /// Multipliers lambda (the algorithm's; after the last update).
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
}

impl SurfaceState {
    pub fn new(nc: usize, d: usize) -> SurfaceState {
        SurfaceState {
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
        }
    }

    fn zero(&mut self) {
        for v in [
            &mut self.phi_n,
            &mut self.phi_t,
            &mut self.lambda_n,
            &mut self.lambda_t,
            &mut self.stress_n,
            &mut self.stress_t,
            &mut self.un,
            &mut self.ut,
        ] {
            v.iter_mut().for_each(|x| *x = 0.0);
        }
        self.in_contact.iter_mut().for_each(|x| *x = false);
        self.slip.iter_mut().for_each(|x| *x = false);
    }
}

/// What a contact algorithm leaves: the surface iterate, the whole
/// displacement, and the history for the report and plots.
pub struct UbrState {
    pub dim: usize,
    pub surface: SurfaceState,
    /// The whole displacement u^k (after the run; a condensed run computes
    /// it at the end).
    pub u: Vector,
    /// Inner (KSP) iterations of every linear solve so far.
    pub inner_iterations: Vec<usize>,
    /// Per outer iteration: the paper's change (4.16)/(5.6) (NaN where not
    /// computed), the constraint residual, and the error estimate (NaN in
    /// the paper's mode).
    pub history: Vec<[f64; 3]>,
    /// The largest contact stress seen since the cold start (the scale of
    /// the held-body tests when nothing touches; kept across warm starts).
    pub peak_stress: f64,
    /// Whether the iterate is the paper's initialization (phi = lambda = 0).
    pub cold: bool,
    /// The largest contact stress of the first evaluation after the cold
    /// start: the stress scale of the accuracy test when nothing touches
    /// (a load-made scale, which no extrapolation inflates).
    pub stress_scale: f64,
    /// The start after the rigid approach ([`super::seat`]), used at every
    /// cold start instead of the paper's zero (None: the paper's).
    pub seat: Option<Seat>,
}

impl UbrState {
    /// The paper's initialization: phi^{-1} = 0, lambda^0 = 0, u = 0.
    pub fn new(problem: &Problem) -> Result<UbrState, Error> {
        let u = problem.lin.rhs0.duplicate()?;
        u.set(0.0)?;
        Ok(UbrState {
            dim: problem.dim,
            surface: SurfaceState::new(problem.contact.len(), problem.dim),
            u,
            inner_iterations: Vec::new(),
            history: Vec::new(),
            peak_stress: 0.0,
            cold: true,
            stress_scale: 0.0,
            seat: None,
        })
    }

    /// Starts from the rigid approach's `seat` (and at every later cold
    /// start): `phi^{-1} = A a`, `lambda^0` the rigid body's pressures.
    pub fn set_seat(&mut self, seat: Option<Seat>) {
        self.seat = seat;
        self.apply_seat();
    }

    fn apply_seat(&mut self) {
        if let Some(seat) = &self.seat {
            self.surface.phi_n.copy_from_slice(&seat.phi_n);
            self.surface.lambda_n.copy_from_slice(&seat.lambda_n);
        }
    }

    /// Back to the start (a cold start): the paper's initialization, or
    /// the rigid approach's seat.
    pub fn reset(&mut self) -> Result<(), Error> {
        self.surface.zero();
        self.peak_stress = 0.0;
        self.cold = true;
        self.stress_scale = 0.0;
        self.apply_seat();
        self.u.set(0.0)
    }
}
