//! PETSc's linear-solver options, checked with the program's own before any
//! work: a Krylov method, preconditioner or solver package this PETSc does
//! not have, or a value PETSc cannot read (`-ksp_rtol abc`), is bad input
//! (exit status 2, one line naming the option), not a PETSc error in the
//! middle of the set-up on every rank. Every rank holds the same options and
//! asks its own PETSc, with no communication: the outcome is collective.

use super::unused::declared;
use super::LinearBackend;
use crate::error::{bad, Error};
use crate::petsc::options;
use crate::petsc::registry::{self, Factor};

/// The value of a PETSc option, trimmed; an error when given empty.
fn word(name: &str) -> Result<Option<String>, Error> {
    match options::get_string(name)? {
        Some(s) if s.trim().is_empty() => bad(format!("option {name} needs a value")),
        other => Ok(other.map(|s| s.trim().to_string())),
    }
}

/// [`word`] without marking the option used: for MUMPS' controls, which a
/// run without MUMPS never reads (and then names unused).
fn peek_word(name: &str) -> Result<Option<String>, Error> {
    match options::peek(name)? {
        Some(s) if s.trim().is_empty() => bad(format!("option {name} needs a value")),
        other => Ok(other.map(|s| s.trim().to_string())),
    }
}

/// Checks `-ksp_type`, `-pc_type`, `-pc_factor_mat_solver_type` against
/// this PETSc (the matrix distributed over `ranks` ranks), then has PETSc
/// read every linear-solver option as the run's solver will. Returns the
/// options PETSc's solver reads.
pub fn check(ranks: usize) -> Result<Vec<String>, Error> {
    if options::has_name("-help")? {
        // PETSc would print its solver options twice.
        return Ok(Vec::new());
    }
    let ksp = word("-ksp_type")?;
    if let Some(k) = &ksp {
        known("-ksp_type", k, &registry::ksp_types()?, "Krylov method")?;
    }
    let pc = word("-pc_type")?;
    if let Some(p) = &pc {
        known("-pc_type", p, &registry::pc_types()?, "preconditioner")?;
    }
    if let (Some("preonly"), Some(p)) = (ksp.as_deref(), pc.as_deref()) {
        preonly(p)?;
    }
    let krylov = match LinearBackend::of(pc.as_deref(), ksp.as_deref(), None, false) {
        LinearBackend::Factorization { ksp, .. } | LinearBackend::Preconditioned { ksp, .. } => {
            ksp != "preonly"
        }
    };
    if krylov && word("-ksp_norm_type")?.as_deref() == Some("none") {
        // CG without a norm never meets a tolerance: it ran 274 iterations
        // to DIVERGED_INDEFINITE_MAT on the Hertz scene (exit 3).
        return bad("option -ksp_norm_type none: the Krylov method then measures no residual and no solve meets its tolerance (each runs to -ksp_max_it or breaks down); leave the norm to the program (unpreconditioned for CG)".to_string());
    }
    factorization(pc.as_deref(), ranks)?;
    tolerances()?;
    mumps_solve_controls()?;
    mumps_choices()?;
    registry::read_solver_options().map_err(|m| Error::BadInput(petsc_message(&m)))
}

/// MUMPS controls that change what a solve returns, which the program
/// takes for the solution of `K u = f`, and their values that do: with
/// them every solver path failed after the factorization, with a bare
/// INFOG(1) (-37, -44, -48, -22; exit 3), or PETSc's interface aborted.
const MUMPS_SOLVE_CONTROLS: [(usize, &str); 4] = [
    (25, "makes a solve return a basis of the null space"),
    (30, "makes a solve compute entries of the inverse"),
    (31, "discards factors the solves need"),
    (
        32,
        "does the forward elimination during the factorization, on right-hand sides the program has not made yet",
    ),
];

/// `-mat_mumps_icntl_{i}` and its value, when given (read without marking
/// it used); an error when it is not an integer.
fn icntl_given(i: usize) -> Result<Option<(String, i32)>, Error> {
    let name = format!("-mat_mumps_icntl_{i}");
    let Some(v) = peek_word(&name)? else {
        return Ok(None);
    };
    match v.parse::<i32>() {
        Ok(k) => Ok(Some((name, k))),
        Err(_) => bad(format!("option {name}: '{v}' is not an integer")),
    }
}

/// Refuses the values of [`MUMPS_SOLVE_CONTROLS`] that change the solves:
/// any but 0 (ICNTL(31) = 2 passed with MUMPS' Cholesky, but an LU through
/// PETSc's interface then failed in its solve, INFOG(1) = -44).
fn mumps_solve_controls() -> Result<(), Error> {
    for (i, what) in MUMPS_SOLVE_CONTROLS {
        let Some((name, k)) = icntl_given(i)? else {
            continue;
        };
        if k != 0 {
            return bad(format!(
                "option {name} {k}: ICNTL({i}) {what}; the program needs MUMPS' plain solves (leave the option out)"
            ));
        }
    }
    Ok(())
}

/// MUMPS controls that choose among numbered methods, their values and
/// what they choose. MUMPS takes any other value for its default in
/// silence (`-mat_mumps_icntl_7 9` ordered with AMD, and the summary named
/// "ICNTL(7) = 9"): refused, on either path.
const MUMPS_CHOICES: [(usize, i32, &str); 5] = [
    (
        6,
        7,
        "the permutation to a zero-free diagonal (0 none, 1 to 6 a method, 7 automatic)",
    ),
    (
        7,
        7,
        "the sequential ordering (0 AMD, 1 given: METIS where ubr-petsc drives MUMPS, 2 AMF, 3 SCOTCH, 4 PORD, 5 METIS, 6 QAMD, 7 automatic)",
    ),
    (
        12,
        3,
        "the ordering strategy of symmetric matrices (0 automatic, 1 usual, 2 compressed, 3 constrained)",
    ),
    (
        28,
        2,
        "the analysis (0 automatic, 1 sequential, 2 parallel)",
    ),
    (
        29,
        2,
        "the parallel ordering (0 automatic, 1 PT-Scotch, 2 ParMETIS)",
    ),
];

/// MUMPS controls that are amounts, 0 or more: a negative one was taken
/// as a cap of -5 MB (ICNTL(23): "needs 7.8 MiB more than the -5 MB a
/// rank may use") or failed the factorization (ICNTL(14) -50: INFOG(1) =
/// -9 through PETSc's interface, exit 3).
const MUMPS_AMOUNTS: [(usize, &str); 2] = [
    (
        14,
        "the percentage of working memory added to MUMPS' estimate",
    ),
    (23, "the working memory per rank in MB (0: MUMPS' estimate)"),
];

/// Refuses the values of [`MUMPS_CHOICES`] that MUMPS does not have, and
/// negative [`MUMPS_AMOUNTS`].
fn mumps_choices() -> Result<(), Error> {
    for (i, what) in MUMPS_AMOUNTS {
        let Some((name, k)) = icntl_given(i)? else {
            continue;
        };
        if k < 0 {
            return bad(format!(
                "option {name} {k}: ICNTL({i}) is {what}, 0 or more"
            ));
        }
    }
    for (i, max, what) in MUMPS_CHOICES {
        let Some((name, k)) = icntl_given(i)? else {
            continue;
        };
        if !(0..=max).contains(&k) {
            return bad(format!(
                "option {name} {k}: ICNTL({i}) chooses {what}, from 0 to {max}"
            ));
        }
    }
    Ok(())
}

/// `-mat_mumps_icntl_7 1` (a given ordering: METIS, where ubr-petsc drives
/// MUMPS) through PETSc's MUMPS interface, which has no way to pass one:
/// PETSc stopped with its own error (exit 1). Refused in words where PETSc
/// drives MUMPS: the comparators (`ubr` false) and `-ubr_mumps_direct 0`.
pub fn given_ordering(linear: &LinearBackend, ubr: bool) -> Result<(), Error> {
    let petsc_mumps = matches!(linear, LinearBackend::Factorization { package, mumps_direct, .. }
        if package == "mumps" && !(ubr && *mumps_direct));
    if petsc_mumps && peek_word("-mat_mumps_icntl_7")?.as_deref() == Some("1") {
        let who = if ubr {
            "-ubr_mumps_direct 0 and the Krylov methods around the factorization"
        } else {
            "the comparators"
        };
        return bad(format!(
            "option -mat_mumps_icntl_7 1: the given ordering (METIS) needs MUMPS driven by ubr-petsc (UBR, -ksp_type preonly, -ubr_mumps_direct 1); PETSc's MUMPS interface, which {who} use, cannot pass one: choose 0 (AMD), 2 (AMF), 4 (PORD), 6 (QAMD) or 7 (automatic)"
        ));
    }
    Ok(())
}

/// Preconditioners that approximate `K^-1`: applied once (`-ksp_type
/// preonly`) they solve nothing. `-ksp_type preonly -pc_type jacobi` (or
/// gamg, bjacobi, icc) ended with exit 3 after 4 to 25 iterations and the
/// words "the body is not held: a rigid-body motion is free" (its answer's
/// equilibrium residual 0.5 to 1.3): the solves, not the scene, were wrong.
const APPROXIMATE_PCS: [&str; 17] = [
    "none",
    "jacobi",
    "pbjacobi",
    "vpbjacobi",
    "bjacobi",
    "sor",
    "eisenstat",
    "icc",
    "ilu",
    "asm",
    "gasm",
    "gamg",
    "mg",
    "ml",
    "hypre",
    "spai",
    "kaczmarz",
];

/// Refuses `-ksp_type preonly` with a preconditioner of [`APPROXIMATE_PCS`].
fn preonly(pc: &str) -> Result<(), Error> {
    if APPROXIMATE_PCS.contains(&pc) {
        return bad(format!("option -ksp_type preonly: -pc_type {pc} applied once is no solve of the elasticity problem (it approximates K^-1); use a Krylov method around it (-ksp_type cg, the default with -pc_type {pc}), or a factorization (-pc_type cholesky, the default)"));
    }
    Ok(())
}

/// The Krylov method's tolerances that leave nothing to solve, refused
/// (PETSc 3.18 takes them without a word): `-ksp_rtol` 1 or more ended
/// every solve before its first iteration and UBR ran to -ubr_max_it on a
/// displacement that never changed (exit 3 after 10,000 iterations, its
/// error estimate 4e137); a negative `-ksp_rtol` or `-ksp_atol` and a
/// `-ksp_max_it` below 1 have no meaning. (Values PETSc cannot read are
/// its own read's to name.)
fn tolerances() -> Result<(), Error> {
    let number = |name: &str| -> Result<Option<(String, f64)>, Error> {
        Ok(word(name)?.and_then(|w| w.parse::<f64>().ok().map(|x| (w, x))))
    };
    if let Some((w, x)) = number("-ksp_rtol")? {
        if !(0.0..1.0).contains(&x) {
            return bad(format!("option -ksp_rtol: {w} is not in [0, 1): the relative decrease of the residual each solve asks of the Krylov method (1 or more: no iteration at all)"));
        }
    }
    if let Some((w, x)) = number("-ksp_atol")? {
        if !(x >= 0.0 && x.is_finite()) {
            return bad(format!(
                "option -ksp_atol: {w} is not a non-negative number"
            ));
        }
    }
    if let Some((w, x)) = number("-ksp_max_it")? {
        if x < 1.0 || x.is_nan() {
            return bad(format!(
                "option -ksp_max_it: {w} is not a positive number of iterations"
            ));
        }
    }
    Ok(())
}

fn known(option: &str, value: &str, types: &[String], what: &str) -> Result<(), Error> {
    if types.iter().any(|t| t == value) {
        return Ok(());
    }
    bad(format!(
        "option {option}: '{value}' is not a {what} of this PETSc (it has: {})",
        types.join(", ")
    ))
}

/// A factorization (`-pc_type lu|cholesky|ilu|icc`, Cholesky by default)
/// needs a solver package that does it for this matrix.
fn factorization(pc: Option<&str>, ranks: usize) -> Result<(), Error> {
    let (factor, kind, pc_text) = match pc {
        None => (
            Factor::Cholesky,
            "Cholesky",
            "-pc_type cholesky (the default)",
        ),
        Some("cholesky") => (Factor::Cholesky, "Cholesky", "-pc_type cholesky"),
        Some("lu") => (Factor::Lu, "LU", "-pc_type lu"),
        Some("ilu") => (Factor::Ilu, "incomplete LU", "-pc_type ilu"),
        Some("icc") => (Factor::Icc, "incomplete Cholesky", "-pc_type icc"),
        Some(_) => return Ok(()),
    };
    let package = word("-pc_factor_mat_solver_type")?;
    if package.is_none() && matches!(factor, Factor::Lu | Factor::Cholesky) {
        // The program's default, MUMPS.
        return Ok(());
    }
    let mat = if ranks > 1 { "mpiaij" } else { "seqaij" };
    let found = registry::factorizes(package.as_deref(), mat, factor)?;
    if found == Some(true) {
        return threads_of(package.as_deref());
    }
    let matrix = if ranks > 1 {
        format!("a matrix distributed over {ranks} ranks ({mat})")
    } else {
        format!("a matrix on one rank ({mat})")
    };
    let available = registry::packages_for(mat, factor)?;
    let available = if available.is_empty() {
        "none".to_string()
    } else {
        available.join(", ")
    };
    match (package, found) {
        (Some(p), None) => bad(format!(
            "option -pc_factor_mat_solver_type: '{p}' is not a solver package of this PETSc (not installed, or misspelt); for {pc_text} on {matrix} it has: {available}"
        )),
        (Some(p), _) => bad(format!(
            "option -pc_factor_mat_solver_type: {p} does no {kind} factorization of {matrix}; for {pc_text} this PETSc has: {available}"
        )),
        (None, _) => bad(format!(
            "option {pc_text}: this PETSc has no {kind} factorization of {matrix}{}",
            if ranks > 1 {
                format!("; on several ranks, -pc_type bjacobi -sub_pc_type {} factorizes each rank's block", pc.unwrap_or("ilu"))
            } else {
                String::new()
            }
        )),
    }
}

/// SuperLU_DIST with several OpenMP threads (`OMP_NUM_THREADS` above 1;
/// the program runs one otherwise, [`crate::dense::one_openmp_thread`]) calls the
/// BLAS from its threads, and Debian's serial OpenBLAS is not made for
/// that: its solves were wrong here (hertz2d h 0.1, 2 threads: "moves
/// without bound" at every run). Refused with OpenBLAS, as MOOSE refuses
/// it; another BLAS (MKL on a cluster) is the user's to judge.
fn threads_of(package: Option<&str>) -> Result<(), Error> {
    let threads = std::env::var("OMP_NUM_THREADS").ok();
    let many = threads
        .as_deref()
        .and_then(|t| t.split(',').next()?.trim().parse::<u32>().ok())
        .is_some_and(|n| n > 1);
    if package == Some("superlu_dist") && many && crate::dense::openblas() {
        return bad(format!(
            "option -pc_factor_mat_solver_type superlu_dist: OMP_NUM_THREADS={} runs SuperLU_DIST on several OpenMP threads, which call OpenBLAS at once and give wrong solves; set OMP_NUM_THREADS=1 (or unset it: one thread), or use MUMPS",
            threads.unwrap_or_default()
        ));
    }
    Ok(())
}

/// PETSc's message of a linear-solver option it could not read, naming the
/// option when one PETSc option (not one of the program's) has a value the
/// message quotes.
fn petsc_message(m: &str) -> String {
    let words: Vec<&str> = m
        .split(|c: char| c.is_whitespace() || "'\"(),;:".contains(c))
        .filter(|w| !w.is_empty())
        .collect();
    let named: Vec<String> = options::all_pairs()
        .unwrap_or_default()
        .into_iter()
        .filter(|(n, v)| {
            !declared(n)
                && v.as_deref()
                    .is_some_and(|v| !v.is_empty() && words.contains(&v))
        })
        .map(|(n, _)| n)
        .collect();
    match named.as_slice() {
        [one] => format!("option {one}: {m} (PETSc, reading the linear solver's options)"),
        _ => format!("the linear solver's options: {m} (PETSc)"),
    }
}
