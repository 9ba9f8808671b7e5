//! Reader for Gmsh `.msh` mesh files.
//!
//! # Supported
//!
//! * MSH **2.2** and MSH **4.1**, each in **ASCII** and **binary** form. Binary
//!   files must have data size 8 (`double`, and `size_t` in 4.1); both byte
//!   orders are accepted (the endianness marker in `$MeshFormat` decides).
//!   Any other version (1.0, 2.0, 3.0, 4.0, ...) is an error naming the version.
//! * Sections: `$MeshFormat`, `$PhysicalNames` (optional), `$Entities` (4.1:
//!   maps element blocks to physical tags), `$Nodes`, `$Elements`. Other
//!   sections (`$Periodic`, `$NodeData`, `$Comments`, ...) are skipped up to
//!   their `$End...` line (a `$Periodic` one is remembered: the run warns
//!   that it ties no periodic boundaries, [`periodic_skipped`]). A
//!   partitioned 4.1 mesh (`$PartitionedEntities`, Gmsh's `-part N`) is
//!   read whole: its element blocks take their physical
//!   tags from the partitioned entities, the facets Gmsh adds on the
//!   interfaces between partitions join no group, and the partition is not
//!   used (ghost cells, in `$GhostElements`, are skipped). One file of
//!   `-part_split` (one partition, its neighbours in other files) is an
//!   error: it is a piece of the body.
//! * Element types 15 (point), 1 (2-node line), 2 (3-node triangle),
//!   3 (4-node quadrilateral), 4 (4-node tetrahedron), 5 (8-node
//!   hexahedron), 6 (6-node prism) and 7 (5-node pyramid), in any mix. Any
//!   other type is an error that names it in words ("second-order triangle
//!   (Gmsh type 9) is not supported").
//!
//! # Result
//!
//! The mesh is 3D when there are 3D cells (tetrahedra, hexahedra, prisms,
//! pyramids), else 2D when there
//! are triangles or quadrilaterals (the z coordinate is dropped: they must lie
//! in a plane z = constant), else an error. [`Mesh::cells`] holds every element
//! of the top dimension in file order, with or without a physical group. Every physical group of lower dimension becomes a [`Group`] (one of the
//! top dimension becomes a [`Group`] without elements, its name kept for messages), named
//! from `$PhysicalNames` (or the decimal tag when unnamed); groups come in the
//! order in which their first element appears, followed by named groups that
//! have no elements (in `$PhysicalNames` order). Lower-dimensional elements
//! without a physical group are ignored. In 2.2 the physical tag is the first
//! element tag (0 = none); Gmsh writes an element once per physical group, so
//! a cell that repeats the previous element's type and nodes is counted once.
//! In 4.1 the physical tags come from the block's entity in `$Entities` (an
//! element belongs to each of them; without `$Entities` there are no groups).
//!
//! Nodes are kept in file order; [`Mesh::node_tags`] holds the file's tags
//! (any `u64`, not necessarily contiguous). Nodes that no cell uses are
//! dropped at the end ([`Mesh::drop_unused_nodes`]).
//!
//! # Errors
//!
//! Every problem (truncation, bad number, count mismatch, missing `$End`
//! marker or section, undefined node, unsupported type or version, ...) is a
//! one-line [`MeshError`]: `file:line: what` while the file is read as text,
//! `file: byte offset: what` for binary files. Whatever the bytes, the parser
//! never panics, and its allocations stay proportional to the input size
//! (header counts are not trusted).

use super::{Cells, Group, Mesh, MeshError};
use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};
use std::fmt;

type Res<T> = Result<T, MeshError>;

/// Whether a file read by this process had a `$Periodic` section, which
/// the program skips (it applies no periodic conditions).
static PERIODIC_SKIPPED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether a mesh file read by this process had a `$Periodic` section
/// (skipped: the boundaries Gmsh matched are not tied).
pub fn periodic_skipped() -> bool {
    PERIODIC_SKIPPED.load(std::sync::atomic::Ordering::Relaxed)
}

/// What a file that is no mesh may be instead, for its error message: the
/// mesh gzip-compressed, or Gmsh's geometry (`.geo`) to mesh with `mesh_it`
/// (`gmsh -2 or -3`); else nothing.
pub fn not_a_mesh_hint(bytes: &[u8], file: &str, mesh_it: &str) -> String {
    if bytes.starts_with(&[0x1f, 0x8b]) {
        ": it is gzip-compressed; gunzip it first".into()
    } else if file.ends_with(".geo") {
        format!(": a .geo file is Gmsh's geometry; mesh it first ({mesh_it} FILE.geo -o FILE.msh)")
    } else {
        String::new()
    }
}

/// Parses the bytes of a Gmsh file; `file_name` is only used in error messages.
pub fn parse_gmsh(bytes: &[u8], file_name: &str) -> Result<Mesh, MeshError> {
    Reader::new(bytes, file_name).parse()
}

/// Dimension and node count of a supported Gmsh element type.
fn element_info(gmsh_type: i32) -> Option<(usize, usize)> {
    match gmsh_type {
        15 => Some((0, 1)),
        1 => Some((1, 2)),
        2 => Some((2, 3)),
        3 => Some((2, 4)),
        4 => Some((3, 4)),
        5 => Some((3, 8)),
        6 => Some((3, 6)),
        7 => Some((3, 5)),
        _ => None,
    }
}

/// The most nodes a supported element has.
const MAX_NODES: usize = 8;

/// Gmsh's element types in words (Gmsh reference manual, "MSH file format").
fn gmsh_type_name(gmsh_type: i32) -> Option<&'static str> {
    Some(match gmsh_type {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrilateral",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "second-order line",
        9 => "second-order triangle",
        10 => "second-order 9-node quadrilateral",
        11 => "second-order tetrahedron",
        12 => "second-order 27-node hexahedron",
        13 => "second-order 18-node prism",
        14 => "second-order 14-node pyramid",
        15 => "point",
        16 => "second-order 8-node quadrilateral",
        17 => "second-order 20-node hexahedron",
        18 => "second-order 15-node prism",
        19 => "second-order 13-node pyramid",
        20 => "third-order incomplete triangle",
        21 => "third-order triangle",
        22 => "fourth-order incomplete triangle",
        23 => "fourth-order triangle",
        24 => "fifth-order incomplete triangle",
        25 => "fifth-order triangle",
        26 => "third-order line",
        27 => "fourth-order line",
        28 => "fifth-order line",
        29 => "third-order tetrahedron",
        30 => "fourth-order tetrahedron",
        31 => "fifth-order tetrahedron",
        92 => "third-order hexahedron",
        93 => "fourth-order hexahedron",
        _ => return None,
    })
}

/// A token for an error message: escaped to one line, and shortened.
fn show(tok: &[u8]) -> String {
    const MAX: usize = 40;
    let mut s = tok.get(..MAX).unwrap_or(tok).escape_ascii().to_string();
    if tok.len() > MAX {
        s.push_str("...");
    }
    s
}

fn parse_u64(t: &[u8]) -> Option<u64> {
    let t = t.strip_prefix(b"+").unwrap_or(t);
    if t.is_empty() {
        return None;
    }
    let mut v: u64 = 0;
    for &c in t {
        let d = c.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        v = v.checked_mul(10)?.checked_add(u64::from(d))?;
    }
    Some(v)
}

fn parse_i32(t: &[u8]) -> Option<i32> {
    match t.strip_prefix(b"-") {
        Some(digits) if !digits.starts_with(b"+") => {
            i32::try_from(-i64::try_from(parse_u64(digits)?).ok()?).ok()
        }
        Some(_) => None,
        None => i32::try_from(parse_u64(t)?).ok(),
    }
}

fn parse_f64(t: &[u8]) -> Option<f64> {
    std::str::from_utf8(t).ok()?.parse().ok()
}

const NO_INDEX: usize = usize::MAX;

/// Node tag -> node index: a dense vector while the tags are small compared
/// with the number of nodes, a hash map otherwise.
enum NodeMap {
    Dense(Vec<usize>),
    Sparse(HashMap<u64, usize>),
}

impl NodeMap {
    /// Records `tag -> idx`; false if the tag is already there.
    fn insert(&mut self, tag: u64, idx: usize) -> bool {
        match self {
            NodeMap::Dense(v) => {
                if let Some(slot) = usize::try_from(tag).ok().and_then(|t| v.get_mut(t)) {
                    if *slot != NO_INDEX {
                        return false;
                    }
                    *slot = idx;
                    return true;
                }
                // The dense table never exceeds about twice the node count.
                let limit = (idx as u64).saturating_mul(2).saturating_add(1024);
                match usize::try_from(tag) {
                    Ok(t) if tag < limit => {
                        let want = (v.len() as u64).saturating_mul(2).min(limit);
                        let len = usize::try_from(want).unwrap_or(t).max(t.saturating_add(1));
                        v.resize(len, NO_INDEX);
                        if let Some(slot) = v.get_mut(t) {
                            *slot = idx;
                        }
                        true
                    }
                    _ => {
                        let mut m: HashMap<u64, usize> = v
                            .iter()
                            .enumerate()
                            .filter(|&(_, &i)| i != NO_INDEX)
                            .map(|(t, &i)| (t as u64, i))
                            .collect();
                        m.insert(tag, idx);
                        *self = NodeMap::Sparse(m);
                        true
                    }
                }
            }
            NodeMap::Sparse(m) => match m.entry(tag) {
                Entry::Occupied(_) => false,
                Entry::Vacant(e) => {
                    e.insert(idx);
                    true
                }
            },
        }
    }

    fn get(&self, tag: u64) -> Option<usize> {
        match self {
            NodeMap::Dense(v) => usize::try_from(tag)
                .ok()
                .and_then(|t| v.get(t))
                .copied()
                .filter(|&i| i != NO_INDEX),
            NodeMap::Sparse(m) => m.get(&tag).copied(),
        }
    }
}

/// A physical group being filled.
struct GroupAcc {
    dim: usize,
    tag: i32,
    conn: Cells,
}

struct Reader<'a> {
    b: &'a [u8],
    pos: usize,
    file: &'a str,
    /// Binary file: errors give byte offsets instead of lines.
    binary: bool,
    /// Big-endian binary data.
    swap: bool,
    /// MSH 4.1 (else 2.2).
    v4: bool,
    /// Current section, for "unexpected end of file in ...".
    section: &'static str,
    names: HashMap<(usize, i32), String>,
    name_order: Vec<(usize, i32)>,
    /// 4.1 `(dim, entity tag) -> range` in `entity_phys` (of the
    /// partitioned entities when the file has them).
    entities: Option<HashMap<(usize, i32), (usize, usize)>>,
    /// 4.1: `$PartitionedEntities` was read.
    partitioned: bool,
    entity_phys: Vec<i32>,
    /// Three coordinates per node.
    coords: Vec<f64>,
    node_tags: Vec<u64>,
    node_map: NodeMap,
    nodes_seen: bool,
    /// Offset of the `$Nodes` header.
    nodes_at: usize,
    /// Offset of the `$Elements` header, once seen.
    elements_at: Option<usize>,
    /// Cells of dimension 2 (triangles, quadrilaterals) and 3 (tetrahedra,
    /// hexahedra), in file order.
    cells2: Cells,
    cells3: Cells,
    /// Their element tags in the file.
    tags2: Vec<u64>,
    tags3: Vec<u64>,
    groups: Vec<GroupAcc>,
    group_index: HashMap<(usize, i32), usize>,
    last_group: Option<(usize, i32, usize)>,
    /// Group connectivity entries so far (4.1 can multiply them by entity).
    group_entries: usize,
    /// Previous 2.2 element (type, nodes), to skip Gmsh's repeated cells.
    prev_v2: Option<(i32, [usize; MAX_NODES])>,
    /// Physical groups of the cells of dimension 2 and 3: (cell index in
    /// `cells2` or `cells3`, index in `groups`).
    members2: Vec<(usize, u32)>,
    members3: Vec<(usize, u32)>,
}

impl<'a> Reader<'a> {
    fn new(b: &'a [u8], file: &'a str) -> Self {
        Reader {
            b,
            pos: 0,
            file,
            binary: false,
            swap: false,
            v4: false,
            section: "$MeshFormat",
            names: HashMap::new(),
            name_order: Vec::new(),
            entities: None,
            partitioned: false,
            entity_phys: Vec::new(),
            coords: Vec::new(),
            node_tags: Vec::new(),
            node_map: NodeMap::Dense(Vec::new()),
            nodes_seen: false,
            nodes_at: 0,
            elements_at: None,
            cells2: Cells::new(),
            cells3: Cells::new(),
            tags2: Vec::new(),
            tags3: Vec::new(),
            groups: Vec::new(),
            group_index: HashMap::new(),
            last_group: None,
            group_entries: 0,
            prev_v2: None,
            members2: Vec::new(),
            members3: Vec::new(),
        }
    }

    // ----- errors -----

    fn err(&self, at: usize, what: impl fmt::Display) -> MeshError {
        if self.binary {
            MeshError(format!("{}: byte {}: {}", self.file, at, what))
        } else {
            MeshError(format!("{}:{}: {}", self.file, self.line_of(at), what))
        }
    }

    /// 1-based line of byte `at`; the end of a file that ends with a newline
    /// counts as its last line.
    fn line_of(&self, at: usize) -> usize {
        let mut end = at.min(self.b.len());
        if end == self.b.len() && self.b.last() == Some(&b'\n') {
            end -= 1;
        }
        let before = self.b.get(..end).unwrap_or(self.b);
        before.iter().filter(|&&c| c == b'\n').count() + 1
    }

    fn eof(&self) -> MeshError {
        self.err(
            self.b.len(),
            format_args!("unexpected end of file in {}", self.section),
        )
    }

    /// Error for token `tok` at `at` that should have been a `what`.
    fn bad(&self, at: usize, tok: &[u8], what: &str) -> MeshError {
        if tok.first() == Some(&b'$') {
            self.err(
                at,
                format_args!(
                    "expected {what}, found `{}` (fewer entries than the header count?)",
                    show(tok)
                ),
            )
        } else {
            self.err(at, format_args!("bad {what} `{}`", show(tok)))
        }
    }

    // ----- text -----

    fn rest(&self) -> &'a [u8] {
        self.b.get(self.pos..).unwrap_or(&[])
    }

    fn remaining(&self) -> usize {
        self.b.len().saturating_sub(self.pos)
    }

    /// `n`, capped by what the rest of the input can hold at `min_bytes` each.
    fn cap(&self, n: u64, min_bytes: usize) -> usize {
        usize::try_from(n)
            .unwrap_or(usize::MAX)
            .min(self.remaining() / min_bytes.max(1))
    }

    fn skip_ws(&mut self) {
        let r = self.rest();
        self.pos += r
            .iter()
            .position(|c| !c.is_ascii_whitespace())
            .unwrap_or(r.len());
    }

    /// Start of the next value: skips whitespace in text mode.
    fn here(&mut self) -> usize {
        if !self.binary {
            self.skip_ws();
        }
        self.pos
    }

    /// The next whitespace-separated token and its offset.
    fn token(&mut self) -> Res<(usize, &'a [u8])> {
        self.skip_ws();
        let r = self.rest();
        let n = r
            .iter()
            .position(|c| c.is_ascii_whitespace())
            .unwrap_or(r.len());
        if n == 0 {
            return Err(self.eof());
        }
        let at = self.pos;
        self.pos += n;
        Ok((at, r.get(..n).unwrap_or(r)))
    }

    fn a_u64(&mut self, what: &str) -> Res<u64> {
        let (at, t) = self.token()?;
        parse_u64(t).ok_or_else(|| self.bad(at, t, what))
    }

    fn a_i32(&mut self, what: &str) -> Res<i32> {
        let (at, t) = self.token()?;
        parse_i32(t).ok_or_else(|| self.bad(at, t, what))
    }

    /// Consumes the rest of a header line (before binary data).
    fn end_of_line(&mut self) -> Res<()> {
        let r = self.rest();
        let n = r
            .iter()
            .position(|&c| !matches!(c, b' ' | b'\t' | b'\r'))
            .unwrap_or(r.len());
        match r.get(n) {
            Some(b'\n') => {
                self.pos += n + 1;
                Ok(())
            }
            Some(_) => Err(self.err(self.pos + n, "expected end of line before binary data")),
            None => Err(self.eof()),
        }
    }

    fn expect_end(&mut self, name: &'static str) -> Res<()> {
        let Ok((at, t)) = self.token() else {
            return Err(self.err(
                self.b.len(),
                format_args!(
                    "unexpected end of file in {} (missing {name})",
                    self.section
                ),
            ));
        };
        if t == name.as_bytes() {
            Ok(())
        } else if t.first() == Some(&b'$') {
            Err(self.err(at, format_args!("expected {name}, found `{}`", show(t))))
        } else {
            Err(self.err(
                at,
                format_args!(
                    "expected {name}, found `{}` (more entries than the header count?)",
                    show(t)
                ),
            ))
        }
    }

    /// A quoted name on the current line.
    fn quoted(&mut self) -> Res<String> {
        let r = self.rest();
        let n = r
            .iter()
            .position(|&c| !matches!(c, b' ' | b'\t' | b'\r'))
            .unwrap_or(r.len());
        let at = self.pos + n;
        match r.get(n) {
            Some(b'"') => {}
            Some(_) => return Err(self.err(at, "expected a quoted physical name")),
            None => return Err(self.eof()),
        }
        let body = r.get(n + 1..).unwrap_or(&[]);
        let len = body
            .iter()
            .position(|&c| c == b'"' || c == b'\n')
            .unwrap_or(body.len());
        if body.get(len) != Some(&b'"') {
            return Err(self.err(at, "unterminated physical name"));
        }
        let name = std::str::from_utf8(body.get(..len).unwrap_or(&[]))
            .map_err(|_| self.err(at, "physical name is not valid UTF-8"))?;
        self.pos = at + len + 2;
        Ok(name.to_owned())
    }

    // ----- binary -----

    fn arr<const N: usize>(&mut self) -> Res<[u8; N]> {
        let a: Option<[u8; N]> = self.rest().get(..N).and_then(|s| s.try_into().ok());
        match a {
            Some(a) => {
                self.pos += N;
                Ok(a)
            }
            None => Err(self.eof()),
        }
    }

    fn b_i32(&mut self) -> Res<i32> {
        let a = self.arr::<4>()?;
        Ok(if self.swap {
            i32::from_be_bytes(a)
        } else {
            i32::from_le_bytes(a)
        })
    }

    fn b_u64(&mut self) -> Res<u64> {
        let a = self.arr::<8>()?;
        Ok(if self.swap {
            u64::from_be_bytes(a)
        } else {
            u64::from_le_bytes(a)
        })
    }

    fn b_f64(&mut self) -> Res<f64> {
        let a = self.arr::<8>()?;
        Ok(if self.swap {
            f64::from_be_bytes(a)
        } else {
            f64::from_le_bytes(a)
        })
    }

    // ----- values in either form (4.1 types: int, size_t, double) -----

    fn int(&mut self, what: &str) -> Res<i32> {
        if self.binary {
            self.b_i32()
        } else {
            self.a_i32(what)
        }
    }

    fn size(&mut self, what: &str) -> Res<u64> {
        if self.binary {
            self.b_u64()
        } else {
            self.a_u64(what)
        }
    }

    fn real(&mut self, what: &str) -> Res<f64> {
        if self.binary {
            self.b_f64()
        } else {
            let (at, t) = self.token()?;
            parse_f64(t).ok_or_else(|| self.bad(at, t, what))
        }
    }

    fn coord(&mut self) -> Res<f64> {
        let at = self.here();
        let x = self.real("coordinate")?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(at, format_args!("non-finite coordinate {x}")))
        }
    }

    // ----- file structure -----

    fn parse(mut self) -> Res<Mesh> {
        match self.token() {
            Ok((_, t)) if t == b"$MeshFormat" => {}
            _ => {
                // What a new user may give instead: the geometry, or the
                // mesh compressed.
                let hint = not_a_mesh_hint(self.b, self.file, "gmsh -2 or -3");
                return Err(self.err(
                    0,
                    format_args!("not a Gmsh mesh file (no $MeshFormat){hint}"),
                ));
            }
        }
        let (at, v) = self.token()?;
        self.v4 = match v {
            b"2.2" => false,
            b"4.1" => true,
            _ => {
                return Err(self.err(
                    at,
                    format_args!(
                        "unsupported MSH version {} (only 2.2 and 4.1 are supported)",
                        show(v)
                    ),
                ))
            }
        };
        let (at, ft) = self.token()?;
        match ft {
            b"0" => {}
            b"1" => self.binary = true,
            _ => {
                return Err(self.err(
                    at,
                    format_args!("bad file type `{}` (0 = ASCII, 1 = binary)", show(ft)),
                ))
            }
        }
        let (at, ds) = self.token()?;
        if self.binary && ds != b"8" {
            return Err(self.err(
                at,
                format_args!("unsupported data size `{}` (binary files need 8)", show(ds)),
            ));
        }
        if parse_u64(ds).is_none() {
            return Err(self.bad(at, ds, "data size"));
        }
        if self.binary {
            self.end_of_line()?;
            let at = self.pos;
            let m = self.arr::<4>()?;
            if i32::from_le_bytes(m) == 1 {
                self.swap = false;
            } else if i32::from_be_bytes(m) == 1 {
                self.swap = true;
            } else {
                return Err(self.err(at, "bad endianness marker (expected the integer 1)"));
            }
        }
        self.expect_end("$EndMeshFormat")?;

        loop {
            self.section = "the file";
            self.skip_ws();
            if self.pos >= self.b.len() {
                break;
            }
            let (at, t) = self.token()?;
            match t {
                b"$PhysicalNames" => self.physical_names()?,
                b"$Entities" if self.v4 => self.entities(at)?,
                b"$PartitionedEntities" if self.v4 => self.partitioned_entities(at)?,
                b"$Nodes" => self.nodes(at)?,
                b"$Elements" => self.elements(at)?,
                b"$MeshFormat" => return Err(self.err(at, "duplicate $MeshFormat section")),
                _ if t.starts_with(b"$") && !t.starts_with(b"$End") => self.skip_section(at, t)?,
                _ => {
                    return Err(self.err(
                        at,
                        format_args!(
                            "expected a section header such as $Nodes, found `{}`",
                            show(t)
                        ),
                    ))
                }
            }
        }
        self.finish()
    }

    /// Skips an unknown section `$Name` up to its `$EndName` line.
    fn skip_section(&mut self, at: usize, header: &[u8]) -> Res<()> {
        let name = header.get(1..).unwrap_or(&[]);
        if name.trim_ascii_end() == b"Periodic" {
            PERIODIC_SKIPPED.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        let mut end_marker = b"$End".to_vec();
        end_marker.extend_from_slice(name);
        let mut i = self.pos;
        while let Some(off) = self
            .b
            .get(i..)
            .and_then(|r| r.iter().position(|&c| c == b'$'))
        {
            let p = i + off;
            let line_start = p == 0 || self.b.get(p - 1).is_some_and(u8::is_ascii_whitespace);
            let cand = self.b.get(p..).unwrap_or(&[]);
            if line_start
                && cand.starts_with(&end_marker)
                && cand
                    .get(end_marker.len())
                    .is_none_or(u8::is_ascii_whitespace)
            {
                self.pos = p + end_marker.len();
                return Ok(());
            }
            i = p + 1;
        }
        Err(self.err(
            at,
            format_args!(
                "section `{}` has no `{}` line",
                show(header),
                show(&end_marker)
            ),
        ))
    }

    fn physical_names(&mut self) -> Res<()> {
        self.section = "$PhysicalNames";
        let n = self.a_u64("number of physical names")?;
        for _ in 0..n {
            let (at, t) = self.token()?;
            let dim = match parse_u64(t) {
                Some(d) if d <= 3 => d as usize,
                _ => return Err(self.bad(at, t, "physical dimension (0 to 3)")),
            };
            let tag = self.a_i32("physical tag")?;
            let name = self.quoted()?;
            if self.names.insert((dim, tag), name).is_some() {
                return Err(self.err(
                    at,
                    format_args!("duplicate physical name for dimension {dim}, tag {tag}"),
                ));
            }
            self.name_order.push((dim, tag));
        }
        self.expect_end("$EndPhysicalNames")
    }

    fn entities(&mut self, at: usize) -> Res<()> {
        if self.entities.is_some() {
            let what = if self.partitioned {
                "$Entities must come before $PartitionedEntities"
            } else {
                "duplicate $Entities section"
            };
            return Err(self.err(at, what));
        }
        self.entity_section(at, "$Entities", false)
    }

    /// A partitioned 4.1 file's `$PartitionedEntities`: its element blocks
    /// refer to these entities, so their physical tags replace those of
    /// `$Entities`. The partition itself is not used (the program partitions
    /// the mesh for its own ranks). The entities Gmsh makes on the interfaces
    /// between partitions (a parent of higher dimension) carry the parent
    /// volume's or surface's physical tags under their own dimension; they
    /// are given none, so their facets join no group.
    fn partitioned_entities(&mut self, at: usize) -> Res<()> {
        if self.partitioned {
            return Err(self.err(at, "duplicate $PartitionedEntities section"));
        }
        self.partitioned = true;
        self.entities = None;
        self.entity_phys.clear();
        self.entity_section(at, "$PartitionedEntities", true)
    }

    /// The body of `$Entities` or `$PartitionedEntities` (the latter starts
    /// with the partition count and the ghost entities, and each entity with
    /// its parent and its partitions).
    fn entity_section(&mut self, at: usize, name: &'static str, parted: bool) -> Res<()> {
        if self.elements_at.is_some() {
            return Err(self.err(at, format_args!("{name} must come before $Elements")));
        }
        self.section = name;
        if self.binary {
            self.end_of_line()?;
        }
        let mut partitions = 0;
        if parted {
            partitions = self.size("number of partitions")?;
            let ghosts = self.size("number of ghost entities")?;
            self.skip_ints(ghosts.saturating_mul(2), "ghost entity tag or partition")?;
        }
        // The partitions of each partitioned entity: (dimension, partition).
        let mut parts: Vec<(usize, i32)> = Vec::new();
        let mut counts = [0u64; 4];
        for c in &mut counts {
            *c = self.size("number of entities")?;
        }
        let mut map = HashMap::new();
        for (dim, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                let at = self.here();
                let tag = self.int("entity tag")?;
                let mut own = true;
                if parted {
                    let parent_at = self.here();
                    let parent = self.int("parent dimension")?;
                    if !(0..=3).contains(&parent) {
                        return Err(self.err(parent_at, "parent dimension must be 0 to 3"));
                    }
                    own = parent as usize == dim;
                    self.int("parent tag")?;
                    let np = self.size("number of partitions")?;
                    for _ in 0..np {
                        parts.push((dim, self.int("partition tag")?));
                    }
                }
                for _ in 0..if dim == 0 { 3 } else { 6 } {
                    self.real("entity coordinate")?;
                }
                let np = self.size("number of physical tags")?;
                let start = self.entity_phys.len();
                for _ in 0..np {
                    let p = self.int("physical tag")?;
                    if own {
                        self.entity_phys.push(p);
                    }
                }
                let end = self.entity_phys.len();
                if dim > 0 {
                    let nb = self.size("number of bounding entities")?;
                    self.skip_ints(nb, "bounding entity tag")?;
                }
                if map.insert((dim, tag), (start, end)).is_some() {
                    return Err(self.err(
                        at,
                        format_args!("duplicate entity (dimension {dim}, tag {tag})"),
                    ));
                }
            }
        }
        self.entities = Some(map);
        if parted {
            self.whole_partition(at, partitions, &counts, &parts)?;
        }
        self.expect_end(if parted {
            "$EndPartitionedEntities"
        } else {
            "$EndEntities"
        })
    }

    /// A partitioned file holds every partition that its entities name:
    /// each partition listed on an entity (an interface, a boundary piece)
    /// has cells, so it has an entity of the top dimension here unless the
    /// file is one piece of Gmsh's `-part_split` (one file per partition),
    /// which would read as a body cut along its interfaces. (A partition
    /// that no entity names may be empty: more partitions than cells.)
    fn whole_partition(
        &self,
        at: usize,
        partitions: u64,
        counts: &[u64; 4],
        parts: &[(usize, i32)],
    ) -> Res<()> {
        let Some(top) = (0..4).rev().find(|&d| counts[d] > 0) else {
            return Ok(());
        };
        let here: HashSet<i32> = parts
            .iter()
            .filter(|&&(d, _)| d == top)
            .map(|&(_, p)| p)
            .collect();
        let mut elsewhere: Vec<i32> = parts
            .iter()
            .map(|&(_, p)| p)
            .filter(|p| !here.contains(p))
            .collect();
        if elsewhere.is_empty() {
            return Ok(());
        }
        elsewhere.sort_unstable();
        elsewhere.dedup();
        let mut here: Vec<i32> = here.into_iter().collect();
        here.sort_unstable();
        let list = |v: &[i32]| {
            v.iter()
                .map(|p| p.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        Err(self.err(
            at,
            format_args!(
                "the file is one piece of a mesh that Gmsh split into files (-part_split): it \
                 holds partition{} {} of {partitions}, and the cells of partition{} {} next to \
                 it are in other files; mesh the model into one file (gmsh -part N without \
                 -part_split, or without -part)",
                if here.len() == 1 { "" } else { "s" },
                list(&here),
                if elsewhere.len() == 1 { "" } else { "s" },
                list(&elsewhere)
            ),
        ))
    }

    /// Skips `n` 4.1 integers (`int`: 4 bytes each in binary files).
    fn skip_ints(&mut self, n: u64, what: &str) -> Res<()> {
        if self.binary {
            let bytes = usize::try_from(n)
                .ok()
                .and_then(|n| n.checked_mul(4))
                .filter(|&n| n <= self.remaining())
                .ok_or_else(|| self.eof())?;
            self.pos += bytes;
        } else {
            for _ in 0..n {
                self.int(what)?;
            }
        }
        Ok(())
    }

    fn nodes(&mut self, at: usize) -> Res<()> {
        if self.nodes_seen {
            return Err(self.err(at, "duplicate $Nodes section"));
        }
        self.section = "$Nodes";
        self.nodes_at = at;
        if self.v4 {
            self.nodes_v4()?;
        } else {
            self.nodes_v2()?;
        }
        self.nodes_seen = true;
        self.expect_end("$EndNodes")
    }

    fn reserve_nodes(&mut self, n: usize) {
        self.node_tags.reserve(n);
        self.coords.reserve(n.saturating_mul(3));
    }

    fn add_node_tag(&mut self, at: usize, tag: u64) -> Res<()> {
        if !self.node_map.insert(tag, self.node_tags.len()) {
            return Err(self.err(at, format_args!("duplicate node tag {tag}")));
        }
        self.node_tags.push(tag);
        Ok(())
    }

    fn nodes_v2(&mut self) -> Res<()> {
        let n = self.a_u64("number of nodes")?;
        if self.binary {
            self.end_of_line()?;
        }
        let cap = self.cap(n, if self.binary { 28 } else { 8 });
        self.reserve_nodes(cap);
        for _ in 0..n {
            let at = self.here();
            let tag = if self.binary {
                let t = self.b_i32()?;
                u64::try_from(t).map_err(|_| self.err(at, format_args!("bad node tag {t}")))?
            } else {
                self.a_u64("node tag")?
            };
            self.add_node_tag(at, tag)?;
            for _ in 0..3 {
                let x = self.coord()?;
                self.coords.push(x);
            }
        }
        Ok(())
    }

    fn nodes_v4(&mut self) -> Res<()> {
        if self.binary {
            self.end_of_line()?;
        }
        let nblocks = self.size("number of node blocks")?;
        let total = self.size("number of nodes")?;
        self.size("minimum node tag")?;
        self.size("maximum node tag")?;
        let cap = self.cap(total, if self.binary { 32 } else { 8 });
        self.reserve_nodes(cap);
        let mut count: u64 = 0;
        for _ in 0..nblocks {
            let bat = self.here();
            let edim = self.int("entity dimension")?;
            self.int("entity tag")?;
            let param = self.int("parametric flag")?;
            let nb = self.size("number of nodes in the block")?;
            let Some(edim) = usize::try_from(edim).ok().filter(|&d| d <= 3) else {
                return Err(self.err(bat, format_args!("bad entity dimension {edim}")));
            };
            if !(0..=1).contains(&param) {
                return Err(self.err(bat, format_args!("bad parametric flag {param}")));
            }
            count = count
                .checked_add(nb)
                .filter(|&c| c <= total)
                .ok_or_else(|| {
                    self.err(
                        bat,
                        format_args!("node blocks hold more than the {total} nodes of the header"),
                    )
                })?;
            for _ in 0..nb {
                let at = self.here();
                let tag = self.size("node tag")?;
                self.add_node_tag(at, tag)?;
            }
            let extra = if param == 1 { edim } else { 0 };
            for _ in 0..nb {
                for _ in 0..3 {
                    let x = self.coord()?;
                    self.coords.push(x);
                }
                for _ in 0..extra {
                    self.real("parametric coordinate")?;
                }
            }
        }
        if count != total {
            let at = self.here();
            return Err(self.err(
                at,
                format_args!("the $Nodes header announces {total} nodes, the blocks hold {count}"),
            ));
        }
        Ok(())
    }

    fn elements(&mut self, at: usize) -> Res<()> {
        if self.elements_at.is_some() {
            return Err(self.err(at, "duplicate $Elements section"));
        }
        if !self.nodes_seen {
            return Err(self.err(at, "$Elements before $Nodes"));
        }
        self.elements_at = Some(at);
        self.section = "$Elements";
        if self.v4 {
            self.elements_v4()?;
        } else {
            self.elements_v2()?;
        }
        self.expect_end("$EndElements")
    }

    /// Dimension and node count of a supported type, else an error naming it.
    fn check_type(&self, at: usize, gmsh_type: i32) -> Res<(usize, usize)> {
        element_info(gmsh_type).ok_or_else(|| {
            const SUPPORTED: &str = "supported: points, 2-node lines, 3-node triangles, \
                                     4-node quadrilaterals, 4-node tetrahedra, 8-node hexahedra, \
                                     6-node prisms, 5-node pyramids";
            match gmsh_type_name(gmsh_type) {
                Some(name) => self.err(
                    at,
                    format_args!(
                        "{name} (Gmsh type {gmsh_type}) is not supported ({SUPPORTED}){}",
                        if name.contains("-order") {
                            "; mesh with first-order elements (gmsh -order 1, or \
                             Mesh.ElementOrder = 1 in the .geo file)"
                        } else {
                            ""
                        }
                    ),
                ),
                None => self.err(
                    at,
                    format_args!(
                        "unknown element type {gmsh_type} (not a Gmsh element type; {SUPPORTED})"
                    ),
                ),
            }
        })
    }

    fn undefined_node(&self, at: usize, tag: impl fmt::Display) -> MeshError {
        self.err(at, format_args!("element refers to undefined node {tag}"))
    }

    fn elements_v2(&mut self) -> Res<()> {
        let n = self.a_u64("number of elements")?;
        if self.binary {
            self.end_of_line()?;
            let mut done: u64 = 0;
            while done < n {
                let hat = self.pos;
                let gmsh_type = self.b_i32()?;
                let nf = self.b_i32()?;
                let ntags = self.b_i32()?;
                let (dim, k) = self.check_type(hat, gmsh_type)?;
                let Some(nf) = u64::try_from(nf).ok().filter(|&f| f > 0 && f <= n - done) else {
                    return Err(self.err(
                        hat,
                        format_args!(
                            "bad element block size {nf} ({} elements left of {n})",
                            n - done
                        ),
                    ));
                };
                let Ok(ntags) = u64::try_from(ntags) else {
                    return Err(self.err(hat, format_args!("bad number of tags {ntags}")));
                };
                for _ in 0..nf {
                    let etag = self.b_i32()?.max(0) as u64;
                    let mut phys = 0;
                    for j in 0..ntags {
                        let v = self.b_i32()?;
                        if j == 0 {
                            phys = v;
                        }
                    }
                    let mut conn = [0usize; MAX_NODES];
                    for c in conn.iter_mut().take(k) {
                        let at = self.pos;
                        let t = self.b_i32()?;
                        *c = u64::try_from(t)
                            .ok()
                            .and_then(|u| self.node_map.get(u))
                            .ok_or_else(|| self.undefined_node(at, t))?;
                    }
                    self.add_v2(gmsh_type, dim, k, conn, phys, etag);
                }
                done += nf;
            }
        } else {
            for _ in 0..n {
                let etag = self.a_u64("element tag")?;
                let (at, t) = self.token()?;
                let gmsh_type = parse_i32(t).ok_or_else(|| self.bad(at, t, "element type"))?;
                let (dim, k) = self.check_type(at, gmsh_type)?;
                let ntags = self.a_u64("number of tags")?;
                let mut phys = 0;
                for j in 0..ntags {
                    let v = self.a_i32("tag")?;
                    if j == 0 {
                        phys = v;
                    }
                }
                let mut conn = [0usize; MAX_NODES];
                for c in conn.iter_mut().take(k) {
                    let (at, t) = self.token()?;
                    let tag = parse_u64(t).ok_or_else(|| self.bad(at, t, "node tag"))?;
                    *c = self
                        .node_map
                        .get(tag)
                        .ok_or_else(|| self.undefined_node(at, tag))?;
                }
                self.add_v2(gmsh_type, dim, k, conn, phys, etag);
            }
        }
        Ok(())
    }

    /// Adds a 2.2 element; a cell repeating the previous element is Gmsh's
    /// copy for another physical group and only joins that group.
    fn add_v2(
        &mut self,
        gmsh_type: i32,
        dim: usize,
        k: usize,
        conn: [usize; MAX_NODES],
        phys: i32,
        etag: u64,
    ) {
        let repeat = self.prev_v2 == Some((gmsh_type, conn));
        self.prev_v2 = Some((gmsh_type, conn));
        let c = conn.get(..k).unwrap_or(&conn);
        if !repeat {
            self.add_cell(dim, c, etag);
        }
        if phys != 0 {
            let g = self.group_slot(dim, phys);
            self.join(dim, g, c);
        }
    }

    /// The last element read (of dimension `dim`, nodes `c`) joins group
    /// `g`: a boundary element as an element of the group, a cell (dimension
    /// 2 or 3) as a member (a group of the mesh's dimension is a body).
    fn join(&mut self, dim: usize, g: usize, c: &[usize]) {
        if dim < 3 {
            if let Some(group) = self.groups.get_mut(g) {
                group.conn.push(c);
            }
        }
        match dim {
            2 => self.members2.push((self.cells2.len() - 1, g as u32)),
            3 => self.members3.push((self.cells3.len() - 1, g as u32)),
            _ => {}
        }
    }

    /// Records a cell of dimension 2 or 3 (others are not cells).
    fn add_cell(&mut self, dim: usize, c: &[usize], etag: u64) {
        match dim {
            2 => {
                self.cells2.push(c);
                self.tags2.push(etag);
            }
            3 => {
                self.cells3.push(c);
                self.tags3.push(etag);
            }
            _ => {}
        }
    }

    /// Index in `groups` of physical group `(dim, tag)`, created if new.
    fn group_slot(&mut self, dim: usize, tag: i32) -> usize {
        if let Some((d, t, g)) = self.last_group {
            if d == dim && t == tag {
                return g;
            }
        }
        let n = self.groups.len();
        let g = *self.group_index.entry((dim, tag)).or_insert(n);
        if g == n {
            self.groups.push(GroupAcc {
                dim,
                tag,
                conn: Cells::new(),
            });
        }
        self.last_group = Some((dim, tag, g));
        g
    }

    fn elements_v4(&mut self) -> Res<()> {
        if self.binary {
            self.end_of_line()?;
        }
        let nblocks = self.size("number of element blocks")?;
        let total = self.size("number of elements")?;
        self.size("minimum element tag")?;
        self.size("maximum element tag")?;
        // Group entries allowed: a 4.1 entity with many physical tags
        // multiplies its elements, so bound that by the input size.
        let budget = self.b.len().saturating_mul(8).saturating_add(1 << 16);
        let mut count: u64 = 0;
        let mut slots: Vec<usize> = Vec::new();
        let mut seen: HashSet<usize> = HashSet::new();
        for _ in 0..nblocks {
            let bat = self.here();
            let edim = self.int("entity dimension")?;
            let etag = self.int("entity tag")?;
            let tat = self.here();
            let gmsh_type = self.int("element type")?;
            let nb = self.size("number of elements in the block")?;
            let (dim, k) = self.check_type(tat, gmsh_type)?;
            if usize::try_from(edim).ok() != Some(dim) {
                return Err(self.err(
                    bat,
                    format_args!(
                        "element type {gmsh_type} (dimension {dim}) in a block of entity dimension {edim}"
                    ),
                ));
            }
            count = count
                .checked_add(nb)
                .filter(|&c| c <= total)
                .ok_or_else(|| {
                    self.err(
                        bat,
                        format_args!(
                            "element blocks hold more than the {total} elements of the header"
                        ),
                    )
                })?;
            slots.clear();
            seen.clear();
            if let Some(ents) = &self.entities {
                let Some(&(s, e)) = ents.get(&(dim, etag)) else {
                    return Err(self.err(
                        bat,
                        format_args!(
                            "element block refers to entity (dimension {dim}, tag {etag}) \
                             that is not in {}",
                            if self.partitioned {
                                "$PartitionedEntities"
                            } else {
                                "$Entities"
                            }
                        ),
                    ));
                };
                if nb > 0 {
                    let phys = self.entity_phys.get(s..e).unwrap_or(&[]).to_vec();
                    for p in phys {
                        if p != 0 {
                            let g = self.group_slot(dim, p);
                            if seen.insert(g) {
                                slots.push(g);
                            }
                        }
                    }
                }
            }
            for _ in 0..nb {
                let etag = self.size("element tag")?;
                let mut conn = [0usize; MAX_NODES];
                for c in conn.iter_mut().take(k) {
                    let at = self.here();
                    let tag = self.size("node tag")?;
                    *c = self
                        .node_map
                        .get(tag)
                        .ok_or_else(|| self.undefined_node(at, tag))?;
                }
                let c = conn.get(..k).unwrap_or(&conn);
                self.add_cell(dim, c, etag);
                for &g in &slots {
                    self.join(dim, g, c);
                }
                self.group_entries = self.group_entries.saturating_add((k + 1) * slots.len());
                if self.group_entries > budget {
                    return Err(self.err(
                        bat,
                        "too many physical-group memberships for the size of the file",
                    ));
                }
            }
        }
        if count != total {
            let at = self.here();
            return Err(self.err(
                at,
                format_args!(
                    "the $Elements header announces {total} elements, the blocks hold {count}"
                ),
            ));
        }
        Ok(())
    }

    /// A 2D mesh loses its z coordinate: its cells must lie in a plane
    /// z = constant (up to rounding).
    fn check_planar(&self) -> Res<()> {
        let z = |v: usize| self.coords.get(3 * v + 2).copied().unwrap_or(0.0);
        let Some(&first) = self.cells2.nodes().first() else {
            return Ok(());
        };
        let z0 = z(first);
        let scale = self.coords.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        let tol = 1e-10 * scale;
        match self
            .cells2
            .nodes()
            .iter()
            .find(|&&v| (z(v) - z0).abs() > tol)
        {
            None => Ok(()),
            Some(&v) => Err(self.err(
                self.nodes_at,
                format_args!(
                    "2D mesh (no 3D cells) not in a plane z = constant: \
                     node {} has z = {}, node {} has z = {z0}; for a 3D body, \
                     put its volume in a Physical Volume (Gmsh writes only \
                     the elements of physical groups)",
                    self.node_tags.get(v).copied().unwrap_or(0),
                    z(v),
                    self.node_tags.get(first).copied().unwrap_or(0),
                ),
            )),
        }
    }

    fn finish(self) -> Res<Mesh> {
        let end = self.b.len();
        if !self.nodes_seen {
            return Err(self.err(end, "missing $Nodes section"));
        }
        let Some(elements_at) = self.elements_at else {
            return Err(self.err(end, "missing $Elements section"));
        };
        let dim = if !self.cells3.is_empty() {
            3
        } else if !self.cells2.is_empty() {
            2
        } else {
            return Err(self.err(
                elements_at,
                "no cells (triangles, quadrilaterals, tetrahedra, hexahedra, prisms or pyramids); \
                 put the body in a Physical Surface (2D) or Physical Volume (3D): Gmsh writes only \
                 the elements of physical groups",
            ));
        };
        if dim == 2 {
            self.check_planar()?;
        }
        let coords = if dim == 3 {
            self.coords
        } else {
            let mut xy = Vec::with_capacity(self.coords.len() / 3 * 2);
            for p in self.coords.chunks_exact(3) {
                xy.extend_from_slice(p.get(..2).unwrap_or(p));
            }
            xy
        };
        let (cells, cell_tags, members) = if dim == 3 {
            (self.cells3, self.tags3, self.members3)
        } else {
            (self.cells2, self.tags2, self.members2)
        };
        // Where each group lands among the mesh's groups (those of its dimension or lower).
        let mut kept = Vec::with_capacity(self.groups.len());
        let mut groups = Vec::new();
        for g in self.groups {
            kept.push(groups.len() as u32);
            if g.dim <= dim {
                let name = match self.names.get(&(g.dim, g.tag)) {
                    Some(n) => n.clone(),
                    None => g.tag.to_string(),
                };
                // A group of cells is kept by its name only, so that an
                // option naming it is told its dimension.
                let conn = if g.dim < dim { g.conn } else { Cells::new() };
                groups.push(Group::new(name, g.dim, conn));
            }
        }
        for key in &self.name_order {
            if key.0 <= dim && !self.group_index.contains_key(key) {
                if let Some(name) = self.names.get(key) {
                    groups.push(Group::new(name.clone(), key.0, Cells::new()));
                }
            }
        }
        let members = members
            .into_iter()
            .map(|(c, g)| (c, kept.get(g as usize).copied().unwrap_or(0)))
            .collect();
        let bodies = super::Bodies::from_members(cells.len(), members);
        let mut mesh = Mesh {
            dim,
            coords,
            node_tags: self.node_tags,
            cells,
            cell_tags,
            groups,
            bodies,
        };
        mesh.drop_unused_nodes();
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square as two triangles, with named and unnamed groups, a
    /// curve in two physical groups (Gmsh repeats its line), a physical point
    /// on an unused geometry point (node 5), and a section to skip.
    const SQ22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
4
0 10 \"corner\"
1 1 \"bottom\"
1 2 \"top\"
2 12 \"body\"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 2 2 0
$EndNodes
$Elements
7
1 15 2 10 1 1
2 15 2 11 5 5
3 1 2 1 1 1 2
4 1 2 2 3 3 4
5 1 2 3 3 3 4
6 2 2 12 1 1 2 3
7 2 2 12 1 1 3 4
$EndElements
$Comments
not $EndComments, and $End alone: skipped
$EndComments
";

    /// The same mesh in MSH 4.1 (with a parametric node block).
    const SQ41: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
4
0 10 \"corner\"
1 1 \"bottom\"
1 2 \"top\"
2 12 \"body\"
$EndPhysicalNames
$Entities
2 2 1 0
1 0 0 0 1 10
5 2 2 0 1 11
1 0 0 0 1 0 0 1 1 2 1 -2
3 0 1 0 1 1 0 2 2 3 2 3 -4
1 0 0 0 1 1 0 1 12 2 1 3
$EndEntities
$Periodic
0
$EndPeriodic
$Nodes
3 5 1 5
0 1 0 1
1
0 0 0
2 1 1 3
2
3
4
1 0 0 1 0
1 1 0 1 1
0 1 0 0 1
0 5 0 1
5
2 2 0
$EndNodes
$Elements
5 6 1 7
0 1 15 1
1 1
0 5 15 1
2 5
1 1 1 1
3 1 2
1 3 1 1
4 3 4
2 1 2 2
6 1 2 3
7 1 3 4
$EndElements
";

    fn parse(s: &[u8]) -> Result<Mesh, MeshError> {
        parse_gmsh(s, "t.msh")
    }

    fn ok(s: &[u8]) -> Mesh {
        match parse(s) {
            Ok(m) => m,
            Err(e) => panic!("unexpected error: {e}"),
        }
    }

    fn err(s: &[u8]) -> String {
        match parse(s) {
            Ok(m) => panic!("expected an error, got {m:?}"),
            Err(e) => e.0,
        }
    }

    /// A group of simplices (`dim + 1` nodes each).
    fn group(name: &str, dim: usize, conn: &[usize]) -> Group {
        Group::new(name, dim, Cells::uniform(conn.to_vec(), dim + 1))
    }

    /// The body groups of the cells: each cell's set, and the sets.
    fn bodies(cell_set: &[u32], sets: &[&[u32]]) -> crate::mesh::Bodies {
        crate::mesh::Bodies {
            cell_set: cell_set.to_vec(),
            sets: sets.iter().map(|s| s.to_vec()).collect(),
        }
    }

    /// `g`, of which `n` more elements in the file were off the body.
    fn off_body(mut g: Group, n: usize) -> Group {
        g.off_body = n;
        g.file_len = g.len() + n;
        g
    }

    /// A group of elements of any sizes.
    fn group_of(name: &str, dim: usize, elems: &[&[usize]]) -> Group {
        Group::new(name, dim, elems.iter().map(|e| e.to_vec()).collect())
    }

    fn square_expected() -> Mesh {
        Mesh {
            dim: 2,
            coords: vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0],
            node_tags: vec![1, 2, 3, 4],
            cells: Cells::uniform(vec![0, 1, 2, 0, 2, 3], 3),
            cell_tags: vec![],
            groups: vec![
                group("corner", 0, &[0]),
                off_body(group("11", 0, &[]), 1),
                group("bottom", 1, &[0, 1]),
                group("top", 1, &[2, 3]),
                group("3", 1, &[2, 3]),
                // The cells' group, by its name only.
                group("body", 2, &[]),
            ],
            // Both cells in "body".
            bodies: bodies(&[1, 1], &[&[], &[5]]),
        }
    }

    // ----- writers for test meshes -----

    struct TElem {
        gmsh_type: i32,
        entity: (i32, i32),
        phys: Vec<i32>,
        nodes: Vec<u64>,
    }

    struct TMesh {
        names: Vec<(i32, i32, &'static str)>,
        nodes: Vec<(u64, [f64; 3])>,
        elems: Vec<TElem>,
    }

    fn el(gmsh_type: i32, entity: (i32, i32), phys: &[i32], nodes: &[u64]) -> TElem {
        TElem {
            gmsh_type,
            entity,
            phys: phys.to_vec(),
            nodes: nodes.to_vec(),
        }
    }

    fn square() -> TMesh {
        TMesh {
            names: vec![
                (0, 10, "corner"),
                (1, 1, "bottom"),
                (1, 2, "top"),
                (2, 12, "body"),
            ],
            nodes: vec![
                (1, [0.0, 0.0, 0.0]),
                (2, [1.0, 0.0, 0.0]),
                (3, [1.0, 1.0, 0.0]),
                (4, [0.0, 1.0, 0.0]),
                (5, [2.0, 2.0, 0.0]),
            ],
            elems: vec![
                el(15, (0, 1), &[10], &[1]),
                el(15, (0, 5), &[11], &[5]),
                el(1, (1, 1), &[1], &[1, 2]),
                el(1, (1, 3), &[2, 3], &[3, 4]),
                el(2, (2, 1), &[12], &[1, 2, 3]),
                el(2, (2, 1), &[12], &[1, 3, 4]),
            ],
        }
    }

    /// Two tetrahedra with sparse node tags, a named boundary triangle, an
    /// unnamed edge group, an edge without a group, and a triangle without one.
    fn tets() -> TMesh {
        TMesh {
            names: vec![(2, 20, "base"), (3, 30, "solid"), (1, 40, "ghost")],
            nodes: vec![
                (10, [0.0, 0.0, 0.0]),
                (20, [1.0, 0.0, 0.0]),
                (30, [0.0, 1.0, 0.0]),
                (2_000_000_000, [0.0, 0.0, 1.0]),
                (7, [1.0, 1.0, 1.0]),
            ],
            elems: vec![
                el(1, (1, 1), &[], &[10, 20]),
                el(1, (1, 2), &[41], &[20, 30]),
                el(2, (2, 1), &[20], &[10, 30, 20]),
                el(2, (2, 2), &[], &[20, 30, 7]),
                el(4, (3, 1), &[30, 31], &[10, 20, 30, 2_000_000_000]),
                el(4, (3, 1), &[30, 31], &[20, 7, 30, 2_000_000_000]),
            ],
        }
    }

    fn tets_expected() -> Mesh {
        Mesh {
            dim: 3,
            coords: vec![
                0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0,
            ],
            node_tags: vec![10, 20, 30, 2_000_000_000, 7],
            cells: Cells::uniform(vec![0, 1, 2, 3, 1, 4, 2, 3], 4),
            cell_tags: vec![],
            groups: vec![
                group("41", 1, &[1, 2]),
                group("base", 2, &[0, 2, 1]),
                group("solid", 3, &[]),
                group("31", 3, &[]),
                group("ghost", 1, &[]),
            ],
            // Both cells in "solid" and in the unnamed "31".
            bodies: bodies(&[1, 1], &[&[], &[2, 3]]),
        }
    }

    struct Out {
        buf: Vec<u8>,
        binary: bool,
        big: bool,
    }

    impl Out {
        fn text(&mut self, s: &str) {
            self.buf.extend_from_slice(s.as_bytes());
        }
        fn int(&mut self, v: i32) {
            if self.binary {
                let b = if self.big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                self.buf.extend_from_slice(&b);
            } else {
                self.text(&format!("{v} "));
            }
        }
        fn size(&mut self, v: u64) {
            if self.binary {
                let b = if self.big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                self.buf.extend_from_slice(&b);
            } else {
                self.text(&format!("{v} "));
            }
        }
        fn real(&mut self, v: f64) {
            if self.binary {
                let b = if self.big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                };
                self.buf.extend_from_slice(&b);
            } else {
                self.text(&format!("{v:?} "));
            }
        }
        /// A 2.2 node tag: `int` in binary files.
        fn tag(&mut self, v: u64) {
            if self.binary {
                self.int(v as i32);
            } else {
                self.size(v);
            }
        }
        fn nl(&mut self) {
            if !self.binary {
                self.text("\n");
            }
        }
        fn header(&mut self, version: &str, m: &TMesh) {
            let ft = if self.binary { 1 } else { 0 };
            self.text(&format!("$MeshFormat\n{version} {ft} 8\n"));
            if self.binary {
                self.int(1);
                self.text("\n");
            }
            self.text("$EndMeshFormat\n");
            self.text(&format!("$PhysicalNames\n{}\n", m.names.len()));
            for (d, t, n) in &m.names {
                self.text(&format!("{d} {t} \"{n}\"\n"));
            }
            self.text("$EndPhysicalNames\n");
        }
    }

    fn write_v2(m: &TMesh, binary: bool, big: bool) -> Vec<u8> {
        let mut o = Out {
            buf: Vec::new(),
            binary,
            big,
        };
        o.header("2.2", m);
        o.text(&format!("$Nodes\n{}\n", m.nodes.len()));
        for (tag, x) in &m.nodes {
            o.tag(*tag);
            for &v in x {
                o.real(v);
            }
            o.nl();
        }
        if binary {
            o.text("\n");
        }
        o.text("$EndNodes\n");
        let lines: Vec<(&TElem, i32)> = m
            .elems
            .iter()
            .flat_map(|e| {
                let phys = if e.phys.is_empty() {
                    vec![0]
                } else {
                    e.phys.clone()
                };
                phys.into_iter().map(move |p| (e, p))
            })
            .collect();
        o.text(&format!("$Elements\n{}\n", lines.len()));
        for (i, (e, p)) in lines.iter().enumerate() {
            if binary {
                o.int(e.gmsh_type);
                o.int(1);
                o.int(2);
            } else {
                o.int(i as i32 + 1);
                o.int(e.gmsh_type);
                o.int(2);
            }
            if binary {
                o.int(i as i32 + 1);
            }
            o.int(*p);
            o.int(e.entity.1);
            for &n in &e.nodes {
                o.tag(n);
            }
            o.nl();
        }
        if binary {
            o.text("\n");
        }
        o.text("$EndElements\n");
        o.buf
    }

    fn write_v4(m: &TMesh, binary: bool, big: bool) -> Vec<u8> {
        let mut o = Out {
            buf: Vec::new(),
            binary,
            big,
        };
        o.header("4.1", m);
        // Entities in order of first use, with their physical tags.
        let mut ents: Vec<((i32, i32), Vec<i32>)> = Vec::new();
        for e in &m.elems {
            if !ents.iter().any(|(k, _)| *k == e.entity) {
                ents.push((e.entity, e.phys.clone()));
            }
        }
        if !ents.iter().any(|(k, _)| *k == (3, 1)) {
            ents.push(((2, 99), vec![]));
        }
        o.text("$Entities\n");
        for d in 0..4 {
            o.size(ents.iter().filter(|(k, _)| k.0 == d).count() as u64);
        }
        o.nl();
        for d in 0..4 {
            for ((_, tag), phys) in ents.iter().filter(|(k, _)| k.0 == d) {
                o.int(*tag);
                for _ in 0..if d == 0 { 3 } else { 6 } {
                    o.real(0.5);
                }
                o.size(phys.len() as u64);
                for &p in phys {
                    o.int(p);
                }
                if d > 0 {
                    o.size(2);
                    o.int(1);
                    o.int(-2);
                }
                o.nl();
            }
        }
        if binary {
            o.text("\n");
        }
        o.text("$EndEntities\n$Nodes\n");
        let n = m.nodes.len() as u64;
        let (lo, hi) = m
            .nodes
            .iter()
            .fold((u64::MAX, 0), |(lo, hi), (t, _)| (lo.min(*t), hi.max(*t)));
        o.size(1);
        o.size(n);
        o.size(lo);
        o.size(hi);
        o.nl();
        o.int(3);
        o.int(1);
        o.int(0);
        o.size(n);
        o.nl();
        for (t, _) in &m.nodes {
            o.size(*t);
            o.nl();
        }
        for (_, x) in &m.nodes {
            for &v in x {
                o.real(v);
            }
            o.nl();
        }
        if binary {
            o.text("\n");
        }
        o.text("$EndNodes\n$Elements\n");
        // Blocks of consecutive elements with the same entity and type.
        let mut blocks: Vec<Vec<&TElem>> = Vec::new();
        for e in &m.elems {
            match blocks.last_mut() {
                Some(b) if b[0].entity == e.entity && b[0].gmsh_type == e.gmsh_type => b.push(e),
                _ => blocks.push(vec![e]),
            }
        }
        o.size(blocks.len() as u64);
        o.size(m.elems.len() as u64);
        o.size(1);
        o.size(m.elems.len() as u64);
        o.nl();
        let mut tag = 0;
        for b in &blocks {
            o.int(b[0].entity.0);
            o.int(b[0].entity.1);
            o.int(b[0].gmsh_type);
            o.size(b.len() as u64);
            o.nl();
            for e in b {
                tag += 1;
                o.size(tag);
                for &n in &e.nodes {
                    o.size(n);
                }
                o.nl();
            }
        }
        if binary {
            o.text("\n");
        }
        o.text("$EndElements\n");
        o.buf
    }

    /// All encodings of a test mesh: (description, bytes).
    fn variants(m: &TMesh) -> Vec<(&'static str, Vec<u8>)> {
        vec![
            ("2.2 ascii", write_v2(m, false, false)),
            ("2.2 binary", write_v2(m, true, false)),
            ("2.2 binary big-endian", write_v2(m, true, true)),
            ("4.1 ascii", write_v4(m, false, false)),
            ("4.1 binary", write_v4(m, true, false)),
            ("4.1 binary big-endian", write_v4(m, true, true)),
        ]
    }

    // ----- valid files -----

    #[test]
    fn square_v22_ascii() {
        let m = ok(SQ22.as_bytes());
        assert_eq!(m, square_expected());
        assert_eq!(m.num_nodes(), 4);
        assert_eq!(m.num_cells(), 2);
        assert!(m.signed_measure(0) > 0.0 && m.signed_measure(1) > 0.0);
        assert_eq!(m.group("top").map(Group::len), Some(1));
        assert!(
            m.group("body").is_some_and(|g| g.dim == 2 && g.is_empty()),
            "a 2D group is kept by its name only"
        );
    }

    #[test]
    fn square_v41_ascii_matches_v22() {
        assert_eq!(ok(SQ41.as_bytes()), ok(SQ22.as_bytes()));
    }

    /// [`SQ41`] partitioned in two by hand as Gmsh's `-part 2` writes it:
    /// the model's `$Entities`, then `$PartitionedEntities` (one triangle in
    /// each part, and an interface curve 8 whose parent is the surface, with
    /// the surface's physical tag 12 and a line element on the diagonal),
    /// the node and element blocks referring to the partitioned entities.
    const SQ41P: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
4
0 10 \"corner\"
1 1 \"bottom\"
1 2 \"top\"
2 12 \"body\"
$EndPhysicalNames
$Entities
2 2 1 0
1 0 0 0 1 10
5 2 2 0 1 11
1 0 0 0 1 0 0 1 1 2 1 -2
3 0 1 0 1 1 0 2 2 3 2 3 -4
1 0 0 0 1 1 0 1 12 2 1 3
$EndEntities
$PartitionedEntities
2
1
3 2
2 3 2 0
11 0 1 1 1 0 0 0 1 10
15 0 5 1 2 2 2 0 1 11
6 1 1 1 1 0 0 0 1 0 0 1 1 2 11 -12
7 1 3 1 2 0 1 0 1 1 0 2 2 3 2 12 -13
8 2 1 2 1 2 0 0 0 1 1 0 1 12 0
2 2 1 1 1 0 0 0 1 1 0 1 12 1 8
3 2 1 1 2 0 0 0 1 1 0 1 12 1 -8
$EndPartitionedEntities
$Periodic
0
$EndPeriodic
$Nodes
3 5 1 5
0 11 0 1
1
0 0 0
2 2 1 3
2
3
4
1 0 0 1 0
1 1 0 1 1
0 1 0 0 1
0 15 0 1
5
2 2 0
$EndNodes
$Elements
7 7 1 8
0 11 15 1
1 1
0 15 15 1
2 5
1 6 1 1
3 1 2
1 7 1 1
4 3 4
1 8 1 1
8 1 3
2 2 2 1
6 1 2 3
2 3 2 1
7 1 3 4
$EndElements
$GhostElements
0
$EndGhostElements
";

    /// One file of Gmsh's `-part_split`: [`SQ41P`] without partition 2's
    /// triangle, which its interface curve 8 still names.
    #[test]
    fn split_partition_piece_is_refused() {
        let piece = SQ41P
            .replace("2\n1\n3 2\n2 3 2 0\n", "2\n1\n3 2\n2 3 1 0\n")
            .replace("3 2 1 1 2 0 0 0 1 1 0 1 12 1 -8\n", "");
        let e = err(piece.as_bytes());
        assert!(
            e.starts_with("t.msh:19: the file is one piece of a mesh that Gmsh split into files")
                && e.contains("holds partition 1 of 2, and the cells of partition 2 next to it"),
            "{e}"
        );
    }

    #[test]
    fn partitioned_v41_reads_whole() {
        assert_eq!(ok(SQ41P.as_bytes()), ok(SQ41.as_bytes()));
        assert_eq!(
            ok(SQ41P.replace('\n', "\r\n").as_bytes()),
            ok(SQ41.as_bytes())
        );
    }

    #[test]
    fn square_crlf_line_ends() {
        let crlf = SQ22.replace('\n', "\r\n");
        assert_eq!(ok(crlf.as_bytes()), square_expected());
        let crlf = SQ41.replace('\n', "\r\n");
        assert_eq!(ok(crlf.as_bytes()), square_expected());
    }

    #[test]
    fn square_all_encodings() {
        for (what, bytes) in variants(&square()) {
            match parse(&bytes) {
                Ok(m) => assert_eq!(m, square_expected(), "{what}"),
                Err(e) => panic!("{what}: {e}"),
            }
        }
    }

    #[test]
    fn binary_v41_and_v22() {
        let b41 = write_v4(&square(), true, false);
        assert!(b41.starts_with(b"$MeshFormat\n4.1 1 8\n\x01\x00\x00\x00\n"));
        assert_eq!(ok(&b41), square_expected());
        let b22 = write_v2(&square(), true, false);
        assert!(b22.starts_with(b"$MeshFormat\n2.2 1 8\n\x01\x00\x00\x00\n"));
        assert_eq!(ok(&b22), square_expected());
    }

    #[test]
    fn tetrahedra_3d() {
        for (what, bytes) in variants(&tets()) {
            match parse(&bytes) {
                Ok(m) => {
                    assert_eq!(m, tets_expected(), "{what}");
                    assert_eq!(m.num_cells(), 2);
                    assert_eq!(m.group("base").and_then(|g| g.conn.stride()), Some(3));
                }
                Err(e) => panic!("{what}: {e}"),
            }
        }
    }

    #[test]
    fn unused_geometry_point_dropped() {
        let m = ok(SQ22.as_bytes());
        assert!(!m.node_tags.contains(&5));
        assert_eq!(m.coords.len(), 8);
        // The point group on it survives, empty, and knows that its one
        // point is off the body.
        assert_eq!(m.group("11"), Some(&off_body(group("11", 0, &[]), 1)));
    }

    #[test]
    fn elements_without_group() {
        // Cells without a physical group are cells; a line without one is ignored.
        let s = SQ22
            .replace("6 2 2 12 1 1 2 3", "6 2 0 1 2 3")
            .replace("3 1 2 1 1 1 2", "3 1 2 0 1 1 2");
        let m = ok(s.as_bytes());
        assert_eq!(m.cells, Cells::uniform(vec![0, 1, 2, 0, 2, 3], 3));
        // "bottom" is named but has no elements: kept empty, after the others
        // (the cells' group "body" too, by its name).
        assert_eq!(m.groups.last(), Some(&group("bottom", 1, &[])));
        assert_eq!(m.groups.len(), 6);
        // The first cell is in no body group, the second in "body".
        assert_eq!(m.bodies.of(0), &[] as &[u32]);
        assert_eq!(m.bodies.of(1), &[4]);
        assert_eq!(m.groups[4].name, "body");
    }

    #[test]
    fn sparse_and_large_node_tags() {
        // Tags beyond `int` only fit 2.2 ASCII (read as u64) and 4.1.
        let mut sq = square();
        let big = 300_000_000_000;
        sq.nodes[2].0 = big;
        for e in &mut sq.elems {
            for n in &mut e.nodes {
                if *n == 3 {
                    *n = big;
                }
            }
        }
        let mut expected = square_expected();
        expected.node_tags[2] = big;
        for bytes in [
            write_v2(&sq, false, false),
            write_v4(&sq, false, false),
            write_v4(&sq, true, false),
        ] {
            assert_eq!(ok(&bytes), expected);
        }
    }

    // ----- errors -----

    fn replace_line(s: &str, line: usize, with: &str) -> String {
        s.lines()
            .enumerate()
            .map(|(i, l)| if i + 1 == line { with } else { l })
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn error_not_gmsh() {
        assert_eq!(
            err(b"hello\n$MeshFormat\n"),
            "t.msh:1: not a Gmsh mesh file (no $MeshFormat)"
        );
        assert_eq!(err(b""), "t.msh:1: not a Gmsh mesh file (no $MeshFormat)");
        assert!(err(b"\x89PNG\r\n").contains("no $MeshFormat"));
        assert!(err(b"\x1f\x8b\x08\x00")
            .ends_with("no $MeshFormat): it is gzip-compressed; gunzip it first"));
        let geo = parse_gmsh(b"Point(1) = {0, 0, 0};\n", "m.geo")
            .unwrap_err()
            .to_string();
        assert!(geo.starts_with("m.geo:1: not a Gmsh mesh file (no $MeshFormat): a .geo file is Gmsh's geometry; mesh it first"), "{geo}");
    }

    #[test]
    fn error_truncated_in_nodes() {
        let s: String = SQ22.lines().take(15).map(|l| format!("{l}\n")).collect();
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:15: unexpected end of file in $Nodes"
        );
        let cut = &SQ41.as_bytes()[..SQ41.find("\n1 1 0 1 1\n").unwrap() + 5];
        assert_eq!(err(cut), "t.msh:32: unexpected end of file in $Nodes");
    }

    #[test]
    fn error_bad_number() {
        let s = replace_line(SQ22, 15, "3 1 1x 0");
        assert_eq!(err(s.as_bytes()), "t.msh:15: bad coordinate `1x`");
        let s = replace_line(SQ22, 25, "5 1 2 3 3 3 four");
        assert_eq!(err(s.as_bytes()), "t.msh:25: bad node tag `four`");
        let s = replace_line(SQ22, 12, "-5");
        assert_eq!(err(s.as_bytes()), "t.msh:12: bad number of nodes `-5`");
        let s = replace_line(SQ22, 15, "3 1 nan 0");
        assert_eq!(err(s.as_bytes()), "t.msh:15: non-finite coordinate NaN");
        let s = replace_line(SQ22, 15, "3 1 \u{e9} 0");
        assert_eq!(err(s.as_bytes()), "t.msh:15: bad coordinate `\\xc3\\xa9`");
        let s = replace_line(SQ22, 15, "99999999999999999999 1 1 0");
        assert!(err(s.as_bytes()).starts_with("t.msh:15: bad node tag"));
    }

    #[test]
    fn error_unknown_node_tag() {
        let s = replace_line(SQ22, 27, "7 2 2 12 1 1 3 9");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:27: element refers to undefined node 9"
        );
        let s = SQ41.replace("7 1 3 4", "7 1 3 44");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:50: element refers to undefined node 44"
        );
    }

    #[test]
    fn error_unsupported_element_type() {
        let s = replace_line(SQ22, 27, "7 9 2 12 1 1 2 3 4 5 6");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:27: second-order triangle (Gmsh type 9) is not supported \
             (supported: points, 2-node lines, 3-node triangles, 4-node quadrilaterals, \
             4-node tetrahedra, 8-node hexahedra, 6-node prisms, 5-node pyramids); mesh with \
             first-order elements (gmsh -order 1, or Mesh.ElementOrder = 1 in the .geo file)"
        );
        let s = SQ41.replace("2 1 2 2\n", "2 1 9 2\n");
        assert!(err(s.as_bytes())
            .starts_with("t.msh:48: second-order triangle (Gmsh type 9) is not supported ("));
        for (t, words) in [
            (8, "second-order line (Gmsh type 8)"),
            (10, "second-order 9-node quadrilateral (Gmsh type 10)"),
            (11, "second-order tetrahedron (Gmsh type 11)"),
            (16, "second-order 8-node quadrilateral (Gmsh type 16)"),
            (17, "second-order 20-node hexahedron (Gmsh type 17)"),
            (21, "third-order triangle (Gmsh type 21)"),
        ] {
            let s = replace_line(SQ22, 27, &format!("7 {t} 2 12 1 1 2 3"));
            assert!(err(s.as_bytes()).starts_with(&format!("t.msh:27: {words} is not supported (")));
        }
        let s = replace_line(SQ22, 27, "7 200 2 12 1 1 2 3");
        assert!(err(s.as_bytes()).starts_with("t.msh:27: unknown element type 200 (not a Gmsh"));
    }

    /// A quadrilateral and a triangle sharing an edge, in 2D, with a
    /// boundary line group; the 2.2 repeat rule compares the type too.
    fn mixed2d() -> TMesh {
        TMesh {
            names: vec![(1, 1, "bottom"), (2, 2, "body")],
            nodes: vec![
                (1, [0.0, 0.0, 0.0]),
                (2, [1.0, 0.0, 0.0]),
                (3, [1.0, 1.0, 0.0]),
                (4, [0.0, 1.0, 0.0]),
                (5, [2.0, 0.5, 0.0]),
            ],
            elems: vec![
                el(1, (1, 1), &[1], &[1, 2]),
                el(3, (2, 1), &[2], &[1, 2, 3, 4]),
                el(2, (2, 2), &[2], &[2, 5, 3]),
            ],
        }
    }

    /// A hexahedron and a tetrahedron on its top face, with a boundary
    /// group holding the hexahedron's bottom quadrilateral and a triangle.
    fn mixed3d() -> TMesh {
        let mut nodes: Vec<(u64, [f64; 3])> = Vec::new();
        for (i, c) in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
            [0.5, 0.5, 2.0],
        ]
        .iter()
        .enumerate()
        {
            nodes.push((i as u64 + 1, *c));
        }
        TMesh {
            names: vec![(2, 1, "faces"), (3, 2, "solid")],
            nodes,
            elems: vec![
                el(3, (2, 1), &[1], &[1, 4, 3, 2]),
                el(2, (2, 2), &[1], &[5, 6, 9]),
                el(5, (3, 1), &[2], &[1, 2, 3, 4, 5, 6, 7, 8]),
                el(4, (3, 2), &[2], &[5, 6, 7, 9]),
            ],
        }
    }

    #[test]
    fn mixed_cells_all_encodings() {
        let m2 = Mesh {
            dim: 2,
            coords: vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 2.0, 0.5],
            node_tags: vec![1, 2, 3, 4, 5],
            cells: vec![vec![0, 1, 2, 3], vec![1, 4, 2]].into_iter().collect(),
            cell_tags: vec![],
            groups: vec![group("bottom", 1, &[0, 1]), group("body", 2, &[])],
            bodies: bodies(&[1, 1], &[&[], &[1]]),
        };
        let m3 = Mesh {
            dim: 3,
            coords: mixed3d().nodes.iter().flat_map(|(_, x)| *x).collect(),
            node_tags: (1..=9).collect(),
            cells: vec![(0..8).collect(), vec![4, 5, 6, 8]]
                .into_iter()
                .collect(),
            cell_tags: vec![],
            groups: vec![
                group_of("faces", 2, &[&[0, 3, 2, 1], &[4, 5, 8]]),
                group("solid", 3, &[]),
            ],
            bodies: bodies(&[1, 1], &[&[], &[1]]),
        };
        for (mesh, expected) in [(mixed2d(), m2), (mixed3d(), m3)] {
            for (what, bytes) in variants(&mesh) {
                match parse(&bytes) {
                    Ok(m) => {
                        assert_eq!(m, expected, "{what}");
                        assert_eq!(m.cells.stride(), None, "{what}");
                        assert_eq!(m.cell_tags.len(), 2, "{what}");
                    }
                    Err(e) => panic!("{what}: {e}"),
                }
            }
        }
        let m = ok(&write_v2(&mixed3d(), false, false));
        assert_eq!(m.cell_kinds_label(), "tetrahedra and hexahedra");
        assert!((m.signed_measure(0) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn error_unsupported_version() {
        for v in ["3.0", "4.0", "1.0", "2.1", "4"] {
            let s = replace_line(SQ22, 2, &format!("{v} 0 8"));
            assert_eq!(
                err(s.as_bytes()),
                format!("t.msh:2: unsupported MSH version {v} (only 2.2 and 4.1 are supported)")
            );
        }
    }

    #[test]
    fn error_counts_and_markers() {
        let s = replace_line(SQ22, 12, "6");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:18: expected node tag, found `$EndNodes` (fewer entries than the header count?)"
        );
        let s = replace_line(SQ22, 12, "4");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:17: expected $EndNodes, found `5` (more entries than the header count?)"
        );
        let s = replace_line(SQ22, 18, "");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:19: expected $EndNodes, found `$Elements`"
        );
        let s: String = SQ22.lines().take(27).map(|l| format!("{l}\n")).collect();
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:27: unexpected end of file in $Elements (missing $EndElements)"
        );
        let s: String = SQ22.lines().take(18).map(|l| format!("{l}\n")).collect();
        assert_eq!(err(s.as_bytes()), "t.msh:18: missing $Elements section");
        let s = SQ22.replace(
            "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 2 0\n$EndNodes\n",
            "",
        );
        assert_eq!(err(s.as_bytes()), "t.msh:11: $Elements before $Nodes");
        let s = SQ22.replace("$Comments", "$Comment");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:29: section `$Comment` has no `$EndComment` line"
        );
        let s = replace_line(SQ41, 23, "3 6 1 6");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:37: the $Nodes header announces 6 nodes, the blocks hold 5"
        );
        let s = replace_line(SQ41, 23, "3 4 1 5");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:34: node blocks hold more than the 4 nodes of the header"
        );
        let s = replace_line(SQ41, 39, "5 7 1 7");
        assert!(err(s.as_bytes()).starts_with("t.msh:51: the $Elements header announces 7"));
    }

    #[test]
    fn error_other_cases() {
        let s = replace_line(SQ22, 16, "3 0 1 0");
        assert_eq!(err(s.as_bytes()), "t.msh:16: duplicate node tag 3");
        let s = replace_line(SQ22, 6, "0 10 \"cor\u{fffd}ner");
        assert_eq!(err(s.as_bytes()), "t.msh:6: unterminated physical name");
        let mut b = SQ22.as_bytes().to_vec();
        b[62] = 0xff; // inside "corner"
        assert_eq!(err(&b), "t.msh:6: physical name is not valid UTF-8");
        let s = SQ22
            .replace("7\n1 15", "5\n1 15")
            .replace("6 2 2 12 1 1 2 3\n7 2 2 12 1 1 3 4\n", "");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:19: no cells (triangles, quadrilaterals, tetrahedra, hexahedra, prisms or pyramids); \
             put the body in a Physical Surface (2D) or Physical Volume (3D): Gmsh writes only the \
             elements of physical groups"
        );
        let s = SQ41.replace("1 3 1 1\n4 3 4", "1 4 1 1\n4 3 4");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:46: element block refers to entity (dimension 1, tag 4) that is not in $Entities"
        );
        let s = SQ41P.replace(
            "$EndEntities\n",
            "$EndEntities\n$Entities\n0 0 0 0\n$EndEntities\n",
        );
        assert_eq!(err(s.as_bytes()), "t.msh:19: duplicate $Entities section");
        let s = SQ41P.replace(
            "$EndPeriodic\n",
            "$EndPeriodic\n$Entities\n0 0 0 0\n$EndEntities\n",
        );
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:35: $Entities must come before $PartitionedEntities"
        );
        let s = SQ41P.replace(
            "$Periodic",
            "$PartitionedEntities\n1\n0\n0 0 0 0\n$EndPartitionedEntities\n$Periodic",
        );
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:32: duplicate $PartitionedEntities section"
        );
        let s = SQ41P.replace("8 2 1 2 1 2", "8 4 1 2 1 2");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:28: parent dimension must be 0 to 3"
        );
        let s = SQ41P.replace("0 15 15 1\n", "0 5 15 1\n");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:55: element block refers to entity (dimension 0, tag 5) that is not in $PartitionedEntities"
        );
        let s = replace_line(SQ22, 2, "2.2 2 8");
        assert!(err(s.as_bytes()).starts_with("t.msh:2: bad file type `2`"));
        let s = SQ22.replace("$EndElements", "$EndElements\n7");
        assert!(err(s.as_bytes()).starts_with("t.msh:29: expected a section header"));
        let s = SQ22.replace("$Nodes\n5\n", "$Nodes\n1000000000000000000\n");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:18: expected node tag, found `$EndNodes` (fewer entries than the header count?)"
        );
    }

    #[test]
    fn error_2d_not_planar() {
        let s = replace_line(SQ22, 15, "3 1 1 0.5");
        assert_eq!(
            err(s.as_bytes()),
            "t.msh:11: 2D mesh (no 3D cells) not in a plane z = constant: \
             node 3 has z = 0.5, node 1 has z = 0; for a 3D body, put its \
             volume in a Physical Volume (Gmsh writes only the elements of \
             physical groups)"
        );
        // A constant z, or an off-plane node no triangle uses, is fine.
        let s = SQ22
            .replace(" 0\n", " 2.5\n")
            .replace("5 2 2 2.5", "5 2 2 7");
        assert_eq!(ok(s.as_bytes()), square_expected());
    }

    #[test]
    fn error_binary() {
        let b = write_v4(&square(), true, false);
        let at = b.windows(7).position(|w| w == b"$Nodes\n").unwrap() + 7;
        let cut = &b[..at + 40];
        assert_eq!(
            err(cut),
            format!("t.msh: byte {}: unexpected end of file in $Nodes", at + 40)
        );
        let mut bad = b.clone();
        bad[20] = 2; // endianness marker
        assert_eq!(
            err(&bad),
            "t.msh: byte 20: bad endianness marker (expected the integer 1)"
        );
        let s = String::from_utf8_lossy(&b).replace("4.1 1 8", "4.1 1 4");
        assert!(err(s.as_bytes()).starts_with("t.msh: byte 18: unsupported data size `4`"));
        // A node count of 2^60 must fail at the end, not allocate.
        let mut huge = b.clone();
        huge[at + 8..at + 16].copy_from_slice(&(1u64 << 60).to_le_bytes());
        assert!(err(&huge).starts_with("t.msh: byte "));
        // 2.2: an undefined node and an unsupported type.
        let b = write_v2(&square(), true, false);
        let el = b.windows(10).position(|w| w == b"$Elements\n").unwrap() + 12;
        let mut bad = b.clone();
        bad[el..el + 4].copy_from_slice(&9i32.to_le_bytes());
        assert!(err(&bad).starts_with(&format!(
            "t.msh: byte {el}: second-order triangle (Gmsh type 9) is not supported"
        )));
        let mut bad = b.clone();
        bad[el + 24..el + 28].copy_from_slice(&(-1i32).to_le_bytes());
        assert_eq!(
            err(&bad),
            format!(
                "t.msh: byte {}: element refers to undefined node -1",
                el + 24
            )
        );
    }

    // ----- robustness -----

    struct XorShift(u64);

    impl XorShift {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next() % n.max(1) as u64) as usize
        }
    }

    fn mutate(rng: &mut XorShift, input: &[u8]) -> Vec<u8> {
        const SPECIAL: &[u8] = b"$\n \"-.0159e\xff\x00\x7f";
        let mut b = input.to_vec();
        for _ in 0..1 + rng.below(3) {
            let i = rng.below(b.len());
            match rng.below(7) {
                0 if !b.is_empty() => b[i] ^= 1 << rng.below(8),
                1 if !b.is_empty() => b[i] = SPECIAL[rng.below(SPECIAL.len())],
                2 => b.insert(i, SPECIAL[rng.below(SPECIAL.len())]),
                3 if !b.is_empty() => {
                    b.remove(i);
                }
                4 => {
                    // Hostile counts: large binary or text numbers.
                    let fill: &[u8] = match rng.below(4) {
                        0 => &[0xff; 8],
                        1 => &[0x7f, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x0f],
                        2 => b"1000000000000000000",
                        _ => b"4294967295",
                    };
                    for (k, &c) in fill.iter().enumerate() {
                        if let Some(x) = b.get_mut(i + k) {
                            *x = c;
                        }
                    }
                }
                5 => {
                    let j = rng.below(b.len());
                    let (lo, hi) = (i.min(j), i.max(j));
                    let chunk = b[lo..hi.min(lo + 64)].to_vec();
                    let at = rng.below(b.len());
                    b.splice(at..at, chunk);
                }
                _ => b.truncate(i),
            }
        }
        b
    }

    fn no_panic(what: &str, bytes: &[u8]) {
        let r = std::panic::catch_unwind(|| parse_gmsh(bytes, "f.msh"));
        match r {
            Ok(Ok(m)) => {
                let d = m.dim;
                assert!(d == 2 || d == 3);
                assert_eq!(m.coords.len(), d * m.node_tags.len());
                assert!(m.cells.nodes().iter().all(|&v| v < m.node_tags.len()));
            }
            Ok(Err(e)) => {
                assert!(e.0.starts_with("f.msh"), "{what}: {e}");
                assert!(!e.0.contains('\n') && !e.0.contains('\r'), "{what}: {e:?}");
            }
            Err(_) => panic!(
                "parse_gmsh panicked on {what}: {:?}",
                bytes.escape_ascii().to_string()
            ),
        }
    }

    #[test]
    fn no_panic_on_mutations() {
        let mut files: Vec<(String, Vec<u8>)> = vec![
            ("SQ22".into(), SQ22.as_bytes().to_vec()),
            ("SQ41".into(), SQ41.as_bytes().to_vec()),
            ("SQ41P".into(), SQ41P.as_bytes().to_vec()),
        ];
        for (what, b) in variants(&square())
            .into_iter()
            .chain(variants(&tets()))
            .chain(variants(&mixed3d()))
        {
            files.push((what.to_string(), b));
        }
        let mut runs = 0;
        for (what, b) in &files {
            no_panic(what, b);
            for n in 0..b.len() {
                no_panic(&format!("{what} cut at {n}"), &b[..n]);
                runs += 1;
            }
        }
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        while runs < 20_000 {
            for (what, b) in &files {
                let m = mutate(&mut rng, b);
                no_panic(&format!("mutated {what}"), &m);
                runs += 1;
            }
        }
    }
}
