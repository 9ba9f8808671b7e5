//! Bad input ends every rank within seconds, with exit status 2, one line
//! naming the problem, and no output file written. Each case runs on 2 ranks.
mod common;
use common::*;
use std::time::Duration;

/// Checks a refused run: exit status 2, one `error:` line naming every
/// needle, no traceback, within seconds.
fn assert_refused(name: &str, run: &Run, needles: &[&str]) {
    run.refused(name, 2, needles);
    for trace in [
        "PETSC ERROR",
        "PETSc error",
        "MPI_ABORT",
        "panicked",
        "internal error",
        "overflowed",
        "Segmentation",
    ] {
        assert!(
            !run.stderr.contains(trace),
            "{name}: '{trace}' on stderr:\n{}",
            run.stderr
        );
    }
    within(Duration::from_secs(20), run);
}

/// `args` on `ranks` ranks with a report asked for: refused, and no report.
fn expect_bad_on(ranks: usize, name: &str, args: &[&str], needles: &[&str]) {
    let dir = scratch(name);
    let rep = dir.join("report.json");
    let rs = rep.to_str().unwrap().to_string();
    let mut a = args.to_vec();
    a.extend_from_slice(&["-report", &rs]);
    let run = mpirun(ranks, &a);
    assert_refused(&format!("{name} (-n {ranks})"), &run, needles);
    assert!(!rep.exists(), "{name}: a report was written");
    let _ = std::fs::remove_dir_all(&dir);
}

fn expect_bad(name: &str, args: &[&str], needle: &str) {
    expect_bad_on(2, name, args, &[needle]);
}

/// The files of `dir`, sorted.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn hertz<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    hertz_args("meshes/hertz_442.msh", extra)
}

/// A shipped options file run from another directory (a scaling study's
/// scratch directory): its relative paths are the working directory's
/// (PETSc's rule), and the one-line error says where they are found.
#[test]
fn options_file_from_another_directory_says_where_its_paths_are() {
    let dir = scratch("elsewhere");
    let root = std::fs::canonicalize(root()).unwrap();
    let from_root = root.display().to_string();
    let run_in = |args: &[&str]| {
        let t = std::time::Instant::now();
        let (mut cmd, _session) = mpi_command("mpirun");
        cmd.current_dir(&dir).args(["-n", "2", BIN]).args(args);
        let out = cmd.output().expect("mpirun runs");
        Run {
            status: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            seconds: t.elapsed().as_secs_f64(),
        }
    };
    let file = |name: &str| root.join("options").join(name).display().to_string();
    // The included file (options/hertz-coulomb names options/hertz).
    let run = run_in(&["-options_file", &file("hertz-coulomb")]);
    let e = run.refused("include", 2, &["-options_file", "'options/hertz'", "line"]);
    assert!(e.contains(&format!("is in {from_root}: run there")), "{e}");
    // The mesh the file names, with the options file and its line.
    let run = run_in(&["-options_file", &file("hertz")]);
    let e = run.refused(
        "mesh",
        2,
        &["option -mesh", "meshes/hertz_", "options/hertz' line"],
    );
    assert!(e.contains(&format!("is in {from_root}: run there")), "{e}");
    assert!(
        e.contains(&dir.display().to_string()),
        "names the working directory: {e}"
    );
    // A path found nowhere says only the rule; one the command line gave,
    // nothing more.
    let opts = dir.join("scene.opts");
    std::fs::write(&opts, "-mesh nowhere/m.msh\n").unwrap();
    let run = run_in(&[
        "-options_file",
        &file("hertz"),
        "-options_file",
        "scene.opts",
    ]);
    let e = run.refused("nowhere", 2, &["nowhere/m.msh", "'scene.opts' line 1"]);
    assert!(
        e.contains("relative to the working directory") && !e.contains("run there"),
        "{e}"
    );
    let run = run_in(&["-options_file", &file("hertz"), "-mesh", "nowhere/m.msh"]);
    let e = run.refused("command line", 2, &["nowhere/m.msh"]);
    assert!(!e.contains("named in"), "{e}");
}

#[test]
fn missing_mesh_file() {
    expect_bad(
        "missing",
        &hertz_args("meshes/does_not_exist.msh", &[]),
        "does_not_exist.msh",
    );
    // With every partition (PT-Scotch's ranks wait for rank 0's read too),
    // on 3 ranks.
    for partition in ["metis", "rcb", "ptscotch"] {
        let extra = ["-partition", partition];
        expect_bad_on(
            3,
            &format!("missing-{partition}"),
            &hertz_args("meshes/does_not_exist.msh", &extra),
            &["does_not_exist.msh"],
        );
    }
}

#[test]
fn not_a_gmsh_file() {
    expect_bad(
        "notgmsh",
        &hertz_args("options/hertz-paper", &[]),
        "options/hertz-paper",
    );
}

#[test]
fn truncated_mesh() {
    let dir = scratch("truncated-src");
    let text = std::fs::read_to_string(root().join("meshes/hertz_442.msh")).unwrap();
    let cut = dir.join("cut.msh");
    std::fs::write(&cut, &text[..text.len() / 2]).unwrap();
    let c = cut.to_str().unwrap().to_string();
    expect_bad("truncated", &hertz_args(&c, &[]), "cut.msh");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A cell given twice under two element tags (two copies of a part
/// concatenated) would count its stiffness twice: refused, naming both.
/// (Gmsh's MSH 2.2 copies of an element for another physical group follow
/// it and are read once: the copy here is placed apart.)
#[test]
fn repeated_cell() {
    let dir = scratch("repeated-src");
    let text = std::fs::read_to_string(root().join("meshes/hertz_442_v22.msh")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let at = lines.iter().position(|l| *l == "$Elements").unwrap();
    let count: usize = lines[at + 1].trim().parse().unwrap();
    let last = lines[at + 1 + count];
    let mut fields: Vec<&str> = last.split_whitespace().collect();
    let tag = (count + 1000).to_string();
    fields[0] = &tag;
    let copy = fields.join(" ");
    let total = (count + 1).to_string();
    let mut out: Vec<&str> = lines[..=at].to_vec();
    out.push(&total);
    out.extend(&lines[at + 2..at + count]);
    out.push(&copy);
    out.extend(&lines[at + count..]);
    let msh = dir.join("repeated.msh");
    std::fs::write(&msh, out.join("\n") + "\n").unwrap();
    let m = msh.to_str().unwrap().to_string();
    expect_bad_on(
        2,
        "repeated",
        &hertz_args(&m, &[]),
        &[&format!(
            "elements {} and {tag} have the same nodes",
            last.split_whitespace().next().unwrap()
        )],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_dirichlet_group() {
    expect_bad("dirgroup", &hertz(&["-dirichlet_nosuch", "ux=0"]), "nosuch");
}

/// A component given twice took the last value without a word.
#[test]
fn dirichlet_component_twice() {
    expect_bad(
        "dirtwice",
        &hertz(&["-dirichlet_symmetry", "ux=0,uy=0,ux=1"]),
        "option -dirichlet_symmetry: ux given twice",
    );
}

#[test]
fn unknown_contact_group() {
    expect_bad(
        "contactgroup",
        &hertz(&["-contact_surface", "nosuch"]),
        "nosuch",
    );
}

#[test]
fn non_positive_young_modulus() {
    expect_bad("E", &hertz(&["-E", "0"]), "-E");
    expect_bad("Eneg", &hertz(&["-E", "-5"]), "-E");
}

/// `-E=5000` (PETSc takes it for a name without a value: the run went on
/// with the options file's E, warned only at its end) is refused, with the
/// option as it should be written; so is a family's, on 1 and 2 ranks.
#[test]
fn an_option_written_with_an_equals_sign_is_refused() {
    for ranks in [1, 2] {
        let run = mpirun(ranks, &hertz(&["-E=5000"]));
        run.refused("-E=5000", 2, &["option -E=5000: an option and its value are separated by a space, not '=' (write -E 5000)"]);
        let run = mpirun(ranks, &hertz(&["-dirichlet_symmetry=ux=0"]));
        run.refused("family", 2, &["(write -dirichlet_symmetry ux=0)"]);
    }
}

#[test]
fn poisson_ratio_out_of_range() {
    expect_bad("nu05", &hertz(&["-nu", "0.5"]), "-nu");
    expect_bad("nu-1", &hertz(&["-nu", "-1"]), "-nu");
}

/// A number far from 1 comes back as typed, with its exponent: Rust's
/// plain digits of -1e-300 made a 340-character line.
#[test]
fn extreme_values_are_echoed_with_their_exponent() {
    for (name, args, value) in [
        ("E", hertz(&["-E", "-1e-300"]), "-1e-300"),
        ("nu", hertz(&["-nu", "-1e300"]), "-1e300"),
        (
            "dir",
            hertz(&["-contact_direction", "1e-300,-1e-300"]),
            "(1e-300,-1e-300)",
        ),
    ] {
        let run = mpirun(1, &args);
        assert_refused(name, &run, &[value]);
        let line = run.stderr.lines().find(|l| l.contains("error")).unwrap();
        assert!(
            line.len() < 160,
            "{name}: a {}-character line: {line}",
            line.len()
        );
    }
}

#[test]
fn non_positive_r() {
    expect_bad("r", &hertz(&["-ubr_r", "0"]), "-ubr_r");
}

#[test]
fn bad_contact_direction() {
    expect_bad(
        "dir2",
        &hertz(&["-contact_direction", "0,-2"]),
        "-contact_direction",
    );
    expect_bad(
        "dir0",
        &hertz(&["-contact_direction", "0,0"]),
        "-contact_direction",
    );
}

#[test]
fn contact_surface_without_candidates() {
    // A ball far to the side: no line x + t n meets it.
    expect_bad(
        "nocand",
        &hertz(&[
            "-contact_normal",
            "fixed",
            "-obstacle",
            "ball",
            "-obstacle_center",
            "100,-10",
            "-obstacle_radius",
            "1",
        ]),
        "no candidate",
    );
}

/// A contact surface inside the body (a line embedded in the mesh, each
/// segment a face of two triangles) is refused, for an obstacle and for a
/// pair, on 1, 2 and 3 ranks; the boundary line beside it is accepted.
#[test]
fn contact_surface_inside_the_body() {
    let (dir, msh) = gmsh_2d("embedded", "tests/edges/embedded2d.geo");
    let base = [
        "-mesh",
        msh.as_str(),
        "-E",
        "1e5",
        "-nu",
        "0.3",
        "-dirichlet_top",
        "ux=0,uy=-0.003",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,-0.01",
    ];
    let with = |extra: &[&'static str]| {
        let mut a = base.to_vec();
        a.extend_from_slice(extra);
        a
    };
    for ranks in [1, 2, 3] {
        expect_bad_on(
            ranks,
            "inside",
            &with(&["-contact_surface", "mid"]),
            &["-contact_surface", "'mid' has 12 facets inside the body"],
        );
    }
    expect_bad_on(
        2,
        "inside-pair",
        &with(&["-contact_surface", "bottom", "-contact_pair", "mid,top"]),
        &["-contact_pair", "'mid' has 12 facets inside the body"],
    );
    let run = mpirun(2, &with(&["-contact_surface", "bottom"]));
    assert_eq!(run.status, Some(0), "{}", run.context());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn not_a_number() {
    expect_bad("nan", &hertz(&["-E", "abc"]), "-E");
}

#[test]
fn friction_options() {
    expect_bad(
        "nof",
        &hertz(&["-friction", "coulomb"]),
        "-friction_coefficient",
    );
    expect_bad(
        "tb",
        &hertz(&[
            "-friction",
            "tresca",
            "-friction_coefficient",
            "0.6",
            "-tresca_bound",
            "-1",
        ]),
        "-tresca_bound",
    );
    expect_bad(
        "tbh",
        &[
            "-mesh",
            "meshes/hertz_442.msh",
            "-E",
            "2000",
            "-nu",
            "0.3",
            "-contact_surface",
            "contact",
            "-contact_direction",
            "0,-1",
            "-obstacle",
            "plane",
            "-obstacle_point",
            "0,0",
            "-friction",
            "tresca",
            "-friction_coefficient",
            "0.6",
            "-tresca_bound",
            "hertz",
        ],
        "-tresca_bound",
    );
    expect_bad("fl", &hertz(&["-friction", "viscous"]), "-friction");
}

#[test]
fn unknown_partitioner() {
    // Refused on every rank count, before any work.
    for ranks in [1, 2] {
        expect_bad_on(
            ranks,
            &format!("part{ranks}"),
            &hertz(&["-partition", "scotch"]),
            &["-partition", "scotch", "auto, metis, rcb"],
        );
    }
}

#[test]
fn inverted_element() {
    // Swap two nodes of one triangle of a valid 2.2 mesh.
    let dir = scratch("inverted-src");
    let text = std::fs::read_to_string(root().join("meshes/hertz_442_v22.msh")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let start = lines.iter().position(|l| l == "$Elements").unwrap();
    let n: usize = lines[start + 1].trim().parse().unwrap();
    let j = (start + 2..start + 2 + n)
        .find(|&j| lines[j].split_whitespace().nth(1) == Some("2"))
        .unwrap();
    let mut f: Vec<String> = lines[j].split_whitespace().map(String::from).collect();
    let len = f.len();
    f.swap(len - 1, len - 2);
    let nodes = format!("{} {} {}", f[len - 3], f[len - 2], f[len - 1]);
    lines[j] = f.join(" ");
    let path = dir.join("inverted.msh");
    std::fs::write(&path, lines.join("\n")).unwrap();
    expect_bad(
        "inverted",
        &hertz_args(path.to_str().unwrap(), &[]),
        &format!("(nodes {nodes}) is inverted"),
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn options_files_leave_nothing_unused() {
    for f in std::fs::read_dir(root().join("options")).unwrap() {
        let f = f.unwrap().path();
        let name = format!("options/{}", f.file_name().unwrap().to_string_lossy());
        let run = mpirun(2, &["-options_file", &name, "-options_left"]);
        assert_eq!(run.status, Some(0), "{name}: {}", run.stderr);
        assert!(
            run.stdout.contains("There are no unused options."),
            "{name}:\n{}",
            run.stdout
        );
    }
}

// ----- options files (items 7 and 9 of "Trust at the edges") -----

/// `-E 1000 -options_file options/hertz` ran at the file's E 2000 without
/// a word (PETSc: the last one given wins): now a warning, on stderr once
/// and in the report, on 2 ranks; `-options_file options/hertz -E 1000`,
/// the usual override, says nothing.
#[test]
fn options_file_over_the_command_line_is_named() {
    let dir = scratch("override");
    let report = dir.join("r.json");
    let r = report.to_str().unwrap();
    let before = ["-E", "1000", "-options_file", "options/hertz", "-report", r];
    let run = mpirun(2, &before);
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    let line = "option -E is given twice: 1000 (the command line), then 2000 ('options/hertz' line 11); the later one, 2000, is used";
    assert_eq!(
        run.stderr.matches("is given twice").count(),
        1,
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains(&format!("warning: {line}")),
        "{}",
        run.stderr
    );
    assert!(common::report(&report)
        .warnings
        .iter()
        .any(|w| w.starts_with(line)));
    let after = ["-options_file", "options/hertz", "-E", "1000", "-report", r];
    let run = mpirun(2, &after);
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    assert!(!run.stderr.contains("given twice"), "{}", run.stderr);
    assert!(run.stdout.contains("E = 1000"), "{}", run.stdout);
    let _ = std::fs::remove_dir_all(&dir);
}

/// An options file that includes itself, directly or through a cycle of
/// files: one line naming the cycle, exit 2, on one rank and on two (it was
/// a stack overflow, exit 139).
#[test]
fn options_file_including_itself() {
    let dir = scratch("selfinclude");
    let own = dir.join("self");
    let own_s = own.to_str().unwrap().to_string();
    std::fs::write(
        &own,
        format!("-options_file options/hertz\n-options_file {own_s}\n"),
    )
    .unwrap();
    let (a, b) = (dir.join("a"), dir.join("b"));
    let (a_s, b_s) = (
        a.to_str().unwrap().to_string(),
        b.to_str().unwrap().to_string(),
    );
    std::fs::write(&a, format!("-E 2000\n-options_file {b_s}\n")).unwrap();
    std::fs::write(&b, format!("# b\n-options_file {a_s}\n")).unwrap();
    let direct = format!("({own_s} -> {own_s})");
    let cycle = format!("({a_s} -> {b_s} -> {a_s})");
    for ranks in [1, 2] {
        expect_bad_on(
            ranks,
            "selfinclude-run",
            &["-options_file", &own_s],
            &["-options_file", "includes itself", &direct],
        );
        expect_bad_on(
            ranks,
            "cycle-run",
            &["-options_file", &a_s],
            &["includes itself", &cycle],
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A path with a space in an options file: PETSc's files take one word per
/// value (a traceback before); the line says so and how to quote it.
#[test]
fn space_in_an_options_file_value() {
    let dir = scratch("space");
    let sub = dir.join("my dir");
    std::fs::create_dir_all(&sub).unwrap();
    let mesh = sub.join("m.msh");
    std::fs::copy(root().join("meshes/hertz_442.msh"), &mesh).unwrap();
    let file = dir.join("scene");
    let file_s = file.to_str().unwrap().to_string();
    let m = mesh.to_str().unwrap();
    std::fs::write(&file, format!("-options_file options/hertz\n-mesh {m}\n")).unwrap();
    let quoted = format!("-mesh \"{m}\"");
    for ranks in [1, 2] {
        expect_bad_on(
            ranks,
            "space-run",
            &["-options_file", &file_s],
            &[&file_s, "line 2", "-mesh", &quoted],
        );
    }
    // Quoted as the message says, it runs.
    std::fs::write(&file, format!("-options_file options/hertz\n{quoted}\n")).unwrap();
    let run = mpirun(2, &["-options_file", &file_s]);
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Other lines PETSc would refuse with a traceback, named with their line.
#[test]
fn malformed_options_file_lines() {
    let dir = scratch("malformed");
    let file = dir.join("scene");
    let file_s = file.to_str().unwrap().to_string();
    for (text, needle) in [
        (
            "-options_file options/hertz\n-E 2000 -nu 0.3\n",
            "two options on one line",
        ),
        (
            "-options_file options/hertz\nE 2000\n",
            "'E' is not an option",
        ),
        (
            "-options_file options/hertz\n-mesh \"a.msh\n",
            "double quote is not closed",
        ),
    ] {
        std::fs::write(&file, text).unwrap();
        expect_bad_on(
            2,
            "malformed-run",
            &["-options_file", &file_s],
            &[&file_s, "line 2", needle],
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ----- PETSc's solver options (item 9) -----

/// A solver package this PETSc does not have: the option, the value and
/// what is available, exit 2, on every rank count (an MPI_ABORT with a
/// PETSc error on each rank before).
#[test]
fn solver_package_not_installed() {
    for ranks in [1, 2] {
        expect_bad_on(
            ranks,
            "pastix",
            &hertz(&["-pc_factor_mat_solver_type", "pastix"]),
            &[
                "option -pc_factor_mat_solver_type",
                "'pastix'",
                "not a solver package",
                "mumps",
            ],
        );
    }
    // A package that cannot do what is asked on this matrix.
    expect_bad_on(
        2,
        "umfpack",
        &hertz(&["-pc_type", "lu", "-pc_factor_mat_solver_type", "umfpack"]),
        &[
            "option -pc_factor_mat_solver_type",
            "umfpack does no LU factorization",
            "2 ranks",
            "mumps",
        ],
    );
    expect_bad_on(
        2,
        "ilu",
        &hertz(&["-pc_type", "ilu"]),
        &["-pc_type ilu", "bjacobi"],
    );
}

/// MUMPS' parallel analysis (`-mat_mumps_icntl_28 2`, which a scaling
/// study tries): with the Schur complement MUMPS refuses it (INFOG(1) =
/// -39), said before the analysis; without it, a MUMPS with no parallel
/// ordering tool (Debian's plain build) stopped the process in the Fortran
/// runtime ("Unit number is negative", MUMPS writing to the error stream the
/// program closes) and now names what is missing; a MUMPS that has one
/// (PT-Scotch or ParMETIS) solves, and the summary says so.
#[test]
fn parallel_analysis_says_what_stops_it() {
    for ranks in [1, 2, 3] {
        expect_bad_on(
            ranks,
            "icntl28-schur",
            &hertz(&["-mat_mumps_icntl_28", "2"]),
            &[
                "option -mat_mumps_icntl_28 2",
                "Schur",
                "-ubr_condense_max 0",
            ],
        );
    }
    let args = hertz(&["-mat_mumps_icntl_28", "2", "-ubr_condense_max", "0"]);
    for ranks in [1, 2] {
        let run = mpirun(ranks, &args);
        if run.status == Some(0) {
            assert!(
                run.stdout
                    .contains("MUMPS' parallel analysis (-mat_mumps_icntl_28 2), ordered by"),
                "{}",
                run.stdout
            );
        } else {
            assert_refused(
                &format!("icntl28 (-n {ranks})"),
                &run,
                &[
                    "option -mat_mumps_icntl_28 2",
                    "built without PT-Scotch and ParMETIS",
                ],
            );
        }
    }
}

/// MUMPS controls that change what a solve returns (a null-space basis,
/// entries of the inverse, discarded factors, a forward elimination during
/// the factorization) ended after the factorization with a bare INFOG(1)
/// (exit 3), or PETSc's interface aborted: refused before any work, on
/// either path.
#[test]
fn mumps_controls_that_change_the_solves() {
    for (icntl, value, path, needle) in [
        ("25", "-1", "1", "null space"),
        ("30", "1", "1", "inverse"),
        ("31", "1", "1", "discards"),
        ("32", "1", "1", "forward elimination"),
        ("25", "-1", "0", "null space"),
        ("31", "2", "0", "discards"),
    ] {
        let name = format!("-mat_mumps_icntl_{icntl}");
        let args = hertz(&[&name, value, "-ubr_mumps_direct", path]);
        expect_bad_on(
            2,
            &format!("icntl{icntl}-{path}"),
            &args,
            &[&format!("option {name} {value}"), needle],
        );
    }
}

/// MUMPS controls that choose among numbered methods: a value MUMPS does
/// not have (it took -mat_mumps_icntl_7 9 for its default, AMD here, in
/// silence) is refused on either path, naming the option and the range;
/// so is a negative amount of memory (ICNTL 14, 23).
#[test]
fn mumps_choices_out_of_range() {
    for (icntl, value, path, range) in [
        ("7", "9", "1", "from 0 to 7"),
        ("28", "3", "1", "from 0 to 2"),
        ("29", "-1", "1", "from 0 to 2"),
        ("12", "4", "0", "from 0 to 3"),
        ("6", "8", "0", "from 0 to 7"),
        ("14", "-50", "0", "0 or more"),
        ("23", "-5", "1", "0 or more"),
    ] {
        let name = format!("-mat_mumps_icntl_{icntl}");
        let args = hertz(&[&name, value, "-ubr_mumps_direct", path]);
        expect_bad_on(
            2,
            &format!("choice{icntl}-{path}"),
            &args,
            &[&format!("option {name} {value}"), range],
        );
    }
}

/// `-mat_mumps_icntl_7 1` (a given ordering, METIS where the program
/// drives MUMPS) where PETSc's MUMPS interface factorizes (the comparators,
/// `-ubr_mumps_direct 0`): PETSc stopped with its own error, exit 1. Now
/// refused in one line, exit 2, naming the orderings PETSc can use.
#[test]
fn given_ordering_through_petsc() {
    for (name, extra) in [
        ("direct0", &["-ubr_mumps_direct", "0"][..]),
        ("snesvi", &["-contact_algorithm", "snesvi"][..]),
    ] {
        let mut args = vec!["-mat_mumps_icntl_7", "1"];
        args.extend_from_slice(extra);
        expect_bad_on(
            2,
            &format!("given-{name}"),
            &hertz(&args),
            &[
                "option -mat_mumps_icntl_7 1",
                "PETSc's MUMPS interface",
                "4 (PORD)",
            ],
        );
    }
}

/// Unknown solver names, and values PETSc cannot read, name the option.
#[test]
fn petsc_solver_options_are_bad_input() {
    expect_bad_on(
        2,
        "kspfoo",
        &hertz(&["-ksp_type", "foo"]),
        &["option -ksp_type", "'foo'", "cg"],
    );
    expect_bad_on(
        1,
        "pcfoo",
        &hertz(&["-pc_type", "foo"]),
        &["option -pc_type", "'foo'", "gamg"],
    );
    expect_bad_on(
        2,
        "ksprtol",
        &hertz(&["-ksp_type", "cg", "-pc_type", "gamg", "-ksp_rtol", "abc"]),
        &["option -ksp_rtol", "abc"],
    );
}

// ----- outputs (items 8 and 14) -----

/// Two outputs on one path, or an output on an input: exit 2 before any
/// work, nothing written, the inputs untouched (the CSV was lost before).
#[test]
fn outputs_on_one_path() {
    let dir = scratch("onepath");
    let d = dir.to_str().unwrap().to_string();
    let x = format!("{d}/X.json");
    let run = mpirun(2, &hertz(&["-report", &x, "-contact_output", &x]));
    assert_refused(
        "report=csv",
        &run,
        &["-report", "-contact_output", "same file", &x],
    );
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    // The same file by another spelling.
    let p1 = format!("{d}/p.png");
    let p2 = format!(
        "{d}/../{}/./p.png",
        dir.file_name().unwrap().to_str().unwrap()
    );
    let run = mpirun(2, &hertz(&["-plot_contact", &p1, "-plot_history", &p2]));
    assert_refused(
        "plots",
        &run,
        &["-plot_contact", "-plot_history", "same file"],
    );
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    // An output on the input mesh: a .pvtu piece of rank 1 here.
    let mesh = format!("{d}/x_1.vtu");
    std::fs::copy(root().join("meshes/hertz_442.msh"), &mesh).unwrap();
    let before = std::fs::read(&mesh).unwrap();
    let pvtu = format!("{d}/x.pvtu");
    let run = mpirun(2, &hertz_args(&mesh, &["-vtk", &pvtu]));
    assert_refused(
        "pvtu-mesh",
        &run,
        &["-vtk", "piece of rank 1", "input mesh"],
    );
    assert_eq!(std::fs::read(&mesh).unwrap(), before);
    assert_eq!(listing(&dir), ["x_1.vtu"]);
    // On one rank there is no piece of rank 1: it runs.
    let run = mpirun(1, &hertz_args(&mesh, &["-vtk", &pvtu]));
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::create_dir_all(&dir).unwrap();
    // An output on an options file.
    let scene = format!("{d}/scene.json");
    std::fs::copy(root().join("options/hertz-paper"), &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    let run = mpirun(
        1,
        &[
            "-options_file",
            &scene,
            "-mesh",
            "meshes/hertz_442.msh",
            "-report",
            &scene,
        ],
    );
    assert_refused(
        "options-file",
        &run,
        &["-report", "options file", "scene.json"],
    );
    assert_eq!(std::fs::read(&scene).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Outputs of a fixed format must be named so: `-vtk out/x.vtk` wrote
/// x.pvtu and its pieces before.
#[test]
fn output_extensions() {
    let dir = scratch("extensions");
    let d = dir.to_str().unwrap().to_string();
    for (option, file, needles) in [
        (
            "-vtk",
            "x.vtk",
            &["option -vtk", "x.vtk", ".vtu or .pvtu"][..],
        ),
        (
            "-report",
            "r.txt",
            &["option -report", "r.txt", ".json"][..],
        ),
        (
            "-contact_output",
            "c.json",
            &["option -contact_output", ".csv"][..],
        ),
        (
            "-plot_contact",
            "p.svg",
            &["option -plot_contact", ".png"][..],
        ),
        ("-plot_history", "h", &["option -plot_history", ".png"][..]),
    ] {
        let path = format!("{d}/{file}");
        let run = mpirun(2, &hertz(&[option, &path]));
        assert_refused(option, &run, needles);
        assert!(listing(&dir).is_empty(), "{option}: {:?}", listing(&dir));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
