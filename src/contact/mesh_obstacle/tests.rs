//! Tests of the mesh obstacle against exact geometry: a unit cube of 12
//! triangles (given in memory and as STL), a sphere and circles meshed by
//! Gmsh at test time (tests/obstacles/*.geo), and every validation error.

use super::*;
use std::path::PathBuf;
use std::process::Command;

/// A fresh directory for this test's files, removed when dropped unless
/// the test is failing (its files are kept to look at).
fn tmp(name: &str) -> Tmp {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("ubr-meshobs-{}-{call}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    Tmp(d)
}

/// See [`tmp`].
struct Tmp(PathBuf);

impl std::ops::Deref for Tmp {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// Meshes `tests/obstacles/{geo}` with `gmsh -{mdim} -format {format}`:
/// the directory and the mesh's path.
fn gmsh(geo: &str, mdim: usize, format: &str, h: f64) -> (Tmp, PathBuf) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/obstacles")
        .join(geo);
    let dir = tmp(&format!("{geo}-{format}-{h}"));
    let out = dir.join("surface.msh");
    let run = Command::new("gmsh")
        .arg(&src)
        .arg(format!("-{mdim}"))
        .args(["-format", format, "-setnumber", "h", &h.to_string(), "-o"])
        .arg(&out)
        .output()
        .expect("gmsh runs (apt-get install gmsh)");
    assert!(run.status.success() && out.exists(), "gmsh failed on {geo}");
    (dir, out)
}

fn message(r: Result<MeshObstacle, Error>) -> String {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// The unit cube [0, 1]^3: 8 corners (corner `i` at the bits of i, x
/// first) and 12 triangles, oriented outward.
fn cube() -> (Vec<f64>, Vec<usize>) {
    let mut coords = Vec::new();
    for i in 0..8 {
        coords.extend([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
    }
    let c = |i: usize| [coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]];
    let mut elems = Vec::new();
    // Each face: its axis, side, and four corners around it.
    for axis in 0..3 {
        for side in 0..2 {
            let mut quad: Vec<usize> = (0..8).filter(|i| (i >> axis) & 1 == side).collect();
            quad.swap(2, 3); // around the face, not across it
            let (a, b, d) = (c(quad[0]), c(quad[1]), c(quad[2]));
            let n = geom::cross(&geom::sub(&b, &a), &geom::sub(&d, &a));
            let outward = if side == 1 { 1.0 } else { -1.0 };
            if n[axis] * outward < 0.0 {
                quad.reverse();
            }
            elems.extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
        }
    }
    (coords, elems)
}

/// The exact signed distance to the unit cube.
fn cube_sdf(x: &[f64]) -> f64 {
    let q: Vec<f64> = x.iter().map(|&v| (v - 0.5).abs() - 0.5).collect();
    let out: f64 = q.iter().map(|v| v.max(0.0).powi(2)).sum::<f64>().sqrt();
    out + q.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v)).min(0.0)
}

/// A deterministic generator of points in [lo, hi)^3.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn point(&mut self, dim: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..dim).map(|_| lo + (hi - lo) * self.next()).collect()
    }
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

/// A query point, its gap, normal and closest point.
type Case = ([f64; 3], f64, [f64; 3], [f64; 3]);

#[test]
fn cube_exact_at_faces_edges_corners() {
    let (coords, elems) = cube();
    let ob = MeshObstacle::from_elements(3, &coords, &elems, "cube").unwrap();
    assert!(ob.is_closed());
    ob.require_closed().unwrap();
    assert!((ob.enclosed_volume() - 1.0).abs() < 1e-14);
    let s = 0.5f64.sqrt();
    let r3 = (1.0f64 / 3.0).sqrt();
    // (x, gap, normal, point)
    let cases: [Case; 9] = [
        ([0.5, 0.5, 1.3], 0.3, [0.0, 0.0, -1.0], [0.5, 0.5, 1.0]),
        ([0.3, 0.6, 0.9], -0.1, [0.0, 0.0, -1.0], [0.3, 0.6, 1.0]),
        ([-0.2, 0.4, 0.7], 0.2, [1.0, 0.0, 0.0], [0.0, 0.4, 0.7]),
        (
            [1.2, 0.5, 1.2],
            0.08f64.sqrt(),
            [-s, 0.0, -s],
            [1.0, 0.5, 1.0],
        ),
        (
            [1.1, 1.2, 1.3],
            0.14f64.sqrt(),
            [-1.0, -2.0, -3.0],
            [1.0, 1.0, 1.0],
        ),
        ([0.95, 0.9, 0.97], -0.03, [0.0, 0.0, -1.0], [0.95, 0.9, 1.0]),
        // On the surface: the reversed pseudo-normal, at a face, an edge, a corner.
        ([0.5, 0.25, 0.0], 0.0, [0.0, 0.0, 1.0], [0.5, 0.25, 0.0]),
        ([1.0, 0.5, 1.0], 0.0, [-s, 0.0, -s], [1.0, 0.5, 1.0]),
        ([1.0, 1.0, 1.0], 0.0, [-r3, -r3, -r3], [1.0, 1.0, 1.0]),
    ];
    for (x, gap, n, p) in cases {
        let c = ob.closest(&x).unwrap();
        let n = geom::unit(&n);
        assert!(
            (c.gap - gap).abs() < 1e-14,
            "{x:?}: gap {} not {gap}",
            c.gap
        );
        assert!(
            close(&c.normal, &n, 1e-14),
            "{x:?}: normal {:?} not {n:?}",
            c.normal
        );
        assert!(
            close(&c.point, &p, 1e-14),
            "{x:?}: point {:?} not {p:?}",
            c.point
        );
    }
}

#[test]
fn cube_signs_near_edges_and_corners() {
    let (coords, elems) = cube();
    let ob = MeshObstacle::from_elements(3, &coords, &elems, "cube").unwrap();
    let mut probes: Vec<Vec<f64>> = Vec::new();
    // Just inside and outside every corner and every edge's midpoint
    // (where the closest point is a vertex or an edge of the mesh).
    for eps in [1e-9, 1e-6, 1e-3] {
        for i in 0..8 {
            let corner: Vec<f64> = (0..3).map(|k| ((i >> k) & 1) as f64).collect();
            for sign in [-1.0, 1.0] {
                probes.push(
                    corner
                        .iter()
                        .map(|&c| c + sign * eps * (2.0 * c - 1.0))
                        .collect(),
                );
                for free in 0..3 {
                    let mut x: Vec<f64> = corner
                        .iter()
                        .map(|&c| c + sign * eps * (2.0 * c - 1.0))
                        .collect();
                    x[free] = 0.5;
                    probes.push(x);
                }
            }
        }
    }
    // And random points about the cube.
    let mut rng = Lcg(7);
    probes.extend((0..20000).map(|_| rng.point(3, -0.5, 1.5)));
    for x in &probes {
        let c = ob.closest(x).unwrap();
        let exact = cube_sdf(x);
        assert!(
            (c.gap - exact).abs() < 1e-12,
            "{x:?}: gap {} not {exact}",
            c.gap
        );
        // The normal points along point - x outside, x - point inside.
        let d: Vec<f64> = c.point.iter().zip(x).map(|(p, q)| p - q).collect();
        let along: f64 = d.iter().zip(&c.normal).map(|(a, b)| a * b).sum();
        assert!(
            (along - c.gap).abs() < 1e-12,
            "{x:?}: normal {:?}",
            c.normal
        );
    }
}

#[test]
fn search_distance_treats_far_points_as_open() {
    let (coords, elems) = cube();
    let ob = MeshObstacle::from_elements(3, &coords, &elems, "cube")
        .unwrap()
        .with_search_distance(0.25);
    assert!(ob.closest(&[0.5, 0.5, 1.2]).is_some());
    assert!(ob.closest(&[0.5, 0.5, 1.3]).is_none());
    assert!(ob.closest(&[0.5, 0.5, 0.5]).is_none(), "0.5 deep");
    assert!(ob.closest(&[0.5, 0.5, 0.8]).is_some());
}

/// Largest circumradius of the triangles, and the chordal error of a
/// mesh of the unit sphere whose nodes lie on it: every point of a
/// triangle is at a distance from the centre in [sqrt(1 - rc^2), 1].
fn sphere_chordal_error(ob: &MeshObstacle) -> (f64, f64) {
    let s = &ob.surface;
    let mut rc_max: f64 = 0.0;
    for c in &s.elems {
        let [a, b, d] = c.map(|i| s.coords[i]);
        let (ab, bd, da) = (geom::sub(&b, &a), geom::sub(&d, &b), geom::sub(&a, &d));
        let area2 = geom::norm(&geom::cross(&ab, &da));
        rc_max = rc_max.max(geom::norm(&ab) * geom::norm(&bd) * geom::norm(&da) / (2.0 * area2));
    }
    (rc_max, 1.0 - (1.0 - rc_max * rc_max).sqrt())
}

/// A point at radius in [0.3, 0.95] or [1.05, 1.7], in any direction.
fn shell_point(rng: &mut Lcg, dim: usize) -> Vec<f64> {
    loop {
        let x = rng.point(dim, -1.7, 1.7);
        let r = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if (0.3..=0.95).contains(&r) || (1.05..=1.7).contains(&r) {
            return x;
        }
    }
}

/// Signed distance within the chordal error `eps` of the exact |x| - 1
/// (the mesh lies between the spheres of radii 1 - eps and 1), and the
/// normal within `max_angle` of the exact -x/|x|; returns the largest angle.
fn check_against_unit_ball(ob: &MeshObstacle, eps: f64, max_angle: f64, dim: usize) -> f64 {
    let mut rng = Lcg(11);
    let mut worst: f64 = 0.0;
    for _ in 0..5000 {
        let x = shell_point(&mut rng, dim);
        let r = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        let c = ob.closest(&x).unwrap();
        let err = c.gap - (r - 1.0);
        assert!(
            (-1e-12..=eps + 1e-12).contains(&err),
            "{x:?}: gap {} at r = {r} (eps {eps})",
            c.gap
        );
        let cos: f64 = -c.normal.iter().zip(&x).map(|(n, v)| n * v).sum::<f64>() / r;
        let angle = cos.min(1.0).acos();
        worst = worst.max(angle);
        assert!(
            angle <= max_angle,
            "{x:?}: normal {:?} at {angle} rad",
            c.normal
        );
    }
    worst
}

#[test]
fn gmsh_sphere_against_exact_sphere() {
    for format in ["msh41", "msh22"] {
        let (_dir, path) = gmsh("sphere.geo", 2, format, 0.15);
        let ob = MeshObstacle::read(&path, 3).unwrap();
        ob.require_closed().unwrap();
        let (rc, eps) = sphere_chordal_error(&ob);
        let ball = 4.0 / 3.0 * std::f64::consts::PI;
        let v = ob.enclosed_volume();
        // Outward normals, and the volume of an inscribed polyhedron.
        assert!(
            v > ball * (1.0 - eps).powi(3) && v < ball,
            "{format}: volume {v}"
        );
        let worst = check_against_unit_ball(&ob, eps, 2.0 * rc.asin(), 3);
        println!(
            "sphere {format}: {} triangles, chordal error {eps:.2e}, worst normal {worst:.3} rad (bound {:.3})",
            ob.len(),
            2.0 * rc.asin()
        );
    }
}

/// The chordal error of a mesh of the unit circle whose nodes lie on it.
fn circle_chordal_error(ob: &MeshObstacle) -> (f64, f64) {
    let s = &ob.surface;
    let half = s
        .elems
        .iter()
        .map(|c| geom::norm(&geom::sub(&s.coords[c[1]], &s.coords[c[0]])) / 2.0)
        .fold(0.0, f64::max);
    (half, 1.0 - (1.0 - half * half).sqrt())
}

#[test]
fn gmsh_circle_counter_clockwise_is_a_disc() {
    for format in ["msh41", "msh22"] {
        let (_dir, path) = gmsh("circles.geo", 1, format, 0.1);
        let rim = MeshObstacle::read_group(&path, 2, Some("rim")).unwrap();
        rim.require_closed().unwrap();
        let (half, eps) = circle_chordal_error(&rim);
        let pi = std::f64::consts::PI;
        let a = rim.enclosed_volume();
        assert!(a > pi * (1.0 - eps).powi(2) && a < pi, "{format}: area {a}");
        let worst = check_against_unit_ball(&rim, eps, 2.0 * half.asin(), 2);
        println!(
            "circle {format}: {} segments, chordal error {eps:.2e}, worst normal {worst:.3} rad",
            rim.len()
        );
        // The other circle, by name and by number; both together.
        let other = MeshObstacle::read_group(&path, 2, Some("other")).unwrap();
        assert!(
            (other.enclosed_volume() - pi / 4.0).abs() < 0.02,
            "{format}"
        );
        let by_tag = MeshObstacle::read_group(&path, 2, Some("2")).unwrap();
        assert_eq!(by_tag.len(), other.len());
        let both = MeshObstacle::read(&path, 2).unwrap();
        assert_eq!(both.len(), rim.len() + other.len());
        both.require_closed().unwrap();
        // Inside the other circle (radius 0.5), within its chordal error.
        let (half_other, _) = circle_chordal_error(&other);
        let eps_other = 0.5 - (0.25 - half_other * half_other).sqrt();
        let c = both.closest(&[5.0, 0.1]).unwrap();
        let err = c.gap + 0.4;
        assert!((0.0..=eps_other + 1e-12).contains(&err), "{format}: {c:?}");
        // Two connected parts; the other circle alone reversed (a hole):
        // the point inside it is now outside the obstacle, by as much, on
        // the same part, and the rim is unchanged.
        assert_eq!(both.components(), 2);
        let part = c.component;
        assert_eq!(both.closest(&[0.0, 0.1]).unwrap().component, 1 - part);
        let mut flip = vec![false; 2];
        flip[part] = true;
        let before = both.enclosed_volume();
        let holed = both.clone().reversed(&flip).unwrap();
        let h = holed.closest(&[5.0, 0.1]).unwrap();
        assert!(
            (h.gap + c.gap).abs() < 1e-12 && h.component == part,
            "{h:?}"
        );
        let r = holed.closest(&[0.0, 0.1]).unwrap();
        assert_eq!(r, both.closest(&[0.0, 0.1]).unwrap());
        let after = holed.enclosed_volume();
        assert!(
            (before - after - 2.0 * other.enclosed_volume()).abs() < 1e-12,
            "{format}"
        );
        let e = message(MeshObstacle::read_group(&path, 2, Some("nope")));
        assert!(
            e.contains("no physical group 'nope' of dimension 1 (the file has: other, rim)"),
            "{e}"
        );
    }
}

#[test]
fn orientation_convention_2d_and_3d() {
    // 2D: segment (0,0) -> (1,0) has outward normal (0, -1).
    let seg = MeshObstacle::from_elements(2, &[0.0, 0.0, 1.0, 0.0], &[0, 1], "seg").unwrap();
    assert!(!seg.is_closed());
    let c = seg.closest(&[0.5, -2.0]).unwrap();
    assert_eq!(
        (c.gap, c.normal, c.point),
        (2.0, vec![0.0, 1.0], vec![0.5, 0.0])
    );
    assert_eq!(seg.closest(&[0.25, 0.5]).unwrap().gap, -0.5);
    // A clockwise square is a hole: its centre is outside.
    let sq = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
    let ccw = MeshObstacle::from_elements(2, &sq, &[0, 1, 1, 2, 2, 3, 3, 0], "ccw").unwrap();
    let cw = MeshObstacle::from_elements(2, &sq, &[1, 0, 2, 1, 3, 2, 0, 3], "cw").unwrap();
    assert_eq!((ccw.enclosed_volume(), cw.enclosed_volume()), (1.0, -1.0));
    assert_eq!(ccw.closest(&[0.5, 0.4]).unwrap().gap, -0.4);
    assert_eq!(cw.closest(&[0.5, 0.4]).unwrap().gap, 0.4);
    // At a corner, outside and inside (the vertex pseudo-normal).
    let c = ccw.closest(&[1.3, 1.4]).unwrap();
    assert!((c.gap - 0.5).abs() < 1e-15 && close(&c.normal, &[-0.6, -0.8], 1e-15));
    assert!((cw.closest(&[1.3, 1.4]).unwrap().gap + 0.5).abs() < 1e-15);
    // 3D: triangle (0,0,0), (1,0,0), (0,1,0) has outward normal +z.
    let tri = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let t = MeshObstacle::from_elements(3, &tri, &[0, 1, 2], "tri").unwrap();
    let c = t.closest(&[0.2, 0.2, 3.0]).unwrap();
    assert!(
        c.gap == 3.0 && close(&c.normal, &[0.0, 0.0, -1.0], 1e-15),
        "{c:?}"
    );
}

/// The cube as ASCII STL (CRLF line ends, two solids) and binary STL.
fn cube_stl(dir: &Path) -> (PathBuf, PathBuf) {
    let (coords, elems) = cube();
    let v = |i: usize| [coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]];
    let mut ascii = String::from("solid cube part one\r\n");
    let mut binary = vec![b' '; 80];
    binary.extend(12u32.to_le_bytes());
    for (t, f) in elems.chunks_exact(3).enumerate() {
        if t == 6 {
            ascii.push_str("endsolid cube part one\r\nsolid two\r\n");
        }
        ascii.push_str("  facet normal 0 0 0\r\n    outer loop\r\n");
        binary.extend([0u8; 12]);
        for &i in f {
            let p = v(i);
            ascii.push_str(&format!("      vertex {:e} {} {}\r\n", p[0], p[1], p[2]));
            for x in p {
                binary.extend((x as f32).to_le_bytes());
            }
        }
        ascii.push_str("    endloop\r\n  endfacet\r\n");
        binary.extend([0u8; 2]);
    }
    ascii.push_str("endsolid two\r\n");
    let (a, b) = (dir.join("cube.stl"), dir.join("cube-binary.stl"));
    std::fs::write(&a, ascii).unwrap();
    std::fs::write(&b, binary).unwrap();
    (a, b)
}

/// The cube as MSH 2.2 with six quadrilaterals, and a point and a
/// tetrahedron that a 3D obstacle skips.
fn cube_quads_msh(dir: &Path) -> PathBuf {
    let (coords, elems) = cube();
    let mut s = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n");
    for (i, p) in coords.chunks_exact(3).enumerate() {
        s.push_str(&format!("{} {} {} {}\n", 10 + i, p[0], p[1], p[2]));
    }
    s.push_str("$EndNodes\n$Elements\n8\n1 15 2 0 1 10\n");
    for (q, t) in elems.chunks_exact(6).enumerate() {
        let n = [t[0], t[1], t[2], t[5]].map(|i| 10 + i);
        s.push_str(&format!(
            "{} 3 2 0 1 {} {} {} {}\n",
            q + 2,
            n[0],
            n[1],
            n[2],
            n[3]
        ));
    }
    s.push_str("8 4 2 0 1 10 11 12 14\n$EndElements\n");
    let path = dir.join("cube-quads.msh");
    std::fs::write(&path, s).unwrap();
    path
}

#[test]
fn stl_and_quadrilaterals_read_as_the_cube() {
    let (coords, elems) = cube();
    let exact = MeshObstacle::from_elements(3, &coords, &elems, "cube").unwrap();
    let dir = tmp("stl");
    let (ascii, binary) = cube_stl(&dir);
    let quads = cube_quads_msh(&dir);
    let mut rng = Lcg(3);
    let probes: Vec<Vec<f64>> = (0..2000).map(|_| rng.point(3, -0.5, 1.5)).collect();
    for path in [&ascii, &binary, &quads] {
        let ob = MeshObstacle::read(path, 3).unwrap();
        assert_eq!((ob.len(), ob.surface.coords.len()), (12, 8), "{path:?}");
        ob.require_closed().unwrap();
        for x in &probes {
            let (a, b) = (ob.closest(x).unwrap(), exact.closest(x).unwrap());
            assert!((a.gap - b.gap).abs() < 1e-15, "{path:?} {x:?}: {a:?} {b:?}");
        }
    }
    let e = message(MeshObstacle::read(&ascii, 2));
    assert!(
        e.contains("an STL file is a 3D surface, the body is 2D"),
        "{e}"
    );
    let e = message(MeshObstacle::read_group(&binary, 3, Some("top")));
    assert!(e.contains("has no physical groups"), "{e}");
}

/// The message of reading `text` as the surface of a `dim`-D obstacle.
fn read_error(text: &str, dim: usize) -> String {
    let dir = tmp("bad");
    let path = dir.join(format!("bad-{:x}.msh", text.len() * 31 + dim));
    std::fs::write(&path, text).unwrap();
    let e = message(MeshObstacle::read(&path, dim));
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.starts_with(&format!("error: option -obstacle_mesh: {}", path.display())),
        "{e}"
    );
    e
}

const ONE_TRIANGLE: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n\
                            3 0 1 0\n$EndNodes\n$Elements\n1\n7 2 0 1 2 3\n$EndElements\n";

#[test]
fn file_errors_name_the_file_and_line() {
    assert!(
        read_error(ONE_TRIANGLE, 2).ends_with("no line elements (the boundary of a 2D obstacle)")
    );
    let lines = ONE_TRIANGLE.replace("7 2 0 1 2 3", "7 1 0 1 2");
    let e = read_error(&lines, 3);
    assert!(
        e.ends_with("no triangles or quadrilaterals (the surface of a 3D obstacle)"),
        "{e}"
    );
    let e = read_error(&ONE_TRIANGLE.replace("2.2 0 8", "2.2 1 8"), 3);
    assert!(e.contains(":2: a binary MSH file"), "{e}");
    let e = read_error(&ONE_TRIANGLE.replace("3 0 1 0", "3 0 x 0"), 3);
    assert!(e.contains(":8: bad coordinate `x`"), "{e}");
    let e = read_error(&ONE_TRIANGLE.replace("1 2 3\n", "1 2 4\n"), 3);
    assert!(
        e.contains(":12: element 7 refers to undefined node 4"),
        "{e}"
    );
    let e = read_error(&ONE_TRIANGLE.replace("7 2 0 1 2 3", "7 9 0 1 2 3 4 5 6"), 3);
    assert!(e.contains(":12: higher-order element (Gmsh type 9)"), "{e}");
    let e = read_error(&ONE_TRIANGLE.replace("$EndElements\n", ""), 3);
    assert!(e.contains("unexpected end of file in $Elements"), "{e}");
    let e = read_error(&format!("{ONE_TRIANGLE}$Nodes\n0\n$EndNodes\n"), 3);
    assert!(e.contains(":14: a second $Nodes section"), "{e}");
    let e = read_error("hello\n", 3);
    assert!(
        e.ends_with("not a Gmsh mesh ($MeshFormat) or an STL file (solid ...)"),
        "{e}"
    );
    // The geometry instead of its mesh.
    let dir = tmp("floor");
    let geo = dir.join("floor.geo");
    std::fs::write(&geo, "Point(1) = {0, 0, 0};\n").unwrap();
    let e = message(MeshObstacle::read(&geo, 3));
    assert!(
        e.ends_with(
            "a .geo file is Gmsh's geometry; mesh it first (gmsh -1 or -2 FILE.geo -o FILE.msh)"
        ),
        "{e}"
    );
    let e = read_error(
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nendloop\n",
        3,
    );
    assert!(e.contains(":5: expected `vertex`, found `endloop`"), "{e}");
    let tilted = lines.replace("3 0 1 0", "3 0 1 0.5");
    let e = read_error(
        &tilted.replace("1\n7 1 0 1 2", "2\n7 1 0 1 2\n8 1 0 2 3"),
        2,
    );
    assert!(
        e.contains("not in a plane z = constant: node 3 has z = 0.5"),
        "{e}"
    );
}

#[test]
fn surface_errors_name_the_element_or_node() {
    let (coords, elems) = cube();
    let err = |coords: &[f64], elems: &[usize]| {
        let e = message(MeshObstacle::from_elements(3, coords, elems, "cube"));
        assert!(e.starts_with("error: option -obstacle_mesh: cube: "), "{e}");
        e
    };
    // Degenerate: a triangle with its third corner on its first edge.
    let mut flat = coords.clone();
    flat.extend([0.5, 0.0, 0.0]);
    let e = err(&flat, &[0, 1, 8]);
    assert!(
        e.ends_with("element 1 (node 1, node 2, node 9) is degenerate (zero area)"),
        "{e}"
    );
    // Flipped: the fourth triangle reversed.
    let mut flipped = elems.clone();
    flipped.swap(10, 11);
    let e = err(&coords, &flipped);
    assert!(
        e.contains("traverse their shared edge") && e.contains("inconsistent orientation"),
        "{e}"
    );
    assert!(e.contains("element 4"), "{e}");
    // Non-manifold: a fin on the edge from corner 0 to corner 1.
    let mut fin = elems.clone();
    let mut fin_coords = coords.clone();
    fin_coords.extend([0.5, -1.0, -1.0]);
    fin.extend([1, 0, 8]);
    let e = err(&fin_coords, &fin);
    assert!(
        e.contains("edge (node 1, node 2) is in 3 triangles (")
            && e.ends_with("not a manifold surface"),
        "{e}"
    );
    // Open: the last triangle missing.
    let open = MeshObstacle::from_elements(3, &coords, &elems[..33], "cube").unwrap();
    assert!(!open.is_closed());
    let e = open.require_closed().unwrap_err().to_string();
    assert!(
        e.starts_with("error: option -obstacle_mesh: cube: the surface is open: edge (node "),
        "{e}"
    );
    assert!(
        e.ends_with("(3 open edges in all); the signed distance needs a closed surface"),
        "{e}"
    );
}

#[test]
fn curve_errors_name_the_element_or_node() {
    let sq = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0];
    let err = |elems: &[usize]| message(MeshObstacle::from_elements(2, &sq, elems, "sq"));
    let e = err(&[0, 1, 1, 2, 2, 3, 4, 0]);
    assert!(
        e.ends_with("element 4 (node 5, node 1) is degenerate (zero length)"),
        "{e}"
    );
    let e = err(&[0, 1, 2, 1, 2, 3, 3, 0]);
    assert!(e.ends_with("element 1 and element 2 both end at node 2: inconsistent orientation (each segment must end where the next one starts; Gmsh writes a line's elements its own way, whatever sign a Curve Loop gives it: draw the lines head to tail, or turn one with Reverse Curve {n};)"), "{e}");
    let e = err(&[0, 1, 1, 2, 2, 0, 1, 3]);
    assert!(
        e.ends_with(
            "node 2 is in 3 segments (element 1, element 2, element 4): not a manifold curve"
        ),
        "{e}"
    );
    let open = MeshObstacle::from_elements(2, &sq, &[0, 1, 1, 2], "sq").unwrap();
    let e = open.require_closed().unwrap_err().to_string();
    assert!(e.ends_with("the surface is open: node 1 is an end of element 1 only (2 open ends in all); the signed distance needs a closed surface"), "{e}");
}

/// The time of `closest` at each of `probes`, and their mean gap.
fn time_queries(ob: &MeshObstacle, probes: &[Vec<f64>]) -> (std::time::Duration, f64) {
    let t = std::time::Instant::now();
    let mut sum = 0.0;
    for x in probes {
        sum += ob.closest(x).map_or(0.0, |c| c.gap);
    }
    (t.elapsed(), sum / probes.len() as f64)
}

#[test]
fn timing_1e5_queries_on_2e4_triangles() {
    let (_dir, path) = gmsh("sphere.geo", 2, "msh41", 0.038);
    let t0 = std::time::Instant::now();
    let ob = MeshObstacle::read(&path, 3).unwrap();
    let read = t0.elapsed();
    assert!(ob.len() > 15_000, "{} triangles", ob.len());
    println!(
        "sphere: {} triangles read and indexed in {read:?}",
        ob.len()
    );
    let mut rng = Lcg(5);
    // Within 0.1 of the surface (where contact candidates are), then
    // anywhere in [-1.5, 1.5]^3 (deep inside, every box is about as near).
    let near: Vec<Vec<f64>> = (0..100_000)
        .map(|_| loop {
            let x = rng.point(3, -1.1, 1.1);
            let r = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            if (r - 1.0).abs() < 0.1 {
                break x;
            }
        })
        .collect();
    let any: Vec<Vec<f64>> = (0..100_000).map(|_| rng.point(3, -1.5, 1.5)).collect();
    for (what, probes) in [
        ("within 0.1 of the surface", &near),
        ("in [-1.5, 1.5]^3", &any),
    ] {
        let (t, mean) = time_queries(&ob, probes);
        println!("sphere: 1e5 queries {what} in {t:?} (mean gap {mean:.3})");
    }
    let ob = ob.with_search_distance(0.1);
    let (t, _) = time_queries(&ob, &any);
    println!("sphere: 1e5 queries in [-1.5, 1.5]^3, search distance 0.1, in {t:?}");
}

/// Whether `x` is inside the tetrahedron or triangle with corners `c`
/// (barycentric coordinates, from signed volumes or areas).
fn in_simplex(c: &[V3], x: &V3) -> bool {
    let vol = |p: &[V3]| match p.len() {
        4 => geom::dot(
            &geom::sub(&p[1], &p[0]),
            &geom::cross(&geom::sub(&p[2], &p[0]), &geom::sub(&p[3], &p[0])),
        ),
        _ => geom::cross(&geom::sub(&p[1], &p[0]), &geom::sub(&p[2], &p[0]))[2],
    };
    let total = vol(c);
    (0..c.len()).all(|i| {
        let mut p = c.to_vec();
        p[i] = *x;
        vol(&p) / total >= 0.0
    })
}

/// A thin simplex (sharp edges and corners, where a face normal alone
/// gives the wrong sign) and its cavity (reflex edges): the sign of the
/// gap at random points matches a point-in-simplex test, and its size
/// the distance to the nearest element.
#[test]
fn sharp_simplex_signs_from_pseudo_normals() {
    let tet: [V3; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 0.15, 0.0],
        [0.45, 0.05, 2.0],
    ];
    let tri: [V3; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.08, 0.0]];
    // Faces of the tetrahedron with outward normals (its volume is positive).
    let tet_faces = [0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2];
    let tri_segs = [0, 1, 1, 2, 2, 0];
    let mut rng = Lcg(13);
    for (dim, corners, elems) in [(3, &tet[..], &tet_faces[..]), (2, &tri[..], &tri_segs[..])] {
        let coords: Vec<f64> = corners.iter().flat_map(|p| p[..dim].to_vec()).collect();
        let solid = MeshObstacle::from_elements(dim, &coords, elems, "solid").unwrap();
        let flipped: Vec<usize> = elems
            .chunks_exact(dim)
            .flat_map(|c| c.iter().rev().copied())
            .collect();
        let cavity = MeshObstacle::from_elements(dim, &coords, &flipped, "cavity").unwrap();
        assert!(solid.enclosed_volume() > 0.0 && cavity.enclosed_volume() < 0.0);
        let mut inside_hits = 0;
        for _ in 0..20000 {
            let mut x = rng.point(dim, -0.3, 1.3);
            if dim == 3 {
                x[2] = 2.6 * x[2] - 0.5;
            }
            let q = [x[0], x[1], x.get(2).copied().unwrap_or(0.0)];
            let inside = in_simplex(corners, &q);
            inside_hits += usize::from(inside);
            let dist = solid
                .surface
                .elems
                .iter()
                .map(|c| {
                    let p = if dim == 3 {
                        geom::closest_on_triangle(
                            &q,
                            &corners[c[0]],
                            &corners[c[1]],
                            &corners[c[2]],
                        )
                        .0
                    } else {
                        geom::closest_on_segment(&q, &corners[c[0]], &corners[c[1]]).0
                    };
                    geom::norm(&geom::sub(&q, &p))
                })
                .fold(f64::INFINITY, f64::min);
            let want = if inside { -dist } else { dist };
            let (a, b) = (solid.closest(&x).unwrap(), cavity.closest(&x).unwrap());
            assert!(
                (a.gap - want).abs() < 1e-12,
                "{dim}D solid {x:?}: {} not {want}",
                a.gap
            );
            assert!(
                (b.gap + want).abs() < 1e-12,
                "{dim}D cavity {x:?}: {} not {}",
                b.gap,
                -want
            );
        }
        assert!(inside_hits > 50, "{dim}D: {inside_hits} points inside");
    }
}
