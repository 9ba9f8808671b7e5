//! The iterate that lives on the contact surface (the operators B and
//! B^T W of the contact set are [`crate::contact::surface`]).

use super::seat::Seat;
use super::Problem;
pub use crate::contact::surface::Surface;
use crate::error::Error;
use crate::petsc::Vector;

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
    /// Quasi-static friction (a load history): the tangential displacement
    /// at the end of the previous load step (`dim` values per candidate),
    /// from which the friction law (5.5) measures the slip of this step;
    /// empty: the paper's static law (the slip from the undeformed state).
    /// A cold start keeps it.
    pub slip_origin: Vec<f64>,
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
            slip_origin: Vec::new(),
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
    /// The plain iteration's contraction K the last run measured above
    /// round-off ([`crate::solver::stopping::Accuracy::seeded`]), for a
    /// run whose residuals are all at round-off, started warm at its
    /// answer: CF-FP's Tresca solve at the fixed point, a load step that
    /// changes nothing (one matrix and r: nearly the same map). Its
    /// estimate was infinite, and such runs failed (exit 3). Kept by
    /// [`UbrState::reset`].
    pub contraction: Option<f64>,
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
            contraction: None,
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
