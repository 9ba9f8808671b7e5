//! Several obstacles (`-obstacles NAME1,NAME2`): each candidate paired
//! with the obstacle of smallest gap, the force on each in the report, the
//! forces per obstacle balancing the loads, ranks agreeing, bad input.

mod common;
use common::*;

/// Squeezed between two plates (each overlapping the block by 0.01) under
/// its weight: both plates carry load, and floor + roof + weight = 0 to
/// 1e-8 of the weight (measured: floor 5.38e4, roof -3.41e4, weight
/// -1.96e4); every candidate of the bottom pairs with the floor, of the top
/// with the roof; 1, 2 and 3 ranks agree to 1e-8.
#[test]
fn a_block_between_two_plates() {
    let (dir, msh) = gmsh_2d("obstacles-plates", "tests/obstacles/multi_block2d.geo");
    let args = block2d(
        &msh,
        &[
            "-density",
            "1000",
            "-gravity",
            "0,-9.81",
            "-contact_surface",
            "bottom,top",
            "-obstacles",
            "floor,roof",
            "-obstacle_floor",
            "plane",
            "-obstacle_floor_point",
            "0,0.01",
            "-obstacle_floor_direction",
            "0,-1",
            "-obstacle_roof",
            "plane",
            "-obstacle_roof_point",
            "0,0.99",
            "-obstacle_roof_direction",
            "0,1",
        ],
    );
    let mut runs = Vec::new();
    for n in 1..=3 {
        let (_, report, rows) = solve_rows(&format!("obstacles-plates-{n}"), n, &args);
        runs.push((report, rows));
    }
    let (report, rows) = &runs[0];
    let o = &report.obstacles;
    assert_eq!(o.len(), 2);
    assert_eq!((o[0].name.as_str(), o[1].name.as_str()), ("floor", "roof"));
    let weight = report.load[1];
    let (floor, roof) = (o[0].force[1], o[1].force[1]);
    assert!(
        floor > 1e3 && roof < -1e3,
        "both plates carry load: {floor}, {roof}"
    );
    let imbalance = floor + roof + weight;
    assert!(
        imbalance.abs() < 1e-8 * weight.abs(),
        "floor {floor} + roof {roof} + weight {weight} = {imbalance:e}"
    );
    assert_eq!(
        o[0].contact_nodes + o[1].contact_nodes,
        report.contact_active as usize
    );
    // Every bottom node pushes on the floor (normal -y), every top one on
    // the roof (+y).
    for r in rows {
        let expect = if r.x[1] < 0.5 { -1.0 } else { 1.0 };
        assert_eq!(r.normal[1], expect, "node {} at y = {}", r.node, r.x[1]);
    }
    for (n, (rep, rows_n)) in runs.iter().enumerate().skip(1) {
        let gap = max_pressure_gap(rows_n, rows);
        assert!(gap < 1e-8, "1 and {} ranks: {gap:e}", n + 1);
        let f = rep.obstacles[1].force[1];
        assert!(
            (f - roof).abs() < 1e-8 * roof.abs(),
            "roof {f} on {} ranks against {roof}",
            n + 1
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// On two rigid discs (radius 1, under x = -0.5 and 0.5) under a top
/// traction: the two forces balance the load to 1e-8, each carries half
/// of it within the mesh's asymmetry (1%; measured 1.4e-4), with the
/// closest-point normals leaning outward on both; and a 3-step history
/// writes each obstacle's force per step.
#[test]
fn a_block_on_two_balls() {
    let (dir, msh) = gmsh_2d("obstacles-balls", "tests/obstacles/multi_block2d.geo");
    let table = dir.join("steps.csv");
    let args = block2d(
        &msh,
        &[
            "-traction_top",
            "0,-1e4",
            "-contact_surface",
            "bottom",
            "-obstacles",
            "left,right",
            "-obstacle_left",
            "ball",
            "-obstacle_left_center",
            "-0.5,-1",
            "-obstacle_left_radius",
            "1",
            "-obstacle_right",
            "ball",
            "-obstacle_right_center",
            "0.5,-1",
            "-obstacle_right_radius",
            "1",
        ],
    );
    let (_, report, rows) = solve_rows("obstacles-balls", 2, &args);
    let o = &report.obstacles;
    let load = report.load[1];
    let (l, r) = (o[0].force[1], o[1].force[1]);
    assert!(
        (l + r + load).abs() < 1e-8 * load.abs(),
        "left {l} + right {r} + load {load}"
    );
    assert!((l - r).abs() < 0.01 * l, "left {l} against right {r}");
    assert!(o[0].contact_nodes > 0 && o[1].contact_nodes > 0);
    for row in rows.iter().filter(|r| r.status != "open") {
        // The normal points down and toward the disc's axis below x = -+0.5.
        let side = if row.x[0] < 0.0 { -0.5 } else { 0.5 };
        assert!(row.normal[1] < -0.9, "node {}: {:?}", row.node, row.normal);
        assert!(
            (side - row.x[0]) * row.normal[0] >= -1e-12,
            "node {}: {:?}",
            row.node,
            row.normal
        );
    }
    // A history: the per-obstacle columns.
    let mut h = args.clone();
    let t = table.to_str().unwrap();
    h.extend(["-load_steps", "3", "-history_output", t]);
    let run = mpirun(2, &h);
    assert_eq!(run.status, Some(0), "{}", run.context());
    let text = std::fs::read_to_string(&table).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|c| *c == name)
            .unwrap_or_else(|| panic!("no {name}"))
    };
    let (cl, cr) = (col("contact_force_left_y"), col("contact_force_right_y"));
    let last: Vec<&str> = text.lines().nth(3).unwrap().split(',').collect();
    let (hl, hr): (f64, f64) = (last[cl].parse().unwrap(), last[cr].parse().unwrap());
    assert!(
        (hl - l).abs() < 1e-6 * l && (hr - r).abs() < 1e-6 * r,
        "history {hl}, {hr} against {l}, {r}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad obstacle lists: exit 2 with one line, on 1 and 2 ranks.
#[test]
fn bad_obstacle_lists_are_refused() {
    let (dir, msh) = gmsh_2d("obstacles-bad", "tests/obstacles/multi_block2d.geo");
    let base = ["-traction_top", "0,-1e4", "-contact_surface", "bottom"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "-obstacles",
                "a,b",
                "-obstacle_a",
                "ball",
                "-obstacle_a_center",
                "0,-1",
                "-obstacle_a_radius",
                "1",
            ],
            "option -obstacle_b (plane, ball, halfball, cylinder or mesh) is required",
        ),
        (
            vec!["-obstacles", "a", "-obstacle_a", "disc"],
            "option -obstacle_a: unknown value 'disc'",
        ),
        (
            vec![
                "-obstacles",
                "a",
                "-obstacle_a",
                "plane",
                "-obstacle_a_point",
                "0,0",
            ],
            "option -obstacle_a_direction is required",
        ),
        (
            vec![
                "-obstacles",
                "a",
                "-obstacle_a",
                "ball",
                "-obstacle_a_center",
                "0,-1",
            ],
            "option -obstacle_a_radius is required",
        ),
        (
            vec!["-obstacles", "a,a"],
            "option -obstacles: 'a' is named twice",
        ),
        (
            vec![
                "-obstacles",
                "a",
                "-obstacle",
                "plane",
                "-obstacle_a",
                "plane",
            ],
            "option -obstacle: with -obstacles each obstacle has its own options",
        ),
        (
            vec![
                "-obstacles",
                "a",
                "-obstacle_a",
                "ball",
                "-obstacle_a_center",
                "0,-1,0",
                "-obstacle_a_radius",
                "1",
            ],
            "option -obstacle_a_center: 3 components given, the mesh is 2D",
        ),
        (
            vec![
                "-obstacles",
                "a",
                "-obstacle_a",
                "mesh",
                "-obstacle_a_mesh",
                "nowhere/rim.msh",
            ],
            "option -obstacle_a_mesh: cannot read 'nowhere/rim.msh'",
        ),
    ];
    for (extra, needle) in cases {
        for ranks in [1, 2] {
            let mut args = block2d(&msh, &base);
            args.extend(&extra);
            let run = mpirun(ranks, &args);
            run.refused(&format!("{extra:?}"), 2, &[needle]);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
