//! The program's settings, read from PETSc's options database (command line,
//! `-options_file`, `PETSC_OPTIONS`). Every option is declared once in
//! [`declared`] with its typed default and help text (which `-help` prints);
//! every parse error names the option. [`files`] expands the options files
//! before PETSc starts; [`outputs`] checks the output paths, [`solver`]
//! PETSc's linear-solver options, before any work; [`inert`] names the
//! options that have no effect in the scene, [`unused`] those that nothing
//! used.

pub mod choices;
pub mod declared;
pub mod files;
pub mod history;
pub mod inert;
pub mod materials;
mod numbers;
pub mod obstacles;
pub mod outputs;
mod pairs;
mod reference;
pub mod solver;
pub mod unused;

use crate::error::{bad, Error};
use crate::petsc;
pub use choices::{Algorithm, LinearBackend, NamedObstacle, NormalMode, Obstacle, StopRule};
pub use declared::print_help;
use declared::*;
use mpi::traits::*;
pub(crate) use numbers::shown;
use numbers::{positive, unit};

#[derive(Clone, Debug, PartialEq)]
pub enum MeshSource {
    File(String),
    /// A built-in mesh; `q1`: quadrilaterals / hexahedra instead of simplices.
    Generate {
        name: String,
        h: f64,
        q1: bool,
    },
}

/// How rank 0 splits the mesh over the ranks (`-partition`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Partitioner {
    Metis,
    Rcb,
    PtScotch,
}

impl Partitioner {
    /// The report's name of the partition on `ranks` ranks.
    pub fn name(self, ranks: usize) -> &'static str {
        match self {
            _ if ranks == 1 => "none",
            Partitioner::Rcb => "rcb",
            Partitioner::Metis => "metis",
            Partitioner::PtScotch => "ptscotch",
        }
    }
    /// The summary's words for it.
    pub fn words(self) -> &'static str {
        match self {
            Partitioner::Rcb => "recursive coordinate bisection",
            Partitioner::Metis => "METIS k-way",
            Partitioner::PtScotch => "PT-Scotch (in parallel)",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Friction {
    None,
    Tresca,
    Coulomb,
}

impl Friction {
    /// The option's word: none, tresca, coulomb.
    pub fn name(self) -> &'static str {
        match self {
            Friction::None => "none",
            Friction::Tresca => "tresca",
            Friction::Coulomb => "coulomb",
        }
    }
}

/// Where the Tresca bound s comes from (`-tresca_bound`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrescaBound {
    /// s = VALUE at every candidate.
    Value(f64),
    /// s = nu_f times the Hertz pressure (needs -reference hertz).
    Hertz,
    /// s = nu_f times lambda_c of a frictionless solve run first.
    Frictionless,
}

#[derive(Clone, Debug)]
pub struct ContactSettings {
    /// The physical groups of Gamma_c (one or more, one obstacle).
    pub surfaces: Vec<String>,
    /// `-contact_direction` (empty when not given, with closest normals).
    pub direction: Vec<f64>,
    /// `-contact_normal`, `auto` resolved.
    pub normal: NormalMode,
    pub obstacle: Obstacle,
    /// Every obstacle: `obstacle` alone (named "obstacle"), or those of
    /// `-obstacles` (then `obstacle`, `normal` are the first's, for what
    /// needs one point or one mode).
    pub obstacles: Vec<NamedObstacle>,
    /// Whether they come from `-obstacles` (their options are then
    /// `-obstacle_NAME_...`).
    pub named: bool,
    /// `-contact_pair`: (slave, master) surface groups of two elastic
    /// bodies ([`crate::contact::mortar`]).
    pub pairs: Vec<(String, String)>,
    /// `-contact_pair_scheme node_to_segment` (not the mortar).
    pub pair_node_to_segment: bool,
}

impl ContactSettings {
    /// "a" or "a, b": the surfaces, for messages.
    /// The contact surfaces' names; with pairs alone, their slaves'.
    pub fn surface_names(&self) -> String {
        let slaves: Vec<&str> = self.pairs.iter().map(|(s, _)| s.as_str()).collect();
        let names: Vec<&str> = self.surfaces.iter().map(String::as_str).collect();
        if names.is_empty() { slaves } else { names }.join(", ")
    }
}

#[derive(Clone, Debug)]
pub struct HertzReference {
    pub force: f64,
    pub radius: f64,
    pub center: Option<Vec<f64>>,
    /// `-reference_axis` (3D, unit): a cylinder lying along it, a line
    /// contact (Hertz's 2D formula, the force per unit length).
    pub axis: Option<Vec<f64>>,
}

/// One prescribed displacement: component `comp` of the nodes of group `group`.
#[derive(Clone, Debug)]
pub struct DirichletBc {
    pub group: String,
    pub comps: Vec<(usize, f64)>,
}

#[derive(Clone, Debug)]
pub struct TractionBc {
    pub group: String,
    pub traction: Vec<f64>,
}

/// A pressure on a boundary group, along its facet normals, positive pushing in.
#[derive(Clone, Debug)]
pub struct PressureBc {
    pub group: String,
    pub pressure: f64,
}

/// UBR settings (r, the acceleration, the stopping test and caps).
#[derive(Clone, Debug)]
pub struct UbrSettings {
    /// r (None: automatic).
    pub r: Option<f64>,
    /// rho (None: rho = r).
    pub rho: Option<f64>,
    pub stop: StopRule,
    pub lambda_rtol: f64,
    pub rtol: f64,
    pub residual_tol: f64,
    pub max_it: usize,
    pub fp_rtol: f64,
    pub fp_max_it: usize,
    /// Anderson memory of CF-FP's outer fixed point (0: plain).
    pub fp_anderson: usize,
    pub monitor: bool,
    pub inner_rtol_factor: f64,
    pub dual_rtol: f64,
    /// Anderson memory (0: the paper's plain iteration).
    pub anderson: usize,
    /// MUMPS called directly for the default direct solver (else through PETSc).
    pub mumps_direct: bool,
    /// Iterative solvers: products with an SBAIJ copy of the operator.
    pub sbaij: bool,
    /// Condense the UBR solve onto the contact unknowns when there are at
    /// most this many (None: the default of the dimension, see `-help`).
    pub condense_max: Option<usize>,
    /// Several ranks: the Schur complement distributed over the ranks and
    /// factorized there by ScaLAPACK (None: not given, the default of the
    /// rank count and dimension, [`crate::linalg::SCHUR_GRID_RANKS`]).
    pub schur_distributed: Option<bool>,
    /// MUMPS' full solves with distributed right-hand sides and solutions
    /// (`-ubr_mumps_rhs distributed`), else through rank 0.
    pub distributed_rhs: bool,
    /// MUMPS' pre-splitting of large fronts (`-ubr_mumps_split`); None: the
    /// default (in 3D with the Schur complement on several ranks).
    pub split_fronts: Option<bool>,
}

#[derive(Clone, Debug)]
pub struct Settings {
    pub mesh: MeshSource,
    pub partition: Partitioner,
    pub young: f64,
    pub nu: f64,
    /// Every material: the global one and those of the body groups.
    pub materials: materials::Materials,
    pub plane_stress: bool,
    pub dirichlet: Vec<DirichletBc>,
    pub traction: Vec<TractionBc>,
    pub pressure: Vec<PressureBc>,
    /// Force per unit volume (`-body_force` plus `-density` x `-gravity`).
    pub body_force: Option<Vec<f64>>,
    pub contact: Option<ContactSettings>,
    pub friction: Friction,
    pub friction_coefficient: f64,
    pub tresca_bound: Option<TrescaBound>,
    pub algorithm: Algorithm,
    pub ubr: UbrSettings,
    /// The linear back-end, decided once here.
    pub linear: LinearBackend,
    /// `-ksp_rtol` given: an iterative back-end keeps it (else UBR adapts
    /// the inner tolerance).
    pub ksp_rtol_given: bool,
    /// SSN-C: r, initial displacement shift, iteration cap.
    pub ssn_r: f64,
    pub ssn_initial_shift: Vec<f64>,
    pub ssn_max_it: usize,
    pub reference: Option<HertzReference>,
    /// Hertz's E* of the contact, from the materials under its surfaces
    /// (set once the mesh is read: [`Settings::e_star`]).
    pub contact_e_star: Option<f64>,
    /// `-reference_center`: the centre of the contact, with or without a reference.
    pub contact_center: Option<Vec<f64>>,
    pub report: Option<String>,
    pub contact_output: Option<String>,
    pub vtk: Option<String>,
    pub plot_contact: Option<String>,
    pub plot_history: Option<String>,
    /// A load history (`-load_steps`, `-load_history`; None: one solve at
    /// the full load) and its outputs.
    pub history: Option<history::LoadHistory>,
    pub history_output: Option<String>,
    pub plot_history_curve: Option<String>,
    /// What the program changed in the user's input (`note: ...`, e.g. a
    /// contact direction normalised) and what in it has no effect
    /// (`warning: ...`: an option the scene ignores, a mistyped name), each
    /// said once on stderr.
    pub notes: Vec<String>,
}

/// Parses `ux=0,uy=-0.2` into (component, value) pairs.
pub fn parse_dirichlet(name: &str, s: &str) -> Result<Vec<(usize, f64)>, Error> {
    let mut out = Vec::new();
    for item in s.split(',') {
        let Some((k, v)) = item.split_once('=') else {
            return bad(format!(
                "option {name}: '{item}' is not of the form ux=VALUE"
            ));
        };
        let comp = match k.trim() {
            "ux" => 0,
            "uy" => 1,
            "uz" => 2,
            other => {
                return bad(format!(
                    "option {name}: unknown component '{other}' (ux, uy, uz)"
                ))
            }
        };
        let v = v.trim();
        if out.iter().any(|&(c, _)| c == comp) {
            return bad(format!("option {name}: {} given twice", k.trim()));
        }
        match v.parse::<f64>() {
            Ok(x) if x.is_finite() => out.push((comp, x)),
            _ => return bad(format!("option {name}: '{v}' is not a finite number")),
        }
    }
    Ok(out)
}

fn mesh_source() -> Result<MeshSource, Error> {
    // -mesh_generate wins, so that `-options_file F -mesh_generate hertz2d`
    // reruns a scene of F on a generated mesh.
    // (-mesh is read either way: overridden, it is not an unused option.)
    let (name, file) = (MESH_GENERATE.get()?, MESH.word()?);
    let element = MESH_ELEMENT.word()?;
    if !MESH_GENERATE.default.values.contains(&name) {
        if element.is_some() {
            return bad("option -mesh_element applies to -mesh_generate only (a mesh file has its own cells)");
        }
        return match file {
            Some(f) => Ok(MeshSource::File(f)),
            None => bad("no mesh: give -mesh FILE or -mesh_generate hertz2d|block3d"),
        };
    }
    let h = positive(MESH_H.name, MESH_H.get()?)?;
    let (simplex, q1) = if name == "hertz2d" {
        ("tri", "quad")
    } else {
        ("tet", "hex")
    };
    let q1 = match element.as_deref() {
        None => false,
        Some(e) if e == simplex => false,
        Some(e) if e == q1 => true,
        Some(e) => {
            return bad(format!(
                "option -mesh_element: '{e}' is not a cell of -mesh_generate {name} ({simplex} or {q1})"
            ))
        }
    };
    Ok(MeshSource::Generate {
        name: name.to_string(),
        h,
        q1,
    })
}

/// Dirichlet conditions, tractions and pressures by group, and the body force.
#[allow(clippy::type_complexity)]
fn loads() -> Result<
    (
        Vec<DirichletBc>,
        Vec<TractionBc>,
        Vec<PressureBc>,
        Option<Vec<f64>>,
    ),
    Error,
> {
    let mut dirichlet = Vec::new();
    for (group, value) in DIRICHLET.members()? {
        let name = format!("-dirichlet_{group}");
        let comps = parse_dirichlet(&name, &value)?;
        dirichlet.push(DirichletBc { group, comps });
    }
    let mut traction = Vec::new();
    for (group, _) in TRACTION.members()? {
        let name = format!("-traction_{group}");
        let t = vector_of(&name)?.unwrap_or_default();
        traction.push(TractionBc { group, traction: t });
    }
    let mut pressure = Vec::new();
    for (group, _) in PRESSURE.members()? {
        let name = format!("-pressure_{group}");
        let Some(p) = real_of(&name)? else {
            return bad(format!("option {name} needs a value"));
        };
        pressure.push(PressureBc { group, pressure: p });
    }
    let mut body = BODY_FORCE.vector()?;
    match (GRAVITY.vector()?, DENSITY.real()?) {
        (Some(g), Some(rho)) => {
            if rho < 0.0 {
                return bad(format!("option -density: {} is negative", shown(rho)));
            }
            let weight: Vec<f64> = g.iter().map(|gi| rho * gi).collect();
            body = Some(match body {
                None => weight,
                Some(b) if b.len() == weight.len() => {
                    b.iter().zip(&weight).map(|(a, w)| a + w).collect()
                }
                Some(b) => {
                    return bad(format!(
                        "options -body_force and -gravity: {} and {} components",
                        b.len(),
                        weight.len()
                    ))
                }
            });
        }
        (Some(_), None) => {
            return bad("option -gravity needs -density RHO (the body force is density x gravity)")
        }
        (None, Some(_)) => {
            return bad(
                "option -density needs -gravity gx,gy[,gz] (the body force is density x gravity)",
            )
        }
        (None, None) => {}
    }
    Ok((dirichlet, traction, pressure, body))
}

/// The contact surface, direction, normal mode and obstacle (None without
/// a surface); a direction within [`numbers::UNIT_TOLERANCE`] of unit length is
/// normalised, with a note.
fn contact(notes: &mut Vec<String>) -> Result<Option<ContactSettings>, Error> {
    let pairs = pairs::contact_pairs()?;
    let nts = CONTACT_PAIR_SCHEME.get()? == "node_to_segment";
    let Some(surfaces) = CONTACT_SURFACE.words()? else {
        return Ok(pairs.map(|p| ContactSettings {
            pair_node_to_segment: nts,
            ..pairs::pairs_only(p)
        }));
    };
    let mut settings = obstacle_contact(surfaces, notes)?;
    settings.pairs = pairs.unwrap_or_default();
    settings.pair_node_to_segment = nts;
    Ok(Some(settings))
}

/// The rigid obstacle(s) of `-contact_surface`.
fn obstacle_contact(
    surfaces: Vec<String>,
    notes: &mut Vec<String>,
) -> Result<ContactSettings, Error> {
    if let Some(names) = OBSTACLES.words()? {
        return obstacles::read(surfaces, names, notes);
    }
    let kind = match OBSTACLE.word_or_required()? {
        Some(k) => k,
        None => {
            return bad(
                "option -obstacle (plane, ball, halfball, cylinder or mesh) is required with -contact_surface",
            )
        }
    };
    let normal = match (CONTACT_NORMAL.get()?, kind) {
        ("fixed", "mesh") => {
            return bad("option -contact_normal fixed: -obstacle mesh measures gaps to each node's closest point (-contact_normal closest or auto)")
        }
        ("fixed", _) | ("auto", "plane") => NormalMode::Fixed,
        _ => NormalMode::Closest,
    };
    let direction = match CONTACT_DIRECTION.vector()? {
        Some(v) => unit(CONTACT_DIRECTION.name, v, notes)?,
        None if normal == NormalMode::Fixed || kind == "halfball" || kind == "plane" => {
            return bad(format!(
                "option -contact_direction is required with -contact_surface (-obstacle {kind}, -contact_normal {})",
                normal.as_str()
            ))
        }
        None => Vec::new(),
    };
    let obstacle = obstacle(kind, notes)?;
    if normal == NormalMode::Closest
        && !direction.is_empty()
        && matches!(kind, "ball" | "cylinder" | "mesh")
    {
        notes.push(
            "note: -contact_direction does not set the gaps with closest normals (-contact_normal); it orients the Hertz comparison and the plots only".into(),
        );
    }
    let obstacles = vec![NamedObstacle {
        name: "obstacle".into(),
        obstacle: obstacle.clone(),
        direction: direction.clone(),
        normal,
    }];
    Ok(ContactSettings {
        surfaces,
        direction,
        normal,
        obstacle,
        obstacles,
        named: false,
        pairs: Vec::new(),
        pair_node_to_segment: false,
    })
}

/// The obstacle of kind `kind` from its options (the dimensions are
/// checked against the mesh's by [`crate::contact::ContactSet::build`]).
fn obstacle(kind: &str, notes: &mut Vec<String>) -> Result<Obstacle, Error> {
    if kind == "mesh" {
        let Some(file) = OBSTACLE_MESH.word()? else {
            return bad("option -obstacle_mesh is required with -obstacle mesh");
        };
        let search = OBSTACLE_SEARCH_DISTANCE
            .real()?
            .map(|d| positive(OBSTACLE_SEARCH_DISTANCE.name, d))
            .transpose()?;
        return Ok(Obstacle::Mesh {
            file,
            group: OBSTACLE_MESH_GROUP.word()?,
            search,
        });
    }
    for (opt, given) in [
        (OBSTACLE_MESH.name, OBSTACLE_MESH.is_set()?),
        (OBSTACLE_MESH_GROUP.name, OBSTACLE_MESH_GROUP.is_set()?),
        (
            OBSTACLE_SEARCH_DISTANCE.name,
            OBSTACLE_SEARCH_DISTANCE.is_set()?,
        ),
    ] {
        if given {
            return bad(format!(
                "option {opt}: only -obstacle mesh reads it (-obstacle {kind})"
            ));
        }
    }
    if kind == "plane" {
        let Some(point) = OBSTACLE_POINT.vector()? else {
            return bad("option -obstacle_point is required with -obstacle plane");
        };
        return Ok(Obstacle::Plane { point });
    }
    let Some(center) = OBSTACLE_CENTER.vector()? else {
        return bad(format!(
            "option -obstacle_center is required with -obstacle {kind}"
        ));
    };
    let Some(radius) = OBSTACLE_RADIUS.real()? else {
        return bad(format!(
            "option -obstacle_radius is required with -obstacle {kind}"
        ));
    };
    let radius = positive(OBSTACLE_RADIUS.name, radius)?;
    let axis = OBSTACLE_AXIS.vector()?;
    if axis.is_some() && kind != "cylinder" {
        return bad(format!(
            "option -obstacle_axis: only a cylinder has an axis (-obstacle {kind})"
        ));
    }
    Ok(match kind {
        "ball" => Obstacle::Ball { center, radius },
        "halfball" => Obstacle::HalfBall { center, radius },
        _ => {
            let axis = match axis {
                None if center.len() == 3 => {
                    return bad("option -obstacle_axis is required with a 3D -obstacle cylinder")
                }
                None => Vec::new(),
                Some(_) if center.len() != 3 => {
                    return bad("option -obstacle_axis: a 2D cylinder is the disc, it has no axis")
                }
                Some(a) if a.len() != 3 => {
                    return bad(format!(
                        "option -obstacle_axis: {} components given, the cylinder is 3D",
                        a.len()
                    ))
                }
                Some(a) => unit(OBSTACLE_AXIS.name, a, notes)?,
            };
            Obstacle::Cylinder {
                center,
                axis,
                radius,
            }
        }
    })
}

impl Opt<Choice> {
    /// The word given, None when not given (a choice without default).
    fn word_or_required(&self) -> Result<Option<&'static str>, Error> {
        let w = self.get()?;
        Ok(self.default.values.contains(&w).then_some(w))
    }
}

fn ubr_settings() -> Result<UbrSettings, Error> {
    let r = match UBR_R.word()?.as_deref() {
        None | Some("auto") => None,
        Some(_) => Some(positive(UBR_R.name, UBR_R.real()?.unwrap_or(0.0))?),
    };
    let anderson = UBR_ANDERSON.get()?;
    if anderson > 100 {
        return bad(format!(
            "option -ubr_anderson: {anderson} is above 100 (a memory of 5-20 suffices)"
        ));
    }
    let rho = UBR_RHO.real()?;
    if let Some(rho) = rho {
        positive(UBR_RHO.name, rho)?;
        if anderson > 0 {
            return bad(format!(
                "option -ubr_rho: the multiplier step applies to the plain iteration (-ubr_anderson 0); the accelerated one takes rho = r (-ubr_anderson is {anderson})"
            ));
        }
    }
    let stop = match UBR_STOP.get()? {
        "paper" => StopRule::Paper,
        _ => StopRule::Accuracy,
    };
    let lambda_rtol = UBR_LAMBDA_RTOL.get()?;
    if !(lambda_rtol > 0.0 && lambda_rtol < 1.0) {
        return bad(format!(
            "option -ubr_lambda_rtol: {lambda_rtol} is not in (0, 1)"
        ));
    }
    let rtol = positive(UBR_RTOL.name, UBR_RTOL.get()?)?;
    // The paper's pair (eps = 1e-5, residual 1e-3) scaled together: a user who
    // tightens -ubr_rtol tightens the constraint residual test too, unless
    // -ubr_residual_tol is given.
    let residual_tol = positive(
        UBR_RESIDUAL_TOL.name,
        UBR_RESIDUAL_TOL
            .real()?
            .unwrap_or(1e-3 * rtol / UBR_RTOL.default),
    )?;
    let fp_rtol = positive(UBR_FP_RTOL.name, UBR_FP_RTOL.get()?)?;
    // Read where the factorization starts (src/linalg/memfit.rs).
    if let Some(v) = UBR_MEMORY_MB.real()? {
        positive(UBR_MEMORY_MB.name, v)?;
    }
    if let Some(v) = UBR_MEMORY_RESERVE.real()? {
        if !(v >= 0.0 && v.is_finite()) {
            return bad(format!(
                "option -ubr_memory_reserve: {v} is not a size in MB (0 or more; 0 turns the watch off)"
            ));
        }
    }
    let inner_rtol_factor = UBR_INNER_RTOL_FACTOR.get()?;
    if !(inner_rtol_factor > 0.0 && inner_rtol_factor < 1.0) {
        return bad(format!(
            "option -ubr_inner_rtol_factor: {inner_rtol_factor} is not in (0, 1)"
        ));
    }
    Ok(UbrSettings {
        r,
        rho,
        stop,
        lambda_rtol,
        rtol,
        residual_tol,
        max_it: UBR_MAX_IT.get()?,
        fp_rtol,
        fp_max_it: UBR_FP_MAX_IT.get()?,
        // Measured on four Coulomb scenes (tests/scenes): M = 3 cut the
        // hemisphere's fixed-point iterations 48 -> 19 (216 -> 138 linear
        // solves) and the disc's 21 -> 14, left the 2D ones (6-7) as they
        // were; M = 5 was worse than 3 on the hemisphere (57).
        fp_anderson: UBR_FP_ANDERSON
            .count()?
            .unwrap_or(if anderson > 0 { 3 } else { 0 }),
        monitor: UBR_MONITOR.get()?,
        anderson,
        mumps_direct: UBR_MUMPS_DIRECT.get()?,
        sbaij: UBR_SBAIJ.get()?,
        condense_max: UBR_CONDENSE_MAX.count()?,
        schur_distributed: UBR_SCHUR_DISTRIBUTED.switch()?,
        distributed_rhs: UBR_MUMPS_RHS.get()? == "distributed",
        split_fronts: UBR_MUMPS_SPLIT.switch()?,
        dual_rtol: positive(
            UBR_DUAL_RTOL.name,
            UBR_DUAL_RTOL.real()?.unwrap_or(10.0 * rtol),
        )?,
        inner_rtol_factor,
    })
}

fn friction() -> Result<(Friction, f64, Option<TrescaBound>), Error> {
    let friction = match FRICTION.get()? {
        "tresca" => Friction::Tresca,
        "coulomb" => Friction::Coulomb,
        _ => Friction::None,
    };
    let coefficient = FRICTION_COEFFICIENT.real()?;
    if let Some(c) = coefficient.filter(|&c| c < 0.0) {
        return bad(format!(
            "option -friction_coefficient: {} is negative",
            shown(c)
        ));
    }
    let tresca_bound = match TRESCA_BOUND.word()?.as_deref() {
        None => None,
        Some("hertz") => Some(TrescaBound::Hertz),
        Some("frictionless") => Some(TrescaBound::Frictionless),
        Some(v) => match v.parse::<f64>() {
            Ok(x) if x.is_finite() && x >= 0.0 => Some(TrescaBound::Value(x)),
            _ => {
                return bad(format!(
                "option -tresca_bound: '{v}' is not a non-negative number, hertz or frictionless"
            ))
            }
        },
    };
    if friction != Friction::None
        && coefficient.is_none()
        && !matches!(tresca_bound, Some(TrescaBound::Value(_)))
    {
        return bad(format!(
            "option -friction_coefficient is required with -friction {}",
            friction.name()
        ));
    }
    Ok((friction, coefficient.unwrap_or(0.0), tresca_bound))
}

/// `-load_steps`/`-load_history` ([`history::read`]), and the outputs and
/// algorithm they need.
fn load_history(
    dirichlet: &[DirichletBc],
    traction: &[TractionBc],
    pressure: &[PressureBc],
    body_force: &Option<Vec<f64>>,
    algorithm: Algorithm,
    out: &outputs::Outputs,
) -> Result<Option<history::LoadHistory>, Error> {
    let history = history::read(&history::Loads {
        dirichlet,
        traction,
        pressure,
        body: body_force.is_some(),
    })?;
    if history.is_none() {
        for (name, given) in [
            (HISTORY_OUTPUT.name, &out.history_output),
            (PLOT_HISTORY_CURVE.name, &out.plot_history_curve),
        ] {
            if given.is_some() {
                return bad(format!(
                    "option {name} needs a load history (-load_steps N or -load_history FILE)"
                ));
            }
        }
    } else if algorithm != Algorithm::Ubr {
        return bad(format!(
            "option -contact_algorithm {algorithm}: load histories (-load_steps, -load_history) run with UBR (-contact_algorithm ubr)"
        ));
    }
    Ok(history)
}

/// What the comparators cannot solve: friction (both), two elastic bodies
/// (SNES VI, a bound on one displacement component per candidate).
fn comparator_limits(
    algorithm: Algorithm,
    friction: Friction,
    contact: Option<&ContactSettings>,
) -> Result<(), Error> {
    if algorithm != Algorithm::Ubr && friction != Friction::None {
        return bad(format!(
            "option -contact_algorithm {algorithm}: this comparator is frictionless (-friction none)"
        ));
    }
    if algorithm == Algorithm::SnesVi && contact.is_some_and(|c| !c.pairs.is_empty()) {
        return bad("option -contact_algorithm snesvi: SNES VI bounds one displacement component at each candidate, and -contact_pair (two elastic bodies) couples the slave to master nodes; solve it with -contact_algorithm ubr or ssn");
    }
    Ok(())
}

impl Settings {
    /// Reads every option. Runs identically on every rank, so its errors are collective.
    pub fn from_options() -> Result<Settings, Error> {
        unused::assignments()?;
        let mesh = mesh_source()?;
        let Some(young) = YOUNG.real()? else {
            return bad("option -E (Young's modulus) is required");
        };
        let young = positive(YOUNG.name, young)?;
        let Some(nu) = NU.real()? else {
            return bad("option -nu (Poisson's ratio) is required");
        };
        let nu = materials::check_nu(NU.name, nu)?;
        let plane_stress = PLANE_STRESS.get()?;
        let (dirichlet, traction, pressure, body_force) = loads()?;
        let materials = materials::read(young, nu)?;
        let mut notes: Vec<String> = files::overridden()
            .iter()
            .map(|w| format!("warning: {w}"))
            .collect();
        let contact = contact(&mut notes)?;
        let (friction, friction_coefficient, tresca_bound) = friction()?;
        let algorithm = Algorithm::parse(ALGORITHM.get()?).expect("a declared choice");
        let ubr = ubr_settings()?;
        let reference = reference::reference()?;
        let contact_center = REFERENCE_CENTER.vector()?;
        let ranks = mpi::topology::SimpleCommunicator::world().size() as usize;
        let out = outputs::Outputs::read(&mesh, files::read(), ranks)?;
        if tresca_bound == Some(TrescaBound::Hertz) && reference.is_none() {
            return bad("option -tresca_bound hertz needs the Hertz reference (-reference hertz -reference_force F -reference_radius R)");
        }
        // The stiffest body's E (the largest) scales SSN-C's default r.
        let e_max = materials.all().fold(young, |e, m| e.max(m.young));
        let ssn_r = positive(SSN_R.name, SSN_R.real()?.unwrap_or(1e3 * e_max))?;
        let ssn_initial_shift = SSN_INITIAL_SHIFT.vector()?.unwrap_or_default();
        let ssn_max_it = SSN_MAX_IT.get()?;
        comparator_limits(algorithm, friction, contact.as_ref())?;
        let history = load_history(
            &dirichlet,
            &traction,
            &pressure,
            &body_force,
            algorithm,
            &out,
        )?;
        let solver_read = solver::check(ranks)?;
        unused::set_solver_options(solver_read.clone());
        let linear = LinearBackend::of(
            petsc::options::get_string("-pc_type")?
                .as_deref()
                .map(str::trim),
            petsc::options::get_string("-ksp_type")?
                .as_deref()
                .map(str::trim),
            petsc::options::get_string("-pc_factor_mat_solver_type")?
                .as_deref()
                .map(str::trim),
            ubr.mumps_direct,
        );
        solver::given_ordering(&linear, algorithm == Algorithm::Ubr)?;
        let ksp_rtol_given = petsc::options::has_name("-ksp_rtol")?;
        let partition = match PARTITION.get()? {
            "metis" => Partitioner::Metis,
            "rcb" => Partitioner::Rcb,
            "ptscotch" => Partitioner::PtScotch,
            // RCB where the factorization's parallel ordering follows it;
            // GAMG converges worse on its slabs (the 1M-node block on 16
            // ranks: 317 preconditioner applications against 179 on
            // METIS' parts, 48 s against 32 s of iterations).
            _ if ranks > 1 && linear.mumps_direct() => Partitioner::Rcb,
            _ => Partitioner::Metis,
        };
        let mut settings = Settings {
            mesh,
            partition,
            young,
            nu,
            materials,
            plane_stress,
            dirichlet,
            traction,
            pressure,
            body_force,
            contact,
            friction,
            friction_coefficient,
            tresca_bound,
            algorithm,
            ubr,
            linear,
            ksp_rtol_given,
            ssn_r,
            ssn_initial_shift,
            ssn_max_it,
            reference,
            contact_e_star: None,
            contact_center,
            report: out.report,
            contact_output: out.contact_output,
            vtk: out.vtk,
            plot_contact: out.plot_contact,
            plot_history: out.plot_history,
            history,
            history_output: out.history_output,
            plot_history_curve: out.plot_history_curve,
            notes,
        };
        // What has no effect here, named now, before any work.
        let mut given = |name: &str| petsc::options::has_name(name).unwrap_or(false);
        for (name, why) in inert::inert(&settings, &solver_read, ranks, &mut given) {
            unused::mark_named(&name);
            settings
                .notes
                .push(format!("warning: option {name} has no effect: {why}"));
        }
        settings.notes.extend(unused::typos()?);
        Ok(settings)
    }
}
