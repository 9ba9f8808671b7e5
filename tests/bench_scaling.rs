//! `bench/scaling` on a user's own options file (issue "Scaling studies",
//! item 5: a study of the user's scene, not only the generated ones): run in
//! the working directory (the file's mesh is relative to it), named by the
//! file, strong only, the node count from the report.

mod common;
use common::*;
use std::process::Command;

#[test]
fn scaling_study_of_an_options_file() {
    let dir = scratch("bench_scaling_file");
    std::fs::copy(root().join("meshes/hertz_442.msh"), dir.join("mine.msh")).unwrap();
    let opts = std::fs::read_to_string(root().join("options/hertz"))
        .unwrap()
        .replace("meshes/hertz_1692.msh", "mine.msh");
    assert!(opts.contains("mine.msh"), "options/hertz names its mesh");
    std::fs::write(dir.join("punch.opts"), opts).unwrap();
    // The mesh's node count, from its $Nodes header (MSH 4.1: blocks,
    // nodes, smallest and largest tag).
    let msh = std::fs::read_to_string(dir.join("mine.msh")).unwrap();
    let header = msh.lines().skip_while(|l| *l != "$Nodes").nth(1).unwrap();
    let nodes = header.split_whitespace().nth(1).unwrap().to_string();
    let out = dir.join("results");
    let run = Command::new(root().join("bench/scaling"))
        .current_dir(&dir)
        .args([
            "--scenes",
            "punch.opts",
            "--ranks",
            "1,2",
            "--paths",
            "mumps",
        ])
        .args(["--study", "strong,weak", "--no-plot", "--bin", BIN, "--out"])
        .arg(&out)
        .output()
        .expect("bench/scaling runs (python3)");
    let stdout = String::from_utf8_lossy(&run.stdout);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("punch.opts is an options file (a fixed mesh): strong scaling only"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out.join("scaling_punch.opts_mumps.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    for (row, ranks) in rows.iter().zip(["1", "2"]) {
        assert_eq!(row[col("study")], "strong", "{csv}");
        assert_eq!(row[col("ranks")], ranks, "{csv}");
        assert_eq!(row[col("nodes")], nodes, "{csv}");
        assert_eq!(row[col("mesh_h")], "file", "{csv}");
        assert_eq!(row[col("converged")], "True", "{csv}");
        let total: f64 = row[col("time_total")].parse().unwrap();
        assert!(total > 0.0, "{csv}");
    }
    // A file that does not exist is named, with the folder it was sought in.
    let run = Command::new(root().join("bench/scaling"))
        .current_dir(&dir)
        .args(["--scenes", "nowhere.opts", "--dry-run"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(
        stderr.contains("unknown scene 'nowhere.opts'") && stderr.contains("no file"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Arguments a user mistypes are refused in one line naming the argument,
/// before any run: `--ranks 1,x` and `--repeat 0` ended in a Python
/// traceback, and `--max-ranks 0`, `--cores 0` and `--nodes-per-rank -5`
/// started a study anyway (the last with a 4-unit mesh size).
#[test]
fn scaling_arguments_are_checked() {
    for (args, needle) in [
        (&["--ranks", "1,x"][..], "--ranks '1,x'"),
        (&["--repeat", "0"][..], "--repeat 0: must be at least 1"),
        (
            &["--max-ranks", "0"][..],
            "--max-ranks 0: must be at least 1",
        ),
        (&["--cores", "0"][..], "--cores 0: must be at least 1"),
        (&["--nodes-per-rank", "-5"][..], "--nodes-per-rank: '-5'"),
        (
            &["--nodes-per-rank", "hertz2d=abc"][..],
            "--nodes-per-rank (scene hertz2d): 'abc'",
        ),
        (
            &["--mesh-h", "0"][..],
            "--mesh-h: '0' is not a positive number",
        ),
    ] {
        let run = Command::new(root().join("bench/scaling"))
            .current_dir(root())
            .args(args)
            .args(["--dry-run", "--bin", BIN])
            .output()
            .expect("bench/scaling runs (python3)");
        let stdout = String::from_utf8_lossy(&run.stdout);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?}: accepted\n{stdout}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(!stderr.contains("Traceback"), "{args:?}: {stderr}");
        assert!(
            !stdout.contains("mpirun"),
            "{args:?}: runs listed\n{stdout}"
        );
    }
}
