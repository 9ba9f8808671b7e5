//! Iterative solvers multiply with a copy of the operator in symmetric block
//! storage (`-ubr_sbaij`, on by default) while the preconditioner is built
//! from the AIJ matrix: the answers are the AIJ products' answers.
mod common;
use common::*;

/// UBR with CG + GAMG, SBAIJ products against AIJ products, on 1, 2 and 3
/// ranks: the same r (to rounding), UBR and CG iteration counts (to 2) and
/// pressures (to 1e-8).
/// In 3D (block3d, the automatic r kept) and in 2D on a scene whose
/// automatic r moves 3.9x from the trial on the iterative path (a change of
/// the matrix after the preconditioner is built: the copy must follow).
#[test]
fn sbaij_products_equal_aij_products() {
    let (dir, msh) = gmsh_2d("sbaij-mesh", "tests/scenes/slab2d_ball_pen.geo");
    let scenes: [(&str, Vec<&str>); 2] = [
        (
            "block3d",
            vec![
                "-options_file",
                "options/block3d",
                "-mesh",
                "meshes/block3d_2357.msh",
            ],
        ),
        (
            "slab2d",
            vec![
                "-options_file",
                "tests/scenes/slab2d_ball_pen.opts",
                "-mesh",
                &msh,
            ],
        ),
    ];
    for (name, base) in &scenes {
        for ranks in [1, 2, 3] {
            let mut results = Vec::new();
            for sbaij in ["0", "1"] {
                let mut args = base.clone();
                args.extend_from_slice(&[
                    "-ksp_type",
                    "cg",
                    "-pc_type",
                    "gamg",
                    "-ubr_sbaij",
                    sbaij,
                ]);
                let (run, r, rows) =
                    solve_rows(&format!("sbaij-{name}-{ranks}-{sbaij}"), ranks, &args);
                let solver = r.linear_solver.as_str().to_string();
                assert_eq!(
                    solver.contains("SBAIJ products"),
                    sbaij == "1",
                    "{name}: {solver}\n{}",
                    run.stdout
                );
                let cg: f64 = r.inner_iterations.iter().copied().sum();
                results.push((r.iterations, cg, r.r, r.r_trial, rows));
            }
            let (aij, sb) = (&results[0], &results[1]);
            assert!(
                (aij.0 - sb.0).abs() <= 2.0 && (aij.1 - sb.1).abs() <= 2.0,
                "{name} -n {ranks}: UBR/CG iterations {}/{} (AIJ) vs {}/{} (SBAIJ)",
                aij.0,
                aij.1,
                sb.0,
                sb.1
            );
            assert!(
                (aij.2 - sb.2).abs() <= 1e-9 * aij.2,
                "{name} -n {ranks}: r {} vs {}",
                aij.2,
                sb.2
            );
            if *name == "slab2d" {
                assert!(
                    sb.2 > 2.0 * sb.3,
                    "{name}: r {} should have moved from the trial {}",
                    sb.2,
                    sb.3
                );
            }
            let g = max_pressure_gap(&sb.4, &aij.4);
            assert!(g <= 1e-8, "{name} -n {ranks}: pressures differ by {g:.2e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
