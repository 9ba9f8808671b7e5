//! The run, step by step, as a reader expects it: read the options, make the
//! mesh, distribute it, assemble and factorize, iterate, report.

use crate::contact::ContactSet;
use crate::error::{bad, Error};
use crate::mesh::{self, distribute, Mesh};
use crate::options::{self, Friction, MeshSource, Settings};
use crate::petsc::{self, LogEvent, LogStage};
use crate::report::{self, ContactRow, Json};
use crate::solver::{allreduce_count, allreduce_max, allreduce_sum, ubr, Problem};
use mpi::traits::*;
use std::time::Instant;

/// `-log_view` stages, one per phase.
pub struct Stages {
    pub mesh: LogStage,
    pub partition: LogStage,
    pub assembly: LogStage,
    pub factorization: LogStage,
    pub iterations: LogStage,
    pub output: LogStage,
}

/// `-log_view` events of the UBR loop.
pub struct Events {
    pub rhs: LogEvent,
    pub solve: LogEvent,
    pub projection: LogEvent,
}

impl Stages {
    pub fn register() -> Result<Stages, Error> {
        Ok(Stages {
            mesh: LogStage::register("Mesh")?,
            partition: LogStage::register("Partition")?,
            assembly: LogStage::register("Assembly")?,
            factorization: LogStage::register("Factorization")?,
            iterations: LogStage::register("Iterations")?,
            output: LogStage::register("Output")?,
        })
    }
}

impl Events {
    pub fn register() -> Result<Events, Error> {
        Ok(Events {
            rhs: LogEvent::register("UBRRhs")?,
            solve: LogEvent::register("UBRSolve")?,
            projection: LogEvent::register("UBRProjection")?,
        })
    }
}

fn load_mesh(source: &MeshSource) -> Result<Mesh, Error> {
    let mesh = match source {
        MeshSource::File(path) => mesh::gmsh::read_gmsh(std::path::Path::new(path))?,
        MeshSource::Generate { name, h } => match name.as_str() {
            "hertz2d" => mesh::hertz2d::generate(*h)?,
            other => return bad(format!("option -mesh_generate: unknown mesh '{other}'")),
        },
    };
    for c in 0..mesh.num_cells() {
        let m = mesh.signed_measure(c);
        if !m.is_finite() || m == 0.0 {
            let k = mesh.dim + 1;
            let tags: Vec<String> = mesh.cells[c * k..(c + 1) * k]
                .iter()
                .map(|&v| mesh.node_tags[v].to_string())
                .collect();
            return bad(format!(
                "mesh: element {} (nodes {}) is degenerate: zero {}",
                c + 1,
                tags.join(" "),
                if mesh.dim == 2 { "area" } else { "volume" }
            ));
        }
    }
    Ok(mesh)
}

fn mesh_label(source: &MeshSource) -> String {
    match source {
        MeshSource::File(p) => p.clone(),
        MeshSource::Generate { name, h } => format!("generated {name}, h = {h}"),
    }
}

/// Runs the program on every rank. Errors are collective: every rank returns
/// the same error.
pub fn run<C: Communicator>(world: &C) -> Result<(), Error> {
    let t_start = Instant::now();
    let root = world.rank() == 0;
    let help = petsc::options::has_name("-help")?;
    if help {
        if root {
            options::print_help();
        }
        if !petsc::options::has_name("-mesh")? && !petsc::options::has_name("-mesh_generate")? {
            return Ok(());
        }
    }
    let stages = Stages::register()?;
    let events = Events::register()?;
    let settings = Settings::from_options()?;
    if settings.friction != Friction::None {
        return bad("option -friction: only 'none' is available in this version (UBR-C)");
    }
    if settings.algorithm != "ubr" {
        return bad("option -contact_algorithm: only 'ubr' is available in this version");
    }
    let Some(contact_settings) = settings.contact.clone() else {
        return bad(
            "option -contact_surface is required (a contact problem needs a candidate surface)",
        );
    };

    // Mesh (rank 0 reads or generates) and partition (METIS on rank 0, then each rank gets its part).
    let mut time_mesh = 0.0;
    let mut time_partition = 0.0;
    let size = world.size() as usize;
    let local = distribute::distribute(
        world,
        || {
            let t = Instant::now();
            let guard = stages.mesh.push()?;
            let mesh = load_mesh(&settings.mesh);
            drop(guard);
            time_mesh = t.elapsed().as_secs_f64();
            mesh
        },
        |mesh| {
            let t = Instant::now();
            let guard = stages.partition.push()?;
            let graph = distribute::NodeGraph::new(mesh);
            let part = distribute::partition_nodes(&graph, size)?;
            let order = distribute::locality_order(&graph, &part, size);
            drop(graph);
            let locals = distribute::split(mesh, &part, &order, size);
            drop(guard);
            time_partition = t.elapsed().as_secs_f64();
            Ok(locals)
        },
    )?;

    // Contact set: owned candidates.
    let cs = ContactSet::build(&local, &contact_settings)?;
    let ncand = allreduce_count(world, cs.len());
    if ncand == 0 {
        return bad(format!(
            "option -contact_surface: surface '{}' has no candidate node facing the obstacle along the contact direction",
            contact_settings.surface
        ));
    }
    let n = cs.n.clone();

    // Assembly of K + r B^T W B, Dirichlet elimination, factorization (once).
    let problem = Problem::setup(world, &local, &settings, cs, false, &stages)?;
    if problem.matrix_mallocs != 0.0 {
        return Err(Error::Internal(format!(
            "{} mallocs during matrix assembly: preallocation is wrong",
            problem.matrix_mallocs
        )));
    }

    // Iterations: Algorithm UBR-C.
    let guard = stages.iterations.push()?;
    let result = ubr::ubr_c(world, &problem, &settings.ubr, &events)?;
    drop(guard);

    // Output.
    let guard = stages.output.push()?;
    let d = local.dim;
    let cs = &problem.contact;
    let rows: Vec<ContactRow> = (0..cs.len())
        .map(|i| {
            let v = cs.node[i];
            let mut x = [0.0; 3];
            x[..d].copy_from_slice(local.x(v));
            let mut ut = [0.0; 3];
            ut[..d].copy_from_slice(&result.ut[i * d..(i + 1) * d]);
            ContactRow {
                node: local.node_tag[v],
                x,
                weight: cs.w[i],
                gap: cs.g[i],
                un: result.un[i],
                ut,
                lambda_n: result.lambda_n[i],
                lambda_t: [0.0; 3],
                status: u8::from(result.in_contact[i]),
            }
        })
        .collect();
    let diag = diagnostics(world, &problem, &result)?;
    let all_rows = report::gather_rows(world, &rows);
    let time_total = t_start.elapsed().as_secs_f64();
    let mut write_error: Option<Error> = None;
    if root {
        let e_star = if d == 2 && !settings.plane_stress {
            settings.young / (1.0 - settings.nu * settings.nu)
        } else if d == 2 {
            settings.young
        } else {
            settings.young / (1.0 - settings.nu * settings.nu)
        };
        let hertz = settings
            .reference
            .as_ref()
            .map(|r| report::compare_hertz(&all_rows, d, &n, e_star, r));
        let contact_force: f64 = all_rows.iter().map(|r| r.weight * r.lambda_n).sum();
        let in_contact = all_rows.iter().filter(|r| r.status != 0).count();
        let times = Times {
            mesh: time_mesh,
            partition: time_partition,
            assembly: problem.time_assembly,
            factorization: problem.time_factorization,
            iterations: result.time_iterations,
            total: time_total,
        };
        print_summary(
            &settings,
            &local,
            size,
            ncand,
            &problem,
            &result,
            contact_force,
            in_contact,
            hertz.as_ref(),
            &times,
            &diag,
        );
        if let Some(path) = &settings.contact_output {
            if let Err(e) =
                report::write_atomic("-contact_output", path, report::csv(&all_rows).as_bytes())
            {
                write_error = Some(e);
            }
        }
        if let Some(path) = &settings.report {
            let mut j = Json::default();
            j.int("dimension", d)
                .int("nodes", local.global_nodes)
                .int("elements", local.global_cells)
                .int("contact_nodes", ncand)
                .int("contact_active", in_contact)
                .int("ranks", size)
                .string("algorithm", "ubr")
                .string("friction", "none")
                .string("mesh", &mesh_label(&settings.mesh))
                .string("linear_solver", &problem.ksp_description)
                .num("E", settings.young)
                .num("nu", settings.nu)
                .num("r", settings.ubr.r)
                .num("rho", settings.ubr.rho)
                .num("rtol", settings.ubr.rtol)
                .int("iterations", result.iterations)
                .int("fixed_point_iterations", 0)
                .boolean("converged", result.converged)
                .num("criterion", result.criterion)
                .num("constraint_residual", result.residual)
                .num("contact_force", contact_force)
                .array("tangential_force", &vec![0.0; d])
                .num("time_mesh", time_mesh)
                .num("time_partition", time_partition)
                .num("time_assembly", problem.time_assembly)
                .num("time_factorization", problem.time_factorization)
                .num("time_iterations", result.time_iterations)
                .num("time_total", time_total)
                .opt("pressure_error_l2", hertz.as_ref().map(|h| h.error_l2))
                .opt("pressure_error_rel", hertz.as_ref().map(|h| h.error_rel))
                .opt("peak_pressure", hertz.as_ref().map(|h| h.peak))
                .opt("peak_pressure_hertz", hertz.as_ref().map(|h| h.peak_hertz))
                .opt("contact_half_width", hertz.as_ref().map(|h| h.half_width))
                .opt(
                    "contact_half_width_hertz",
                    hertz.as_ref().map(|h| h.half_width_hertz),
                )
                .num("equilibrium_residual", diag.equilibrium_abs)
                .num("equilibrium_residual_rel", diag.equilibrium_rel)
                .num("load_norm", diag.load_norm)
                .num("min_lambda_n", diag.min_lambda)
                .num("max_penetration", diag.max_penetration)
                .num("max_abs_gap", diag.max_abs_gap)
                .num("complementarity", diag.complementarity)
                .num("matrix_mallocs", problem.matrix_mallocs)
                .int_array("inner_iterations", &result.inner_iterations);
            if let Err(e) = report::write_atomic("-report", path, j.render().as_bytes()) {
                write_error = write_error.or(Some(e));
            }
        }
    }
    drop(guard);
    // Make a write failure on rank 0 collective.
    let failed = allreduce_max(world, if write_error.is_some() { 1.0 } else { 0.0 });
    if failed > 0.0 {
        return Err(write_error
            .unwrap_or_else(|| Error::BadInput("writing an output file failed on rank 0".into())));
    }
    if !result.converged {
        return Err(Error::NotConverged(format!(
            "UBR-C stopped after {} iterations (-ubr_max_it): relative change {:.3e} (target {:.1e}), constraint residual {:.3e} (target {:.1e})",
            result.iterations, result.criterion, settings.ubr.rtol, result.residual, settings.ubr.residual_tol
        )));
    }
    Ok(())
}

struct Times {
    mesh: f64,
    partition: f64,
    assembly: f64,
    factorization: f64,
    iterations: f64,
    total: f64,
}

/// The discrete optimality conditions at the returned iterate.
pub struct Diagnostics {
    /// `||K u - f + B^T W lambda||` on the free dofs, and relative to `||f||`.
    pub equilibrium_abs: f64,
    pub equilibrium_rel: f64,
    pub load_norm: f64,
    pub min_lambda: f64,
    /// `max (u_n - g)` over the candidates.
    pub max_penetration: f64,
    pub max_abs_gap: f64,
    /// `sum w lambda_n (g - u_n)`.
    pub complementarity: f64,
}

fn diagnostics<C: Communicator>(
    world: &C,
    p: &Problem,
    res: &ubr::UbrResult,
) -> Result<Diagnostics, Error> {
    let d = p.dim;
    let cs = &p.contact;
    let au = p.rhs0.duplicate()?;
    p.matrix.mult(&res.solution, &au)?;
    let (eq2, f2) = au.write(|a| {
        p.rhs0.read(|b| {
            p.load.read(|f| {
                for (ai, bi) in a.iter_mut().zip(b) {
                    *ai -= bi;
                }
                for i in 0..cs.len() {
                    let base = cs.node[i] * d;
                    for c in 0..d {
                        // remove r B^T W B u, add B^T W lambda
                        let w = cs.w[i];
                        let bu = if p.tangential {
                            res.un[i] * cs.n[c] + res.ut[i * d + c]
                        } else {
                            res.un[i] * cs.n[c]
                        };
                        a[base + c] += w * (res.lambda_n[i] * cs.n[c] - p.r * bu);
                    }
                }
                let mut eq2 = 0.0;
                let mut f2 = 0.0;
                for (i, ai) in a.iter().enumerate() {
                    if !p.is_dirichlet[i] {
                        eq2 += ai * ai;
                        f2 += f[i] * f[i];
                    }
                }
                (eq2, f2)
            })
        })
    })???;
    let mut min_lambda = f64::INFINITY;
    let mut max_pen = f64::NEG_INFINITY;
    let mut max_gap = 0.0f64;
    let mut compl = 0.0;
    for i in 0..cs.len() {
        min_lambda = min_lambda.min(res.lambda_n[i]);
        max_pen = max_pen.max(res.un[i] - cs.g[i]);
        max_gap = max_gap.max(cs.g[i].abs());
        compl += cs.w[i] * res.lambda_n[i] * (cs.g[i] - res.un[i]);
    }
    let [eq2, f2, compl] = allreduce_sum(world, [eq2, f2, compl]);
    let min_lambda = -allreduce_max(world, -min_lambda);
    let max_penetration = allreduce_max(world, max_pen);
    let max_abs_gap = allreduce_max(world, max_gap);
    Ok(Diagnostics {
        equilibrium_abs: eq2.sqrt(),
        equilibrium_rel: if f2 > 0.0 {
            (eq2 / f2).sqrt()
        } else {
            eq2.sqrt()
        },
        load_norm: f2.sqrt(),
        min_lambda,
        max_penetration,
        max_abs_gap,
        complementarity: compl,
    })
}

#[allow(clippy::too_many_arguments)]
fn print_summary(
    s: &Settings,
    local: &distribute::LocalMesh,
    ranks: usize,
    ncand: usize,
    p: &Problem,
    res: &ubr::UbrResult,
    force: f64,
    in_contact: usize,
    hertz: Option<&report::HertzComparison>,
    t: &Times,
    diag: &Diagnostics,
) {
    let cells = if local.dim == 2 {
        "triangles"
    } else {
        "tetrahedra"
    };
    println!(
        "ubr-petsc: Algorithm UBR-C (frictionless), {ranks} rank{}",
        if ranks == 1 { "" } else { "s" }
    );
    println!("  mesh            {}", mesh_label(&s.mesh));
    println!(
        "                  {} nodes, {} {cells}, {} contact candidates",
        local.global_nodes, local.global_cells, ncand
    );
    println!(
        "  material        E = {}, nu = {}, {}",
        s.young,
        s.nu,
        if local.dim == 3 {
            "3D"
        } else if s.plane_stress {
            "plane stress"
        } else {
            "plane strain"
        }
    );
    println!("  linear solver   {}", p.ksp_description);
    println!(
        "  r               {} (rho = {}, r/E = {})",
        s.ubr.r,
        s.ubr.rho,
        s.ubr.r / s.young
    );
    println!(
        "  iterations      {}, {} (rel. change {:.3e}, target {:.1e}; residual {:.3e}, target {:.1e})",
        res.iterations,
        if res.converged { "converged" } else { "NOT converged" },
        res.criterion,
        s.ubr.rtol,
        res.residual,
        s.ubr.residual_tol
    );
    if p.iterative {
        let total: usize = res.inner_iterations.iter().sum();
        println!("  inner its       {total} in total");
    }
    println!("  contact         {in_contact} nodes in contact, total contact force {force:.10e}");
    println!(
        "  optimality      equilibrium {:.2e} (rel.), min lambda_n {:.3e}, max u_n - g {:.3e}, complementarity {:.3e}",
        diag.equilibrium_rel, diag.min_lambda, diag.max_penetration, diag.complementarity
    );
    if let Some(h) = hertz {
        println!(
            "  hertz           pressure error L2 {:.4e}, relative {:.3}%",
            h.error_l2,
            100.0 * h.error_rel
        );
        println!(
            "                  peak pressure {:.4} vs Hertz p0 {:.4}; contact half-width {:.4} vs Hertz {:.4}",
            h.peak, h.peak_hertz, h.half_width, h.half_width_hertz
        );
    }
    println!(
        "  time (s)        mesh {:.3}, partition {:.3}, assembly {:.3}, factorization {:.3}, iterations {:.3}, total {:.3}",
        t.mesh, t.partition, t.assembly, t.factorization, t.iterations, t.total
    );
}
