use super::*;
use std::path::PathBuf;
use std::process::Command;

/// A fresh empty directory for one test.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ubr-vtk-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create a temporary directory");
    dir
}

/// The Python interpreter for the reader checks: `UBR_PYTHON` if set,
/// else Debian's `/usr/bin/python3` (where `apt-get install
/// python3-meshio python3-vtk9` puts the modules; a `python3` earlier on
/// the PATH, e.g. pyenv's, does not see them), else `python3`.
fn python() -> String {
    if let Ok(p) = std::env::var("UBR_PYTHON") {
        return p;
    }
    if Path::new("/usr/bin/python3").exists() {
        return "/usr/bin/python3".into();
    }
    "python3".into()
}

/// Runs a Python script with arguments and parses its standard output
/// as JSON; panics with a clear message if the module is missing.
fn run_python(module: &str, package: &str, script: &str, args: &[&Path]) -> serde_json::Value {
    let py = python();
    let probe = Command::new(&py)
        .arg("-c")
        .arg(format!("import {module}"))
        .output();
    match probe {
        Ok(o) if o.status.success() => {}
        Ok(o) => panic!(
            "these tests read the files back with Python's {module}, which {py} cannot \
             import: install Debian's {package} (apt-get install -y {package}) or set \
             UBR_PYTHON to an interpreter that has it.\n{}",
            String::from_utf8_lossy(&o.stderr)
        ),
        Err(e) => panic!(
            "these tests need a Python interpreter with {module} ({package}); cannot run \
             '{py}': {e}. Install Debian's python3 and {package}, or set UBR_PYTHON."
        ),
    }
    let out = Command::new(&py)
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("run python");
    assert!(
        out.status.success(),
        "the {module} reader failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "reader output is not JSON ({e}):\n{}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

const MESHIO_DUMP: &str = r#"
import json, sys
import meshio, numpy
# Values go as the hex of their little-endian float64 bytes: exact.
h = lambda a: numpy.asarray(a, dtype="<f8").tobytes().hex()
m = meshio.read(sys.argv[1])
out = {
    "points": h(m.points),
    "cells": [[b.type, h(b.data)] for b in m.cells],
    "point_data": {k: [str(v.dtype), list(v.shape), h(v)] for k, v in m.point_data.items()},
    "cell_data": {k: [str(v[0].dtype), list(v[0].shape), h(v[0])] for k, v in m.cell_data.items()},
}
print(json.dumps(out))
"#;

const VTK_DUMP: &str = r#"
import json, sys
import numpy, vtk
from vtk.util.numpy_support import vtk_to_numpy
# Values go as the hex of their little-endian float64 bytes: exact.
h = lambda a: numpy.asarray(a, dtype="<f8").tobytes().hex()
path = sys.argv[1]
r = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
errors = []
def on_error(obj, ev):
    errors.append(ev)
r.AddObserver("ErrorEvent", on_error)
r.GetExecutive().AddObserver("ErrorEvent", on_error)
r.SetFileName(path)
r.Update()
if r.GetErrorCode() != 0 or errors:
    sys.exit("vtk reported errors reading " + path)
g = r.GetOutput()
def arrays(d):
    out = {}
    for i in range(d.GetNumberOfArrays()):
        a = d.GetArray(i)
        out[a.GetName()] = [a.GetDataTypeAsString(), a.GetNumberOfComponents(), h(vtk_to_numpy(a))]
    return out
pts = g.GetPoints()
cells = []
for c in range(g.GetNumberOfCells()):
    cell = g.GetCell(c)
    cells.append([g.GetCellType(c), [cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]])
print(json.dumps({
    "num_points": g.GetNumberOfPoints(),
    "num_cells": g.GetNumberOfCells(),
    "points": h(vtk_to_numpy(pts.GetData())) if pts is not None else "",
    "cells": cells,
    "point_data": arrays(g.GetPointData()),
    "cell_data": arrays(g.GetCellData()),
}))
"#;

/// Owned data of a test piece.
struct Data {
    dim: usize,
    coords: Vec<f64>,
    cells: Vec<usize>,
    offsets: Vec<usize>,
    p_scalar: Vec<f64>,
    p_vector: Vec<f64>,
    p_tensor: Vec<f64>,
    p_int: Vec<i32>,
    c_scalar: Vec<f64>,
    c_vector: Vec<f64>,
    c_tensor: Vec<f64>,
    c_int: Vec<i32>,
}

impl Data {
    fn piece(&self) -> Piece<'_> {
        Piece {
            dim: self.dim,
            coords: &self.coords,
            cells: &self.cells,
            offsets: &self.offsets,
            point_data: vec![
                Field::Scalar("gap", &self.p_scalar),
                Field::Vector("displacement", &self.p_vector),
                Field::Tensor("stress_nodal", &self.p_tensor),
                Field::Int("status", &self.p_int),
            ],
            cell_data: vec![
                Field::Scalar("von_mises", &self.c_scalar),
                Field::Vector("traction", &self.c_vector),
                Field::Tensor("stress", &self.c_tensor),
                Field::Int("rank", &self.c_int),
            ],
        }
    }

    /// The values as they must appear in the file (3 / 9 components).
    fn expanded_vector(v: &[f64], dim: usize, n: usize) -> Vec<f64> {
        if v.len() == 3 * n || dim == 3 {
            return v.to_vec();
        }
        v.chunks(2).flat_map(|e| [e[0], e[1], 0.0]).collect()
    }
    fn expanded_tensor(v: &[f64], dim: usize, n: usize) -> Vec<f64> {
        if v.len() == 9 * n || dim == 3 {
            return v.to_vec();
        }
        v.chunks(4)
            .flat_map(|e| [e[0], e[1], 0.0, e[2], e[3], 0.0, 0.0, 0.0, 0.0])
            .collect()
    }
    fn points3(&self) -> Vec<f64> {
        if self.dim == 3 {
            return self.coords.clone();
        }
        self.coords
            .chunks(2)
            .flat_map(|p| [p[0], p[1], 0.0])
            .collect()
    }
}

/// Two triangles of the unit square, shifted by `dx`; 2-component
/// point vectors and 2x2 cell tensors (padded by the writer), full-width
/// cell vectors and point tensors.
fn two_triangles(dx: f64, rank: i32) -> Data {
    Data {
        dim: 2,
        coords: vec![dx, 0.0, dx + 1.0, 0.0, dx + 1.0, 1.0, dx, 1.0],
        cells: vec![0, 1, 2, 0, 2, 3],
        offsets: vec![],
        p_scalar: vec![0.5, -1.25, 1e-300, 3.0e12],
        p_vector: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0],
        p_tensor: (0..36).map(|i| i as f64 * 0.5 + dx).collect(),
        p_int: vec![0, 1, 2, 3],
        c_scalar: vec![10.0 + dx, 20.0 + dx],
        c_vector: vec![0.1, 0.2, 0.3, -0.1, -0.2, -0.3],
        c_tensor: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0],
        c_int: vec![rank, rank],
    }
}

fn one_tet() -> Data {
    Data {
        dim: 3,
        coords: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        cells: vec![0, 1, 2, 3],
        offsets: vec![],
        p_scalar: vec![1.0, 2.0, 3.0, 4.0],
        p_vector: (0..12).map(|i| i as f64 - 5.5).collect(),
        p_tensor: (0..36).map(|i| (i as f64).sqrt()).collect(),
        p_int: vec![-1, 0, 1, i32::MAX],
        c_scalar: vec![std::f64::consts::PI],
        c_vector: vec![1.0, -2.0, 3.5],
        c_tensor: (1..=9).map(f64::from).collect(),
        c_int: vec![7],
    }
}

/// The numbers in `v`: a hex string of little-endian `f64` bytes (as
/// the Python scripts print arrays), or a (nested) JSON array of numbers.
fn as_f64s(v: &serde_json::Value) -> Vec<f64> {
    if let Some(hex) = v.as_str() {
        let bytes: Vec<u8> = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).expect("hex"))
            .collect();
        return bytes
            .chunks(8)
            .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect();
    }
    fn walk(v: &serde_json::Value, out: &mut Vec<f64>) {
        match v {
            serde_json::Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
            x => out.push(x.as_f64().expect("a number")),
        }
    }
    let mut out = Vec::new();
    walk(v, &mut out);
    out
}

/// Checks what meshio read from a `.vtu` written from `d`.
fn check_meshio(d: &Data, got: &serde_json::Value) {
    let np = d.coords.len() / d.dim;
    let nc = d.cells.len() / (d.dim + 1);
    assert_eq!(as_f64s(&got["points"]), d.points3());
    let cells = got["cells"].as_array().expect("cells");
    assert_eq!(cells.len(), 1, "one cell block");
    let ty = if d.dim == 2 { "triangle" } else { "tetra" };
    assert_eq!(cells[0][0], ty);
    let conn: Vec<usize> = as_f64s(&cells[0][1]).iter().map(|&x| x as usize).collect();
    assert_eq!(conn, d.cells);

    let pd = &got["point_data"];
    assert_eq!(pd.as_object().map(|o| o.len()), Some(4), "{pd}");
    assert_eq!(pd["gap"][0], "float64");
    assert_eq!(as_f64s(&pd["gap"][2]), d.p_scalar);
    assert_eq!(as_f64s(&pd["displacement"][1]), vec![np as f64, 3.0]);
    assert_eq!(
        as_f64s(&pd["displacement"][2]),
        Data::expanded_vector(&d.p_vector, d.dim, np)
    );
    assert_eq!(as_f64s(&pd["stress_nodal"][1]), vec![np as f64, 9.0]);
    assert_eq!(
        as_f64s(&pd["stress_nodal"][2]),
        Data::expanded_tensor(&d.p_tensor, d.dim, np)
    );
    assert_eq!(pd["status"][0], "int32");
    let ints: Vec<f64> = d.p_int.iter().map(|&i| f64::from(i)).collect();
    assert_eq!(as_f64s(&pd["status"][2]), ints);

    let cd = &got["cell_data"];
    assert_eq!(cd.as_object().map(|o| o.len()), Some(4), "{cd}");
    assert_eq!(as_f64s(&cd["von_mises"][2]), d.c_scalar);
    assert_eq!(as_f64s(&cd["traction"][1]), vec![nc as f64, 3.0]);
    assert_eq!(
        as_f64s(&cd["traction"][2]),
        Data::expanded_vector(&d.c_vector, d.dim, nc)
    );
    assert_eq!(as_f64s(&cd["stress"][1]), vec![nc as f64, 9.0]);
    assert_eq!(
        as_f64s(&cd["stress"][2]),
        Data::expanded_tensor(&d.c_tensor, d.dim, nc)
    );
    assert_eq!(cd["rank"][0], "int32");
    let ints: Vec<f64> = d.c_int.iter().map(|&i| f64::from(i)).collect();
    assert_eq!(as_f64s(&cd["rank"][2]), ints);
}

const VTK_SIZES: &str = r#"
import json, sys
import vtk
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(sys.argv[1])
r.Update()
g = r.GetOutput()
f = vtk.vtkCellSizeFilter()
f.SetInputData(g)
f.Update()
cd = f.GetOutput().GetCellData()
key = "Volume" if g.GetCell(0).GetCellDimension() == 3 else "Area"
print(json.dumps({
    "types": [g.GetCellType(c) for c in range(g.GetNumberOfCells())],
    "sizes": [cd.GetArray(key).GetValue(c) for c in range(g.GetNumberOfCells())],
}))
"#;

/// A unit square as a quadrilateral and two triangles (2D); a unit cube
/// as a hexahedron, with a prism, a pyramid and a tetrahedron beside it (3D).
fn mixed(dim: usize) -> Data {
    let (coords, cells, offsets) = if dim == 2 {
        (
            vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 2.0, 0.0, 2.0, 1.0],
            vec![0, 1, 2, 3, 1, 4, 5, 1, 5, 2],
            vec![4, 7, 10],
        )
    } else {
        let mut x = Vec::new();
        for z in [0.0, 1.0] {
            for (px, py) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                x.extend_from_slice(&[px, py, z]);
            }
        }
        // 8, 9: the prism's far edge (x = 2, y = 0); 10: the pyramid's
        // apex (x = 0.5, y = 0.5, z = 2); 11: the tetrahedron's last node.
        x.extend_from_slice(&[2.0, 0.0, 0.0, 2.0, 0.0, 1.0, 0.5, 0.5, 2.0, 1.5, 1.5, 2.0]);
        (
            x,
            [
                &[0, 1, 2, 3, 4, 5, 6, 7][..],
                &[1, 8, 2, 5, 9, 6],
                &[4, 5, 6, 7, 10],
                &[5, 6, 10, 11],
            ]
            .concat(),
            vec![8, 14, 19, 23],
        )
    };
    let np = coords.len() / dim;
    let nc = offsets.len();
    Data {
        dim,
        coords,
        cells,
        offsets,
        p_scalar: vec![1.0; np],
        p_vector: vec![0.5; 3 * np],
        p_tensor: vec![0.25; 9 * np],
        p_int: vec![3; np],
        c_scalar: (0..nc).map(|c| c as f64).collect(),
        c_vector: vec![1.0; 3 * nc],
        c_tensor: vec![2.0; 9 * nc],
        c_int: vec![0; nc],
    }
}

#[test]
fn mixed_cells_read_back_with_vtk_and_meshio() {
    let dir = temp_dir("mixed");
    for (dim, types, sizes) in [
        (
            2,
            vec![VTK_QUAD, VTK_TRIANGLE, VTK_TRIANGLE],
            vec![1.0, 0.5, 0.5],
        ),
        (
            3,
            vec![VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID, VTK_TETRA],
            vec![1.0, 0.5, 1.0 / 3.0, 1.0 / 6.0],
        ),
    ] {
        let d = mixed(dim);
        let path = dir.join(format!("mixed{dim}.vtu"));
        write_vtu(&path, &d.piece()).expect("write the piece");
        // VTK: the right types, and positive measures (the wedge's
        // points reordered).
        let got = run_python("vtk", "python3-vtk9", VTK_SIZES, &[&path]);
        let t: Vec<u8> = got["types"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as u8)
            .collect();
        assert_eq!(t, types);
        let v = as_f64s(&got["sizes"]);
        for (a, b) in v.iter().zip(&sizes) {
            assert!((a - b).abs() < 1e-12, "{v:?} vs {sizes:?}");
        }
        // meshio: one block per kind, in file order.
        let got = run_python("meshio", "python3-meshio", MESHIO_DUMP, &[&path]);
        let blocks: Vec<&str> = got["cells"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| b[0].as_str().unwrap())
            .collect();
        let want: &[&str] = if dim == 2 {
            &["quad", "triangle"]
        } else {
            &["hexahedron", "wedge", "pyramid", "tetra"]
        };
        assert_eq!(blocks, want);
        // (The dump shows the first block's cell data: one cell.)
        assert_eq!(as_f64s(&got["cell_data"]["von_mises"][2]), [d.c_scalar[0]]);
    }
    // Offsets that do not describe linear cells are refused.
    let mut d = mixed(2);
    d.offsets = vec![4, 6, 10];
    let e = vtu_bytes(&d.piece()).expect_err("a 2-point cell");
    assert!(e.to_string().contains("cell 1 has 2 points"), "{e}");
    d.offsets = vec![4, 7];
    assert!(vtu_bytes(&d.piece()).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn base64_matches_rfc4648() {
    for (input, want) in [
        ("", ""),
        ("f", "Zg=="),
        ("fo", "Zm8="),
        ("foo", "Zm9v"),
        ("foob", "Zm9vYg=="),
        ("fooba", "Zm9vYmE="),
        ("foobar", "Zm9vYmFy"),
    ] {
        let mut s = String::new();
        base64_into(&mut s, input.as_bytes());
        assert_eq!(s, want);
    }
    let mut s = String::new();
    base64_into(&mut s, &[0xfb, 0xff, 0xbf]);
    assert_eq!(s, "+/+/");
}

#[test]
fn vtu_pieces_read_back_with_meshio() {
    let dir = temp_dir("meshio");
    for (name, d) in [("tri.vtu", two_triangles(0.0, 0)), ("tet.vtu", one_tet())] {
        let path = dir.join(name);
        write_vtu(&path, &d.piece()).expect("write the piece");
        let got = run_python("meshio", "python3-meshio", MESHIO_DUMP, &[&path]);
        check_meshio(&d, &got);
    }
    // Only the two pieces: no temporary file left behind.
    assert_eq!(std::fs::read_dir(&dir).map(|d| d.count()).ok(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn vtu_piece_reads_back_with_vtk() {
    let dir = temp_dir("vtk1");
    let d = one_tet();
    let path = dir.join("tet.vtu");
    write_vtu(&path, &d.piece()).expect("write the piece");
    let got = run_python("vtk", "python3-vtk9", VTK_DUMP, &[&path]);
    assert_eq!(got["num_points"], 4);
    assert_eq!(got["num_cells"], 1);
    assert_eq!(got["cells"][0][0], i64::from(VTK_TETRA));
    assert_eq!(as_f64s(&got["cells"][0][1]), vec![0.0, 1.0, 2.0, 3.0]);
    assert_eq!(as_f64s(&got["points"]), d.coords);
    assert_eq!(got["cell_data"]["stress"][0], "double");
    assert_eq!(got["cell_data"]["stress"][1], 9);
    assert_eq!(as_f64s(&got["cell_data"]["stress"][2]), d.c_tensor);
    assert_eq!(got["point_data"]["status"][0], "int");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pvtu_over_pieces_reads_back_with_vtk() {
    let dir = temp_dir("pvtu");
    let a = two_triangles(0.0, 0);
    let b = two_triangles(1.0, 1);
    // A rank that owns nothing still writes a (valid, empty) piece.
    let empty_data = Data {
        dim: 2,
        coords: vec![],
        cells: vec![],
        offsets: vec![],
        p_scalar: vec![],
        p_vector: vec![],
        p_tensor: vec![],
        p_int: vec![],
        c_scalar: vec![],
        c_vector: vec![],
        c_tensor: vec![],
        c_int: vec![],
    };
    let names: Vec<String> = (0..3).map(|r| piece_file_name("out", r)).collect();
    assert_eq!(names[1], "out_1.vtu");
    for (name, d) in names.iter().zip([&a, &b, &empty_data]) {
        write_vtu(&dir.join(name), &d.piece()).expect("write a piece");
    }
    let pa = a.piece();
    let index = dir.join("out.pvtu");
    write_pvtu(&index, &names, &pa.point_fields(), &pa.cell_fields()).expect("write pvtu");
    let got = run_python("vtk", "python3-vtk9", VTK_DUMP, &[&index]);

    assert_eq!(got["num_points"], 8);
    assert_eq!(got["num_cells"], 4);
    let mut points = a.points3();
    points.extend(b.points3());
    assert_eq!(as_f64s(&got["points"]), points);
    for c in 0..4 {
        assert_eq!(got["cells"][c][0], i64::from(VTK_TRIANGLE));
    }
    // Piece b's point indices are shifted by piece a's 4 points.
    assert_eq!(as_f64s(&got["cells"][2][1]), vec![4.0, 5.0, 6.0]);

    let pd = &got["point_data"];
    let cd = &got["cell_data"];
    let names_of = |v: &serde_json::Value| {
        let mut n: Vec<String> = v.as_object().expect("arrays").keys().cloned().collect();
        n.sort();
        n
    };
    assert_eq!(
        names_of(pd),
        ["displacement", "gap", "status", "stress_nodal"]
    );
    assert_eq!(names_of(cd), ["rank", "stress", "traction", "von_mises"]);
    let cat = |x: &[f64], y: &[f64]| [x, y].concat();
    assert_eq!(as_f64s(&pd["gap"][2]), cat(&a.p_scalar, &b.p_scalar));
    assert_eq!(pd["displacement"][1], 3);
    assert_eq!(
        as_f64s(&pd["displacement"][2]),
        cat(
            &Data::expanded_vector(&a.p_vector, 2, 4),
            &Data::expanded_vector(&b.p_vector, 2, 4)
        )
    );
    assert_eq!(pd["stress_nodal"][1], 9);
    assert_eq!(
        as_f64s(&pd["stress_nodal"][2]),
        cat(&a.p_tensor, &b.p_tensor)
    );
    assert_eq!(pd["status"][0], "int");
    assert_eq!(as_f64s(&cd["von_mises"][2]), cat(&a.c_scalar, &b.c_scalar));
    assert_eq!(as_f64s(&cd["traction"][2]), cat(&a.c_vector, &b.c_vector));
    assert_eq!(
        as_f64s(&cd["stress"][2]),
        cat(
            &Data::expanded_tensor(&a.c_tensor, 2, 2),
            &Data::expanded_tensor(&b.c_tensor, 2, 2)
        )
    );
    assert_eq!(as_f64s(&cd["rank"][2]), vec![0.0, 0.0, 1.0, 1.0]);
    assert_eq!(cd["rank"][0], "int");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn non_finite_value_fails_and_leaves_no_file() {
    let dir = temp_dir("nan");
    let mut d = one_tet();
    d.p_vector[7] = f64::NAN;
    let path = dir.join("bad.vtu");
    let e = write_vtu(&path, &d.piece()).expect_err("a NaN must be refused");
    assert_eq!(e.kind(), io::ErrorKind::InvalidData);
    let msg = e.to_string();
    assert!(msg.contains("'displacement'"), "{msg}");
    assert!(msg.contains("entry 2"), "{msg}");
    assert!(!path.exists());

    let mut d = two_triangles(0.0, 0);
    d.c_tensor[5] = f64::INFINITY;
    let e = write_vtu(&path, &d.piece()).expect_err("an infinity must be refused");
    assert_eq!(e.kind(), io::ErrorKind::InvalidData);
    assert!(e.to_string().contains("'stress'"), "{e}");

    let mut d = two_triangles(0.0, 0);
    d.coords[3] = f64::NEG_INFINITY;
    let e = write_vtu(&path, &d.piece()).expect_err("bad coordinates must be refused");
    assert_eq!(e.kind(), io::ErrorKind::InvalidData);
    assert!(e.to_string().contains("coordinates"), "{e}");

    // A valid piece over an existing file, then a failure, keeps the old file.
    write_vtu(&path, &one_tet().piece()).expect("write a valid piece");
    let before = std::fs::read(&path).expect("read back");
    let mut d = one_tet();
    d.c_scalar[0] = f64::NAN;
    assert!(write_vtu(&path, &d.piece()).is_err());
    assert_eq!(std::fs::read(&path).expect("read back"), before);
    assert_eq!(std::fs::read_dir(&dir).map(|d| d.count()).ok(), Some(1));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn inconsistent_sizes_are_refused() {
    let d = two_triangles(0.0, 0);
    let mut p = d.piece();
    p.point_data.push(Field::Scalar("short", &[1.0, 2.0]));
    let e = vtu_bytes(&p).expect_err("short field");
    assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
    assert!(e.to_string().contains("'short'"), "{e}");

    let mut p = d.piece();
    p.point_data.push(Field::Scalar("gap", &d.p_scalar));
    assert!(vtu_bytes(&p).is_err(), "duplicate names");

    let mut p = d.piece();
    p.cells = &[0, 1, 4];
    let e = vtu_bytes(&p).expect_err("index out of range");
    assert!(e.to_string().contains("out of range"), "{e}");

    let mut p = d.piece();
    p.dim = 4;
    assert!(vtu_bytes(&p).is_err());

    // 3D does not accept 2-component vectors.
    let t = one_tet();
    let mut p = t.piece();
    p.point_data = vec![Field::Vector("v", &[0.0; 8])];
    assert!(vtu_bytes(&p).is_err());

    assert!(pvtu_bytes(&[], &[], &[]).is_err());
    assert!(pvtu_bytes(&["/abs/a.vtu".into()], &[], &[]).is_err());
}

#[test]
fn names_are_escaped_and_write_errors_name_the_file() {
    let d = one_tet();
    let mut p = d.piece();
    p.point_data = vec![Field::Scalar("a<b & \"c\"", &d.p_scalar)];
    let s = String::from_utf8(vtu_bytes(&p).expect("valid")).expect("utf-8");
    assert!(s.contains("Name=\"a&lt;b &amp; &quot;c&quot;\""), "{s}");

    let dir = temp_dir("missing");
    let bad = dir.join("no/such/dir/x.vtu");
    let e = write_vtu(&bad, &d.piece()).expect_err("missing directory");
    assert!(e.to_string().contains("x.vtu"), "{e}");
    assert_eq!(std::fs::read_dir(&dir).map(|d| d.count()).ok(), Some(0));
    let _ = std::fs::remove_dir_all(&dir);
}
