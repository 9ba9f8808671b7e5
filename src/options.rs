//! The program's settings, read from PETSc's options database (command line,
//! `-options_file`, `PETSC_OPTIONS`). Every option is listed in [`HELP`] with
//! its default, which `-help` prints; every parse error names the option.

use crate::error::{bad, Error};
use crate::petsc::options;
use crate::solver::stopping::StopRule;

/// (option, default, description) for `-help`.
pub const HELP: &[(&str, &str, &str)] = &[
    ("-mesh FILE", "none", "Gmsh mesh (.msh 2.2 or 4.1, ASCII or binary); boundary conditions name its physical groups"),
    ("-mesh_generate NAME", "none", "built-in mesh, wins over -mesh: hertz2d (quarter cylinder, section 7.1) or block3d (the block of section 7.2)"),
    ("-mesh_h H", "0.5", "element size of -mesh_generate"),
    ("-mesh_element tri|quad|tet|hex", "tri (hertz2d), tet (block3d)", "cells of -mesh_generate: P1 triangles or Q1 quadrilaterals (hertz2d), P1 tetrahedra or Q1 hexahedra (block3d)"),
    ("-E VALUE", "required", "Young's modulus"),
    ("-nu VALUE", "required", "Poisson's ratio, in (-1, 0.5)"),
    ("-plane_stress", "false", "2D: plane stress instead of plane strain"),
    ("-dirichlet_NAME ux=V,uy=V[,uz=V]", "none", "prescribed displacement components on physical group NAME"),
    ("-traction_NAME tx,ty[,tz]", "none", "surface traction (force per unit measure) on physical group NAME"),
    ("-contact_surface NAME", "none", "physical group of the candidate contact surface Gamma_c"),
    ("-contact_direction nx,ny[,nz]", "required with a contact surface", "unit contact direction n, toward the obstacle"),
    ("-obstacle plane|ball|halfball", "required with a contact surface", "rigid obstacle; ball: candidates are the nodes whose line along n meets the ball; halfball: the half-ball standing on its flat face on a floor (the plane through the centre orthogonal to n), every surface node a candidate (the paper's 3D Gamma_c)"),
    ("-obstacle_point x,y[,z]", "required for plane", "a point of the obstacle plane (orthogonal to n)"),
    ("-obstacle_center x,y[,z]", "required for ball, halfball", "centre of the obstacle ball (circle in 2D)"),
    ("-obstacle_radius R", "required for ball, halfball", "radius of the obstacle ball"),
    ("-friction none|tresca|coulomb", "none", "friction law"),
    ("-friction_coefficient NU_F", "required with friction", "Coulomb friction coefficient nu_f (also scales -tresca_bound hertz|frictionless)"),
    ("-tresca_bound VALUE|hertz|frictionless", "frictionless (tresca), 0 (coulomb)", "Tresca bound s: a constant, nu_f x Hertz pressure, or nu_f x lambda_c of a frictionless solve; with coulomb, the starting s^0"),
    ("-contact_algorithm ubr|ssn|snesvi", "ubr", "UBR (the paper's algorithms), the SSN-C comparator, or PETSc's SNES VI (vinewtonrsls; contact direction along an axis)"),
    ("-ubr_r auto|R", "auto", "augmentation parameter r of the augmented Lagrangian (3.7): auto chooses it from the spectrum of the contact compliance W^1/2 B K^-1 B^T W^1/2 (a few Lanczos steps with the first factorization); a number is used as given"),
    ("-ubr_anderson M", "10", "memory of the safeguarded type-II Anderson acceleration of the UBR map on the contact surface (z = lambda + r B u); 0: the paper's plain iteration"),
    ("-ubr_stop accuracy|paper", "accuracy", "stopping test: accuracy stops when the estimated error of lambda (the map's residual times the estimated error amplification, normal and tangential parts each relative to their max norm) is below -ubr_lambda_rtol / 4 and no contact status changed in 3 iterations; paper is the paper's (4.16)/(5.6) with -ubr_rtol and -ubr_residual_tol"),
    ("-ubr_lambda_rtol TOL", "1e-3", "accuracy stop: the relative error of the contact stresses lambda to guarantee"),
    ("-ubr_rho RHO", "r", "multiplier step rho in (4.4) (plain iteration only, -ubr_anderson 0); convergence needs 0 < rho < r(1+sqrt 5)/2"),
    ("-ubr_rtol EPS", "1e-5", "paper stop: relative tolerance eps_c = eps_f of the stopping tests (4.16), (5.6)"),
    ("-ubr_residual_tol TOL", "1e-3 * ubr_rtol / 1e-5", "paper stop: tolerance on the constraint residual ||B u - phi||_{0,Gamma_c} (section 7)"),
    ("-ubr_dual_rtol TOL", "10 * ubr_rtol", "paper stop: tolerance on the dual residual r||phi^k - phi^(k-1)|| / ||lambda^(k+1)|| (guards the stopping test against the slow regime of large r)"),
    ("-ubr_max_it N", "10000", "maximum UBR iterations"),
    ("-ubr_fp_rtol EPS", "1e-4", "paper stop: fixed-point tolerance eps_fp of (5.7) (CF-FP)"),
    ("-ubr_fp_max_it N", "100", "maximum fixed-point iterations (CF-FP)"),
    ("-ubr_fp_anderson M", "3 (0 with -ubr_anderson 0)", "memory of the Anderson acceleration of CF-FP's outer fixed point s -> nu_f |lambda_c(s)|; 0: the paper's plain fixed point"),
    ("-ubr_monitor", "false", "print one line per UBR iteration"),
    ("-ubr_condense_max P", "2000 in 2D, 4000 in 3D", "MUMPS: condense each UBR solve onto the P or fewer contact unknowns (the Schur complement from the one factorization, on rank 0 whatever the rank count; a dense solve per iteration, the whole displacement only at the end; with -ubr_stop paper not with -ubr_monitor, -plot_history); 0: a full sparse solve per iteration"),
    ("-ubr_mumps_direct 0|1", "1", "the default direct solver (-pc_type cholesky -pc_factor_mat_solver_type mumps) calls MUMPS itself: METIS nested-dissection ordering, the Schur complement on any rank count; 0: through PETSc's MUMPS interface (AMD/PORD, no condensation)"),
    ("-ubr_inner_rtol_factor F", "0.1", "iterative solvers (inexact Uzawa): each inner solve reduces the residual of the previous iterate b - A u^{k-1} by F (a given -ksp_rtol wins)"),
    ("-ssn_r R", "1e3 E", "SSN-C parameter r of (7.1)"),
    ("-ssn_initial_shift ux,uy[,uz]", "0", "SSN-C initial guess u^0, the same at every node (the paper: 0,-0.01 for the floating Hertz body)"),
    ("-ssn_max_it N", "100", "maximum SSN-C iterations"),
    ("-reference hertz", "none", "compare the contact pressure with the analytic Hertz pressure"),
    ("-reference_force F", "required with -reference", "Hertz load: per unit thickness of the whole cylinder (2D), on the whole sphere (3D)"),
    ("-reference_radius R", "required with -reference", "radius of the Hertz cylinder or sphere"),
    ("-reference_center x,y[,z]", "candidate with the smallest gap", "centre of the Hertz contact"),
    ("-report FILE.json", "none", "write a JSON report"),
    ("-contact_output FILE.csv", "none", "write the contact nodes (one row per candidate)"),
    ("-vtk PATH.pvtu", "none", "ParaView output: PATH.pvtu and one PATH_RANK.vtu piece per rank (displacement, stress, von Mises, rank, contact fields)"),
    ("-plot_contact FILE.png", "none", "plot the contact pressure (and tangential traction, friction bound, Hertz) along the surface"),
    ("-plot_history FILE.png", "none", "plot the UBR change (4.16)/(5.6) and constraint residual per iteration"),
    ("-help", "", "this list (PETSc's solver options are listed when a scene is given too)"),
];

pub fn print_help() {
    println!(
        "ubr-petsc: Uzawa block relaxation for unilateral contact in linear elasticity (Koko 2010)"
    );
    println!("usage: mpirun -n N ubr-petsc -options_file options/hertz [options]\n");
    println!("Options (default in brackets):");
    for (name, default, text) in HELP {
        if default.is_empty() {
            println!("  {name:<40} {text}");
        } else {
            println!("  {name:<40} {text} [{default}]");
        }
    }
    println!("\nDefaults: the UBR map Anderson-accelerated, r chosen from the spectrum of the contact compliance,");
    println!(
        "and a stop that bounds the error of the contact stresses by -ubr_lambda_rtol (1e-3)."
    );
    println!("The paper's algorithm as it runs it: -ubr_anderson 0 -ubr_stop paper -ubr_r R (options/*-paper).");
    println!("\nLinear solver: the unprefixed PETSc options (-ksp_type, -pc_type, -pc_factor_mat_solver_type, ...);");
    println!("default -ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps, factorized once.");
    println!("Profiling: -log_view (stages Mesh, Partition, Assembly, Factorization, RChoice, Iterations, Output).");
    println!("Exit status: 0 converged, 2 bad input or an ill-posed scene (a rigid motion nothing holds), 3 not converged.");
}

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

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Friction {
    None,
    Tresca,
    Coulomb,
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

#[derive(Clone, Debug, PartialEq)]
pub enum Obstacle {
    Plane {
        point: Vec<f64>,
    },
    Ball {
        center: Vec<f64>,
        radius: f64,
    },
    /// The paper's 3D obstacle (section 7.2): the half of the ball facing the
    /// body, standing on its flat face on a rigid floor, the plane through the
    /// centre orthogonal to n. Every node of the contact surface is a
    /// candidate (the paper's Gamma_c is the whole surface).
    HalfBall {
        center: Vec<f64>,
        radius: f64,
    },
}

#[derive(Clone, Debug)]
pub struct ContactSettings {
    pub surface: String,
    pub direction: Vec<f64>,
    pub obstacle: Obstacle,
}

#[derive(Clone, Debug)]
pub struct HertzReference {
    pub force: f64,
    pub radius: f64,
    pub center: Option<Vec<f64>>,
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
    /// Condense the UBR solve onto the contact unknowns when there are at
    /// most this many (None: the default of the dimension, see `-help`).
    pub condense_max: Option<usize>,
}

#[derive(Clone, Debug)]
pub struct Settings {
    pub mesh: MeshSource,
    pub young: f64,
    pub nu: f64,
    pub plane_stress: bool,
    pub dirichlet: Vec<DirichletBc>,
    pub traction: Vec<TractionBc>,
    pub contact: Option<ContactSettings>,
    pub friction: Friction,
    pub friction_coefficient: f64,
    pub tresca_bound: Option<TrescaBound>,
    pub algorithm: String,
    pub ubr: UbrSettings,
    /// SSN-C: r, initial displacement shift, iteration cap.
    pub ssn_r: f64,
    pub ssn_initial_shift: Vec<f64>,
    pub ssn_max_it: usize,
    pub reference: Option<HertzReference>,
    pub report: Option<String>,
    pub contact_output: Option<String>,
    pub vtk: Option<String>,
    pub plot_contact: Option<String>,
    pub plot_history: Option<String>,
}

fn get(name: &str) -> Result<Option<String>, Error> {
    options::get_string(name)
}

fn parse_f64(name: &str, s: &str) -> Result<f64, Error> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => bad(format!("option {name}: '{s}' is not a finite number")),
    }
}

fn get_f64(name: &str) -> Result<Option<f64>, Error> {
    match get(name)? {
        None => Ok(None),
        Some(s) if s.is_empty() => bad(format!("option {name} needs a value")),
        Some(s) => parse_f64(name, &s).map(Some),
    }
}

fn get_usize(name: &str, default: usize) -> Result<usize, Error> {
    match get(name)? {
        None => Ok(default),
        Some(s) => match s.trim().parse::<usize>() {
            Ok(v) => Ok(v),
            _ => bad(format!(
                "option {name}: '{s}' is not a non-negative integer"
            )),
        },
    }
}

fn get_vec(name: &str) -> Result<Option<Vec<f64>>, Error> {
    match get(name)? {
        None => Ok(None),
        Some(s) if s.trim().is_empty() => bad(format!("option {name} needs a value")),
        Some(s) => s
            .split(',')
            .map(|t| parse_f64(name, t))
            .collect::<Result<Vec<_>, _>>()
            .map(Some),
    }
}

fn get_word(name: &str) -> Result<Option<String>, Error> {
    match get(name)? {
        None => Ok(None),
        Some(s) if s.trim().is_empty() => bad(format!("option {name} needs a value")),
        Some(s) => Ok(Some(s.trim().to_string())),
    }
}

fn get_bool(name: &str) -> Result<bool, Error> {
    match get(name)? {
        None => Ok(false),
        Some(s) => match s.trim().to_ascii_lowercase().as_str() {
            "" | "1" | "true" | "yes" | "on" => Ok(true),
            "0" | "false" | "no" | "off" => Ok(false),
            _ => bad(format!("option {name}: '{s}' is not a boolean")),
        },
    }
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
        out.push((comp, parse_f64(name, v)?));
    }
    Ok(out)
}

impl Settings {
    /// Reads every option. Runs identically on every rank, so its errors are collective.
    pub fn from_options() -> Result<Settings, Error> {
        let mesh = match (get("-mesh")?, get("-mesh_generate")?) {
            // -mesh_generate wins, so that `-options_file F -mesh_generate hertz2d`
            // reruns a scene of F on a generated mesh.
            (Some(f), None) if f.trim().is_empty() => return bad("option -mesh needs a file name"),
            (Some(_), None) if get("-mesh_element")?.is_some() => {
                return bad("option -mesh_element applies to -mesh_generate only (a mesh file has its own cells)")
            }
            (Some(f), None) => MeshSource::File(f.trim().to_string()),
            (_, Some(g)) => {
                let name = g.trim().to_string();
                if name != "hertz2d" && name != "block3d" {
                    return bad(format!(
                        "option -mesh_generate: unknown mesh '{name}' (hertz2d, block3d)"
                    ));
                }
                let h = get_f64("-mesh_h")?.unwrap_or(0.5);
                if h <= 0.0 {
                    return bad(format!("option -mesh_h: {h} is not positive"));
                }
                let (simplex, q1) = if name == "hertz2d" {
                    ("tri", "quad")
                } else {
                    ("tet", "hex")
                };
                let q1 = match get("-mesh_element")?.as_deref().map(str::trim) {
                    None => false,
                    Some(e) if e == simplex => false,
                    Some(e) if e == q1 => true,
                    Some(e) => {
                        return bad(format!(
                            "option -mesh_element: '{e}' is not a cell of -mesh_generate {name} ({simplex} or {q1})"
                        ))
                    }
                };
                MeshSource::Generate { name, h, q1 }
            }
            (None, None) => {
                return bad("no mesh: give -mesh FILE or -mesh_generate hertz2d|block3d")
            }
        };
        let Some(young) = get_f64("-E")? else {
            return bad("option -E (Young's modulus) is required");
        };
        if young <= 0.0 {
            return bad(format!("option -E: {young} is not positive"));
        }
        let Some(nu) = get_f64("-nu")? else {
            return bad("option -nu (Poisson's ratio) is required");
        };
        if !(nu > -1.0 && nu < 0.5) {
            return bad(format!("option -nu: {nu} is outside (-1, 0.5)"));
        }
        let plane_stress = get_bool("-plane_stress")?;

        let mut dirichlet = Vec::new();
        let mut traction = Vec::new();
        for opt in options::all_names()? {
            if let Some(group) = opt.strip_prefix("-dirichlet_") {
                let s = get(&opt)?.unwrap_or_default();
                dirichlet.push(DirichletBc {
                    group: group.to_string(),
                    comps: parse_dirichlet(&opt, &s)?,
                });
            } else if let Some(group) = opt.strip_prefix("-traction_") {
                let t = get_vec(&opt)?.unwrap_or_default();
                traction.push(TractionBc {
                    group: group.to_string(),
                    traction: t,
                });
            }
        }
        dirichlet.sort_by(|a, b| a.group.cmp(&b.group));
        dirichlet.dedup_by(|a, b| a.group == b.group);
        traction.sort_by(|a, b| a.group.cmp(&b.group));
        traction.dedup_by(|a, b| a.group == b.group);

        let contact = match get_word("-contact_surface")? {
            None => None,
            Some(surface) => {
                let Some(direction) = get_vec("-contact_direction")? else {
                    return bad("option -contact_direction is required with -contact_surface");
                };
                let norm = direction.iter().map(|v| v * v).sum::<f64>().sqrt();
                if (norm - 1.0).abs() > 1e-6 {
                    return bad(format!(
                        "option -contact_direction: ({}) is not a unit vector (norm {norm})",
                        direction
                            .iter()
                            .map(|v| v.to_string())
                            .collect::<Vec<_>>()
                            .join(",")
                    ));
                }
                let obstacle = match get_word("-obstacle")?.as_deref() {
                    None => {
                        return bad(
                            "option -obstacle (plane, ball or halfball) is required with -contact_surface",
                        )
                    }
                    Some("plane") => {
                        let Some(point) = get_vec("-obstacle_point")? else {
                            return bad("option -obstacle_point is required with -obstacle plane");
                        };
                        Obstacle::Plane { point }
                    }
                    Some(kind @ ("ball" | "halfball")) => {
                        let Some(center) = get_vec("-obstacle_center")? else {
                            return bad(format!(
                                "option -obstacle_center is required with -obstacle {kind}"
                            ));
                        };
                        let Some(radius) = get_f64("-obstacle_radius")? else {
                            return bad(format!(
                                "option -obstacle_radius is required with -obstacle {kind}"
                            ));
                        };
                        if radius <= 0.0 {
                            return bad(format!(
                                "option -obstacle_radius: {radius} is not positive"
                            ));
                        }
                        if kind == "ball" {
                            Obstacle::Ball { center, radius }
                        } else {
                            Obstacle::HalfBall { center, radius }
                        }
                    }
                    Some(other) => {
                        return bad(format!(
                            "option -obstacle: unknown obstacle '{other}' (plane, ball, halfball)"
                        ))
                    }
                };
                Some(ContactSettings {
                    surface,
                    direction,
                    obstacle,
                })
            }
        };

        let friction = match get_word("-friction")?.as_deref() {
            None | Some("none") => Friction::None,
            Some("tresca") => Friction::Tresca,
            Some("coulomb") => Friction::Coulomb,
            Some(o) => {
                return bad(format!(
                    "option -friction: unknown law '{o}' (none, tresca, coulomb)"
                ))
            }
        };
        let algorithm = get_word("-contact_algorithm")?.unwrap_or_else(|| "ubr".into());
        if !["ubr", "ssn", "snesvi"].contains(&algorithm.as_str()) {
            return bad(format!(
                "option -contact_algorithm: unknown algorithm '{algorithm}' (ubr, ssn, snesvi)"
            ));
        }

        let r = match get_word("-ubr_r")?.as_deref() {
            None | Some("auto") => None,
            Some(v) => {
                let r = parse_f64("-ubr_r", v)?;
                if r <= 0.0 {
                    return bad(format!("option -ubr_r: {r} is not positive"));
                }
                Some(r)
            }
        };
        let anderson = {
            let m = get_usize("-ubr_anderson", 10)?;
            if m > 100 {
                return bad(format!(
                    "option -ubr_anderson: {m} is above 100 (a memory of 5-20 suffices)"
                ));
            }
            m
        };
        let rho = get_f64("-ubr_rho")?;
        if let Some(rho) = rho {
            if rho <= 0.0 {
                return bad(format!("option -ubr_rho: {rho} is not positive"));
            }
            if anderson > 0 {
                return bad(format!(
                    "option -ubr_rho: the multiplier step applies to the plain iteration (-ubr_anderson 0); the accelerated one takes rho = r (-ubr_anderson is {anderson})"
                ));
            }
        }
        let stop = match get_word("-ubr_stop")?.as_deref() {
            None | Some("accuracy") => StopRule::Accuracy,
            Some("paper") => StopRule::Paper,
            Some(o) => {
                return bad(format!(
                    "option -ubr_stop: unknown test '{o}' (accuracy, paper)"
                ))
            }
        };
        let lambda_rtol = get_f64("-ubr_lambda_rtol")?.unwrap_or(1e-3);
        if !(lambda_rtol > 0.0 && lambda_rtol < 1.0) {
            return bad(format!(
                "option -ubr_lambda_rtol: {lambda_rtol} is not in (0, 1)"
            ));
        }
        let rtol = get_f64("-ubr_rtol")?.unwrap_or(1e-5);
        if rtol <= 0.0 {
            return bad(format!("option -ubr_rtol: {rtol} is not positive"));
        }
        // The paper's pair (eps = 1e-5, residual 1e-3) scaled together: a user who
        // tightens -ubr_rtol tightens the constraint residual test too, unless
        // -ubr_residual_tol is given.
        let residual_tol = get_f64("-ubr_residual_tol")?.unwrap_or(1e-3 * rtol / 1e-5);
        if residual_tol <= 0.0 {
            return bad(format!(
                "option -ubr_residual_tol: {residual_tol} is not positive"
            ));
        }
        let fp_rtol = get_f64("-ubr_fp_rtol")?.unwrap_or(1e-4);
        if fp_rtol <= 0.0 {
            return bad(format!("option -ubr_fp_rtol: {fp_rtol} is not positive"));
        }
        let ubr = UbrSettings {
            r,
            rho,
            stop,
            lambda_rtol,
            rtol,
            residual_tol,
            max_it: get_usize("-ubr_max_it", 10000)?,
            fp_rtol,
            fp_max_it: get_usize("-ubr_fp_max_it", 100)?,
            // Measured on four Coulomb scenes (tests/scenes): M = 3 cut the
            // hemisphere's fixed-point iterations 48 -> 19 (216 -> 138 linear
            // solves) and the disc's 21 -> 14, left the 2D ones (6-7) as they
            // were; M = 5 was worse than 3 on the hemisphere (57).
            fp_anderson: get_usize("-ubr_fp_anderson", if anderson > 0 { 3 } else { 0 })?,
            monitor: get_bool("-ubr_monitor")?,
            anderson,
            mumps_direct: match get("-ubr_mumps_direct")? {
                None => true,
                Some(_) => get_bool("-ubr_mumps_direct")?,
            },
            condense_max: match get("-ubr_condense_max")? {
                None => None,
                Some(_) => Some(get_usize("-ubr_condense_max", 0)?),
            },
            dual_rtol: {
                let v = get_f64("-ubr_dual_rtol")?.unwrap_or(10.0 * rtol);
                if v <= 0.0 {
                    return bad(format!("option -ubr_dual_rtol: {v} is not positive"));
                }
                v
            },
            inner_rtol_factor: {
                let f = get_f64("-ubr_inner_rtol_factor")?.unwrap_or(0.1);
                if !(f > 0.0 && f < 1.0) {
                    return bad(format!(
                        "option -ubr_inner_rtol_factor: {f} is not in (0, 1)"
                    ));
                }
                f
            },
        };

        let reference = match get_word("-reference")?.as_deref() {
            None => None,
            Some("hertz") => {
                let Some(force) = get_f64("-reference_force")? else {
                    return bad("option -reference_force is required with -reference hertz");
                };
                let Some(radius) = get_f64("-reference_radius")? else {
                    return bad("option -reference_radius is required with -reference hertz");
                };
                if force <= 0.0 || radius <= 0.0 {
                    return bad("options -reference_force and -reference_radius must be positive");
                }
                Some(HertzReference {
                    force,
                    radius,
                    center: get_vec("-reference_center")?,
                })
            }
            Some(o) => {
                return bad(format!(
                    "option -reference: unknown reference '{o}' (hertz)"
                ))
            }
        };
        let report = get_word("-report")?;
        let contact_output = get_word("-contact_output")?;
        let vtk = get_word("-vtk")?;
        let plot_contact = get_word("-plot_contact")?;
        let plot_history = get_word("-plot_history")?;
        // Output paths are checked before any work: a run that cannot write
        // its results fails at once, not after the solve.
        for (opt, path) in [
            ("-report", &report),
            ("-contact_output", &contact_output),
            ("-vtk", &vtk),
            ("-plot_contact", &plot_contact),
            ("-plot_history", &plot_history),
        ] {
            if let Some(path) = path {
                let p = std::path::Path::new(path);
                let dir = p
                    .parent()
                    .filter(|d| !d.as_os_str().is_empty())
                    .unwrap_or(std::path::Path::new("."));
                if !dir.is_dir() {
                    return bad(format!(
                        "option {opt}: directory '{}' of '{path}' does not exist",
                        dir.display()
                    ));
                }
                if p.is_dir() {
                    return bad(format!("option {opt}: '{path}' is a directory"));
                }
            }
        }
        let friction_coefficient = get_f64("-friction_coefficient")?.unwrap_or(0.0);
        if friction_coefficient < 0.0 {
            return bad(format!(
                "option -friction_coefficient: {friction_coefficient} is negative"
            ));
        }
        let tresca_bound = match get_word("-tresca_bound")?.as_deref() {
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
        if tresca_bound == Some(TrescaBound::Hertz) && reference.is_none() {
            return bad("option -tresca_bound hertz needs the Hertz reference (-reference hertz -reference_force F -reference_radius R)");
        }
        if friction != Friction::None
            && get_f64("-friction_coefficient")?.is_none()
            && !matches!(tresca_bound, Some(TrescaBound::Value(_)))
        {
            return bad(format!(
                "option -friction_coefficient is required with -friction {}",
                if friction == Friction::Tresca {
                    "tresca"
                } else {
                    "coulomb"
                }
            ));
        }
        let ssn_r = get_f64("-ssn_r")?.unwrap_or(1e3 * young);
        if ssn_r <= 0.0 {
            return bad(format!("option -ssn_r: {ssn_r} is not positive"));
        }
        let ssn_initial_shift = get_vec("-ssn_initial_shift")?.unwrap_or_default();
        let ssn_max_it = get_usize("-ssn_max_it", 100)?;
        if algorithm != "ubr" && friction != Friction::None {
            return bad(format!(
                "option -contact_algorithm {algorithm}: this comparator is frictionless (-friction none)"
            ));
        }

        Ok(Settings {
            mesh,
            young,
            nu,
            plane_stress,
            dirichlet,
            traction,
            contact,
            friction,
            friction_coefficient,
            tresca_bound,
            algorithm,
            ubr,
            ssn_r,
            ssn_initial_shift,
            ssn_max_it,
            reference,
            report,
            contact_output,
            vtk,
            plot_contact,
            plot_history,
        })
    }
}
