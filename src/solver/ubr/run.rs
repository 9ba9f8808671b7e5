//! One UBR run as a struct whose methods are the paper's steps: the
//! right-hand side and solve (4.5)/(5.3), the projections (4.15), (5.5) and
//! the update (4.4), the reductions, the Anderson step, and the stopping
//! tests.

use super::measures::{z_weights, Maxima, Sums};
use super::messages::{failure, roundoff, stalled, StallScene};
use super::{tangential_from_whole, whole_displacement, Pending};
use super::{UbrControl, UbrOutcome, Whole, DRIFT_ITS, INNER_FACTOR_MIN, TANGENTIAL_FLOOR};
use crate::comm::{allreduce_max, allreduce_max_n, allreduce_sum};
use crate::contact::{project_normal, project_normal_z, project_tangential, project_tangential_z};
use crate::error::Error;
use crate::linalg::linear::LinearSolver;
use crate::solver::anderson::Anderson;
use crate::solver::deferred::{Candidate, Deferred, Resolution};
use crate::solver::mass_norms;
use crate::solver::stopping::{paper_change, Accuracy, Progress, StopRule, STALL_ITS};
use crate::solver::surface::{Surface, UbrState};
use mpi::collective::SystemOperation;
use mpi::traits::*;

mod drift;
use drift::{unbounded, Retreat};

/// One UBR run: the iterate's arrays, and what the stopping tests remember.
/// [`Run::iterate`] is one iteration k, its methods the paper's steps.
pub(super) struct Run<'a, C: Communicator> {
    world: &'a C,
    lin: &'a mut LinearSolver,
    surface: Surface<'a>,
    lumped_mass: &'a [f64],
    state: &'a mut UbrState,
    friction_bound: Option<&'a [f64]>,
    ctl: &'a UbrControl,
    events: &'a crate::petsc::Events,
    d: usize,
    nc: usize,
    r: f64,
    rho: f64,
    root: bool,
    name: &'static str,
    paper: bool,
    out: UbrOutcome,
    /// Anderson, and the point whose projection is the current (phi,
    /// lambda) (None before the first evaluation, which starts from the
    /// state); `z_out = T(z_in)`, `next` the extrapolated point.
    aa: Option<Anderson>,
    z_in: Option<Vec<f64>>,
    z_out: Vec<f64>,
    next: Vec<f64>,
    /// The contact part of the right-hand side, `B^T W (r phi - lambda)`, and
    /// `u_C`, at this iteration and the previous one.
    c: Vec<f64>,
    c_prev: Vec<f64>,
    uc: Vec<f64>,
    uc_prev: Vec<f64>,
    acc: Accuracy,
    progress: Progress,
    /// The paper's test on the condensed back-end: candidates decided later.
    /// Their decision leaves the whole displacement of the chosen one in u.
    deferred: Option<Deferred>,
    /// u^{k-1} of a full solve, for the change (4.16)/(5.6).
    u_prev: Vec<f64>,
    /// Evaluations in a row with nothing in contact, everything moving away
    /// and the stresses not decaying; the stress scale at the first of them.
    drifting: usize,
    drift_stress: f64,
    /// A contact node's largest displacement at the first iterate: the
    /// scale of the elastic response (a very soft body moves past its size).
    first_umax: Option<f64>,
    cold: bool,
    was_condensed: bool,
    last: Sums,
    /// A zero bound everywhere (a frictionless solve through UBR-TF).
    no_friction: bool,
    inner_factor: f64,
    /// Anderson's way back to the plain iteration where its iterates drift.
    retreat: Retreat,
    k: usize,
}

impl<'a, C: Communicator> Run<'a, C> {
    /// The paper's initialization from `state`, and the monitor's header.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        world: &'a C,
        lin: &'a mut LinearSolver,
        surface: Surface<'a>,
        lumped_mass: &'a [f64],
        state: &'a mut UbrState,
        friction_bound: Option<&'a [f64]>,
        ctl: &'a UbrControl,
        events: &'a crate::petsc::Events,
    ) -> Result<Self, Error> {
        let d = surface.dim;
        let nc = surface.len();
        let r = lin.r();
        let rho = ctl.rho.unwrap_or(r);
        let root = world.rank() == 0;
        let name = if friction_bound.is_some() {
            "UBR-TF"
        } else {
            "UBR-C"
        };
        assert_eq!(friction_bound.is_some(), surface.tangential);
        let paper = ctl.stop == StopRule::Paper;
        let nt = if surface.tangential { nc * d } else { 0 };
        let out = UbrOutcome {
            criterion: f64::NAN,
            residual: f64::INFINITY,
            // Unknown until an evaluation: null in the report.
            error_estimate: f64::NAN,
            p: f64::NAN,
            k: f64::NAN,
            ..Default::default()
        };
        if root && ctl.monitor {
            let test = if paper {
                "rel. change (4.16) ||Bu - phi||    "
            } else {
                "error estimate     residual P   K  "
            };
            if friction_bound.is_some() {
                println!("  {name}   it   {test} contact  stick   slip");
            } else {
                println!("  {name}   it   {test} contact");
            }
        }
        let aa = (ctl.anderson > 0).then(|| Anderson::new(ctl.anderson, z_weights(&surface)));
        let deferred = (paper && lin.is_condensed()).then(|| Deferred::new(lumped_mass.len() * d));
        let mut u_prev = vec![0.0; lumped_mass.len() * d];
        state.u.read(|u| u_prev.copy_from_slice(u))?;
        let cold = std::mem::replace(&mut state.cold, false);
        let (was_condensed, inexact, seed) = (lin.is_condensed(), lin.iterative, state.contraction);
        let no_friction = friction_bound.is_some_and(|b| {
            allreduce_max(world, b.iter().fold(0.0, |a: f64, &x| a.max(x))) == 0.0
        });
        let acc = Accuracy::new(ctl.lambda_rtol).seeded(seed).inexact(inexact);
        let retreat = Retreat::new(&acc, state, aa.is_some() && ctl.retreat);
        Ok(Run {
            world,
            lin,
            surface,
            lumped_mass,
            state,
            friction_bound,
            ctl,
            events,
            d,
            nc,
            r,
            rho,
            root,
            name,
            paper,
            out,
            aa,
            z_in: None,
            z_out: vec![0.0; nc + nt],
            next: vec![0.0; nc + nt],
            c: vec![0.0; nc * d],
            c_prev: vec![0.0; nc * d],
            uc: vec![0.0; nc * d],
            uc_prev: vec![0.0; nc * d],
            acc,
            progress: Progress::new(cold),
            deferred,
            u_prev,
            drifting: 0,
            drift_stress: 0.0,
            first_umax: None,
            cold,
            was_condensed,
            last: Sums::default(),
            no_friction,
            inner_factor: ctl.inner_rtol_factor,
            retreat,
            k: 0,
        })
    }

    /// Iterates until a stopping test holds or `-ubr_max_it`, then
    /// finishes.
    pub(super) fn run(mut self) -> Result<UbrOutcome, Error> {
        while self.k < self.ctl.max_it {
            if self.iterate()? {
                break;
            }
        }
        self.finish()
    }

    /// Iteration k: right-hand side and solve (4.5)/(5.3), projection and
    /// update (4.15), (5.5), (4.4), the reductions, the Anderson step, and
    /// the stopping tests. Returns whether the run stops.
    fn iterate(&mut self) -> Result<bool, Error> {
        self.right_hand_side();
        let its = self.solve()?;
        let mut sums = Sums::default();
        let mut ext = Maxima {
            dun: f64::NEG_INFINITY,
            ..Default::default()
        };
        self.change_of_u(&mut sums)?;
        self.project(&mut sums, &mut ext);
        let (sums, ext) = self.reduce(sums, ext);
        let p = self.residual_p(&ext);
        self.keep_best(p, sums.contact > 0.0);
        let amplification = self.accelerate(sums.f2.sqrt());
        let est = self.record(p, &sums, amplification);
        self.monitor(its, est, p);
        self.k += 1;
        self.out.iterations = self.k;
        if self.guard(&sums, &ext, p)? {
            return Ok(false); // back to the plain iteration: no test of the drift
        }
        if self.stop(&sums, &ext, p)? {
            return Ok(true);
        }
        self.project_next();
        Ok(false)
    }

    /// Step 1, its right-hand side: only the contact part changes, by
    /// `c = B^T W (r phi^{k-1} - lambda^k)` on the contact nodes (4.5)/(5.3).
    fn right_hand_side(&mut self) {
        std::mem::swap(&mut self.c, &mut self.c_prev);
        std::mem::swap(&mut self.uc, &mut self.uc_prev);
        let (st, r, d) = (&self.state.surface, self.r, self.d);
        let _e = self.events.rhs.begin();
        self.surface.load(
            |i| r * st.phi_n[i] - st.lambda_n[i],
            |i, cc| r * st.phi_t[i * d + cc] - st.lambda_t[i * d + cc],
            &mut self.c,
        );
    }

    /// Step 1, the elasticity subproblem (4.5)/(5.3) with the matrix
    /// factorized once: `u_C` (and u, a full solve). Returns the inner
    /// iterations.
    fn solve(&mut self) -> Result<usize, Error> {
        if self.lin.iterative && self.lin.adaptive_inner {
            // Inexact Uzawa: each solve starts from u^{k-1} and reduces the
            // residual b - A u^{k-1} (the change this iteration brings) by
            // the factor.
            self.lin.set_inner_rtol(self.inner_factor)?;
        }
        let its = {
            let _e = self.events.solve.begin();
            self.lin
                .solve(&self.surface, &self.c, &mut self.uc, &self.state.u)?
        };
        self.state.inner_iterations.push(its);
        Ok(its)
    }

    /// The paper's change of u (4.16)/(5.6): a full solve knows it now; a
    /// condensed one, its part at the contact nodes (the candidates decide
    /// the rest).
    fn change_of_u(&mut self, sums: &mut Sums) -> Result<(), Error> {
        let d = self.d;
        if self.lin.is_condensed() {
            for (i, &v) in self.surface.cs.node.iter().enumerate() {
                let m = self.lumped_mass[v];
                for cc in 0..d {
                    sums.dc2 += m * (self.uc[i * d + cc] - self.uc_prev[i * d + cc]).powi(2);
                }
            }
        } else {
            let (lumped_mass, u_prev) = (self.lumped_mass, &mut self.u_prev);
            self.state.u.read(|u| {
                (sums.du2, sums.u2) = mass_norms(lumped_mass, d, u, u_prev);
                u_prev.copy_from_slice(u);
            })?;
        }
        Ok(())
    }

    /// Steps 2 and 3, pointwise: the projections (4.15), (5.5) and the
    /// multiplier update (4.4), with this rank's sums and maxima.
    #[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
    fn project(&mut self, sums: &mut Sums, ext: &mut Maxima) {
        let _e = self.events.projection.begin();
        let (d, r, rho) = (self.d, self.r, self.rho);
        let cs = self.surface.cs;
        for i in 0..self.nc {
            let st = &mut self.state.surface;
            let w = cs.w[i];
            let uni = self.surface.normal(&self.uc, i);
            // -sigma_n(u^k) by (4.7), before the update
            let stress = st.lambda_n[i] + r * (uni - st.phi_n[i]);
            st.stress_n[i] = stress;
            ext.tension = ext.tension.max(-stress);
            ext.stress = ext.stress.max(stress.abs());
            ext.un = ext.un.max(uni.abs());
            for cc in 0..d {
                ext.umax = ext.umax.max(self.uc[i * d + cc].abs());
            }
            ext.dun = ext.dun.max(uni - st.un[i]);
            let f = stress - st.lambda_n[i];
            ext.f_n = ext.f_n.max(f.abs());
            sums.f2 += w * f * f;
            self.z_out[i] = st.lambda_n[i] + r * uni;
            let (phi_new, lambda_new, contact) =
                project_normal(uni, st.lambda_n[i], cs.g[i], r, rho);
            ext.lam_n = ext.lam_n.max(st.lambda_n[i].abs()).max(lambda_new.abs());
            sums.dphi2 += w * (phi_new - st.phi_n[i]).powi(2);
            sums.phi2 += w * phi_new * phi_new;
            sums.res2 += w * (uni - phi_new).powi(2);
            sums.lam2 += w * lambda_new * lambda_new;
            st.un[i] = uni;
            st.phi_n[i] = phi_new;
            st.lambda_n[i] = lambda_new;
            if contact != st.in_contact[i] {
                sums.changes += 1.0;
            }
            st.in_contact[i] = contact;
            let mut ut = [0.0; 3];
            self.surface.tangential_part(&self.uc, i, uni, &mut ut);
            st.ut[i * d..(i + 1) * d].copy_from_slice(&ut[..d]);
            if let Some(bound) = self.friction_bound {
                self.project_tangential(i, &ut, bound[i], contact, sums, ext);
            }
            if contact {
                sums.contact += 1.0;
            }
        }
    }

    /// Step 2 with Tresca friction at candidate i: (5.5) with the bound
    /// `s_i`, and the update (4.4) of `lambda_t`.
    #[allow(clippy::needless_range_loop)] // per-component arrays indexed together
    fn project_tangential(
        &mut self,
        i: usize,
        ut: &[f64; 3],
        bound: f64,
        contact: bool,
        sums: &mut Sums,
        ext: &mut Maxima,
    ) {
        let (d, r, rho, nc) = (self.d, self.r, self.rho, self.nc);
        let w = self.surface.cs.w[i];
        let st = &mut self.state.surface;
        let t = i * d..(i + 1) * d;
        let mut ft = 0.0;
        let mut lt = 0.0f64;
        for cc in 0..d {
            let stress = st.lambda_t[i * d + cc] + r * (ut[cc] - st.phi_t[i * d + cc]);
            st.stress_t[i * d + cc] = stress;
            let f = stress - st.lambda_t[i * d + cc];
            ft += f * f;
            lt += st.lambda_t[i * d + cc].powi(2);
            self.z_out[nc + i * d + cc] = st.lambda_t[i * d + cc] + r * ut[cc];
        }
        sums.f2 += w * ft;
        ext.f_t = ext.f_t.max(ft.sqrt());
        let mut phi_t = [0.0; 3];
        let mut lam_t = [0.0; 3];
        // Quasi-static friction: (5.5) on the slip of this load step,
        // u_t - o (o: the step's origin), phi_t = o + the projection.
        let origin = st.slip_origin.get(t.clone());
        let mut slip_ut = *ut;
        if let Some(o) = origin {
            for cc in 0..d {
                slip_ut[cc] -= o[cc];
            }
        }
        let slip = project_tangential(
            &slip_ut[..d],
            &st.lambda_t[t.clone()],
            bound,
            r,
            rho,
            &mut phi_t[..d],
            &mut lam_t[..d],
        );
        if let Some(o) = origin {
            for cc in 0..d {
                phi_t[cc] += o[cc];
            }
        }
        for cc in 0..d {
            let old = st.phi_t[i * d + cc];
            sums.dphi2 += w * (phi_t[cc] - old).powi(2);
            sums.phi2 += w * phi_t[cc] * phi_t[cc];
            sums.res2 += w * (ut[cc] - phi_t[cc]).powi(2);
        }
        let ln = lam_t[..d].iter().map(|v| v * v).sum::<f64>();
        ext.lam_t = ext.lam_t.max(lt.sqrt()).max(ln.sqrt());
        st.phi_t[t.clone()].copy_from_slice(&phi_t[..d]);
        st.lambda_t[t].copy_from_slice(&lam_t[..d]);
        sums.lam2 += w * ln;
        if slip != st.slip[i] && contact {
            sums.changes += 1.0;
        }
        st.slip[i] = slip;
        if contact {
            if slip {
                sums.slip += 1.0;
            } else {
                sums.stick += 1.0;
            }
        }
    }

    /// The sums and maxima over the ranks (one reduction each), and the
    /// measures of this iteration they give: the tension, the dual residual,
    /// the change (4.16)/(5.6), the constraint residual, the counts.
    fn reduce(&mut self, sums: Sums, ext: Maxima) -> (Sums, Maxima) {
        let ext = Maxima::from_array(allreduce_max_n(self.world, ext.to_array()));
        let sums = Sums::from_array(allreduce_sum(self.world, sums.to_array()));
        self.last = sums;
        let out = &mut self.out;
        out.tension = if ext.stress > 0.0 {
            ext.tension / ext.stress
        } else {
            0.0
        };
        self.state.peak_stress = self.state.peak_stress.max(ext.stress);
        if self.cold && self.k == 0 {
            self.state.stress_scale = ext.stress;
        }
        // The dual residual r ||phi^k - phi^{k-1}||, relative to ||lambda^{k+1}||:
        // the gap between the multiplier and the stress of u^k (4.7).
        out.dual = if sums.lam2 > 0.0 {
            self.r * (sums.dphi2 / sums.lam2).sqrt()
        } else {
            0.0
        };
        out.criterion = if self.lin.is_condensed() {
            f64::NAN // decided with the candidates
        } else {
            paper_change(sums.du2, sums.dphi2, sums.u2, sums.phi2)
        };
        out.residual = sums.res2.sqrt();
        out.contact = sums.contact as usize;
        out.stick = sums.stick as usize;
        out.slip = sums.slip as usize;
        (sums, ext)
    }

    /// The accuracy test's residual P: the map's residual |stress - lambda|
    /// (which also bounds the change of lambda by one plain step), normal
    /// and tangential parts each relative to their multiplier's max norm;
    /// with nothing in contact, relative to the stress of the first
    /// evaluation (the load's scale).
    fn residual_p(&self, ext: &Maxima) -> f64 {
        let scale_n = if ext.lam_n > 0.0 {
            ext.lam_n
        } else {
            self.state.stress_scale
        };
        let p_n = if ext.f_n == 0.0 {
            0.0
        } else {
            ext.f_n / scale_n
        };
        let p_t = if ext.f_t == 0.0 {
            0.0
        } else if self.no_friction {
            ext.f_t / scale_n // s = 0: lambda_t = 0, its stress relative to the pressure
        } else {
            ext.f_t / ext.lam_t.max(TANGENTIAL_FLOOR * scale_n)
        };
        p_n.max(p_t)
    }

    /// Anderson: the next point from `z_out = T(z_in)` and the residual
    /// norm `f` (the first evaluation only starts it). Returns the step's
    /// amplification.
    fn accelerate(&mut self, f: f64) -> Option<f64> {
        let aa = self.aa.as_mut()?;
        let mut amplification = None;
        if let Some(zi) = self.z_in.as_mut() {
            let world = self.world;
            let step = aa.step(
                |s, rcv| world.all_reduce_into(s, rcv, SystemOperation::sum()),
                zi,
                &self.z_out,
                f,
                &mut self.next,
            );
            amplification = step.amplification;
            if step.rejected && self.inner_factor > INNER_FACTOR_MIN {
                // The inexact solves' errors spoil the secant pairs
                // (tube2d_tresca with CG+GAMG: 81 rejections and 1759
                // iterations at 0.1; at 0.01 none and 115): solve the
                // rest more accurately.
                self.inner_factor = (self.inner_factor * 0.1).max(INNER_FACTOR_MIN);
            }
            std::mem::swap(zi, &mut self.next);
        } else {
            self.z_in = Some(self.z_out.clone());
        }
        self.out.anderson_steps = aa.steps;
        self.out.anderson_rejected = aa.rejected;
        amplification
    }

    /// The accuracy test's error estimate P K, and the history's entry.
    fn record(&mut self, p: f64, sums: &Sums, amplification: Option<f64>) -> f64 {
        let est = self.acc.record(
            p,
            sums.changes as usize,
            self.aa.is_some().then_some(amplification),
        );
        let out = &mut self.out;
        out.p = self.acc.residual;
        (out.k, self.state.contraction) = (self.acc.amplification, self.acc.contraction());
        out.error_estimate = est;
        self.state.history.push([
            out.criterion,
            out.residual,
            if self.paper { f64::NAN } else { est },
        ]);
        est
    }

    /// The monitor's line (`-ubr_monitor`), or the progress line.
    fn monitor(&self, its: usize, est: f64, p: f64) {
        let (out, name, k, ctl) = (&self.out, self.name, self.k, self.ctl);
        if self.root && ctl.monitor {
            let inner = if self.lin.iterative {
                format!("   inner its {its}")
            } else {
                String::new()
            };
            let test = if self.paper {
                format!("{:.6e}       {:.6e}", out.criterion, out.residual)
            } else {
                format!("{:.3e}   {:.3e}   {:.1e}", est, p, out.k)
            };
            if self.friction_bound.is_some() {
                println!(
                    "  {name} {:5}   {test}   {:7} {:6} {:6}{inner}",
                    k, out.contact, out.stick, out.slip
                );
            } else {
                println!("  {name} {:5}   {test}   {}{inner}", k, out.contact);
            }
        } else {
            crate::progress::tick(|| {
                let test = if self.paper {
                    format!(
                        "rel. change (4.16) {:.2e} (target {:.0e})",
                        out.criterion, ctl.rtol
                    )
                } else if est.is_finite() {
                    format!("estimated error {est:.2e} (target {:.0e})", ctl.lambda_rtol)
                } else {
                    format!("error not yet estimated (target {:.0e})", ctl.lambda_rtol)
                };
                format!(
                    "{name} iteration {k}: {test}, {} nodes in contact",
                    out.contact
                )
            });
        }
    }

    /// The run cannot go on: a non-finite iterate, a body pulled off the
    /// obstacle, or iterates that move without bound (true: Anderson's,
    /// the run goes on plain from its best evaluation).
    fn guard(&mut self, sums: &Sums, ext: &Maxima, p: f64) -> Result<bool, Error> {
        let (name, k) = (self.name, self.k);
        if !self.out.residual.is_finite() || !p.is_finite() {
            // At the first iteration no contact stress has acted yet: the
            // first solve's own values do not fit in double precision.
            let hint = if k <= 1 {
                ": the first solve's values do not fit in double precision; if the loads or prescribed displacements are that large against E (or E that small), express the problem in other units"
            } else {
                ""
            };
            return Err(Error::NotConverged(format!(
                "{name} produced a non-finite iterate at iteration {k}{hint}"
            )));
        }
        // A body that nothing but the contact holds along n, pulled away:
        // nothing touches, every candidate moves away from the obstacle,
        // and the stresses (then the iteration's lag r (u_n^k - u_n^{k-1}))
        // stay instead of dying out.
        if sums.contact == 0.0 && ext.dun < 0.0 && ext.stress > 0.0 {
            if self.drifting == 0 {
                self.drift_stress = ext.stress;
            }
            self.drifting += 1;
            if ext.stress < 0.999 * self.drift_stress {
                self.drifting = 0;
            }
        } else {
            self.drifting = 0;
        }
        if self.drifting >= DRIFT_ITS {
            return Err(Error::IllPosed(format!(
                "nothing holds the body along the contact direction: no node touches the obstacle and the body moves away from it by the same step every iteration ({DRIFT_ITS} iterations of {name}), so the loads pull it off the obstacle; check the signs of the loads, the contact direction (-contact_direction points from the body toward the obstacle) and the obstacle's position"
            )));
        }
        // Any body that contact alone holds, moving without bound: no
        // contact state holds the loads (a Tresca bound too small for the
        // tangential load, a pressure that friction cannot use).
        let first = *self.first_umax.get_or_insert(ext.umax);
        if ext.umax > self.ctl.drift_limit.max(10.0 * first) {
            let umax = ext.umax;
            if self.retreat(format_args!(
                "move without bound (a contact node has moved {umax:.3e})"
            )) {
                return Ok(true);
            }
            return Err(unbounded(self, sums, ext, first));
        }
        Ok(false)
    }

    /// The stopping tests ([`super::stopping`]): the accuracy test, or the
    /// paper's (4.16)/(5.6) with the held-body tests; and a stalled run.
    fn stop(&mut self, sums: &Sums, ext: &Maxima, p: f64) -> Result<bool, Error> {
        let (ctl, k) = (self.ctl, self.k);
        // The accuracy test stops at round-off too (its estimate cannot
        // fall further); the paper's test may still (its change of u).
        // Stalled far from the target, not at a floor near it (a Tresca
        // solve of CF-FP at 2e-12 with -ubr_r 31 times r0).
        let stalled = self.progress.record(p, sums.changes as usize);
        let far = self.out.error_estimate > 100.0 * ctl.lambda_rtol;
        if stalled && far && self.retreat(format_args!("have stalled (P {p:.3e})")) {
            return Ok(false);
        }
        let stalled = stalled || !self.paper && self.progress.at_roundoff();
        // Held-body tests: where nodes touch, the stress of u^k must not turn
        // tensile; where none does, an open node's stress is the lag
        // r (u_n^k - u_n^{k-1}), which dies out with the iteration when the
        // body is held: the stresses must then have decayed by eps (or to
        // round-off), their sign being noise. The dual residual, relative to
        // a multiplier that is itself noise, means nothing there.
        let (held, dual_ok) = if sums.contact > 0.0 {
            (
                self.out.tension < ctl.tension_tol,
                self.out.dual < ctl.dual_rtol,
            )
        } else {
            let decayed = ext.stress <= ctl.rtol * self.state.peak_stress
                || ext.stress <= 1e-13 * self.r * ext.un;
            (decayed, true)
        };
        let last = k >= ctl.max_it || stalled;
        let others_ok = k >= 2 && self.out.residual < ctl.residual_tol && dual_ok && held;
        if !self.paper {
            if k >= 2 && self.acc.satisfied() {
                self.out.converged = true;
                return Ok(true);
            }
        } else if self.deferred.is_some() {
            if self.stop_deferred(sums, others_ok, last)? {
                return Ok(true);
            }
        } else if others_ok && self.out.criterion < ctl.rtol {
            self.out.converged = true;
            return Ok(true);
        }
        Ok(stalled)
    }

    /// The paper's test on the condensed back-end: the change (4.16)/(5.6)
    /// needs the whole displacement: decided for the evaluations where it
    /// is the last test open (unless it surely fails), a batch at a time,
    /// going back to the first that passes, and for the last.
    fn stop_deferred(&mut self, sums: &Sums, others_ok: bool, last: bool) -> Result<bool, Error> {
        let ctl = self.ctl;
        let def = self.deferred.as_mut().expect("a deferred test");
        let decide = if others_ok || last {
            def.offer(
                Candidate {
                    iteration: self.k,
                    evaluation: self.state.history.len(),
                    inner_len: self.state.inner_iterations.len(),
                    others_ok,
                    dphi2: sums.dphi2,
                    phi2: sums.phi2,
                    dc2: sums.dc2,
                    c: self.c.clone(),
                    c_prev: self.c_prev.clone(),
                    uc: self.uc.clone(),
                    uc_prev: self.uc_prev.clone(),
                    snap: self.state.surface.clone(),
                    peak_stress: self.state.peak_stress,
                    change: f64::NAN,
                },
                ctl.rtol,
                last,
            )
        } else {
            false
        };
        if !decide {
            return Ok(false);
        }
        let found = {
            let _e = self.events.solve.begin();
            def.decide(
                self.world,
                self.lin,
                &self.surface,
                self.lumped_mass,
                &self.state.u,
                ctl.rtol,
            )?
        };
        if let Resolution::Inconsistent(why) = &found {
            if self.root {
                eprintln!(
                    "warning: {}: {why} Going on without condensation.",
                    self.name
                );
            }
            def.pending.clear();
            self.deferred = None;
            return self.uncondense(sums, others_ok);
        }
        for cand in &def.pending {
            self.state.history[cand.evaluation - 1][0] = cand.change;
        }
        if let Resolution::Converged(i) = found {
            let cand = def.pending.swap_remove(i);
            self.state.history.truncate(cand.evaluation);
            self.state.inner_iterations.truncate(cand.inner_len);
            self.state.surface = cand.snap;
            self.state.peak_stress = cand.peak_stress;
            self.out.iterations = cand.iteration;
            self.out.criterion = cand.change;
            self.out.converged = true;
            return Ok(true); // u is the candidate's
        }
        self.out.criterion = def.pending.last().map_or(f64::NAN, |c| c.change);
        def.pending.clear();
        Ok(false)
    }

    /// The condensed back-end's candidates disagree: on without
    /// condensation, this iteration's change (4.16)/(5.6) from u^{k-1} and
    /// u^k by full solves. Returns whether the run converged.
    fn uncondense(&mut self, sums: &Sums, others_ok: bool) -> Result<bool, Error> {
        let d = self.d;
        self.lin.uncondense();
        let mut scratch = vec![0.0; self.nc * d];
        self.lin
            .solve(&self.surface, &self.c_prev, &mut scratch, &self.state.u)?;
        let u_prev = &mut self.u_prev;
        self.state.u.read(|u| u_prev.copy_from_slice(u))?;
        self.lin
            .solve(&self.surface, &self.c, &mut scratch, &self.state.u)?;
        let lumped_mass = self.lumped_mass;
        let (du2, u2) = self.state.u.read(|u| {
            let s = mass_norms(lumped_mass, d, u, u_prev);
            u_prev.copy_from_slice(u);
            s
        })?;
        let [du2, u2] = allreduce_sum(self.world, [du2, u2]);
        self.out.criterion = paper_change(du2, sums.dphi2, u2, sums.phi2);
        if others_ok && self.out.criterion < self.ctl.rtol {
            self.out.converged = true;
            return Ok(true);
        }
        Ok(false)
    }

    /// Anderson: the next (phi, lambda), the projection of the new z (rho = r).
    fn project_next(&mut self) {
        let Some(zi) = self.z_in.as_mut().filter(|_| self.aa.is_some()) else {
            return;
        };
        let (d, nc, r) = (self.d, self.nc, self.r);
        let cs = self.surface.cs;
        let st = &mut self.state.surface;
        for i in 0..nc {
            let (phi, lambda, _) = project_normal_z(zi[i], cs.g[i], r);
            st.phi_n[i] = phi;
            st.lambda_n[i] = lambda;
            if let Some(bound) = self.friction_bound {
                let t = i * d..(i + 1) * d;
                let z = &mut zi[nc + i * d..nc + (i + 1) * d];
                // The tangential z in the tangent plane. The map ignores
                // its normal part (T keeps it as it is: the traction is
                // lambda_n n + lambda_t), so nothing pulls it back: the
                // extrapolation's round-off along n grew unchecked at the
                // residual's round-off floor, moving lambda_n and lambda_t
                // by 1e-5 with the traction unchanged (incline2d_coulomb
                // at -ubr_lambda_rtol 1e-10, a tilted normal). Exact zero
                // on an axis-aligned normal.
                let n = cs.n(i);
                let zn: f64 = z.iter().zip(n).map(|(a, b)| a * b).sum();
                for (zc, nk) in z.iter_mut().zip(n) {
                    *zc -= zn * nk;
                }
                let z = &*z;
                match st.slip_origin.get(t.clone()) {
                    // Quasi-static: lambda_t = P_s(z - r o), phi_t =
                    // (z - lambda_t) / r (o + the slip of the step).
                    Some(o) => {
                        let mut zs = [0.0; 3];
                        for ((s, z), o) in zs.iter_mut().zip(z).zip(o) {
                            *s = z - r * o;
                        }
                        let lam = &mut st.lambda_t[t.clone()];
                        project_tangential_z(&zs[..d], bound[i], r, &mut st.phi_t[t.clone()], lam);
                        let (phi, lam) = (&mut st.phi_t[t.clone()], &st.lambda_t[t]);
                        for ((p, z), l) in phi.iter_mut().zip(z).zip(lam) {
                            *p = (z - l) / r;
                        }
                    }
                    None => {
                        project_tangential_z(
                            z,
                            bound[i],
                            r,
                            &mut st.phi_t[t.clone()],
                            &mut st.lambda_t[t],
                        );
                    }
                }
            }
        }
    }

    /// The whole displacement of the last evaluation, `u_t` from it (a
    /// condensed run), why the run failed, and the Anderson summary.
    fn finish(mut self) -> Result<UbrOutcome, Error> {
        // A condensed run knows it at the contact nodes only (the paper's
        // candidates leave theirs).
        // (A run that did not converge reports its state: with its
        // displacement, even where none was wanted.)
        let mode = match self.ctl.displacement {
            Whole::No if !self.out.converged => Whole::Only,
            m => m,
        };
        let pending = Pending {
            c_prev: std::mem::take(&mut self.c_prev),
            uc_prev: std::mem::take(&mut self.uc_prev),
            c: std::mem::take(&mut self.c),
            uc: std::mem::take(&mut self.uc),
            dphi2: self.last.dphi2,
            phi2: self.last.phi2,
        };
        if self.ctl.defer_whole && self.lin.is_condensed() && !self.paper {
            // The caller makes it (`complete`), once it knows it is wanted.
            self.out.pending = Some(pending);
        } else {
            let (lin, surface) = (&mut *self.lin, &self.surface);
            let paper = self.paper;
            let state = &mut *self.state;
            if let Some(c) = whole_displacement(
                self.world,
                lin,
                surface,
                self.lumped_mass,
                state,
                &pending,
                mode,
                paper,
            )? {
                self.out.criterion = c;
            }
            if self.was_condensed && mode != Whole::No && !lin.condenses_every_component() {
                tangential_from_whole(surface, state)?;
            }
        }
        let (name, ctl, r) = (self.name, self.ctl, self.r);
        let mut out = self.out;
        if !out.converged {
            out.roundoff = !self.paper && self.progress.at_roundoff();
            out.failure = Some(if out.roundoff {
                roundoff(name, ctl, &out, &self.acc, &self.progress)
            } else if self.progress.since >= STALL_ITS {
                out.stalled = true;
                // Slipping everywhere explains a stall only where the body
                // can move rigidly: some rigid motion that no Dirichlet
                // condition holds (a finite drift limit).
                let slides = self.friction_bound.is_some()
                    && !self.no_friction
                    && ctl.drift_limit.is_finite();
                let (inexact, its) = (self.lin.iterative, &self.state.inner_iterations);
                let scene = StallScene::new(slides, inexact, its);
                stalled(name, ctl, &out, r, &self.acc, &self.progress, scene)
            } else {
                failure(name, ctl, &out, r, &self.acc)
            });
        }
        if self.root && ctl.monitor && self.aa.is_some() {
            println!(
                "  {name}: Anderson: {} of {} evaluations at extrapolated points, {} rejected by the safeguard",
                out.anderson_steps, out.iterations, out.anderson_rejected
            );
        }
        Ok(out)
    }
}
