//! Iterates that move without bound: Anderson's retreat to the plain
//! iteration, and the error that names what holds the bodies.
//!
//! Anderson's extrapolation can stagnate on a Tresca problem that has a
//! solution: its residual flat while z moves along a direction the residual
//! does not see, and the iterates drift (the Hertz quarter without its
//! symmetry condition, Coulomb 0.3 and a sideways load of a tenth of the
//! normal one: CF-FP's third Tresca solve moved a contact node 1e7 with its
//! residual P flat at 0.143, while the plain iteration from the same bound
//! converges in 1038 iterations). Such a run goes back to the evaluation of
//! its smallest residual and goes on with the plain iteration, which
//! converges wherever a solution exists (Koko 2010, Theorem 4.1). The best
//! of Anderson's iterates may have drifted already, its residual flat (the
//! Hertz quarter held by uy = 0 on its cut, free along x, Tresca s = 22,
//! a sideways load of 240: P flat at 0.1254 from iteration 74, the plain
//! iteration from its best at 169 flat too for 500 iterations, where the
//! plain iteration from the start converges in 782): where the plain
//! iteration drifts or stalls too, it starts again from the run's start,
//! once, and only if that drifts or stalls is the run stopped. (CF-FP
//! halves such a step of its bound first, which is cheaper:
//! [`super::super::UbrControl::retreat`].)

use super::super::measures::{Maxima, Sums};
use super::super::messages::r_far_words;
use super::Run;
use crate::error::Error;
use crate::solver::stopping::{Accuracy, Progress};
use crate::solver::surface::{SurfaceState, UbrState};
use mpi::traits::*;

/// The plain iterate after the evaluation of Anderson's smallest residual,
/// and whether (at which iteration) the run has gone back to it.
pub(super) struct Retreat {
    /// The smallest residual P of the run, at iteration `best_k`.
    best: f64,
    best_k: usize,
    /// phi_n, phi_t, lambda_n, lambda_t, u_n, u_t after that evaluation.
    point: [Vec<f64>; 6],
    /// The same at the run's start, where `kept` (no retreat can come
    /// otherwise; the same on every rank, unlike the vectors' lengths).
    origin: [Vec<f64>; 6],
    kept: bool,
    /// Whether the plain iteration has started again from `origin`.
    pub restarted: bool,
    /// The accuracy test as the run started.
    start: Accuracy,
    /// The iteration at which Anderson's iterates drifted (None: they have not).
    pub at: Option<usize>,
    /// The last evaluation at which nothing touched.
    untouched: Option<usize>,
}

/// Evaluations with nodes in contact, in a row, that make a drift
/// Anderson's, not a body the loads pull off (where nothing touches, the
/// loads pull the body off whatever the iteration: a history step of the
/// Hertz Tresca scene with the load reversed drifted with one node
/// touching now and then, and was called two things at random).
const TOUCHING: usize = 10;

impl Retreat {
    /// `state`: the run's start, kept where `keep` (Anderson on, and its
    /// caller lets the run go on plain).
    pub(super) fn new(start: &Accuracy, state: &UbrState, keep: bool) -> Retreat {
        let mut origin: [Vec<f64>; 6] = Default::default();
        if keep {
            copy_point(&mut origin, &state.surface);
        }
        Retreat {
            best: f64::INFINITY,
            best_k: 0,
            point: Default::default(),
            origin,
            kept: keep,
            restarted: false,
            start: start.clone(),
            at: None,
            untouched: None,
        }
    }
}

impl<C: Communicator> Run<'_, C> {
    /// Anderson: keeps the plain iterate of an evaluation whose residual P
    /// is the smallest so far (the projection's phi and lambda, before the
    /// extrapolation replaces them), and notes one where nothing touches.
    pub(super) fn keep_best(&mut self, p: f64, touching: bool) {
        let rt = &mut self.retreat;
        if !touching {
            rt.untouched = Some(self.k);
        }
        // A warm start's first evaluation measures the run before, not this
        // bound's iteration (CF-FP's Tresca solves: 4.0e-8 there, 6.9e-3
        // next); taken for the smallest, its point was the start again.
        let warm_first = self.k == 0 && !self.cold;
        if self.aa.is_none() || rt.at.is_some() || p.is_nan() || p >= rt.best || warm_first {
            return;
        }
        rt.best = p;
        rt.best_k = self.k;
        copy_point(&mut rt.point, &self.state.surface);
    }

    /// Anderson's iterates drift or stall (`why`, for the monitor): goes
    /// back to the plain iterate of the smallest residual, and on without
    /// Anderson; where that plain iteration drifts or stalls too, to the
    /// run's start, once. False where the run was plain from its start (the
    /// drift or the stall is the problem's), where its caller goes on
    /// otherwise ([`super::super::UbrControl::retreat`]), where nothing
    /// touched lately ([`TOUCHING`]), or where both were tried.
    pub(super) fn retreat(&mut self, why: std::fmt::Arguments) -> bool {
        let rt = &mut self.retreat;
        // An r far from the trial r0 is the cause the failure names.
        let far = self.ctl.r_far.is_some();
        let lately = rt.untouched.is_some_and(|k| self.k < k + TOUCHING);
        if !self.ctl.retreat || far || lately {
            return false;
        }
        let first = self.aa.is_some() && rt.at.is_none() && rt.best.is_finite();
        let again = rt.at.is_some() && !rt.restarted && rt.kept;
        let (point, whence) = if first {
            rt.at = Some(self.k);
            self.out.anderson_retreats = 1;
            let whence = format!(
                "the plain iteration from the evaluation of the smallest residual P ({:.3e}, iteration {})",
                rt.best, rt.best_k
            );
            (&rt.point, whence)
        } else if again {
            rt.restarted = true;
            self.out.plain_restarts = 1;
            (
                &rt.origin,
                "the plain iteration again from the run's start".into(),
            )
        } else {
            return false;
        };
        let st = &mut self.state.surface;
        let to = [
            &mut st.phi_n,
            &mut st.phi_t,
            &mut st.lambda_n,
            &mut st.lambda_t,
            &mut st.un,
            &mut st.ut,
        ];
        for (to, from) in to.into_iter().zip(point) {
            to.copy_from_slice(from);
        }
        self.aa = None;
        self.z_in = None;
        // The plain iteration's own tests: its residuals and contraction,
        // none of the drift's.
        self.acc = rt.start.clone();
        // From the start of a warm run, the first evaluation is the warm
        // start's again, not a residual to beat (the rolling quarter's
        // Tresca solve: 4.0e-8 there, then converging from 6.9e-3 but
        // called stalled 500 iterations later).
        self.progress = Progress::new(first || self.cold);
        self.drifting = 0;
        if self.root && self.ctl.monitor {
            let whose = if first {
                "Anderson's iterates"
            } else {
                "the plain iterates"
            };
            println!(
                "  {}: {whose} {why} at iteration {}: {whence}",
                self.name, self.k
            );
        }
        true
    }
}

/// phi_n, phi_t, lambda_n, lambda_t, u_n, u_t of `st` into `to` (its
/// buffers reused).
fn copy_point(to: &mut [Vec<f64>; 6], st: &SurfaceState) {
    let from = [
        &st.phi_n,
        &st.phi_t,
        &st.lambda_n,
        &st.lambda_t,
        &st.un,
        &st.ut,
    ];
    for (to, from) in to.iter_mut().zip(from) {
        to.clone_from(from);
    }
}

/// The error of iterates that move without bound: what holds the bodies
/// and what to try.
/// `first`: the largest displacement of a contact node at the first
/// iterate, where ten times it is above the drift limit.
pub(super) fn unbounded<C: Communicator>(
    run: &Run<'_, C>,
    sums: &Sums,
    ext: &Maxima,
    first: f64,
) -> Error {
    let (name, k, ctl) = (run.name, run.k, run.ctl);
    if let Some(r0) = ctl.r_far {
        return Error::NotConverged(format!(
            "{name}: the iterates move without bound (a contact node has moved {:.3e} after {k} iterations): {}",
            ext.umax,
            r_far_words(run.r, r0)
        ));
    }
    let what = if sums.contact == 0.0 {
        "no node touches the obstacle".to_string()
    } else if run.friction_bound.is_some() && sums.stick == 0.0 && !run.no_friction {
        format!(
            "every one of the {} contact nodes slips: friction cannot hold the loads (their tangential part, or their moment) with the pressures this body develops, and the body slides or rolls",
            sums.contact
        )
    } else {
        format!("{} nodes touch the obstacle", sums.contact)
    };
    let scale = if 10.0 * first > ctl.drift_limit {
        format!("its largest displacement at the first iterate ({first:.3e})")
    } else {
        format!(
            "the size and gap of the bodies that only contact holds ({:.3e})",
            ctl.drift_limit / 10.0
        )
    };
    let plain = match (run.retreat.at, run.retreat.restarted) {
        (Some(at), false) => format!(
            "; Anderson's iterates drifted or stalled first (iteration {at}), and the plain iteration from their smallest residual drifts too"
        ),
        (Some(at), true) => format!(
            "; Anderson's iterates drifted or stalled first (iteration {at}), and the plain iteration drifts too, from their smallest residual and from the start"
        ),
        (None, _) => String::new(),
    };
    Error::NotConverged(format!(
        "{name}: the body moves without bound: after {k} iterations a contact node has moved {:.3e}, ten times {scale}; {what}{plain}; no contact state found holds the loads (lower the loads, raise the friction, or add a Dirichlet condition)",
        ext.umax,
    ))
}
