//! What users look at: ParaView files read back by an independent reader
//! (Debian's VTK), PNG plots, and no partial files after a killed run.
mod common;
use common::*;
use std::process::Command;

/// A 2-rank .pvtu reads back with VTK's own reader: every cell once, the
/// fields, and the pressure field's maximum equal to the report's peak.
#[test]
fn pvtu_reads_back_with_vtk() {
    let dir = scratch("vtk");
    let pvtu = dir.join("hertz.pvtu");
    let rep = dir.join("r.json");
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz-coulomb-paper",
            "-vtk",
            pvtu.to_str().unwrap(),
            "-report",
            rep.to_str().unwrap(),
        ],
    );
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    assert!(dir.join("hertz_0.vtu").exists() && dir.join("hertz_1.vtu").exists());
    let script = r#"
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkXMLPUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update(); o = r.GetOutput()
pd, cd = o.GetPointData(), o.GetCellData()
print(o.GetNumberOfPoints(), o.GetNumberOfCells())
print(",".join(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())))
print(",".join(cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())))
print(repr(float(vtk_to_numpy(pd.GetArray("contact_pressure")).max())))
print(pd.GetArray("displacement").GetNumberOfComponents(), cd.GetArray("stress").GetNumberOfComponents())
print(repr(float(vtk_to_numpy(cd.GetArray("von_mises")).max())), sorted(set(vtk_to_numpy(cd.GetArray("rank")).tolist())))
"#;
    let out = Command::new(python())
        .args(["-c", script, pvtu.to_str().unwrap()])
        .output()
        .expect("python3 runs (apt-get install python3-vtk9)");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "VTK reader failed (python3-vtk9 installed?): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<&str> = text.lines().collect();
    let r = report(&rep);
    let counts: Vec<f64> = lines[0]
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(counts[1], r.elements, "every cell written once");
    assert!(counts[0] >= r.nodes, "points {}", counts[0]);
    for f in [
        "displacement",
        "contact_pressure",
        "tangential_traction",
        "gap",
        "contact_status",
    ] {
        assert!(
            lines[1].split(',').any(|x| x == f),
            "point field {f} missing: {}",
            lines[1]
        );
    }
    for f in ["stress", "von_mises", "rank"] {
        assert!(
            lines[2].split(',').any(|x| x == f),
            "cell field {f} missing: {}",
            lines[2]
        );
    }
    let pmax: f64 = lines[3].parse().unwrap();
    assert!(
        (pmax - r.peak_pressure).abs() <= 1e-12 * pmax,
        "{pmax} vs {}",
        r.peak_pressure
    );
    assert_eq!(lines[4], "3 9");
    assert!(lines[5].ends_with("[0, 1]"), "{}", lines[5]);
    let vm: f64 = lines[5].split_whitespace().next().unwrap().parse().unwrap();
    assert!(vm > 0.0 && vm.is_finite());
    let _ = std::fs::remove_dir_all(&dir);
}

fn png_size(path: &std::path::Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    let w = u32::from_be_bytes(b[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(b[20..24].try_into().unwrap());
    (w, h)
}

/// The contact and history plots are written as PNG images.
#[test]
fn plots_are_pngs() {
    let dir = scratch("plots");
    let (c, h) = (dir.join("contact.png"), dir.join("history.png"));
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz-tresca-paper",
            "-plot_contact",
            c.to_str().unwrap(),
            "-plot_history",
            h.to_str().unwrap(),
        ],
    );
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    assert_eq!(png_size(&c), (1200, 800));
    assert_eq!(png_size(&h), (1200, 800));
    assert!(std::fs::metadata(&c).unwrap().len() > 10_000);
    let _ = std::fs::remove_dir_all(&dir);
}

/// An output path in a missing directory is bad input, found before any work.
#[test]
fn unwritable_output_is_bad_input_at_once() {
    for opt in [
        "-report",
        "-contact_output",
        "-vtk",
        "-plot_contact",
        "-plot_history",
    ] {
        let run = mpirun(
            2,
            &[
                "-options_file",
                "options/hertz-paper",
                opt,
                "/nonexistent-dir/x.out",
            ],
        );
        assert_eq!(run.status, Some(2), "{opt}: {}", run.stderr);
        let line = run
            .stderr
            .lines()
            .find(|l| l.starts_with("error:"))
            .unwrap_or("");
        assert!(line.contains(opt), "{opt}: {line}");
        assert!(run.seconds < 20.0);
    }
}

/// A `.pvtu` piece that cannot be written on one rank: a directory in
/// its place is refused before any work, naming the piece; a piece file
/// that cannot be replaced (immutable, `chattr +i`, where the file system
/// allows it) ends the run with the piece and the rank named by rank 0,
/// no index and no other piece left behind.
#[test]
fn pvtu_piece_that_cannot_be_written() {
    let dir = scratch("pvtu-piece");
    let pvtu = dir.join("v.pvtu");
    let run_3 = || {
        mpirun(
            3,
            &[
                "-options_file",
                "options/hertz",
                "-vtk",
                pvtu.to_str().unwrap(),
            ],
        )
    };
    std::fs::create_dir(dir.join("v_1.vtu")).unwrap();
    let e = run_3()
        .refused(
            "a directory",
            2,
            &["-vtk", "rank 1", "v_1.vtu", "is a directory"],
        )
        .to_string();
    assert!(!e.contains("v_0"), "{e}");
    std::fs::remove_dir(dir.join("v_1.vtu")).unwrap();
    let piece = dir.join("v_2.vtu");
    std::fs::write(&piece, "").unwrap();
    let immutable = Command::new("chattr").arg("+i").arg(&piece).status();
    if !immutable.is_ok_and(|s| s.success()) {
        eprintln!("chattr +i is not available here: the write failure is not tested");
        let _ = std::fs::remove_dir_all(&dir);
        return;
    }
    let run = run_3();
    let _ = Command::new("chattr").arg("-i").arg(&piece).status();
    run.refused(
        "immutable",
        2,
        &["option -vtk", "cannot write", "v_2.vtu", "(on rank 2)"],
    );
    let mut left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["v_2.vtu"], "only the file that was there");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `.pvtu` written again on fewer ranks: the pieces the earlier run left
/// beyond the new rank count (which ParaView offered with the new ones as
/// one time series) are removed; a file of that name that is not a VTK
/// piece, and pieces beyond a gap, are left.
#[test]
fn pvtu_on_fewer_ranks_leaves_no_stale_piece() {
    let dir = scratch("pvtu-stale");
    let pvtu = dir.join("s.pvtu");
    let run = |ranks: usize| {
        let r = mpirun(
            ranks,
            &[
                "-options_file",
                "options/hertz",
                "-vtk",
                pvtu.to_str().unwrap(),
            ],
        );
        assert_eq!(r.status, Some(0), "{}", r.context());
    };
    let listing = || {
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    run(4);
    std::fs::copy(dir.join("s_3.vtu"), dir.join("s_6.vtu")).unwrap();
    run(2);
    assert_eq!(listing(), ["s.pvtu", "s_0.vtu", "s_1.vtu", "s_6.vtu"]);
    run(3);
    std::fs::write(dir.join("s_1.vtu"), "not a piece").unwrap();
    std::fs::remove_file(dir.join("s_0.vtu")).unwrap();
    // One rank writes s_0.vtu, and s_1.vtu is not ours: it stays.
    run(1);
    assert_eq!(
        listing(),
        ["s.pvtu", "s_0.vtu", "s_1.vtu", "s_2.vtu", "s_6.vtu"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run killed mid-way (SIGTERM) leaves no output file behind, whole or partial.
#[test]
fn sigterm_leaves_no_partial_output() {
    let dir = scratch("sigterm");
    let out = |n: &str| dir.join(n).to_str().unwrap().to_string();
    let (rep, csv, vtk, png) = (out("r.json"), out("c.csv"), out("v.pvtu"), out("p.png"));
    let (mut cmd, _session) = mpi_command("mpirun");
    let mut child = cmd
        .args([
            "-n",
            "2",
            BIN,
            "-options_file",
            "options/hertz-paper",
            "-mesh",
            "meshes/hertz_37473.msh",
        ])
        // Full sparse solves (no condensation): a run long enough to kill.
        .args([
            "-ubr_rtol",
            "1e-14",
            "-ubr_max_it",
            "100000",
            "-ubr_condense_max",
            "0",
        ])
        .args([
            "-report",
            &rep,
            "-contact_output",
            &csv,
            "-vtk",
            &vtk,
            "-plot_contact",
            &png,
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs(3));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before it was killed"
    );
    // SAFETY: kill(2) takes plain integers: the pid of the child spawned
    // above (not yet reaped, so it cannot have been reused) and SIGTERM.
    unsafe {
        libc_kill(child.id() as i32, 15);
    }
    let t = std::time::Instant::now();
    let status = child.wait().unwrap();
    assert!(!status.success());
    assert!(t.elapsed().as_secs() < 20, "ranks did not end promptly");
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

extern "C" {
    #[link_name = "kill"]
    fn libc_kill(pid: i32, sig: i32) -> i32;
}

// ---------------------------------------------------------------------------
// Plots and summary at the edges (issue "Trust at the edges", items 13, 15).

use ubr_petsc::report::plot::{break_lines, contact_zoom, history_curves, linear_axis};

/// A uniform pressure (constant up to round-off) gets a stress axis from
/// zero with distinct, short tick labels, not a range magnified into
/// noise where every label reads "1e6"; so does a nearly constant one on
/// an axis that is not from zero.
#[test]
fn uniform_pressure_axis_is_readable() {
    let p = 2.307_692_307_692_3e8;
    let (range, labels) = linear_axis(Some((p * (1.0 - 3e-13), p)), true);
    assert!(range.start <= 0.0 && range.end >= p, "{range:?}");
    assert!(labels.len() >= 3, "{labels:?}");
    assert!(labels.iter().any(|l| l == "0"), "{labels:?}");
    let mut distinct = labels.clone();
    distinct.dedup();
    assert_eq!(distinct, labels, "tick labels repeat");
    assert!(labels.iter().all(|l| l.len() <= 6), "{labels:?}");
    // Not from zero: a spread of 1e-9 of the value still gives distinct labels.
    let (range, labels) = linear_axis(Some((1e6 * (1.0 - 2e-9), 1e6 * (1.0 + 2e-9))), false);
    assert!(range.start < 1e6 && range.end > 1e6);
    let mut distinct = labels.clone();
    distinct.dedup();
    assert!(labels.len() >= 3 && distinct == labels, "{labels:?}");
}

/// The contact plot zooms on a contact zone that is 5% of the surface
/// (with a margin and the next open candidate on each side), and shows the
/// whole surface when nothing or nearly everything touches.
#[test]
fn contact_plot_zooms_on_the_contact_zone() {
    let x: Vec<f64> = (0..=200).map(|i| 0.5 * f64::from(i)).collect(); // 0..100
    let touching: Vec<bool> = x.iter().map(|&v| (40.0..=45.0).contains(&v)).collect();
    let z = contact_zoom(&x, &touching).expect("a zoom");
    assert!(z.start < 40.0 && z.end > 45.0, "{z:?}");
    assert!(
        z.start <= 39.5 && z.end >= 45.5,
        "the next open candidates show: {z:?}"
    );
    assert!(z.end - z.start < 0.15 * 100.0, "{z:?}");
    // A contact zone at the end of the surface stays within it.
    let edge: Vec<bool> = x.iter().map(|&v| v <= 3.0).collect();
    let z = contact_zoom(&x, &edge).expect("a zoom");
    assert!(z.start == 0.0 && z.end > 3.0 && z.end < 10.0, "{z:?}");
    // Nothing or nearly everything in contact: the whole surface.
    assert_eq!(contact_zoom(&x, &vec![false; x.len()]), None);
    let most: Vec<bool> = x.iter().map(|&v| v > 10.0).collect();
    assert_eq!(contact_zoom(&x, &most), None);
    // Scattered order (3D distances) gives the same zoom.
    let mut rev = x.clone();
    rev.reverse();
    let mut rev_t = touching.clone();
    rev_t.reverse();
    assert_eq!(contact_zoom(&rev, &rev_t), contact_zoom(&x, &touching));
}

/// The bound's line is broken between two contact surfaces and across a
/// hole in one, never inside a graded surface.
#[test]
fn contact_plot_lines_break_between_groups() {
    let nan_at = |(x, _): (Vec<f64>, Vec<f64>)| -> Vec<usize> {
        x.iter()
            .enumerate()
            .filter(|(_, v)| v.is_nan())
            .map(|(i, _)| i)
            .collect()
    };
    let y = [1.0; 8];
    // Two groups, side by side (a NaN goes between them).
    let x = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7];
    let g = [0, 0, 0, 0, 1, 1, 1, 1];
    assert_eq!(nan_at(break_lines(&x, &y, &g)), vec![4]);
    // One group with a hole between 0.3 and 1.0.
    let x = [0.0, 0.1, 0.2, 0.3, 1.0, 1.1, 1.2, 1.3];
    assert_eq!(nan_at(break_lines(&x, &y, &[0; 8])), vec![4]);
    // A graded surface (spacing x1.5 per node): one line.
    let mut x = vec![0.0];
    for k in 0..7 {
        x.push(x[k] + 0.1 * 1.5f64.powi(k as i32));
    }
    let (bx, by) = break_lines(&x, &y, &[0; 8]);
    assert_eq!((bx, by), (x.clone(), y.to_vec()));
}

/// -plot_history at the defaults (accuracy stop, condensed: no change
/// (4.16) per iteration) draws the error estimate and its target
/// -ubr_lambda_rtol/4 (CF-FP: the last Tresca solves' /40), and no legend
/// entry for a change it does not have; under the paper's stop, the change.
#[test]
fn history_plot_draws_what_the_stop_uses() {
    let nan = f64::NAN;
    let condensed = [
        [nan, 1e-2, f64::INFINITY],
        [nan, 1e-3, 0.5],
        [nan, 1e-4, 1e-4],
    ];
    let c = history_curves(&condensed, None, Some(1e-3), false);
    let labels: Vec<&str> = c.iter().map(|c| c.label.as_str()).collect();
    assert!(!labels.iter().any(|l| l.contains("change")), "{labels:?}");
    // The change computed after the loop: one point, at the end.
    let end = history_curves(&condensed, Some(3e-7), Some(1e-3), false);
    assert!(end[0].label.contains("at the end only"), "{}", end[0].label);
    assert!(end[0].y[..2].iter().all(|v| v.is_nan()) && end[0].y[2] == 3e-7);
    let est = c
        .iter()
        .find(|c| c.label.contains("estimated error"))
        .expect("the error estimate");
    assert_eq!(est.y[2], 1e-4);
    let target = c.iter().find(|c| c.dashed).expect("the target");
    assert!(target.y.iter().all(|&v| v == 2.5e-4), "{:?}", target.y);
    assert!(target.label.contains("2.5e-4"), "{}", target.label);
    let coulomb = history_curves(&condensed, None, Some(1e-3), true);
    let target = coulomb.iter().find(|c| c.dashed).expect("the target");
    assert!((target.y[0] - 2.5e-5).abs() < 1e-20, "{}", target.label);
    let paper = [[1.0, 1e-2, nan], [1e-3, 1e-3, nan]];
    let c = history_curves(&paper, Some(1e-3), None, false);
    assert!(c[0].label.contains("relative change (4.16)") && c[0].y[1] == 1e-3);
    assert!(!c.iter().any(|c| c.dashed || c.label.contains("estimated")));
}

/// The number in `line` after the last `key` (e.g. "half-width 2.5542e-3").
fn number_after(line: &str, key: &str) -> f64 {
    let rest = &line[line
        .rfind(key)
        .unwrap_or_else(|| panic!("no '{key}' in {line}"))
        + key.len()..];
    let word = rest.split_whitespace().next().unwrap();
    word.trim_end_matches([';', ','])
        .parse()
        .unwrap_or_else(|_| panic!("'{word}' in {line}"))
}

/// An SI scene (E = 210 GPa, a contact 2.6 mm wide): the summary prints E
/// and the Hertz comparison in significant digits (4 fixed decimals gave
/// "0.0026 vs Hertz 0.0026"), and the report's per-group force of its one
/// contact surface is the total.
#[test]
fn summary_prints_si_values_in_significant_digits() {
    let (dir, mesh) = gmsh_2d("out-punch", "tests/scenes/punch2d_steel.geo");
    let args = [
        "-options_file",
        "tests/scenes/punch2d_steel.opts",
        "-mesh",
        &mesh,
        "-reference",
        "hertz",
        "-reference_force",
        "6e6",
        "-reference_radius",
        "0.2",
    ];
    let (run, r, _) = solve_rows("out-punch-run", 2, &args);
    assert!(
        run.stdout.contains("E = 2.1e11, nu = 0.3"),
        "{}",
        run.stdout
    );
    assert!(!run.stdout.contains("210000000000"), "{}", run.stdout);
    let line = run
        .stdout
        .lines()
        .find(|l| l.contains("peak pressure"))
        .expect("the Hertz line");
    assert!(
        line.contains("contact half-width") && !line.contains("radius"),
        "{line}"
    );
    let close = |printed: f64, exact: f64, key: &str| {
        assert!(
            (printed - exact).abs() <= 1e-4 * exact.abs(),
            "{key}: printed {printed}, report {exact}: {line}"
        );
    };
    close(
        number_after(line, "half-width"),
        r.contact_half_width,
        "contact_half_width",
    );
    close(
        number_after(line, "vs Hertz"),
        r.contact_half_width_hertz,
        "contact_half_width_hertz",
    );
    close(
        number_after(line, "peak pressure"),
        r.peak_pressure,
        "peak_pressure",
    );
    close(
        number_after(line, "Hertz p0"),
        r.peak_pressure_hertz,
        "peak_pressure_hertz",
    );
    let groups = &r.contact_force_groups;
    assert_eq!(groups.len(), 1);
    let f = r.contact_force;
    assert!((groups["contact"] - f).abs() <= 1e-12 * f);
    assert!(!run.stdout.contains("by surface"), "{}", run.stdout);
    let _ = std::fs::remove_dir_all(&dir);
}

/// In 3D the Hertz line names the contact radius, not a half-width.
#[test]
fn summary_says_radius_in_3d() {
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_198.msh",
            "-reference",
            "hertz",
            "-reference_force",
            "1e4",
            "-reference_radius",
            "0.5",
        ],
    );
    assert_eq!(run.status, Some(0), "{}\n{}", run.stdout, run.stderr);
    let line = run
        .stdout
        .lines()
        .find(|l| l.contains("peak pressure"))
        .expect("the Hertz line");
    assert!(
        line.contains("contact radius") && !line.contains("half-width"),
        "{line}"
    );
    assert!(
        run.stdout.contains("E = 1e6, nu = 0.45, 3D"),
        "{}",
        run.stdout
    );
}

/// A table on two feet: -contact_surface foot_a,foot_b gives each foot's
/// contact force in the summary and the report, adding up to the total;
/// the CSV keeps its columns. With foot_a and `feet` (both feet), a node
/// counts in the first group that names it.
const FEET: &str = r#"
h = 0.05;
Point(1) = {0, 0, 0, h}; Point(2) = {0.5, 0, 0, h}; Point(3) = {0.5, 0.5, 0, h}; Point(4) = {1.5, 0.5, 0, h};
Point(5) = {1.5, 0, 0, h}; Point(6) = {2, 0, 0, h}; Point(7) = {2, 1, 0, h}; Point(8) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8}; Plane Surface(1) = {1};
Physical Curve("foot_a") = {1}; Physical Curve("foot_b") = {5}; Physical Curve("feet") = {1, 5};
Physical Curve("top") = {7}; Physical Surface("body") = {1};
"#;

#[test]
fn contact_force_of_each_group() {
    let dir = scratch("out-feet");
    let geo = dir.join("feet.geo");
    std::fs::write(&geo, FEET).unwrap();
    let mesh = dir.join("feet.msh");
    let g = Command::new("gmsh")
        .args(["-2", "-format", "msh41", "-o"])
        .arg(&mesh)
        .arg(&geo)
        .output()
        .expect("gmsh runs");
    assert!(g.status.success());
    let mesh = mesh.to_str().unwrap();
    let plot = dir.join("feet.png");
    let args = |surfaces: &'static str| {
        vec![
            "-mesh",
            mesh,
            "-E",
            "1000",
            "-nu",
            "0.3",
            "-dirichlet_top",
            "ux=0.002,uy=-0.01",
            "-contact_surface",
            surfaces,
            "-contact_direction",
            "0,-1",
            "-obstacle",
            "plane",
            "-obstacle_point",
            "0,0",
            "-friction",
            "coulomb",
            "-friction_coefficient",
            "0.3",
            "-plot_contact",
            plot.to_str().unwrap(),
        ]
    };
    let (run, r, rows) = solve_rows("out-feet-two", 2, &args("foot_a,foot_b"));
    let total = r.contact_force;
    let groups = &r.contact_force_groups;
    let force = |g: &std::collections::BTreeMap<String, f64>, k: &str| {
        *g.get(k).unwrap_or_else(|| panic!("no {k}: {g:?}"))
    };
    let (a, b) = (force(groups, "foot_a"), force(groups, "foot_b"));
    assert_eq!(groups.len(), 2);
    assert!(a > 0.3 * total && b > 0.3 * total, "{a} {b} of {total}");
    assert!(
        (a + b - total).abs() <= 1e-12 * total,
        "{a} + {b} vs {total}"
    );
    let line = run
        .stdout
        .lines()
        .find(|l| l.contains("contact force by surface"))
        .unwrap_or_else(|| panic!("no per-surface line:\n{}", run.stdout));
    assert!(
        (number_after(line, "foot_a") - a).abs() <= 1e-6 * a,
        "{line}"
    );
    assert!(
        (number_after(line, "foot_b") - b).abs() <= 1e-6 * b,
        "{line}"
    );
    assert!(rows.len() > 10 && png_size(&plot) == (1200, 800));
    // `feet` holds foot_a's nodes too: they count in foot_a, named first.
    let (_, r2, _) = solve_rows("out-feet-overlap", 2, &args("foot_a,feet"));
    let g2 = &r2.contact_force_groups;
    assert!((force(g2, "foot_a") - a).abs() <= 1e-9 * total, "{g2:?}");
    assert!((force(g2, "feet") - b).abs() <= 1e-9 * total, "{g2:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
