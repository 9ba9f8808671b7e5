//! Bad input ends every rank within seconds, with exit status 2, one line
//! naming the problem, and no output file written. Each case runs on 2 ranks.
mod common;
use common::*;
use std::time::Duration;

fn expect_bad(name: &str, args: &[&str], needle: &str) {
    let dir = scratch(name);
    let rep = dir.join("report.json");
    let rs = rep.to_str().unwrap().to_string();
    let mut a = args.to_vec();
    a.extend_from_slice(&["-report", &rs]);
    let run = mpirun(2, &a);
    assert_eq!(
        run.status,
        Some(2),
        "{name}: status {:?}\nstdout:\n{}\nstderr:\n{}",
        run.status,
        run.stdout,
        run.stderr
    );
    let ours: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("error:"))
        .collect();
    assert_eq!(
        ours.len(),
        1,
        "{name}: expected one error line, got:\n{}",
        run.stderr
    );
    assert!(
        ours[0].contains(needle),
        "{name}: '{}' does not name '{needle}'",
        ours[0]
    );
    assert!(!rep.exists(), "{name}: a report was written");
    within(Duration::from_secs(20), &run);
    let _ = std::fs::remove_dir_all(&dir);
}

fn hertz<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    hertz_args("meshes/hertz_442.msh", extra)
}

#[test]
fn missing_mesh_file() {
    expect_bad(
        "missing",
        &hertz_args("meshes/does_not_exist.msh", &[]),
        "does_not_exist.msh",
    );
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

#[test]
fn unknown_dirichlet_group() {
    expect_bad("dirgroup", &hertz(&["-dirichlet_nosuch", "ux=0"]), "nosuch");
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

#[test]
fn poisson_ratio_out_of_range() {
    expect_bad("nu05", &hertz(&["-nu", "0.5"]), "-nu");
    expect_bad("nu-1", &hertz(&["-nu", "-1"]), "-nu");
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
