//! Every option of the program, declared once: its name, the argument it
//! takes, its typed default and its help text (PETSc's
//! `PetscOptionsReal("-alpha", "help", "", alpha, &alpha, NULL)` in one
//! place). `-help` prints [`ALL`]; [`Settings`](super::Settings) reads the
//! values through the typed getters, whose errors name the option; the
//! unknown-option check ([`super::unused`]) suggests names from [`ALL`].

use crate::error::{bad, Error};
use crate::petsc::options;

/// One declared option; `T` is the type of its default.
pub struct Opt<T: 'static> {
    pub name: &'static str,
    /// What follows the name in `-help` ("EPS", "x,y[,z]", ... or "").
    pub arg: &'static str,
    pub default: T,
    pub help: &'static str,
}

/// One word out of `values`, `default` when not given.
pub struct Choice {
    pub default: &'static str,
    pub values: &'static [&'static str],
}

/// No default value: the option is optional, required in some settings, or
/// its default is derived from other options (the text says which).
pub struct Given(pub &'static str);

/// A family of options `-PREFIX_NAME` (NAME: a physical group of the mesh).
pub struct Family;

/// What `-help` and the unknown-option check need of any declared option.
pub trait Declared: Sync {
    fn name(&self) -> &'static str;
    fn arg(&self) -> &'static str;
    fn help(&self) -> &'static str;
    /// The default as `-help` shows it ("" for none worth showing).
    fn default_text(&self) -> String;
    /// A family `-dirichlet_NAME`: its prefix `-dirichlet_`.
    fn prefix(&self) -> Option<&'static str> {
        None
    }
}

macro_rules! declared {
    ($t:ty, |$s:ident| $text:expr $(, prefix |$p:ident| $prefix:expr)?) => {
        impl Declared for Opt<$t> {
            fn name(&self) -> &'static str {
                self.name
            }
            fn arg(&self) -> &'static str {
                self.arg
            }
            fn help(&self) -> &'static str {
                self.help
            }
            fn default_text(&self) -> String {
                let $s = self;
                $text
            }
            $(fn prefix(&self) -> Option<&'static str> {
                let $p = self;
                $prefix
            })?
        }
    };
}
declared!(f64, |s| format_real(s.default));
declared!(usize, |s| s.default.to_string());
declared!(bool, |s| s.default.to_string());
declared!(Choice, |s| s.default.default.into());
declared!(Given, |s| s.default.0.into());
declared!(
    Family,
    |_s| "none".into(),
    prefix | s | s.name.strip_suffix("NAME")
);

/// 1e-5, not 0.00001: as a user would type it.
fn format_real(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e5) {
        let s = format!("{v:e}");
        s.replace("e-0", "e-").replace("e0", "e")
    } else {
        v.to_string()
    }
}

fn raw(name: &str) -> Result<Option<String>, Error> {
    options::get_string(name)
}

fn parse_real(name: &str, s: &str) -> Result<f64, Error> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => bad(format!("option {name}: '{s}' is not a finite number")),
    }
}

/// The value of `-name`, None when not given, an error when given empty.
pub fn nonempty(name: &str) -> Result<Option<String>, Error> {
    match raw(name)? {
        Some(s) if s.trim().is_empty() => bad(format!("option {name} needs a value")),
        other => Ok(other.map(|s| s.trim().to_string())),
    }
}

pub fn real_of(name: &str) -> Result<Option<f64>, Error> {
    nonempty(name)?.map(|s| parse_real(name, &s)).transpose()
}

pub fn vector_of(name: &str) -> Result<Option<Vec<f64>>, Error> {
    nonempty(name)?
        .map(|s| s.split(',').map(|t| parse_real(name, t)).collect())
        .transpose()
}

fn count_of(name: &str) -> Result<Option<usize>, Error> {
    match raw(name)? {
        None => Ok(None),
        Some(s) => match s.trim().parse::<usize>() {
            Ok(v) => Ok(Some(v)),
            _ => bad(format!(
                "option {name}: '{s}' is not a non-negative integer"
            )),
        },
    }
}

impl Opt<f64> {
    pub fn get(&self) -> Result<f64, Error> {
        Ok(real_of(self.name)?.unwrap_or(self.default))
    }
}

impl Opt<usize> {
    pub fn get(&self) -> Result<usize, Error> {
        Ok(count_of(self.name)?.unwrap_or(self.default))
    }
}

/// The switch `-name` given as `s` (empty: on).
fn parse_switch(name: &str, s: &str) -> Result<bool, Error> {
    match s.trim().to_ascii_lowercase().as_str() {
        "" | "1" | "true" | "yes" | "on" => Ok(true),
        "0" | "false" | "no" | "off" => Ok(false),
        _ => bad(format!("option {name}: '{s}' is not a boolean")),
    }
}

impl Opt<bool> {
    /// A switch: given without a value, on.
    pub fn get(&self) -> Result<bool, Error> {
        match raw(self.name)? {
            None => Ok(self.default),
            Some(s) => parse_switch(self.name, &s),
        }
    }
}

impl Opt<Choice> {
    /// The word given (one of the values), or the default.
    pub fn get(&self) -> Result<&'static str, Error> {
        let Some(word) = nonempty(self.name)? else {
            return Ok(self.default.default);
        };
        match self.default.values.iter().find(|v| **v == word) {
            Some(v) => Ok(v),
            None => bad(format!(
                "option {}: unknown value '{word}' ({})",
                self.name,
                self.default.values.join(", ")
            )),
        }
    }
}

impl Opt<Given> {
    pub fn real(&self) -> Result<Option<f64>, Error> {
        real_of(self.name)
    }
    pub fn vector(&self) -> Result<Option<Vec<f64>>, Error> {
        vector_of(self.name)
    }
    /// A switch whose default depends on the run (None: not given).
    pub fn switch(&self) -> Result<Option<bool>, Error> {
        raw(self.name)?
            .map(|s| parse_switch(self.name, &s))
            .transpose()
    }

    pub fn count(&self) -> Result<Option<usize>, Error> {
        count_of(self.name)
    }
    pub fn word(&self) -> Result<Option<String>, Error> {
        nonempty(self.name)
    }
    /// A comma-separated list of words.
    pub fn words(&self) -> Result<Option<Vec<String>>, Error> {
        let Some(s) = nonempty(self.name)? else {
            return Ok(None);
        };
        let words: Vec<String> = s.split(',').map(|w| w.trim().to_string()).collect();
        if words.iter().any(|w| w.is_empty()) {
            return bad(format!("option {}: empty name in '{s}'", self.name));
        }
        Ok(Some(words))
    }
    pub fn is_set(&self) -> Result<bool, Error> {
        options::has_name(self.name)
    }
}

impl Opt<Family> {
    /// `(NAME, value)` of every `-PREFIX_NAME` given, sorted by NAME.
    pub fn members(&self) -> Result<Vec<(String, String)>, Error> {
        let prefix = self.prefix().expect("a family's name ends in NAME");
        let mut out: Vec<(String, String)> = Vec::new();
        for opt in options::all_names()? {
            if let Some(group) = opt.strip_prefix(prefix) {
                if !group.is_empty() && out.iter().all(|(g, _)| g != group) {
                    out.push((group.to_string(), raw(&opt)?.unwrap_or_default()));
                }
            }
        }
        out.sort();
        Ok(out)
    }
}

macro_rules! opt {
    ($id:ident: $t:ty = $name:literal $arg:literal, $default:expr, $help:literal) => {
        pub const $id: Opt<$t> = Opt {
            name: $name,
            arg: $arg,
            default: $default,
            help: $help,
        };
    };
}

// Mesh
opt!(MESH: Given = "-mesh" "FILE", Given("none"), "Gmsh mesh (.msh 2.2 or 4.1, ASCII or binary); boundary conditions name its physical groups");
opt!(MESH_GENERATE: Choice = "-mesh_generate" "NAME", Choice { default: "none", values: &["hertz2d", "block3d"] }, "built-in mesh, wins over -mesh: hertz2d (quarter cylinder, section 7.1) or block3d (the block of section 7.2)");
opt!(MESH_H: f64 = "-mesh_h" "H", 0.5, "element size of -mesh_generate");
opt!(MESH_ELEMENT: Given = "-mesh_element" "tri|quad|tet|hex", Given("tri (hertz2d), tet (block3d)"), "cells of -mesh_generate: P1 triangles or Q1 quadrilaterals (hertz2d), P1 tetrahedra or Q1 hexahedra (block3d)");
opt!(PARTITION: Choice = "-partition" "auto|metis|rcb|ptscotch", Choice { default: "auto", values: &["auto", "metis", "rcb", "ptscotch"] }, "how the mesh is split over the ranks: metis (METIS k-way on the nodal graph, on rank 0: the smallest interfaces), ptscotch (PT-Scotch on the nodal graph, every rank partitioning its share), rcb (recursive coordinate bisection: planes across the longest extent, n/P nodes per rank, parts along the tree of the parallel ordering; no graph), auto: rcb on several ranks with the direct solver MUMPS called directly (its parallel ordering follows the bisection tree), metis otherwise (GAMG converges slower on RCB's slabs)");
// Material
opt!(YOUNG: Given = "-E" "VALUE", Given("required"), "Young's modulus");
opt!(NU: Given = "-nu" "VALUE", Given("required"), "Poisson's ratio, in (-1, 0.5)");
opt!(YOUNG_BODY: Family = "-E_NAME" "VALUE", Family, "Young's modulus of the cells of body group NAME (a physical group of the mesh's dimension: Physical Surface in 2D, Physical Volume in 3D), instead of -E");
opt!(NU_BODY: Family = "-nu_NAME" "VALUE", Family, "Poisson's ratio of the cells of body group NAME, in (-1, 0.5), instead of -nu");
opt!(DENSITY_BODY: Family = "-density_NAME" "RHO", Family, "mass density of the cells of body group NAME, instead of -density (with -gravity)");
opt!(PLANE_STRESS: bool = "-plane_stress" "", false, "2D: plane stress instead of plane strain");
// Loads and supports
opt!(DIRICHLET: Family = "-dirichlet_NAME" "ux=V,uy=V[,uz=V]", Family, "prescribed displacement components on physical group NAME (its reaction force is in the summary and the report)");
opt!(TRACTION: Family = "-traction_NAME" "tx,ty[,tz]", Family, "surface traction (force per unit measure) on physical group NAME");
opt!(PRESSURE: Family = "-pressure_NAME" "P", Family, "pressure on physical group NAME along its facet normals, positive pushing in");
opt!(BODY_FORCE: Given = "-body_force" "fx,fy[,fz]", Given("none"), "body force per unit volume (added to -gravity x -density)");
opt!(GRAVITY: Given = "-gravity" "gx,gy[,gz]", Given("none"), "gravitational acceleration; with -density gives the body force density x gravity");
opt!(DENSITY: Given = "-density" "RHO", Given("required with -gravity"), "mass density (force per unit volume: density x gravity)");
// Contact
opt!(CONTACT_SURFACE: Given = "-contact_surface" "NAME[,NAME2...]", Given("required unless -contact_pair"), "physical group(s) of the candidate contact surface Gamma_c (one obstacle)");
opt!(CONTACT_PAIR: Given = "-contact_pair" "SLAVE,MASTER[,SLAVE2,MASTER2...]", Given("none"), "two elastic bodies in contact, or two surfaces of one body facing each other (a crack, a slot: contact with itself): the surface groups (lines in 2D, triangles and quadrilaterals in 3D) of each pair, slave side first; mortar coupling with dual multipliers, the slave's nodes the candidates (every option of the contact algorithm applies); with or without -contact_surface and a rigid obstacle on other surfaces");
opt!(CONTACT_PAIR_SCHEME: Choice = "-contact_pair_scheme" "mortar|node_to_segment", Choice { default: "mortar", values: &["mortar", "node_to_segment"] }, "-contact_pair's coupling: mortar (dual multipliers, segment-based; passes the contact patch test on non-matching meshes) or node_to_segment (2D: each slave node against the master point its normal meets, for comparison: it does not pass it)");
opt!(CONTACT_DIRECTION: Given = "-contact_direction" "nx,ny[,nz]", Given("required with fixed normals, a plane or a halfball"), "unit contact direction n, toward the obstacle (a vector within 1e-3 of unit length is normalised)");
opt!(CONTACT_NORMAL: Choice = "-contact_normal" "auto|fixed|closest", Choice { default: "auto", values: &["auto", "fixed", "closest"] }, "each candidate's gap and normal: fixed, along -contact_direction (the paper's); closest, from its closest point on the obstacle (every surface node a candidate); auto: fixed for a plane, closest for a ball, halfball or cylinder");
opt!(OBSTACLE: Choice = "-obstacle" "plane|ball|halfball|cylinder|mesh", Choice { default: "required with a contact surface", values: &["plane", "ball", "halfball", "cylinder", "mesh"] }, "rigid obstacle; ball: with fixed normals the candidates are the nodes whose line along n meets the ball; halfball: the half-ball standing on its flat face on a floor (the plane through the centre orthogonal to n), every surface node a candidate (the paper's 3D Gamma_c); cylinder: around -obstacle_axis through -obstacle_center (2D: the disc, as ball); mesh: the surface of -obstacle_mesh (closest-point normals); a ball or cylinder with most of the body inside it is read as the cavity it bounds (a socket, a bore), with a warning");
opt!(OBSTACLES: Given = "-obstacles" "NAME1,NAME2,...", Given("none: one obstacle, -obstacle"), "several rigid obstacles, each NAME described by -obstacle_NAME KIND (plane|ball|halfball|cylinder|mesh) and -obstacle_NAME_point, _center, _radius, _axis, _direction (its fixed contact direction, toward it; required for a plane; default -contact_direction), _mesh, _mesh_group; each candidate is paired with the obstacle of smallest gap; the summary and the report give the force on each");
opt!(OBSTACLE_MESH: Given = "-obstacle_mesh" "FILE", Given("required for mesh"), "the rigid surface of -obstacle mesh: Gmsh .msh 2.2 or 4.1 ASCII with line elements (2D) or triangles and quadrilaterals (3D), or STL (3D, ASCII or binary); closed and oriented with its normals outward (counter-clockwise in 2D; a surface oriented inward is a cavity, a seat; a connected part whose orientation puts most of the body's nodes nearest to it inside the obstacle is read reversed, with a warning); gaps and normals from each node's closest point (pseudo-normals at edges and vertices)");
opt!(OBSTACLE_MESH_GROUP: Given = "-obstacle_mesh_group" "NAME", Given("every element of the surface's dimension"), "the physical group (name or number) of -obstacle_mesh that is the obstacle");
opt!(OBSTACLE_SEARCH_DISTANCE: Given = "-obstacle_search_distance" "D", Given("none: every node of the contact surface"), "-obstacle mesh: a node farther than D from the surface is no candidate (it stays open)");
opt!(OBSTACLE_POINT: Given = "-obstacle_point" "x,y[,z]", Given("required for plane"), "a point of the obstacle plane (orthogonal to n)");
opt!(OBSTACLE_CENTER: Given = "-obstacle_center" "x,y[,z]", Given("required for ball, halfball, cylinder"), "centre of the obstacle ball (circle in 2D); for a cylinder, a point of its axis");
opt!(OBSTACLE_AXIS: Given = "-obstacle_axis" "ax,ay,az", Given("required for a 3D cylinder"), "unit axis of the cylinder (3D only; a vector within 1e-3 of unit length is normalised)");
opt!(OBSTACLE_RADIUS: Given = "-obstacle_radius" "R", Given("required for ball, halfball, cylinder"), "radius of the obstacle ball or cylinder");
// Friction
opt!(FRICTION: Choice = "-friction" "none|tresca|coulomb", Choice { default: "none", values: &["none", "tresca", "coulomb"] }, "friction law");
opt!(FRICTION_COEFFICIENT: Given = "-friction_coefficient" "NU_F", Given("required with friction"), "Coulomb friction coefficient nu_f (also scales -tresca_bound hertz|frictionless)");
opt!(TRESCA_BOUND: Given = "-tresca_bound" "VALUE|hertz|frictionless", Given("frictionless (tresca), 0 (coulomb)"), "Tresca bound s: a constant, nu_f x Hertz pressure, or nu_f x lambda_c of a frictionless solve (solved 100x tighter than -ubr_lambda_rtol, its error part of the estimate); the paper's Tresca law bounds the friction by s on the whole contact surface, touching or not, so a constant s also acts on open candidates (the summary warns when they carry more than 5% of the friction); frictionless and hertz vanish where nothing touches (frictionless where friction alone holds a body that the loads move: refused, exit 2, that solve has none); with coulomb, the starting s^0");
// Algorithm
opt!(ALGORITHM: Choice = "-contact_algorithm" "ubr|ssn|snesvi", Choice { default: "ubr", values: &["ubr", "ssn", "snesvi"] }, "UBR (the paper's algorithms), the SSN-C comparator, or PETSc's SNES VI (vinewtonrsls; contact direction along an axis; not with -contact_pair: refused, exit 2)");
opt!(UBR_R: Given = "-ubr_r" "auto|R", Given("auto"), "augmentation parameter r of the augmented Lagrangian (3.7): auto chooses it from the spectrum of the contact compliance W^1/2 B K^-1 B^T W^1/2 (a few Lanczos steps with the first factorization); a number is used as given");
opt!(UBR_ANDERSON: usize = "-ubr_anderson" "M", 10, "memory of the safeguarded type-II Anderson acceleration of the UBR map on the contact surface (z = lambda + r B u); 0: the paper's plain iteration");
opt!(UBR_STOP: Choice = "-ubr_stop" "accuracy|paper", Choice { default: "accuracy", values: &["accuracy", "paper"] }, "stopping test: accuracy stops when the estimated error of lambda (the map's residual times the estimated error amplification, normal and tangential parts each relative to their max norm) is below -ubr_lambda_rtol / 4 and no contact status changed in 3 iterations; paper is the paper's (4.16)/(5.6) with -ubr_rtol and -ubr_residual_tol");
opt!(UBR_LAMBDA_RTOL: f64 = "-ubr_lambda_rtol" "TOL", 1e-3, "accuracy stop: the relative error of the contact stresses lambda to guarantee");
opt!(UBR_RHO: Given = "-ubr_rho" "RHO", Given("r"), "multiplier step rho in (4.4) (plain iteration only, -ubr_anderson 0); convergence needs 0 < rho < r(1+sqrt 5)/2");
opt!(UBR_RTOL: f64 = "-ubr_rtol" "EPS", 1e-5, "paper stop: relative tolerance eps_c = eps_f of the stopping tests (4.16), (5.6)");
opt!(UBR_RESIDUAL_TOL: Given = "-ubr_residual_tol" "TOL", Given("1e-3 * ubr_rtol / 1e-5"), "paper stop: tolerance on the constraint residual ||B u - phi||_{0,Gamma_c} (section 7)");
opt!(UBR_DUAL_RTOL: Given = "-ubr_dual_rtol" "TOL", Given("10 * ubr_rtol"), "paper stop: tolerance on the dual residual r||phi^k - phi^(k-1)|| / ||lambda^(k+1)|| (guards the stopping test against the slow regime of large r)");
opt!(UBR_MAX_IT: usize = "-ubr_max_it" "N", 10000, "maximum UBR iterations");
opt!(UBR_FP_RTOL: f64 = "-ubr_fp_rtol" "EPS", 1e-4, "paper stop: fixed-point tolerance eps_fp of (5.7) (CF-FP)");
opt!(UBR_FP_MAX_IT: usize = "-ubr_fp_max_it" "N", 100, "maximum fixed-point iterations (CF-FP)");
opt!(UBR_FP_ANDERSON: Given = "-ubr_fp_anderson" "M", Given("3 (0 with -ubr_anderson 0)"), "memory of the Anderson acceleration of CF-FP's outer fixed point s -> nu_f |lambda_c(s)|; 0: the paper's plain fixed point");
opt!(UBR_MONITOR: bool = "-ubr_monitor" "", false, "print one line per UBR iteration");
opt!(UBR_CONDENSE_MAX: Given = "-ubr_condense_max" "P", Given("6000 in 2D; 4000 in 3D, 6000 with friction"), "MUMPS: condense each UBR solve onto the P or fewer contact unknowns (the Schur complement from the one factorization, on rank 0 on one rank (and on 2-3 ranks in 2D), over every rank from 2 ranks in 3D and 4 in 2D: -ubr_schur_distributed; a dense solve per iteration, the whole displacement only at the end; with -ubr_stop paper not with -ubr_monitor, -plot_history; in 3D at the default, not where MUMPS' analysis predicts fewer sparse factorization flops than m^3 / 2); 0: a full sparse solve per iteration");
opt!(UBR_MEMORY_MB: Given = "-ubr_memory_mb" "MB", Given("what each machine has free"), "the memory in MB that the ranks of one machine may use together: a run whose stiffness matrix alone exceeds it is refused before the assembly, and with MUMPS called directly a factorization that MUMPS' analysis predicts larger (INFO(15) summed over the machine's ranks) before it starts, exit 4 (default: the machine's MemAvailable and SwapFree, within its memory cgroup's limit; the factorization is not checked with -mat_mumps_icntl_23, MUMPS' own cap per rank)");
opt!(UBR_MEMORY_RESERVE: Given = "-ubr_memory_reserve" "MB", Given("3% of the machine's memory, 256 MB to 2 GB"), "the free memory in MB that a run keeps on each of its machines: a run that leaves less while it works ends with exit 4 and the phase it was in, before the system kills a rank; a machine with less free at the start is refused (0: no watch)");
opt!(UBR_SCHUR_DISTRIBUTED: Given = "-ubr_schur_distributed" "0|1", Given("1 from 2 ranks on in 3D, from 4 in 2D; 0 below"), "condensed MUMPS solves on several ranks: MUMPS returns the Schur complement distributed over every rank (ICNTL(19) = 3 on a 1 x P grid; its root front assembled by all), and ScaLAPACK factorizes it (pdpotrf) and solves with it (pdpotrs) there; 0: on rank 0 (ICNTL(19) = 1), by LAPACK; the same answer to round-off (3D Coulomb, 63k nodes, 5952 unknowns, 16 ranks: 8.1-9.1 s against 13.5 s, the dense factorization 0.28 s against 1.56 s; on 2 ranks: 3D faster, 63k nodes 12.0 s against 12.5 s, Coulomb 8% faster; 2D 1-2% slower on small scenes, hence the default)");
opt!(UBR_MUMPS_RHS: Choice = "-ubr_mumps_rhs" "distributed|centralized", Choice { default: "distributed", values: &["distributed", "centralized"] }, "MUMPS called directly: full solves hand MUMPS each rank's rows of the right-hand sides and send its distributed solution to the rows' owners (ICNTL(20) = 10, ICNTL(21) = 1); centralized: gathered on rank 0 and scattered from there (ICNTL(20) = ICNTL(21) = 0)");
opt!(UBR_MUMPS_SPLIT: Given = "-ubr_mumps_split" "0|1", Given("1 in 3D with the Schur complement on 2 ranks or more, 0 otherwise"), "MUMPS called directly: its analysis splits large fronts into chains of smaller ones (KEEP(210) = 1, MUMPS' pre-splitting, which it otherwise does only out of core): the master of a large front no longer factorizes its whole pivot block while the other ranks wait for its panels (the flops are unchanged; the summary says how many fronts were split). 3D block, 63k nodes, condensed, 2 ranks: factorization 13.1-13.4 s -> 11.4-11.8 s; without the Schur complement it split the root too and was slower (9.0-9.3 -> 9.6-9.8 s); in 2D (small fronts) nothing gained at 582k nodes and 2% lost at 37k, hence the default");
opt!(UBR_MUMPS_DIRECT: bool = "-ubr_mumps_direct" "0|1", true, "the default direct solver (-pc_type cholesky -pc_factor_mat_solver_type mumps) calls MUMPS itself: METIS nested-dissection ordering, the Schur complement on any rank count; 0: through PETSc's MUMPS interface (AMD/PORD, no condensation)");
opt!(UBR_SBAIJ: bool = "-ubr_sbaij" "0|1", true, "iterative solvers: the Krylov method's and the smoothers' products use a copy of the operator in symmetric block storage (the upper block triangle: about half the bytes read per product, for 40-50% more matrix memory), the preconditioner is built from the AIJ matrix; 0: AIJ products");
opt!(UBR_INNER_RTOL_FACTOR: f64 = "-ubr_inner_rtol_factor" "F", 0.1, "iterative solvers (inexact Uzawa): each inner solve reduces the residual of the previous iterate b - A u^{k-1} by F, tightened tenfold (down to 1e-3) at each Anderson step the safeguard rejects (a given -ksp_rtol wins)");
opt!(SSN_R: Given = "-ssn_r" "R", Given("1e3 E"), "SSN-C parameter r of (7.1)");
opt!(SSN_INITIAL_SHIFT: Given = "-ssn_initial_shift" "ux,uy[,uz]", Given("0"), "SSN-C initial guess u^0, the same at every node (the paper: 0,-0.01 for the floating Hertz body)");
opt!(SSN_MAX_IT: usize = "-ssn_max_it" "N", 100, "maximum SSN-C iterations");
// Reference
opt!(REFERENCE: Choice = "-reference" "hertz", Choice { default: "none", values: &["hertz"] }, "compare the contact pressure with the analytic Hertz pressure");
opt!(REFERENCE_FORCE: Given = "-reference_force" "F", Given("required with -reference"), "Hertz load: per unit thickness of the whole cylinder (2D), on the whole sphere (3D)");
opt!(REFERENCE_RADIUS: Given = "-reference_radius" "R|R1,R2", Given("required with -reference"), "radius of the Hertz cylinder or sphere on a plane; two curved surfaces (two bodies, or a body on a curved obstacle): their radii R1,R2 (1/R = 1/R1 + 1/R2, a concave one negative: a pin in a hole), or that R");
opt!(REFERENCE_AXIS: Given = "-reference_axis" "x,y,z", Given("none: a sphere in 3D"), "3D: the axis of a cylinder lying on its side (a line contact): Hertz's cylinder formula, -reference_force per unit length of the whole cylinder, distances from the contact line");
opt!(REFERENCE_CENTER: Given = "-reference_center" "x,y[,z]", Given("candidate with the smallest gap"), "centre of the contact, for the Hertz comparison and -plot_contact (with or without -reference)");
// Output
opt!(REPORT: Given = "-report" "FILE.json", Given("none"), "write a JSON report");
opt!(CONTACT_OUTPUT: Given = "-contact_output" "FILE.csv", Given("none"), "write the contact nodes (one row per candidate)");
opt!(VTK: Given = "-vtk" "FILE.vtu|PATH.pvtu", Given("none"), "ParaView output with displacement, stress, von Mises, rank, contact fields and the mesh file's node tag: FILE.vtu, one file gathered on rank 0 (readable by meshio); PATH.pvtu, an index and one PATH_RANK.vtu piece per rank");
opt!(PLOT_CONTACT: Given = "-plot_contact" "FILE.png", Given("none"), "plot the contact pressure (and tangential traction, friction bound, Hertz) along the surface: against a signed coordinate along it in 2D, the distance from the contact centre in 3D");
opt!(PLOT_HISTORY: Given = "-plot_history" "FILE.png", Given("none"), "plot the UBR change (4.16)/(5.6) and constraint residual per iteration");
opt!(LOAD_STEPS: Given = "-load_steps" "N", Given("1: one solve at the full load"), "a load history of N proportional steps: every load and prescribed displacement scaled by k/N at step k; one factorization for the whole history, each step warm-started from the last, friction quasi-static (on the slip of each step); at most 1000000 steps");
opt!(LOAD_HISTORY: Given = "-load_history" "FILE", Given("none"), "a load history from a table: a header 'step,factor' (every load scaled by factor) or 'step,GROUP,...' with GROUP one of traction_NAME, pressure_NAME, dirichlet_NAME, body (the load of that option, scaled by its column; loads not named stay at 1), then one row per step; '#' comments");
opt!(HISTORY_OUTPUT: Given = "-history_output" "FILE.csv", Given("none"), "with a load history: one row per step (factors, contact force, contact area, peak pressure, stick/slip counts, each Dirichlet group's reaction, iterations, time); -vtk then also writes one file per step and a ParaView .pvd series");
opt!(PLOT_HISTORY_CURVE: Given = "-plot_history_curve" "FILE.png", Given("none"), "with a load history: the force on a load group against its mean displacement over the steps (-history_curve)");
opt!(HISTORY_CURVE: Given = "-history_curve" "GROUP[,ux|uy|uz]", Given("the first group of the history with a load, its largest component"), "the group of -plot_history_curve (dirichlet_NAME: its reaction; traction_NAME, pressure_NAME: the applied force) and the component of force and displacement");
opt!(HELP: bool = "-help" "", false, "this list (PETSc's solver options are listed when a scene is given too)");

/// Every option, in the order `-help` lists them.
pub const ALL: &[&dyn Declared] = &[
    &MESH,
    &MESH_GENERATE,
    &MESH_H,
    &MESH_ELEMENT,
    &PARTITION,
    &YOUNG,
    &NU,
    &YOUNG_BODY,
    &NU_BODY,
    &DENSITY_BODY,
    &PLANE_STRESS,
    &DIRICHLET,
    &TRACTION,
    &PRESSURE,
    &BODY_FORCE,
    &GRAVITY,
    &DENSITY,
    &CONTACT_SURFACE,
    &CONTACT_PAIR,
    &CONTACT_PAIR_SCHEME,
    &CONTACT_DIRECTION,
    &CONTACT_NORMAL,
    &OBSTACLE,
    &OBSTACLE_POINT,
    &OBSTACLE_CENTER,
    &OBSTACLE_AXIS,
    &OBSTACLES,
    &OBSTACLE_MESH,
    &OBSTACLE_MESH_GROUP,
    &OBSTACLE_SEARCH_DISTANCE,
    &OBSTACLE_RADIUS,
    &FRICTION,
    &FRICTION_COEFFICIENT,
    &TRESCA_BOUND,
    &ALGORITHM,
    &UBR_R,
    &UBR_ANDERSON,
    &UBR_STOP,
    &UBR_LAMBDA_RTOL,
    &UBR_RHO,
    &UBR_RTOL,
    &UBR_RESIDUAL_TOL,
    &UBR_DUAL_RTOL,
    &UBR_MAX_IT,
    &UBR_FP_RTOL,
    &UBR_FP_MAX_IT,
    &UBR_FP_ANDERSON,
    &UBR_MONITOR,
    &UBR_CONDENSE_MAX,
    &UBR_MUMPS_DIRECT,
    &UBR_SCHUR_DISTRIBUTED,
    &UBR_MEMORY_MB,
    &UBR_MEMORY_RESERVE,
    &UBR_MUMPS_RHS,
    &UBR_MUMPS_SPLIT,
    &UBR_SBAIJ,
    &UBR_INNER_RTOL_FACTOR,
    &SSN_R,
    &SSN_INITIAL_SHIFT,
    &SSN_MAX_IT,
    &REFERENCE,
    &REFERENCE_FORCE,
    &REFERENCE_RADIUS,
    &REFERENCE_AXIS,
    &REFERENCE_CENTER,
    &REPORT,
    &CONTACT_OUTPUT,
    &VTK,
    &PLOT_CONTACT,
    &PLOT_HISTORY,
    &LOAD_STEPS,
    &LOAD_HISTORY,
    &HISTORY_OUTPUT,
    &PLOT_HISTORY_CURVE,
    &HISTORY_CURVE,
    &HELP,
];

/// `-help`: every option with its default, then how the defaults and the
/// paper's settings relate.
pub fn print_help() {
    println!(
        "ubr-petsc: Uzawa block relaxation for unilateral contact in linear elasticity (Koko 2010)"
    );
    println!("usage: mpirun -n N ubr-petsc -options_file options/hertz [options]\n");
    println!("Options (default in brackets):");
    for o in ALL {
        let head = format!("{} {}", o.name(), o.arg());
        let default = o.default_text();
        if default.is_empty() || o.name() == "-help" {
            println!("  {:<40} {}", head.trim_end(), o.help());
        } else {
            println!("  {:<40} {} [{default}]", head.trim_end(), o.help());
        }
    }
    println!("\nDefaults: the UBR map Anderson-accelerated, r chosen from the spectrum of the contact compliance,");
    println!(
        "and a stop that bounds the error of the contact stresses by -ubr_lambda_rtol ({}).",
        UBR_LAMBDA_RTOL.default_text()
    );
    println!("The paper's algorithm as it runs it: -ubr_anderson 0 -ubr_stop paper -ubr_r R (options/*-paper).");
    println!("\nLinear solver: the unprefixed PETSc options (-ksp_type, -pc_type, -pc_factor_mat_solver_type, ...);");
    println!("default -ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps, factorized once.");
    println!("Profiling: -log_view (stages Mesh, Partition, Assembly, Factorization, RChoice, Iterations, Output).");
    println!(
        "An option that has no effect in the scene is named on stderr when the options are read, one that"
    );
    println!("neither ubr-petsc nor PETSc used at the end of the run.");
    println!(
        "Options files: one option per line, '#' comments, a value with spaces in double quotes."
    );
    println!("Exit status: 0 converged, 1 a PETSc, MPI or internal error, 2 bad input or an ill-posed scene (a rigid motion nothing holds), 3 not converged (the report still written), 4 out of memory, 70 a panic (docs/DESIGN.md).");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_defaults_print_as_typed() {
        let mut names: Vec<&str> = ALL.iter().map(|o| o.name()).collect();
        names.sort();
        let n = names.len();
        names.dedup();
        assert_eq!(names.len(), n);
        assert_eq!(UBR_RTOL.default_text(), "1e-5");
        assert_eq!(UBR_LAMBDA_RTOL.default_text(), "1e-3");
        assert_eq!(MESH_H.default_text(), "0.5");
        assert_eq!(UBR_MAX_IT.default_text(), "10000");
        assert_eq!(DIRICHLET.prefix(), Some("-dirichlet_"));
    }
}
