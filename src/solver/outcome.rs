//! Which algorithm runs and what it produced: [`solve`] dispatches to UBR-C,
//! UBR-TF, CF-FP or a comparator as the options ask, and returns the state
//! and a [`Solved`] whatever ran.

use super::stopping::StopRule;
use super::surface::UbrState;
use super::{cf_fp, penalty, seat, snesvi, ssn, ubr, Problem};
use crate::comm::{allreduce_max, allreduce_max_n};
use crate::contact::surface::Surface;
use crate::contact::{hertz, ContactSet};
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::options::{Algorithm, Friction, HertzReference, Settings, TrescaBound};
use crate::petsc::Events;
use crate::wellposed::Restraint;
use mpi::traits::*;

/// The method that ran, by its name in the paper (UBR-C, UBR-TF, CF-FP)
/// or the comparator's; [`std::fmt::Display`] writes that name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    UbrC,
    UbrTf,
    CfFp,
    SsnC,
    SnesVi,
}

impl Method {
    pub fn as_str(self) -> &'static str {
        match self {
            Method::UbrC => "UBR-C",
            Method::UbrTf => "UBR-TF",
            Method::CfFp => "CF-FP",
            Method::SsnC => "SSN-C",
            Method::SnesVi => "SNES-VI",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the iterations produced, whichever algorithm ran.
pub struct Solved {
    pub name: Method,
    pub iterations: usize,
    pub fixed_point_iterations: usize,
    /// UBR iterations of the frictionless solve behind `-tresca_bound frictionless`.
    pub frictionless_iterations: usize,
    pub converged: bool,
    pub last: ubr::UbrOutcome,
    pub fp_change: Option<f64>,
    /// The friction bound s per owned candidate (empty without friction).
    pub bound: Vec<f64>,
    /// The accuracy test's error estimate of lambda (None in the paper's mode).
    pub error_estimate: Option<f64>,
    /// Why the run did not converge.
    pub failure: Option<String>,
    /// No answer: the run stopped with an error before one (the state is
    /// the zero start, which the summary must not pass for an answer).
    pub unsolved: bool,
}

impl Solved {
    fn new() -> Solved {
        Solved {
            name: Method::UbrC,
            iterations: 0,
            fixed_point_iterations: 0,
            frictionless_iterations: 0,
            converged: false,
            last: ubr::UbrOutcome::default(),
            fp_change: None,
            bound: Vec::new(),
            error_estimate: None,
            failure: None,
            unsolved: false,
        }
    }

    /// The comparators, whose iterations have no UBR stopping test.
    pub fn is_comparator(&self) -> bool {
        matches!(self.name, Method::SsnC | Method::SnesVi)
    }

    /// Why the run did not converge, for the message of exit status 3.
    pub fn failure(&self) -> String {
        // A -ubr_r far from the trial r0 is the likelier cause than a body
        // that is not held, and the iteration's message names it (a
        // history's step of tube2d_tresca at -ubr_r 1e6, 3.7e3 times r0,
        // was told to check its Dirichlet conditions).
        if let Some(f) = self.failure.as_ref().filter(|f| ubr::names_far_r(f)) {
            return f.clone();
        }
        if self.last.tension > 0.1 {
            return format!(
                "{} stopped after {} iterations (relative change {:.3e}, constraint residual {:.3e}): the body is not held: the contact surface would have to pull (tensile contact stress {:.0}% of the largest), so a rigid-body motion is free and the body drifts; check the Dirichlet conditions (-dirichlet_NAME), the loads and the obstacle",
                self.name,
                self.iterations,
                self.last.criterion,
                self.last.residual,
                100.0 * self.last.tension
            );
        }
        if self.name == Method::SsnC {
            return format!(
                "SSN-C stopped after {} iterations (-ssn_max_it): the active set still changes",
                self.iterations
            );
        }
        self.failure.clone().unwrap_or_else(|| {
            format!("{} stopped after {} iterations", self.name, self.iterations)
        })
    }

    fn take(&mut self, run: ubr::UbrOutcome, accuracy: bool) {
        self.iterations = run.iterations;
        self.converged = run.converged;
        self.failure = run.failure.clone();
        self.error_estimate = accuracy.then_some(run.error_estimate);
        self.last = run;
    }
}

/// The tolerances and caps of the UBR runs, from the settings.
pub fn control(settings: &Settings) -> ubr::UbrControl {
    let u = &settings.ubr;
    ubr::UbrControl {
        rho: u.rho,
        stop: u.stop,
        rtol: u.rtol,
        residual_tol: u.residual_tol,
        dual_rtol: u.dual_rtol,
        tension_tol: ubr::TENSION_TOL,
        lambda_rtol: u.lambda_rtol,
        max_it: u.max_it,
        monitor: u.monitor,
        inner_rtol_factor: u.inner_rtol_factor,
        anderson: u.anderson,
        drift_limit: f64::INFINITY,
        r_far: None,
        displacement: ubr::Whole::WithChange,
        defer_whole: false,
        retreat: true,
    }
}

/// The Tresca bound from `-tresca_bound hertz`: nu_f times the Hertz pressure
/// at each owned candidate, centred as the reference says (default: the
/// candidate with the smallest gap over all ranks).
pub fn hertz_bound<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    cs: &ContactSet,
    reference: &HertzReference,
    nu_f: f64,
    e_star: f64,
) -> Vec<f64> {
    let d = local.dim;
    // (gap, x, y, z) of each rank's candidate with the smallest gap.
    let mut mine: [f64; 4] = [f64::INFINITY, 0.0, 0.0, 0.0];
    for i in 0..cs.len() {
        if cs.g[i] < mine[0] {
            mine[0] = cs.g[i];
            mine[1..1 + d].copy_from_slice(local.x(cs.node[i]));
        }
    }
    let mut all = vec![0.0f64; 4 * world.size() as usize];
    world.all_gather_into(&mine[..], &mut all[..]);
    let center = hertz::center(
        reference.center.as_deref(),
        d,
        all.chunks(4).map(|c| (c[0], &c[1..])),
    );
    (0..cs.len())
        .map(|i| {
            let x = local.x(cs.node[i]);
            nu_f * reference
                .pressure_at(d, e_star, x, &center, &cs.direction)
                .0
        })
        .collect()
}

/// nu_f |lambda_n| at every candidate: the bound of a frictionless solve.
fn coulomb_bound(state: &UbrState, nu_f: f64) -> Vec<f64> {
    state
        .surface
        .stress_n
        .iter()
        .map(|l| nu_f * l.abs())
        .collect()
}

/// The accuracy of the frictionless solve behind a Tresca bound
/// `nu_f lambda_c`: its target, relative to the Tresca solve's. Where a
/// node slips, `lambda_t = s`, so the error of lambda_c enters lambda_t
/// whole: solved this much tighter, it is a small part of the error budget
/// (3D beam, Tresca at the defaults: true tangential error 1.2e-3 with the
/// frictionless solve at the same target, against 1e-3 promised).
const BOUND_TIGHTER: f64 = 0.01;

/// What the error of a frictionless solve's bound does to a Tresca solve.
#[derive(Clone, Copy, Debug)]
pub struct BoundError {
    /// The frictionless solve's error estimate (relative to its largest
    /// lambda_c), its largest lambda_c, and its iterations.
    estimate: f64,
    max_lambda_c: f64,
    nu_f: f64,
    iterations: usize,
}

impl BoundError {
    /// The error the bound brings to the Tresca solve's tangential
    /// stresses, relative to their max norm (as the accuracy test's): at a
    /// slipping node `|d lambda_t| = |d s| <= nu_f e max lambda_c`; zero
    /// where nothing slips.
    fn relative<C: Communicator>(&self, world: &C, state: &UbrState) -> f64 {
        let sf = &state.surface;
        let d = state.dim;
        let nc = sf.slip.len();
        let mut ext = [0.0f64; 3]; // [any slip, max |lambda_t|, max lambda_n]
        for i in 0..nc {
            if sf.slip[i] {
                ext[0] = 1.0;
            }
            let lt = (0..d)
                .map(|c| sf.lambda_t[i * d + c].powi(2))
                .sum::<f64>()
                .sqrt();
            ext[1] = ext[1].max(lt);
            ext[2] = ext[2].max(sf.lambda_n[i].abs());
        }
        let [slips, lt, ln] = allreduce_max_n(world, ext);
        if slips == 0.0 {
            return 0.0;
        }
        let scale = lt.max(1e-6 * ln).max(f64::MIN_POSITIVE);
        self.nu_f * self.estimate * self.max_lambda_c / scale
    }
}

/// The Tresca bound `nu_f lambda_c` of a frictionless solve (UBR-TF with
/// s = 0, the same matrix), solved [`BOUND_TIGHTER`] than the Tresca
/// target (at the target for CF-FP's start); the state is back at its
/// start after it.
fn frictionless_bound<C: Communicator>(
    world: &C,
    settings: &Settings,
    problem: &mut Problem,
    state: &mut UbrState,
    ctl: &ubr::UbrControl,
    events: &Events,
) -> Result<(Vec<f64>, BoundError), Error> {
    let nc = problem.contact.len();
    let nu_f = settings.friction_coefficient;
    // CF-FP only starts from it (its fixed point corrects the bound).
    let factor = if settings.friction == Friction::Tresca {
        BOUND_TIGHTER
    } else {
        1.0
    };
    let tight = ubr::UbrControl {
        lambda_rtol: ctl.lambda_rtol * factor,
        ..*ctl
    };
    let zero = vec![0.0; nc];
    let run = ubr::ubr(world, problem, state, Some(&zero), &tight, events)?;
    // A bound tightened below what double precision resolves stops at
    // round-off: as accurate as it gets, its estimate goes into the Tresca
    // solve's, which says whether the target is met (it failed the run at
    // -ubr_anderson 0 -ubr_lambda_rtol 1e-9: the frictionless solve's
    // residual flat at 2e-16, its estimate 6e-12 against 2.5e-12).
    let at_roundoff = run.roundoff && run.error_estimate.is_finite();
    if !run.converged && !at_roundoff {
        return Err(Error::NotConverged(format!(
            "the frictionless solve that gives the Tresca bound did not converge: {}",
            run.failure.unwrap_or_default()
        )));
    }
    let max_lc = state
        .surface
        .stress_n
        .iter()
        .fold(0.0f64, |m, l| m.max(l.abs()));
    let error = BoundError {
        // The paper's stop has no estimate: its bound's error is not known.
        estimate: if settings.ubr.stop == StopRule::Accuracy {
            run.error_estimate
        } else {
            0.0
        },
        max_lambda_c: allreduce_max(world, max_lc),
        nu_f,
        iterations: run.iterations,
    };
    let s = coulomb_bound(state, nu_f);
    state.reset()?;
    Ok((s, error))
}

/// The bound s^0 from -tresca_bound (None: a frictionless solve first for
/// Tresca, or zero for CF-FP).
#[allow(clippy::too_many_arguments)]
fn explicit_bound<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    state: &mut UbrState,
    solved: &mut Solved,
    bound_error: &mut Option<BoundError>,
    ctl: &ubr::UbrControl,
    events: &Events,
) -> Result<Option<Vec<f64>>, Error> {
    let nc = problem.contact.len();
    let nu_f = settings.friction_coefficient;
    Ok(match settings.tresca_bound {
        Some(TrescaBound::Value(v)) => Some(vec![v; nc]),
        Some(TrescaBound::Hertz) => Some(hertz_bound(
            world,
            local,
            &problem.contact,
            settings
                .reference
                .as_ref()
                .expect("checked with the options"),
            nu_f,
            settings.e_star(local.dim),
        )),
        Some(TrescaBound::Frictionless) => {
            let (bound, error) = frictionless_bound(world, settings, problem, state, ctl, events)?;
            solved.frictionless_iterations = error.iterations;
            *bound_error = Some(error);
            Some(bound)
        }
        None => None,
    })
}

/// The comparators: PETSc's SNES VI, or SSN-C.
fn comparator<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    events: &Events,
) -> Result<(UbrState, Solved), Error> {
    let mut state = UbrState::new(problem)?;
    let mut solved = Solved::new();
    let run = if settings.algorithm == Algorithm::SnesVi {
        solved.name = Method::SnesVi;
        snesvi::snes_vi(world, problem, &mut state, &settings.ssn_initial_shift)?
    } else {
        let ctl = ssn::SsnControl {
            r: settings.ssn_r,
            max_it: settings.ssn_max_it,
            initial_shift: settings.ssn_initial_shift.clone(),
            monitor: settings.ubr.monitor,
            linear: settings.linear.clone(),
        };
        solved.name = Method::SsnC;
        ssn::ssn_c(world, problem, local, &mut state, &ctl, events)?.0
    };
    solved.iterations = run.iterations;
    solved.converged = run.converged;
    solved.failure = run.failure.clone();
    solved.last = run;
    Ok((state, solved))
}

/// Ten times the largest size of the bodies that contact alone holds along
/// some rigid motion and the largest gap: a candidate displaced further
/// has drifted ([`ubr::UbrControl::drift_limit`]); infinite where every
/// body is held by Dirichlet conditions.
fn drift_limit<C: Communicator>(world: &C, restraint: &Restraint, cs: &ContactSet) -> f64 {
    let size = restraint
        .contact_held
        .iter()
        .map(|m| restraint.bodies.size(m.body))
        .fold(0.0f64, f64::max);
    if size == 0.0 {
        return f64::INFINITY;
    }
    let gap = allreduce_max(world, cs.g.iter().fold(0.0f64, |m, g| m.max(g.abs())));
    10.0 * (size + gap)
}

/// The trial r0 where the user's r is more than [`ubr::R_FAR`] times away
/// from it.
pub fn r_far<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &Problem,
) -> Option<f64> {
    settings.ubr.r?;
    let d = local.dim;
    // The stiffest body's modulus, as the trial r0 was made with.
    let m = settings.stiffest(d);
    let modulus = penalty::p_wave_modulus(m.young, m.nu, d, settings.plane_stress);
    let r0 = penalty::trial(world, local, &problem.contact, modulus);
    let ratio = problem.r() / r0;
    (!(1.0 / ubr::R_FAR..=ubr::R_FAR).contains(&ratio)).then_some(r0)
}

/// UBR-TF with the bound `s`; `bound_error`: the error of a bound from a
/// frictionless solve, which adds to the estimate; where the sum misses
/// the target, the Tresca solve goes on (warm) to a target that leaves
/// room for it.
/// `lower`: friction alone holds a rigid motion and r is automatic, so a
/// stalled solve goes on at a lower r ([`lower_r`]).
#[allow(clippy::too_many_arguments)]
fn tresca<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    s: Vec<f64>,
    ctl: &ubr::UbrControl,
    bound_error: Option<BoundError>,
    solved: &mut Solved,
    events: &Events,
    lower: bool,
) -> Result<(), Error> {
    let accuracy = ctl.stop == StopRule::Accuracy;
    let mut run = ubr::ubr(world, problem, state, Some(&s), ctl, events)?;
    run = lower_r(world, problem, state, &s, ctl, events, (lower, run))?;
    // The bound's own error adds to the estimate; where the sum
    // misses the target, the Tresca solve goes on (warm) to a
    // target that leaves room for it.
    let added = match bound_error {
        Some(e) if accuracy => e.relative(world, state),
        _ => 0.0,
    };
    let budget = 0.25 * ctl.lambda_rtol;
    if run.converged && added > 0.0 && run.error_estimate + added > budget && added < 0.5 * budget {
        let more = ubr::UbrControl {
            lambda_rtol: 4.0 * (budget - added),
            max_it: ctl.max_it.saturating_sub(run.iterations),
            ..*ctl
        };
        let first = run.iterations;
        run = ubr::ubr(world, problem, state, Some(&s), &more, events)?;
        run.iterations += first;
    }
    let total = run.error_estimate + added;
    let missed = accuracy && run.converged && total > budget;
    solved.take(run, accuracy);
    if accuracy {
        solved.error_estimate = Some(total);
    }
    if missed {
        solved.converged = false;
        solved.failure = Some(format!(
            "UBR-TF: the error estimate of lambda {total:.3e} (the Tresca solve's {:.3e} and the frictionless bound's {added:.3e}) misses the target -ubr_lambda_rtol {:.1e} / 4: the bound nu_f lambda_c is not known accurately enough; try a looser -ubr_lambda_rtol",
            total - added,
            ctl.lambda_rtol
        ));
    }
    solved.bound = s;
    Ok(())
}

/// How many times a stalled Tresca solve of a friction-held body goes on
/// at a third of its r (in a whole run: UBR-TF's one solve, or all of
/// CF-FP's), and the factor.
const LOWER_TRIES: usize = 3;
const LOWER_FACTOR: f64 = 3.0;

/// r lowered after a stall where friction alone holds a rigid motion and
/// r is automatic: a third of r, up to [`LOWER_TRIES`] times (the
/// condensed back-end moves r without refactorizing). The automatic r is
/// already a third of the spectral estimate there
/// ([`penalty::FRICTION_HELD`]): the sliding or rolling mode is none of
/// the compliance's modes, and some scenes want less still.
pub(super) struct Lowering {
    allowed: bool,
    tries: usize,
    r_first: f64,
}

impl Lowering {
    /// `allowed`: friction alone holds a rigid motion and r is automatic.
    pub(super) fn new(allowed: bool, problem: &Problem) -> Lowering {
        Lowering {
            allowed,
            tries: 0,
            r_first: problem.r(),
        }
    }

    /// After a stalled solve: r divided by [`LOWER_FACTOR`], where allowed
    /// and tries are left; false otherwise (r unchanged).
    pub(super) fn lower(&mut self, problem: &mut Problem) -> Result<bool, Error> {
        if !self.allowed || self.tries >= LOWER_TRIES {
            return Ok(false);
        }
        self.tries += 1;
        let surface = Surface {
            cs: &problem.contact,
            dim: problem.dim,
            tangential: problem.tangential,
            dirichlet: &problem.dirichlet.contact,
        };
        let r = problem.r() / LOWER_FACTOR;
        problem.lin.set_r(&surface, r, problem.owned_start)?;
        Ok(true)
    }

    /// The warning of a run that lowered r (`what`: the solve that
    /// stalled, `how`: what came of it), none where it did not.
    pub(super) fn warn(&self, problem: &mut Problem, what: &str, how: &str) {
        if self.tries == 0 {
            return;
        }
        let r = problem.r();
        problem.lin.warnings.push(format!(
            "{what} stalled at r = {:.4e}, where friction alone holds a rigid motion (its sliding or rolling mode converges slowly at a large r); it went on from its last iterate at r = {r:.4e} (r / {}) and {how}",
            self.r_first,
            LOWER_FACTOR.powi(self.tries as i32),
        ));
    }
}

/// A Tresca solve that stalled where friction alone holds a rigid motion
/// and r is automatic (`allowed`) goes on from its last iterate at a
/// lower r ([`Lowering`]), within -ubr_max_it. Measured (the Hertz quarter without `ux = 0`, Tresca
/// s = 2 under the traction (2, -100), 1 rank): stalled after 3208
/// iterations at r = 722, stalled again at 241 (1091 more), converged at
/// 80 in 64 more; the other 20 scenes of `bench/friction_held/run.sh`'s
/// Tresca grid converge first and are unchanged. A warning says so.
fn lower_r<C: Communicator>(
    world: &C,
    problem: &mut Problem,
    state: &mut UbrState,
    s: &[f64],
    ctl: &ubr::UbrControl,
    events: &Events,
    (allowed, mut run): (bool, ubr::UbrOutcome),
) -> Result<ubr::UbrOutcome, Error> {
    let mut lowering = Lowering::new(allowed, problem);
    while run.stalled && run.iterations < ctl.max_it && lowering.lower(problem)? {
        let more = ubr::UbrControl {
            max_it: ctl.max_it - run.iterations,
            ..*ctl
        };
        let before = run.iterations;
        run = ubr::ubr(world, problem, state, Some(s), &more, events)?;
        run.iterations += before;
    }
    if lowering.tries > 0 {
        let how = if run.converged {
            "converged"
        } else {
            "did not converge"
        };
        let how = format!("{how}, {} iterations in all", run.iterations);
        lowering.warn(problem, "UBR-TF", &how);
    }
    Ok(run)
}

/// Runs the algorithm the options ask for. `restraint`: what holds the
/// bodies (a body that contact alone holds and that starts away from the
/// obstacle is first moved onto it, [`seat`]; where friction alone holds
/// some rigid motion, CF-FP starts from sticking).
pub fn solve<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    restraint: &Restraint,
    events: &Events,
) -> Result<(UbrState, Solved), Error> {
    if settings.algorithm != Algorithm::Ubr {
        return comparator(world, local, settings, problem, events);
    }
    let mut state = UbrState::new(problem)?;
    state.set_seat(seat::approach(world, local, restraint, problem)?);
    let solved = run(
        world, local, settings, problem, restraint, events, &mut state, None,
    )?;
    Ok((state, solved))
}

/// One step of a load history (UBR): the algorithm on the problem's
/// current load from `state`, the previous step's iterate (warm); CF-FP
/// starts from `s_prev`, the previous step's bound nu_f |lambda_c|, where
/// no `-tresca_bound` gives s^0; `displacement`: what of the step's whole
/// displacement is wanted (condensed: [`ubr::Whole`]).
#[allow(clippy::too_many_arguments)]
pub fn solve_step<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    restraint: &Restraint,
    events: &Events,
    state: &mut UbrState,
    s_prev: &[f64],
    displacement: ubr::Whole,
) -> Result<Solved, Error> {
    let warm = Warm {
        s_prev,
        displacement,
    };
    run(
        world,
        local,
        settings,
        problem,
        restraint,
        events,
        state,
        Some(warm),
    )
}

/// A later step of a load history: the previous bound, and whether the
/// step's whole displacement is wanted.
struct Warm<'a> {
    s_prev: &'a [f64],
    displacement: ubr::Whole,
}

/// UBR-C, UBR-TF or CF-FP from `state`.
#[allow(clippy::too_many_arguments)]
fn run<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    restraint: &Restraint,
    events: &Events,
    state: &mut UbrState,
    warm: Option<Warm>,
) -> Result<Solved, Error> {
    let friction_held = restraint.friction_held.is_some();
    let u = &settings.ubr;
    let ctl = ubr::UbrControl {
        drift_limit: drift_limit(world, restraint, &problem.contact),
        r_far: r_far(world, local, settings, problem),
        displacement: warm
            .as_ref()
            .map_or(ubr::Whole::WithChange, |w| w.displacement),
        ..control(settings)
    };
    let s_prev = warm.map(|w| w.s_prev);
    let nc = problem.contact.len();
    let nu_f = settings.friction_coefficient;
    let mut solved = Solved::new();
    let accuracy = u.stop == StopRule::Accuracy;
    let mut bound_error = None;
    let explicit = if settings.friction == Friction::None {
        None
    } else {
        explicit_bound(
            world,
            local,
            settings,
            problem,
            state,
            &mut solved,
            &mut bound_error,
            &ctl,
            events,
        )?
    };
    match settings.friction {
        Friction::None => {
            let run = ubr::ubr(world, problem, state, None, &ctl, events)?;
            solved.take(run, accuracy);
        }
        Friction::Tresca => {
            solved.name = Method::UbrTf;
            let s = match explicit {
                Some(s) => s,
                None => {
                    // Default: as the paper's 3D setting, nu_f x lambda_c of a frictionless solve.
                    match frictionless_bound(world, settings, problem, state, &ctl, events) {
                        Ok((s, error)) => {
                            solved.frictionless_iterations = error.iterations;
                            bound_error = Some(error);
                            s
                        }
                        Err(Error::NotConverged(why)) => {
                            solved.failure = Some(why);
                            solved.last = ubr::UbrOutcome::default();
                            return Ok(solved);
                        }
                        Err(e) => return Err(e),
                    }
                }
            };
            let lower = friction_held && u.r.is_none();
            tresca(
                world,
                problem,
                state,
                s,
                &ctl,
                bound_error,
                &mut solved,
                events,
                lower,
            )?;
        }
        Friction::Coulomb => {
            solved.name = Method::CfFp;
            // s^0 = 0 (the paper's frictionless first solve), unless
            // friction alone holds the body: that solve has no solution
            // then, and the first Tresca solve sticks (s^0 = infinity).
            // A later load step starts from the previous step's bound,
            // unless friction alone holds the body: that bound may not
            // hold the larger load (a Tresca problem without solution,
            // the body slides), so it sticks first as the first step did.
            let stick = if friction_held { f64::INFINITY } else { 0.0 };
            let s0 = explicit
                .or_else(|| s_prev.filter(|_| !friction_held).map(<[f64]>::to_vec))
                .unwrap_or_else(|| vec![stick; nc]);
            let fp = cf_fp::cf_fp(
                world,
                problem,
                state,
                nu_f,
                s0,
                &ctl,
                &cf_fp::FpControl::new(u, friction_held),
                events,
            )?;
            solved.iterations = fp.inner_iterations;
            solved.fixed_point_iterations = fp.fixed_point_iterations;
            solved.converged = fp.converged;
            solved.failure = fp.failure.clone();
            solved.error_estimate =
                accuracy.then_some(fp.last.error_estimate.max(fp.fp_error_estimate));
            solved.last = fp.last;
            solved.fp_change = Some(fp.fp_change);
            solved.bound = fp.bound;
        }
    }
    Ok(solved)
}
