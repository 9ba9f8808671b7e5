//! Algorithm CF-FP (Koko 2010, section 5): Coulomb friction as the fixed
//! point of Tresca problems.
//!
//! Iteration m = 0: s^0 given (zero, i.e. a frictionless first Tresca solve,
//! unless `-tresca_bound` says otherwise; infinite, a sticking first solve,
//! when friction alone holds the body and a frictionless solve has none). Iteration m >= 0: solve the Tresca
//! problem with bound s^m by UBR-TF, warm-started from the previous iterate,
//! to the variable tolerance `eps_f^m = max(0.1^m, eps_f)` of section 7; then
//! `s^{m+1} = nu_f |lambda_c^m|`. Every Tresca solve uses the same factorized
//! matrix: one factorization for the whole run. A zero bound after a zero
//! bound (nothing touches) is converged, never 0/0.
//!
//! Stopping. Paper mode: (5.7) `||s^{m+1} - s^m||_{0,Gamma_c} < eps_fp
//! ||s^{m+1}||_{0,Gamma_c}` with the last Tresca solve at the full
//! tolerance. Accuracy mode (default): the inner tolerances follow the
//! schedule `max(0.1^m, tol)` down to the target tol of lambda, and the
//! fixed point stops on the same kind of guarantee as UBR: the change of
//! lambda between two Tresca solutions (normal and tangential parts, each
//! relative to its max norm) times the outer amplification `1 / (1 - q)`,
//! q the largest recent ratio of consecutive changes (the q last measured
//! where the change is at the noise of the Tresca solves), below tol / 4; or a
//! bound s that reproduces itself exactly (its outer error is nil, the
//! estimate is the last Tresca solve's).

use super::anderson::Anderson;
use super::outcome::Lowering;
use super::stopping::StopRule;
use super::surface::{SurfaceState, UbrState};
use super::ubr::{complete, ubr, UbrControl, UbrOutcome, Whole};
use super::Problem;
use crate::comm::{allreduce_max, allreduce_max_n, allreduce_sum};
use crate::error::Error;
use crate::petsc::Vector;
use mpi::traits::*;

/// Accuracy stop: the Tresca solves' target, relative to the outer one.
const INNER_TIGHTER: f64 = 0.1;

/// A relative change of s at round-off, and how many in a row make a
/// fixed point stopped at the cap one that has stopped moving.
const FLAT_CHANGE: f64 = 1e-13;
const FLAT_ITS: usize = 10;

/// What the fixed point did.
#[derive(Clone, Debug, Default)]
pub struct CfFpOutcome {
    pub fixed_point_iterations: usize,
    pub inner_iterations: usize,
    pub converged: bool,
    /// Relative change of s at the last fixed-point iteration, (5.7).
    pub fp_change: f64,
    /// Accuracy mode: the outer error estimate of lambda.
    pub fp_error_estimate: f64,
    /// The last Tresca run.
    pub last: UbrOutcome,
    /// The bound of the last Tresca solve.
    pub bound: Vec<f64>,
    /// Why the fixed point stopped without converging.
    pub failure: Option<String>,
}

/// The fixed point's own controls: -ubr_fp_rtol, -ubr_fp_max_it,
/// -ubr_fp_anderson, and whether a stalled Tresca solve may go on at a
/// lower r (friction alone holds a rigid motion and r is automatic).
pub struct FpControl {
    pub rtol: f64,
    pub max_it: usize,
    pub anderson: usize,
    pub lower: bool,
}

impl FpControl {
    /// From the options; `friction_held`: friction alone holds a rigid
    /// motion.
    pub fn new(u: &crate::options::UbrSettings, friction_held: bool) -> FpControl {
        FpControl {
            rtol: u.fp_rtol,
            max_it: u.fp_max_it,
            anderson: u.fp_anderson,
            lower: friction_held && u.r.is_none(),
        }
    }
}

/// Runs CF-FP from `s0` (one bound per owned candidate).
#[allow(clippy::too_many_arguments)]
pub fn cf_fp<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    nu_f: f64,
    s0: Vec<f64>,
    ctl: &UbrControl,
    fp: &FpControl,
    events: &crate::petsc::Events,
) -> Result<CfFpOutcome, Error> {
    let mut lowering = Lowering::new(fp.lower, problem);
    let low = &mut lowering;
    let mut out = fixed_point(world, problem, state, nu_f, s0, ctl, fp, low, events)?;
    let how = match out.converged {
        true => "the fixed point converged",
        false => "the fixed point did not converge",
    };
    lowering.warn(problem, "CF-FP: a Tresca solve", how);
    // The answer's whole displacement, from the last Tresca solve (a fixed
    // point that failed reports its state with it, even where a load
    // history's step wanted none).
    let mode = match ctl.displacement {
        Whole::No if !out.converged => Whole::Only,
        m => m,
    };
    complete(world, problem, state, &mut out.last, mode)?;
    Ok(out)
}

/// The fixed point of [`cf_fp`]; the whole displacement of its last
/// Tresca solve is left pending ([`complete`]).
#[allow(clippy::too_many_arguments)]
fn fixed_point<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    nu_f: f64,
    s0: Vec<f64>,
    ctl: &UbrControl,
    fp: &FpControl,
    lowering: &mut Lowering,
    events: &crate::petsc::Events,
) -> Result<CfFpOutcome, Error> {
    let w = problem.contact.w.clone();
    let root = world.rank() == 0;
    let paper = ctl.stop == StopRule::Paper;
    let mut s = s0;
    let mut next = vec![0.0; s.len()];
    let mut out = CfFpOutcome::default();
    // Accuracy mode: the previous Tresca solution's multipliers, and the
    // recent changes between solutions.
    let mut changes = Changes::default();
    let mut outer = (fp.anderson > 0).then(|| Anderson::new(fp.anderson, w.clone()));
    let mut floors = Floors::default();
    // Consecutive fixed-point iterations whose change of s is round-off.
    let mut flat = 0;
    let mut halving = Halving::new(ctl.monitor);
    let mut retreats = [0, 0];
    for m in 0..fp.max_it {
        let (mut inner, full_tolerance) = floors.control(ctl, m, paper);
        // A step of s that can still be halved is, before the plain
        // iteration's slow way (the rolling quarter: 382 against 1331
        // iterations); the last one may take it.
        inner.retreat = !halving.can_back();
        let run = match ubr(world, problem, state, Some(&s), &inner, events) {
            // Iterates without bound (a Tresca problem without solution):
            // back to the last bound that held, half the step; none left,
            // the answer is that bound's solution, with the failure.
            Err(Error::NotConverged(why)) => {
                if halving.back(world, &mut s, state, (&mut outer, &mut changes))? {
                    continue;
                }
                let Some((bound, good)) = halving.restore(state)? else {
                    return Err(Error::NotConverged(why));
                };
                (out.bound, out.last) = (bound, good);
                out.failure = Some(format!("CF-FP fixed-point iteration {m}: {why}"));
                break;
            }
            r => r?,
        };
        let (at_floor, stalled) = floors.judge(&run, ctl, paper);
        out.inner_iterations += run.iterations;
        run.count_retreats(&mut retreats);
        out.fixed_point_iterations = m + 1;
        // (Two solves in a row at their floor: no bound would do better.)
        let retreat = (&mut *lowering, &mut halving, &mut outer, &mut changes);
        if stalled && !at_floor && again(world, problem, state, &mut s, retreat)? {
            continue;
        }
        if !stalled {
            halving.keep(&s, state, &run)?;
        }
        let st = &state.surface;
        // s^{m+1} = nu_f |lambda_c^m| (the multiplier of the Tresca solve)
        for (x, l) in next.iter_mut().zip(&st.lambda_n) {
            *x = nu_f * l.abs();
        }
        out.fp_change = relative_change(world, &w, &next, &s);
        flat = (flat + 1) * usize::from(out.fp_change <= FLAT_CHANGE);
        // Accuracy mode: the change of lambda between Tresca solutions.
        let mut estimate = f64::INFINITY;
        if !paper {
            changes.noise = run.error_estimate;
            estimate = outer_estimate(world, problem.dim, st, &mut changes);
            out.fp_error_estimate = estimate;
        }
        progress(m, out.fp_change, run.contact);
        if root && ctl.monitor {
            monitor(m, &run, &inner, paper, out.fp_change, estimate);
        }
        out.bound.clone_from(&s);
        // Stopped by its cap or stalled, no halving left (a Tresca problem
        // its bound cannot hold): the fixed point cannot converge either.
        out.last = run;
        if stalled {
            out.failure = out.last.failure.clone().map(|f| {
                format!("CF-FP fixed-point iteration {m}: the Tresca solve did not converge: {f}")
            });
            break; // a Tresca solve that cannot converge: the fixed point cannot either
        }
        // s reproduced itself bit for bit (a zero friction coefficient,
        // nothing touching, a converged stick state): the last Tresca
        // solution is the Coulomb one, within its own estimate.
        let exact = !paper && out.fp_change == 0.0 && m > 0;
        let done = if paper {
            out.fp_change < fp.rtol
        } else {
            estimate <= 0.25 * ctl.lambda_rtol || exact
        };
        // The last Tresca solve at its floor: its estimate within the
        // outer target.
        let last_ok =
            out.last.converged || at_floor && out.last.error_estimate <= 0.25 * ctl.lambda_rtol;
        if done && full_tolerance && last_ok {
            out.converged = true;
            if exact {
                // The outer error is nil; the changes of lambda between
                // Tresca solves (of one bound at tightening tolerances)
                // measure the inner ones, and gave inf to a converged run.
                out.fp_error_estimate = 0.0;
            }
            break;
        }
        outer_step(world, outer.as_mut(), &mut s, &mut next);
    }
    if !out.converged && out.failure.is_none() {
        out.failure = Some(cap_message(&out, paper, fp.rtol, ctl.lambda_rtol, flat));
    }
    [out.last.anderson_retreats, out.last.plain_restarts] = retreats;
    Ok(out)
}

/// What [`again`] may change: r, the halving, the outer acceleration and
/// the outer estimate's history.
type Retreat<'a> = (
    &'a mut Lowering,
    &'a mut Halving,
    &'a mut Option<Anderson>,
    &'a mut Changes,
);

/// A Tresca solve stalled (not at its floor): whether the fixed point
/// goes on. Where friction alone holds a rigid motion and r is automatic,
/// a stall is first the sliding or rolling mode's slow convergence at a
/// large r: the same bound again from this iterate at a lower r
/// ([`Lowering`]), before any halving; then half the step ([`Halving`]).
/// The ring under its own weight on a plane (tests/edges/ring2d.geo),
/// Coulomb 0.3: the first Tresca solve at the full tolerance stalled at
/// r = 629, four halvings too, exit 3; now the same bound stalls at r / 3
/// and r / 9 and converges at r / 27 (2063 iterations in all). Measured, 1
/// rank, against no lowering: 30 rings (sideways load 0-0.3 of the weight,
/// nu_f 0.1-0.6, pressure in the hole) 7 -> 0 failed; the rolling Hertz
/// quarter, Coulomb (36) 0 -> 0 (the 9 whose path changed: 16,245 ->
/// 11,380 iterations); held by uy = 0 (30) the same 4 beyond what friction
/// holds fail, after 3x the iterations. Halving first (two lowerings): 3
/// rings failed; two lowerings: 1 ring and 1 rolling quarter (both at
/// exactly the load friction holds).
fn again<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    s: &mut [f64],
    (lowering, halving, outer, changes): Retreat,
) -> Result<bool, Error> {
    if lowering.lower(problem)? {
        if halving.monitor && world.rank() == 0 {
            println!(
                "  CF-FP: the Tresca solve stalled: the same bound at r = {:.4e}",
                problem.r()
            );
        }
        return Ok(true);
    }
    halving.back(world, s, state, (outer, changes))
}

/// The Tresca solves stopped at their floor: consecutive ones, and the
/// tolerance below which the last of them says the Tresca solves cannot go.
#[derive(Default)]
struct Floors {
    in_a_row: usize,
    floor: f64,
}

impl Floors {
    /// The control of the Tresca solve at fixed-point iteration m, and
    /// whether its tolerance is the full one. The paper's variable inner
    /// tolerance eps_f^m = max(0.1^m, eps_f); our dual and tension tests
    /// loosen with it (an open node's stress is r (u_n^k - u_n^{k-1})
    /// until u settles: at eps_f^0 = 1 a tension test at its final value
    /// would hold the first, frictionless, solve for tens of iterations).
    fn control(&self, ctl: &UbrControl, m: usize, paper: bool) -> (UbrControl, bool) {
        let (mut inner, full_tolerance) = inner_control(ctl, m, paper);
        // Never tighter than the round-off an earlier solve stopped at.
        inner.lambda_rtol = inner.lambda_rtol.max(self.floor);
        // Only the last Tresca solve's whole displacement is wanted, and
        // which is last is known after it: made once, at the end.
        inner.defer_whole = true;
        (inner, full_tolerance)
    }

    /// After a Tresca solve: whether it stopped at its floor, and whether
    /// it failed. At its floor: at round-off, or stalled at the outer
    /// target (a floor above 1e-12: stamp2d_gravity_coulomb at -ubr_r 1e6,
    /// 2e-12). A solve stopped there is as accurate as it gets: the outer
    /// test decides, the later solves aiming at that floor, unless two in
    /// a row stopped there (stamp2d_gravity_coulomb on 2 and 3 ranks at
    /// -ubr_lambda_rtol 1e-10: Tresca solves flat at 5.8e-14 and 1.4e-13,
    /// their estimates 2.2e-11 and 6.3e-12 above their target of 2.5e-12,
    /// ten times tighter than the outer one).
    fn judge(&mut self, run: &UbrOutcome, ctl: &UbrControl, paper: bool) -> (bool, bool) {
        let at_floor = run.roundoff
            || !paper && !run.converged && run.error_estimate <= 0.25 * ctl.lambda_rtol;
        if at_floor {
            // Eight times its estimate: a later solve at this floor passes
            // at twice it; never looser than the outer target.
            self.floor = (8.0 * run.error_estimate).min(ctl.lambda_rtol);
        }
        self.in_a_row = if at_floor { self.in_a_row + 1 } else { 0 };
        (
            at_floor,
            !run.converged && (!at_floor || self.in_a_row >= 2),
        )
    }
}

/// Halvings of one step of s before CF-FP gives up (each one is a
/// fixed-point iteration: `-ubr_fp_max_it` bounds them all).
const HALVINGS: usize = 4;

/// The last good Tresca solve: its bound, state, whole displacement and
/// outcome (whose pending whole displacement is that state's).
struct Good {
    s: Vec<f64>,
    surface: SurfaceState,
    u: Vector,
    run: UbrOutcome,
}

/// The last Tresca solve that converged, and the halvings of the step
/// from its bound. Where the next bound nu_f |lambda_c| makes a Tresca
/// problem without solution, CF-FP goes back to it and takes half the
/// step, up to [`HALVINGS`] times: the bounds under which a Tresca problem
/// has a solution form a convex set (those of the loads' balance with
/// |lambda_t| <= s), and the last good bound is in it. Where that bound's
/// solution slips at every contact node, it sits on the set's edge (the
/// friction forces all at their bounds balance the loads): a smaller bound
/// in the direction the body slides holds nothing, nor does any midpoint
/// toward one. The halved bound is then kept at least the good one (the
/// set holds every bound above one of its own: more room for |lambda_t|),
/// where the step raises it somewhere; where it raises nothing, that would
/// be the good bound again, and the plain midpoint is taken. (The Hertz
/// quarter without its symmetry condition, Coulomb 0.3, pushed sideways by
/// a quarter of its normal load: on 2 ranks, about one run in ten failed
/// after four plain halvings, its good bounds slipping everywhere, now
/// none in 50; on 1 rank 5 of 36 sideways loads from 10 to 28 and
/// coefficients from 0.28 to 0.32 failed, now only 28 at 0.28, the load
/// friction can just hold.) A sticking start (infinite s) goes back to
/// the bound `|lambda_t|` of its solution (the Hertz quarter held by uy = 0
/// on its cut instead of ux = 0, Coulomb 0.5, pushed sideways by 240: the
/// first bound nu_f lambda_n of the sticking solution held nothing, exit 3
/// at any nu_f). The Coulomb fixed point is the halved map's too.
struct Halving {
    good: Option<Good>,
    count: usize,
    /// Whether the monitor prints each halving.
    monitor: bool,
}

impl Halving {
    fn new(monitor: bool) -> Halving {
        Halving {
            good: None,
            count: 0,
            monitor,
        }
    }

    /// A Tresca solve with the bound `s` converged (or stopped at its
    /// floor): its state is the one to go back to. A sticking solve's
    /// (infinite s) is the Tresca solution of the bound `|lambda_t|` it
    /// found (sticking where the bound is reached is allowed), the bound
    /// kept in place of the infinite ones.
    fn keep(&mut self, s: &[f64], state: &UbrState, run: &UbrOutcome) -> Result<(), Error> {
        let lt = &state.surface.lambda_t;
        let d = if s.is_empty() { 1 } else { lt.len() / s.len() };
        let finite = |(i, &x): (usize, &f64)| match x.is_infinite() {
            true => lt[i * d..(i + 1) * d]
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt(),
            false => x,
        };
        let s: Vec<f64> = s.iter().enumerate().map(finite).collect();
        let s = &s[..];
        self.count = 0;
        match &mut self.good {
            Some(g) => {
                g.s.clear();
                g.s.extend_from_slice(s);
                g.surface.clone_from(&state.surface);
                g.u.copy_from(&state.u)?;
                g.run.clone_from(run);
            }
            None => {
                let u = state.u.duplicate()?;
                u.copy_from(&state.u)?;
                let (s, surface, run) = (s.to_vec(), state.surface.clone(), run.clone());
                self.good = Some(Good { s, surface, u, run });
            }
        }
        Ok(())
    }

    /// Whether a failed Tresca solve can be halved.
    fn can_back(&self) -> bool {
        self.good.is_some() && self.count < HALVINGS
    }

    /// The Tresca solve with `s` failed: `s` halfway back to the last
    /// good bound (nowhere below it where that bound is on the edge), the
    /// state its solution, the outer estimate's history and the outer
    /// acceleration restarted. False where there is none (the first solve)
    /// or after [`HALVINGS`] halvings of this step.
    fn back<C: Communicator>(
        &mut self,
        world: &C,
        s: &mut [f64],
        state: &mut UbrState,
        (outer, changes): (&mut Option<Anderson>, &mut Changes),
    ) -> Result<bool, Error> {
        let more = self.can_back();
        let Some(g) = self.good.as_ref().filter(|_| more) else {
            return Ok(false);
        };
        self.count += 1;
        // A good solution that slips at every contact node: nowhere below
        // its bound, where the step raises it somewhere (see [`Halving`]).
        let rise = s
            .iter()
            .zip(&g.s)
            .fold(0.0, |a: f64, (x, gs)| a.max(x - gs));
        let edge = g.run.stick == 0 && g.run.contact > 0 && allreduce_max(world, rise) > 0.0;
        for (x, gs) in s.iter_mut().zip(&g.s) {
            let mid = 0.5 * (*x + gs);
            *x = if edge { mid.max(*gs) } else { mid };
        }
        state.surface.clone_from(&g.surface);
        state.u.copy_from(&g.u)?;
        if let Some(aa) = outer.as_mut() {
            aa.restart();
        }
        // The next solve's bound is no step of the map from the last one's:
        // the change of lambda between them measures no fixed point (a
        // bound near the good one gives about its solution again, a change
        // near 0: a trial that kept the good bound "converged" with s 24
        // times nu_f |lambda_n|).
        *changes = Changes::default();
        if self.monitor && world.rank() == 0 {
            println!(
                "  CF-FP: the Tresca solve failed: half the step from the last bound that held ({} of {HALVINGS})",
                self.count
            );
        }
        Ok(true)
    }

    /// No halving left after a solve whose iterates moved without bound:
    /// the state back to the last good solve's; its bound and outcome (the
    /// answer reported with the failure, not the drifted iterate).
    fn restore(&mut self, state: &mut UbrState) -> Result<Option<(Vec<f64>, UbrOutcome)>, Error> {
        let Some(g) = self.good.take() else {
            return Ok(None);
        };
        state.surface = g.surface;
        state.u.copy_from(&g.u)?;
        Ok(Some((g.s, g.run)))
    }
}

/// The next bound s from `next` = nu_f |lambda_c(s)|: Anderson on the
/// outer map (a bound is never negative), or the plain step.
fn outer_step<C: Communicator>(
    world: &C,
    outer: Option<&mut Anderson>,
    s: &mut Vec<f64>,
    next: &mut Vec<f64>,
) {
    // A sticking start (infinite s^0) is no point of the map's
    // history: the fixed point proper starts from s^1.
    let sticking =
        allreduce_sum(world, [s.iter().filter(|x| x.is_infinite()).count() as f64])[0] > 0.0;
    match outer.filter(|_| !sticking) {
        Some(aa) => {
            let fnorm = allreduce_sum(world, [aa.local_norm2(&diff_of(next, s))])[0].sqrt();
            let mut z = vec![0.0; s.len()];
            aa.step(
                |a, b| world.all_reduce_into(a, b, mpi::collective::SystemOperation::sum()),
                s,
                next,
                fnorm,
                &mut z,
            );
            for (x, zi) in s.iter_mut().zip(&z) {
                *x = zi.max(0.0);
            }
        }
        None => std::mem::swap(s, next),
    }
}

/// The failure of CF-FP stopped by `-ubr_fp_max_it`.
fn cap_message(
    out: &CfFpOutcome,
    paper: bool,
    fp_rtol: f64,
    lambda_rtol: f64,
    flat: usize,
) -> String {
    if !paper && flat >= FLAT_ITS {
        // More iterations would not help: the fixed point has stopped
        // moving, and its estimate is inf because the ratios of round-off
        // changes give no contraction.
        return format!(
            "CF-FP stopped after {} fixed-point iterations (-ubr_fp_max_it): the bound s has changed by at most {FLAT_CHANGE:.0e} (relative, round-off) over the last {flat}, but the changes of lambda between them are round-off and bound its error by nothing below the target -ubr_lambda_rtol {:.1e} / 4 (outer error estimate {:.3e}); the answer is as accurate as double precision resolves this problem: ask for a looser -ubr_lambda_rtol",
            out.fixed_point_iterations, lambda_rtol, out.fp_error_estimate
        );
    }
    if paper {
        format!(
            "CF-FP stopped after {} fixed-point iterations (-ubr_fp_max_it): relative change of s {:.3e} (target -ubr_fp_rtol {:.1e}); try -ubr_fp_max_it larger",
            out.fixed_point_iterations, out.fp_change, fp_rtol
        )
    } else {
        format!(
            "CF-FP stopped after {} fixed-point iterations (-ubr_fp_max_it): the outer error estimate of lambda is {:.3e} (target -ubr_lambda_rtol {:.1e} / 4), relative change of s {:.3e}; try -ubr_fp_max_it larger",
            out.fixed_point_iterations, out.fp_error_estimate, lambda_rtol, out.fp_change
        )
    }
}

fn diff_of(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// The Tresca solve's control at fixed-point iteration m: the paper's
/// variable inner tolerance `eps_f^m = max(0.1^m, eps_f)`, and whether it
/// is the full one.
fn inner_control(ctl: &UbrControl, m: usize, paper: bool) -> (UbrControl, bool) {
    let schedule = 0.1f64.powi(m as i32);
    if paper {
        let eps = schedule.max(ctl.rtol);
        (
            UbrControl {
                rtol: eps,
                dual_rtol: ctl.dual_rtol * eps / ctl.rtol,
                tension_tol: ctl.tension_tol * eps / ctl.rtol,
                ..*ctl
            },
            eps <= ctl.rtol,
        )
    } else {
        // The outer estimate below is built from the changes of lambda
        // between Tresca solutions, each accurate to a quarter of its
        // tolerance: at the outer target itself their errors (up to
        // half the target between two solutions) would hide the
        // changes it must see below a quarter of the target, and the
        // test would pass only by chance (hemisphere3d_coulomb at 1e-6
        // with GAMG: 100 outer iterations, the changes' ratios noise).
        // The inner target is ten times tighter.
        let inner_target = ctl.lambda_rtol * INNER_TIGHTER;
        let tol = schedule.max(inner_target);
        (
            UbrControl {
                lambda_rtol: tol,
                ..*ctl
            },
            tol <= inner_target,
        )
    }
}

/// The paper's (5.7): `||s^{m+1} - s^m|| / ||s^{m+1}||` (weights w).
fn relative_change<C: Communicator>(world: &C, w: &[f64], next: &[f64], s: &[f64]) -> f64 {
    let mut local = [0.0; 2];
    for i in 0..s.len() {
        local[0] += w[i] * (next[i] - s[i]).powi(2);
        local[1] += w[i] * next[i] * next[i];
    }
    let [diff2, norm2] = allreduce_sum(world, local);
    if norm2 > 0.0 {
        (diff2 / norm2).sqrt()
    } else if diff2 == 0.0 {
        0.0 // zero after zero: nothing touches
    } else {
        f64::INFINITY
    }
}

/// The changes of lambda between Tresca solutions (accuracy mode), and
/// what decides whether the latest is noise.
#[derive(Default)]
struct Changes {
    /// The previous Tresca solution's lambda_n and lambda_t.
    prev: Option<(Vec<f64>, Vec<f64>)>,
    list: Vec<f64>,
    /// The error estimate of the Tresca solve just made, and of the one
    /// before it: the noise their errors leave in the change between them.
    noise: f64,
    last_noise: f64,
    /// The contraction q (below 1) last measured.
    q: Option<f64>,
}

/// A change of lambda between Tresca solves within this many times the sum
/// of their error estimates is noise (inexact solves: CG + GAMG): ratios of
/// such changes scatter about 1 and measure no contraction. Where they do
/// not, the q last measured holds: the fixed point has reached the solves'
/// noise, and its contraction is what it was. (The outer estimate stayed
/// inf, and CF-FP stopped at -ubr_fp_max_it on 2 ranks of hertz_mixed_1692
/// at -ubr_lambda_rtol 1e-9, while 1 and 3 ranks converged.)
const CHANGE_NOISE: f64 = 4.0;

/// Accuracy mode: the outer error estimate of lambda from the changes of
/// lambda between Tresca solutions (`changes`: the previous one's
/// multipliers and the recent changes): the last change times
/// 1 / (1 - q), q the largest of the last four ratios of consecutive
/// changes, or the one last measured where the change is noise
/// ([`CHANGE_NOISE`]).
fn outer_estimate<C: Communicator>(
    world: &C,
    d: usize,
    st: &SurfaceState,
    changes: &mut Changes,
) -> f64 {
    let mut estimate = f64::INFINITY;
    let (ln, lt) = (&st.lambda_n, &st.lambda_t);
    let finite = |e: f64| if e.is_finite() { e } else { 0.0 };
    let noise = CHANGE_NOISE * (finite(changes.noise) + finite(changes.last_noise));
    changes.last_noise = changes.noise;
    if let Some((pn, pt)) = changes.prev.as_ref() {
        let mut ext = [0.0f64; 4];
        for i in 0..ln.len() {
            ext[0] = ext[0].max((ln[i] - pn[i]).abs());
            ext[1] = ext[1].max(ln[i].abs());
            let (mut dt, mut nt) = (0.0, 0.0);
            for c in 0..d {
                dt += (lt[i * d + c] - pt[i * d + c]).powi(2);
                nt += lt[i * d + c].powi(2);
            }
            ext[2] = ext[2].max(dt.sqrt());
            ext[3] = ext[3].max(nt.sqrt());
        }
        let [dn, nn, dt, nt] = allreduce_max_n(world, ext);
        let rel = |a: f64, b: f64| if a == 0.0 { 0.0 } else { a / b };
        let change = rel(dn, nn).max(rel(dt, nt.max(1e-6 * nn)));
        let list = &mut changes.list;
        list.push(change);
        let mut q = list
            .iter()
            .rev()
            .take(4)
            .zip(list.iter().rev().skip(1))
            .map(|(a, b)| if *b > 0.0 { a / b } else { 0.0 })
            .fold(f64::NEG_INFINITY, f64::max);
        if list.len() >= 2 && q < 1.0 {
            changes.q = Some(q);
        } else if change <= noise {
            q = changes.q.unwrap_or(q);
        }
        estimate = if change == 0.0 {
            0.0
        } else if list.len() < 2 || q.is_nan() || q >= 1.0 {
            f64::INFINITY
        } else {
            change / (1.0 - q.max(0.0))
        };
    }
    changes.prev = Some((ln.clone(), lt.clone()));
    estimate
}

/// The progress line of fixed-point iteration m (every few seconds).
fn progress(m: usize, fp_change: f64, contact: usize) {
    crate::progress::tick(|| {
        let change = if fp_change.is_finite() {
            format!("{fp_change:.2e}")
        } else {
            "not yet known".into()
        };
        format!("CF-FP fixed-point iteration {m}: change of s {change}, {contact} nodes in contact")
    });
}

/// The monitor's line of fixed-point iteration m (`-ubr_monitor`).
fn monitor(
    m: usize,
    run: &UbrOutcome,
    inner: &UbrControl,
    paper: bool,
    fp_change: f64,
    estimate: f64,
) {
    println!(
        "  CF-FP {:3}: {} Tresca iterations (tol {:.0e}), ||s^(m+1) - s^m|| / ||s^(m+1)|| = {:.3e}{}, contact {} stick {} slip {}",
        m,
        run.iterations,
        if paper { inner.rtol } else { inner.lambda_rtol },
        fp_change,
        if paper {
            String::new()
        } else {
            format!(", outer error estimate {estimate:.3e}")
        },
        run.contact,
        run.stick,
        run.slip
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At the cap, a fixed point whose s has stopped moving (round-off
    /// changes for FLAT_ITS iterations) is told to loosen the tolerance,
    /// not to iterate longer; one still moving is told to iterate longer.
    #[test]
    fn the_cap_message_tells_a_stopped_fixed_point_from_a_slow_one() {
        let out = CfFpOutcome {
            fixed_point_iterations: 100,
            fp_change: 1.7e-15,
            fp_error_estimate: f64::INFINITY,
            ..Default::default()
        };
        let stopped = cap_message(&out, false, 1e-4, 1e-9, FLAT_ITS);
        assert!(
            stopped.contains("ask for a looser -ubr_lambda_rtol"),
            "{stopped}"
        );
        assert!(!stopped.contains("-ubr_fp_max_it larger"), "{stopped}");
        let slow = cap_message(&out, false, 1e-4, 1e-9, FLAT_ITS - 1);
        assert!(slow.contains("try -ubr_fp_max_it larger"), "{slow}");
        let paper = cap_message(&out, true, 1e-4, 1e-9, FLAT_ITS);
        assert!(paper.contains("target -ubr_fp_rtol"), "{paper}");
    }
}
