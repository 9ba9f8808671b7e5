//! Options that nothing used: a mistyped name (`-ubr_rtoll`, `-frictoin`)
//! is otherwise silently ignored. Every rank holds the same database, so
//! rank 0 alone warns, with the closest known name:
//! `warning: option -ubr_rtoll was not used; did you mean -ubr_rtol?`.
//!
//! Checked twice: before the iterations ([`Unused::early`]: by then the
//! program and PETSc's solver objects have read their options, so a name
//! that looks like one of the program's and is unused is certainly wrong),
//! and at the end of the run ([`Unused::finish`]: every option left).

use super::declared::ALL;
use crate::error::Error;
use crate::petsc::options;
use std::sync::Mutex;
use strsim::osa_distance;

/// The options already named on stderr (by any check of the run): each is
/// named once.
static WARNED: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Whether `name` was named already; marks it named.
fn first_time(name: &str) -> bool {
    let mut w = WARNED.lock().unwrap_or_else(|e| e.into_inner());
    if w.iter().any(|n| n == name) {
        return false;
    }
    w.push(name.to_string());
    true
}

/// The options PETSc's linear solvers read (found when the options are
/// read, [`super::solver`]).
static SOLVER_OPTIONS: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Remembers the options PETSc's linear solvers read.
pub fn set_solver_options(names: Vec<String>) {
    *SOLVER_OPTIONS.lock().unwrap_or_else(|e| e.into_inner()) = names;
}

fn solver_option(name: &str) -> bool {
    let s = SOLVER_OPTIONS.lock().unwrap_or_else(|e| e.into_inner());
    s.iter().any(|n| n == name)
}

/// Marks `name` as named (by another check), so that it is not again.
pub fn mark_named(name: &str) {
    first_time(name);
}

/// PETSc options a user commonly types, for suggestions (the program's own
/// come from [`ALL`]).
const PETSC_NAMES: &[&str] = &[
    "-ksp_type",
    "-pc_type",
    "-ksp_rtol",
    "-ksp_atol",
    "-ksp_max_it",
    "-ksp_monitor",
    "-ksp_view",
    "-ksp_converged_reason",
    "-ksp_norm_type",
    "-pc_factor_mat_solver_type",
    "-pc_gamg_threshold",
    "-mat_mumps_icntl_7",
    "-mat_mumps_icntl_14",
    "-log_view",
    "-options_left",
    "-options_file",
    "-snes_monitor",
    "-snes_type",
    "-no_signal_handler",
    "-malloc_debug",
    "-info",
];

/// Options PETSc reads only in `PetscFinalize`, after the run: never
/// reported at its end.
const READ_AT_FINALIZE: &[&str] = &[
    "-options_left",
    "-options_view",
    "-log_view",
    "-log_view_memory",
    "-log_summary",
    "-log_all",
    "-log_trace",
    "-malloc_dump",
    "-malloc_view",
    "-memory_view",
    "-objects_dump",
    "-checkstack",
];

/// Prefixes of the program's own options.
const OUR_PREFIXES: &[&str] = &[
    "-ubr_",
    "-ssn_",
    "-mesh",
    "-contact_",
    "-obstacle",
    "-friction",
    "-tresca",
    "-reference",
    "-plot_",
    "-dirichlet",
    "-traction",
    "-pressure",
];

/// How far a name may be from a known one to be suggested.
fn close_enough(name: &str, distance: usize) -> bool {
    distance <= 2.max(name.len() / 5)
}

/// The known name closest to `name` (a program option, a family member
/// `-dirichlet_NAME` with its prefix corrected, a PETSc option used in this
/// run or commonly typed), if one is close enough.
pub fn suggestion(name: &str, used: &[String]) -> Option<String> {
    let mut best: Option<(usize, String)> = None;
    let mut consider = |dist: usize, candidate: String| {
        if candidate != name
            && close_enough(name, dist)
            && best.as_ref().is_none_or(|(d, _)| dist < *d)
        {
            best = Some((dist, candidate));
        }
    };
    for o in ALL {
        match o.prefix() {
            None => consider(osa_distance(name, o.name()), o.name().to_string()),
            Some(prefix) => {
                // -dirichlett_left: the prefix mistyped, the group name kept.
                let chars: Vec<char> = name.chars().collect();
                let p = prefix.chars().count();
                for k in p.saturating_sub(2)..=(p + 2).min(chars.len().saturating_sub(1)) {
                    let head: String = chars[..k].iter().collect();
                    let tail: String = chars[k..].iter().collect();
                    // A short prefix (`-E_`, `-nu_`) only within one
                    // edit per four characters: `-pc_` is no `-nu_`.
                    let dist = osa_distance(&head, prefix);
                    if head.ends_with('_') && 4 * dist <= p {
                        consider(dist, format!("{prefix}{tail}"));
                    }
                }
            }
        }
    }
    for n in PETSC_NAMES
        .iter()
        .map(|s| s.to_string())
        .chain(used.iter().cloned())
    {
        consider(osa_distance(name, &n), n);
    }
    best.map(|(_, s)| s)
}

/// Whether `name` looks like one of the program's options (so that, unused
/// once the program has read its options, it is certainly a mistake).
fn looks_ours(name: &str, used: &[String]) -> bool {
    if OUR_PREFIXES.iter().any(|p| name.starts_with(p)) {
        return true;
    }
    suggestion(name, used).is_some_and(|s| {
        ALL.iter()
            .any(|o| o.name() == s || o.prefix().is_some_and(|p| s.starts_with(p)))
    })
}

/// Whether `name` is one of the program's options (or of a family).
pub fn declared(name: &str) -> bool {
    ALL.iter()
        .any(|o| o.name() == name || o.prefix().is_some_and(|p| name.starts_with(p)))
}

/// The N of `-mat_mumps_icntl_N` when the direct solver sets ICNTL(N)
/// itself (it then reads no such option).
fn owned_icntl(name: &str) -> Option<usize> {
    let i: usize = name.strip_prefix("-mat_mumps_icntl_")?.parse().ok()?;
    crate::mumps::OWNED_ICNTL.contains(&i).then_some(i)
}

/// The keys of a named obstacle's options, `-obstacle_NAME_KEY`.
const OBSTACLE_KEYS: [&str; 8] = [
    "point",
    "center",
    "radius",
    "axis",
    "direction",
    "mesh",
    "mesh_group",
    "search_distance",
];

/// The obstacle of an option of the `-obstacles` family: `(NAME, KEY)`
/// of `-obstacle_NAME_KEY` (KEY empty for `-obstacle_NAME`) where NAME is
/// one of `listed`, or, with a KEY of [`OBSTACLE_KEYS`], any NAME.
fn obstacle_of(name: &str, listed: &[String]) -> Option<(String, String)> {
    let rest = name.strip_prefix("-obstacle_")?;
    for n in listed {
        if rest == n {
            return Some((n.clone(), String::new()));
        }
        if let Some(key) = rest
            .strip_prefix(n.as_str())
            .and_then(|k| k.strip_prefix('_'))
        {
            if OBSTACLE_KEYS.contains(&key) {
                return Some((n.clone(), key.to_string()));
            }
        }
    }
    // A name that is none of the listed ones (no key ends another).
    OBSTACLE_KEYS.iter().find_map(|k| {
        let n = rest.strip_suffix(k)?.strip_suffix('_')?;
        (!n.is_empty() && !OBSTACLE_KEYS.contains(&n)).then(|| (n.to_string(), k.to_string()))
    })
}

/// The names `-obstacles` lists (read without marking it used).
fn listed_obstacles() -> Vec<String> {
    options::peek("-obstacles")
        .ok()
        .flatten()
        .map(|v| v.split(',').map(|n| n.trim().to_string()).collect())
        .unwrap_or_default()
}

/// Why an option of the `-obstacles` family went unused: its obstacle is
/// not listed, or its kind takes no such option.
fn obstacle_message(name: &str) -> Option<String> {
    let rest = name.strip_prefix("-obstacle_")?;
    let listed = listed_obstacles();
    let Some((obstacle, key)) = obstacle_of(name, &listed) else {
        // A key mistyped (`-obstacle_a_raduis`), or a name -obstacles
        // does not list (`-obstacle_b plane`).
        let typo = listed.iter().find_map(|n| {
            let typed = rest.strip_prefix(n.as_str())?.strip_prefix('_')?;
            let key = OBSTACLE_KEYS
                .iter()
                .min_by_key(|k| osa_distance(typed, k))
                .filter(|k| osa_distance(typed, k) <= 2)?;
            Some(format!("-obstacle_{n}_{key}"))
        });
        return match typo {
            Some(meant) => Some(format!(
                "warning: option {name} was not used; did you mean {meant}?"
            )),
            None if !listed.is_empty() && !rest.contains('_') => Some(format!(
                "warning: option {name} was not used: '{rest}' is no obstacle of this run (-obstacles names {})",
                listed.join(",")
            )),
            None => None,
        };
    };
    if !listed.contains(&obstacle) {
        let among = if listed.is_empty() {
            "no -obstacles is given (one obstacle: -obstacle, -obstacle_point, ...)".to_string()
        } else {
            format!("-obstacles names {}", listed.join(","))
        };
        return Some(format!(
            "warning: option {name} was not used: '{obstacle}' is no obstacle of this run ({among})"
        ));
    }
    let kind = options::peek(&format!("-obstacle_{obstacle}"))
        .ok()
        .flatten()
        .unwrap_or_default();
    Some(format!(
        "warning: option {name} was not used: obstacle '{obstacle}' is a {} (-obstacle_{obstacle}), which takes no _{key} (-help lists each kind's options)",
        kind.trim()
    ))
}

/// Whether `name` is an option of an obstacle `-obstacles` lists (valid,
/// though unread when the run failed before the obstacles were read).
fn of_listed_obstacle(name: &str) -> bool {
    if !name.starts_with("-obstacle_") {
        return false;
    }
    let listed = listed_obstacles();
    obstacle_of(name, &listed).is_some_and(|(o, _)| listed.contains(&o))
}

/// The warning line for an unused option.
pub fn message(name: &str, used: &[String]) -> String {
    if declared(name) {
        return format!(
            "warning: option {name} was not used: the option it goes with is not given, or another overrides it (-help)"
        );
    }
    if let Some(i) = owned_icntl(name) {
        return format!(
            "warning: option {name} was not used: MUMPS called directly (the default direct solver) has ICNTL({i}) set by ubr-petsc (5, 18: the input; 19, 26: the Schur complement, -ubr_schur_distributed; 20, 21: the right-hand sides, -ubr_mumps_rhs)"
        );
    }
    if name.starts_with("-mat_mumps_icntl_") || name.starts_with("-mat_mumps_cntl_") {
        // Not a typo of another option ("did you mean -mat_mumps_icntl_7?"
        // of -mat_mumps_cntl_1 in a run with GAMG).
        return format!(
            "warning: option {name} was not used: MUMPS did not read it (the linear solver of this run has no MUMPS factorization, or MUMPS has no such control)"
        );
    }
    if solver_option(name) {
        return format!(
            "warning: option {name} was not used: PETSc's linear solvers know it, but the one of this run did not read it (-help lists what it reads)"
        );
    }
    if let Some(m) = obstacle_message(name) {
        return m;
    }
    let suggested = suggestion(name, used);
    // `--friction`, `--ksp_type`: a known name typed with two dashes.
    let one_dash = name
        .strip_prefix('-')
        .filter(|n| n.starts_with('-') && (declared(n) || suggested.as_deref() == Some(*n)));
    if let Some(single) = one_dash {
        return format!(
            "warning: option {name} was not used: options take one dash; did you mean {single}?"
        );
    }
    match suggested {
        Some(s) => format!("warning: option {name} was not used; did you mean {s}?"),
        None => format!(
            "warning: option {name} was not used (neither ubr-petsc nor PETSc knows it here; -help lists the options)"
        ),
    }
}

/// Prefixes of PETSc's options: read by PETSc after the program's own, so
/// not judged when the program has read its options.
const PETSC_PREFIXES: &[&str] = &[
    "-ksp",
    "-pc_",
    "-mat_",
    "-snes",
    "-sub_",
    "-mg_",
    "-log",
    "-vec_",
    "-dm_",
    "-is_",
    "-options",
    "-malloc",
    "-info",
    "-viewer",
    "-draw",
    "-on_error",
    "-help",
    "-version",
    "-petsc",
    "-sys_",
    "-fp_trap",
    "-no_signal",
    "-objects",
    "-memory",
    "-skip",
    "-debugger",
    "-start_in",
    "-stop_for",
    "-tao_",
    "-ts_",
    "-use_gpu",
    "-device",
    "-citations",
    "-check",
    "-history",
    "-display",
    "-mpi",
    "-prefix",
];

/// Refuses an option written `-E=5000`: PETSc takes it all for a name
/// without a value (and `-dirichlet_left=ux=0` for a group
/// `left=ux=0`), and the run would go on with another E. Called before
/// any option is read.
pub fn assignments() -> Result<(), Error> {
    for name in options::unused()? {
        if let Some((key, value)) = name.split_once('=') {
            first_time(&name);
            return Err(Error::BadInput(format!(
                "option {name}: an option and its value are separated by a space, not '=' (write {key} {value})"
            )));
        }
    }
    Ok(())
}

/// The warning lines for the options that look like the program's and are
/// none of them (`-frcition`: the run would be frictionless), once the
/// program has read its options, before any work; each marked named.
pub fn typos() -> Result<Vec<String>, Error> {
    let mut out = Vec::new();
    for name in options::unused()? {
        if !declared(&name)
            && !PETSC_PREFIXES.iter().any(|p| name.starts_with(p))
            && looks_ours(&name, &[])
            && first_time(&name)
        {
            out.push(message(&name, &[]));
        }
    }
    Ok(out)
}

/// The unknown-option check of one run (what it has named is shared with
/// the other checks: each option is named once).
#[derive(Default)]
pub struct Unused {}

impl Unused {
    /// Warns (rank 0) about the unused options that look like the
    /// program's own: called once the program and the linear solver have
    /// read theirs, before a long solve.
    pub fn early(&mut self, root: bool) -> Result<(), Error> {
        self.warn(root, true)
    }

    /// Warns (rank 0) about every option nothing used, at the end of the run.
    pub fn finish(&mut self, root: bool) -> Result<(), Error> {
        self.warn(root, false)
    }

    /// After a failure (some options unread): warns about the names that
    /// look like the program's but are none of them (`-contact_surfce`:
    /// often the cause of the failure).
    pub fn undeclared(&mut self, root: bool) -> Result<(), Error> {
        let left = options::unused()?;
        for name in left {
            if !declared(&name)
                && looks_ours(&name, &[])
                && !of_listed_obstacle(&name)
                && first_time(&name)
                && root
            {
                eprintln!("{}", message(&name, &[]));
            }
        }
        Ok(())
    }

    fn warn(&mut self, root: bool, only_ours: bool) -> Result<(), Error> {
        let left = options::unused()?;
        let all = options::all_names()?;
        let used: Vec<String> = all.into_iter().filter(|n| !left.contains(n)).collect();
        for name in left {
            if READ_AT_FINALIZE.contains(&name.as_str())
                || (only_ours && !looks_ours(&name, &used))
                || !first_time(&name)
            {
                continue;
            }
            if root {
                eprintln!("{}", message(&name, &used));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_of_named_obstacles() {
        let listed = vec!["a".to_string(), "left_wall".to_string()];
        let of = |n: &str| obstacle_of(n, &listed);
        let pair = |o: &str, k: &str| Some((o.to_string(), k.to_string()));
        assert_eq!(of("-obstacle_a"), pair("a", ""));
        assert_eq!(of("-obstacle_a_radius"), pair("a", "radius"));
        assert_eq!(
            of("-obstacle_left_wall_mesh_group"),
            pair("left_wall", "mesh_group")
        );
        assert_eq!(
            of("-obstacle_b_search_distance"),
            pair("b", "search_distance")
        );
        assert_eq!(of("-obstacle_b_mesh"), pair("b", "mesh"));
        // The single obstacle's options and typos are none.
        assert_eq!(of("-obstacle_radius"), None);
        assert_eq!(of("-obstacle_mesh_group"), None);
        assert_eq!(of("-obstacle_pont"), None);
        assert_eq!(of("-obstacle_a_raduis"), None);
    }

    #[test]
    fn suggestions_of_the_trial() {
        let none: Vec<String> = Vec::new();
        assert_eq!(
            suggestion("-ubr_rtoll", &none).as_deref(),
            Some("-ubr_rtol")
        );
        assert_eq!(suggestion("-frictoin", &none).as_deref(), Some("-friction"));
        assert_eq!(
            message("--friction", &none),
            "warning: option --friction was not used: options take one dash; did you mean -friction?"
        );
        assert_eq!(suggestion("-gravty", &none).as_deref(), Some("-gravity"));
        assert_eq!(
            suggestion("-dirichlett_left", &none).as_deref(),
            Some("-dirichlet_left")
        );
        assert_eq!(suggestion("-ksp_tpye", &none).as_deref(), Some("-ksp_type"));
        assert_eq!(suggestion("-completely_different_thing", &none), None);
        assert!(looks_ours("-ubr_rtoll", &none));
        assert!(looks_ours("-frictoin", &none));
        assert!(!looks_ours("-pc_gamg_agg_nsmooths", &none));
        // The families of a material per body: exact, and close typos.
        assert!(declared("-E_soft") && declared("-nu_soft") && declared("-density_soft"));
        assert_eq!(
            suggestion("-densty_soft", &none).as_deref(),
            Some("-density_soft")
        );
        assert!(!looks_ours("-pc_mg_levels", &none));
        // The MUMPS controls the direct solver sets: said so, no suggestion.
        assert_eq!(owned_icntl("-mat_mumps_icntl_19"), Some(19));
        assert_eq!(owned_icntl("-mat_mumps_icntl_14"), None);
        assert!(message("-mat_mumps_icntl_19", &none).contains("ICNTL(19) set by ubr-petsc"));
        // A MUMPS control no MUMPS read is no typo of another.
        let m = message("-mat_mumps_cntl_1", &none);
        assert!(
            m.contains("MUMPS did not read it") && !m.contains("did you mean"),
            "{m}"
        );
    }

    #[test]
    fn distance_counts_transpositions_once() {
        assert_eq!(osa_distance("abc", "acb"), 1);
        assert_eq!(osa_distance("kitten", "sitting"), 3);
        assert_eq!(osa_distance("", "ab"), 2);
    }
}
