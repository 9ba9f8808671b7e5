//! Load histories on the one factorization: the load of a step is a
//! combination of fixed parts, one per load group of the history
//! ([`crate::options::history`]), so moving from one step to the next
//! changes only the right-hand side `rhs0 = f - A x_D` (and, condensed,
//! its Schur components `y0`: one solve with the factors), never K or B.
//!
//! The parts are made at the assembly, while the matrix still has its
//! Dirichlet rows: `f_g - A x_{D,g}` for each named group g (its tractions,
//! pressures or body force f_g, its prescribed values x_{D,g}), and the
//! rest (every load the history does not name, at factor 1) as the whole
//! less their sum. `-load_steps` scales the whole load: one part.

use super::{Dirichlet, Problem};
use crate::error::Error;
use crate::fem;
use crate::mesh::distribute::LocalMesh;
use crate::options::history::LoadGroup;
use crate::options::Settings;
use crate::petsc::{Matrix, Vector};

/// One part of the load: `f`, `f - A x_D` with `diag_scale x_D` on the
/// Dirichlet rows, and `x_D` (per owned dof, 0 where not prescribed).
#[derive(Clone, Debug)]
pub struct LoadPart {
    pub load: Vec<f64>,
    pub rhs0: Vec<f64>,
    pub xd: Vec<f64>,
}

/// The parts of a history's load: one per group, then (for named groups)
/// the rest, which stays at factor 1.
#[derive(Clone, Debug)]
pub struct LoadParts {
    pub parts: Vec<LoadPart>,
    pub rest: Option<LoadPart>,
    /// Condensed: the Schur components of `u_C` for each part's `rhs0`
    /// (then the rest's), made at the first step: a step's `y0` is their
    /// combination, with no solve.
    y0: Option<Vec<Vec<f64>>>,
}

/// Per named group, before the elimination: `f_g` and `f_g - A x_{D,g}`.
/// None without a history, or for a proportional one (`[All]`: its part is
/// the whole load, [`finish`]).
pub fn split(
    mesh: &LocalMesh,
    settings: &Settings,
    matrix: &Matrix,
    lumped_mass: &[f64],
    template: &Vector,
    transform: Option<&super::mortar::Transform>,
) -> Result<Option<Vec<LoadPart>>, Error> {
    let Some(history) = &settings.history else {
        return Ok(None);
    };
    if history.groups == [LoadGroup::All] {
        return Ok(None);
    }
    let d = mesh.dim;
    let nown = mesh.owned_count * d;
    // The group whose value a Dirichlet dof takes: the first that names it
    // (as [`fem::dirichlet_dofs`] keeps it).
    let mut owner = vec![usize::MAX; nown];
    let mut value = vec![0.0; nown];
    for (k, bc) in settings.dirichlet.iter().enumerate() {
        for (i, v) in fem::dirichlet_dofs(mesh, std::slice::from_ref(bc))? {
            if owner[i] == usize::MAX {
                owner[i] = k;
                value[i] = v;
            }
        }
    }
    let mut parts = Vec::with_capacity(history.groups.len());
    for g in &history.groups {
        let mut only = settings.clone();
        only.traction.clear();
        only.pressure.clear();
        only.body_force = None;
        let mut xd = vec![0.0; nown];
        match g {
            LoadGroup::Traction(n) => only
                .traction
                .extend(settings.traction.iter().filter(|t| &t.group == n).cloned()),
            LoadGroup::Pressure(n) => only
                .pressure
                .extend(settings.pressure.iter().filter(|t| &t.group == n).cloned()),
            LoadGroup::Body => only.body_force = settings.body_force.clone(),
            LoadGroup::Dirichlet(n) => {
                let k = settings.dirichlet.iter().position(|b| &b.group == n);
                for i in 0..nown {
                    if Some(owner[i]) == k {
                        xd[i] = value[i];
                    }
                }
            }
            LoadGroup::All => unreachable!("a proportional history has no named group"),
        }
        let load = fem::loads::external_load(mesh, &only, lumped_mass)?;
        let x = template.duplicate()?;
        x.write(|v| v.copy_from_slice(&xd))?;
        let ax = template.duplicate()?;
        matrix.mult(&x, &ax)?;
        // (With a contact pair the right-hand side is on the changed
        // unknowns, `T^T f_g - A x_D`; `load` stays f_g.)
        let on_unknowns = match transform {
            Some(t) => t.transpose_apply(&load, d)?,
            None => load.clone(),
        };
        let rhs0 = ax.read(|a| on_unknowns.iter().zip(a).map(|(f, a)| f - a).collect())?;
        parts.push(LoadPart { load, rhs0, xd });
    }
    Ok(Some(parts))
}

/// The parts after the elimination (`rhs0`: the whole lifted load, `dir`
/// with its diagonal): the Dirichlet rows of each named part, and the
/// rest; a proportional history's one part is the whole load.
pub fn finish(
    settings: &Settings,
    named: Option<Vec<LoadPart>>,
    load: &Vector,
    rhs0: &Vector,
    dir: &Dirichlet,
) -> Result<Option<LoadParts>, Error> {
    if settings.history.is_none() {
        return Ok(None);
    }
    let load = load.read(|v| v.to_vec())?;
    let rhs0 = rhs0.read(|v| v.to_vec())?;
    let mut xd = vec![0.0; load.len()];
    for &(i, v) in &dir.dofs {
        xd[i] = v;
    }
    let whole = LoadPart { load, rhs0, xd };
    let Some(mut parts) = named else {
        return Ok(Some(LoadParts {
            parts: vec![whole],
            rest: None,
            y0: None,
        }));
    };
    let mut rest = whole;
    for p in &mut parts {
        for &(i, _) in &dir.dofs {
            p.rhs0[i] = dir.diag_scale * p.xd[i];
        }
        for (r, x) in [
            (&mut rest.load, &p.load),
            (&mut rest.rhs0, &p.rhs0),
            (&mut rest.xd, &p.xd),
        ] {
            r.iter_mut().zip(x).for_each(|(r, x)| *r -= x);
        }
    }
    Ok(Some(LoadParts {
        parts,
        rest: Some(rest),
        y0: None,
    }))
}

impl LoadParts {
    /// `(f, rhs0, x_D)` at the factors of one step (one per part).
    pub fn at(&self, factors: &[f64]) -> LoadPart {
        let n = self.parts[0].load.len();
        let mut out = match &self.rest {
            Some(r) => r.clone(),
            None => LoadPart {
                load: vec![0.0; n],
                rhs0: vec![0.0; n],
                xd: vec![0.0; n],
            },
        };
        for (p, &a) in self.parts.iter().zip(factors) {
            for (o, x) in [
                (&mut out.load, &p.load),
                (&mut out.rhs0, &p.rhs0),
                (&mut out.xd, &p.xd),
            ] {
                o.iter_mut().zip(x).for_each(|(o, x)| *o += a * x);
            }
        }
        out
    }
}

impl Problem {
    /// Moves the problem to the load of `factors` (one per group of the
    /// history): the load f, the Dirichlet values and the lifted
    /// right-hand side, on the same factorization.
    /// `keep`: the columns of the step's whole displacement wanted at its
    /// end (condensed: a solve prepares their expansion; 0: no solve).
    pub fn apply_load(&mut self, factors: &[f64], keep: usize) -> Result<(), Error> {
        // The condensed response is always the combination of the parts'
        // (a step whose whole displacement is wanted also solves, for its
        // expansion only): the one solve's y0 would differ by round-off,
        // and a step's outputs (-history_output, -vtk) would change the
        // steps after it (a sliding Coulomb history at -ubr_lambda_rtol
        // 1e-9 converged without -history_output and stopped at
        // -ubr_fp_max_it with it).
        self.part_responses()?;
        let Some(parts) = &self.parts else {
            return Err(Error::Internal("a load step without a load history".into()));
        };
        let step = parts.at(factors);
        let y0a = match &parts.y0 {
            Some(y0) => {
                let mut y = vec![0.0; y0[0].len()];
                let rest = parts.rest.as_ref().map(|_| &y0[parts.parts.len()]);
                for (yg, &a) in y0.iter().zip(factors) {
                    y.iter_mut().zip(yg).for_each(|(y, g)| *y += a * g);
                }
                if let Some(r) = rest {
                    y.iter_mut().zip(r).for_each(|(y, g)| *y += g);
                }
                Some(y)
            }
            _ => None,
        };
        self.load.write(|f| f.copy_from_slice(&step.load))?;
        let d = self.dim;
        for (i, v) in self.dirichlet.dofs.iter_mut() {
            *v = step.xd[*i];
        }
        let values: Vec<f64> = self
            .contact
            .node
            .iter()
            .flat_map(|&v| (0..d).map(move |c| v * d + c))
            .map(|i| step.xd[i])
            .collect();
        for (cv, (&fixed, v)) in self
            .dirichlet
            .contact_values
            .iter_mut()
            .zip(self.dirichlet.contact.iter().zip(values))
        {
            *cv = if fixed { v } else { 0.0 };
        }
        let surface = super::Surface {
            cs: &self.contact,
            dim: d,
            tangential: self.tangential,
            dirichlet: &self.dirichlet.contact,
        };
        self.lin.set_load(
            &surface,
            &step.rhs0,
            self.dirichlet.contact_values.clone(),
            self.dirichlet.dofs.clone(),
            y0a,
            keep,
        )
    }

    /// Condensed: the Schur components of each part's response, once.
    fn part_responses(&mut self) -> Result<(), Error> {
        let Some(parts) = self.parts.as_mut() else {
            return Ok(());
        };
        if parts.y0.is_some() {
            return Ok(());
        }
        let surface = super::Surface {
            cs: &self.contact,
            dim: self.dim,
            tangential: self.tangential,
            dirichlet: &self.dirichlet.contact,
        };
        let mut y0 = Vec::new();
        for p in parts.parts.iter().chain(&parts.rest) {
            match self.lin.contact_part(&surface, &p.rhs0)? {
                Some(y) => y0.push(y),
                None => return Ok(()),
            }
        }
        parts.y0 = Some(y0);
        Ok(())
    }
}
