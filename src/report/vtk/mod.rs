//! ParaView output: one `.vtu` piece per MPI rank plus a `.pvtu` index.
//!
//! Each rank writes its own part of the mesh with [`write_vtu`] (an XML
//! `UnstructuredGrid` of linear cells: triangles and quadrilaterals in 2D,
//! tetrahedra, hexahedra, prisms (VTK wedges, their points reordered) and
//! pyramids in 3D, in any mix), and
//! rank 0 writes the `.pvtu` index with [`write_pvtu`], which names the pieces
//! by file names relative to the index's directory and declares the same
//! fields. ParaView opens the `.pvtu` and shows the whole mesh.
//!
//! # Format
//! The XML is written by hand: the format is small, and the one crate for it
//! (`vtkio` 0.6) can read but not write a `PUnstructuredGrid` index (its writer
//! loads the pieces and inlines them). Arrays are stored inline as `binary`
//! (base64 of a little-endian `UInt64` byte count followed by the
//! little-endian values, header and values in one base64 stream, no
//! compression), the encoding that VTK/ParaView, meshio and other Python
//! readers all accept. Points are `Float64` with 3 components (2D points get
//! z = 0), connectivity and offsets `Int64`, cell types `UInt8`, real fields
//! `Float64` and integer fields `Int32`.
//!
//! # Fields
//! * [`Field::Scalar`]: one value per entry.
//! * [`Field::Vector`]: 3 components per entry; in 2D, 2 components per entry
//!   are also accepted and padded with a zero z component.
//! * [`Field::Tensor`]: 9 components per entry (row-major 3x3); in 2D, 4
//!   components per entry (row-major 2x2) are also accepted and embedded in
//!   the upper-left block of a 3x3 tensor with zeros elsewhere.
//! * [`Field::Int`]: one `i32` per entry (a rank, a contact status).
//! * [`Field::Id`]: one `i64` per entry (the mesh file's node tag).
//!
//! Point fields have one entry per point, cell fields one per cell.
//!
//! # Errors
//! Nothing is written unless the whole piece is valid. Inconsistent sizes
//! (coordinates, connectivity, a field's length, a point index out of range)
//! give an error of kind [`std::io::ErrorKind::InvalidInput`]; a NaN or an
//! infinity in the coordinates or a field gives
//! [`std::io::ErrorKind::InvalidData`] naming the field and the entry. A
//! failure while writing leaves no file behind: files are written to a
//! temporary file in the same directory, then renamed.

use super::write_atomic;
use base64::Engine as _;
use std::io;
use std::path::Path;

/// VTK cell type of a linear triangle.
const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a bilinear quadrilateral.
const VTK_QUAD: u8 = 9;
/// VTK cell type of a linear tetrahedron.
const VTK_TETRA: u8 = 10;
/// VTK cell type of a trilinear hexahedron.
const VTK_HEXAHEDRON: u8 = 12;
/// VTK cell type of a linear wedge (prism).
const VTK_WEDGE: u8 = 13;
/// VTK cell type of a linear pyramid.
const VTK_PYRAMID: u8 = 14;

/// The VTK type of a cell of `n` points in dimension `dim`.
fn vtk_cell_type(dim: usize, n: usize) -> Option<u8> {
    match (dim, n) {
        (2, 3) => Some(VTK_TRIANGLE),
        (2, 4) => Some(VTK_QUAD),
        (3, 4) => Some(VTK_TETRA),
        (3, 8) => Some(VTK_HEXAHEDRON),
        (3, 6) => Some(VTK_WEDGE),
        (3, 5) => Some(VTK_PYRAMID),
        _ => None,
    }
}

/// VTK point `i` of a cell of type `ty` is point `vtk_order(ty)[i]` of the
/// cell in Gmsh's order. Gmsh's order is VTK's except for the wedge: VTK
/// wants its first triangle's normal (right-hand rule) to point away from
/// the second triangle, Gmsh has it pointing toward it.
fn vtk_order(ty: u8) -> &'static [usize] {
    match ty {
        VTK_WEDGE => &[0, 2, 1, 3, 5, 4],
        _ => &[0, 1, 2, 3, 4, 5, 6, 7],
    }
}

/// What a field holds per entry, as declared in the `.pvtu` index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    /// One `f64`.
    Scalar,
    /// Three `f64` (x, y, z).
    Vector,
    /// Nine `f64` (row-major 3x3).
    Tensor,
    /// One `i32`.
    Int,
    /// One `i64` (an identifier, e.g. the mesh file's node tag).
    Id,
}

impl FieldKind {
    /// Number of components per entry in the file.
    pub fn components(self) -> usize {
        match self {
            FieldKind::Scalar | FieldKind::Int | FieldKind::Id => 1,
            FieldKind::Vector => 3,
            FieldKind::Tensor => 9,
        }
    }

    fn vtk_type(self) -> &'static str {
        match self {
            FieldKind::Int => "Int32",
            FieldKind::Id => "Int64",
            _ => "Float64",
        }
    }
}

/// A named array attached to the points or the cells of a [`Piece`].
#[derive(Clone, Copy, Debug)]
pub enum Field<'a> {
    /// One value per entry.
    Scalar(&'a str, &'a [f64]),
    /// 3 components per entry (or `dim` = 2 components, padded with z = 0).
    Vector(&'a str, &'a [f64]),
    /// 9 components per entry, row-major 3x3 (or, in 2D, 4 components,
    /// row-major 2x2, embedded in a 3x3 tensor).
    Tensor(&'a str, &'a [f64]),
    /// One integer per entry.
    Int(&'a str, &'a [i32]),
    /// One 64-bit identifier per entry (written as `Int64`).
    Id(&'a str, &'a [u64]),
}

impl<'a> Field<'a> {
    /// The field's name.
    pub fn name(&self) -> &'a str {
        match *self {
            Field::Scalar(n, _)
            | Field::Vector(n, _)
            | Field::Tensor(n, _)
            | Field::Int(n, _)
            | Field::Id(n, _) => n,
        }
    }

    /// The field's kind.
    pub fn kind(&self) -> FieldKind {
        match self {
            Field::Scalar(..) => FieldKind::Scalar,
            Field::Vector(..) => FieldKind::Vector,
            Field::Tensor(..) => FieldKind::Tensor,
            Field::Int(..) => FieldKind::Int,
            Field::Id(..) => FieldKind::Id,
        }
    }
}

/// One rank's part of the mesh with its fields.
#[derive(Clone, Debug)]
pub struct Piece<'a> {
    /// 2 (triangles, quadrilaterals) or 3 (tetrahedra, hexahedra).
    pub dim: usize,
    /// `dim` values per point (2D points are padded with z = 0 in the file).
    pub coords: &'a [f64],
    /// Point indices (into this piece's points) of the cells, one after the other.
    pub cells: &'a [usize],
    /// Where each cell ends in `cells` (VTK's `offsets`); empty when every
    /// cell has `dim + 1` points (simplices).
    pub offsets: &'a [usize],
    /// One entry per point each.
    pub point_data: Vec<Field<'a>>,
    /// One entry per cell each.
    pub cell_data: Vec<Field<'a>>,
}

impl<'a> Piece<'a> {
    /// Number of points (0 if `dim` is not 2 or 3).
    pub fn num_points(&self) -> usize {
        match self.dim {
            2 | 3 => self.coords.len() / self.dim,
            _ => 0,
        }
    }

    /// Number of cells (0 if `dim` is not 2 or 3).
    pub fn num_cells(&self) -> usize {
        match self.dim {
            2 | 3 if !self.offsets.is_empty() => self.offsets.len(),
            2 | 3 => self.cells.len() / (self.dim + 1),
            _ => 0,
        }
    }

    /// Names and kinds of the point fields, as [`write_pvtu`] wants them.
    pub fn point_fields(&self) -> Vec<(&'a str, FieldKind)> {
        self.point_data
            .iter()
            .map(|f| (f.name(), f.kind()))
            .collect()
    }

    /// Names and kinds of the cell fields, as [`write_pvtu`] wants them.
    pub fn cell_fields(&self) -> Vec<(&'a str, FieldKind)> {
        self.cell_data
            .iter()
            .map(|f| (f.name(), f.kind()))
            .collect()
    }
}

/// The conventional file name of rank `rank`'s piece: `{stem}_{rank}.vtu`.
pub fn piece_file_name(stem: &str, rank: usize) -> String {
    format!("{stem}_{rank}.vtu")
}

/// Writes one `.vtu` piece (XML `UnstructuredGrid`). Atomic.
pub fn write_vtu(path: &Path, piece: &Piece) -> io::Result<()> {
    let bytes = vtu_bytes(piece)?;
    write_named(path, &bytes)
}

/// Writes the `.pvtu` index naming the pieces (file names relative to the
/// index's directory) and declaring the fields the pieces hold (same names,
/// same kinds, same order). Atomic.
pub fn write_pvtu(
    path: &Path,
    pieces: &[String],
    point_fields: &[(&str, FieldKind)],
    cell_fields: &[(&str, FieldKind)],
) -> io::Result<()> {
    let bytes = pvtu_bytes(pieces, point_fields, cell_fields)?;
    write_named(path, &bytes)
}

/// [`write_atomic`], its error naming the file.
fn write_named(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic(path, bytes)
        .map_err(|e| io::Error::new(e.kind(), format!("cannot write '{}': {e}", path.display())))
}

/// The contents of a `.vtu` file for `piece`, after checking it.
pub fn vtu_bytes(piece: &Piece) -> io::Result<Vec<u8>> {
    let dim = piece.dim;
    if dim != 2 && dim != 3 {
        return Err(invalid_input(format!("dimension {dim} (want 2 or 3)")));
    }
    if !piece.coords.len().is_multiple_of(dim) {
        return Err(invalid_input(format!(
            "{} coordinates is not a multiple of the dimension {dim}",
            piece.coords.len()
        )));
    }
    let nv = dim + 1;
    let offsets: Vec<i64> = if piece.offsets.is_empty() {
        if !piece.cells.len().is_multiple_of(nv) {
            return Err(invalid_input(format!(
                "{} cell point indices is not a multiple of {nv}",
                piece.cells.len()
            )));
        }
        (1..=piece.cells.len() / nv)
            .map(|c| (c * nv) as i64)
            .collect()
    } else {
        piece.offsets.iter().map(|&o| o as i64).collect()
    };
    let mut types = Vec::with_capacity(offsets.len());
    let mut begin = 0i64;
    for (c, &end) in offsets.iter().enumerate() {
        let ty = usize::try_from(end - begin)
            .ok()
            .and_then(|n| vtk_cell_type(dim, n))
            .ok_or_else(|| {
                invalid_input(format!(
                    "cell {c} has {} points: not a linear {dim}D cell",
                    end - begin
                ))
            })?;
        types.push(ty);
        begin = end;
    }
    if begin != piece.cells.len() as i64 {
        return Err(invalid_input(format!(
            "the offsets end at {begin}, the cells hold {} point indices",
            piece.cells.len()
        )));
    }
    let np = piece.num_points();
    let nc = piece.num_cells();
    if let Some(&bad) = piece.cells.iter().find(|&&i| i >= np) {
        return Err(invalid_input(format!(
            "cell point index {bad} out of range ({np} points)"
        )));
    }
    check_finite("point coordinates", piece.coords, 1)?;

    let mut x = String::with_capacity(1024 + 40 * (np + nc));
    x.push_str(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n",
    );
    x.push_str(&format!(
        "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">\n"
    ));

    let pd = encode_fields("point", &piece.point_data, np, dim)?;
    x.push_str("      <PointData>\n");
    x.push_str(&pd);
    x.push_str("      </PointData>\n");
    let cd = encode_fields("cell", &piece.cell_data, nc, dim)?;
    x.push_str("      <CellData>\n");
    x.push_str(&cd);
    x.push_str("      </CellData>\n");

    let mut points = Vec::with_capacity(3 * np);
    for p in piece.coords.chunks(dim) {
        points.extend_from_slice(p);
        if dim == 2 {
            points.push(0.0);
        }
    }
    x.push_str("      <Points>\n");
    data_array(&mut x, "Points", "Float64", 3, &f64_bytes(&points));
    x.push_str("      </Points>\n");

    let mut connectivity: Vec<i64> = Vec::with_capacity(piece.cells.len());
    let mut begin = 0usize;
    for (&ty, &end) in types.iter().zip(&offsets) {
        let cell = &piece.cells[begin..end as usize];
        connectivity.extend(vtk_order(ty)[..cell.len()].iter().map(|&a| cell[a] as i64));
        begin = end as usize;
    }
    x.push_str("      <Cells>\n");
    data_array(
        &mut x,
        "connectivity",
        "Int64",
        1,
        &i64_bytes(&connectivity),
    );
    data_array(&mut x, "offsets", "Int64", 1, &i64_bytes(&offsets));
    data_array(&mut x, "types", "UInt8", 1, &types);
    x.push_str("      </Cells>\n");
    x.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    Ok(x.into_bytes())
}

/// The contents of a `.pvtu` index, after checking the arguments.
pub fn pvtu_bytes(
    pieces: &[String],
    point_fields: &[(&str, FieldKind)],
    cell_fields: &[(&str, FieldKind)],
) -> io::Result<Vec<u8>> {
    if pieces.is_empty() {
        return Err(invalid_input(
            "a .pvtu index needs at least one piece".into(),
        ));
    }
    for p in pieces {
        if p.is_empty() || Path::new(p).is_absolute() {
            return Err(invalid_input(format!(
                "piece name '{p}': want a file name relative to the .pvtu's directory"
            )));
        }
    }
    check_unique("point", point_fields.iter().map(|f| f.0))?;
    check_unique("cell", cell_fields.iter().map(|f| f.0))?;
    let declare = |x: &mut String, fields: &[(&str, FieldKind)]| {
        for (name, kind) in fields {
            x.push_str(&format!(
                "      <PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                kind.vtk_type(),
                xml_escape(name),
                kind.components()
            ));
        }
    };
    let mut x = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  \
         <PUnstructuredGrid GhostLevel=\"0\">\n",
    );
    x.push_str("    <PPointData>\n");
    declare(&mut x, point_fields);
    x.push_str("    </PPointData>\n    <PCellData>\n");
    declare(&mut x, cell_fields);
    x.push_str("    </PCellData>\n    <PPoints>\n");
    x.push_str("      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n");
    x.push_str("    </PPoints>\n");
    for p in pieces {
        x.push_str(&format!("    <Piece Source=\"{}\"/>\n", xml_escape(p)));
    }
    x.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    Ok(x.into_bytes())
}

/// Checks and encodes the `<DataArray>` elements of one `PointData` or
/// `CellData` block (`n` entries per field).
fn encode_fields(location: &str, fields: &[Field], n: usize, dim: usize) -> io::Result<String> {
    check_unique(location, fields.iter().map(|f| f.name()))?;
    let mut x = String::new();
    for f in fields {
        let name = f.name();
        let what = format!("{location} field '{name}'");
        let bad_len = |len: usize, want: &str| {
            invalid_input(format!(
                "{what}: {len} values for {n} {location}s (want {want} per {location})"
            ))
        };
        match *f {
            Field::Scalar(_, v) => {
                if v.len() != n {
                    return Err(bad_len(v.len(), "1"));
                }
                check_finite(&what, v, 1)?;
                data_array(&mut x, name, "Float64", 1, &f64_bytes(v));
            }
            Field::Vector(_, v) => {
                let per = entry_width(v.len(), n, 3, if dim == 2 { 2 } else { 3 })
                    .ok_or_else(|| bad_len(v.len(), if dim == 2 { "2 or 3" } else { "3" }))?;
                check_finite(&what, v, per)?;
                let mut out = Vec::with_capacity(3 * n);
                for e in v.chunks(per.max(1)) {
                    out.extend_from_slice(e);
                    if per == 2 {
                        out.push(0.0);
                    }
                }
                data_array(&mut x, name, "Float64", 3, &f64_bytes(&out));
            }
            Field::Tensor(_, v) => {
                let per = entry_width(v.len(), n, 9, if dim == 2 { 4 } else { 9 })
                    .ok_or_else(|| bad_len(v.len(), if dim == 2 { "4 or 9" } else { "9" }))?;
                check_finite(&what, v, per)?;
                let mut out = Vec::with_capacity(9 * n);
                for e in v.chunks(per.max(1)) {
                    if per == 4 {
                        out.extend_from_slice(&[e[0], e[1], 0.0, e[2], e[3], 0.0, 0.0, 0.0, 0.0]);
                    } else {
                        out.extend_from_slice(e);
                    }
                }
                data_array(&mut x, name, "Float64", 9, &f64_bytes(&out));
            }
            Field::Int(_, v) => {
                if v.len() != n {
                    return Err(bad_len(v.len(), "1"));
                }
                let bytes: Vec<u8> = v.iter().flat_map(|i| i.to_le_bytes()).collect();
                data_array(&mut x, name, "Int32", 1, &bytes);
            }
            Field::Id(_, v) => {
                if v.len() != n {
                    return Err(bad_len(v.len(), "1"));
                }
                let ids: Vec<i64> = v.iter().map(|&i| i as i64).collect();
                data_array(&mut x, name, "Int64", 1, &i64_bytes(&ids));
            }
        }
    }
    Ok(x)
}

/// Components per entry of a field of `len` values over `n` entries, if it
/// is `full` or `short`.
fn entry_width(len: usize, n: usize, full: usize, short: usize) -> Option<usize> {
    if len == full * n {
        Some(full)
    } else if len == short * n {
        Some(short)
    } else {
        None
    }
}

fn check_finite(what: &str, v: &[f64], per: usize) -> io::Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "{what}: value {} at entry {} (component {}) is not finite",
                v[i],
                i / per.max(1),
                i % per.max(1)
            ),
        )),
    }
}

fn check_unique<'a>(location: &str, names: impl Iterator<Item = &'a str>) -> io::Result<()> {
    let mut seen: Vec<&str> = Vec::new();
    for n in names {
        if n.is_empty() {
            return Err(invalid_input(format!(
                "a {location} field has an empty name"
            )));
        }
        if seen.contains(&n) {
            return Err(invalid_input(format!(
                "two {location} fields are named '{n}'"
            )));
        }
        seen.push(n);
    }
    Ok(())
}

fn invalid_input(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Appends one inline binary `<DataArray>` holding `bytes`.
fn data_array(x: &mut String, name: &str, ty: &str, components: usize, bytes: &[u8]) {
    let mut block = Vec::with_capacity(8 + bytes.len());
    block.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    block.extend_from_slice(bytes);
    x.push_str(&format!(
        "        <DataArray type=\"{ty}\" Name=\"{}\" NumberOfComponents=\"{components}\" \
         format=\"binary\">",
        xml_escape(name)
    ));
    base64_into(x, &block);
    x.push_str("</DataArray>\n");
}

fn f64_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn i64_bytes(v: &[i64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Appends standard base64 of `data` (RFC 4648, with padding).
fn base64_into(out: &mut String, data: &[u8]) {
    base64::engine::general_purpose::STANDARD.encode_string(data, out);
}

fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests;
