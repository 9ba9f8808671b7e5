//! Which algorithm runs and what it produced: [`solve`] dispatches to UBR-C,
//! UBR-TF, CF-FP or a comparator as the options ask, and returns the state
//! and a [`Solved`] whatever ran.

use super::stopping::StopRule;
use super::surface::UbrState;
use super::{cf_fp, snesvi, ssn, ubr, Problem};
use crate::contact::{hertz, ContactSet};
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::options::{Friction, HertzReference, Settings, TrescaBound};
use crate::petsc::Events;
use mpi::traits::*;

/// What the iterations produced, whichever algorithm ran.
pub struct Solved {
    pub name: &'static str,
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
}

impl Solved {
    fn new() -> Solved {
        Solved {
            name: "UBR-C",
            iterations: 0,
            fixed_point_iterations: 0,
            frictionless_iterations: 0,
            converged: false,
            last: ubr::UbrOutcome::default(),
            fp_change: None,
            bound: Vec::new(),
            error_estimate: None,
            failure: None,
        }
    }

    /// The comparators, whose iterations have no UBR stopping test.
    pub fn is_comparator(&self) -> bool {
        self.name == "SSN-C" || self.name == "SNES-VI"
    }

    /// Why the run did not converge, for the message of exit status 3.
    pub fn failure(&self) -> String {
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
        if self.name == "SSN-C" {
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
    }
}

/// The Tresca bound from `-tresca_bound hertz`: nu_f times the Hertz pressure
/// at each owned candidate, centred as the reference says (default: the
/// candidate with the smallest gap over all ranks).
fn hertz_bound<C: Communicator>(
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
            let dist = hertz::distance(local.x(cs.node[i]), &center, &cs.n);
            nu_f * hertz::pressure(d, reference.force, reference.radius, e_star, dist).0
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

/// The bound s^0 from -tresca_bound (None: a frictionless solve first for
/// Tresca, or zero for CF-FP).
fn explicit_bound<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    state: &mut UbrState,
    solved: &mut Solved,
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
            // A frictionless solve with the same matrix: UBR-TF with s = 0.
            let zero = vec![0.0; nc];
            let run = ubr::ubr(
                world,
                problem,
                state,
                Some(&zero),
                &control(settings),
                events,
            )?;
            solved.frictionless_iterations = run.iterations;
            if !run.converged {
                return Err(Error::NotConverged(format!(
                    "the frictionless solve behind -tresca_bound frictionless did not converge: {}",
                    run.failure.unwrap_or_default()
                )));
            }
            let s = coulomb_bound(state, nu_f);
            state.reset()?;
            Some(s)
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
    let run = if settings.algorithm == "snesvi" {
        solved.name = "SNES-VI";
        snesvi::snes_vi(world, problem, &mut state, &settings.ssn_initial_shift)?
    } else {
        let ctl = ssn::SsnControl {
            r: settings.ssn_r,
            max_it: settings.ssn_max_it,
            initial_shift: settings.ssn_initial_shift.clone(),
            monitor: settings.ubr.monitor,
        };
        solved.name = "SSN-C";
        ssn::ssn_c(world, problem, local, &mut state, &ctl, events)?.0
    };
    solved.iterations = run.iterations;
    solved.converged = run.converged;
    solved.last = run;
    Ok((state, solved))
}

/// Runs the algorithm the options ask for. `friction_held`: some rigid
/// motion is held by friction alone (CF-FP then starts from sticking).
pub fn solve<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    friction_held: bool,
    events: &Events,
) -> Result<(UbrState, Solved), Error> {
    if settings.algorithm != "ubr" {
        return comparator(world, local, settings, problem, events);
    }
    let u = &settings.ubr;
    let ctl = control(settings);
    let nc = problem.contact.len();
    let nu_f = settings.friction_coefficient;
    let mut state = UbrState::new(problem)?;
    let mut solved = Solved::new();
    let accuracy = u.stop == StopRule::Accuracy;
    let explicit = if settings.friction == Friction::None {
        None
    } else {
        explicit_bound(
            world,
            local,
            settings,
            problem,
            &mut state,
            &mut solved,
            events,
        )?
    };
    match settings.friction {
        Friction::None => {
            let run = ubr::ubr(world, problem, &mut state, None, &ctl, events)?;
            solved.take(run, accuracy);
        }
        Friction::Tresca => {
            solved.name = "UBR-TF";
            let s = match explicit {
                Some(s) => s,
                None => {
                    // Default: as the paper's 3D setting, nu_f x lambda_c of a frictionless solve.
                    let zero = vec![0.0; nc];
                    let run = ubr::ubr(world, problem, &mut state, Some(&zero), &ctl, events)?;
                    solved.frictionless_iterations = run.iterations;
                    if !run.converged {
                        solved.failure = run.failure.map(|f| {
                            format!("the frictionless solve that gives the Tresca bound did not converge: {f}")
                        });
                        solved.last = ubr::UbrOutcome::default();
                        return Ok((state, solved));
                    }
                    let s = coulomb_bound(&state, nu_f);
                    state.reset()?;
                    s
                }
            };
            let run = ubr::ubr(world, problem, &mut state, Some(&s), &ctl, events)?;
            solved.take(run, accuracy);
            solved.bound = s;
        }
        Friction::Coulomb => {
            solved.name = "CF-FP";
            // s^0 = 0 (the paper's frictionless first solve), unless
            // friction alone holds the body: that solve has no solution
            // then, and the first Tresca solve sticks (s^0 = infinity).
            let stick = if friction_held { f64::INFINITY } else { 0.0 };
            let s0 = explicit.unwrap_or_else(|| vec![stick; nc]);
            let fp = cf_fp::cf_fp(
                world,
                problem,
                &mut state,
                nu_f,
                s0,
                &ctl,
                u.fp_rtol,
                u.fp_max_it,
                u.fp_anderson,
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
    Ok((state, solved))
}
