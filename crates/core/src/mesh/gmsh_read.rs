//! Reading Gmsh 4.1 meshes (`.msh`, ASCII or binary) into a [`Mesh`]: any planar shape can swing.
//!
//! **What is read.** `$MeshFormat` (version 4.1, file type 0 = ASCII or 1 = binary with 8-byte
//! `size_t`, either byte order), `$PhysicalNames`, `$Entities` (which physical groups each curve and
//! surface belongs to), `$Nodes` and `$Elements`; other sections are skipped. Triangles are 3-node
//! (type 2) or 6-node (type 9: corners, then the mid nodes of the edges 0→1, 1→2, 2→0), all of one
//! kind; 2- and 3-node lines (types 1 and 8) name boundary edges through the physical groups of
//! their curves; points (type 15) are ignored. The nodes must lie in the plane `z = 0`.
//!
//! **The mesh built.** Corner nodes first, then mid-edge nodes, each in the order of their tags
//! (so a file written by `pendulum_fem_render::gmsh::write_msh` reads back with the same numbering); 3-node
//! triangles get straight mid-edge nodes (`order = 1`), 6-node triangles keep theirs (`order = 2`).
//! Clockwise triangles are turned counter-clockwise. Every edge used by one triangle is a boundary
//! edge, named by the physical group of the line element on it (`"default"` without one); the
//! physical group `rotation` (the hinge) is required, `contact_head` is optional, others are kept
//! by name. The region is named by the triangles' 2-D physical group (`"pendulum"` without one).
//!
//! **Errors** name the file and the line (ASCII) or byte offset (binary) and what was expected:
//! a missing section, a count that does not fit the file, an unknown node, an unsupported element
//! type, a degenerate or non-conforming triangle, a named line that is not on the boundary.

use std::collections::HashMap;
use std::path::Path;

use crate::mesh::{BoundaryEdge, Mesh};
use crate::Error;

/// The boundary name the hinge must carry.
pub const HINGE_NAME: &str = "rotation";

/// Reads a Gmsh 4.1 file.
pub fn read_msh(path: &Path) -> Result<Mesh, Error> {
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_msh(&data, &path.display().to_string())
}

/// Parses the bytes of a Gmsh 4.1 file; `source` names it in error messages.
pub fn parse_msh(data: &[u8], source: &str) -> Result<Mesh, Error> {
    let raw = Parser::new(data, source).parse()?;
    build_mesh(raw, source)
}

/// What the file holds, before it becomes a mesh.
#[derive(Default)]
struct RawMesh {
    /// `(dim, tag) → name`.
    physical_names: HashMap<(i32, i32), String>,
    /// Physical tags of curves (dim 1) and surfaces (dim 2): `(dim, entity tag) → tags`.
    entity_physicals: HashMap<(i32, i32), Vec<i32>>,
    /// Node tag → `[x, y, z]`.
    nodes: HashMap<u64, [f64; 3]>,
    /// `(element tag, entity tag, node tags)` of triangles.
    triangles: Vec<(u64, i32, Vec<u64>)>,
    /// `(element tag, entity tag, node tags)` of lines.
    lines: Vec<(u64, i32, Vec<u64>)>,
}

struct Parser<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
    source: &'a str,
    binary: bool,
    swap: bool,
    /// The section being read, for messages.
    section: &'static str,
}

/// Nodes per element of the supported types; `None`: unsupported.
fn nodes_of(element_type: i32) -> Option<usize> {
    match element_type {
        15 => Some(1),
        1 => Some(2),
        8 => Some(3),
        2 => Some(3),
        9 => Some(6),
        _ => None,
    }
}

fn type_name(element_type: i32) -> &'static str {
    match element_type {
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        10 => "9-node quadrangle",
        16 => "8-node quadrangle",
        21 => "10-node triangle",
        _ => "an element type",
    }
}

impl<'a> Parser<'a> {
    fn new(data: &'a [u8], source: &'a str) -> Self {
        Self {
            data,
            pos: 0,
            line: 1,
            source,
            binary: false,
            swap: false,
            section: "",
        }
    }

    fn err(&self, message: impl std::fmt::Display) -> Error {
        let at = if self.binary && !self.section.is_empty() && self.section != "$PhysicalNames" {
            format!("byte {}", self.pos)
        } else {
            format!("line {}", self.line)
        };
        let within = if self.section.is_empty() {
            String::new()
        } else {
            format!(" (in {})", self.section)
        };
        Error::Input(format!("{}: {at}{within}: {message}", self.source))
    }

    /// The next whitespace-separated token (ASCII), or `None` at the end of the data.
    fn token(&mut self) -> Option<&'a str> {
        while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
            if self.data[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        (self.pos > start).then(|| std::str::from_utf8(&self.data[start..self.pos]).unwrap_or("\u{fffd}"))
    }

    fn expect_token(&mut self, what: &str) -> Result<&'a str, Error> {
        self.token()
            .ok_or_else(|| self.err(format!("the file ends where {what} was expected")))
    }

    fn number<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, Error> {
        let t = self.expect_token(what)?;
        t.parse().map_err(|_| self.err(format!("`{t}` is not a valid {what}")))
    }

    /// The rest of the current line (ASCII), without the line break.
    fn rest_of_line(&mut self) -> &'a str {
        let start = self.pos;
        while self.pos < self.data.len() && self.data[self.pos] != b'\n' {
            self.pos += 1;
        }
        std::str::from_utf8(&self.data[start..self.pos]).unwrap_or("\u{fffd}")
    }

    fn bytes<const N: usize>(&mut self, what: &str) -> Result<[u8; N], Error> {
        let end = self.pos.checked_add(N).filter(|&e| e <= self.data.len());
        let Some(end) = end else {
            return Err(self.err(format!("the file ends inside {what}")));
        };
        let mut b: [u8; N] = self.data[self.pos..end].try_into().expect("N bytes");
        if self.swap {
            b.reverse();
        }
        self.pos = end;
        Ok(b)
    }

    /// A `size_t` (binary) or an unsigned integer token (ASCII).
    fn size(&mut self, what: &str) -> Result<u64, Error> {
        if self.binary {
            Ok(u64::from_le_bytes(self.bytes::<8>(what)?))
        } else {
            self.number(what)
        }
    }

    /// An `int` (binary) or an integer token (ASCII).
    fn int(&mut self, what: &str) -> Result<i32, Error> {
        if self.binary {
            Ok(i32::from_le_bytes(self.bytes::<4>(what)?))
        } else {
            self.number(what)
        }
    }

    /// A `double` (binary) or a number token (ASCII); must be finite.
    fn real(&mut self, what: &str) -> Result<f64, Error> {
        let v: f64 = if self.binary {
            f64::from_le_bytes(self.bytes::<8>(what)?)
        } else {
            self.number(what)?
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(format!("{what} is {v}, not a finite number")))
        }
    }

    /// A count read from the file, checked against the bytes left (each item takes at least
    /// `min_bytes`), so that a corrupt count cannot demand absurd memory.
    fn count(&mut self, what: &str, min_bytes: usize) -> Result<usize, Error> {
        let n = self.size(what)?;
        let left = (self.data.len() - self.pos) as u64;
        if n > left / min_bytes.max(1) as u64 {
            return Err(self.err(format!("{what} = {n} does not fit in the rest of the file")));
        }
        Ok(n as usize)
    }

    /// In a binary section, the line break after the section name.
    fn start_binary_section(&mut self) {
        if self.binary && self.data.get(self.pos) == Some(&b'\n') {
            self.pos += 1;
            self.line += 1;
        }
    }

    fn end_section(&mut self, name: &str) -> Result<(), Error> {
        let end = format!("$End{name}");
        match self.token() {
            Some(t) if t == end => {
                self.section = "";
                Ok(())
            }
            Some(t) => Err(self.err(format!("`{t}` where `{end}` was expected"))),
            None => Err(self.err(format!("the file ends before `{end}`"))),
        }
    }

    fn parse(mut self) -> Result<RawMesh, Error> {
        let mut raw = RawMesh::default();
        let mut seen_format = false;
        let (mut seen_nodes, mut seen_elements) = (false, false);
        while let Some(t) = self.token() {
            if !seen_format && t != "$MeshFormat" {
                return Err(self.err(format!(
                    "`{t}`: the file must start with $MeshFormat (is this a Gmsh .msh file?)"
                )));
            }
            let Some(name) = t.strip_prefix('$') else {
                return Err(self.err(format!("`{t}` outside any section (expected a `$Section` line)")));
            };
            match name {
                "MeshFormat" => {
                    self.section = "$MeshFormat";
                    self.format()?;
                    seen_format = true;
                }
                "PhysicalNames" => {
                    self.section = "$PhysicalNames";
                    self.physical_names(&mut raw)?;
                }
                "Entities" => {
                    self.section = "$Entities";
                    self.start_binary_section();
                    self.entities(&mut raw)?;
                }
                "Nodes" => {
                    self.section = "$Nodes";
                    self.start_binary_section();
                    self.nodes(&mut raw)?;
                    seen_nodes = true;
                }
                "Elements" => {
                    self.section = "$Elements";
                    self.start_binary_section();
                    self.elements(&mut raw)?;
                    seen_elements = true;
                }
                _ => self.skip_section(name)?,
            }
            self.end_section(name)?;
        }
        if !seen_format {
            return Err(self.err("empty file: expected $MeshFormat"));
        }
        if !seen_nodes || !seen_elements {
            return Err(self.err("the file has no $Nodes or no $Elements section"));
        }
        Ok(raw)
    }

    fn format(&mut self) -> Result<(), Error> {
        let version = self.expect_token("the version")?;
        if version != "4.1" {
            return Err(self.err(format!(
                "version {version}: only Gmsh 4.1 files are read (gmsh -format msh41, or Mesh.MshFileVersion = 4.1)"
            )));
        }
        let file_type: u32 = self.number("file type")?;
        let data_size: u32 = self.number("data size")?;
        match file_type {
            0 => {}
            1 => {
                if data_size != 8 {
                    return Err(self.err(format!("data size {data_size}: binary files need 8-byte size_t")));
                }
                self.binary = true;
                self.start_binary_section();
                let one = self.bytes::<4>("the byte-order marker")?;
                if i32::from_le_bytes(one) == 1 {
                    self.swap = false;
                } else if i32::from_be_bytes(one) == 1 {
                    self.swap = true;
                } else {
                    return Err(self.err("the binary byte-order marker is not the integer 1"));
                }
            }
            _ => return Err(self.err(format!("file type {file_type}: allowed 0 (ASCII) or 1 (binary)"))),
        }
        Ok(())
    }

    fn physical_names(&mut self, raw: &mut RawMesh) -> Result<(), Error> {
        // ASCII also in binary files
        let n: usize = self.number("number of physical names")?;
        for _ in 0..n {
            let dim: i32 = self.number("physical dimension")?;
            let tag: i32 = self.number("physical tag")?;
            let rest = self.rest_of_line().trim();
            let name = rest
                .strip_prefix('"')
                .and_then(|r| r.strip_suffix('"'))
                .ok_or_else(|| self.err(format!("physical name `{rest}` is not in double quotes")))?;
            raw.physical_names.insert((dim, tag), name.to_string());
        }
        Ok(())
    }

    fn entities(&mut self, raw: &mut RawMesh) -> Result<(), Error> {
        let counts = [
            self.count("number of points", 4)?,
            self.count("number of curves", 4)?,
            self.count("number of surfaces", 4)?,
            self.count("number of volumes", 4)?,
        ];
        for (dim, &count) in counts.iter().enumerate() {
            for _ in 0..count {
                let tag = self.int("entity tag")?;
                let coordinates = if dim == 0 { 3 } else { 6 };
                for _ in 0..coordinates {
                    self.real("entity bounding box")?;
                }
                let n = self.count("number of physical tags", 4)?;
                let mut tags = Vec::with_capacity(n);
                for _ in 0..n {
                    tags.push(self.int("physical tag")?);
                }
                if dim > 0 {
                    let b = self.count("number of bounding entities", 4)?;
                    for _ in 0..b {
                        self.int("bounding entity tag")?;
                    }
                }
                raw.entity_physicals.insert((dim as i32, tag), tags);
            }
        }
        Ok(())
    }

    fn nodes(&mut self, raw: &mut RawMesh) -> Result<(), Error> {
        let blocks = self.count("number of node blocks", 4)?;
        let total = self.count("number of nodes", 8)?;
        self.size("smallest node tag")?;
        self.size("largest node tag")?;
        let mut read = 0usize;
        for _ in 0..blocks {
            let _dim = self.int("entity dimension")?;
            let _entity = self.int("entity tag")?;
            let parametric = self.int("parametric flag")?;
            if parametric != 0 {
                return Err(self.err("parametric node coordinates are not supported (save without them)"));
            }
            let n = self.count("number of nodes in the block", 8)?;
            let mut tags = Vec::with_capacity(n);
            for _ in 0..n {
                tags.push(self.size("node tag")?);
            }
            for tag in tags {
                let p = [
                    self.real("x coordinate")?,
                    self.real("y coordinate")?,
                    self.real("z coordinate")?,
                ];
                if raw.nodes.insert(tag, p).is_some() {
                    return Err(self.err(format!("node tag {tag} appears twice")));
                }
            }
            read += n;
        }
        if read != total {
            return Err(self.err(format!("the header announces {total} nodes, the blocks hold {read}")));
        }
        Ok(())
    }

    fn elements(&mut self, raw: &mut RawMesh) -> Result<(), Error> {
        let blocks = self.count("number of element blocks", 4)?;
        let total = self.count("number of elements", 4)?;
        self.size("smallest element tag")?;
        self.size("largest element tag")?;
        let mut read = 0usize;
        for _ in 0..blocks {
            let dim = self.int("entity dimension")?;
            let entity = self.int("entity tag")?;
            let kind = self.int("element type")?;
            let per = nodes_of(kind).ok_or_else(|| {
                self.err(format!(
                    "element type {kind} ({}) is not supported: mesh the plane shape with 3- or 6-node triangles",
                    type_name(kind)
                ))
            })?;
            let min_bytes = if self.binary { 8 * (per + 1) } else { 2 * (per + 1) };
            let n = self.count("number of elements in the block", min_bytes)?;
            for _ in 0..n {
                let tag = self.size("element tag")?;
                let mut nodes = Vec::with_capacity(per);
                for _ in 0..per {
                    nodes.push(self.size("node tag")?);
                }
                match (dim, kind) {
                    (2, 2 | 9) => raw.triangles.push((tag, entity, nodes)),
                    (1, 1 | 8) => raw.lines.push((tag, entity, nodes)),
                    (0, 15) => {}
                    _ => return Err(self.err(format!("element {tag}: type {kind} on an entity of dimension {dim}"))),
                }
            }
            read += n;
        }
        if read != total {
            return Err(self.err(format!("the header announces {total} elements, the blocks hold {read}")));
        }
        Ok(())
    }

    /// Skips an unknown section up to its `$End` line (sections are text-delimited also in binary
    /// files).
    fn skip_section(&mut self, name: &str) -> Result<(), Error> {
        let end = format!("\n$End{name}");
        let rest = &self.data[self.pos..];
        let at = rest
            .windows(end.len())
            .position(|w| w == end.as_bytes())
            .ok_or_else(|| self.err(format!("section ${name} has no $End{name}")))?;
        self.line += rest[..at].iter().filter(|&&b| b == b'\n').count();
        self.pos += at;
        Ok(())
    }
}

fn build_mesh(raw: RawMesh, source: &str) -> Result<Mesh, Error> {
    let err = |m: String| Error::Input(format!("{source}: {m}"));
    if raw.triangles.is_empty() {
        return Err(err("no triangles (element types 2 or 9) in $Elements".into()));
    }
    let six = raw.triangles[0].2.len() == 6;
    if let Some(t) = raw.triangles.iter().find(|t| (t.2.len() == 6) != six) {
        return Err(err(format!(
            "element {}: 3- and 6-node triangles are mixed; use one kind",
            t.0
        )));
    }
    let extent = raw
        .nodes
        .values()
        .fold(0.0f64, |a, p| a.max(p[0].abs()).max(p[1].abs()));
    let point = |tag: u64, element: u64| -> Result<[f64; 2], Error> {
        let p = raw
            .nodes
            .get(&tag)
            .ok_or_else(|| err(format!("element {element} uses node {tag}, which is not in $Nodes")))?;
        if p[2].abs() > 1e-9 * extent.max(1e-300) {
            return Err(err(format!(
                "node {tag} has z = {}: the mesh must lie in the plane z = 0",
                p[2]
            )));
        }
        Ok([p[0], p[1]])
    };
    // corners and mid nodes by tag
    let mut corner_tags: Vec<u64> = Vec::new();
    let mut mid_tags: Vec<u64> = Vec::new();
    for (tag, _, nodes) in &raw.triangles {
        for &n in &nodes[..3] {
            point(n, *tag)?;
            corner_tags.push(n);
        }
        for &n in &nodes[3..] {
            point(n, *tag)?;
            mid_tags.push(n);
        }
    }
    corner_tags.sort_unstable();
    corner_tags.dedup();
    mid_tags.sort_unstable();
    mid_tags.dedup();
    if let Some(n) = mid_tags.iter().find(|n| corner_tags.binary_search(n).is_ok()) {
        return Err(err(format!(
            "node {n} is a corner of one triangle and a mid-edge node of another"
        )));
    }
    let mut index: HashMap<u64, usize> = HashMap::with_capacity(corner_tags.len() + mid_tags.len());
    let mut nodes: Vec<[f64; 2]> = Vec::with_capacity(corner_tags.len() + mid_tags.len());
    for &t in corner_tags.iter().chain(&mid_tags) {
        index.insert(t, nodes.len());
        nodes.push([raw.nodes[&t][0], raw.nodes[&t][1]]);
    }
    let num_vertices = corner_tags.len();
    // triangles, counter-clockwise, with one mid node per edge
    let mut mid_of: HashMap<(usize, usize), usize> = HashMap::new();
    let mut uses: HashMap<(usize, usize), usize> = HashMap::new();
    let mut triangles = Vec::with_capacity(raw.triangles.len());
    for (tag, _, tn) in &raw.triangles {
        let v: Vec<usize> = tn.iter().map(|t| index[t]).collect();
        let [a, b, c] = [nodes[v[0]], nodes[v[1]], nodes[v[2]]];
        let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area2 == 0.0 || area2.is_nan() || v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
            return Err(err(format!(
                "triangle element {tag} is degenerate (zero area or a repeated node)"
            )));
        }
        let mut t = if six {
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        } else {
            [v[0], v[1], v[2], usize::MAX, usize::MAX, usize::MAX]
        };
        if area2 < 0.0 {
            t = [t[0], t[2], t[1], t[5], t[4], t[3]];
        }
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            let key = (p.min(q), p.max(q));
            let count = uses.entry(key).or_insert(0);
            *count += 1;
            if *count > 2 {
                return Err(err(format!(
                    "triangle element {tag}: its edge between nodes {} and {} belongs to three triangles",
                    corner_tags[p], corner_tags[q]
                )));
            }
            if six {
                let m = *mid_of.entry(key).or_insert(t[3 + k]);
                if m != t[3 + k] {
                    return Err(err(format!(
                        "triangle element {tag}: the edge between nodes {} and {} has two different mid nodes",
                        corner_tags[p], corner_tags[q]
                    )));
                }
            } else {
                let m = *mid_of.entry(key).or_insert_with(|| {
                    nodes.push([(nodes[p][0] + nodes[q][0]) / 2.0, (nodes[p][1] + nodes[q][1]) / 2.0]);
                    nodes.len() - 1
                });
                t[3 + k] = m;
            }
        }
        triangles.push(t);
    }
    // boundary names from the physical groups of the line elements
    let physical_name = |dim: i32, entity: i32| -> Option<&String> {
        raw.entity_physicals
            .get(&(dim, entity))?
            .iter()
            .find_map(|p| raw.physical_names.get(&(dim, *p)))
    };
    let mut line_name: HashMap<(usize, usize), (String, u64)> = HashMap::new();
    for (tag, entity, ln) in &raw.lines {
        let Some(name) = physical_name(1, *entity) else {
            continue;
        };
        let ends: Vec<usize> = ln[..2]
            .iter()
            .map(|t| {
                index.get(t).copied().filter(|&i| i < num_vertices).ok_or_else(|| {
                    err(format!(
                        "line element {tag} (physical \"{name}\") ends at node {t}, which is no triangle corner"
                    ))
                })
            })
            .collect::<Result<_, _>>()?;
        let key = (ends[0].min(ends[1]), ends[0].max(ends[1]));
        if uses.get(&key) != Some(&1) {
            return Err(err(format!(
                "line element {tag} (physical \"{name}\") is not on the boundary of the triangles"
            )));
        }
        line_name.insert(key, (name.clone(), *tag));
    }
    let mut names: Vec<String> = Vec::new();
    let mut groups: Vec<(i32, &String)> = raw
        .physical_names
        .iter()
        .filter(|((dim, _), _)| *dim == 1)
        .map(|((_, tag), name)| (*tag, name))
        .collect();
    groups.sort();
    for (_, name) in groups {
        if line_name.values().any(|(n, _)| n == name) && !names.contains(name) {
            names.push(name.clone());
        }
    }
    if !names.iter().any(|n| n == HINGE_NAME) {
        return Err(err(format!(
            "no boundary edges in a physical curve group named \"{HINGE_NAME}\": name the hinge edge's physical \
             group {HINGE_NAME} (Physical Curve(\"{HINGE_NAME}\") = {{…}} in a .geo file)"
        )));
    }
    // the hinge first, as in generated meshes
    let hinge = names.iter().position(|n| n == HINGE_NAME).expect("present");
    let h = names.remove(hinge);
    names.insert(0, h);
    let mut boundary_edges = Vec::new();
    let mut unnamed = false;
    for (ti, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            let key = (p.min(q), p.max(q));
            if uses[&key] != 1 {
                continue;
            }
            let name = match line_name.get(&key) {
                Some((n, _)) => names.iter().position(|x| x == n).expect("collected"),
                None => {
                    unnamed = true;
                    usize::MAX
                }
            };
            boundary_edges.push(BoundaryEdge {
                nodes: [p, q, t[3 + k]],
                name,
                triangle: ti,
                local_edge: k,
            });
        }
    }
    if unnamed {
        let default = match names.iter().position(|n| n == "default") {
            Some(i) => i,
            None => {
                names.push("default".into());
                names.len() - 1
            }
        };
        for e in &mut boundary_edges {
            if e.name == usize::MAX {
                e.name = default;
            }
        }
    }
    let region_name = raw
        .triangles
        .first()
        .and_then(|(_, entity, _)| physical_name(2, *entity))
        .cloned()
        .unwrap_or_else(|| "pendulum".into());
    Ok(Mesh {
        nodes,
        num_vertices,
        triangles,
        boundary_edges,
        boundary_names: names,
        region_name,
        order: if six { 2 } else { 1 },
    })
}
