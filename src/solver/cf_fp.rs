//! Algorithm CF-FP (Koko 2010, section 5): Coulomb friction as the fixed
//! point of Tresca problems.
//!
//! Iteration m = 0: s^0 given (zero, i.e. a frictionless first Tresca solve,
//! unless `-tresca_bound` says otherwise). Iteration m >= 0: solve the Tresca
//! problem with bound s^m by UBR-TF, warm-started from the previous iterate,
//! to the variable tolerance `eps_f^m = max(0.1^m, eps_f)` of section 7; then
//! `s^{m+1} = nu_f |lambda_c^m|`; stop when (5.7)
//! `||s^{m+1} - s^m||_{0,Gamma_c} < eps_fp ||s^{m+1}||_{0,Gamma_c}` and the
//! last Tresca solve ran at the full tolerance. Every Tresca solve uses the
//! same factorized matrix: one factorization for the whole run. A zero bound
//! after a zero bound (nothing touches) is converged, never 0/0.

use super::allreduce_sum;
use super::ubr::{ubr, UbrControl, UbrOutcome, UbrState};
use super::Problem;
use crate::error::Error;
use mpi::traits::*;

/// What the fixed point did.
#[derive(Clone, Debug, Default)]
pub struct CfFpOutcome {
    pub fixed_point_iterations: usize,
    pub inner_iterations: usize,
    pub converged: bool,
    /// Relative change of s at the last fixed-point iteration, (5.7).
    pub fp_change: f64,
    /// The last Tresca run.
    pub last: UbrOutcome,
    /// The bound of the last Tresca solve.
    pub bound: Vec<f64>,
}

/// Runs CF-FP from `s0` (one bound per owned candidate).
#[allow(clippy::too_many_arguments)]
pub fn cf_fp<C: Communicator>(
    world: &C,
    problem: &Problem,
    state: &mut UbrState,
    nu_f: f64,
    s0: Vec<f64>,
    ctl: &UbrControl,
    fp_rtol: f64,
    fp_max_it: usize,
    events: &crate::Events,
) -> Result<CfFpOutcome, Error> {
    let cs = &problem.contact;
    let root = world.rank() == 0;
    let mut s = s0;
    let mut next = vec![0.0; s.len()];
    let mut out = CfFpOutcome::default();
    for m in 0..fp_max_it {
        // The paper's variable inner tolerance eps_f^m = max(0.1^m, eps_f);
        // our dual and tension tests loosen with it (an open node's stress is
        // r (u_n^k - u_n^{k-1}) until u settles: at eps_f^0 = 1 a tension test
        // at its final value would hold the first, frictionless, solve for
        // tens of iterations).
        let eps = 0.1f64.powi(m as i32).max(ctl.rtol);
        let inner = UbrControl {
            rtol: eps,
            dual_rtol: ctl.dual_rtol * eps / ctl.rtol,
            tension_tol: ctl.tension_tol * eps / ctl.rtol,
            ..*ctl
        };
        let run = ubr(world, problem, state, Some(&s), &inner, events)?;
        out.inner_iterations += run.iterations;
        out.fixed_point_iterations = m + 1;
        out.last = run;
        // s^{m+1} = nu_f |lambda_c^m| (the multiplier of the Tresca solve)
        for (x, l) in next.iter_mut().zip(&state.lambda_n) {
            *x = nu_f * l.abs();
        }
        let mut local = [0.0; 2];
        for i in 0..s.len() {
            local[0] += cs.w[i] * (next[i] - s[i]).powi(2);
            local[1] += cs.w[i] * next[i] * next[i];
        }
        let [diff2, norm2] = allreduce_sum(world, local);
        out.fp_change = if norm2 > 0.0 {
            (diff2 / norm2).sqrt()
        } else if diff2 == 0.0 {
            0.0 // zero after zero: nothing touches
        } else {
            f64::INFINITY
        };
        if root && ctl.monitor {
            println!(
                "  CF-FP {:3}: {} Tresca iterations (eps {:.0e}), ||s^(m+1) - s^m|| / ||s^(m+1)|| = {:.3e}, contact {} stick {} slip {}",
                m, run.iterations, eps, out.fp_change, run.contact, run.stick, run.slip
            );
        }
        out.bound.clone_from(&s);
        if !run.converged && run.iterations >= ctl.max_it {
            break; // a Tresca solve that cannot converge: the fixed point cannot either
        }
        let full_tolerance = eps <= ctl.rtol;
        if out.fp_change < fp_rtol && full_tolerance && run.converged {
            out.converged = true;
            break;
        }
        std::mem::swap(&mut s, &mut next);
    }
    Ok(out)
}
