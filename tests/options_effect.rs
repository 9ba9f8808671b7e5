//! Options that change nothing are named, and options files are read as a
//! user expects ("Trust at the edges", items 9 and 12): a UTF-8 byte-order
//! mark is skipped; an option the scene ignores (`-friction_coefficient`
//! on a frictionless contact) and a mistyped one (`-frcition`) are named on
//! stderr, once, and the run goes on (exit status 0).
mod common;
use common::*;

fn warnings(run: &Run) -> Vec<&str> {
    run.stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect()
}

fn hertz442(extra: &[&str]) -> Run {
    let mut a = vec![
        "-options_file",
        "options/hertz",
        "-mesh",
        "meshes/hertz_442.msh",
    ];
    a.extend_from_slice(extra);
    mpirun(2, &a)
}

/// The run exits 0 and names `option` once, in a line that holds `why`.
fn named_once(run: &Run, option: &str, why: &str) {
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    let lines: Vec<&str> = warnings(run)
        .into_iter()
        .filter(|l| l.contains(&format!("option {option} ")))
        .collect();
    assert_eq!(lines.len(), 1, "{option}: {}", run.stderr);
    assert!(lines[0].contains(why), "{option}: {}", lines[0]);
}

fn not_named(run: &Run, option: &str) {
    assert!(
        !warnings(run)
            .iter()
            .any(|l| l.contains(&format!("option {option} "))),
        "{option}: {}",
        run.stderr
    );
}

#[test]
fn friction_options_on_a_frictionless_contact() {
    let why = "has no effect: the contact is frictionless (-friction none)";
    named_once(
        &hertz442(&["-friction_coefficient", "0.5"]),
        "-friction_coefficient",
        why,
    );
    named_once(
        &hertz442(&["-friction", "none", "-friction_coefficient", "0.5"]),
        "-friction_coefficient",
        why,
    );
    named_once(&hertz442(&["-tresca_bound", "3"]), "-tresca_bound", why);
    // The typo leaves the run frictionless: named with the option meant.
    let run = hertz442(&["-frcition", "coulomb", "-friction_coefficient", "0.5"]);
    named_once(&run, "-frcition", "was not used; did you mean -friction?");
    // Two dashes: the option meant, not "an option of PETSc's linear
    // solvers" (PETSc keeps `--friction` as the name `-friction`).
    let run = hertz442(&["--friction", "coulomb", "-friction_coefficient", "0.5"]);
    named_once(
        &run,
        "--friction",
        "was not used: options take one dash; did you mean -friction?",
    );
    named_once(&run, "-friction_coefficient", why);
    // Tresca with a given bound does not use nu_f, nor CF-FP's settings.
    let run = hertz442(&[
        "-friction",
        "tresca",
        "-friction_coefficient",
        "0.6",
        "-tresca_bound",
        "50",
        "-ubr_fp_max_it",
        "3",
    ]);
    named_once(
        &run,
        "-friction_coefficient",
        "-tresca_bound 50 gives the Tresca bound",
    );
    named_once(&run, "-ubr_fp_max_it", "-friction coulomb only");
    not_named(&run, "-tresca_bound");
}

#[test]
fn algorithm_and_solver_options_that_do_not_apply() {
    // The comparator runs no UBR iteration; SSN-C reads -ubr_monitor and
    // its own initial guess.
    let run = hertz442(&[
        "-contact_algorithm",
        "ssn",
        "-ssn_initial_shift",
        "0,-0.01",
        "-ubr_anderson",
        "5",
        "-ubr_monitor",
    ]);
    named_once(
        &run,
        "-ubr_anderson",
        "-contact_algorithm ssn runs no UBR iteration",
    );
    not_named(&run, "-ubr_monitor");
    not_named(&run, "-ssn_initial_shift");
    // UBR ignores the comparators' settings, and the tolerances of the other
    // stopping test.
    let run = hertz442(&["-ssn_initial_shift", "0,-0.01", "-ubr_rtol", "1e-6"]);
    named_once(&run, "-ssn_initial_shift", "comparators' initial guess");
    named_once(&run, "-ubr_rtol", "-ubr_stop is accuracy");
    // PETSc's solver options, when the program drives MUMPS itself.
    let run = hertz442(&["-ksp_rtol", "1e-9", "-ubr_sbaij", "0"]);
    named_once(&run, "-ksp_rtol", "MUMPS driven by ubr-petsc");
    named_once(&run, "-ubr_sbaij", "iterative solvers");
    // ... and not when a PETSc solver reads them.
    let run = hertz442(&["-ksp_type", "cg", "-pc_type", "gamg", "-ksp_rtol", "1e-9"]);
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    not_named(&run, "-ksp_rtol");
}

#[test]
fn reference_and_mesh_options_that_do_not_apply() {
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_198.msh",
            "-reference_force",
            "5",
            "-mesh_h",
            "0.1",
        ],
    );
    named_once(&run, "-reference_force", "-reference hertz is not given");
    named_once(&run, "-mesh_h", "the mesh is read from -mesh");
}

/// The shipped scene warns of no option.
#[test]
fn a_correct_scene_names_no_option() {
    let run = hertz442(&[]);
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    assert!(
        !run.stderr.contains("has no effect") && !run.stderr.contains("was not used"),
        "{}",
        run.stderr
    );
}

/// An options file saved with a UTF-8 byte-order mark runs as without it
/// (a PETSc traceback, exit 1, before), on one rank and on two; a file it
/// includes may have one too.
#[test]
fn byte_order_mark_is_skipped() {
    let dir = scratch("bom-files");
    let inner = dir.join("inner");
    std::fs::write(&inner, "\u{feff}-options_file options/hertz-paper\n").unwrap();
    let outer = dir.join("outer");
    std::fs::write(
        &outer,
        format!(
            "\u{feff}# saved by an editor that writes a BOM\n-options_file {}\n-mesh meshes/hertz_442.msh\n",
            inner.display()
        ),
    )
    .unwrap();
    let outer_s = outer.to_str().unwrap().to_string();
    for ranks in [1, 2] {
        let (run, _, with_bom) = solve_rows("bom", ranks, &["-options_file", &outer_s]);
        assert!(!run.stderr.contains("error"), "{}", run.stderr);
        let (_, _, plain) = solve_rows("plain", ranks, &hertz_args("meshes/hertz_442.msh", &[]));
        assert_eq!(max_pressure_gap(&with_bom, &plain), 0.0);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `-ubr_schur_distributed` (issue "Scaling studies") places the Schur
/// complement of the condensed solves over the ranks: on one rank, or
/// with `-ubr_condense_max 0`, it was ignored in silence; it is named. On
/// two condensed ranks it chooses, and is not named.
#[test]
fn schur_layout_without_ranks_or_condensation() {
    let args = [
        "-options_file",
        "options/hertz",
        "-mesh",
        "meshes/hertz_442.msh",
        "-ubr_schur_distributed",
        "1",
    ];
    let one = mpirun(1, &args);
    named_once(&one, "-ubr_schur_distributed", "the run has one rank");
    let full = hertz442(&["-ubr_schur_distributed", "1", "-ubr_condense_max", "0"]);
    named_once(
        &full,
        "-ubr_schur_distributed",
        "-ubr_condense_max 0 condenses nothing",
    );
    let two = hertz442(&["-ubr_schur_distributed", "1"]);
    assert_eq!(two.status, Some(0), "{}", two.stderr);
    not_named(&two, "-ubr_schur_distributed");
}

/// `-mat_mumps_icntl_29` picks the ordering of MUMPS' own parallel
/// analysis: without `-mat_mumps_icntl_28 2` the program orders and
/// analyses itself, and the option was accepted in silence. It is named;
/// through PETSc's interface (`-ubr_mumps_direct 0`, where MUMPS may
/// choose a parallel analysis itself) it is not.
#[test]
fn parallel_ordering_tool_without_parallel_analysis() {
    let run = hertz442(&["-mat_mumps_icntl_29", "1"]);
    named_once(&run, "-mat_mumps_icntl_29", "-mat_mumps_icntl_28 2 only");
    let petsc = hertz442(&["-mat_mumps_icntl_29", "1", "-ubr_mumps_direct", "0"]);
    assert_eq!(petsc.status, Some(0), "{}", petsc.stderr);
    not_named(&petsc, "-mat_mumps_icntl_29");
}

/// MUMPS' controls in a run without MUMPS (CG + GAMG): the program's own
/// checks of them (ranges, the given ordering) read them without marking
/// them used, so they are still named unused, and not as typos ("did you
/// mean -mat_mumps_icntl_7?" was said of -mat_mumps_cntl_1).
#[test]
fn mumps_controls_without_mumps_are_named_unused() {
    let run = hertz442(&[
        "-ksp_type",
        "cg",
        "-pc_type",
        "gamg",
        "-mat_mumps_icntl_7",
        "1",
        "-mat_mumps_cntl_1",
        "0.1",
    ]);
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    for option in ["-mat_mumps_icntl_7", "-mat_mumps_cntl_1"] {
        let lines = run.stderr_with(&format!("option {option} was not used"));
        assert_eq!(lines.len(), 1, "{option}: {}", run.stderr);
        assert!(lines[0].contains("MUMPS did not read it"), "{}", lines[0]);
        assert!(!lines[0].contains("did you mean"), "{}", lines[0]);
    }
}

/// The options of named obstacles (`-obstacles`) are named by what is
/// wrong with them: an obstacle not listed, a key its kind does not take,
/// a mistyped key (each was "did you mean -obstacle_radius?"); and a run
/// that fails before reading them does not call the listed ones typos.
#[test]
fn named_obstacle_options_are_named_by_their_fault() {
    let dir = scratch("named-obstacles");
    let opts = dir.join("two-obstacles");
    std::fs::write(
        &opts,
        "-mesh meshes/hertz_442.msh\n-E 2000\n-nu 0.3\n-dirichlet_symmetry ux=0\n\
         -traction_top 0,-100\n-contact_surface contact\n-obstacles a\n-obstacle_a plane\n\
         -obstacle_a_point 0,0\n-obstacle_a_direction 0,-1\n",
    )
    .unwrap();
    let o = opts.to_str().unwrap();
    let run = mpirun(
        2,
        &[
            "-options_file",
            o,
            "-obstacle_b_radius",
            "1",
            "-obstacle_a_radius",
            "1",
            "-obstacle_a_pont",
            "0,0",
        ],
    );
    named_once(
        &run,
        "-obstacle_b_radius",
        "'b' is no obstacle of this run (-obstacles names a)",
    );
    named_once(
        &run,
        "-obstacle_a_radius",
        "obstacle 'a' is a plane (-obstacle_a), which takes no _radius",
    );
    named_once(&run, "-obstacle_a_pont", "did you mean -obstacle_a_point?");
    // A run refused before the obstacles are read: one error, no warning
    // about the listed obstacle's options.
    let run = mpirun(2, &["-options_file", o, "-obstacle", "plane"]);
    run.refused(
        "two kinds",
        2,
        &["with -obstacles each obstacle has its own options"],
    );
    assert!(warnings(&run).is_empty(), "{}", run.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every option declared (`opt!` in `src/options/declared.rs`) is in the
/// list `-help` prints and the inert-option rules read (`ALL`), and in the
/// contract's option tables (`docs/DESIGN.md`): an option added to one and
/// not the others (`-ubr_mumps_split` was, at first) fails here. And
/// `-help` prints it.
#[test]
fn every_declared_option_is_listed_and_documented() {
    let declared = std::fs::read_to_string(root().join("src/options/declared.rs")).unwrap();
    let design = std::fs::read_to_string(root().join("docs/DESIGN.md")).unwrap();
    let mut options = Vec::new();
    for line in declared.lines().filter(|l| l.starts_with("opt!(")) {
        let id = line["opt!(".len()..].split(':').next().unwrap().trim();
        let flag = line.split('"').nth(1).unwrap();
        options.push((id.to_string(), flag.to_string()));
    }
    assert!(options.len() > 50, "{} options parsed", options.len());
    let help = mpirun(1, &["-help"]);
    assert_eq!(help.status, Some(0), "{}", help.context());
    for (id, flag) in &options {
        assert!(
            declared.contains(&format!("    &{id},\n")),
            "{id} ({flag}) is declared but not in ALL"
        );
        assert!(
            design.contains(&format!("`{flag} ")) || design.contains(&format!("`{flag}`")),
            "{flag} is not in docs/DESIGN.md's option tables"
        );
        assert!(
            help.stdout.contains(flag.as_str()),
            "-help does not print {flag}"
        );
    }
}
