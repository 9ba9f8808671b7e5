//! A Gmsh file of 50,000 nodes or more is renumbered for memory locality
//! when read (src/mesh/locality.rs): whatever the file's order of nodes and
//! cells, the answer is the same and keeps the file's tags, and a bad cell
//! is named as the file lists it.

mod common;
use common::*;
use std::fmt::Write as _;
use std::path::Path;

/// The block [0, 3] x [0, 1] in NX x NY squares, two triangles each:
/// 301 x 171 = 51,471 nodes.
const NX: usize = 300;
const NY: usize = 170;
/// The pressure on the top.
const P: f64 = 1e3;

fn node(i: usize, j: usize) -> usize {
    j * (NX + 1) + i
}

fn coords(v: usize) -> [f64; 2] {
    let (i, j) = (v % (NX + 1), v / (NX + 1));
    [3.0 * i as f64 / NX as f64, j as f64 / NY as f64]
}

/// The triangles, counterclockwise, in row order.
fn triangles() -> Vec<[usize; 3]> {
    let mut t = Vec::new();
    for j in 0..NY {
        for i in 0..NX {
            let (a, b, c, d) = (
                node(i, j),
                node(i + 1, j),
                node(i + 1, j + 1),
                node(i, j + 1),
            );
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    t
}

/// A permutation of 0..n from a fixed seed (Fisher-Yates on an LCG).
fn shuffled(n: usize, seed: u64) -> Vec<usize> {
    let mut p: Vec<usize> = (0..n).collect();
    let mut s = seed;
    for i in (1..n).rev() {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        p.swap(i, (s >> 33) as usize % (i + 1));
    }
    p
}

/// Writes the block as Gmsh 2.2: the nodes listed in `node_order` with the
/// tags `tag`, the triangles in `tri_order`, those of `flip` inverted;
/// groups contact (bottom), top, symmetry (left) and the body.
fn write_block(
    path: &Path,
    node_order: &[usize],
    tag: &[u64],
    tri_order: &[usize],
    flip: &[usize],
) {
    let mut s = String::from(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"contact\"\n1 2 \"top\"\n1 3 \"symmetry\"\n2 4 \"body\"\n$EndPhysicalNames\n",
    );
    writeln!(s, "$Nodes\n{}", node_order.len()).unwrap();
    for &v in node_order {
        let [x, y] = coords(v);
        writeln!(s, "{} {x} {y} 0", tag[v]).unwrap();
    }
    let mut lines: Vec<(u32, usize, usize)> = Vec::new();
    for i in 0..NX {
        lines.push((1, node(i, 0), node(i + 1, 0)));
        lines.push((2, node(i + 1, NY), node(i, NY)));
    }
    for j in 0..NY {
        lines.push((3, node(0, j + 1), node(0, j)));
    }
    let tris = triangles();
    writeln!(s, "$EndNodes\n$Elements\n{}", lines.len() + tris.len()).unwrap();
    let mut etag = 0;
    for (g, a, b) in lines {
        etag += 1;
        writeln!(s, "{etag} 1 2 {g} {g} {} {}", tag[a], tag[b]).unwrap();
    }
    for &t in tri_order {
        let [a, mut b, mut c] = tris[t];
        if flip.contains(&t) {
            std::mem::swap(&mut b, &mut c);
        }
        etag += 1;
        writeln!(s, "{etag} 2 2 4 4 {} {} {}", tag[a], tag[b], tag[c]).unwrap();
    }
    s.push_str("$EndElements\n");
    std::fs::write(path, s).unwrap();
}

fn scene(mesh: &str) -> Vec<&str> {
    vec![
        "-mesh",
        mesh,
        "-E",
        "1e6",
        "-nu",
        "0.3",
        "-dirichlet_symmetry",
        "ux=0",
        "-traction_top",
        "0,-1e3",
        "-contact_surface",
        "contact",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0",
        "-ubr_lambda_rtol",
        "1e-9",
    ]
}

/// Uniform pressure on a block resting on a frictionless plane: a uniform
/// stress state, which linear elements reproduce, so the contact stress is
/// P at every bottom node. The block written in its natural order and in a
/// shuffled one (nodes listed in random order under random tags, cells in
/// random order): both exact on 1 and 2 ranks, the same answer node by node,
/// each CSV with its own file's tags.
#[test]
fn any_numbering_of_a_large_file_gives_the_same_answer() {
    let dir = scratch("locality-any-order");
    let n = (NX + 1) * (NY + 1);
    let ntri = 2 * NX * NY;
    let natural = dir.join("natural.msh");
    let natural_tags: Vec<u64> = (1..=n as u64).collect();
    write_block(
        &natural,
        &(0..n).collect::<Vec<_>>(),
        &natural_tags,
        &(0..ntri).collect::<Vec<_>>(),
        &[],
    );
    let shuffled_msh = dir.join("shuffled.msh");
    let perm = shuffled(n, 7);
    let shuffled_tags: Vec<u64> = perm.iter().map(|&p| 10 * p as u64 + 3).collect();
    write_block(
        &shuffled_msh,
        &shuffled(n, 11),
        &shuffled_tags,
        &shuffled(ntri, 13),
        &[],
    );
    let tag_at = |tags: &[u64], x: f64| {
        let i = (x * NX as f64 / 3.0).round() as usize;
        tags[node(i, 0)]
    };
    let mut answers = Vec::new();
    for (mesh, tags) in [(&natural, &natural_tags), (&shuffled_msh, &shuffled_tags)] {
        for ranks in [1, 2] {
            let (_, rep, rows) = solve_rows("locality", ranks, &scene(mesh.to_str().unwrap()));
            assert!(rep.converged, "{rep:?}");
            assert_eq!(rows.len(), NX + 1, "every bottom node a candidate");
            for r in &rows {
                assert!(
                    (r.lambda_n - P).abs() <= 1e-6 * P,
                    "{} -n {ranks}: lambda_n {} at x = {} (exact {P})",
                    mesh.display(),
                    r.lambda_n,
                    r.x[0]
                );
                assert_eq!(
                    r.node,
                    tag_at(tags, r.x[0]),
                    "the file's tag at x = {}",
                    r.x[0]
                );
            }
            let mut by_x: Vec<(f64, f64, f64)> =
                rows.iter().map(|r| (r.x[0], r.un, r.lambda_n)).collect();
            by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
            answers.push(by_x);
        }
    }
    for other in &answers[1..] {
        for (a, b) in answers[0].iter().zip(other) {
            assert_eq!(a.0, b.0);
            assert!(
                (a.2 - b.2).abs() <= 1e-8 * P,
                "lambda_n at x = {}: {} against {}",
                a.0,
                a.2,
                b.2
            );
            assert!(
                (a.1 - b.1).abs() <= 1e-8 * (1.0 + a.1.abs()),
                "u_n at x = {}",
                a.0
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two inverted triangles: the first one the file lists is named (its
/// element tag and its nodes' tags), though the renumbering puts the other,
/// at the origin, first; exit 2 on 1 and 2 ranks.
#[test]
fn the_first_bad_cell_of_the_file_is_named() {
    let dir = scratch("locality-bad-cell");
    let n = (NX + 1) * (NY + 1);
    let ntri = 2 * NX * NY;
    let tags: Vec<u64> = (1..=n as u64).collect();
    // The top right triangle listed first, the one at the origin last.
    let mut order: Vec<usize> = (0..ntri).collect();
    order.swap(0, ntri - 1);
    let (far, origin) = (ntri - 1, 0);
    let msh = dir.join("inverted.msh");
    write_block(
        &msh,
        &(0..n).collect::<Vec<_>>(),
        &tags,
        &order,
        &[far, origin],
    );
    // Element tags: the 2 NX + NY lines, then the triangles in file order.
    let first_tag = 2 * NX + NY + 1;
    let [a, b, c] = triangles()[far];
    let nodes = format!("{} {} {}", tags[a], tags[c], tags[b]);
    for ranks in [1, 2] {
        let run = mpirun(ranks, &scene(msh.to_str().unwrap()));
        assert_eq!(run.status, Some(2), "-n {ranks}: {}", run.context());
        let want = format!("element {first_tag} (nodes {nodes}) is inverted");
        assert!(
            run.stderr.contains(&want),
            "-n {ranks}: want '{want}' in {}",
            run.stderr
        );
        assert_eq!(
            run.stderr
                .lines()
                .filter(|l| l.contains("inverted"))
                .count(),
            1,
            "{}",
            run.stderr
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
