//! The parser of the `.msh` sections: tokens (ASCII) or little- and big-endian values (binary),
//! `$MeshFormat`, `$PhysicalNames`, `$Entities`, `$Nodes` and `$Elements` into a [`RawMesh`],
//! other sections skipped; errors name the line or byte offset.

use super::RawMesh;
use crate::error::Error;

pub(super) struct Parser<'a> {
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
    pub(super) fn new(data: &'a [u8], source: &'a str) -> Self {
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

    pub(super) fn parse(mut self) -> Result<RawMesh, Error> {
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
