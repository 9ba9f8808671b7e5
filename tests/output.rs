//! What users look at: ParaView files read back by an independent reader
//! (Debian's VTK), PNG plots, and no partial files after a killed run.
mod common;
use common::*;
use std::process::Command;

fn python() -> String {
    std::env::var("UBR_PYTHON").unwrap_or_else(|_| "/usr/bin/python3".into())
}

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
    assert_eq!(counts[1], num(&r, "elements"), "every cell written once");
    assert!(counts[0] >= num(&r, "nodes"), "points {}", counts[0]);
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
        (pmax - num(&r, "peak_pressure")).abs() <= 1e-12 * pmax,
        "{pmax} vs {}",
        num(&r, "peak_pressure")
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
