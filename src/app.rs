//! The run, step by step, as a reader expects it: read the options, make the
//! mesh, distribute it, assemble and factorize, iterate, report.

use crate::contact::ContactSet;
use crate::error::{bad, Error};
use crate::mesh::{self, distribute, Mesh};
use crate::options::{self, Friction, MeshSource, Settings, TrescaBound};
use crate::petsc::{self, sys, Events, Stages};
use crate::report::{self, ContactRow, Json};
use crate::solver::stopping::StopRule;
use crate::solver::surface::UbrState;
use crate::solver::{
    allreduce_count, allreduce_max, allreduce_sum, cf_fp, penalty, snesvi, ssn, ubr, ContactTerms,
    Problem,
};
use mpi::traits::*;
use std::time::Instant;

fn load_mesh(source: &MeshSource) -> Result<Mesh, Error> {
    let mesh = match source {
        MeshSource::File(path) => mesh::gmsh::read_gmsh(std::path::Path::new(path))?,
        MeshSource::Generate { name, h, q1 } => match (name.as_str(), q1) {
            ("hertz2d", false) => mesh::hertz2d::generate(*h)?,
            ("hertz2d", true) => mesh::hertz2d::generate_quad(*h)?,
            ("block3d", false) => mesh::block3d::generate(*h)?,
            ("block3d", true) => mesh::block3d::generate_hex(*h)?,
            (other, _) => return bad(format!("option -mesh_generate: unknown mesh '{other}'")),
        },
    };
    // Cells of both orientations: the minority ones are inverted (a broken
    // mesh, e.g. a node moved across an edge); name the first of them. The
    // orientation is the sign of the Jacobian determinant, constant on a
    // simplex, taken at every Gauss point of a Q1 cell: a sign change
    // inside one means it is folded.
    let ranges: Vec<(f64, f64)> = (0..mesh.num_cells())
        .map(|c| mesh.jacobian_range(c))
        .collect();
    let positive = ranges.iter().filter(|r| r.0 > 0.0).count();
    let negative_is_minority = 2 * positive >= mesh.num_cells();
    let nodes_of = |c: usize| -> String {
        let tags: Vec<String> = mesh
            .cells
            .get(c)
            .iter()
            .map(|&v| mesh.node_tags[v].to_string())
            .collect();
        tags.join(" ")
    };
    for (c, &(lo, hi)) in ranges.iter().enumerate() {
        let finite = lo.is_finite() && hi.is_finite();
        let kind = mesh.cell_kind(c);
        if finite && lo < 0.0 && hi > 0.0 {
            return bad(format!(
                "mesh: element {} (nodes {}) is folded: its Jacobian determinant changes sign inside it (from {lo:.3e} to {hi:.3e} at its Gauss points; a {} with its nodes out of order, or not convex)",
                mesh.cell_tag(c),
                nodes_of(c),
                kind.name()
            ));
        }
        let inverted = finite && (lo > 0.0 || hi < 0.0) && ((hi < 0.0) == negative_is_minority);
        if inverted && positive != 0 && positive != mesh.num_cells() {
            return bad(format!(
                "mesh: element {} (nodes {}) is inverted: its orientation is opposite to that of the other {} cells",
                mesh.cell_tag(c),
                nodes_of(c),
                if negative_is_minority { positive } else { mesh.num_cells() - positive }
            ));
        }
        if !finite || lo == 0.0 || hi == 0.0 {
            return bad(format!(
                "mesh: element {} (nodes {}) is degenerate: zero {}",
                mesh.cell_tag(c),
                nodes_of(c),
                match (mesh.dim, lo == hi) {
                    (2, true) => "area",
                    (3, true) => "volume",
                    _ => "Jacobian determinant at a Gauss point",
                }
            ));
        }
    }
    Ok(mesh)
}

fn mesh_label(source: &MeshSource) -> String {
    match source {
        MeshSource::File(p) => p.clone(),
        MeshSource::Generate { name, h, q1 } => format!(
            "generated {name}, h = {h}{}",
            match (q1, name.as_str()) {
                (false, _) => "",
                (true, "hertz2d") => ", quadrilaterals",
                (true, _) => ", hexahedra",
            }
        ),
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
    // Every rigid motion must be held (by Dirichlet data, contact along n,
    // or friction): an ill-posed scene is named now, not met as a zero pivot.
    let friction = settings.friction != Friction::None;
    let dirichlet = crate::fem::dirichlet_dofs(&local, &settings.dirichlet)?;
    let restraint = crate::solver::wellposed::check(world, &local, &dirichlet, &cs, friction)?;
    let n = cs.n.clone();
    let d = local.dim;
    let e_star = if d == 2 && settings.plane_stress {
        settings.young
    } else {
        settings.young / (1.0 - settings.nu * settings.nu)
    };

    // Assembly of K + r B^T W B, Dirichlet elimination, factorization (once).
    let ssn = settings.algorithm != "ubr";
    if ssn && !settings.ssn_initial_shift.is_empty() && settings.ssn_initial_shift.len() != d {
        return bad(format!(
            "option -ssn_initial_shift: {} components given, the mesh is {d}D",
            settings.ssn_initial_shift.len()
        ));
    }
    let terms = if ssn {
        ContactTerms::None
    } else {
        ContactTerms::Ubr {
            tangential: friction,
        }
    };
    // r: the user's, or a trial r0 refined after the factorization (auto).
    let ubr_run = !ssn;
    let auto_r = ubr_run && settings.ubr.r.is_none();
    let r0 = settings.ubr.r.unwrap_or_else(|| {
        let modulus =
            penalty::p_wave_modulus(settings.young, settings.nu, d, settings.plane_stress);
        penalty::trial(world, &local, &cs, modulus)
    });
    let mut problem = Problem::setup(world, &local, &settings, cs, terms, r0, &stages)?;
    if !friction {
        let load = problem.load.read(|f| f.to_vec())?;
        crate::solver::wellposed::check_loads(world, &local, &restraint, &problem.contact, &load)?;
    }
    let t_choice = Instant::now();
    let choice = if ubr_run {
        let _guard = stages.r_choice.push()?;
        let solves = problem.lin.solves;
        let choice = penalty::choose(
            world,
            &mut problem,
            &restraint,
            &local,
            auto_r,
            settings.ubr.monitor,
        )?;
        let _ = solves;
        Some(choice)
    } else {
        None
    };
    let time_r_choice = t_choice.elapsed().as_secs_f64();
    if problem.matrix_mallocs != 0.0 {
        return Err(Error::Internal(format!(
            "{} mallocs during matrix assembly: preallocation is wrong",
            problem.matrix_mallocs
        )));
    }

    // Iterations: UBR-C, UBR-TF or CF-FP.
    let guard = stages.iterations.push()?;
    let t_iter = Instant::now();
    let (state, mut solved) = solve(world, &local, &settings, &mut problem, &events, e_star)?;
    let time_iterations = t_iter.elapsed().as_secs_f64();
    drop(guard);

    // Output.
    let guard = stages.output.push()?;
    let ssn_run = ssn_like(solved.name);
    let cs = &problem.contact;
    let rows: Vec<ContactRow> = (0..cs.len())
        .map(|i| {
            let v = cs.node[i];
            let mut x = [0.0; 3];
            x[..d].copy_from_slice(local.x(v));
            let mut ut = [0.0; 3];
            ut[..d].copy_from_slice(&state.surface.ut[i * d..(i + 1) * d]);
            let mut lt = [0.0; 3];
            if friction {
                lt[..d].copy_from_slice(&state.surface.stress_t[i * d..(i + 1) * d]);
            }
            let status = match (state.surface.in_contact[i], friction, state.surface.slip[i]) {
                (false, _, _) => 0,
                (true, false, _) => 1,
                (true, true, false) => 2,
                (true, true, true) => 3,
            };
            ContactRow {
                node: local.node_tag[v],
                x,
                weight: cs.w[i],
                gap: cs.g[i],
                un: state.surface.un[i],
                ut,
                // + 0.0 turns -0 into 0 in the CSV
                lambda_n: state.surface.stress_n[i] + 0.0,
                lambda_t: lt.map(|v| v + 0.0),
                status,
                bound: solved.bound.get(i).copied().unwrap_or(0.0),
            }
        })
        .collect();
    // The friction bound the conditions are checked against: s for Tresca,
    // nu_f |lambda_n| of the returned solution for Coulomb.
    let check_bound: Vec<f64> = if settings.friction == Friction::Coulomb {
        state
            .surface
            .stress_n
            .iter()
            .map(|l| settings.friction_coefficient * l.abs())
            .collect()
    } else {
        solved.bound.clone()
    };
    let diag = diagnostics(world, &problem, &state, &check_bound)?;
    // A direct solve of a singular matrix (a rigid motion nothing holds, e.g. a
    // sideways load on a frictionless body) does not always fail: the
    // equilibrium of the answer tells.
    let mut singular = None;
    if !problem.lin.iterative && diag.equilibrium_rel > 1e-4 {
        singular = Some(format!(
            "{} stopped after {} iterations: the answer violates equilibrium (relative residual {:.1e}): the body is not held: a rigid-body motion is free or the loads pull it off the obstacle; check the Dirichlet conditions, the loads and the obstacle",
            solved.name, solved.iterations, diag.equilibrium_rel
        ));
        solved.converged = false;
    }
    let all_rows = report::gather_rows(world, &rows);
    // Peak resident memory (VmHWM) of each rank: rank 0's, the largest, the sum.
    let hwm = peak_memory_mb();
    let mem_max = allreduce_max(world, hwm);
    let [mem_sum] = allreduce_sum(world, [hwm]);
    let time_total = t_start.elapsed().as_secs_f64();
    let mut write_error: Option<Error> = None;
    if root {
        let hertz = settings
            .reference
            .as_ref()
            .map(|r| report::compare_hertz(&all_rows, d, &n, e_star, r));
        let contact_force: f64 = all_rows.iter().map(|r| r.weight * r.lambda_n).sum();
        let mut tangential_force = vec![0.0; d];
        for r in &all_rows {
            for (c, t) in tangential_force.iter_mut().enumerate() {
                *t += r.weight * r.lambda_t[c];
            }
        }
        let count = |s: u8| all_rows.iter().filter(|r| r.status == s).count();
        let in_contact = all_rows.iter().filter(|r| r.status != 0).count();
        let (nstick, nslip) = (count(2), count(3));
        let times = Times {
            mesh: time_mesh,
            partition: time_partition,
            assembly: problem.time_assembly,
            factorization: problem.time_factorization,
            iterations: time_iterations,
            total: time_total,
        };
        print_summary(&Summary {
            settings: &settings,
            local: &local,
            ranks: size,
            ncand,
            problem: &problem,
            solved: &solved,
            inner_total: state.inner_iterations.iter().sum(),
            force: contact_force,
            tangential_force: &tangential_force,
            in_contact,
            stick: nstick,
            slip: nslip,
            hertz: hertz.as_ref(),
            times: &times,
            diag: &diag,
            mem: (hwm, mem_max, mem_sum),
            choice: choice.as_ref(),
        });
        if let Some(path) = &settings.plot_contact {
            if let Err(e) = plot_contact(path, &settings, &all_rows, d, &n, e_star) {
                write_error = write_error.or(Some(e));
            }
        }
        if let Some(path) = &settings.plot_history {
            let its: Vec<f64> = (0..state.history.len()).map(|k| k as f64).collect();
            let change: Vec<f64> = state.history.iter().map(|h| h[0]).collect();
            let residual: Vec<f64> = state.history.iter().map(|h| h[1]).collect();
            let title = format!("{}: convergence history", solved.name);
            if let Err(e) = report::plot::plot_history(
                std::path::Path::new(path),
                &title,
                &its,
                &[
                    ("relative change (4.16)/(5.6)", &change),
                    ("constraint residual ||Bu - phi||", &residual),
                ],
            ) {
                write_error =
                    write_error.or(Some(Error::BadInput(format!("option -plot_history: {e}"))));
            }
        }
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
                .int("stick_nodes", nstick)
                .int("slip_nodes", nslip)
                .int("ranks", size)
                .string("algorithm", &settings.algorithm)
                .string("paper_algorithm", solved.name)
                .string("friction", friction_name(settings.friction))
                .num("friction_coefficient", settings.friction_coefficient)
                .string("mesh", &mesh_label(&settings.mesh))
                .string("linear_solver", &problem.lin.description)
                .num("E", settings.young)
                .num("nu", settings.nu)
                .num("r", if ssn_run { settings.ssn_r } else { problem.r() })
                .num("rho", settings.ubr.rho.unwrap_or(problem.r()))
                .string(
                    "r_source",
                    match choice.as_ref().map(|c| c.source) {
                        Some(penalty::Source::Auto) => "auto",
                        _ => "option",
                    },
                )
                .opt(
                    "r_trial",
                    choice
                        .as_ref()
                        .filter(|c| c.source == penalty::Source::Auto)
                        .map(|c| c.r0),
                )
                .opt(
                    "r_estimate",
                    choice
                        .as_ref()
                        .map(|c| c.estimate)
                        .filter(|x| x.is_finite()),
                )
                .int("r_estimate_solves", choice.as_ref().map_or(0, |c| c.steps))
                .num("time_r_choice", time_r_choice)
                .string(
                    "stop",
                    if settings.ubr.stop == StopRule::Paper {
                        "paper"
                    } else {
                        "accuracy"
                    },
                )
                .num("lambda_rtol", settings.ubr.lambda_rtol)
                .opt("lambda_error_estimate", solved.error_estimate)
                .int("linear_solves", problem.lin.solves)
                .int("anderson_memory", settings.ubr.anderson)
                .int("condensed_unknowns", problem.lin.condensed_unknowns())
                .num("rtol", settings.ubr.rtol)
                .num("residual_tol", settings.ubr.residual_tol)
                .int("iterations", solved.iterations)
                .int("fixed_point_iterations", solved.fixed_point_iterations)
                .int("frictionless_iterations", solved.frictionless_iterations)
                .boolean("converged", solved.converged)
                .num("criterion", solved.last.criterion)
                .num("constraint_residual", solved.last.residual)
                .num("dual_residual", solved.last.dual)
                .opt("fixed_point_change", solved.fp_change)
                .num("contact_force", contact_force)
                .array("tangential_force", &tangential_force)
                .num("time_mesh", time_mesh)
                .num("time_partition", time_partition)
                .num("time_assembly", problem.time_assembly)
                .num("time_factorization", problem.time_factorization)
                .num("time_iterations", time_iterations)
                .num("time_total", time_total)
                .opt("pressure_error_l2", hertz.as_ref().map(|h| h.error_l2))
                .opt("pressure_error_rel", hertz.as_ref().map(|h| h.error_rel))
                .opt("peak_pressure_hertz", hertz.as_ref().map(|h| h.peak_hertz))
                .opt(
                    "contact_half_width_hertz",
                    hertz.as_ref().map(|h| h.half_width_hertz),
                )
                .num(
                    "peak_pressure",
                    all_rows.iter().map(|r| r.lambda_n).fold(0.0, f64::max),
                )
                .num(
                    "contact_half_width",
                    hertz.as_ref().map(|h| h.half_width).unwrap_or(f64::NAN),
                )
                .num("equilibrium_residual", diag.equilibrium_abs)
                .num("equilibrium_residual_rel", diag.equilibrium_rel)
                .num("equilibrium_scale", diag.load_norm)
                .num("min_lambda_n", diag.min_lambda)
                .num("max_penetration", diag.max_penetration)
                .num("max_abs_gap", diag.max_abs_gap)
                .num("complementarity", diag.complementarity)
                .num("max_friction_excess", diag.max_friction_excess)
                .num("max_bound", diag.max_bound)
                .num("max_slip", diag.max_slip)
                .num("max_stick_slip", diag.max_stick_slip)
                .num("min_slip_alignment", diag.min_slip_alignment)
                .num("matrix_mallocs", problem.matrix_mallocs)
                .num("peak_memory_rank0_mb", hwm)
                .num("peak_memory_max_mb", mem_max)
                .num("peak_memory_total_mb", mem_sum)
                .int_array("inner_iterations", &state.inner_iterations);
            if let Err(e) = report::write_atomic("-report", path, j.render().as_bytes()) {
                write_error = write_error.or(Some(e));
            }
        }
    }
    if let Some(path) = &settings.vtk {
        let rows = report::broadcast_rows(world, &all_rows);
        if let Err(e) = write_vtk(world, path, &settings, &local, &problem, &state, &rows) {
            write_error = write_error.or(Some(e));
        }
    }
    drop(guard);
    // Make a write failure on any rank collective.
    let failed = allreduce_max(world, if write_error.is_some() { 1.0 } else { 0.0 });
    if failed > 0.0 {
        return Err(write_error
            .unwrap_or_else(|| Error::BadInput("writing an output file failed on rank 0".into())));
    }
    if let Some(msg) = singular {
        return Err(Error::NotConverged(msg));
    }
    if !solved.converged {
        return Err(Error::NotConverged(solved.failure()));
    }
    Ok(())
}

/// `-plot_contact`: pressure, and with friction |lambda_t| and the bound s,
/// against the distance along the surface from the contact centre (the
/// candidate with the smallest gap, or -reference_center), with the Hertz curve.
fn plot_contact(
    path: &str,
    s: &Settings,
    rows: &[ContactRow],
    d: usize,
    n: &[f64],
    e_star: f64,
) -> Result<(), Error> {
    use report::plot::{plot_lines, Series, Style};
    let center: Vec<f64> = match s.reference.as_ref().and_then(|r| r.center.clone()) {
        Some(c) => c,
        None => rows
            .iter()
            .min_by(|a, b| a.gap.total_cmp(&b.gap))
            .map(|r| r.x[..d].to_vec())
            .unwrap_or(vec![0.0; d]),
    };
    let dist = |r: &ContactRow| {
        let dx: Vec<f64> = (0..d).map(|k| r.x[k] - center[k]).collect();
        let dn: f64 = dx.iter().zip(n).map(|(a, b)| a * b).sum();
        dx.iter()
            .zip(n)
            .map(|(a, b)| (a - dn * b).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by(|&a, &b| dist(&rows[a]).total_cmp(&dist(&rows[b])));
    let x: Vec<f64> = order.iter().map(|&i| dist(&rows[i])).collect();
    let p: Vec<f64> = order.iter().map(|&i| rows[i].lambda_n).collect();
    let lt: Vec<f64> = order
        .iter()
        .map(|&i| rows[i].lambda_t.iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    let bound: Vec<f64> = order.iter().map(|&i| rows[i].bound).collect();
    let mut series = vec![Series {
        label: "contact pressure lambda_n",
        x: &x,
        y: &p,
        style: Style::Points,
    }];
    let friction = s.friction != Friction::None;
    if friction {
        series.push(Series {
            label: "|tangential traction lambda_t|",
            x: &x,
            y: &lt,
            style: Style::Points,
        });
        series.push(Series {
            label: "friction bound s",
            x: &x,
            y: &bound,
            style: Style::Line,
        });
    }
    let (hx, hy): (Vec<f64>, Vec<f64>) = match &s.reference {
        Some(r) => {
            let xmax = x.last().copied().unwrap_or(0.0);
            (0..=400)
                .map(|k| {
                    let xi = xmax * k as f64 / 400.0;
                    (
                        xi,
                        report::hertz_pressure(d, r.force, r.radius, e_star, xi).0,
                    )
                })
                .unzip()
        }
        None => (Vec::new(), Vec::new()),
    };
    if s.reference.is_some() {
        series.push(Series {
            label: "Hertz pressure",
            x: &hx,
            y: &hy,
            style: Style::DashedLine,
        });
    }
    let title = format!(
        "Contact stresses ({}), {} candidates",
        friction_name(s.friction),
        rows.len()
    );
    plot_lines(
        std::path::Path::new(path),
        &title,
        "distance from the contact centre, orthogonal to n",
        "stress",
        &series,
        false,
    )
    .map_err(|e| Error::BadInput(format!("option -plot_contact: {e}")))
}

/// `-vtk PATH.pvtu`: every rank writes the cells it owns (those whose smallest
/// global node it owns) with all their nodes; rank 0 writes the index.
fn write_vtk<C: Communicator>(
    world: &C,
    path: &str,
    s: &Settings,
    local: &distribute::LocalMesh,
    p: &Problem,
    st: &UbrState,
    rows: &[ContactRow],
) -> Result<(), Error> {
    use report::vtk::{self, Field, Piece};
    let d = local.dim;
    let k = d + 1;
    let rank = world.rank() as usize;
    let bad_path =
        |e: std::io::Error| Error::BadInput(format!("option -vtk: cannot write '{path}': {e}"));
    let target = std::path::Path::new(path);
    let stem_path = target.with_extension("");
    let stem = stem_path
        .file_name()
        .map(|x| x.to_string_lossy().into_owned())
        .unwrap_or_else(|| "ubr".into());
    let dir = stem_path
        .parent()
        .filter(|x| !x.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."))
        .to_path_buf();
    let pvtu = dir.join(format!("{stem}.pvtu"));
    // Displacement at every local node (owned and ghost).
    let idx: Vec<sys::PetscInt> = local
        .node_global
        .iter()
        .flat_map(|&g| (0..d).map(move |c| (g * d + c) as sys::PetscInt))
        .collect();
    let gather = petsc::Gather::new(&st.u, &idx)?;
    gather.gather(&st.u)?;
    let u_local: Vec<f64> = gather.local.read(|v| v.to_vec())?;
    // Cells this rank writes.
    let mine: Vec<usize> = (0..local.num_cells())
        .filter(|&c| {
            let gmin = local
                .cells
                .get(c)
                .iter()
                .map(|&v| local.node_global[v])
                .min()
                .unwrap_or(0);
            gmin >= local.owned_start && gmin < local.owned_start + local.owned_count
        })
        .collect();
    let mut cells = Vec::with_capacity(mine.len() * k);
    let mut offsets = Vec::with_capacity(mine.len());
    let mut stress = Vec::with_capacity(mine.len() * 9);
    let mut von_mises = Vec::with_capacity(mine.len());
    let mut xs = Vec::with_capacity(8 * d);
    let mut us = Vec::with_capacity(8 * d);
    for &c in &mine {
        let cell = local.cells.get(c);
        xs.clear();
        us.clear();
        for &v in cell {
            xs.extend_from_slice(local.x(v));
            us.extend_from_slice(&u_local[v * d..(v + 1) * d]);
        }
        cells.extend_from_slice(cell);
        offsets.push(cells.len());
        let (sig, vm) = crate::fem::stress::cell_stress(d, &xs, &us, s.young, s.nu, s.plane_stress);
        stress.extend_from_slice(&sig);
        von_mises.push(vm);
    }
    let ranks = vec![rank as i32; mine.len()];
    // Contact fields at the nodes (-1 status: not a candidate).
    let by_tag: std::collections::HashMap<u64, &ContactRow> =
        rows.iter().map(|r| (r.node, r)).collect();
    let npts = local.num_local_nodes();
    let mut pressure = vec![0.0; npts];
    let mut traction = vec![0.0; npts * 3];
    let mut gap = vec![0.0; npts];
    let mut status = vec![-1i32; npts];
    let mut disp = vec![0.0; npts * 3];
    for v in 0..npts {
        disp[v * 3..v * 3 + d].copy_from_slice(&u_local[v * d..(v + 1) * d]);
        if let Some(r) = by_tag.get(&local.node_tag[v]) {
            pressure[v] = r.lambda_n;
            traction[v * 3..v * 3 + 3].copy_from_slice(&r.lambda_t);
            gap[v] = r.gap;
            status[v] = r.status as i32;
        }
    }
    let _ = p;
    let piece = Piece {
        dim: d,
        coords: &local.coords,
        cells: &cells,
        offsets: &offsets,
        point_data: vec![
            Field::Vector("displacement", &disp),
            Field::Scalar("contact_pressure", &pressure),
            Field::Vector("tangential_traction", &traction),
            Field::Scalar("gap", &gap),
            Field::Int("contact_status", &status),
        ],
        cell_data: vec![
            Field::Tensor("stress", &stress),
            Field::Scalar("von_mises", &von_mises),
            Field::Int("rank", &ranks),
        ],
    };
    let name = vtk::piece_file_name(&stem, rank);
    vtk::write_vtu(&dir.join(&name), &piece).map_err(bad_path)?;
    if rank == 0 {
        let names: Vec<String> = (0..world.size() as usize)
            .map(|r| vtk::piece_file_name(&stem, r))
            .collect();
        vtk::write_pvtu(&pvtu, &names, &piece.point_fields(), &piece.cell_fields())
            .map_err(bad_path)?;
    }
    Ok(())
}

/// This process's peak resident memory in MiB (VmHWM from /proc/self/status; 0 if unknown).
fn peak_memory_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map(|kb| kb / 1024.0)
        .unwrap_or(0.0)
}

/// The comparators, whose iterations have no UBR stopping test.
fn ssn_like(name: &str) -> bool {
    name == "SSN-C" || name == "SNES-VI"
}

fn friction_name(f: Friction) -> &'static str {
    match f {
        Friction::None => "none",
        Friction::Tresca => "tresca",
        Friction::Coulomb => "coulomb",
    }
}

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
    fn failure(&self) -> String {
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
}

/// The Tresca bound from `-tresca_bound hertz`: nu_f times the Hertz pressure
/// at each owned candidate, centred as the reference says (default: the
/// candidate with the smallest gap over all ranks).
fn hertz_bound<C: Communicator>(
    world: &C,
    local: &distribute::LocalMesh,
    cs: &ContactSet,
    reference: &options::HertzReference,
    nu_f: f64,
    e_star: f64,
) -> Vec<f64> {
    let d = local.dim;
    let center = match &reference.center {
        Some(c) => c.clone(),
        None => {
            // (gap, x, y, z) of the local minimum, gathered everywhere.
            let mut mine: [f64; 4] = [f64::INFINITY, 0.0, 0.0, 0.0];
            for i in 0..cs.len() {
                if cs.g[i] < mine[0] {
                    mine[0] = cs.g[i];
                    mine[1..1 + d].copy_from_slice(local.x(cs.node[i]));
                }
            }
            let mut all = vec![0.0f64; 4 * world.size() as usize];
            world.all_gather_into(&mine[..], &mut all[..]);
            let best = all
                .chunks(4)
                .min_by(|a, b| a[0].total_cmp(&b[0]))
                .map(|c| c[1..1 + d].to_vec())
                .unwrap_or(vec![0.0; d]);
            best
        }
    };
    (0..cs.len())
        .map(|i| {
            let x = local.x(cs.node[i]);
            let dx: Vec<f64> = (0..d).map(|k| x[k] - center[k]).collect();
            let dn: f64 = dx.iter().zip(&cs.n).map(|(a, b)| a * b).sum();
            let dist = dx
                .iter()
                .zip(&cs.n)
                .map(|(a, b)| (a - dn * b).powi(2))
                .sum::<f64>()
                .sqrt();
            nu_f * report::hertz_pressure(d, reference.force, reference.radius, e_star, dist).0
        })
        .collect()
}

/// The bound s^0 from -tresca_bound (None: a frictionless solve first for
/// Tresca, or zero for CF-FP).
#[allow(clippy::too_many_arguments)]
fn explicit_bound<C: Communicator>(
    world: &C,
    local: &distribute::LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    state: &mut UbrState,
    solved: &mut Solved,
    ctl: &ubr::UbrControl,
    events: &Events,
    e_star: f64,
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
            e_star,
        )),
        Some(TrescaBound::Frictionless) => {
            // A frictionless solve with the same matrix: UBR-TF with s = 0.
            let zero = vec![0.0; nc];
            let run = ubr::ubr(world, problem, state, Some(&zero), ctl, events)?;
            solved.frictionless_iterations = run.iterations;
            if !run.converged {
                return Err(Error::NotConverged(format!(
                    "the frictionless solve behind -tresca_bound frictionless did not converge: {}",
                    run.failure.unwrap_or_default()
                )));
            }
            let s = state
                .surface
                .stress_n
                .iter()
                .map(|l| nu_f * l.abs())
                .collect();
            state.reset()?;
            Some(s)
        }
        None => None,
    })
}

/// Runs the algorithm the options ask for.
fn solve<C: Communicator>(
    world: &C,
    local: &distribute::LocalMesh,
    settings: &Settings,
    problem: &mut Problem,
    events: &Events,
    e_star: f64,
) -> Result<(UbrState, Solved), Error> {
    let u = &settings.ubr;
    let ctl = ubr::UbrControl {
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
    };
    let nc = problem.contact.len();
    let nu_f = settings.friction_coefficient;
    let mut state = UbrState::new(problem)?;
    let mut solved = Solved {
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
    };
    if settings.algorithm == "snesvi" {
        let run = snesvi::snes_vi(world, problem, &mut state, &settings.ssn_initial_shift)?;
        solved.name = "SNES-VI";
        solved.iterations = run.iterations;
        solved.converged = run.converged;
        solved.last = run;
        return Ok((state, solved));
    }
    if settings.algorithm == "ssn" {
        let ctl = ssn::SsnControl {
            r: settings.ssn_r,
            max_it: settings.ssn_max_it,
            initial_shift: settings.ssn_initial_shift.clone(),
            monitor: u.monitor,
        };
        let (run, _) = ssn::ssn_c(world, problem, local, &mut state, &ctl, events)?;
        solved.name = "SSN-C";
        solved.iterations = run.iterations;
        solved.converged = run.converged;
        solved.last = run;
        return Ok((state, solved));
    }
    let accuracy = u.stop == StopRule::Accuracy;
    match settings.friction {
        Friction::None => {
            let run = ubr::ubr(world, problem, &mut state, None, &ctl, events)?;
            solved.iterations = run.iterations;
            solved.converged = run.converged;
            solved.failure = run.failure.clone();
            solved.error_estimate = accuracy.then_some(run.error_estimate);
            solved.last = run;
        }
        Friction::Tresca => {
            solved.name = "UBR-TF";
            let bound = explicit_bound(
                world,
                local,
                settings,
                problem,
                &mut state,
                &mut solved,
                &ctl,
                events,
                e_star,
            )?;
            let s = match bound {
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
                    let s = state
                        .surface
                        .stress_n
                        .iter()
                        .map(|l| nu_f * l.abs())
                        .collect();
                    state.reset()?;
                    s
                }
            };
            let run = ubr::ubr(world, problem, &mut state, Some(&s), &ctl, events)?;
            solved.iterations = run.iterations;
            solved.converged = run.converged;
            solved.failure = run.failure.clone();
            solved.error_estimate = accuracy.then_some(run.error_estimate);
            solved.last = run;
            solved.bound = s;
        }
        Friction::Coulomb => {
            solved.name = "CF-FP";
            let s0 = explicit_bound(
                world,
                local,
                settings,
                problem,
                &mut state,
                &mut solved,
                &ctl,
                events,
                e_star,
            )?
            .unwrap_or_else(|| vec![0.0; nc]);
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
    /// `||K u - f + B^T W lambda||` on the free dofs, and relative to
    /// `max(||f||, ||B^T W lambda||)` (the load, or the contact forces when
    /// the body is loaded by a prescribed displacement only).
    pub equilibrium_abs: f64,
    pub equilibrium_rel: f64,
    pub load_norm: f64,
    pub min_lambda: f64,
    /// `max (u_n - g)` over the candidates.
    pub max_penetration: f64,
    pub max_abs_gap: f64,
    /// `sum w lambda_n (g - u_n)`.
    pub complementarity: f64,
    /// `max (|lambda_t| - s)` over the candidates (0 without friction), and max s.
    pub max_friction_excess: f64,
    pub max_bound: f64,
    /// Largest tangential slip |u_t| over all candidates, and over the sticking
    /// ones (s > 1e-6 max s and `|lambda_t + r u_t| <= s` at the last projection).
    pub max_slip: f64,
    pub max_stick_slip: f64,
    /// Smallest cosine between u_t and lambda_t over the sliding candidates
    /// whose slip exceeds 1e-6 of the largest (1: same direction, (2.9)).
    pub min_slip_alignment: f64,
}

#[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
fn diagnostics<C: Communicator>(
    world: &C,
    p: &Problem,
    st: &UbrState,
    bound: &[f64],
) -> Result<Diagnostics, Error> {
    let d = p.dim;
    let cs = &p.contact;
    let au = p.lin.rhs0.duplicate()?;
    p.lin.matrix.mult(&st.u, &au)?;
    let (eq2, f2) = au.write(|a| {
        p.lin.rhs0.read(|b| {
            p.load.read(|f| {
                for (ai, bi) in a.iter_mut().zip(b) {
                    *ai -= bi;
                }
                for i in 0..cs.len() {
                    let base = cs.node[i] * d;
                    let w = cs.w[i];
                    for c in 0..d {
                        // remove r B^T W B u, add B^T W lambda
                        let (bu, lam) = if p.tangential {
                            (
                                st.surface.un[i] * cs.n[c] + st.surface.ut[i * d + c],
                                st.surface.stress_n[i] * cs.n[c] + st.surface.stress_t[i * d + c],
                            )
                        } else {
                            (st.surface.un[i] * cs.n[c], st.surface.stress_n[i] * cs.n[c])
                        };
                        let r = if p.terms == ContactTerms::None {
                            0.0
                        } else {
                            p.lin.r_assembled()
                        };
                        a[base + c] += w * (lam - r * bu);
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
                // The scale: the load, or the contact forces when the body is
                // loaded through a prescribed displacement only.
                let mut c2 = 0.0;
                for i in 0..cs.len() {
                    let w = cs.w[i];
                    c2 += (w * st.surface.stress_n[i]).powi(2);
                    if p.tangential {
                        for c in 0..d {
                            c2 += (w * st.surface.stress_t[i * d + c]).powi(2);
                        }
                    }
                }
                // Loaded by prescribed displacements only: their lifting load.
                let mut l2 = 0.0;
                for (i, bi) in b.iter().enumerate() {
                    if !p.is_dirichlet[i] {
                        l2 += bi * bi;
                    }
                }
                (eq2, f2.max(c2).max(l2))
            })
        })
    })???;
    let mut min_lambda = f64::INFINITY;
    let mut max_pen = f64::NEG_INFINITY;
    let mut max_gap = 0.0f64;
    let mut compl = 0.0;
    let mut excess = f64::NEG_INFINITY;
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    // Friction laws are checked where the bound is meaningful: s above 1e-6 of
    // the largest (an open node's Coulomb bound is nu_f times round-off).
    let max_bound = allreduce_max(world, bound.iter().fold(0.0, |a: f64, &b| a.max(b)));
    let meaningful = |i: usize| !bound.is_empty() && bound[i] > 1e-6 * max_bound;
    let mut max_slip = 0.0f64;
    let mut max_stick_slip = 0.0f64;
    for i in 0..cs.len() {
        let slip = norm(&st.surface.ut[i * d..(i + 1) * d]);
        max_slip = max_slip.max(slip);
        if p.tangential && !st.surface.slip[i] && meaningful(i) {
            max_stick_slip = max_stick_slip.max(slip);
        }
    }
    let max_slip = allreduce_max(world, max_slip);
    let max_stick_slip = allreduce_max(world, max_stick_slip);
    let mut min_cos = 1.0f64;
    if p.tangential {
        for i in 0..cs.len() {
            let ut = &st.surface.ut[i * d..(i + 1) * d];
            let lt = &st.surface.stress_t[i * d..(i + 1) * d];
            let (nu, nl) = (norm(ut), norm(lt));
            if st.surface.slip[i] && meaningful(i) && nu > 1e-6 * max_slip && nl > 0.0 {
                let dot: f64 = ut.iter().zip(lt).map(|(a, b)| a * b).sum();
                min_cos = min_cos.min(dot / (nu * nl));
            }
        }
    }
    let min_slip_alignment = -allreduce_max(world, -min_cos);
    for i in 0..cs.len() {
        min_lambda = min_lambda.min(st.surface.stress_n[i]);
        max_pen = max_pen.max(st.surface.un[i] - cs.g[i]);
        max_gap = max_gap.max(cs.g[i].abs());
        compl += cs.w[i] * st.surface.stress_n[i] * (cs.g[i] - st.surface.un[i]);
        if !bound.is_empty() {
            let lt = st.surface.stress_t[i * d..(i + 1) * d]
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt();
            excess = excess.max(lt - bound[i]);
        }
    }
    let [eq2, f2, compl] = allreduce_sum(world, [eq2, f2, compl]);
    let min_lambda = -allreduce_max(world, -min_lambda);
    let max_penetration = allreduce_max(world, max_pen);
    let max_abs_gap = allreduce_max(world, max_gap);
    let max_friction_excess = if p.tangential {
        allreduce_max(world, excess)
    } else {
        0.0
    };
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
        max_friction_excess,
        max_bound,
        max_slip,
        max_stick_slip,
        min_slip_alignment,
    })
}

struct Summary<'a> {
    settings: &'a Settings,
    local: &'a distribute::LocalMesh,
    ranks: usize,
    ncand: usize,
    problem: &'a Problem,
    solved: &'a Solved,
    inner_total: usize,
    force: f64,
    tangential_force: &'a [f64],
    in_contact: usize,
    stick: usize,
    slip: usize,
    hertz: Option<&'a report::HertzComparison>,
    times: &'a Times,
    diag: &'a Diagnostics,
    /// Peak memory: rank 0, largest rank, all ranks (MiB).
    mem: (f64, f64, f64),
    choice: Option<&'a penalty::Choice>,
}

fn print_summary(m: &Summary) {
    let s = m.settings;
    let local = m.local;
    let res = m.solved;
    let t = m.times;
    let diag = m.diag;
    let cells = &local.cell_kinds;
    let what = match s.friction {
        Friction::None => "frictionless",
        Friction::Tresca => "Tresca friction",
        Friction::Coulomb => "Coulomb friction",
    };
    println!(
        "ubr-petsc: Algorithm {} ({what}), {} rank{}",
        res.name,
        m.ranks,
        if m.ranks == 1 { "" } else { "s" }
    );
    println!("  mesh            {}", mesh_label(&s.mesh));
    println!(
        "                  {} nodes, {} {cells}, {} contact candidates",
        local.global_nodes, local.global_cells, m.ncand
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
    if s.friction != Friction::None {
        println!("  friction        nu_f = {}", s.friction_coefficient);
    }
    println!("  linear solver   {}", m.problem.lin.description);
    if res.name == "SNES-VI" {
        println!(
            "  iterations      {} Newton iterations of PETSc's vinewtonrsls ({} linear)",
            res.iterations, m.inner_total
        );
    } else if res.name == "SSN-C" {
        println!(
            "  r (SSN-C)       {} (r/E = {}), initial guess ({})",
            s.ssn_r,
            s.ssn_r / s.young,
            if s.ssn_initial_shift.is_empty() {
                "0".to_string()
            } else {
                s.ssn_initial_shift
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(",")
            }
        );
        println!(
            "  iterations      {}, {} (one factorization each)",
            res.iterations,
            if res.converged {
                "converged: the active set repeated"
            } else {
                "NOT converged"
            }
        );
    } else {
        let r = m.problem.r();
        let source = match m.choice {
            Some(c) if c.source == penalty::Source::Auto => {
                let moved = if c.r == c.r0 {
                    "kept: within 3x of the estimate"
                } else if c.refactorized {
                    "refactorized"
                } else {
                    "moved without refactorization"
                };
                if c.estimate.is_finite() {
                    format!(
                        "auto: spectral estimate {:.4e} from {} Lanczos solves, trial {:.4e} {moved}",
                        c.estimate, c.steps, c.r0
                    )
                } else {
                    format!(
                        "auto: trial {:.4e} (too few candidates for an estimate)",
                        c.r0
                    )
                }
            }
            _ => "option -ubr_r".to_string(),
        };
        println!(
            "  r               {:.6e} (r/E = {:.4}; {source})",
            r,
            r / s.young
        );
        if let Some(rho) = s.ubr.rho {
            println!("  rho             {rho} (-ubr_rho)");
        }
        if s.ubr.anderson > 0 {
            println!(
                "  Anderson        memory {} (safeguarded type II on z = lambda + r B u): {} of {} evaluations extrapolated, {} rejected",
                s.ubr.anderson,
                res.last.anderson_steps,
                res.last.iterations,
                res.last.anderson_rejected
            );
        } else {
            println!("  Anderson        off (-ubr_anderson 0: the paper's plain iteration)");
        }
    }
    if res.frictionless_iterations > 0 {
        println!(
            "  frictionless    {} UBR iterations for the bound s = nu_f lambda_c",
            res.frictionless_iterations
        );
    }
    if res.fixed_point_iterations > 0 {
        println!(
            "  fixed point     {} iterations, {} Tresca iterations in total, {} (change of s {:.3e}, target {:.1e})",
            res.fixed_point_iterations,
            res.iterations,
            if res.converged { "converged" } else { "NOT converged" },
            res.fp_change.unwrap_or(f64::NAN),
            s.ubr.fp_rtol
        );
    }
    if !ssn_like(res.name) {
        let verdict = if res.converged {
            "converged"
        } else {
            "NOT converged"
        };
        if s.ubr.stop == StopRule::Paper {
            println!(
                "  iterations      {}, {verdict} (paper's test, last run: rel. change (4.16) {:.3e}, target {:.1e}; residual {:.3e}, target {:.1e})",
                res.iterations, res.last.criterion, s.ubr.rtol, res.last.residual, s.ubr.residual_tol
            );
        } else {
            println!(
                "  iterations      {}, {verdict}: estimated error of lambda {:.3e} (relative, max norm; target {:.1e}); the paper's (4.16) {:.3e}",
                res.iterations,
                res.error_estimate.unwrap_or(f64::NAN),
                s.ubr.lambda_rtol,
                res.last.criterion
            );
        }
        println!(
            "  linear solves   {} (r choice included)",
            m.problem.lin.solves
        );
    }
    if m.problem.lin.iterative {
        println!("  inner its       {} in total", m.inner_total);
    }
    if s.friction != Friction::None {
        println!(
            "  contact         {} nodes in contact ({} stick, {} slip), total contact force {:.10e}",
            m.in_contact, m.stick, m.slip, m.force
        );
        println!(
            "                  tangential force ({})",
            m.tangential_force
                .iter()
                .map(|v| format!("{v:.6e}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    } else {
        println!(
            "  contact         {} nodes in contact, total contact force {:.10e}",
            m.in_contact, m.force
        );
    }
    println!(
        "  optimality      equilibrium {:.2e} (rel.), min lambda_n {:.3e}, max u_n - g {:.3e}, complementarity {:.3e}",
        diag.equilibrium_rel, diag.min_lambda, diag.max_penetration, diag.complementarity
    );
    if s.friction != Friction::None {
        println!(
            "                  max (|lambda_t| - s) {:.3e}, slip at stick nodes {:.3e} (max slip {:.3e}), min cos(u_t, lambda_t) at slip nodes {:.12}",
            diag.max_friction_excess, diag.max_stick_slip, diag.max_slip, diag.min_slip_alignment
        );
    }
    if let Some(h) = m.hertz {
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
    println!(
        "  memory (MiB)    peak {:.0} on rank 0, {:.0} on the largest rank, {:.0} in all",
        m.mem.0, m.mem.1, m.mem.2
    );
}
