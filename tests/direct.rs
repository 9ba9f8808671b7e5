//! The direct back-end on MUMPS itself (issue 13): its solves equal PETSc's
//! KSP path, condensed iterates equal full-solve iterates, the rank count
//! changes nothing, and a singular operator ends with a message, never a
//! crash or a hang.
mod common;
use common::*;

/// The paper's iteration at a fixed r and tolerance: a linear contraction
/// whose iterates round-off cannot move far.
fn hertz_plain(extra: &[&'static str]) -> Vec<&'static str> {
    let mut v = vec![
        "-options_file",
        "options/hertz",
        "-mesh",
        "meshes/hertz_1692.msh",
        "-ubr_r",
        "2000",
        "-ubr_anderson",
        "0",
        "-ubr_stop",
        "paper",
        "-ubr_rtol",
        "1e-8",
    ];
    v.extend_from_slice(extra);
    v
}

fn block_plain(extra: &[&'static str]) -> Vec<&'static str> {
    let mut v = vec![
        "-options_file",
        "options/block3d",
        "-mesh",
        "meshes/block3d_739.msh",
        "-ubr_r",
        "4e6",
        "-ubr_anderson",
        "0",
        "-ubr_stop",
        "paper",
        "-ubr_rtol",
        "1e-8",
    ];
    v.extend_from_slice(extra);
    v
}

/// MUMPS called directly (full solves) against PETSc's MUMPS interface:
/// the same iterations and pressures to 1e-10, on 1, 2 and 3 ranks, in 2D
/// (AMD ordering, and METIS when asked for) and 3D (METIS).
#[test]
fn direct_solves_equal_petsc_ksp() {
    for (name, scene) in [
        (
            "hertz",
            hertz_plain as fn(&[&'static str]) -> Vec<&'static str>,
        ),
        ("block", block_plain),
    ] {
        let (_, rk, k) = solve_rows(
            &format!("{name}-ksp"),
            1,
            &scene(&["-ubr_mumps_direct", "0", "-ubr_condense_max", "0"]),
        );
        assert!(rk
            .linear_solver
            .as_str()
            .contains("preonly + cholesky (mumps)"));
        // One rank: 3D orders by METIS; this 2D scene is small enough for
        // AMD, and takes METIS when asked for. Several ranks: every rank
        // orders its part (the parallel nested dissection).
        let default = if name == "block" {
            "METIS nested dissection"
        } else {
            "MUMPS' AMD"
        };
        let parallel = "nested dissection in parallel";
        let none: &[&str] = &[];
        let mut runs = vec![(1, none, default), (2, none, parallel), (3, none, parallel)];
        if name == "hertz" {
            runs.push((2, &["-mat_mumps_icntl_7", "1"], "METIS nested dissection"));
        }
        for (ranks, extra, ordering) in runs {
            let mut args = vec!["-ubr_condense_max", "0"];
            args.extend_from_slice(extra);
            let (run, rd, dm) = solve_rows(
                &format!("{name}-direct-{ranks}-{}", extra.len()),
                ranks,
                &scene(&args),
            );
            let ordering = format!("MUMPS Cholesky, called directly ({ordering}");
            assert!(run.stdout.contains(&ordering), "{}", run.stdout);
            assert_eq!(rd.iterations, rk.iterations, "{name} -n {ranks}");
            let g = max_pressure_gap(&dm, &k);
            assert!(
                g <= 1e-10,
                "{name} -n {ranks}: direct and KSP differ by {g:.2e}"
            );
        }
    }
}

/// Condensed solves (the Schur complement on rank 0) against full solves:
/// the same iterates, on 1, 2 and 3 ranks; frictionless (the normal axis
/// alone in the Schur complement) and with Coulomb friction (every
/// component), and at the defaults, whose automatic r the condensed
/// back-end reaches by a dense shift of the Schur complement (the full run
/// is given that r).
#[test]
fn condensed_iterates_equal_full_ones() {
    for (name, args) in [
        ("hertz", hertz_plain(&[])),
        (
            "coulomb",
            vec![
                "-options_file",
                "options/hertz-coulomb-paper",
                "-mesh",
                "meshes/hertz_1692.msh",
            ],
        ),
        ("defaults", vec!["-options_file", "options/hertz"]),
        ("block", block_plain(&["-ubr_condense_max", "1000"])),
    ] {
        let mut reference: Option<(Report, Vec<Row>)> = None;
        for ranks in [1, 2, 3] {
            let (run, rc, c) = solve_rows(&format!("{name}-cond-{ranks}"), ranks, &args);
            assert!(rc.condensed_unknowns > 0.0, "{name}: {}", run.stdout);
            if reference.is_none() {
                let r = format!("{:e}", rc.r);
                let mut full = args.clone();
                full.extend_from_slice(&["-ubr_condense_max", "0", "-ubr_r", &r]);
                let (_, rf, f) = solve_rows(&format!("{name}-full"), 1, &full);
                assert_eq!(rf.condensed_unknowns, 0.0);
                assert_eq!(rf.r, rc.r);
                reference = Some((rf, f));
            }
            let (rf, f) = reference.as_ref().unwrap();
            assert_eq!(rc.iterations, rf.iterations, "{name} -n {ranks}");
            let g = max_pressure_gap(&c, f);
            assert!(
                g <= 1e-9,
                "{name} -n {ranks}: condensed and full differ by {g:.2e}"
            );
            // u_t comes from the whole displacement at the end (condensed
            // on the normal components alone: the expansion of MUMPS' kept
            // forward elimination from u_C, Direct::expand).
            for (x, y) in c.iter().zip(f) {
                for k in 0..3 {
                    assert!(
                        (x.ut[k] - y.ut[k]).abs() <= 1e-9 * (1.0 + y.ut[k].abs()),
                        "{name} -n {ranks}: u_t of node {}",
                        x.node
                    );
                }
            }
        }
    }
}

/// Two squares joined at one node, the lower one clamped: the upper one can
/// turn about the joint without deforming (a mechanism the rigid motions of
/// the whole body do not show). The factorization meets a singular
/// operator: exit 3 with the reason, never a crash or a hang.
#[test]
fn a_mechanism_is_a_message() {
    let dir = scratch("hinge");
    let mesh = dir.join("hinge.msh");
    std::fs::write(
        &mesh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"fixed\"\n1 2 \"contact\"\n1 4 \"load\"\n2 3 \"body\"\n$EndPhysicalNames\n\
$Nodes\n7\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 1 0\n6 2 2 0\n7 1 2 0\n$EndNodes\n\
$Elements\n7\n1 1 2 1 1 1 2\n2 1 2 2 2 4 3\n3 1 2 4 4 6 7\n4 2 2 3 3 1 2 3\n5 2 2 3 3 1 3 4\n6 2 2 3 3 3 5 6\n7 2 2 3 3 3 6 7\n$EndElements\n",
    )
    .unwrap();
    let m = mesh.to_str().unwrap();
    for ranks in [1, 2] {
        let run = mpirun(
            ranks,
            &[
                "-mesh",
                m,
                "-E",
                "100",
                "-nu",
                "0.3",
                "-dirichlet_fixed",
                "ux=0,uy=0",
                "-traction_load",
                "1,0",
                "-contact_surface",
                "contact",
                "-contact_direction",
                "0,1",
                "-obstacle",
                "plane",
                "-obstacle_point",
                "0,1.1",
            ],
        );
        // The hinge is not found before the solve (the scene analysis sees
        // rigid motions of the whole body only): the run ends not converged
        // (exit 3) on its equilibrium check, which names the cause.
        assert_eq!(run.status, Some(3), "-n {ranks}: {}", run.context());
        let line = run
            .stderr
            .lines()
            .find(|l| l.starts_with("not converged:"))
            .unwrap_or_else(|| panic!("-n {ranks}: {}", run.context()));
        assert!(
            line.contains("violates equilibrium") && line.contains("the body is not held"),
            "-n {ranks}: {line}"
        );
        assert!(run.seconds < 60.0);
    }
}

/// `-mat_mumps_cntl_N` reaches MUMPS called directly, as `-mat_mumps_icntl_N`
/// does: MUMPS' own statistics (ICNTL(3) = 6, ICNTL(4) = 2) show the BLR
/// dropping parameter CNTL(7) given; the answer stays the default one to
/// that accuracy; a value that is not a number is exit 2 naming the option.
#[test]
fn mumps_cntl_options_reach_mumps() {
    let (_, _, reference) = solve_rows("cntl-default", 2, &block_plain(&[]));
    let (run, _, blr) = solve_rows(
        "cntl-blr",
        2,
        &block_plain(&[
            "-mat_mumps_icntl_35",
            "2",
            "-mat_mumps_cntl_7",
            "1e-9",
            "-mat_mumps_icntl_3",
            "6",
            "-mat_mumps_icntl_4",
            "2",
        ]),
    );
    let line = run
        .stdout
        .lines()
        .find(|l| l.contains("CNTL(7)"))
        .unwrap_or_else(|| panic!("no CNTL(7) in MUMPS' statistics:\n{}", run.stdout));
    assert!(line.contains("1.0E-09"), "{line}");
    let g = max_pressure_gap(&blr, &reference);
    assert!(g <= 1e-6, "BLR at 1e-9 moved the pressures by {g:.2e}");
    let bad = mpirun(2, &block_plain(&["-mat_mumps_cntl_7", "abc"]));
    assert_eq!(bad.status, Some(2), "{}", bad.stderr);
    assert!(
        bad.stderr.contains("-mat_mumps_cntl_7") && bad.stderr.contains("abc"),
        "{}",
        bad.stderr
    );
}

/// MUMPS' input leaves out the zeroed Dirichlet couplings (exact zeros
/// between two nodes); a change of r refactorizes with the same entries.
/// On a scene whose automatic r moves 3.9x from the trial (the full
/// back-end refactorizes), with Dirichlet data on its top: the direct
/// back-end's r, iterations and pressures are PETSc's KSP path's (which
/// factorizes the whole pattern), on 1, 2 and 3 ranks. (What it saves:
/// bench/README.md, block3d_17887 5.45e10 -> 4.78e10 flops.)
#[test]
fn refactorization_of_the_trimmed_input() {
    let (dir, msh) = gmsh_2d("trimmed-mesh", "tests/scenes/slab2d_ball_pen.geo");
    let base = [
        "-options_file",
        "tests/scenes/slab2d_ball_pen.opts",
        "-mesh",
        &msh,
        "-ubr_condense_max",
        "0",
    ];
    let mut ksp = base.to_vec();
    ksp.extend_from_slice(&["-ubr_mumps_direct", "0"]);
    let (run_k, rk, k) = solve_rows("trimmed-ksp", 1, &ksp);
    assert!(run_k.stdout.contains("refactorized"), "{}", run_k.stdout);
    for ranks in [1, 2, 3] {
        let (run, rd, dm) = solve_rows(&format!("trimmed-direct-{ranks}"), ranks, &base);
        assert!(
            run.stdout.contains("MUMPS Cholesky, called directly")
                && run.stdout.contains("refactorized"),
            "{}",
            run.stdout
        );
        assert_eq!(rd.iterations, rk.iterations, "-n {ranks}");
        let (r_d, r_k) = (rd.r, rk.r);
        assert!(
            (r_d - r_k).abs() <= 1e-8 * r_k,
            "-n {ranks}: r {r_d} against {r_k}"
        );
        let g = max_pressure_gap(&dm, &k);
        assert!(g <= 1e-10, "-n {ranks}: direct and KSP differ by {g:.2e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The 2D Hertz scene of 1692 nodes at a tight tolerance.
const HERTZ_TIGHT: &[&str] = &[
    "-options_file",
    "options/hertz",
    "-mesh",
    "meshes/hertz_1692.msh",
    "-ubr_lambda_rtol",
    "1e-10",
];

/// What the summary says of a Schur complement on ScaLAPACK's grid.
const ON_THE_GRID: &str = "factorized and solved there by ScaLAPACK";

/// `-ubr_schur_distributed 1` (issue "Scaling studies", item 2): MUMPS
/// returns the Schur complement on a 1 x P grid, and ScaLAPACK factorizes
/// it and solves with it there (the changes of r included: the Coulomb
/// scene's automatic r moves). The same contact stresses as the
/// centralized Schur complement (`-ubr_schur_distributed 0`) to round-off,
/// on 2, 3 and 4 ranks, 2D and 3D, frictionless, Coulomb and Tresca (whose
/// whole solves condense several columns at once), and the summary says
/// which layout ran.
#[test]
fn distributed_schur_equals_centralized() {
    let scenes: [&[&str]; 4] = [
        HERTZ_TIGHT,
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_739.msh",
            "-ubr_lambda_rtol",
            "1e-10",
        ],
        &[
            "-options_file",
            "options/block3d-coulomb",
            "-mesh",
            "meshes/block3d_739.msh",
            "-ubr_lambda_rtol",
            "1e-10",
        ],
        &[
            "-options_file",
            "options/block3d-tresca",
            "-mesh",
            "meshes/block3d_739.msh",
            "-ubr_lambda_rtol",
            "1e-10",
        ],
    ];
    for (k, scene) in scenes.iter().enumerate() {
        for ranks in [2, 3, 4] {
            let mut central_args = scene.to_vec();
            central_args.extend_from_slice(&["-ubr_schur_distributed", "0"]);
            let (crun, _, central) =
                solve_rows(&format!("schur_c{k}_{ranks}"), ranks, &central_args);
            assert!(!crun.stdout.contains("ScaLAPACK"), "{}", crun.stdout);
            let mut args = scene.to_vec();
            args.extend_from_slice(&["-ubr_schur_distributed", "1"]);
            let (run, _, dist) = solve_rows(&format!("schur_d{k}_{ranks}"), ranks, &args);
            assert!(
                run.stdout.contains(&format!(
                    "the Schur complement from MUMPS distributed over the ranks, {ON_THE_GRID}"
                )),
                "{}",
                run.stdout
            );
            let e = max_pressure_gap(&dist, &central);
            assert!(
                e <= 1e-10,
                "scene {k}, -n {ranks}: pressures differ by {e:.2e}"
            );
            let peak = central
                .iter()
                .map(|r| r.lambda_t.iter().map(|x| x * x).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
            for (a, b) in dist.iter().zip(&central) {
                for c in 0..3 {
                    assert!((a.lambda_t[c] - b.lambda_t[c]).abs() <= 1e-10 * peak.max(1e-300));
                }
            }
        }
    }
}

/// The default layout of the Schur complement follows the rank count and
/// the dimension (`SCHUR_GRID_RANKS`): in 2D on rank 0 on 2 ranks, on
/// ScaLAPACK's grid on 4; in 3D on the grid from 2 ranks; the same contact
/// stresses either way.
#[test]
fn schur_grid_is_the_default_from_four_ranks_in_2d_two_in_3d() {
    let scene = HERTZ_TIGHT;
    let (two, _, rows2) = solve_rows("grid_default_2", 2, scene);
    assert!(two.stdout.contains("condensed on"), "{}", two.stdout);
    assert!(!two.stdout.contains("ScaLAPACK"), "{}", two.stdout);
    let (four, _, rows4) = solve_rows("grid_default_4", 4, scene);
    assert!(four.stdout.contains(ON_THE_GRID), "{}", four.stdout);
    let e = max_pressure_gap(&rows4, &rows2);
    assert!(e <= 1e-10, "2 and 4 ranks differ by {e:.2e}");
    let block = [
        "-options_file",
        "options/block3d-coulomb",
        "-mesh",
        "meshes/block3d_739.msh",
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    let (one, _, rows1) = solve_rows("grid_default_3d_1", 1, &block);
    assert!(one.stdout.contains("condensed on"), "{}", one.stdout);
    assert!(!one.stdout.contains("ScaLAPACK"), "{}", one.stdout);
    let (two, _, rows2) = solve_rows("grid_default_3d_2", 2, &block);
    assert!(two.stdout.contains(ON_THE_GRID), "{}", two.stdout);
    let e = max_pressure_gap(&rows2, &rows1);
    assert!(e <= 1e-9, "3D: 1 and 2 ranks differ by {e:.2e}");
}

/// The contact stresses and displacements of `a` equal those of `b`, row
/// by row, to 1e-10 of their largest (two runs that differ by round-off).
fn same_to_round_off(a: &[Row], b: &[Row], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    let peak = b.iter().map(|r| r.lambda_n.abs()).fold(0.0, f64::max);
    let umax = b.iter().map(|r| r.un.abs()).fold(0.0, f64::max);
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x.lambda_n - y.lambda_n).abs() <= 1e-10 * peak,
            "{what}: pressure {} against {}",
            x.lambda_n,
            y.lambda_n
        );
        assert!(
            (x.un - y.un).abs() <= 1e-10 * umax,
            "{what}: u_n {} against {}",
            x.un,
            y.un
        );
        for c in 0..3 {
            assert!(
                (x.lambda_t[c] - y.lambda_t[c]).abs() <= 1e-10 * peak,
                "{what}"
            );
            assert!((x.ut[c] - y.ut[c]).abs() <= 1e-10 * umax, "{what}");
        }
    }
}

/// Full solves with MUMPS' distributed right-hand sides and solutions
/// (the default; issue "Scaling studies", item 3) against the centralized
/// ones (`-ubr_mumps_rhs centralized`): the same contact stresses and
/// displacements to round-off on 1, 2 and 3 ranks, condensed (the
/// condensation and the expansion) and uncondensed (every UBR solve a full
/// one), 2D and 3D, frictionless and Coulomb; a bad value exits 2.
#[test]
fn distributed_rhs_equals_centralized() {
    let tight = ["-ubr_lambda_rtol", "1e-10"];
    let scenes: [Vec<&str>; 3] = [
        [
            &[
                "-options_file",
                "options/hertz",
                "-mesh",
                "meshes/hertz_1692.msh",
            ][..],
            &tight,
        ]
        .concat(),
        [
            &[
                "-options_file",
                "options/hertz",
                "-mesh",
                "meshes/hertz_1692.msh",
                "-ubr_condense_max",
                "0",
            ][..],
            &tight,
        ]
        .concat(),
        [
            &[
                "-options_file",
                "options/block3d-coulomb",
                "-mesh",
                "meshes/block3d_739.msh",
            ][..],
            &tight,
        ]
        .concat(),
    ];
    for (k, scene) in scenes.iter().enumerate() {
        for ranks in [1, 2, 3] {
            let (_, _, dist) = solve_rows(&format!("rhs_d{k}_{ranks}"), ranks, scene);
            let mut args = scene.clone();
            args.extend_from_slice(&["-ubr_mumps_rhs", "centralized"]);
            let (_, _, central) = solve_rows(&format!("rhs_c{k}_{ranks}"), ranks, &args);
            same_to_round_off(&dist, &central, &format!("scene {k}, -n {ranks}"));
        }
    }
    let mut args = scenes[0].clone();
    args.extend_from_slice(&["-ubr_mumps_rhs", "scattered"]);
    for ranks in [1, 2] {
        mpirun(ranks, &args).refused(
            "-ubr_mumps_rhs scattered",
            2,
            &["-ubr_mumps_rhs", "scattered"],
        );
    }
}

/// The parallel nested dissection (issue "Scaling studies", item 1): on 2,
/// 3 and 4 ranks every rank orders its own part; the contact stresses equal
/// the one-rank run's (METIS on rank 0) to 1e-8 at a tight tolerance, 2D
/// and 3D, frictionless and Coulomb, condensed and full, and with GAMG.
#[test]
fn rank_counts_agree_with_the_parallel_ordering() {
    let scenes: [&[&str]; 5] = [
        &[
            "-options_file",
            "options/hertz",
            "-mesh",
            "meshes/hertz_6619.msh",
        ],
        &[
            "-options_file",
            "options/hertz-coulomb",
            "-mesh",
            "meshes/hertz_1692.msh",
        ],
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_2357.msh",
        ],
        &[
            "-options_file",
            "options/block3d-coulomb",
            "-mesh",
            "meshes/block3d_739.msh",
            "-ubr_condense_max",
            "0",
        ],
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_739.msh",
            "-ksp_type",
            "cg",
            "-pc_type",
            "gamg",
            "-ksp_rtol",
            "1e-12",
        ],
    ];
    for (k, scene) in scenes.iter().enumerate() {
        let mut args = scene.to_vec();
        args.extend_from_slice(&["-ubr_lambda_rtol", "1e-10"]);
        let (_, _, one) = solve_rows(&format!("pnd{k}_1"), 1, &args);
        let pmax = one.iter().map(|r| r.lambda_n).fold(0.0, f64::max);
        // The default split on 2, 3, 4 ranks, the other one on 3, and
        // PT-Scotch's (the graph partitioned by every rank) on 2 and 3.
        let alt = if scene.contains(&"gamg") {
            "rcb"
        } else {
            "metis"
        };
        let splits = [
            (2, "auto"),
            (3, "auto"),
            (4, "auto"),
            (3, alt),
            (2 + k % 2, "ptscotch"),
        ];
        for (ranks, partition) in splits {
            let mut args = args.clone();
            args.extend_from_slice(&["-partition", partition]);
            let tag = format!("pnd{k}_{ranks}_{partition}");
            let (run, rep, other) = solve_rows(&tag, ranks, &args);
            // auto: RCB with the direct solver, METIS' parts for GAMG.
            let gamg = scene.contains(&"gamg");
            let want = match partition {
                "metis" | "ptscotch" | "rcb" => partition,
                _ if gamg => "metis",
                _ => "rcb",
            };
            assert_eq!(Some(rep.partition.as_str()), Some(want), "{tag}");
            let words = match want {
                "metis" => "by METIS k-way",
                "ptscotch" => "by PT-Scotch (in parallel)",
                _ => "by recursive coordinate bisection",
            };
            assert!(run.stdout.contains(words), "{tag}: {}", run.stdout);
            if !scene.contains(&"gamg") {
                assert!(
                    run.stdout.contains("nested dissection in parallel"),
                    "{}",
                    run.stdout
                );
            }
            let e = max_pressure_gap(&other, &one);
            assert!(e <= 1e-8, "{tag}: pressures differ by {e:.2e}");
            for (a, b) in other.iter().zip(&one) {
                for c in 0..3 {
                    assert!(
                        (a.lambda_t[c] - b.lambda_t[c]).abs() <= 1e-8 * pmax,
                        "{tag}, node {}: friction differs",
                        a.node
                    );
                }
            }
        }
    }
}

/// MUMPS' pre-splitting of large fronts (`-ubr_mumps_split`, KEEP(210) =
/// 1): on by default in 3D with the Schur complement on several ranks, the
/// summary saying how many fronts were split; the contact stresses and
/// displacements equal those of the unsplit factorization to round-off on 2
/// and 3 ranks (frictionless and Coulomb, the 3D block of 2,357 nodes,
/// whose analysis splits 4 fronts on 2 ranks); off on one rank and in 2D
/// unless asked for; a bad value exits 2.
#[test]
fn split_fronts_change_nothing_but_the_time() {
    const SPLIT: &str = "split in chains";
    let tight = ["-ubr_lambda_rtol", "1e-10"];
    let scenes: [Vec<&str>; 2] = [
        [
            &[
                "-options_file",
                "options/block3d",
                "-mesh",
                "meshes/block3d_2357.msh",
            ][..],
            &tight,
        ]
        .concat(),
        [
            &[
                "-options_file",
                "options/block3d-coulomb",
                "-mesh",
                "meshes/block3d_2357.msh",
            ][..],
            &tight,
        ]
        .concat(),
    ];
    for (k, scene) in scenes.iter().enumerate() {
        for ranks in [2, 3] {
            let (run, _, split) = solve_rows(&format!("split_d{k}_{ranks}"), ranks, scene);
            assert!(run.stdout.contains(SPLIT), "{}", run.stdout);
            let mut args = scene.clone();
            args.extend_from_slice(&["-ubr_mumps_split", "0"]);
            let (run0, _, whole) = solve_rows(&format!("split_0{k}_{ranks}"), ranks, &args);
            assert!(!run0.stdout.contains(SPLIT), "{}", run0.stdout);
            same_to_round_off(&split, &whole, &format!("scene {k}, -n {ranks}"));
        }
    }
    // One rank, and 2D: not split unless asked for.
    let one = mpirun(1, &scenes[0]);
    assert!(
        one.status == Some(0) && !one.stdout.contains(SPLIT),
        "{}",
        one.context()
    );
    let hertz = [
        "-options_file",
        "options/hertz",
        "-mesh",
        "meshes/hertz_37473.msh",
    ];
    let two = mpirun(2, &hertz);
    assert!(
        two.status == Some(0) && !two.stdout.contains(SPLIT),
        "{}",
        two.context()
    );
    let asked = mpirun(2, &[&hertz[..], &["-ubr_mumps_split", "1"]].concat());
    assert!(
        asked.status == Some(0) && asked.stdout.contains(SPLIT),
        "{}",
        asked.context()
    );
    for ranks in [1, 2] {
        mpirun(
            ranks,
            &[&scenes[0][..], &["-ubr_mumps_split", "2"]].concat(),
        )
        .refused("-ubr_mumps_split", 2, &["-ubr_mumps_split", "2"]);
    }
}
