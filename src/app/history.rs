//! The Iterations stage of a load history: every step on the one
//! factorization ([`Problem::apply_load`]), warm-started from the step
//! before, friction quasi-static (the slip measured from the previous
//! step's tangential displacement), a row of measures per step and, with
//! `-vtk`, one ParaView file per step.

use super::{ContactProblem, Solution};
use crate::checks;
use crate::comm::allreduce_sum_vec;
use crate::contact::hertz;
use crate::error::Error;
use crate::fem;
use crate::mesh::distribute::LocalMesh;
use crate::options::history::{LoadGroup, LoadHistory};
use crate::options::{Friction, Settings};
use crate::progress;
use crate::report::history::{step_path, StepRow};
use crate::report::{self, files, ContactRow};
use crate::solver::outcome;
use crate::solver::ubr::Whole;
use crate::solver::Problem;
use crate::wellposed::{LoadStep, Restraint, MAX_CHECKED_STEPS};
use mpi::traits::*;
use std::collections::HashSet;
use std::time::Instant;

/// The force-displacement curve of a history: a load group, a component,
/// the group's owned nodes and its force at factor 1 (applied loads).
pub struct Curve {
    pub label: String,
    group: LoadGroup,
    comp: usize,
    nodes: Vec<usize>,
    count: f64,
    full_force: Vec<f64>,
}

impl Curve {
    /// The curve `-history_curve` names, else the first group of the
    /// history with a load (a Dirichlet group with a non-zero value first),
    /// along its largest component.
    pub fn new<C: Communicator>(
        world: &C,
        local: &LocalMesh,
        s: &Settings,
        problem: &Problem,
    ) -> Result<Curve, Error> {
        let h = s.history.as_ref().expect("a load history");
        let d = local.dim;
        let (group, comp) = match &h.curve {
            Some((g, c)) => (g.clone(), *c),
            None => (default_group(s, h), None),
        };
        let force = applied_force(world, local, s, problem, &group)?;
        let (option, name) = match &group {
            LoadGroup::Traction(n) => ("-traction_", n.as_str()),
            LoadGroup::Pressure(n) => ("-pressure_", n.as_str()),
            LoadGroup::Dirichlet(n) => ("-dirichlet_", n.as_str()),
            LoadGroup::Body | LoadGroup::All => ("", ""),
        };
        let nodes: Vec<usize> = if name.is_empty() {
            (0..local.owned_count).collect()
        } else {
            let g = local.group_for(&format!("{option}{name}"), name, 0..=d - 1, "a load")?;
            let mut v: Vec<usize> = g
                .conn
                .nodes()
                .iter()
                .copied()
                .filter(|&v| local.is_owned(v))
                .collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        let count = allreduce_sum_vec(world, &[nodes.len() as f64])[0].max(1.0);
        let comp = comp.unwrap_or_else(|| largest_component(s, &group, &force, d));
        let label = format!("{}_{}", group.name(), ["ux", "uy", "uz"][comp]);
        Ok(Curve {
            label,
            group,
            comp,
            nodes,
            count,
            full_force: force,
        })
    }

    /// The point of a step: the group's mean displacement along the
    /// component, and the force on it (a Dirichlet group's reaction, else
    /// the applied load at the step's factor). Collective.
    fn point<C: Communicator>(
        &self,
        world: &C,
        h: &LoadHistory,
        factors: &[f64],
        d: usize,
        u_local: &[f64],
        reactions: &[(String, Vec<f64>)],
    ) -> (f64, f64) {
        let sum: f64 = self.nodes.iter().map(|&v| u_local[v * d + self.comp]).sum();
        let x = allreduce_sum_vec(world, &[sum])[0] / self.count;
        let y = match &self.group {
            LoadGroup::Dirichlet(n) => reactions
                .iter()
                .find(|(g, _)| g == n)
                .map_or(0.0, |(_, f)| f[self.comp]),
            g => factor_of(h, g, factors) * self.full_force[self.comp],
        };
        (x, y)
    }
}

/// The factor of group `g` at a step: its column, the proportional
/// factor, or 1 (a load the history does not name).
fn factor_of(h: &LoadHistory, g: &LoadGroup, factors: &[f64]) -> f64 {
    if h.groups == [LoadGroup::All] {
        return factors[0];
    }
    h.groups
        .iter()
        .position(|x| x == g)
        .map_or(1.0, |k| factors[k])
}

fn default_group(s: &Settings, h: &LoadHistory) -> LoadGroup {
    if let Some(g) = h.groups.iter().find(|g| **g != LoadGroup::All) {
        return g.clone();
    }
    if let Some(b) = s
        .dirichlet
        .iter()
        .find(|b| b.comps.iter().any(|&(_, v)| v != 0.0))
    {
        return LoadGroup::Dirichlet(b.group.clone());
    }
    if let Some(t) = s.traction.first() {
        return LoadGroup::Traction(t.group.clone());
    }
    if let Some(p) = s.pressure.first() {
        return LoadGroup::Pressure(p.group.clone());
    }
    LoadGroup::Body
}

/// The component of the curve: a Dirichlet group's largest prescribed
/// value, else the largest component of the applied force.
fn largest_component(s: &Settings, g: &LoadGroup, force: &[f64], d: usize) -> usize {
    let mut best = (0, -1.0);
    let mut consider = |c: usize, v: f64| {
        if c < d && v.abs() > best.1 {
            best = (c, v.abs());
        }
    };
    match g {
        LoadGroup::Dirichlet(n) => {
            for b in s.dirichlet.iter().filter(|b| &b.group == n) {
                for &(c, v) in &b.comps {
                    consider(c, v);
                }
            }
        }
        _ => force.iter().enumerate().for_each(|(c, &v)| consider(c, v)),
    }
    best.0
}

/// The total force of an applied load group at factor 1 (zero for a
/// Dirichlet group). Collective.
fn applied_force<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    s: &Settings,
    problem: &Problem,
    g: &LoadGroup,
) -> Result<Vec<f64>, Error> {
    let d = local.dim;
    let mut only = s.clone();
    only.traction
        .retain(|t| matches!(g, LoadGroup::Traction(n) if *n == t.group));
    only.pressure
        .retain(|p| matches!(g, LoadGroup::Pressure(n) if *n == p.group));
    if *g != LoadGroup::Body {
        only.body_force = None;
    }
    let f = fem::loads::external_load(local, &only, &problem.lumped_mass)?;
    let mut total = vec![0.0; d];
    for (i, v) in f.iter().enumerate() {
        total[i % d] += v;
    }
    Ok(allreduce_sum_vec(world, &total))
}

/// The measures of a step from the gathered rows (rank 0): contact area,
/// extent from `center` (orthogonal to `n` where given), peak pressure,
/// and the node counts.
fn measures(
    rows: &[ContactRow],
    d: usize,
    center: &[f64],
    n: Option<&[f64]>,
    line: Option<&[f64]>,
    row: &mut StepRow,
) {
    for r in rows.iter().filter(|r| r.status != 0) {
        row.contact_nodes += 1;
        match r.status {
            2 => row.stick += 1,
            3 => row.slip += 1,
            _ => {}
        }
        row.contact_area += r.weight;
        row.peak_pressure = row.peak_pressure.max(r.lambda_n);
        let mut v: Vec<f64> = (0..d).map(|c| r.x[c] - center[c]).collect();
        if let Some(n) = n {
            let along: f64 = v.iter().zip(n).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(n).for_each(|(a, b)| *a -= along * b);
        }
        // (A line contact, `-reference_axis`: from the contact line.)
        if let Some(l) = line {
            let along: f64 = v.iter().zip(l).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(l).for_each(|(a, b)| *a -= along * b);
        }
        let dist = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        row.contact_extent = row.contact_extent.max(dist);
    }
}

impl<C: Communicator> ContactProblem<'_, C> {
    /// Every step of the history; returns the last step's solution (the
    /// first that failed, if one did, and the steps before it are kept).
    pub(super) fn solve_history(
        &mut self,
        local: &LocalMesh,
        problem: &mut Problem,
        restraint: &Restraint,
    ) -> Result<Solution, Error> {
        let _guard = self.stages.iterations.push()?;
        let t_all = Instant::now();
        let h = self.settings.history.clone().expect("a load history");
        let curve = Curve::new(self.world, local, &self.settings, problem)?;
        // (Named now: a step that cannot go on ends the history early, and
        // the table of the steps before it is written.)
        self.curve_label = curve.label.clone();
        let n = h.factors.len();
        let friction = self.settings.friction != Friction::None;
        let s = &self.settings;
        let every = s.history_output.is_some() || s.plot_history_curve.is_some() || s.vtk.is_some();
        let mut last: Option<Solution> = None;
        for (k, factors) in h.factors.iter().enumerate() {
            let t = Instant::now();
            let label = format!(
                "load step {}/{n} ({} {})",
                k + 1,
                h.source,
                fmt_factors(factors)
            );
            progress::phase(false, || label.clone());
            // What of the step's whole displacement is wanted: u and the
            // paper's change at the last step (and the first, a single
            // solve's), u alone for a per-step output, else nothing.
            let whole = if k == 0 || k + 1 == n {
                Whole::WithChange
            } else if every {
                Whole::Only
            } else {
                Whole::No
            };
            let keep = match whole {
                Whole::WithChange => 2,
                Whole::Only => 1,
                Whole::No => 0,
            };
            problem.apply_load(factors, keep)?;
            // A solve that cannot go on (a non-finite iterate, a body that
            // moves without bound) names the step, as one that stops
            // unconverged does below.
            let at_step = |e: Error| match e {
                Error::NotConverged(m) => Error::NotConverged(format!("{label}: {m}")),
                e => e,
            };
            let sol = match last.take() {
                None => {
                    let (state, solved) = outcome::solve(
                        self.world,
                        local,
                        &self.settings,
                        problem,
                        restraint,
                        &self.events,
                    )
                    .map_err(at_step)?;
                    Solution { state, solved }
                }
                Some(mut prev) => {
                    if friction {
                        // Quasi-static: this step's slip from where the
                        // last one left the surface.
                        prev.state.surface.slip_origin = prev.state.surface.ut.clone();
                    }
                    let s_prev: Vec<f64> = prev
                        .state
                        .surface
                        .lambda_n
                        .iter()
                        .map(|l| self.settings.friction_coefficient * l.abs())
                        .collect();
                    let solved = outcome::solve_step(
                        self.world,
                        local,
                        &self.settings,
                        problem,
                        restraint,
                        &self.events,
                        &mut prev.state,
                        &s_prev,
                        whole,
                    )
                    .map_err(at_step)?;
                    Solution {
                        state: prev.state,
                        solved,
                    }
                }
            };
            for w in std::mem::take(&mut problem.lin.warnings) {
                self.warn(format!("{label}: {w}"));
            }
            // Without a per-step output, a step's whole displacement, its
            // forces and rows are not made (the last step's are, by the run).
            let stop = !sol.solved.converged;
            let mut sol = sol;
            if stop {
                // The run's failure names the step.
                let why = sol.solved.failure();
                sol.solved.failure = Some(format!("{label}: {why}"));
                // (`failure()` puts a tension message first: it is in `why`.)
                sol.solved.last.tension = 0.0;
            }
            if every {
                let row = self.step_row(local, problem, restraint, &sol, &curve, &h, k, t)?;
                self.steps.push(row);
            }
            last = Some(sol);
            if stop {
                break;
            }
        }
        self.times.iterations = t_all.elapsed().as_secs_f64();
        Ok(last.expect("at least one step"))
    }

    /// The row of step `k` (and its ParaView file).
    #[allow(clippy::too_many_arguments)]
    fn step_row(
        &mut self,
        local: &LocalMesh,
        problem: &Problem,
        restraint: &Restraint,
        sol: &Solution,
        curve: &Curve,
        h: &LoadHistory,
        k: usize,
        t: Instant,
    ) -> Result<StepRow, Error> {
        let d = local.dim;
        // The measures of the step; the checks of the answer (optimality,
        // deformation, bodies touching) are the last step's, in the run.
        let _ = restraint;
        let world = self.world;
        let s = &self.settings;
        let u_local = checks::local_displacement(local, &problem.physical(&sol.state.u)?)?;
        let forces = checks::forces(world, local, s, problem, &sol.state, &u_local)?;
        let rows = report::contact_rows(local, problem, &sol.state, &sol.solved.bound);
        let rows = report::gather_rows(world, &rows);
        let mut row = StepRow {
            step: k + 1,
            factors: h.factors[k].clone(),
            contact_force: forces.contact.clone(),
            reactions: forces.reactions.clone(),
            obstacles: history_forces(s, &forces.obstacles),
            iterations: sol.solved.iterations,
            converged: sol.solved.converged,
            ..Default::default()
        };
        row.curve = curve.point(world, h, &h.factors[k], d, &u_local, &forces.reactions);
        if self.root {
            let contact = s.contact.as_ref().expect("a contact surface");
            // The contact centre: -reference_center, else the candidate
            // with the smallest gap; the extent is measured orthogonal to
            // -contact_direction, else to that candidate's normal.
            let center = hertz::center(
                s.contact_center.as_deref(),
                d,
                rows.iter().map(|r| (r.gap, &r.x[..])),
            );
            let nearest = rows.iter().min_by(|a, b| a.gap.total_cmp(&b.gap));
            let n = if contact.direction.len() == d {
                contact.direction.clone()
            } else {
                nearest.map_or(vec![0.0; d], |r| r.normal[..d].to_vec())
            };
            let line = s.reference.as_ref().and_then(|h| h.line(&n));
            measures(&rows, d, &center, Some(&n), line.as_deref(), &mut row);
        }
        if let Some(path) = &s.vtk {
            let rows = report::broadcast_rows(world, &rows);
            let step = step_path(path, k + 1);
            let written = files::write_vtk(world, &step, (s, local), &u_local, &rows, None);
            files::collective(world, written)?;
        }
        row.time = t.elapsed().as_secs_f64();
        Ok(row)
    }
}

/// The loads of a history's steps to judge before the factorization
/// ([`crate::wellposed::check_steps`]): one per direction of the factors
/// (a positive multiple of a load is held as it is; the rest's factor 1
/// appended where `rest`), the first [`MAX_CHECKED_STEPS`] directions,
/// named as the step's solve is. Not `distinct`: every step (a Tresca
/// bound holds a load up to a size, [`crate::wellposed::check_tresca`]).
pub(super) fn steps_to_check(h: &LoadHistory, rest: bool, distinct: bool) -> Vec<LoadStep> {
    let n = h.factors.len();
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    for (k, f) in h.factors.iter().enumerate() {
        let mut coefs = f.clone();
        if rest {
            coefs.push(1.0);
        }
        let big = coefs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if big == 0.0 || !big.is_finite() {
            continue;
        }
        let key: Vec<i64> = coefs
            .iter()
            .map(|x| (x / big * 1e12).round() as i64)
            .collect();
        if distinct && !seen.insert(key) {
            continue;
        }
        let label = format!("load step {}/{n} ({} {})", k + 1, h.source, fmt_factors(f));
        out.push(LoadStep {
            label: Some(label),
            coefs,
        });
        if distinct && out.len() == MAX_CHECKED_STEPS {
            break;
        }
    }
    out
}

fn fmt_factors(f: &[f64]) -> String {
    // (An exponent outside 1e-3..1e6: a factor of 1e300 is one number.)
    f.iter()
        .map(|&x| match x.abs() {
            a if a != 0.0 && !(1e-3..1e6).contains(&a) => format!("{x:.4e}"),
            _ => format!("{x:.4}"),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// The forces of the history table's own columns: each rigid obstacle's
/// where there are several (one's is `contact_force`), and each contact
/// pair's (`SLAVE/MASTER`: the master's force on the slave, which
/// `contact_force` leaves out), in the order of `forces`.
fn history_forces(s: &Settings, forces: &[(String, Vec<f64>, usize)]) -> Vec<(String, Vec<f64>)> {
    let rigid = s.contact.as_ref().map_or(0, |c| c.obstacles.len());
    forces
        .iter()
        .enumerate()
        .filter(|&(k, _)| rigid > 1 || k >= rigid)
        .map(|(_, (n, f, _))| (n.clone(), f.clone()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_checked_once_per_load_direction() {
        let h = LoadHistory {
            groups: vec![LoadGroup::All],
            factors: vec![vec![0.5], vec![1.0], vec![0.0], vec![-1.0], vec![-0.25]],
            source: "-load_history h.csv".into(),
            curve: None,
        };
        let steps = steps_to_check(&h, false, true);
        let labels: Vec<_> = steps.iter().map(|s| s.label.clone().unwrap()).collect();
        assert_eq!(
            labels,
            [
                "load step 1/5 (-load_history h.csv 0.5000)",
                "load step 4/5 (-load_history h.csv -1.0000)"
            ]
        );
        // With the rest at factor 1, each step's factors are a direction.
        let steps = steps_to_check(&h, true, true);
        assert_eq!(steps.len(), 5);
        assert_eq!(steps[2].coefs, [0.0, 1.0]);
        // Every step where a bound holds a load up to a size (Tresca),
        // the zero one left out.
        let steps = steps_to_check(&h, false, false);
        let labels: Vec<_> = steps.iter().map(|s| s.label.clone().unwrap()).collect();
        assert_eq!(labels.len(), 4);
        assert_eq!(labels[1], "load step 2/5 (-load_history h.csv 1.0000)");
    }
}
