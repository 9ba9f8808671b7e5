//! Reading an obstacle's surface: Gmsh MSH 2.2 and 4.1 (ASCII), and STL
//! (ASCII and binary) in 3D.

use super::geom::V3;
use super::{Surface, OPTION};
use crate::error::{bad, Error};
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// Reads the surface of a `dim`-D obstacle (all elements of dimension
/// `dim - 1`, or those of physical group `group`).
pub(super) fn read(path: &Path, dim: usize, group: Option<&str>) -> Result<Surface, Error> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        let hint = crate::options::files::path_hint(OPTION, &file);
        Error::BadInput(format!("option {OPTION}: cannot read '{file}': {e}{hint}"))
    })?;
    let start = bytes.iter().position(|c| !c.is_ascii_whitespace());
    let text_start = bytes.get(start.unwrap_or(0)..).unwrap_or(&[]);
    if text_start.starts_with(b"$MeshFormat") {
        let text = String::from_utf8_lossy(&bytes);
        return Gmsh::new(&text, &file, dim).read(group);
    }
    let binary_stl = stl_binary_count(&bytes).is_some();
    if binary_stl || text_start.starts_with(b"solid") {
        if dim != 3 {
            return bad(format!(
                "option {OPTION}: {file}: an STL file is a 3D surface, the body is {dim}D"
            ));
        }
        if let Some(g) = group {
            return bad(format!(
                "option {OPTION}: {file}: an STL file has no physical groups (group '{g}' asked for)"
            ));
        }
        let facets = if binary_stl {
            stl_binary(&bytes)
        } else {
            stl_ascii(&String::from_utf8_lossy(&bytes), &file)?
        };
        return Ok(weld(facets, file));
    }
    let hint = crate::mesh::gmsh::not_a_mesh_hint(&bytes, &file, "gmsh -1 or -2");
    bad(format!(
        "option {OPTION}: {file}: not a Gmsh mesh ($MeshFormat) or an STL file (solid ...){hint}"
    ))
}

// ----- STL -----

/// The facet count of a binary STL file whose size matches it.
fn stl_binary_count(b: &[u8]) -> Option<usize> {
    let n = u32::from_le_bytes(b.get(80..84)?.try_into().ok()?) as usize;
    (n.checked_mul(50)?.checked_add(84)? == b.len()).then_some(n)
}

fn stl_binary(b: &[u8]) -> Vec<[V3; 3]> {
    let n = stl_binary_count(b).unwrap_or(0);
    let f = |at: usize| {
        let w = b.get(at..at + 4).and_then(|s| s.try_into().ok());
        f64::from(f32::from_le_bytes(w.unwrap_or([0; 4])))
    };
    (0..n)
        .map(|t| {
            // 12 bytes of normal, then the three vertices.
            let at = 84 + 50 * t + 12;
            [0, 1, 2].map(|v| [0, 1, 2].map(|k| f(at + 12 * v + 4 * k)))
        })
        .collect()
}

/// ASCII STL: `solid name`, then `facet normal nx ny nz`, `outer loop`,
/// three `vertex x y z`, `endloop`, `endfacet`, ..., `endsolid name`
/// (several solids are joined).
fn stl_ascii(text: &str, file: &str) -> Result<Vec<[V3; 3]>, Error> {
    let mut toks: Vec<(usize, &str)> = Vec::new();
    for (l, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(w) = words.next() {
            toks.push((l + 1, w));
            // The name after solid / endsolid may be anything.
            if w != "solid" && w != "endsolid" {
                toks.extend(words.map(|w| (l + 1, w)));
            }
        }
    }
    let last_line = toks.last().map_or(1, |t| t.0);
    let mut it = toks.into_iter().peekable();
    let err =
        |l: usize, what: String| Error::BadInput(format!("option {OPTION}: {file}:{l}: {what}"));
    let expect = |it: &mut std::iter::Peekable<std::vec::IntoIter<(usize, &str)>>,
                  want: &str|
     -> Result<(), Error> {
        match it.next() {
            Some((_, w)) if w == want => Ok(()),
            Some((l, w)) => Err(err(l, format!("expected `{want}`, found `{w}`"))),
            None => Err(err(
                last_line,
                format!("unexpected end of file (expected `{want}`)"),
            )),
        }
    };
    let mut facets = Vec::new();
    while it.peek().is_some() {
        expect(&mut it, "solid")?;
        while it.peek().is_some_and(|t| t.1 == "facet") {
            it.next();
            expect(&mut it, "normal")?;
            for _ in 0..3 {
                it.next();
            }
            expect(&mut it, "outer")?;
            expect(&mut it, "loop")?;
            let mut f = [[0.0; 3]; 3];
            for v in &mut f {
                expect(&mut it, "vertex")?;
                for x in v.iter_mut() {
                    *x = match it.next() {
                        Some((l, w)) => match w.parse::<f64>() {
                            Ok(x) if x.is_finite() => x,
                            _ => return Err(err(l, format!("bad vertex coordinate `{w}`"))),
                        },
                        None => {
                            return Err(err(last_line, "unexpected end of file in a vertex".into()))
                        }
                    };
                }
            }
            expect(&mut it, "endloop")?;
            expect(&mut it, "endfacet")?;
            facets.push(f);
        }
        expect(&mut it, "endsolid")?;
    }
    Ok(facets)
}

/// Nodes from an STL's facets: vertices with equal coordinates are one.
fn weld(facets: Vec<[V3; 3]>, file: String) -> Surface {
    let mut index: HashMap<[u64; 3], usize> = HashMap::new();
    let mut coords = Vec::new();
    let mut elems = Vec::with_capacity(facets.len());
    for f in &facets {
        elems.push(f.map(|p| {
            // + 0.0 makes -0.0 equal to 0.0.
            let key = p.map(|x| (x + 0.0).to_bits());
            *index.entry(key).or_insert_with(|| {
                coords.push(p);
                coords.len() - 1
            })
        }));
    }
    Surface {
        dim: 3,
        file,
        coords,
        elem_id: (1..=elems.len() as u64).collect(),
        elems,
        node_id: None,
    }
}

// ----- Gmsh -----

/// A kept element before the group filter: its tag, nodes (indices in
/// the file's node list), 2 to 4 of them, and its physical tag (2.2) or
/// entity tag (4.1).
struct RawElem {
    tag: u64,
    nodes: [usize; 4],
    k: usize,
    phys_or_entity: i32,
}

struct Gmsh<'a> {
    file: &'a str,
    dim: usize,
    lines: Vec<&'a str>,
    /// Index in `lines` of the next line to read.
    at: usize,
    v4: bool,
    names: HashMap<(usize, i32), String>,
    /// 4.1: the physical tags of each entity of the surface dimension.
    entities: HashMap<i32, Vec<i32>>,
    node_index: HashMap<u64, usize>,
    node_tags: Vec<u64>,
    coords: Vec<V3>,
    elems: Vec<RawElem>,
    section: &'static str,
}

type Line<'a> = (usize, Vec<&'a str>);

impl<'a> Gmsh<'a> {
    fn new(text: &'a str, file: &'a str, dim: usize) -> Gmsh<'a> {
        Gmsh {
            file,
            dim,
            lines: text.lines().collect(),
            at: 0,
            v4: false,
            names: HashMap::new(),
            entities: HashMap::new(),
            node_index: HashMap::new(),
            node_tags: Vec::new(),
            coords: Vec::new(),
            elems: Vec::new(),
            section: "$MeshFormat",
        }
    }

    fn err<T>(&self, line: usize, what: impl std::fmt::Display) -> Result<T, Error> {
        bad(format!("option {OPTION}: {}:{line}: {what}", self.file))
    }

    /// The next non-blank line, split into words.
    fn next(&mut self) -> Option<Line<'a>> {
        while let Some(l) = self.lines.get(self.at) {
            self.at += 1;
            let words: Vec<&str> = l.split_whitespace().collect();
            if !words.is_empty() {
                return Some((self.at, words));
            }
        }
        None
    }

    /// The next line, an error at the end of the file.
    fn line(&mut self, what: &str) -> Result<Line<'a>, Error> {
        match self.next() {
            Some(l) => Ok(l),
            None => {
                let n = self.lines.len().max(1);
                self.err(
                    n,
                    format_args!(
                        "unexpected end of file in {} (expected {what})",
                        self.section
                    ),
                )
            }
        }
    }

    /// Word `i` of line `l` as a number.
    fn num<T: std::str::FromStr>(&self, l: &Line<'_>, i: usize, what: &str) -> Result<T, Error> {
        match l.1.get(i).map(|w| w.parse::<T>()) {
            Some(Ok(x)) => Ok(x),
            Some(Err(_)) => self.err(l.0, format_args!("bad {what} `{}`", l.1[i])),
            None => self.err(l.0, format_args!("missing {what}")),
        }
    }

    fn coord(&self, l: &Line<'_>, i: usize) -> Result<f64, Error> {
        let x: f64 = self.num(l, i, "coordinate")?;
        if !x.is_finite() {
            return self.err(l.0, "coordinate is not finite");
        }
        Ok(x)
    }

    fn expect_end(&mut self, marker: &str) -> Result<(), Error> {
        let l = self.line(marker)?;
        if l.1[0] != marker {
            return self.err(l.0, format_args!("expected `{marker}`, found `{}`", l.1[0]));
        }
        Ok(())
    }

    fn read(mut self, group: Option<&str>) -> Result<Surface, Error> {
        self.format()?;
        let mut seen = Vec::new();
        while let Some(l) = self.next() {
            match l.1[0] {
                "$PhysicalNames" => self.physical_names()?,
                "$Entities" if self.v4 => self.entities()?,
                "$Nodes" | "$Elements" if seen.contains(&l.1[0]) => {
                    return self.err(l.0, format_args!("a second {} section", l.1[0]))
                }
                "$Nodes" => {
                    seen.push("$Nodes");
                    self.nodes()?
                }
                "$Elements" => {
                    seen.push("$Elements");
                    self.elements()?
                }
                w if w.starts_with("$End") || !w.starts_with('$') => {
                    return self.err(l.0, format_args!("expected a section header, found `{w}`"))
                }
                w => {
                    let end = format!("$End{}", &w[1..]);
                    while self.line(&end)?.1[0] != end {}
                }
            }
        }
        self.finish(group)
    }

    fn format(&mut self) -> Result<(), Error> {
        self.next();
        let l = self.line("the version")?;
        match l.1[0] {
            "2.2" => self.v4 = false,
            "4.1" => self.v4 = true,
            v => {
                return self.err(
                    l.0,
                    format_args!("unsupported MSH version {v} (2.2 and 4.1 are read)"),
                )
            }
        }
        if l.1.get(1) != Some(&"0") {
            return self.err(
                l.0,
                "a binary MSH file; write the obstacle's surface as ASCII (gmsh -format msh41 without -bin)",
            );
        }
        self.expect_end("$EndMeshFormat")
    }

    /// `dim tag "name"` per line.
    fn physical_names(&mut self) -> Result<(), Error> {
        self.section = "$PhysicalNames";
        let l = self.line("the number of names")?;
        let n: usize = self.num(&l, 0, "number of physical names")?;
        for _ in 0..n {
            let l = self.line("a physical name")?;
            let d: usize = self.num(&l, 0, "physical dimension")?;
            let tag: i32 = self.num(&l, 1, "physical tag")?;
            let raw = self.lines[l.0 - 1].trim();
            let name = raw.find('"').map_or("", |i| &raw[i..]).trim_matches('"');
            self.names.insert((d, tag), name.to_string());
        }
        self.expect_end("$EndPhysicalNames")
    }

    /// 4.1: the physical tags of the entities of the surface dimension.
    fn entities(&mut self) -> Result<(), Error> {
        self.section = "$Entities";
        let l = self.line("the entity counts")?;
        let mut counts = [0usize; 4];
        for (i, c) in counts.iter_mut().enumerate() {
            *c = self.num(&l, i, "number of entities")?;
        }
        for (d, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                let l = self.line("an entity")?;
                let tag: i32 = self.num(&l, 0, "entity tag")?;
                let at = if d == 0 { 4 } else { 7 };
                let np: usize = self.num(&l, at, "number of physical tags")?;
                let mut phys = Vec::with_capacity(np.min(64));
                for j in 0..np {
                    phys.push(self.num(&l, at + 1 + j, "physical tag")?);
                }
                if d + 1 == self.dim {
                    self.entities.insert(tag, phys);
                }
            }
        }
        self.expect_end("$EndEntities")
    }

    fn add_node(&mut self, line: usize, tag: u64) -> Result<(), Error> {
        if self.node_index.insert(tag, self.node_tags.len()).is_some() {
            return self.err(line, format_args!("duplicate node tag {tag}"));
        }
        self.node_tags.push(tag);
        Ok(())
    }

    fn nodes(&mut self) -> Result<(), Error> {
        self.section = "$Nodes";
        let h = self.line("the node count")?;
        if !self.v4 {
            let n: usize = self.num(&h, 0, "number of nodes")?;
            for _ in 0..n {
                let l = self.line("a node")?;
                self.add_node(l.0, self.num(&l, 0, "node tag")?)?;
                let p = [self.coord(&l, 1)?, self.coord(&l, 2)?, self.coord(&l, 3)?];
                self.coords.push(p);
            }
            return self.expect_end("$EndNodes");
        }
        let blocks: usize = self.num(&h, 0, "number of node blocks")?;
        for _ in 0..blocks {
            let b = self.line("a node block")?;
            let n: usize = self.num(&b, 3, "number of nodes in the block")?;
            for _ in 0..n {
                let l = self.line("a node tag")?;
                self.add_node(l.0, self.num(&l, 0, "node tag")?)?;
            }
            for _ in 0..n {
                let l = self.line("node coordinates")?;
                let p = [self.coord(&l, 0)?, self.coord(&l, 1)?, self.coord(&l, 2)?];
                self.coords.push(p);
            }
        }
        self.expect_end("$EndNodes")
    }

    /// Node count of a kept element type; None for a type to skip, an
    /// error for a higher-order element of the surface dimension.
    fn kept_type(&self, line: usize, t: i32) -> Result<Option<usize>, Error> {
        let sdim = self.dim - 1;
        match (sdim, t) {
            (1, 1) => Ok(Some(2)),
            (2, 2) => Ok(Some(3)),
            (2, 3) => Ok(Some(4)),
            (1, 8 | 26..=28) | (2, 9 | 10 | 16 | 20..=25) => {
                self.err(
                    line,
                    format_args!(
                    "higher-order element (Gmsh type {t}); mesh the obstacle with first-order {}",
                    if sdim == 1 { "lines" } else { "triangles or quadrilaterals" }
                ),
                )
            }
            _ => Ok(None),
        }
    }

    /// An element of `k` nodes from words `first..` of `l`.
    fn push_elem(
        &mut self,
        l: &Line<'_>,
        tag: u64,
        first: usize,
        k: usize,
        phys: i32,
    ) -> Result<(), Error> {
        let mut nodes = [0; 4];
        for (j, n) in nodes.iter_mut().take(k).enumerate() {
            let t: u64 = self.num(l, first + j, "node tag")?;
            *n = match self.node_index.get(&t) {
                Some(&i) => i,
                None => {
                    return self.err(
                        l.0,
                        format_args!("element {tag} refers to undefined node {t}"),
                    )
                }
            };
        }
        self.elems.push(RawElem {
            tag,
            nodes,
            k,
            phys_or_entity: phys,
        });
        Ok(())
    }

    fn elements(&mut self) -> Result<(), Error> {
        self.section = "$Elements";
        let h = self.line("the element count")?;
        if !self.v4 {
            let n: usize = self.num(&h, 0, "number of elements")?;
            for _ in 0..n {
                let l = self.line("an element")?;
                let tag: u64 = self.num(&l, 0, "element tag")?;
                let t: i32 = self.num(&l, 1, "element type")?;
                let ntags: usize = self.num(&l, 2, "number of tags")?;
                if let Some(k) = self.kept_type(l.0, t)? {
                    let phys = if ntags > 0 {
                        self.num(&l, 3, "physical tag")?
                    } else {
                        0
                    };
                    self.push_elem(&l, tag, 3 + ntags, k, phys)?;
                }
            }
            return self.expect_end("$EndElements");
        }
        let blocks: usize = self.num(&h, 0, "number of element blocks")?;
        for _ in 0..blocks {
            let b = self.line("an element block")?;
            let entity: i32 = self.num(&b, 1, "entity tag")?;
            let t: i32 = self.num(&b, 2, "element type")?;
            let n: usize = self.num(&b, 3, "number of elements in the block")?;
            let kept = self.kept_type(b.0, t)?;
            for _ in 0..n {
                let l = self.line("an element")?;
                if let Some(k) = kept {
                    let tag = self.num(&l, 0, "element tag")?;
                    self.push_elem(&l, tag, 1, k, entity)?;
                }
            }
        }
        self.expect_end("$EndElements")
    }
}

impl Gmsh<'_> {
    /// The physical tags of group `g` (a name, or a number), of the
    /// surface dimension; an error naming the groups there are.
    fn group_tags(&self, g: &str) -> Result<HashSet<i32>, Error> {
        let sdim = self.dim - 1;
        let mut tags: HashSet<i32> = self
            .names
            .iter()
            .filter(|((d, _), name)| *d == sdim && name.as_str() == g)
            .map(|((_, t), _)| *t)
            .collect();
        if tags.is_empty() {
            if let Ok(t) = g.parse::<i32>() {
                tags.insert(t);
            } else {
                let mut have: Vec<&str> = self
                    .names
                    .iter()
                    .filter(|((d, _), _)| *d == sdim)
                    .map(|(_, n)| n.as_str())
                    .collect();
                have.sort_unstable();
                return bad(format!(
                    "option {OPTION}: {}: no physical group '{g}' of dimension {sdim} ({})",
                    self.file,
                    if have.is_empty() {
                        "the file names none".to_string()
                    } else {
                        format!("the file has: {}", have.join(", "))
                    }
                ));
            }
        }
        Ok(tags)
    }

    /// The kept elements (of group `group`), duplicates dropped,
    /// quadrilaterals split, nodes renumbered to the used ones.
    fn finish(self, group: Option<&str>) -> Result<Surface, Error> {
        let wanted = group.map(|g| self.group_tags(g)).transpose()?;
        let member = |e: &RawElem| match &wanted {
            None => true,
            Some(w) if self.v4 => self
                .entities
                .get(&e.phys_or_entity)
                .is_some_and(|ps| ps.iter().any(|p| w.contains(p))),
            Some(w) => w.contains(&e.phys_or_entity),
        };
        let mut seen = HashSet::new();
        let mut renumber = vec![usize::MAX; self.coords.len()];
        let mut surface = Surface {
            dim: self.dim,
            file: self.file.to_string(),
            coords: Vec::new(),
            elems: Vec::new(),
            elem_id: Vec::new(),
            node_id: Some(Vec::new()),
        };
        let mut used = Vec::new();
        for e in self.elems.iter().filter(|e| member(e)) {
            // Gmsh 2.2 repeats an element once per physical group.
            if !seen.insert(e.nodes) {
                continue;
            }
            let nodes = e.nodes.map(|i| {
                if renumber[i] == usize::MAX {
                    renumber[i] = used.len();
                    used.push(i);
                }
                renumber[i]
            });
            let [a, b, c, d] = nodes;
            match e.k {
                2 => surface.elems.push([a, b, b]),
                3 => surface.elems.push([a, b, c]),
                _ => surface.elems.extend([[a, b, c], [a, c, d]]),
            }
            let split = if e.k == 4 { 2 } else { 1 };
            surface.elem_id.extend(std::iter::repeat_n(e.tag, split));
        }
        if surface.elems.is_empty() {
            if let Some(g) = group {
                return bad(format!(
                    "option {OPTION}: {}: physical group '{g}' has no {}",
                    self.file,
                    if self.dim == 3 {
                        "triangles or quadrilaterals"
                    } else {
                        "line elements"
                    }
                ));
            }
        }
        surface.coords = used.iter().map(|&i| self.coords[i]).collect();
        surface.node_id = Some(used.iter().map(|&i| self.node_tags[i]).collect());
        if self.dim == 2 {
            flatten(&mut surface)?;
        }
        Ok(surface)
    }
}

/// A 2D obstacle's nodes lie in a plane z = constant: z becomes 0.
fn flatten(s: &mut Surface) -> Result<(), Error> {
    let Some(first) = s.coords.first().copied() else {
        return Ok(());
    };
    let scale = s
        .coords
        .iter()
        .flatten()
        .fold(1.0f64, |m, x| m.max(x.abs()));
    if let Some(i) = s
        .coords
        .iter()
        .position(|p| (p[2] - first[2]).abs() > 1e-10 * scale)
    {
        return s.error(format_args!(
            "a 2D obstacle not in a plane z = constant: {} has z = {}, {} has z = {}",
            s.node_name(i),
            s.coords[i][2],
            s.node_name(0),
            first[2]
        ));
    }
    for p in &mut s.coords {
        p[2] = 0.0;
    }
    Ok(())
}
